//! Numbers for human-readable messages (error lines, summaries), shared by every crate
//! that writes them, so that one value reads the same everywhere.

/// `x` with six significant digits and no trailing zeros: `0.00702305`, `1234.57`,
/// `7.02305e-6`, `1e-300`, `1e100`. Plain notation for magnitudes from 1e-4 up to 1e6,
/// scientific otherwise, so that a tiny or huge value does not print hundreds of digits;
/// `0` (for either sign), `inf`, `-inf` and `NaN` as such. Values meant to be read back
/// (JSON, files) keep full precision instead.
#[must_use]
pub fn short_number(x: f64) -> String {
    fn trim(text: &str) -> &str {
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.')
        } else {
            text
        }
    }
    if x == 0.0 {
        return "0".to_string();
    }
    if !x.is_finite() {
        return x.to_string();
    }
    let magnitude = x.abs();
    if (1e-4..1e6).contains(&magnitude) {
        #[allow(clippy::cast_possible_truncation, reason = "a small exponent")]
        let exponent = magnitude.log10().floor() as i32;
        let decimals = usize::try_from((5 - exponent).max(0)).unwrap_or(0);
        // Rounding may carry into a new digit (999999.5 -> "1000000"); still fine.
        trim(&format!("{x:.decimals$}")).to_string()
    } else {
        let text = format!("{x:.5e}");
        match text.split_once('e') {
            Some((mantissa, exponent)) => format!("{}e{exponent}", trim(mantissa)),
            None => text,
        }
    }
}

/// `x` exactly (the shortest text that reads back as the same `f64`), for a message that
/// echoes a value it refuses, where six digits could hide why (`1.0000001` is not `1`):
/// plain notation for magnitudes from 1e-4 up to 1e15 (`0.5`, `-1`, `180.0001`),
/// scientific otherwise (`1e300`, `2.5e-7`), so that a huge or tiny value does not print
/// hundreds of digits; `0`, `inf`, `-inf` and `NaN` as such.
#[must_use]
pub fn exact_number(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&x.abs()) {
        // Display: the shortest round-trip digits, without an exponent.
        x.to_string()
    } else {
        // LowerExp: the same digits with an exponent (`1e300`, `2.5e-7`).
        format!("{x:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_numbers_read_back() {
        assert_eq!(exact_number(0.5), "0.5");
        assert_eq!(exact_number(-1.0), "-1");
        assert_eq!(exact_number(0.0), "0");
        assert_eq!(exact_number(180.0001), "180.0001");
        assert_eq!(exact_number(1.000_000_1), "1.0000001");
        assert_eq!(exact_number(1e300), "1e300");
        assert_eq!(exact_number(-2.5e-7), "-2.5e-7");
        assert_eq!(exact_number(1e15), "1e15");
        assert_eq!(exact_number(f64::NAN), "NaN");
        assert_eq!(exact_number(f64::INFINITY), "inf");
        for x in [0.1, 1e-310, 123_456.789, 6.02e23, -1e-4, 9.999e14] {
            assert_eq!(exact_number(x).parse::<f64>().unwrap(), x, "{x}");
        }
    }

    #[test]
    fn six_significant_digits_without_trailing_zeros() {
        assert_eq!(short_number(1e-300), "1e-300");
        assert_eq!(short_number(1e100), "1e100");
        assert_eq!(short_number(1.138_071_187_457_698_3), "1.13807");
        assert_eq!(short_number(0.007_023_049_277_268_29), "0.00702305");
        assert_eq!(short_number(7.023_049_277e-6), "7.02305e-6");
        assert_eq!(short_number(0.1), "0.1");
        assert_eq!(short_number(0.0), "0");
        assert_eq!(short_number(-0.0), "0");
        assert_eq!(short_number(f64::NEG_INFINITY), "-inf");
    }
}
