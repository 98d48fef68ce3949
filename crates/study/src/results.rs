//! The study's results: one row per surface, scheme and iteration, as CSV and JSON.

use serde::Serialize;

/// One observation: a surface smoothed with a scheme for a number of iterations.
/// Metrics that do not apply to the surface (a volume of an open one, a boundary of a
/// closed one) are `None` (empty in CSV, `null` in JSON).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// The surface's name.
    pub surface: String,
    /// The scheme's name (`"input"` for the noisy input at iteration 0).
    pub scheme: String,
    /// Iterations done (0 = the noisy input).
    pub iteration: usize,
    /// Cumulative smoothing wall time up to this iteration, seconds (weights and
    /// updates; metric computations excluded).
    pub time_s: f64,
    /// RMS of the vertex distances to the clean surface (closest point on the closest
    /// triangle) — the paper's smoothness metric. Length unit of the surface.
    pub rms: f64,
    /// Mean vertex distance to the clean surface.
    pub mean: f64,
    /// Largest vertex distance to the clean surface.
    pub max: f64,
    /// Area-weighted RMS distance (barycentric vertex areas of the smoothed mesh).
    pub area_rms: f64,
    /// Mean angle between corresponding face normals of the smoothed and the clean
    /// mesh, degrees.
    pub normal_mean_deg: f64,
    /// RMS of those angles, degrees.
    pub normal_rms_deg: f64,
    /// Enclosed volume (closed surfaces), unit³.
    pub volume: Option<f64>,
    /// Volume relative to the clean surface's (`None` when that is zero).
    pub volume_ratio: Option<f64>,
    /// Radius of the least-squares sphere through the vertices (sphere, golf ball).
    pub sphere_radius: Option<f64>,
    /// Mean displacement of boundary vertices from the noisy input (open surfaces).
    pub boundary_mean: Option<f64>,
    /// Largest displacement of a boundary vertex from the noisy input.
    pub boundary_max: Option<f64>,
    /// Mean dihedral angle at the clean surface's feature edges (block), degrees: 90
    /// for a perfectly sharp edge, smaller as edges blur.
    pub feature_dihedral_deg: Option<f64>,
    /// Vertices that could not move in the last iteration (weights summing to ≤ 0).
    pub stuck_vertices: usize,
    /// The seed of the noise of this row's input.
    pub seed: u64,
    /// Faces whose normal points against the clean mesh's (turned by more than 90°):
    /// folds (`None` when the positions are not finite).
    pub flipped_faces: Option<usize>,
    /// The smallest corner angle of the mesh's non-degenerate triangles, degrees.
    pub min_angle_deg: Option<f64>,
}

/// The CSV header, in the order of [`Row`]'s fields.
pub const CSV_HEADER: &str = "surface,scheme,iteration,time_s,rms,mean,max,area_rms,normal_mean_deg,normal_rms_deg,volume,volume_ratio,sphere_radius,boundary_mean,boundary_max,feature_dihedral_deg,stuck_vertices,seed,flipped_faces,min_angle_deg";

fn opt(v: Option<f64>) -> String {
    v.map_or_else(String::new, |x| format!("{x:e}"))
}

impl Row {
    /// The row as one CSV line (no newline). Numbers in Rust's shortest round-trip
    /// scientific notation, so the CSV holds the exact values.
    #[must_use]
    pub fn to_csv(&self) -> String {
        format!(
            "{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{},{},{},{},{},{},{},{},{}",
            self.surface,
            self.scheme,
            self.iteration,
            self.time_s,
            self.rms,
            self.mean,
            self.max,
            self.area_rms,
            self.normal_mean_deg,
            self.normal_rms_deg,
            opt(self.volume),
            opt(self.volume_ratio),
            opt(self.sphere_radius),
            opt(self.boundary_mean),
            opt(self.boundary_max),
            opt(self.feature_dihedral_deg),
            self.stuck_vertices,
            self.seed,
            self.flipped_faces
                .map_or_else(String::new, |n| n.to_string()),
            opt(self.min_angle_deg)
        )
    }
}

/// All rows as CSV text with a header line.
#[must_use]
pub fn to_csv(rows: &[Row]) -> String {
    let mut out = String::with_capacity(rows.len() * 200);
    out.push_str(CSV_HEADER);
    out.push('\n');
    for r in rows {
        out.push_str(&r.to_csv());
        out.push('\n');
    }
    out
}
