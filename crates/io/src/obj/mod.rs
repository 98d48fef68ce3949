//! Wavefront OBJ (positions and polygon faces), written by hand.

mod read;
mod write;

pub(crate) use read::read_obj;
pub(crate) use write::write_obj_to;
