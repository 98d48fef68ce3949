//! The metrics of one snapshot, against the clean surface.

use beltrami_halfedge::DVec3;
use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::{DistanceStats, SurfaceIndex};
use beltrami_metrics::distortion::{
    RingProfile, boundary_displacement, error_by_ring, feature_edge_distortion,
};
use beltrami_metrics::fits::{FitOptions, FitPoints, fit_sphere};
use beltrami_metrics::normals::normal_deviation;
use beltrami_surfaces::SurfaceKind;

use crate::case::SurfaceCase;
use crate::results::Row;

/// Edges of the clean block whose faces meet at this angle or more are its features.
pub const FEATURE_THRESHOLD_DEG: f64 = 60.0;

/// A snapshot's row and, for open surfaces, its error profile by ring distance from
/// the boundary.
#[derive(Clone, Debug)]
pub struct Measured {
    /// The CSV/JSON row.
    pub row: Row,
    /// RMS distance to the clean surface per ring of vertices at the same graph
    /// distance from the boundary (open surfaces only).
    pub rings: Option<RingProfile>,
}

/// What every snapshot of a surface is measured against.
pub(crate) struct Reference<'a> {
    case: &'a SurfaceCase,
    index: SurfaceIndex,
    clean_volume: Option<f64>,
}

impl<'a> Reference<'a> {
    pub(crate) fn new(case: &'a SurfaceCase) -> Result<Self, MetricsError> {
        let index = SurfaceIndex::new(&case.mesh, &case.clean.positions)?;
        let clean_volume = if case.mesh.is_closed() {
            Some(Geometry::new(&case.mesh, &case.clean.positions)?.volume()?)
        } else {
            None
        };
        Ok(Self {
            case,
            index,
            clean_volume,
        })
    }

    /// The signed distances of `positions` to the clean surface (positive outside).
    pub(crate) fn signed_distances(&self, positions: &[DVec3]) -> Result<Vec<f64>, MetricsError> {
        self.index.signed_distances(positions)
    }

    /// The RMS distance of `positions` to the clean surface.
    pub(crate) fn rms(&self, positions: &[DVec3]) -> Result<f64, MetricsError> {
        let d = self.index.distances(positions)?;
        Ok(DistanceStats::new(&d, &vec![1.0; d.len()])?.rms)
    }

    pub(crate) fn measure(
        &self,
        scheme: &str,
        iteration: usize,
        time_s: f64,
        stuck_vertices: usize,
        positions: &[DVec3],
    ) -> Result<Measured, MetricsError> {
        let case = self.case;
        let mesh = &case.mesh;
        let geometry = Geometry::new(mesh, positions)?;
        let clean = Geometry::new(mesh, &case.clean.positions)?;
        let distances = self.index.distances(positions)?;
        let areas = geometry.vertex_areas(VertexAreaKind::Barycentric)?;
        let stats = DistanceStats::new(&distances, areas.as_slice())?;
        let normals = normal_deviation(mesh, positions, mesh, &case.clean.positions)?;
        let volume = if mesh.is_closed() {
            Some(geometry.volume()?)
        } else {
            None
        };
        let sphere_radius = match case.kind {
            SurfaceKind::Sphere | SurfaceKind::GolfBall => {
                Some(fit_sphere(&FitPoints::new(positions), &FitOptions::default())?.radius)
            }
            _ => None,
        };
        let (boundary_mean, boundary_max, rings) = if mesh.is_closed() {
            (None, None, None)
        } else {
            let input = Geometry::new(mesh, &case.noisy)?;
            let b = boundary_displacement(&input, &geometry)?;
            (
                Some(b.mean),
                Some(b.max),
                Some(error_by_ring(mesh, &distances)?),
            )
        };
        let feature_dihedral_deg = if case.kind == SurfaceKind::Block {
            Some(
                feature_edge_distortion(&clean, &geometry, FEATURE_THRESHOLD_DEG)?
                    .smoothed
                    .mean,
            )
        } else {
            None
        };
        Ok(Measured {
            row: Row {
                surface: case.clean.name.to_string(),
                scheme: scheme.to_string(),
                iteration,
                time_s,
                rms: stats.rms,
                mean: stats.mean,
                max: stats.max,
                area_rms: stats.area_weighted_rms,
                normal_mean_deg: normals.mean_deg,
                normal_rms_deg: normals.rms_deg,
                volume,
                volume_ratio: volume
                    .zip(self.clean_volume)
                    .map(|(v, c)| v / c)
                    .filter(|r| r.is_finite()),
                sphere_radius,
                boundary_mean,
                boundary_max,
                feature_dihedral_deg,
                stuck_vertices,
                seed: case.seed,
                flipped_faces: beltrami_algorithms::flipped_faces(
                    mesh,
                    positions,
                    &case.clean.positions,
                )
                .ok(),
                min_angle_deg: beltrami_algorithms::mesh_quality(mesh, positions)
                    .ok()
                    .and_then(|q| q.shape)
                    .map(|s| s.min_angle),
            },
            rings,
        })
    }
}
