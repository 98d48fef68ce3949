//! STL reader: detects binary or ascii, welds the triangle soup.

use std::io::{BufRead, Read, Seek, SeekFrom};

use beltrami_halfedge::PolygonList;
use glam::DVec3;

use super::weld::{Welder, weld_within};
use super::{BINARY_HEADER, BINARY_TRIANGLE};
use crate::error::IoError;
use crate::read_options::{ReadReport, Weld};
use crate::text::{BOM, LineReader, any_binary_bytes, parse_number, stream_len, token_text};
use beltrami_halfedge::MeshData;

/// Reads an STL file from `reader`, streaming its triangles, and welds its corners as
/// `weld` says (see [`Weld`] for the rule).
///
/// A file whose length is exactly what its binary triangle count says is binary, even
/// when it starts with `solid` (many binary exporters write that). Otherwise a file
/// starting with `solid` is ascii; the rest is a binary file whose count is wrong.
pub(crate) fn read_stl<R: BufRead + Seek>(
    reader: R,
    weld: &Weld,
) -> Result<(MeshData, ReadReport), IoError> {
    let Soup {
        positions,
        triangles,
    } = read_welded_exactly(reader)?;
    let distance = weld.distance(diagonal(&positions))?;
    if distance == 0.0 {
        let report = ReadReport {
            weld_distance: Some(0.0),
            ..ReadReport::default()
        };
        let faces = PolygonList::from_triangles(&triangles);
        return Ok((MeshData { positions, faces }, report));
    }
    let welded = weld_within(positions, &triangles, distance);
    let report = ReadReport {
        weld_distance: Some(distance),
        welded_vertices: welded.merged,
        dropped_faces: welded.dropped,
        ..ReadReport::default()
    };
    let mesh = MeshData {
        positions: welded.positions,
        faces: welded.faces,
    };
    Ok((mesh, report))
}

/// The diagonal of the bounding box of `positions` (0 for none).
fn diagonal(positions: &[DVec3]) -> f64 {
    let Some(&first) = positions.first() else {
        return 0.0;
    };
    let (low, high) = positions
        .iter()
        .fold((first, first), |(low, high), &p| (low.min(p), high.max(p)));
    (high - low).length()
}

/// Triangles on exactly welded vertices.
struct Soup {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

/// The triangle soup with identical corners welded (see [`Welder`]).
fn read_welded_exactly<R: BufRead + Seek>(mut reader: R) -> Result<Soup, IoError> {
    let length = stream_len(&mut reader)?;
    if length == 0 {
        return Err(IoError::Empty);
    }
    let file_length = usize::try_from(length).unwrap_or(usize::MAX);
    let mut head = Vec::with_capacity(BINARY_HEADER);
    (&mut reader)
        .take(BINARY_HEADER as u64)
        .read_to_end(&mut head)
        .map_err(IoError::io("read the file"))?;
    let declared = binary_count(&head);
    if let Some(n) = declared
        && binary_length(n) == Some(file_length)
    {
        return read_binary(reader, n as usize);
    }
    let count_error = |declared| IoError::StlTriangleCount {
        declared,
        file_length,
    };
    rewind(&mut reader)?;
    let start = first_word(&mut reader)?;
    if start == Start::Blank {
        return Err(IoError::Empty);
    }
    if start == Start::Solid {
        rewind(&mut reader)?;
        return match read_ascii(&mut reader) {
            Ok(mesh) => Ok(mesh),
            Err(e) => match declared {
                // "solid" then bytes no text holds: a binary file with a wrong count.
                Some(n) if rewind(&mut reader).is_ok() && any_binary_bytes(&mut reader)? => {
                    Err(count_error(n))
                }
                _ => Err(e),
            },
        };
    }
    match declared {
        Some(n) => Err(count_error(n)),
        None => Err(IoError::StlTooShort { file_length }),
    }
}

fn rewind(reader: &mut impl Seek) -> Result<(), IoError> {
    reader
        .seek(SeekFrom::Start(0))
        .map(drop)
        .map_err(IoError::io("read the file"))
}

/// The triangle count of a binary STL read from the start of `reader`, when the file
/// is one (its length, `length` bytes, is what the count says); `None` for ascii.
pub(crate) fn declared_triangles(
    reader: &mut impl Read,
    length: u64,
) -> Result<Option<usize>, IoError> {
    let mut header = Vec::with_capacity(BINARY_HEADER);
    reader
        .take(BINARY_HEADER as u64)
        .read_to_end(&mut header)
        .map_err(IoError::io("read the file"))?;
    Ok(binary_count(&header)
        .filter(|&n| binary_length(n).is_some_and(|l| l as u64 == length))
        .map(|n| n as usize))
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

/// How a file starts, after a byte order mark and whitespace.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Start {
    /// The word `solid` (any letter case): ascii STL.
    Solid,
    /// Anything else.
    Other,
    /// Nothing: the file holds only whitespace.
    Blank,
}

/// How the text after a byte order mark and leading whitespace starts.
fn first_word(reader: &mut impl BufRead) -> Result<Start, IoError> {
    let buffer = reader.fill_buf().map_err(IoError::io("read the file"))?;
    if buffer.starts_with(BOM) {
        reader.consume(BOM.len());
    }
    loop {
        let buffer = reader.fill_buf().map_err(IoError::io("read the file"))?;
        if buffer.is_empty() {
            return Ok(Start::Blank);
        }
        match buffer.iter().position(|b| !b.is_ascii_whitespace()) {
            Some(start) => {
                reader.consume(start);
                break;
            }
            None => {
                let n = buffer.len();
                reader.consume(n);
            }
        }
    }
    let mut word = Vec::with_capacity(6);
    reader
        .take(6)
        .read_to_end(&mut word)
        .map_err(IoError::io("read the file"))?;
    let solid = word
        .get(..5)
        .is_some_and(|w| w.eq_ignore_ascii_case(b"solid"))
        && word.get(5).is_none_or(u8::is_ascii_whitespace);
    Ok(if solid { Start::Solid } else { Start::Other })
}

fn read_binary(mut reader: impl Read, n: usize) -> Result<Soup, IoError> {
    // A closed triangle mesh has about half as many vertices as triangles.
    let mut welder = Welder::with_capacity(n / 2 + 3);
    let mut triangles = Vec::with_capacity(n);
    let mut record = [0u8; BINARY_TRIANGLE];
    for facet in 0..n {
        // The file length was checked against the count: a short read is an I/O error.
        reader
            .read_exact(&mut record)
            .map_err(IoError::io("read the file"))?;
        let mut triangle = [0; 3];
        for (corner, id) in triangle.iter_mut().enumerate() {
            let at = 12 + 12 * corner;
            let p = [
                f32_at(&record, at),
                f32_at(&record, at + 4),
                f32_at(&record, at + 8),
            ];
            *id = insert(&mut welder, p, facet, None)?;
        }
        triangles.push(triangle);
    }
    Ok(Soup {
        positions: welder.into_positions(),
        triangles,
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

/// Whitespace-separated tokens with their line numbers, read line by line.
struct Tokens<R> {
    lines: LineReader<R>,
    line: usize,
    /// Where the unread rest of the current line starts.
    at: usize,
}

impl<R: BufRead> Tokens<R> {
    fn new(reader: R) -> Self {
        Self {
            lines: LineReader::new(reader),
            line: 1,
            at: 0,
        }
    }

    /// The next token and its line.
    fn next(&mut self) -> Result<Option<(usize, &[u8])>, IoError> {
        loop {
            let text = self.lines.line();
            if let Some(skip) = text[self.at..]
                .iter()
                .position(|b| !b.is_ascii_whitespace())
            {
                let start = self.at + skip;
                let end = text[start..]
                    .iter()
                    .position(u8::is_ascii_whitespace)
                    .map_or(text.len(), |n| start + n);
                self.at = end;
                return Ok(Some((self.line, &self.lines.line()[start..end])));
            }
            match self.lines.next_line()? {
                Some(line) => {
                    self.line = line;
                    self.at = 0;
                }
                None => return Ok(None),
            }
        }
    }

    /// Drops the rest of the current line (the name after `solid` or `endsolid`).
    fn skip_line(&mut self) {
        self.at = self.lines.line().len();
    }

    /// The next token, which must be `keyword` (any letter case).
    fn expect(&mut self, keyword: &'static str, quoted: &'static str) -> Result<(), IoError> {
        match self.next()? {
            Some((_, token)) if token.eq_ignore_ascii_case(keyword.as_bytes()) => Ok(()),
            Some(found) => Err(syntax(quoted, found)),
            None => Err(end_of_file(self.line, quoted)),
        }
    }

    /// The next token as an `f32`.
    fn number(&mut self) -> Result<(usize, f32), IoError> {
        match self.next()? {
            Some((line, token)) => match parse_number(token) {
                Some(value) => Ok((line, value)),
                None => Err(syntax("a number", (line, token))),
            },
            None => Err(end_of_file(self.line, "a number")),
        }
    }
}

/// A syntax error at the token `found` (its line and text).
fn syntax(expected: &'static str, (line, token): (usize, &[u8])) -> IoError {
    IoError::Syntax {
        line,
        expected,
        found: Some(token_text(token)),
    }
}

/// A syntax error at the end of the file, whose last line is `line`.
fn end_of_file(line: usize, expected: &'static str) -> IoError {
    IoError::Syntax {
        line,
        expected,
        found: None,
    }
}

/// `solid name`, then facets, then `endsolid name`; several solids may follow each
/// other. Keywords are matched in any letter case.
fn read_ascii(reader: impl BufRead) -> Result<Soup, IoError> {
    let mut tokens = Tokens::new(reader);
    let mut welder = Welder::with_capacity(0);
    let mut triangles = Vec::new();
    tokens.expect("solid", "\"solid\"")?;
    tokens.skip_line();
    loop {
        match tokens.next()? {
            Some((_, t)) if t.eq_ignore_ascii_case(b"facet") => {
                let triangle = read_facet(&mut tokens, &mut welder, triangles.len())?;
                triangles.push(triangle);
            }
            Some((_, t)) if t.eq_ignore_ascii_case(b"endsolid") => {
                tokens.skip_line();
                match tokens.next()? {
                    None => break,
                    Some((_, t)) if t.eq_ignore_ascii_case(b"solid") => tokens.skip_line(),
                    Some(found) => return Err(syntax("\"solid\" or the end of the file", found)),
                }
            }
            Some(found) => return Err(syntax("\"facet\" or \"endsolid\"", found)),
            None => return Err(end_of_file(tokens.line, "\"facet\" or \"endsolid\"")),
        }
    }
    Ok(Soup {
        positions: welder.into_positions(),
        triangles,
    })
}

/// The rest of a facet after `facet`: `normal nx ny nz` (ignored: normals are
/// recomputed from the vertices where needed), `outer loop`, three `vertex x y z`,
/// `endloop`, `endfacet`.
fn read_facet(
    tokens: &mut Tokens<impl BufRead>,
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
