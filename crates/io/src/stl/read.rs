//! STL reader: detects binary or ascii, welds the triangle soup.

use beltrami_halfedge::PolygonList;

use super::weld::Welder;
use super::{BINARY_HEADER, BINARY_TRIANGLE};
use crate::error::IoError;
use crate::mesh::MeshData;
use crate::text::{Lines, has_binary_bytes, parse_number, token_text};

/// Reads a whole STL file held in memory.
///
/// A file whose length is exactly what its binary triangle count says is binary, even
/// when it starts with `solid` (many binary exporters write that). Otherwise a file
/// starting with `solid` is ascii; the rest is a binary file whose count is wrong.
pub(crate) fn read_stl(bytes: &[u8]) -> Result<MeshData, IoError> {
    if bytes.is_empty() {
        return Err(IoError::Empty);
    }
    let declared = binary_count(bytes);
    if let Some(n) = declared {
        if binary_length(n) == Some(bytes.len()) {
            return read_binary(bytes, n as usize);
        }
    }
    let count_error = |declared| IoError::StlTriangleCount {
        declared,
        file_length: bytes.len(),
    };
    if starts_with_solid(bytes) {
        return read_ascii(bytes).map_err(|e| match declared {
            // "solid" then bytes no text holds: a binary file with a wrong count.
            Some(n) if Lines::new(bytes).any(|(_, line)| has_binary_bytes(line)) => count_error(n),
            _ => e,
        });
    }
    match declared {
        Some(n) => Err(count_error(n)),
        None => Err(IoError::StlTooShort {
            file_length: bytes.len(),
        }),
    }
}

/// The triangle count of a binary header, if the file is long enough to have one.
fn binary_count(bytes: &[u8]) -> Option<u32> {
    let count = bytes.get(80..BINARY_HEADER)?;
    Some(u32::from_le_bytes([count[0], count[1], count[2], count[3]]))
}

/// The length a binary file with `n` triangles has.
fn binary_length(n: u32) -> Option<usize> {
    (n as usize)
        .checked_mul(BINARY_TRIANGLE)?
        .checked_add(BINARY_HEADER)
}

fn starts_with_solid(bytes: &[u8]) -> bool {
    let text = bytes.trim_ascii_start();
    text.get(..5)
        .is_some_and(|w| w.eq_ignore_ascii_case(b"solid"))
        && text.get(5).is_none_or(u8::is_ascii_whitespace)
}

fn read_binary(bytes: &[u8], n: usize) -> Result<MeshData, IoError> {
    // A closed triangle mesh has about half as many vertices as triangles.
    let mut welder = Welder::with_capacity(n / 2 + 3);
    let mut faces = PolygonList::with_capacity(n, 3 * n);
    let records = bytes[BINARY_HEADER..].chunks_exact(BINARY_TRIANGLE);
    for (facet, record) in records.enumerate() {
        let mut triangle = [0; 3];
        for (corner, id) in triangle.iter_mut().enumerate() {
            let at = 12 + 12 * corner;
            let p = [
                f32_at(record, at),
                f32_at(record, at + 4),
                f32_at(record, at + 8),
            ];
            *id = insert(&mut welder, p, facet, None)?;
        }
        faces.push(&triangle);
    }
    Ok(MeshData {
        positions: welder.into_positions(),
        faces,
    })
}

fn f32_at(record: &[u8], at: usize) -> f32 {
    f32::from_le_bytes([record[at], record[at + 1], record[at + 2], record[at + 3]])
}

fn insert(
    welder: &mut Welder,
    p: [f32; 3],
    facet: usize,
    line: Option<usize>,
) -> Result<u32, IoError> {
    if let Some(&value) = p.iter().find(|c| !c.is_finite()) {
        return Err(IoError::NonFiniteFacet {
            line,
            facet,
            value: f64::from(value),
        });
    }
    welder.insert(p)
}

/// Whitespace-separated tokens with their line numbers.
struct Tokens<'a> {
    lines: Lines<'a>,
    line: usize,
    rest: &'a [u8],
}

impl<'a> Tokens<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Self {
            lines: Lines::new(bytes),
            line: 1,
            rest: &[],
        }
    }

    fn next(&mut self) -> Option<(usize, &'a [u8])> {
        loop {
            if let Some(start) = self.rest.iter().position(|b| !b.is_ascii_whitespace()) {
                let rest = &self.rest[start..];
                let end = rest
                    .iter()
                    .position(u8::is_ascii_whitespace)
                    .unwrap_or(rest.len());
                self.rest = &rest[end..];
                return Some((self.line, &rest[..end]));
            }
            let (line, text) = self.lines.next()?;
            self.line = line;
            self.rest = text;
        }
    }

    /// Drops the rest of the current line (the name after `solid` or `endsolid`).
    fn skip_line(&mut self) {
        self.rest = &[];
    }

    /// The next token, which must be `keyword` (any letter case).
    fn expect(&mut self, keyword: &'static str, quoted: &'static str) -> Result<(), IoError> {
        match self.next() {
            Some((_, token)) if token.eq_ignore_ascii_case(keyword.as_bytes()) => Ok(()),
            found => Err(self.syntax(quoted, found)),
        }
    }

    /// The next token as an `f32`.
    fn number(&mut self) -> Result<(usize, f32), IoError> {
        match self.next() {
            Some((line, token)) => match parse_number(token) {
                Some(value) => Ok((line, value)),
                None => Err(self.syntax("a number", Some((line, token)))),
            },
            None => Err(self.syntax("a number", None)),
        }
    }

    fn syntax(&self, expected: &'static str, found: Option<(usize, &[u8])>) -> IoError {
        match found {
            Some((line, token)) => IoError::Syntax {
                line,
                expected,
                found: Some(token_text(token)),
            },
            None => IoError::Syntax {
                line: self.line,
                expected,
                found: None,
            },
        }
    }
}

/// `solid name`, then facets, then `endsolid name`; several solids may follow each
/// other. Keywords are matched in any letter case.
fn read_ascii(bytes: &[u8]) -> Result<MeshData, IoError> {
    let mut tokens = Tokens::new(bytes);
    let mut welder = Welder::with_capacity(0);
    let mut faces = PolygonList::new();
    tokens.expect("solid", "\"solid\"")?;
    tokens.skip_line();
    loop {
        match tokens.next() {
            Some((_, t)) if t.eq_ignore_ascii_case(b"facet") => {
                let triangle = read_facet(&mut tokens, &mut welder, faces.len())?;
                faces.push(&triangle);
            }
            Some((_, t)) if t.eq_ignore_ascii_case(b"endsolid") => {
                tokens.skip_line();
                match tokens.next() {
                    None => break,
                    Some((_, t)) if t.eq_ignore_ascii_case(b"solid") => tokens.skip_line(),
                    found => return Err(tokens.syntax("\"solid\" or the end of the file", found)),
                }
            }
            found => return Err(tokens.syntax("\"facet\" or \"endsolid\"", found)),
        }
    }
    Ok(MeshData {
        positions: welder.into_positions(),
        faces,
    })
}

/// The rest of a facet after `facet`: `normal nx ny nz` (ignored: normals are
/// recomputed from the vertices where needed), `outer loop`, three `vertex x y z`,
/// `endloop`, `endfacet`.
fn read_facet(
    tokens: &mut Tokens<'_>,
    welder: &mut Welder,
    facet: usize,
) -> Result<[u32; 3], IoError> {
    tokens.expect("normal", "\"normal\"")?;
    for _ in 0..3 {
        tokens.number()?;
    }
    tokens.expect("outer", "\"outer\"")?;
    tokens.expect("loop", "\"loop\"")?;
    let mut triangle = [0; 3];
    for id in &mut triangle {
        tokens.expect("vertex", "\"vertex\"")?;
        let (line, x) = tokens.number()?;
        let (_, y) = tokens.number()?;
        let (_, z) = tokens.number()?;
        *id = insert(welder, [x, y, z], facet, Some(line))?;
    }
    tokens.expect("endloop", "\"endloop\"")?;
    tokens.expect("endfacet", "\"endfacet\"")?;
    Ok(triangle)
}
