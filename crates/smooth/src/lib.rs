//! # beltrami-smooth
//!
//! Laplacian diffusion smoothing, `x ← x + λ L x`, with any
//! [`WeightScheme`](beltrami_weights::WeightScheme): explicit Jacobi iterations, fixed,
//! free or curve-constrained boundaries, pinned vertices, weights recomputed every
//! iteration or frozen, and an observer that sees every iteration.
//!
//! Beyond plain diffusion ([`Method::Laplacian`]), which shrinks: Taubin's λ|μ filter
//! ([`Method::Taubin`]), the HC push-back towards the input, which works on open patches
//! ([`Method::Hc`]), a volume-preserving rescale for closed meshes
//! ([`SmoothConfig::preserve_volume`]), and implicit backward-Euler steps of any size
//! ([`Method::Implicit`]). One [`SmoothConfig`], one [`Smoother`], one observer view
//! ([`IterationView`]) and one [`SmoothReport`] serve every method. A run can be given in physical units — a
//! diffusion time in length² or a Gaussian cut-off wavelength ([`DiffusionTime`]) — and
//! can stop once it has converged ([`SmoothConfig::until_change`]).
//!
//! Three layers: [`smooth`] for one call, [`Smoother::step`] to drive iterations
//! yourself, and [`Smoother::run`] with an observer
//! `FnMut(&IterationView) -> ControlFlow<()>` (metrics, progress, early stop). The observer's
//! positions and statistics are computed when it asks for them, so an observer that only
//! counts iterations costs nothing; [`Statistics::OnDemand`] also drops the per-iteration
//! statistics of the report. A caller that no longer needs its mesh and positions gives
//! them to [`Smoother::from_owned`], which keeps them instead of copying them and hands
//! the mesh back from [`Smoother::run_owned`].
//!
//! ## Quick start
//!
//! ```
//! use std::ops::ControlFlow;
//! use beltrami_halfedge::primitives;
//! use beltrami_smooth::{SmoothConfig, Smoother};
//! use beltrami_weights::InverseDistance;
//!
//! let grid = primitives::grid(8, 8);
//! let mesh = grid.mesh().unwrap();
//! let mut max_moves = Vec::new();
//! let out = Smoother::new(&mesh, &grid.positions, &InverseDistance, SmoothConfig::new(0.8, 20))?
//!     .run(|it| {
//!         max_moves.push(it.stats().max_displacement);
//!         ControlFlow::Continue(())
//!     })?;
//! assert_eq!(max_moves.len(), 20);
//! // A flat, regular grid with a fixed boundary is already smooth: nothing moves.
//! assert!(out.positions.iter().zip(&grid.positions).all(|(a, b)| (*a - *b).length() < 1e-12));
//! # Ok::<(), beltrami_smooth::SmoothError>(())
//! ```

mod config;
mod duration;
mod error;
mod explicit;
mod implicit;
mod numbering;
mod report;
mod smoother;

pub use config::{
    Boundary, DEFAULT_LAMBDA, DiffusionTime, HC_ALPHA, HC_BETA, ImplicitSolver, Method, Reorder,
    SmoothConfig, Statistics, Summation, TAUBIN_LAMBDA, TAUBIN_PASS_BAND, WeightUpdate,
};
pub use duration::area_step;
pub use error::SmoothError;

/// The range of the largest absolute coordinate a mesh may have for implicit smoothing,
/// 2⁻⁴⁸⁰ to 2⁴⁸⁰ (about 10^±144): the implicit step computes vertex areas and
/// norms, squared lengths, which beyond about 2^±500 leave the range of numbers
/// ([`SmoothError::ImplicitScale`]). Inside it the step scales with the mesh (tested at
/// 2^±400 to 1e-14 relative), as long as its edges are not so much shorter than its
/// largest coordinate that their squares leave the range themselves. A mesh at the origin
/// alone (all coordinates zero) is not refused.
pub const IMPLICIT_COORDINATES: std::ops::RangeInclusive<f64> =
    3.203_332_952_292_961_5e-145..=3.121_748_550_315_992_2e144;
pub use report::{
    IterationView, SmoothReport, Smoothed, SolveStats, SolverReport, StepStats, StopReason,
};
pub use smoother::{OwnedFaces, Smoother, smooth};
