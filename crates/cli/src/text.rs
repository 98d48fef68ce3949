//! Numbers and words in human-readable output. JSON output keeps full precision;
//! tables and one-line summaries use these.

/// `x` with six significant digits and no trailing zeros: `0.00702`, `1234.57`,
/// `7.02305e-6`, `1.5e12`. Plain notation for magnitudes from 1e-4 up to 1e6,
/// scientific otherwise; `0`, `inf`, `-inf` and `NaN` as such.
///
/// # Examples
/// ```ignore
/// assert_eq!(number(0.0070230492772682895), "0.00702305");
/// ```
pub(crate) fn number(x: f64) -> String {
    beltrami_halfedge::short_number(x)
}

/// `x` exactly as given, for a usage error that echoes a value back: the shortest text
/// that reads back to the same number, in scientific notation when very large or small
/// (`180.0001`, not [`number`]'s `180`; `1e300`, not 301 digits), as the library's
/// messages write it ([`beltrami_halfedge::exact_number`]).
pub(crate) fn exact(x: f64) -> String {
    beltrami_halfedge::exact_number(x)
}

/// A point or direction as `(x, y, z)` with [`number`]s.
pub(crate) fn vector(v: glam::DVec3) -> String {
    format!("({}, {}, {})", number(v.x), number(v.y), number(v.z))
}

/// `one` when `n` is 1, `many` otherwise: "1 triangle", "2 triangles".
pub(crate) fn plural<'a>(n: usize, one: &'a str, many: &'a str) -> &'a str {
    if n == 1 { one } else { many }
}

/// `n` followed by the right form of the noun: `counted(1, "face", "faces")` is
/// "1 face".
pub(crate) fn counted(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", plural(n, one, many))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_values_are_echoed_exactly_and_briefly() {
        assert_eq!(exact(180.0001), "180.0001");
        assert_eq!(exact(1e300), "1e300");
        assert_eq!(exact(1e-300), "1e-300");
        assert_eq!(exact(-1.0), "-1");
        assert_eq!(exact(f64::INFINITY), "inf");
    }

    #[test]
    fn numbers_have_six_significant_digits_and_no_trailing_zeros() {
        assert_eq!(number(0.007_023_049_277_268_29), "0.00702305");
        assert_eq!(number(0.000_007_023_049_277_268_29), "7.02305e-6");
        assert_eq!(number(0.8), "0.8");
        assert_eq!(number(-0.5), "-0.5");
        assert_eq!(number(1234.5678), "1234.57");
        assert_eq!(number(1.5e12), "1.5e12");
        assert_eq!(number(10.0), "10");
        assert_eq!(number(0.0), "0");
        assert_eq!(number(f64::INFINITY), "inf");
        assert_eq!(number(1e-4), "0.0001");
    }

    #[test]
    fn words_agree_with_their_count() {
        assert_eq!(counted(1, "face", "faces"), "1 face");
        assert_eq!(counted(0, "face", "faces"), "0 faces");
        assert_eq!(counted(2, "vertex", "vertices"), "2 vertices");
    }
}
