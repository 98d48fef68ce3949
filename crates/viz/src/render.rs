//! Shaded, scalar-coloured renders of triangle meshes (PNG), and figure grids of them.
//!
//! [`render_mesh`] draws a mesh with an orthographic camera ([`View`]), a depth buffer,
//! smooth shading from area-weighted vertex normals with two-sided Lambert light, and
//! per-vertex scalars (a signed distance to a reference, say) through a diverging
//! blue–white–red [`ColorMap`]. [`grid`] assembles renders into a figure with a title,
//! row and column labels and a colour bar; [`render_with_colorbar`] draws one mesh with
//! its colour bar ([`ColorBar`]) below, at an exact image size. Text is rasterised from
//! the bundled DejaVu Sans, never from system fonts.
//!
//! The rasteriser is written here: no maintained crate offers a small, deterministic,
//! z-buffered triangle rasteriser with per-vertex colours and smooth shading without
//! pulling in a GPU stack or a scene graph, and the figures must be byte-identical from
//! run to run and machine to machine.
//!
//! # Examples
//! ```
//! use beltrami_halfedge::{DVec3, primitives};
//! use beltrami_viz::render::{ColorMap, View, grid, render_mesh};
//!
//! let sphere = primitives::icosphere(3);
//! let mesh = sphere.mesh()?;
//! let z: Vec<f64> = sphere.positions.iter().map(|p| p.z).collect();
//! let map = ColorMap::symmetric(1.0);
//! let frame = Some((DVec3::splat(-1.0), DVec3::splat(1.0)));
//! let panel = render_mesh(&mesh, &sphere.positions, Some(&z), &map, &View::from_side(), frame, 160, 120)?;
//! let figure = grid(&[panel], 1, &[], &[], "z on the unit sphere", Some((&map, "z (mm)")))?;
//! let png = figure.encode_png()?;
//! assert_eq!(&png[1..4], b"PNG");
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod colorbar;
mod colormap;
mod grid;
mod image;
mod raster;
mod view;

pub use colorbar::{ColorBar, ColorBarTicks, MIN_COLORBAR_RENDER_SIZE, render_with_colorbar};
pub use colormap::ColorMap;
pub use grid::{MAX_GRID_SIZE, grid};
pub use image::Image;
pub use raster::{
    AMBIENT, BACKGROUND, FRAME_MARGIN, HEAD_LIGHT, KEY_LIGHT, MAX_RENDER_SIZE, MAX_SAMPLES,
    NEUTRAL, RenderOptions, render_mesh, render_mesh_with,
};
pub use view::View;
