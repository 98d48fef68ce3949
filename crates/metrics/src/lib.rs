//! # beltrami-metrics
//!
//! What a metrologist measures after smoothing: distances from a mesh to a reference
//! surface (closest point on the closest triangle, signed, Hausdorff), normal deviation
//! between meshes of the same topology, least-squares sphere, circle and cylinder fits,
//! boundary and edge distortion, cross-section profiles, and the ISO 25178-2 areal
//! parameters of a residual surface.
//!
//! This crate does not depend on the smoothing crate: a smoother's observer joins them.
//! All quantities are `f64`, in the unit of the input positions (lengths), its square
//! (areas) or cube (volumes); angles are reported in degrees where the name says so.

pub mod distance;
pub mod distortion;
mod error;
pub mod fits;
pub mod measures;
pub mod normals;
pub mod profile;
pub mod residual;
mod sum;

pub use error::MetricsError;
