//! OFF writer.

use std::io::{BufWriter, Write};

use crate::error::IoError;
use crate::format::Precision;
use crate::validate::{check_faces, check_positions};
use beltrami_halfedge::MeshData;

/// Writes `OFF`, the counts (`vertices faces 0`), `x y z` lines (the shortest decimal
/// that reads back to the same value) and 0-based `n i0 … i(n-1)` face lines.
pub(crate) fn write_off_to<W: Write>(
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
    writeln!(out, "OFF\n{} {} 0", mesh.positions.len(), mesh.faces.len())?;
    for p in &mesh.positions {
        match precision {
            Precision::Double => writeln!(out, "{} {} {}", p.x, p.y, p.z)?,
            Precision::Single => {
                writeln!(out, "{} {} {}", p.x as f32, p.y as f32, p.z as f32)?;
            }
        }
    }
    for face in mesh.faces.iter() {
        write!(out, "{}", face.len())?;
        for &i in face {
            write!(out, " {i}")?;
        }
        out.write_all(b"\n")?;
    }
    Ok(())
}
