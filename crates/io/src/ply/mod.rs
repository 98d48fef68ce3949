//! Stanford PLY, through `ply-rs-bw` (an implementation detail: none of its types
//! appear in the public API).

mod fast;
mod read;
mod records;
mod write;

pub(crate) use read::{declared_counts, read_ply};
pub(crate) use write::write_ply_to;
