//! # beltrami-viz
//!
//! Line plots (SVG and PNG) and shaded, scalar-coloured renders of triangle meshes (PNG),
//! for the study's figures and reports. Output files are written atomically.

mod error;
pub mod plot;
pub mod render;

pub use error::VizError;
