//! Checks the writers make before the first byte is written, so that every file they
//! produce can be read back.

use glam::DVec3;

use crate::error::IoError;
use beltrami_halfedge::MeshData;

/// Every coordinate finite; with `single`, also within the range of `f32`.
pub(crate) fn check_positions(positions: &[DVec3], single: bool) -> Result<(), IoError> {
    for (vertex, p) in positions.iter().enumerate() {
        for value in p.to_array() {
            if !value.is_finite() {
                return Err(IoError::NonFiniteCoordinate {
                    line: None,
                    vertex,
                    value,
                });
            }
            #[allow(clippy::cast_possible_truncation, reason = "the cast is the check")]
            if single && (value as f32).is_infinite() {
                return Err(IoError::CoordinateOutOfRange { vertex, value });
            }
        }
    }
    Ok(())
}

/// Every face index names a vertex. `first_line` is the line of face 0 in a text
/// file with one face per line.
pub(crate) fn check_faces(mesh: &MeshData, first_line: Option<usize>) -> Result<(), IoError> {
    let n_vertices = mesh.positions.len();
    if mesh
        .faces
        .max_index()
        .is_none_or(|max| (max as usize) < n_vertices)
    {
        return Ok(());
    }
    for (face, indices) in mesh.faces.iter().enumerate() {
        if let Some(&index) = indices.iter().find(|&&i| i as usize >= n_vertices) {
            return Err(IoError::FaceIndexOutOfRange {
                line: first_line.map(|l| l + face),
                face,
                index: i64::from(index),
                n_vertices,
            });
        }
    }
    Ok(())
}
