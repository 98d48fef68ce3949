//! OFF reader: a keyword, the counts, then one vertex and one face per line.

use std::io::{BufRead, Seek};

use beltrami_halfedge::{MAX_ELEMENTS, PolygonList};
use glam::DVec3;

use crate::error::IoError;
use crate::read::DeclaredCounts;
use crate::text::{LineReader, has_binary_bytes, parse_number, stream_len, token_text, tokens};
use beltrami_halfedge::MeshData;

/// The fewest bytes a vertex line takes (`0 0 0` and its line ending).
const MIN_VERTEX_BYTES: u64 = 6;
/// The fewest bytes a face line takes (`0` and its line ending: a face of no vertices).
const MIN_FACE_BYTES: u64 = 2;

/// The header keyword `[ST][C][N][4][n]OFF`: which values a vertex line carries.
pub(super) struct Keyword {
    /// `4OFF`: four homogeneous coordinates per vertex.
    four: bool,
    /// `nOFF`: a dimension line follows the keyword.
    n_dimensional: bool,
}

impl Keyword {
    /// The keyword at the start of `word`, and what follows it there: nothing, or the
    /// vertex count of files that write no space after the keyword (`OFF1234 5678 0`,
    /// as in ModelNet).
    pub(super) fn parse(word: &[u8]) -> Option<(Self, &[u8])> {
        let mut rest = word;
        // Texture coordinates, colours and normals are ignored: they follow the
        // coordinates on a vertex line.
        for prefix in [&b"ST"[..], b"C", b"N"] {
            rest = rest.strip_prefix(prefix).unwrap_or(rest);
        }
        let mut flag = |prefix: &[u8]| match rest.strip_prefix(prefix) {
            Some(after) => {
                rest = after;
                true
            }
            None => false,
        };
        let four = flag(b"4");
        let n_dimensional = flag(b"n");
        let rest = rest.strip_prefix(b"OFF")?;
        if rest.first().is_some_and(|b| !b.is_ascii_digit()) {
            return None;
        }
        Some((
            Self {
                four,
                n_dimensional,
            },
            rest,
        ))
    }
}

/// The lines of an OFF file that hold something: blank lines and `#` comments are
/// skipped.
struct Content<R> {
    lines: LineReader<R>,
    /// No line so far held anything but whitespace.
    blank: bool,
}

impl<R: BufRead> Content<R> {
    fn new(reader: R) -> Self {
        Self {
            lines: LineReader::new(reader),
            blank: true,
        }
    }

    /// Moves to the next line with content and returns its number, or `None` at the
    /// end of the file.
    fn next(&mut self) -> Result<Option<usize>, IoError> {
        while let Some(line) = self.lines.next_line()? {
            let text = self.lines.line();
            self.blank &= text.iter().all(u8::is_ascii_whitespace);
            if !self.text().trim_ascii().is_empty() {
                return Ok(Some(line));
            }
        }
        Ok(None)
    }

    /// The current line without its comment.
    fn text(&self) -> &[u8] {
        let text = self.lines.line();
        text.iter()
            .position(|&b| b == b'#')
            .map_or(text, |start| &text[..start])
    }
}

/// The counts of the header.
struct Header {
    vertices: usize,
    faces: usize,
}

/// Reads the keyword and the counts; leaves `content` at the counts line.
fn read_header<R: BufRead>(content: &mut Content<R>) -> Result<Header, IoError> {
    let Some(line) = content.next()? else {
        return Err(if content.blank {
            IoError::Empty
        } else {
            IoError::OffHeader {
                line: None,
                reason: "the file holds only comments, no \"OFF\" line".to_owned(),
            }
        });
    };
    if has_binary_bytes(content.lines.line()) {
        return Err(IoError::NotText { line });
    }
    // The line is short; a copy leaves `content` free to move on.
    let text = content.text().to_vec();
    let mut words = tokens(&text);
    let first = words.next().unwrap_or_default();
    match Keyword::parse(first) {
        Some((keyword, rest)) => {
            let unsupported = |reason: &str| IoError::OffHeader {
                line: Some(line),
                reason: reason.to_owned(),
            };
            if keyword.four {
                return Err(unsupported(
                    "4OFF (homogeneous coordinates) is not supported",
                ));
            }
            if keyword.n_dimensional {
                return Err(unsupported(
                    "nOFF (a dimension given in the file) is not supported",
                ));
            }
            let mut counts = (!rest.is_empty())
                .then_some(rest)
                .into_iter()
                .chain(words)
                .peekable();
            if counts
                .peek()
                .is_some_and(|w| w.eq_ignore_ascii_case(b"BINARY"))
            {
                return Err(unsupported(
                    "binary off is not supported (convert the file to ascii off or ply)",
                ));
            }
            if counts.peek().is_some() {
                return parse_counts(counts, line);
            }
            // The counts on a line of their own.
            match content.next()? {
                Some(line) => parse_counts(tokens(content.text()), line),
                None => Err(IoError::Syntax {
                    line,
                    expected: "the vertex count",
                    found: None,
                }),
            }
        }
        // The keyword is optional (Geomview): a line of counts starts the file.
        None if first.iter().all(u8::is_ascii_digit) => parse_counts(tokens(&text), line),
        None => Err(IoError::OffHeader {
            line: Some(line),
            reason: format!(
                "the file starts with {:?}, not with \"OFF\"{}",
                token_text(first),
                hint(first)
            ),
        }),
    }
}

/// A hint at the format of a file that starts with `word`.
fn hint(word: &[u8]) -> &'static str {
    if word == b"ply" {
        "; is this a ply file? rename it to .ply"
    } else if word.eq_ignore_ascii_case(b"solid") {
        "; is this an stl file? rename it to .stl"
    } else if matches!(word, b"v" | b"vn" | b"vt" | b"f" | b"o" | b"g" | b"mtllib") {
        "; is this an obj file? rename it to .obj"
    } else {
        ""
    }
}

/// `vertices faces [edges]`: the edge count is optional and not used.
fn parse_counts<'a>(
    mut words: impl Iterator<Item = &'a [u8]>,
    line: usize,
) -> Result<Header, IoError> {
    let mut count = |expected: &'static str, optional: bool| match words.next() {
        Some(word) => match parse_number::<usize>(word) {
            Some(n) => Ok(Some(n)),
            None => Err(IoError::Syntax {
                line,
                expected,
                found: Some(token_text(word)),
            }),
        },
        None if optional => Ok(None),
        None => Err(IoError::Syntax {
            line,
            expected,
            found: None,
        }),
    };
    let vertices = count("the vertex count", false)?.unwrap_or_default();
    let faces = count("the face count", false)?.unwrap_or_default();
    count("the edge count", true)?;
    if let Some(word) = words.next() {
        return Err(IoError::Syntax {
            line,
            expected: "the end of the counts line",
            found: Some(token_text(word)),
        });
    }
    if vertices > MAX_ELEMENTS {
        return Err(IoError::TooManyVertices {
            declared: vertices,
            max: MAX_ELEMENTS,
        });
    }
    Ok(Header { vertices, faces })
}

/// The counts an OFF header declares, read from the start of `reader`.
pub(crate) fn declared_counts(reader: &mut impl BufRead) -> Result<DeclaredCounts, IoError> {
    let header = read_header(&mut Content::new(reader))?;
    Ok(DeclaredCounts {
        vertices: Some(header.vertices),
        faces: header.faces,
    })
}

/// Reads an ascii OFF file from `reader`.
///
/// The keyword (`OFF`, `COFF`, `NOFF`, `CNOFF`, `STOFF`, … or none) is followed by
/// the vertex, face and (optional, unused) edge counts, on its line or the next. Then
/// one vertex per line, `x y z` and values that are ignored (normals, colours,
/// texture coordinates), and one face per line, `n i0 … i(n-1)` (0-based) and values
/// that are ignored (a colour). `#` starts a comment; blank lines are skipped.
pub(crate) fn read_off<R: BufRead + Seek>(mut reader: R) -> Result<MeshData, IoError> {
    let length = stream_len(&mut reader)?;
    if length == 0 {
        return Err(IoError::Empty);
    }
    let mut content = Content::new(reader);
    let Header { vertices, faces } = read_header(&mut content)?;
    check_counts(
        vertices,
        faces,
        length.saturating_sub(content.lines.bytes_read()),
    )?;
    let mut positions = Vec::with_capacity(vertices);
    for vertex in 0..vertices {
        let Some(line) = content.next()? else {
            return Err(IoError::Truncated {
                element: "vertex".to_owned(),
                index: vertex,
            });
        };
        let mut words = tokens(content.text());
        let mut p = [0.0_f64; 3];
        for c in &mut p {
            let word = words.next();
            *c = word.and_then(parse_number).ok_or_else(|| IoError::Syntax {
                line,
                expected: "a number",
                found: word.map(token_text),
            })?;
        }
        if let Some(&value) = p.iter().find(|c| !c.is_finite()) {
            return Err(IoError::NonFiniteCoordinate {
                line: Some(line),
                vertex,
                value,
            });
        }
        positions.push(DVec3::from_array(p));
    }
    let reserve = faces.min(usize::try_from(length / 8).unwrap_or(usize::MAX));
    let mut polygons = PolygonList::with_capacity(reserve, 3 * reserve);
    let mut corners = Vec::new();
    for face in 0..faces {
        let Some(line) = content.next()? else {
            return Err(IoError::Truncated {
                element: "face".to_owned(),
                index: face,
            });
        };
        let mut words = tokens(content.text());
        let word = words.next();
        let n: usize = word.and_then(parse_number).ok_or_else(|| IoError::Syntax {
            line,
            expected: "the number of vertices of the face",
            found: word.map(token_text),
        })?;
        corners.clear();
        for _ in 0..n {
            let word = words.next();
            let index: i64 = word.and_then(parse_number).ok_or_else(|| IoError::Syntax {
                line,
                expected: "a vertex index",
                found: word.map(token_text),
            })?;
            match u32::try_from(index) {
                Ok(i) if (i as usize) < vertices => corners.push(i),
                _ => {
                    return Err(IoError::FaceIndexOutOfRange {
                        line: Some(line),
                        face,
                        index,
                        n_vertices: vertices,
                    });
                }
            }
        }
        polygons.push(&corners);
    }
    if let Some(line) = content.next()? {
        return Err(IoError::TrailingData {
            line: Some(line),
            bytes: None,
            element: "face".to_owned(),
            count: faces,
        });
    }
    Ok(MeshData {
        positions,
        faces: polygons,
    })
}

/// Checks, before anything is allocated, that the declared vertex and face lines fit
/// in the `remaining` bytes of the file.
fn check_counts(vertices: usize, faces: usize, remaining: u64) -> Result<(), IoError> {
    // The last line may lack its line ending.
    let budget = remaining.saturating_add(1);
    let exceeds = |element: &str, declared: usize, available: u64| IoError::CountExceedsFile {
        element: element.to_owned(),
        declared,
        available: usize::try_from(available).unwrap_or(usize::MAX),
    };
    let vertex_bytes = (vertices as u64).saturating_mul(MIN_VERTEX_BYTES);
    if vertex_bytes > budget {
        return Err(exceeds("vertex", vertices, budget / MIN_VERTEX_BYTES));
    }
    let left = budget - vertex_bytes;
    if (faces as u64).saturating_mul(MIN_FACE_BYTES) > left {
        return Err(exceeds("face", faces, left / MIN_FACE_BYTES));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keywords_and_what_follows_them() {
        for word in [
            &b"OFF"[..],
            b"COFF",
            b"NOFF",
            b"CNOFF",
            b"STOFF",
            b"STCNOFF",
            b"4OFF",
            b"nOFF",
        ] {
            assert!(super::super::is_off_keyword(word), "{word:?}");
        }
        for word in [&b"off"[..], b"OF", b"OFFX", b"XOFF", b"NCOFF", b"OFF1"] {
            assert!(!super::super::is_off_keyword(word), "{word:?}");
        }
        let (_, rest) = Keyword::parse(b"OFF1234").expect("glued counts");
        assert_eq!(rest, b"1234");
    }
}
