//! OBJ writer.

use std::io::Write;

use crate::error::IoError;
use crate::format::Precision;
use crate::text::{write_text_mesh, write_xyz};
use beltrami_halfedge::MeshData;

/// Writes `v x y z` lines (shortest decimal that reads back to the same value) and
/// 1-based `f` lines.
pub(crate) fn write_obj_to<W: Write>(
    writer: W,
    mesh: &MeshData,
    precision: Precision,
) -> Result<(), IoError> {
    write_text_mesh(writer, mesh, precision, |out| {
        writeln!(
            out,
            "# {} vertices, {} faces",
            mesh.positions.len(),
            mesh.faces.len()
        )?;
        for &p in &mesh.positions {
            write_xyz(out, "v ", p, precision)?;
        }
        for face in mesh.faces.iter() {
            out.write_all(b"f")?;
            for &i in face {
                write!(out, " {}", u64::from(i) + 1)?;
            }
            out.write_all(b"\n")?;
        }
        Ok(())
    })
}
