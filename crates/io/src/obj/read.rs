//! OBJ reader: a line parser for `v` and `f`.

use std::io::BufRead;

use beltrami_halfedge::PolygonList;
use glam::DVec3;

use crate::error::IoError;
use crate::mesh::MeshData;
use crate::text::{LineReader, has_binary_bytes, parse_number, token_text, tokens};
use crate::validate::check_faces;

/// Reads an OBJ file line by line from `reader`.
///
/// `v x y z [w]` adds a vertex (values after `z`, such as `w` or vertex colours, are
/// ignored); `f` adds a polygon whose corners are `a`, `a/b`, `a//c` or `a/b/c`, of
/// which only the vertex index `a` is used: 1-based, or negative to count back from
/// the last vertex defined so far. Every other statement (`vt`, `vn`, `g`, `usemtl`,
/// …) is ignored, and so is everything after a `#`. Line continuations (`\` at the end of a line) are not
/// supported.
pub(crate) fn read_obj(reader: impl BufRead) -> Result<MeshData, IoError> {
    let mut lines = LineReader::new(reader);
    let mut positions = Vec::new();
    let mut faces = PolygonList::new();
    let mut corners = Vec::new();
    // Faces with an index beyond the vertices defined so far (a forward reference,
    // checked at the end), with their lines: the line of an error without a second
    // pass over the file.
    let mut forward: Vec<(usize, usize)> = Vec::new();
    while let Some(line) = lines.next_line()? {
        let text = lines.line();
        // `#` starts a comment, also after a statement.
        let statement = text
            .iter()
            .position(|&b| b == b'#')
            .map_or(text, |start| &text[..start]);
        let mut words = tokens(statement);
        match words.next() {
            Some(b"v") => {
                let mut p = [0.0_f64; 3];
                for c in &mut p {
                    *c = match words.next() {
                        Some(token) => parse_number(token).ok_or_else(|| IoError::Syntax {
                            line,
                            expected: "a number",
                            found: Some(token_text(token)),
                        })?,
                        None => {
                            return Err(IoError::Syntax {
                                line,
                                expected: "a number",
                                found: None,
                            });
                        }
                    };
                }
                if let Some(&value) = p.iter().find(|c| !c.is_finite()) {
                    return Err(IoError::NonFiniteCoordinate {
                        line: Some(line),
                        vertex: positions.len(),
                        value,
                    });
                }
                positions.push(DVec3::from_array(p));
            }
            Some(b"f") => {
                corners.clear();
                for corner in words {
                    corners.push(vertex_index(corner, positions.len(), line, faces.len())?);
                }
                if corners.iter().any(|&c| c as usize >= positions.len()) {
                    forward.push((faces.len(), line));
                }
                faces.push(&corners);
            }
            _ => {
                if has_binary_bytes(text) {
                    return Err(IoError::NotText { line });
                }
            }
        }
    }
    if lines.lines_read() == 0 {
        return Err(IoError::Empty);
    }
    let mesh = MeshData { positions, faces };
    // Positive indices may refer forward; check them now that all vertices are known.
    if let Err(error) = check_faces(&mesh, None) {
        return Err(match error {
            IoError::FaceIndexOutOfRange {
                face,
                index,
                n_vertices,
                ..
            } => IoError::FaceIndexOutOfRange {
                line: forward
                    .binary_search_by_key(&face, |&(f, _)| f)
                    .ok()
                    .map(|i| forward[i].1),
                face,
                index: index + 1,
                n_vertices,
            },
            other => other,
        });
    }
    Ok(mesh)
}

/// The 0-based vertex of a corner token `a[/b[/c]]`; `defined` vertices precede it.
fn vertex_index(corner: &[u8], defined: usize, line: usize, face: usize) -> Result<u32, IoError> {
    let text = corner.split(|&b| b == b'/').next().unwrap_or_default();
    let index: i64 = parse_number(text).ok_or_else(|| IoError::Syntax {
        line,
        expected: "a vertex index",
        found: Some(token_text(corner)),
    })?;
    let out_of_range = || IoError::FaceIndexOutOfRange {
        line: Some(line),
        face,
        index,
        n_vertices: defined,
    };
    match index {
        0 => Err(IoError::ZeroIndex { line, face }),
        1.. => u32::try_from(index - 1).map_err(|_| out_of_range()),
        _ => {
            let back = usize::try_from(index.unsigned_abs()).map_err(|_| out_of_range())?;
            let vertex = defined.checked_sub(back).ok_or_else(out_of_range)?;
            u32::try_from(vertex).map_err(|_| out_of_range())
        }
    }
}
