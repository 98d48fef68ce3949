//! OBJ writer.

use std::io::{BufWriter, Write};

use crate::error::IoError;
use crate::format::Precision;
use crate::validate::{check_faces, check_positions};
use beltrami_halfedge::MeshData;

/// Writes `v x y z` lines (shortest decimal that reads back to the same value) and
/// 1-based `f` lines.
pub(crate) fn write_obj_to<W: Write>(
    writer: W,
    mesh: &MeshData,
    precision: Precision,
) -> Result<(), IoError> {
    check_positions(&mesh.positions, precision == Precision::Single)?;
    check_faces(mesh, None)?;
    let mut out = BufWriter::new(writer);
    write(&mut out, mesh, precision)
        .and_then(|()| out.flush())
        .map_err(IoError::io("write the file"))
}

#[allow(
    clippy::cast_possible_truncation,
    reason = "single precision output is asked for; the range was checked"
)]
fn write<W: Write>(out: &mut W, mesh: &MeshData, precision: Precision) -> std::io::Result<()> {
    writeln!(
        out,
        "# {} vertices, {} faces",
        mesh.positions.len(),
        mesh.faces.len()
    )?;
    for p in &mesh.positions {
        match precision {
            Precision::Double => writeln!(out, "v {} {} {}", p.x, p.y, p.z)?,
            Precision::Single => {
                writeln!(out, "v {} {} {}", p.x as f32, p.y as f32, p.z as f32)?;
            }
        }
    }
    for face in mesh.faces.iter() {
        out.write_all(b"f")?;
        for &i in face {
            write!(out, " {}", u64::from(i) + 1)?;
        }
        out.write_all(b"\n")?;
    }
    Ok(())
}
