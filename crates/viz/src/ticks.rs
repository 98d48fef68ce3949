//! Axis ranges, "nice" tick positions and tick labels, shared by plots and colour bars.
//!
//! Tick labels are chosen from the tick step, so that small metrology values (an RMS of
//! 1e-4 mm) get readable labels: plain decimals with as many digits as the step needs,
//! and scientific notation (`2.5e-4`) when the values are below 10⁻³ or from 10⁶ up.

/// An axis range `[lo, hi]` covering `[min, max]` with `margin` (a fraction of the span)
/// on each side; a zero span is widened to ±10 % of the value (±1 around 0).
pub(crate) fn padded_range(min: f64, max: f64, margin: f64) -> (f64, f64) {
    let span = max - min;
    if span > 0.0 && span.is_finite() {
        (min - margin * span, max + margin * span)
    } else {
        let half = if min == 0.0 { 1.0 } else { 0.1 * min.abs() };
        (min - half, max + half)
    }
}

/// A step of 1, 2, 2.5 or 5 times a power of ten giving about `target` ticks over
/// `[lo, hi]` (`lo < hi`, both finite).
pub(crate) fn nice_step(lo: f64, hi: f64, target: usize) -> f64 {
    // Halves first: the span of [-1e308, 1e308] is beyond the largest finite number.
    let raw = (hi / 2.0 - lo / 2.0) / target.max(1) as f64 * 2.0;
    let magnitude = 10f64.powf(raw.log10().floor());
    let normalised = raw / magnitude;
    let factor = if normalised <= 1.0 {
        1.0
    } else if normalised <= 2.0 {
        2.0
    } else if normalised <= 2.5 {
        2.5
    } else if normalised <= 5.0 {
        5.0
    } else {
        10.0
    };
    factor * magnitude
}

/// The multiples of a nice step (see [`nice_step`]) inside `[lo, hi]`, and the step.
pub(crate) fn linear_ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, f64) {
    let step = nice_step(lo, hi, target);
    // A relative tolerance keeps ends that rounding puts a hair outside (3e-4 / 5e-5).
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    // A multiple computed as k·step (no accumulation), snapped to 0 when it should be.
    let ticks = (first..=last)
        .map(|k| k as f64 * step)
        .map(|v| if v.abs() < step * 1e-9 { 0.0 } else { v })
        .collect();
    (ticks, step)
}

/// Tick positions for a log axis in decades: `[lo, hi]` are log₁₀ values. Ticks at the
/// powers of ten, thinned to at most about `target`; at 2× and 5× as well when fewer
/// than three decades are visible; at every mantissa when the range is within one
/// decade. Returns the positions (log₁₀ values).
pub(crate) fn log_ticks(lo: f64, hi: f64, target: usize) -> Vec<f64> {
    let first = lo.ceil() as i64;
    let last = hi.floor() as i64;
    let decades = last - first + 1;
    let mantissas: &[f64] = if hi - lo < 1.0 {
        &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
    } else if decades < 3 {
        &[1.0, 2.0, 5.0]
    } else {
        &[1.0]
    };
    let every = ((decades as f64) / target.max(1) as f64).ceil().max(1.0) as i64;
    let mut ticks = Vec::new();
    for k in (lo.floor() as i64)..=(hi.ceil() as i64) {
        if mantissas.len() == 1 && k.rem_euclid(every) != 0 {
            continue;
        }
        for &m in mantissas {
            let v = m.log10() + k as f64;
            if v >= lo && v <= hi {
                ticks.push(v);
            }
        }
    }
    ticks
}

/// The number of decimals that shows a multiple of `step` exactly (at most 12).
fn decimals_for(step: f64) -> usize {
    let mut decimals = (-step.log10().floor()).max(0.0) as usize;
    while decimals < 12 {
        let scaled = step * 10f64.powi(decimals as i32);
        if (scaled - scaled.round()).abs() < 1e-6 * scaled.abs().max(1.0) {
            break;
        }
        decimals += 1;
    }
    decimals
}

/// A label for `value`, one of the ticks of step `step` on an axis whose largest absolute
/// tick is `magnitude`: plain decimals, or scientific notation (`2.5e-4`, mantissas
/// sharing one exponent) when `magnitude` is below 10⁻³ or from 10⁶ up.
pub(crate) fn format_tick(value: f64, step: f64, magnitude: f64) -> String {
    if !value.is_finite() {
        return format!("{value}");
    }
    if value == 0.0 || value.abs() < step * 1e-9 {
        return "0".to_owned();
    }
    let scientific = magnitude > 0.0 && !(1e-3..1e6).contains(&magnitude);
    if scientific {
        let exponent = magnitude.log10().floor() as i32;
        let scale = 10f64.powi(exponent);
        let decimals = decimals_for(step / scale);
        format!("{:.*}e{}", decimals, value / scale, exponent)
    } else {
        format!("{:.*}", decimals_for(step), value)
    }
}

/// `value` to `digits` significant digits (at least 1), without trailing zeros: plain
/// decimals from 10⁻³ up to 10⁶, otherwise scientific notation (`-1.23e-4`). For the
/// labels of values that are not round, such as the ends of a colour bar.
pub(crate) fn format_significant(value: f64, digits: usize) -> String {
    if value == 0.0 || !value.is_finite() {
        return if value == 0.0 {
            "0".to_owned()
        } else {
            format!("{value}")
        };
    }
    let digits = digits.max(1) as i32;
    let mut exponent = value.abs().log10().floor() as i32;
    // Rounding can carry into the next decade (9.996 → 10.0).
    let rounded = |exponent: i32| {
        let scale = 10f64.powi(digits - 1 - exponent);
        (value.abs() * scale).round() / scale
    };
    if rounded(exponent) >= 10f64.powi(exponent + 1) {
        exponent += 1;
    }
    if (-3..6).contains(&exponent) {
        let decimals = (digits - 1 - exponent).max(0) as usize;
        trim_zeros(&format!("{value:.decimals$}")).to_owned()
    } else {
        let mantissa = value / 10f64.powi(exponent);
        let text = format!("{mantissa:.*}", (digits - 1) as usize);
        format!("{}e{exponent}", trim_zeros(&text))
    }
}

/// `text` without the trailing zeros of its fraction (and without a bare point).
fn trim_zeros(text: &str) -> &str {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        text
    }
}

/// A label for the value `10^exponent10` on a log axis: a plain number between 10⁻³ and
/// 10⁵, otherwise `2e-5`.
pub(crate) fn format_log_tick(exponent10: f64) -> String {
    let value = 10f64.powf(exponent10);
    let decade = exponent10.floor() as i32;
    let mantissa = (value / 10f64.powi(decade)).round();
    // Snap mantissa rounding (0.99999 → 1.0 → next decade).
    let (mantissa, decade) = if mantissa >= 10.0 {
        (1.0, decade + 1)
    } else {
        (mantissa.max(1.0), decade)
    };
    if (-3..5).contains(&decade) {
        let decimals = (-decade).max(0) as usize;
        format!("{:.*}", decimals, mantissa * 10f64.powi(decade))
    } else {
        format!("{mantissa:.0}e{decade}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_ticks_are_round_multiples() {
        let (ticks, step) = linear_ticks(-0.05, 1.05, 6);
        assert_eq!(step, 0.2);
        assert_eq!(ticks.len(), 6);
        assert_eq!(ticks[0], 0.0);
        assert!((ticks[5] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn labels_of_small_values_are_readable() {
        let (ticks, step) = linear_ticks(0.0, 3e-4, 6);
        let magnitude = ticks.iter().fold(0f64, |m, t| m.max(t.abs()));
        let labels: Vec<String> = ticks
            .iter()
            .map(|&t| format_tick(t, step, magnitude))
            .collect();
        assert_eq!(
            labels,
            [
                "0", "0.5e-4", "1.0e-4", "1.5e-4", "2.0e-4", "2.5e-4", "3.0e-4"
            ]
        );
        assert_eq!(format_tick(0.25, 0.05, 1.0), "0.25");
        assert_eq!(format_tick(40.0, 20.0, 100.0), "40");
        assert_eq!(format_tick(-0.5, 0.5, 1.0), "-0.5");
        assert_eq!(format_tick(2.5, 2.5, 10.0), "2.5");
    }

    #[test]
    fn significant_digits_label_values_that_are_not_round() {
        let labels: Vec<String> = [
            0.012345, -0.012345, 255.0, 3.2, 1.5e-4, -2.0e-5, 9.9996, 0.0, 1234.6, 2.5e7,
        ]
        .iter()
        .map(|&v| format_significant(v, 3))
        .collect();
        assert_eq!(
            labels,
            [
                "0.0123", "-0.0123", "255", "3.2", "1.5e-4", "-2e-5", "10", "0", "1235", "2.5e7"
            ]
        );
        assert_eq!(format_significant(0.00099996, 3), "0.001");
    }

    #[test]
    fn log_ticks_fall_on_decades() {
        let ticks = log_ticks(-4.2, 0.3, 10);
        let labels: Vec<String> = ticks.iter().map(|&t| format_log_tick(t)).collect();
        assert_eq!(labels, ["1e-4", "0.001", "0.01", "0.1", "1"]);
        let ticks = log_ticks(-1.2, 0.1, 10);
        let labels: Vec<String> = ticks.iter().map(|&t| format_log_tick(t)).collect();
        assert_eq!(labels, ["0.1", "0.2", "0.5", "1"]);
    }

    #[test]
    fn zero_span_is_widened() {
        assert_eq!(padded_range(0.0, 0.0, 0.05), (-1.0, 1.0));
        let (lo, hi) = padded_range(2.0, 2.0, 0.05);
        assert!(lo < 2.0 && hi > 2.0);
    }
}
