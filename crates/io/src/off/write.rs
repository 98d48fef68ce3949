//! OFF writer.

use std::io::Write;

use crate::error::IoError;
use crate::format::Precision;
use crate::text::{write_text_mesh, write_xyz};
use beltrami_halfedge::MeshData;

/// Writes `OFF`, the counts (`vertices faces 0`), `x y z` lines (the shortest decimal
/// that reads back to the same value) and 0-based `n i0 … i(n-1)` face lines.
pub(crate) fn write_off_to<W: Write>(
    writer: W,
    mesh: &MeshData,
    precision: Precision,
) -> Result<(), IoError> {
    write_text_mesh(writer, mesh, precision, |out| {
        writeln!(out, "OFF\n{} {} 0", mesh.positions.len(), mesh.faces.len())?;
        for &p in &mesh.positions {
            write_xyz(out, "", p, precision)?;
        }
        for face in mesh.faces.iter() {
            write!(out, "{}", face.len())?;
            for &i in face {
                write!(out, " {i}")?;
            }
            out.write_all(b"\n")?;
        }
        Ok(())
    })
}
