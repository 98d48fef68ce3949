//! # beltrami-viz
//!
//! Line plots (SVG and PNG) and shaded, scalar-coloured renders of triangle meshes (PNG),
//! for the study's figures and reports: metrics against iterations per weight scheme
//! ([`plot`]), and smoothed meshes coloured by signed distance to a reference, laid out
//! in a grid of schemes × iteration counts ([`render`]).
//!
//! - **No system fonts.** All text in PNG output is rasterised from the bundled DejaVu
//!   Sans (`assets/`, Bitstream Vera licence), so figures look the same on a machine
//!   without fonts.
//! - **Deterministic.** The same input gives the same bytes.
//! - **Atomic files.** [`plot::write_plot`] and [`render::Image::write_png`] write
//!   through [`beltrami_io::write_bytes_atomic`]: a failure never leaves a half-written
//!   file.
//!
//! ## Quick start
//!
//! ```
//! use beltrami_halfedge::primitives;
//! use beltrami_viz::plot::{LinePlot, Series, plot_svg};
//! use beltrami_viz::render::{ColorMap, View, render_mesh};
//!
//! let mut plot = LinePlot::new("RMS distance", "iterations", "RMS (mm)");
//! plot.series.push(Series::new("cotangent", [(0.0, 3e-4), (10.0, 1e-4), (20.0, 5e-5)]));
//! let svg = plot_svg(&plot, 640, 400)?;
//! assert!(svg.contains("RMS distance"));
//!
//! let sphere = primitives::icosphere(3);
//! let mesh = sphere.mesh()?;
//! let z: Vec<f64> = sphere.positions.iter().map(|p| p.z).collect();
//! let view = View::default_for(&sphere.positions);
//! let image = render_mesh(&mesh, &sphere.positions, Some(&z), &ColorMap::symmetric(1.0), &view, None, 200, 150)?;
//! assert_eq!((image.width, image.height), (200, 150));
//! let png = image.encode_png()?;
//! assert_eq!(&png[1..4], b"PNG");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod error;
mod font;
pub mod plot;
pub mod render;
mod ticks;

pub use error::VizError;
