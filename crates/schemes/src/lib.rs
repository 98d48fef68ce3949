//! # beltrami-schemes
//!
//! Edge-preserving Laplacian weight schemes for beltrami, written only through the
//! public plug-in API of `beltrami-weights` ([`WeightScheme`]).
//!
//! The paper beltrami starts from ends by asking for "a weight function that does not
//! blur edges". [`BilateralNormal`] (`bilateral`) is one: the cotangent weight
//! attenuated by how much the two vertex normals of an edge differ, so that diffusion
//! smooths flat regions as usual but does not pull vertices across sharp edges.
//! `beltrami-study`'s `edge_preservation` measures what it buys: it compares the scheme
//! (or any scheme) with a reference scheme at equal smoothness of the flat regions, by the
//! dihedral-angle error at the feature edges and the volume loss. `docs/schemes.md` gives
//! the formulas, defaults, references, the measured numbers on the block and the
//! limitations.
//!
//! ## Quick start
//!
//! ```
//! use beltrami_halfedge::primitives;
//! use beltrami_schemes::{register_all, BilateralNormal};
//! use beltrami_smooth::{smooth, SmoothConfig};
//! use beltrami_weights::WeightRegistry;
//!
//! // Everywhere schemes are chosen by name (the CLI, the study):
//! let mut registry = WeightRegistry::with_builtins();
//! register_all(&mut registry)?;
//! assert_eq!(registry.names(), ["uniform", "distance", "cotangent", "bilateral"]);
//!
//! // Or directly, like any scheme:
//! let sphere = primitives::icosphere(2);
//! let mesh = sphere.mesh()?;
//! let out = smooth(&mesh, &sphere.positions, &BilateralNormal::default(), SmoothConfig::new(0.8, 10))?;
//! assert!(out.positions.iter().all(|p| p.is_finite() && p.length() < 1.0));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod bilateral;
mod error;

use beltrami_weights::WeightRegistry;
#[cfg(doc)]
use beltrami_weights::WeightScheme;

pub use bilateral::{BaseWeight, BilateralNormal, DEFAULT_SIGMA};
pub use error::SchemesError;

/// Registers every scheme of this crate with its default parameters, in this order:
/// `bilateral` ([`BilateralNormal::default`]).
///
/// # Errors
/// [`SchemesError::Weights`] when a name is already taken in `registry` (the schemes
/// registered before the clash stay registered).
///
/// # Examples
/// ```
/// use beltrami_schemes::register_all;
/// use beltrami_weights::WeightRegistry;
///
/// let mut registry = WeightRegistry::new();
/// register_all(&mut registry)?;
/// assert_eq!(registry.names(), ["bilateral"]);
/// assert!(register_all(&mut registry).is_err()); // already there
/// # Ok::<(), beltrami_schemes::SchemesError>(())
/// ```
pub fn register_all(registry: &mut WeightRegistry) -> Result<(), SchemesError> {
    registry.register(BilateralNormal::default())?;
    Ok(())
}
