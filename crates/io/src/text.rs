//! Helpers shared by the text readers (OBJ, OFF, ascii STL, ascii PLY).

use std::io::{BufRead, Seek, SeekFrom};

use crate::error::IoError;

/// The UTF-8 byte order mark, which some Windows editors write at the start of a text
/// file. Readers skip it.
pub(crate) const BOM: &[u8] = b"\xef\xbb\xbf";

/// Lines read one at a time from a stream into a reused buffer: memory is bounded by
/// the longest line, not by the file.
///
/// A line ends at `\n`, `\r\n` or a lone `\r` (classic Mac OS); the ending is not part
/// of the line. A byte order mark at the start of the first line is dropped.
pub(crate) struct LineReader<R> {
    reader: R,
    buffer: Vec<u8>,
    number: usize,
    /// The last line ended with `\r`: a `\n` right after it belongs to that ending.
    after_cr: bool,
    /// Whether the stream starts at the start of the file (where a BOM may be).
    at_file_start: bool,
    /// Bytes consumed from the stream so far.
    consumed: u64,
}

impl<R: BufRead> LineReader<R> {
    /// Lines from the start of a file.
    pub(crate) fn new(reader: R) -> Self {
        Self {
            reader,
            buffer: Vec::new(),
            number: 0,
            after_cr: false,
            at_file_start: true,
            consumed: 0,
        }
    }

    /// Lines from the middle of a file (no byte order mark is looked for).
    pub(crate) fn mid_file(reader: R) -> Self {
        Self {
            at_file_start: false,
            ..Self::new(reader)
        }
    }

    /// Reads the next line (without its ending) and returns its 1-based number, or
    /// `None` at the end of the input.
    pub(crate) fn next_line(&mut self) -> Result<Option<usize>, IoError> {
        self.buffer.clear();
        let mut started = false;
        loop {
            let available = self
                .reader
                .fill_buf()
                .map_err(IoError::io("read the file"))?;
            if available.is_empty() {
                break;
            }
            if std::mem::take(&mut self.after_cr) && available[0] == b'\n' {
                self.reader.consume(1);
                self.consumed += 1;
                continue;
            }
            started = true;
            if let Some(end) = available.iter().position(|&b| b == b'\n' || b == b'\r') {
                self.buffer.extend_from_slice(&available[..end]);
                self.after_cr = available[end] == b'\r';
                self.reader.consume(end + 1);
                self.consumed += end as u64 + 1;
                break;
            }
            self.buffer.extend_from_slice(available);
            let n = available.len();
            self.reader.consume(n);
            self.consumed += n as u64;
        }
        if !started {
            return Ok(None);
        }
        if self.number == 0 && self.at_file_start && self.buffer.starts_with(BOM) {
            self.buffer.drain(..BOM.len());
        }
        self.number += 1;
        Ok(Some(self.number))
    }

    /// The line read last (empty before the first).
    pub(crate) fn line(&self) -> &[u8] {
        &self.buffer
    }

    /// The number of lines read so far.
    pub(crate) fn lines_read(&self) -> usize {
        self.number
    }

    /// The number of bytes read so far (the ending of the last line included, except
    /// the `\n` of a `\r\n` ending, which is read with the next line).
    pub(crate) fn bytes_read(&self) -> u64 {
        self.consumed
    }
}

/// The length of a seekable stream; leaves it at the start.
pub(crate) fn stream_len(reader: &mut impl Seek) -> Result<u64, IoError> {
    let length = reader
        .seek(SeekFrom::End(0))
        .map_err(IoError::io("read the file"))?;
    reader
        .seek(SeekFrom::Start(0))
        .map_err(IoError::io("read the file"))?;
    Ok(length)
}

/// Reads `reader` to its end in buffer-sized pieces, calling `chunk` on each: a pass
/// over a file without holding it.
pub(crate) fn scan(
    reader: &mut impl BufRead,
    mut chunk: impl FnMut(&[u8]) -> bool,
) -> Result<(), IoError> {
    loop {
        let buffer = reader.fill_buf().map_err(IoError::io("read the file"))?;
        if buffer.is_empty() {
            return Ok(());
        }
        let n = buffer.len();
        let more = chunk(buffer);
        reader.consume(n);
        if !more {
            return Ok(());
        }
    }
}

/// The number of lines [`Lines`] (and [`LineReader`]) would yield for the rest of
/// `reader`, counted without holding the data.
pub(crate) fn count_lines_in(reader: &mut impl BufRead) -> Result<usize, IoError> {
    let mut counter = LineCounter::default();
    scan(reader, |chunk| {
        counter.add(chunk);
        true
    })?;
    Ok(counter.lines())
}

/// Counts line endings (`\n`, `\r\n`, lone `\r`) over consecutive pieces of a text.
#[derive(Default)]
struct LineCounter {
    endings: usize,
    last: Option<u8>,
}

impl LineCounter {
    fn add(&mut self, chunk: &[u8]) {
        let Some(&first) = chunk.first() else { return };
        let newlines = chunk.iter().filter(|&&b| b == b'\n').count();
        let returns = chunk.iter().filter(|&&b| b == b'\r').count();
        // Each `\r\n` is one ending, counted at its `\r`.
        let pairs = chunk.windows(2).filter(|w| w == b"\r\n").count()
            + usize::from(self.last == Some(b'\r') && first == b'\n');
        self.endings += newlines + returns - pairs;
        self.last = chunk.last().copied();
    }

    fn lines(&self) -> usize {
        self.endings + usize::from(self.last.is_some_and(|b| b != b'\n' && b != b'\r'))
    }
}

/// Whether the rest of `reader` holds a byte [`has_binary_bytes`] refuses in a line.
pub(crate) fn any_binary_bytes(reader: &mut impl BufRead) -> Result<bool, IoError> {
    let mut found = false;
    scan(reader, |chunk| {
        found = chunk.iter().any(|&b| b != b'\n' && has_binary_bytes(&[b]));
        !found
    })?;
    Ok(found)
}

/// The lines of a byte buffer, 1-based numbers, split as [`LineReader`] splits them
/// (endings `\n`, `\r\n` or a lone `\r`; a byte order mark before the first line
/// dropped).
#[derive(Clone)]
pub(crate) struct Lines<'a> {
    rest: &'a [u8],
    number: usize,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        Self {
            rest: bytes.strip_prefix(BOM).unwrap_or(bytes),
            number: 0,
        }
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.rest.is_empty() {
            return None;
        }
        let (line, rest) = match self.rest.iter().position(|&b| b == b'\n' || b == b'\r') {
            Some(end) => {
                let skip = if self.rest[end..].starts_with(b"\r\n") {
                    2
                } else {
                    1
                };
                (&self.rest[..end], &self.rest[end + skip..])
            }
            None => (self.rest, &self.rest[self.rest.len()..]),
        };
        self.rest = rest;
        self.number += 1;
        Some((self.number, line))
    }
}

/// The number of lines [`Lines`] yields for `bytes` (without a byte order mark).
#[cfg(test)]
pub(crate) fn count_lines(bytes: &[u8]) -> usize {
    let mut counter = LineCounter::default();
    counter.add(bytes);
    counter.lines()
}

/// Whether the rest of `reader` holds nothing but ASCII whitespace (after a byte
/// order mark at its start): a file that is empty to the eye.
pub(crate) fn is_blank_stream(reader: &mut impl BufRead) -> Result<bool, IoError> {
    let mut blank = true;
    let mut first = true;
    scan(reader, |mut chunk| {
        if std::mem::take(&mut first) {
            chunk = chunk.strip_prefix(BOM).unwrap_or(chunk);
        }
        blank = chunk.iter().all(u8::is_ascii_whitespace);
        blank
    })?;
    Ok(blank)
}

/// Whether a line holds bytes that never occur in a text file (control characters
/// other than tab, carriage return and form feed).
pub(crate) fn has_binary_bytes(line: &[u8]) -> bool {
    line.iter()
        .any(|&b| (b < 0x20 && !matches!(b, b'\t' | b'\r' | 0x0c)) || b == 0x7f)
}

/// Whitespace-separated tokens of a line.
pub(crate) fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|b| b.is_ascii_whitespace())
        .filter(|token| !token.is_empty())
}

/// A token as quoted in an error message: lossy UTF-8, at most 40 characters.
pub(crate) fn token_text(token: &[u8]) -> String {
    const MAX: usize = 40;
    let text = String::from_utf8_lossy(token);
    if text.chars().count() <= MAX {
        text.into_owned()
    } else {
        let mut short: String = text.chars().take(MAX).collect();
        short.push('…');
        short
    }
}

/// Parses a token as a number of type `T` (`f32`, `f64`, `i64`).
pub(crate) fn parse_number<T: std::str::FromStr>(token: &[u8]) -> Option<T> {
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// Writes a text mesh format through a buffer: checks that a reader would accept the
/// mesh (finite positions, in `f32` range for single precision; face indices in
/// range), runs `body`, then flushes. Shared by the OBJ and OFF writers.
pub(crate) fn write_text_mesh<W: std::io::Write>(
    writer: W,
    mesh: &beltrami_halfedge::MeshData,
    precision: crate::format::Precision,
    body: impl FnOnce(&mut std::io::BufWriter<W>) -> std::io::Result<()>,
) -> Result<(), IoError> {
    use std::io::Write as _;
    crate::validate::check_positions(
        &mesh.positions,
        precision == crate::format::Precision::Single,
    )?;
    crate::validate::check_faces(mesh, None)?;
    let mut out = std::io::BufWriter::new(writer);
    body(&mut out)
        .and_then(|()| out.flush())
        .map_err(IoError::io("write the file"))
}

/// Writes `prefix x y z` and a newline, with the shortest decimal that reads back to
/// the same `f64` (or `f32` with single precision).
#[allow(
    clippy::cast_possible_truncation,
    reason = "single precision output is asked for; the range was checked"
)]
pub(crate) fn write_xyz(
    out: &mut impl std::io::Write,
    prefix: &str,
    p: glam::DVec3,
    precision: crate::format::Precision,
) -> std::io::Result<()> {
    match precision {
        crate::format::Precision::Double => writeln!(out, "{prefix}{} {} {}", p.x, p.y, p.z),
        crate::format::Precision::Single => {
            writeln!(out, "{prefix}{} {} {}", p.x as f32, p.y as f32, p.z as f32)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_strip_endings_and_count() {
        let text = b"a\r\nb\n\nc";
        let lines: Vec<_> = Lines::new(text).collect();
        assert_eq!(
            lines,
            [
                (1, &b"a"[..]),
                (2, &b"b"[..]),
                (3, &b""[..]),
                (4, &b"c"[..])
            ]
        );
        assert_eq!(count_lines(text), 4);
        assert_eq!(count_lines(b"a\n"), 1);
        assert_eq!(count_lines(b""), 0);
        assert_eq!(Lines::new(b"a\n").count(), 1);
    }

    #[test]
    fn streamed_lines_and_counts_agree_with_the_slice_versions() {
        for text in [
            &b"a\r\nb\n\nc"[..],
            b"a\n",
            b"",
            b"\n\n",
            b"x\ry",
            b"x\r\r\ny\r",
            b"\r\n\r",
            b"\xef\xbb\xbfa\rb",
        ] {
            let mut reader = LineReader::new(text);
            let mut streamed = Vec::new();
            while let Some(n) = reader.next_line().unwrap() {
                streamed.push((n, reader.line().to_vec()));
            }
            let sliced: Vec<_> = Lines::new(text).map(|(n, l)| (n, l.to_vec())).collect();
            assert_eq!(streamed, sliced);
            let unmarked = text.strip_prefix(BOM).unwrap_or(text);
            assert_eq!(
                count_lines_in(&mut &unmarked[..]).unwrap(),
                count_lines(text)
            );
            // Read through a one-byte buffer: endings split across reads.
            let mut reader = LineReader::new(std::io::BufReader::with_capacity(1, text));
            let mut split = Vec::new();
            while let Some(n) = reader.next_line().unwrap() {
                split.push((n, reader.line().to_vec()));
            }
            assert_eq!(split, sliced);
            let mut counted = std::io::BufReader::with_capacity(1, unmarked);
            assert_eq!(count_lines_in(&mut counted).unwrap(), count_lines(text));
        }
        assert!(any_binary_bytes(&mut &b"solid\x00"[..]).unwrap());
        assert!(!any_binary_bytes(&mut &b"solid a\r\n\tx\n"[..]).unwrap());
    }

    #[test]
    fn old_mac_endings_and_byte_order_marks() {
        let lines: Vec<_> = Lines::new(b"\xef\xbb\xbfv 1\rv 2\r\rf\r\n").collect();
        assert_eq!(lines, [(1, &b"v 1"[..]), (2, b"v 2"), (3, b""), (4, b"f")]);
        // A byte order mark is looked for at the start of a file only.
        let mut reader = LineReader::mid_file(&b"\xef\xbb\xbfa"[..]);
        reader.next_line().unwrap();
        assert_eq!(reader.line(), b"\xef\xbb\xbfa");
        assert!(is_blank_stream(&mut &b"\xef\xbb\xbf \r\n\t"[..]).unwrap());
        assert!(is_blank_stream(&mut &b""[..]).unwrap());
        assert!(!is_blank_stream(&mut &b" \n#"[..]).unwrap());
    }

    #[test]
    fn tokens_split_on_any_whitespace() {
        let t: Vec<_> = tokens(b"  f 1/2/3\t4//5  6 ").collect();
        assert_eq!(t, [&b"f"[..], b"1/2/3", b"4//5", b"6"]);
    }

    #[test]
    fn long_tokens_are_shortened() {
        assert_eq!(token_text(&[b'a'; 50]).chars().count(), 41);
        assert_eq!(token_text(b"abc"), "abc");
    }
}
