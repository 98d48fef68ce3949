//! Height maps on a regular grid, and the resampling of a residual on a mesh onto one in
//! the mesh's best-fit plane.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh};

use super::areal::Surface;
use crate::MetricsError;
use crate::fits::{FitPoints, fit_plane, in_plane_axes};

/// A height map on a regular grid of `nx × ny` points with spacings `dx` and `dy`, some
/// of them possibly invalid (not measured, or outside the surface).
///
/// Point `(i, j)` lies at `(i dx, j dy)`; heights are stored row by row, `i` fastest
/// (index `j · nx + i`). This is the layout of instrument files (ISO 25178-71 SDF,
/// ISO 25178-72 X3P), whose invalid points become `None`.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightGrid {
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    heights: Vec<Option<f64>>,
}

impl HeightGrid {
    /// A grid of `nx × ny` heights (row by row, `i` fastest) with spacings `dx`, `dy`.
    ///
    /// # Errors
    /// - [`MetricsError::FieldLength`] when `heights` does not hold `nx · ny` values;
    /// - [`MetricsError::InvalidParameter`] for a spacing that is not positive and finite;
    /// - [`MetricsError::NonFinite`] for a non-finite valid height (`"height"`).
    pub fn new(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        heights: Vec<Option<f64>>,
    ) -> Result<Self, MetricsError> {
        if heights.len() != nx.saturating_mul(ny) {
            return Err(MetricsError::FieldLength {
                what: "heights",
                got: heights.len(),
                expected: nx.saturating_mul(ny),
            });
        }
        for (name, d) in [("grid spacing dx", dx), ("grid spacing dy", dy)] {
            if !(d > 0.0 && d.is_finite()) {
                return Err(MetricsError::InvalidParameter {
                    name,
                    reason: "must be positive and finite",
                });
            }
        }
        if let Some(index) = heights
            .iter()
            .position(|h| h.is_some_and(|h| !h.is_finite()))
        {
            return Err(MetricsError::NonFinite {
                what: "height",
                index,
            });
        }
        Ok(Self {
            nx,
            ny,
            dx,
            dy,
            heights,
        })
    }

    /// The number of points along x.
    #[must_use]
    pub fn nx(&self) -> usize {
        self.nx
    }

    /// The number of points along y.
    #[must_use]
    pub fn ny(&self) -> usize {
        self.ny
    }

    /// The spacing along x, in length units.
    #[must_use]
    pub fn dx(&self) -> f64 {
        self.dx
    }

    /// The spacing along y, in length units.
    #[must_use]
    pub fn dy(&self) -> f64 {
        self.dy
    }

    /// The height at `(i, j)`, `None` when invalid or outside the grid.
    #[must_use]
    pub fn height(&self, i: usize, j: usize) -> Option<f64> {
        if i < self.nx && j < self.ny {
            self.heights[j * self.nx + i]
        } else {
            None
        }
    }

    /// All heights, row by row.
    #[must_use]
    pub fn heights(&self) -> &[Option<f64>] {
        &self.heights
    }

    /// The number of valid points.
    #[must_use]
    pub fn valid_count(&self) -> usize {
        self.heights.iter().filter(|h| h.is_some()).count()
    }
}

/// How [`resample_to_grid`] samples a residual.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ResampleOptions {
    /// The grid spacing, in length units; `None` (the default) for the median edge length
    /// of the mesh.
    pub step: Option<f64>,
    /// The most grid points (default 2²⁰ = 1 048 576); a finer grid is coarsened to this.
    pub max_points: usize,
    /// The largest share of the projected area that may face away from the plane's
    /// normal (default 1 %): beyond it, the surface folds over its plane and is no height
    /// field.
    pub max_folded_fraction: f64,
}

impl ResampleOptions {
    /// Sets [`step`](Self::step): the grid spacing in length units (`None`: the median edge length).
    #[must_use]
    pub fn step(mut self, step: Option<f64>) -> Self {
        self.step = step;
        self
    }

    /// Sets [`max_points`](Self::max_points): the most grid points.
    #[must_use]
    pub fn max_points(mut self, max_points: usize) -> Self {
        self.max_points = max_points;
        self
    }

    /// Sets [`max_folded_fraction`](Self::max_folded_fraction): the largest share of folded projected area.
    #[must_use]
    pub fn max_folded_fraction(mut self, max_folded_fraction: f64) -> Self {
        self.max_folded_fraction = max_folded_fraction;
        self
    }
}

impl Default for ResampleOptions {
    fn default() -> Self {
        Self {
            step: None,
            max_points: 1 << 20,
            max_folded_fraction: 0.01,
        }
    }
}

/// A right-handed orthonormal frame of a plane: `u_axis`, `v_axis` in it, `normal` out of
/// it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneFrame {
    /// A point of the plane (the area-weighted centroid of the surface).
    pub origin: DVec3,
    /// The first in-plane axis: the projection of the x axis (of y when the plane is
    /// nearly orthogonal to x). Texture directions are measured from it.
    pub u_axis: DVec3,
    /// The second in-plane axis, `normal × u_axis`.
    pub v_axis: DVec3,
    /// The unit normal, on the side the surface's faces point to on balance.
    pub normal: DVec3,
}

/// A residual resampled onto a regular grid in a plane. See [`resample_to_grid`].
#[derive(Clone, Debug, PartialEq)]
pub struct ResampledGrid {
    /// The heights; point `(i, j)` lies at `u = u0 + i · step`, `v = v0 + j · step` in
    /// the frame.
    pub grid: HeightGrid,
    /// The plane and its axes.
    pub frame: PlaneFrame,
    /// The `u` coordinate of the grid's first column.
    pub u0: f64,
    /// The `v` coordinate of the grid's first row.
    pub v0: f64,
    /// The spacing used, in length units.
    pub step: f64,
    /// The share of the surface's projected area that faced away from the normal and was
    /// left out (0 for a height field).
    pub folded_fraction: f64,
}

/// Resamples a per-vertex field on a triangle mesh (a residual, heights over the mesh's
/// reference surface) onto a regular square grid in the mesh's best-fit plane, for the
/// parameters defined on grids (the spatial parameters).
///
/// 1. The plane is the area-weighted least-squares plane of the mesh's positions
///    ([`fit_plane`] with the barycentric vertex areas as weights), its normal turned to
///    the side the faces point to on balance (`Σ_T` of the face vector areas), so that
///    "up" is the surface's outside. The in-plane axes are the projection of x (or y,
///    see [`PlaneFrame`]) and `normal × u`: seen from the normal's side, `v` is `u`
///    turned 90° counter-clockwise.
/// 2. The spacing is `options.step`, by default the median edge length of the mesh
///    (about the sampling of the surface: a regular grid mesh is resampled at its own
///    points); coarsened when the bounding rectangle of the projection would need more
///    than `options.max_points` points.
/// 3. Each triangle is projected onto the plane and each grid point inside it gets the
///    linear interpolation of the field at its corners (barycentric coordinates in the
///    plane). Grid points outside the projection of the mesh are invalid (`None`) and
///    excluded from whatever is computed on the grid. A triangle that faces away from the
///    normal in projection (the surface folds back over the plane there) or has no
///    projected area is skipped; where two triangles cover a point, the first one (in
///    face order) gives it its value.
///
/// The heights are the field's values themselves (lengths measured along the reference
/// surface's normal), placed at their projected positions: for a curved form the
/// projection shortens distances by the cosine of the form's slope, so the grid suits
/// surfaces that are nearly flat over their extent, which is what parameters on grids
/// assume.
///
/// # Errors
/// - as [`areal_parameters`](super::areal_parameters) for the mesh, positions and field;
/// - [`MetricsError::InvalidParameter`] for a `step` that is not positive and finite, or
///   `max_points` below 16;
/// - [`MetricsError::NotAHeightField`] when more than `options.max_folded_fraction` of
///   the projected area faces away from the plane's normal (a closed surface, or one
///   that folds over its plane);
/// - [`MetricsError::Empty`] (`"height grid"`) when fewer than 4 × 4 grid points fit
///   across the projection;
/// - the errors of [`fit_plane`] when the vertices are collinear.
///
/// # Complexity
/// O(V log V + F + grid points).
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::residual::{resample_to_grid, ResampleOptions};
///
/// // A 20 × 10 grid mesh is resampled at its own spacing: 21 × 11 points, all valid.
/// let grid = primitives::grid(20, 10);
/// let mesh = grid.mesh()?;
/// let r: Vec<f64> = grid.positions.iter().map(|p| (0.5 * p.x).sin()).collect();
/// let g = resample_to_grid(&Geometry::new(&mesh, &grid.positions)?, &r, &ResampleOptions::default())?;
/// assert_eq!((g.grid.nx(), g.grid.ny(), g.step), (21, 11, 1.0));
/// assert_eq!(g.grid.valid_count(), 231);
/// assert!((g.grid.height(3, 4).unwrap() - 1.5f64.sin()).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # References
/// ISO 25178-2:2012, clause 3.1 (the reference surface and its coordinate system, in
/// which the spatial parameters of clause 4.2 are defined on `z(x, y)`).
pub fn resample_to_grid(
    geometry: &Geometry<'_>,
    field: &[f64],
    options: &ResampleOptions,
) -> Result<ResampledGrid, MetricsError> {
    // Validates the mesh, positions and field.
    Surface::new(geometry, field)?;
    check_options(options)?;
    let frame = mean_plane_frame(geometry)?;
    let project = |p: DVec3| {
        let d = p - frame.origin;
        (d.dot(frame.u_axis), d.dot(frame.v_axis))
    };
    let projected: Vec<(f64, f64)> = geometry.positions().iter().map(|&p| project(p)).collect();
    let (low, high) = projected_extent(geometry, &projected)?;
    let (step, nx, ny) = grid_size(geometry, options, low, high)?;
    let Rasterised {
        heights,
        facing,
        folded,
    } = rasterise(geometry.mesh(), &projected, field, low, step, (nx, ny));
    let folded_fraction = if facing + folded > 0.0 {
        folded / (facing + folded)
    } else {
        0.0
    };
    if folded_fraction > options.max_folded_fraction {
        return Err(MetricsError::NotAHeightField {
            folded_percent: 100.0 * folded_fraction,
        });
    }
    Ok(ResampledGrid {
        grid: HeightGrid::new(nx, ny, step, step, heights)?,
        frame,
        u0: low[0],
        v0: low[1],
        step,
        folded_fraction,
    })
}

/// Refuses a grid step that is not positive and finite and fewer than 16 points.
fn check_options(options: &ResampleOptions) -> Result<(), MetricsError> {
    if let Some(step) = options.step
        && !(step > 0.0 && step.is_finite())
    {
        return Err(MetricsError::InvalidParameter {
            name: "grid step",
            reason: "must be positive and finite",
        });
    }
    if options.max_points < 16 {
        return Err(MetricsError::InvalidParameter {
            name: "max_points",
            reason: "must be at least 16",
        });
    }
    Ok(())
}

/// The least-squares mean plane of the surface (area-weighted), its normal turned to
/// the side the faces face on balance, with in-plane axes.
fn mean_plane_frame(geometry: &Geometry<'_>) -> Result<PlaneFrame, MetricsError> {
    let mesh = geometry.mesh();
    let positions = geometry.positions();
    let plane = fit_plane(&FitPoints::area_weighted(mesh, positions)?)?;
    let mut balance = DVec3::ZERO;
    for f in mesh.faces() {
        balance += geometry.face_vector_area(f);
    }
    let normal = if balance.dot(plane.normal) < 0.0 {
        -plane.normal
    } else {
        plane.normal
    };
    let (u_axis, v_axis) = in_plane_axes(normal);
    Ok(PlaneFrame {
        origin: plane.point,
        u_axis,
        v_axis,
        normal,
    })
}

/// The lowest and highest in-plane coordinates `(u, v)` of the vertices in a face;
/// [`MetricsError::CoordinateTooLarge`] when the extent overflows.
fn projected_extent(
    geometry: &Geometry<'_>,
    projected: &[(f64, f64)],
) -> Result<([f64; 2], [f64; 2]), MetricsError> {
    let mesh = geometry.mesh();
    let positions = geometry.positions();
    let (mut low, mut high) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for f in mesh.faces() {
        for v in mesh.triangle_vertices(f) {
            let (u, w) = projected[v.index()];
            low = [low[0].min(u), low[1].min(w)];
            high = [high[0].max(u), high[1].max(w)];
        }
    }
    if !(high[0] - low[0]).is_finite() || !(high[1] - low[1]).is_finite() {
        // The projected extent overflows: name the largest coordinate.
        let (index, value) = positions
            .iter()
            .enumerate()
            .flat_map(|(i, p)| [(i, p.x), (i, p.y), (i, p.z)])
            .fold((0, 0.0f64), |best, (i, c)| {
                if c.abs() > best.1.abs() { (i, c) } else { best }
            });
        return Err(MetricsError::CoordinateTooLarge {
            what: "vertex",
            index,
            value,
            limit: f64::MAX / 2.0,
        });
    }
    Ok((low, high))
}

/// The grid step (the option's, or the median edge length, coarsened until the grid
/// has at most `max_points` points) and the point counts along u and v.
fn grid_size(
    geometry: &Geometry<'_>,
    options: &ResampleOptions,
    low: [f64; 2],
    high: [f64; 2],
) -> Result<(f64, usize, usize), MetricsError> {
    let mut step = match options.step {
        Some(step) => step,
        None => median_edge_length(geometry).ok_or(MetricsError::Empty { what: "mesh area" })?,
    };
    // Point counts as floats (they may be astronomical before the coarsening).
    let count = |step: f64, k: usize| ((high[k] - low[k]) / step + 1e-9).floor() + 1.0;
    let limit = options.max_points as f64;
    while count(step, 0) * count(step, 1) > limit {
        let excess = count(step, 0) * count(step, 1) / limit;
        step *= excess.sqrt().max(1.0) * 1.0001;
    }
    // Both counts are now at most max_points.
    let (nx, ny) = (count(step, 0) as usize, count(step, 1) as usize);
    if nx < 4 || ny < 4 {
        return Err(MetricsError::Empty {
            what: "height grid",
        });
    }

    Ok((step, nx, ny))
}

/// The heights interpolated on the grid, and the projected areas of the faces that face
/// the plane and of the folded ones.
struct Rasterised {
    heights: Vec<Option<f64>>,
    facing: f64,
    folded: f64,
}

/// Interpolates `field` linearly at the grid points `(low + i·step, low + j·step)`
/// inside each face that faces the plane (the first face to cover a point gives its
/// height), and sums the projected areas of the facing and folded faces; faces of
/// (nearly) zero projected area are skipped.
fn rasterise(
    mesh: &HalfedgeMesh,
    projected: &[(f64, f64)],
    field: &[f64],
    low: [f64; 2],
    step: f64,
    (nx, ny): (usize, usize),
) -> Rasterised {
    let mut heights: Vec<Option<f64>> = vec![None; nx * ny];
    let (mut facing, mut folded) = (0.0, 0.0);
    for f in mesh.faces() {
        let [a, b, c] = mesh.triangle_vertices(f);
        let (pa, pb, pc) = (
            projected[a.index()],
            projected[b.index()],
            projected[c.index()],
        );
        let cross = |o: (f64, f64), p: (f64, f64), q: (f64, f64)| {
            (p.0 - o.0) * (q.1 - o.1) - (p.1 - o.1) * (q.0 - o.0)
        };
        let doubled = cross(pa, pb, pc);
        let longest = [(pa, pb), (pb, pc), (pc, pa)]
            .iter()
            .map(|(p, q)| (p.0 - q.0).powi(2) + (p.1 - q.1).powi(2))
            .fold(0.0f64, f64::max);
        if doubled.abs() <= 1e-12 * longest {
            continue;
        }
        if doubled < 0.0 {
            folded -= 0.5 * doubled;
            continue;
        }
        facing += 0.5 * doubled;
        let (ra, rb, rc) = (field[a.index()], field[b.index()], field[c.index()]);
        let range = |k: usize, values: [f64; 3]| {
            let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let n = if k == 0 { nx } else { ny };
            let first = ((lo - low[k]) / step - 1e-9).ceil().max(0.0) as usize;
            let last = (((hi - low[k]) / step + 1e-9).floor().max(0.0) as usize).min(n - 1);
            first..=last
        };
        let tolerance = -1e-12;
        for j in range(1, [pa.1, pb.1, pc.1]) {
            let y = low[1] + j as f64 * step;
            for i in range(0, [pa.0, pb.0, pc.0]) {
                let slot = &mut heights[j * nx + i];
                if slot.is_some() {
                    continue;
                }
                let q = (low[0] + i as f64 * step, y);
                let la = cross(q, pb, pc) / doubled;
                let lb = cross(q, pc, pa) / doubled;
                let lc = 1.0 - la - lb;
                if la >= tolerance && lb >= tolerance && lc >= tolerance {
                    *slot = Some(la * ra + lb * rb + lc * rc);
                }
            }
        }
    }
    Rasterised {
        heights,
        facing,
        folded,
    }
}

/// The median length of the mesh's edges, `None` when all have length 0 (or there is
/// no edge).
fn median_edge_length(geometry: &Geometry<'_>) -> Option<f64> {
    let mesh = geometry.mesh();
    let mut lengths: Vec<f64> = mesh
        .edges()
        .map(|e| geometry.edge_length(e))
        .filter(|&l| l > 0.0)
        .collect();
    if lengths.is_empty() {
        return None;
    }
    let middle = lengths.len() / 2;
    let (_, median, _) = lengths.select_nth_unstable_by(middle, f64::total_cmp);
    Some(*median)
}
