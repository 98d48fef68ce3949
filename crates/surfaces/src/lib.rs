//! # beltrami-surfaces
//!
//! The test surfaces of the Laplace–Beltrami comparison (the paper's Table 1) and
//! seeded Gaussian noise along vertex normals, and seeded round holes ([`cut_holes`]) as
//! a scan leaves them:
//!
//! | surface | what | vertices / faces | unit |
//! |---|---|---|---|
//! | [`flens`] | open free-form optical surface (biconic + XY polynomial) on a 68 × 33 grid | 2244 / 4288 (as the paper) | mm |
//! | [`sphere`] | unit icosphere, 6 subdivisions | 40962 / 81920 (as the paper) | 1 |
//! | [`block`] | closed genus-3 box with three through-holes, sharp edges | 8780 / 17568 (paper: 8771 / 17550) | mm |
//! | [`golf_ball`] | regulation-size ball with 362 icosahedral dimples | 79212 / 158420 (paper: 78721 / 157438) | mm |
//!
//! ## Quick start
//!
//! ```
//! use beltrami_surfaces::{add_normal_noise, flens, FLensParams, NoiseLevel};
//!
//! let lens = flens(&FLensParams::default());
//! let mesh = lens.mesh().unwrap();
//! assert_eq!((mesh.n_vertices(), mesh.n_faces()), (2244, 4288));
//! let (noisy, sigma) =
//!     add_normal_noise(&mesh, &lens.positions, NoiseLevel::RelativeToMeanEdge(0.2), 42)?;
//! assert!(sigma > 0.0 && noisy.len() == 2244);
//! # Ok::<(), beltrami_surfaces::SurfaceError>(())
//! ```

mod block;
mod error;
mod flens;
mod golfball;
mod holes;
mod noise;
mod surface;

pub use block::{BlockParams, block};
pub use error::SurfaceError;
pub use flens::{FLensParams, flens};
pub use golfball::{GolfBallParams, geodesic_sphere, golf_ball};
pub use holes::{CutHoles, cut_holes};
pub use noise::{NoiseLevel, NormalRng, add_normal_noise};
pub use surface::{Surface, shuffle_order};

/// The paper's unit sphere: an icosphere with `level` subdivisions (the paper uses 6:
/// 40962 vertices, 81920 faces), radius 1.
#[must_use]
pub fn sphere(level: u32) -> Surface {
    let p = beltrami_halfedge::primitives::icosphere(level);
    Surface {
        name: "sphere",
        data: p,
        unit: "1",
    }
}

/// The four built-in surfaces by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum SurfaceKind {
    /// [`flens`] with default parameters.
    FLens,
    /// [`sphere`] with 6 subdivisions.
    Sphere,
    /// [`block`] with default parameters.
    Block,
    /// [`golf_ball`] with default parameters.
    GolfBall,
}

impl SurfaceKind {
    /// All built-in surfaces, in the paper's order.
    pub const ALL: [SurfaceKind; 4] = [Self::FLens, Self::Sphere, Self::Block, Self::GolfBall];

    /// The surface's name: `flens`, `sphere`, `block`, `golfball`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::FLens => "flens",
            Self::Sphere => "sphere",
            Self::Block => "block",
            Self::GolfBall => "golfball",
        }
    }

    /// The surface called `name`.
    ///
    /// # Errors
    /// [`SurfaceError::UnknownSurface`].
    pub fn from_name(name: &str) -> Result<Self, SurfaceError> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| SurfaceError::UnknownSurface {
                name: name.to_string(),
            })
    }

    /// Generates the surface with its default parameters (the paper's sizes).
    #[must_use]
    pub fn generate(self) -> Surface {
        self.generate_sized(Size::Paper)
    }

    /// Generates the surface at the paper's size or as a small, fast variant of the same
    /// shape (for tests and quick looks).
    #[must_use]
    pub fn generate_sized(self, size: Size) -> Surface {
        match (self, size) {
            (Self::FLens, Size::Paper) => flens(&FLensParams::default()),
            (Self::FLens, Size::Small) => flens(&FLensParams {
                nx: 24,
                ny: 12,
                ..FLensParams::default()
            }),
            (Self::Sphere, Size::Paper) => sphere(6),
            (Self::Sphere, Size::Small) => sphere(3),
            (Self::Block, Size::Paper) => block(&BlockParams::default()),
            (Self::Block, Size::Small) => block(&BlockParams {
                cells: [9, 9, 17],
                pitch: 20.0 / 9.0,
                hole: [2, 2],
                ..BlockParams::default()
            }),
            (Self::GolfBall, Size::Paper) => golf_ball(&GolfBallParams::default()),
            (Self::GolfBall, Size::Small) => golf_ball(&GolfBallParams {
                mesh_frequency: 24,
                dimple_frequency: 2,
                dimple_diameter: 8.0,
                dimple_depth: 0.4,
                ..GolfBallParams::default()
            }),
        }
    }
}

/// The size of a generated surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Size {
    /// The paper's vertex counts (Table 1).
    #[default]
    Paper,
    /// A few hundred to a few thousand vertices: the same shapes, coarser.
    Small,
}
