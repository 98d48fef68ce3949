//! Helpers shared by the text readers (OBJ, ascii STL, ascii PLY).

use std::io::{BufRead, Seek, SeekFrom};

use crate::error::IoError;

/// Lines read one at a time from a stream into a reused buffer: memory is bounded by
/// the longest line, not by the file.
pub(crate) struct LineReader<R> {
    reader: R,
    buffer: Vec<u8>,
    number: usize,
}

impl<R: BufRead> LineReader<R> {
    pub(crate) fn new(reader: R) -> Self {
        Self {
            reader,
            buffer: Vec::new(),
            number: 0,
        }
    }

    /// Reads the next line (without its `\n` or `\r\n` ending) and returns its
    /// 1-based number, or `None` at the end of the input.
    pub(crate) fn next_line(&mut self) -> Result<Option<usize>, IoError> {
        self.buffer.clear();
        let n = self
            .reader
            .read_until(b'\n', &mut self.buffer)
            .map_err(IoError::io("read the file"))?;
        if n == 0 {
            return Ok(None);
        }
        if self.buffer.last() == Some(&b'\n') {
            self.buffer.pop();
        }
        if self.buffer.last() == Some(&b'\r') {
            self.buffer.pop();
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

/// The number of lines [`Lines`] would yield for the rest of `reader`, counted without
/// holding the data.
pub(crate) fn count_lines_in(reader: &mut impl BufRead) -> Result<usize, IoError> {
    let mut newlines = 0;
    let mut last = None;
    scan(reader, |chunk| {
        newlines += chunk.iter().filter(|&&b| b == b'\n').count();
        last = chunk.last().copied();
        true
    })?;
    Ok(newlines + usize::from(last.is_some_and(|b| b != b'\n')))
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

/// The lines of a byte buffer, 1-based numbers, without the `\n` or `\r\n` ending.
#[derive(Clone)]
pub(crate) struct Lines<'a> {
    rest: &'a [u8],
    number: usize,
}

impl<'a> Lines<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        Self {
            rest: bytes,
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
        let (line, rest) = match self.rest.iter().position(|&b| b == b'\n') {
            Some(end) => (&self.rest[..end], &self.rest[end + 1..]),
            None => (self.rest, &self.rest[self.rest.len()..]),
        };
        self.rest = rest;
        self.number += 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        Some((self.number, line))
    }
}

/// The number of lines [`Lines`] yields for `bytes`.
#[cfg(test)]
pub(crate) fn count_lines(bytes: &[u8]) -> usize {
    let newlines = bytes.iter().filter(|&&b| b == b'\n').count();
    newlines + usize::from(bytes.last().is_some_and(|&b| b != b'\n'))
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
        for text in [&b"a\r\nb\n\nc"[..], b"a\n", b"", b"\n\n", b"x\ry"] {
            let mut reader = LineReader::new(text);
            let mut streamed = Vec::new();
            while let Some(n) = reader.next_line().unwrap() {
                streamed.push((n, reader.line().to_vec()));
            }
            let sliced: Vec<_> = Lines::new(text).map(|(n, l)| (n, l.to_vec())).collect();
            assert_eq!(streamed, sliced);
            assert_eq!(count_lines_in(&mut &text[..]).unwrap(), count_lines(text));
        }
        assert!(any_binary_bytes(&mut &b"solid\x00"[..]).unwrap());
        assert!(!any_binary_bytes(&mut &b"solid a\r\n\tx\n"[..]).unwrap());
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
