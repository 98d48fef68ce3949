//! STL, binary and ascii, written by hand.
//!
//! No maintained STL crate welds the way metrology needs it (identical `f32` bit
//! patterns, with `-0.0` treated as `0.0`, then within a tolerance by a rule that
//! depends on the file alone; ids in order of first appearance), and the format is
//! small enough to read directly.

mod read;
mod weld;
mod write;

pub(crate) use read::{declared_triangles, read_stl};
pub(crate) use write::write_stl_to;

/// Bytes before the first triangle of a binary STL: an 80-byte header and the count.
const BINARY_HEADER: usize = 84;
/// Bytes per binary triangle: normal, three vertices (12 `f32`) and a `u16`.
const BINARY_TRIANGLE: usize = 50;
