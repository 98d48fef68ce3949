//! OBJ reader: a line parser for `v` and `f`.

use std::io::BufRead;

use beltrami_halfedge::PolygonList;
use glam::DVec3;

use crate::error::IoError;
use crate::format::MeshFormat;
use crate::text::{LineReader, has_binary_bytes, parse_number, token_text, tokens};
use crate::validate::check_faces;
use beltrami_halfedge::MeshData;

/// The statements of the OBJ specification (Wavefront, version 3.0) other than `v`
/// and `f`, superseded ones included: read past without effect. Free-form geometry,
/// texture coordinates, normals, groups, materials, points (`p`) and lines (`l`) are
/// not part of a polygon mesh.
const IGNORED: [&[u8]; 42] = [
    b"vt",
    b"vn",
    b"vp",
    b"p",
    b"l",
    b"g",
    b"o",
    b"s",
    b"mg",
    b"usemtl",
    b"mtllib",
    b"usemap",
    b"maplib",
    b"cstype",
    b"deg",
    b"bmat",
    b"step",
    b"curv",
    b"curv2",
    b"surf",
    b"parm",
    b"trim",
    b"hole",
    b"scrv",
    b"sp",
    b"end",
    b"con",
    b"lod",
    b"ctech",
    b"stech",
    b"shadow_obj",
    b"trace_obj",
    b"call",
    b"csh",
    b"bevel",
    b"c_interp",
    b"d_interp",
    b"res",
    b"bsp",
    b"bzp",
    b"cdc",
    b"cdp",
];

/// Reads an OBJ file line by line from `reader`.
///
/// `v x y z [w]` adds a vertex (values after `z`, such as `w` or vertex colours, are
/// ignored); `f` adds a polygon whose corners are `a`, `a/b`, `a//c` or `a/b/c`, of
/// which only the vertex index `a` is used: 1-based, or negative to count back from
/// the last vertex defined so far. The other statements of the specification (`vt`,
/// `vn`, `g`, `usemtl`, `l`, `p`, …) are ignored, and so is everything after a `#`.
/// A `\` that ends the statement part of a line (before any `#`) joins the next line
/// to it; errors name the first line of a joined statement. Lines end at `\n`,
/// `\r\n` or a lone `\r`; a UTF-8 byte order mark at the start is skipped.
///
/// Words that are no OBJ statement are ignored in a file that has vertices; in a file
/// without any `v` line, the first of them is an [`IoError::NotObj`] (the file is not
/// OBJ at all: a PLY, STL or OFF file with the wrong extension reads as no mesh
/// instead of an empty one). A file with nothing but whitespace is
/// [`IoError::Empty`].
pub(crate) fn read_obj(reader: impl BufRead) -> Result<MeshData, IoError> {
    let mut lines = LineReader::new(reader);
    let mut positions = Vec::new();
    let mut faces = PolygonList::new();
    let mut corners = Vec::new();
    // Faces with an index beyond the vertices defined so far (a forward reference,
    // checked at the end), with their lines: the line of an error without a second
    // pass over the file.
    let mut forward: Vec<(usize, usize)> = Vec::new();
    // The first word that is no OBJ statement, with its line.
    let mut unknown: Option<(usize, String)> = None;
    let mut blank = true;
    // A statement continued over several lines, joined.
    let mut joined = Vec::new();
    while let Some(line) = lines.next_line()? {
        let text = lines.line();
        blank &= text.iter().all(u8::is_ascii_whitespace);
        let mut statement = without_comment(text);
        if continued(statement).is_some() {
            join_continued(&mut lines, &mut joined)?;
            statement = &joined;
        }
        let mut words = tokens(statement);
        match words.next() {
            Some(b"v") => positions.push(parse_vertex(words, line, positions.len())?),
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
            word => {
                // Control bytes: a binary file (checked here only, to keep the `v` and
                // `f` lines fast).
                if has_binary_bytes(lines.line()) || has_binary_bytes(statement) {
                    return Err(IoError::NotText { line });
                }
                if let Some(word) = word
                    && unknown.is_none()
                    && !IGNORED.contains(&word)
                {
                    unknown = Some((line, token_text(word)));
                }
            }
        }
    }
    if blank {
        return Err(IoError::Empty);
    }
    if let (true, Some((line, keyword))) = (positions.is_empty(), unknown) {
        return Err(IoError::NotObj {
            line,
            format: format_named_by(&keyword),
            keyword,
        });
    }
    let mesh = MeshData { positions, faces };
    check_indices(&mesh, &forward)?;
    Ok(mesh)
}

/// The position of a `v` statement of line `line` that defines vertex `vertex`, from
/// the words after `v`: three finite numbers (any further ones are ignored).
#[inline]
fn parse_vertex<'a>(
    mut words: impl Iterator<Item = &'a [u8]>,
    line: usize,
    vertex: usize,
) -> Result<DVec3, IoError> {
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
            vertex,
            value,
        });
    }
    Ok(DVec3::from_array(p))
}

/// Checks the face indices now that all vertices are known (positive indices may refer
/// forward); an index out of range is reported with its 1-based value and the line of
/// its face, found among the faces with a forward reference (`forward`: face and line,
/// by face).
fn check_indices(mesh: &MeshData, forward: &[(usize, usize)]) -> Result<(), IoError> {
    check_faces(mesh, None).map_err(|error| match error {
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
    })
}

/// The line before its `#` comment.
fn without_comment(text: &[u8]) -> &[u8] {
    text.iter()
        .position(|&b| b == b'#')
        .map_or(text, |start| &text[..start])
}

/// The statement without its final `\`, when it ends with one (trailing whitespace
/// aside): it continues on the next line.
fn continued(statement: &[u8]) -> Option<&[u8]> {
    statement.trim_ascii_end().strip_suffix(b"\\")
}

/// Joins the current line of `lines`, which ends with `\`, and the lines it continues
/// on into `joined` (each `\` replaced by a space). A `\` on the last line of the
/// file continues on nothing.
fn join_continued(
    lines: &mut LineReader<impl BufRead>,
    joined: &mut Vec<u8>,
) -> Result<(), IoError> {
    joined.clear();
    let mut part = continued(without_comment(lines.line())).unwrap_or_default();
    loop {
        joined.extend_from_slice(part);
        joined.push(b' ');
        if lines.next_line()?.is_none() {
            return Ok(());
        }
        let statement = without_comment(lines.line());
        match continued(statement) {
            Some(rest) => part = rest,
            None => {
                joined.extend_from_slice(statement);
                return Ok(());
            }
        }
    }
}

/// The format whose files start with `word`, for a hint in [`IoError::NotObj`].
fn format_named_by(word: &str) -> Option<MeshFormat> {
    if word == "ply" {
        Some(MeshFormat::Ply)
    } else if word.eq_ignore_ascii_case("solid") {
        Some(MeshFormat::Stl)
    } else if crate::off::is_off_keyword(word.as_bytes()) {
        Some(MeshFormat::Off)
    } else {
        None
    }
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
