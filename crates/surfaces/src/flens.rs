//! The F-lens: an open free-form optical surface on a 68 × 33 grid.

use beltrami_halfedge::{DVec3, PolygonList};

use crate::surface::Surface;

/// Parameters of the F-lens sag, a biconic plus an XY polynomial (Zemax "Biconic" and
/// "Extended Polynomial" conventions), in millimetres:
///
/// ```text
/// z(x, y) = (c_x x² + c_y y²) / (1 + √(1 − (1 + k_x) c_x² x² − (1 + k_y) c_y² y²))
///           + A40 x⁴ + A22 x² y² + A04 y⁴ + A21 x² y
/// ```
///
/// The paper's F-lens ("F-theta" scan-lens free-form) is not published; these defaults
/// give its exact counts (68 × 33 grid: 2244 vertices, 4288 faces) and a smooth sag of
/// 0 … 8.95 mm over a 60 × 28.66 mm aperture with 0.8955 mm pitch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FLensParams {
    /// Grid points along x.
    pub nx: u32,
    /// Grid points along y.
    pub ny: u32,
    /// Half-width of the aperture along x, mm.
    pub half_x: f64,
    /// Radius of curvature along x (1/c_x), mm.
    pub radius_x: f64,
    /// Conic constant along x.
    pub conic_x: f64,
    /// Radius of curvature along y (1/c_y), mm.
    pub radius_y: f64,
    /// Conic constant along y.
    pub conic_y: f64,
    /// Coefficients (A40, A22, A04, A21), in mm^(1−i−j).
    pub poly: [f64; 4],
}

impl Default for FLensParams {
    fn default() -> Self {
        Self {
            nx: 68,
            ny: 33,
            half_x: 30.0,
            radius_x: 80.0,
            conic_x: -1.5,
            radius_y: 25.0,
            conic_y: 0.0,
            poly: [-2.0e-6, 1.5e-6, -1.0e-5, 2.0e-5],
        }
    }
}

impl FLensParams {
    /// The grid pitch (equal in x and y), mm.
    #[must_use]
    pub fn pitch(&self) -> f64 {
        2.0 * self.half_x / f64::from(self.nx - 1)
    }

    /// The sag z(x, y), mm: the analytic surface the mesh samples.
    #[must_use]
    pub fn sag(&self, x: f64, y: f64) -> f64 {
        let (cx, cy) = (1.0 / self.radius_x, 1.0 / self.radius_y);
        let root =
            1.0 - (1.0 + self.conic_x) * cx * cx * x * x - (1.0 + self.conic_y) * cy * cy * y * y;
        let [a40, a22, a04, a21] = self.poly;
        (cx * x * x + cy * y * y) / (1.0 + root.max(0.0).sqrt())
            + a40 * x.powi(4)
            + a22 * x * x * y * y
            + a04 * y.powi(4)
            + a21 * x * x * y
    }
}

/// The F-lens mesh: an `nx × ny` grid of equal pitch centred on the origin, each cell split
/// along its (i, j)–(i+1, j+1) diagonal, vertices lifted to the sag. Vertex `(i, j)` has
/// index `j·nx + i`. Millimetres. Open, one boundary loop.
///
/// # Panics
/// If `nx` or `ny` is below 2.
#[must_use]
pub fn flens(params: &FLensParams) -> Surface {
    let (nx, ny) = (params.nx, params.ny);
    assert!(
        nx >= 2 && ny >= 2,
        "the F-lens grid needs at least 2 x 2 points"
    );
    let h = params.pitch();
    let half_y = h * f64::from(ny - 1) / 2.0;
    let mut positions = Vec::with_capacity((nx * ny) as usize);
    for j in 0..ny {
        for i in 0..nx {
            let x = -params.half_x + h * f64::from(i);
            let y = -half_y + h * f64::from(j);
            positions.push(DVec3::new(x, y, params.sag(x, y)));
        }
    }
    let id = |i: u32, j: u32| j * nx + i;
    let mut faces = PolygonList::with_capacity((2 * (nx - 1) * (ny - 1)) as usize, 0);
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            faces.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    Surface::new("flens", positions, faces, "mm")
}
