//! Helpers shared by the text readers (OBJ, ascii STL).

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
