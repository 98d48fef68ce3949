//! Rounding to significant digits, the one rule every summary uses.

/// Significant digits of the measured quantities in [`MeshSummary`](crate::MeshSummary),
/// [`MetricsTable`](crate::MetricsTable)
/// and [`SmoothingSummary`](crate::SmoothingSummary): six, enough to see any real change
/// of a bounding box, an area or a displacement, few enough that a last-bit difference
/// (a different summation order, another platform's `libm`) almost never shows.
pub const SUMMARY_DIGITS: u32 = 6;

/// Significant digits of a deviation in a [`ComparisonTable`](crate::ComparisonTable):
/// two, since a deviation matters by its order of magnitude.
pub const DEVIATION_DIGITS: u32 = 2;

/// `x` rounded to `digits` significant decimal digits (at least 1), half to even on the
/// exact decimal value of `x` (Rust's `{:e}` formatting, identical on every platform).
/// Zero (of either sign) gives `+0.0`; NaN and infinities are returned unchanged.
///
/// # Examples
/// ```
/// use beltrami_testkit::round_significant;
/// assert_eq!(round_significant(123_456.789, 3), 123_000.0);
/// assert_eq!(round_significant(0.000_123_456, 2), 0.000_12);
/// assert_eq!(round_significant(-2.5e-17, 1), -2e-17);
/// assert_eq!(round_significant(-0.0, 6), 0.0);
/// ```
///
/// # Panics
/// Never: a finite `f64` formats as a number that parses back.
#[must_use]
pub fn round_significant(x: f64, digits: u32) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    if !x.is_finite() {
        return x;
    }
    let digits = digits.max(1) as usize;
    format!("{:.*e}", digits - 1, x)
        .parse()
        .expect("Rust formats a finite f64 as a parsable number")
}

/// `x` rounded to `digits` significant digits and written for people: plain decimals
/// for magnitudes in `[1e-4, 1e6)`, scientific notation otherwise, no trailing zeros.
///
/// # Examples
/// ```
/// use beltrami_testkit::format_significant;
/// assert_eq!(format_significant(3.14159265, 3), "3.14");
/// assert_eq!(format_significant(2.0, 6), "2");
/// assert_eq!(format_significant(1.234e-17, 2), "1.2e-17");
/// assert_eq!(format_significant(0.0, 2), "0");
/// ```
///
/// # Panics
/// Never: scientific formatting always writes an `e`.
#[must_use]
pub fn format_significant(x: f64, digits: u32) -> String {
    let r = round_significant(x, digits);
    if r == 0.0 || !r.is_finite() {
        return format!("{r}");
    }
    let magnitude = r.abs();
    if (1e-4..1e6).contains(&magnitude) {
        format!("{r}")
    } else {
        let digits = digits.max(1) as usize;
        let s = format!("{:.*e}", digits - 1, r);
        // Drop trailing zeros of the mantissa: 1.20e-5 -> 1.2e-5, 1.0e-5 -> 1e-5.
        let (mantissa, exponent) = s.split_once('e').expect("scientific notation");
        let mantissa = if mantissa.contains('.') {
            mantissa.trim_end_matches('0').trim_end_matches('.')
        } else {
            mantissa
        };
        format!("{mantissa}e{exponent}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_is_half_even_on_the_exact_value() {
        // 0.125 is exact: a tie, rounded to even.
        assert_eq!(round_significant(0.125, 2), 0.12);
        assert_eq!(round_significant(0.375, 2), 0.38);
        // 2.675 is stored as 2.67499999...: rounds down, as its exact value says.
        assert_eq!(round_significant(2.675, 3), 2.67);
    }

    #[test]
    fn special_values_pass_through() {
        assert!(round_significant(f64::NAN, 3).is_nan());
        assert_eq!(round_significant(f64::INFINITY, 3), f64::INFINITY);
        assert_eq!(round_significant(1e300, 0), 1e300);
    }

    #[test]
    fn formatting_switches_to_scientific_outside_the_plain_range() {
        assert_eq!(format_significant(123_456_789.0, 3), "1.23e8");
        assert_eq!(format_significant(0.000_012_3, 2), "1.2e-5");
        assert_eq!(format_significant(-0.5, 6), "-0.5");
        assert_eq!(format_significant(999_999.9, 6), "1e6");
    }
}
