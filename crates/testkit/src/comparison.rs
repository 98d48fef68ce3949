//! [`Deviation`] between two sets of positions and a [`ComparisonTable`] of them.

use std::fmt;

use beltrami_halfedge::DVec3;
use serde::Serialize;

use crate::round::{DEVIATION_DIGITS, format_significant, round_significant};

/// How far two position sets lie apart: the largest Euclidean distance between
/// corresponding vertices, absolute and in units of a reference length (normally the
/// bounding-box diagonal of the input).
///
/// # Examples
/// ```
/// use beltrami_halfedge::DVec3;
/// use beltrami_testkit::Deviation;
/// let a = [DVec3::ZERO, DVec3::X];
/// let b = [DVec3::ZERO, DVec3::new(1.0, 0.0, 1e-13)];
/// let d = Deviation::between(&a, &b, 2.0);
/// assert_eq!(d.max, 1e-13);
/// assert_eq!(d.relative(), 5e-14);
/// assert!(!d.identical);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Deviation {
    /// The largest distance between corresponding positions.
    pub max: f64,
    /// The reference length the deviation is measured against.
    pub reference_length: f64,
    /// Whether every coordinate is bit for bit the same.
    pub identical: bool,
    /// The index of the vertex with the largest deviation (0 when identical).
    pub worst_vertex: usize,
}

impl Deviation {
    /// The deviation of `b` from `a`, measured against `reference_length`.
    ///
    /// # Panics
    /// If `a` and `b` have different lengths (a programming error in the test).
    #[must_use]
    pub fn between(a: &[DVec3], b: &[DVec3], reference_length: f64) -> Self {
        assert_eq!(a.len(), b.len(), "position sets of different sizes");
        let mut max: f64 = 0.0;
        let mut worst = 0;
        let mut identical = true;
        for (i, (p, q)) in a.iter().zip(b).enumerate() {
            let same_bits = p.x.to_bits() == q.x.to_bits()
                && p.y.to_bits() == q.y.to_bits()
                && p.z.to_bits() == q.z.to_bits();
            identical &= same_bits;
            let d = (*q - *p).length();
            if d > max || d.is_nan() {
                max = d;
                worst = i;
            }
        }
        Self {
            max,
            reference_length,
            identical,
            worst_vertex: worst,
        }
    }

    /// `max / reference_length` (or `max` when the reference length is not positive).
    #[must_use]
    pub fn relative(&self) -> f64 {
        if self.reference_length > 0.0 {
            self.max / self.reference_length
        } else {
            self.max
        }
    }
}

/// One row of a [`ComparisonTable`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ComparisonRow {
    /// What was compared.
    pub case: String,
    /// The largest deviation over the reference length, rounded to [`DEVIATION_DIGITS`]
    /// significant digits.
    pub deviation: f64,
    /// Whether the two sides agree bit for bit.
    pub identical: bool,
    /// The largest acceptable relative deviation.
    pub tolerance: f64,
    /// Whether the (unrounded) deviation is within the tolerance.
    pub within: bool,
}

/// A table of comparisons, each a relative [`Deviation`] against a tolerance — the
/// readable form of "how close are we to the reference" for a snapshot.
///
/// Deviations are rounded to [`DEVIATION_DIGITS`] significant digits; the `bits` column
/// says `identical` when the two sides agree to the last bit. `Display` prints an aligned
/// text table; `serde` gives the rows.
///
/// # Examples
/// ```
/// use beltrami_halfedge::DVec3;
/// use beltrami_testkit::{ComparisonTable, Deviation};
/// let mut table = ComparisonTable::new("demo");
/// let a = [DVec3::ONE];
/// table.push("same", Deviation::between(&a, &a, 1.0), 1e-12);
/// table.push("off", Deviation::between(&a, &[DVec3::new(1.0, 1.0, 1.1)], 1.0), 1e-12);
/// assert!(!table.all_within());
/// assert_eq!(table.failures().len(), 1);
/// assert!(table.to_string().contains("identical"));
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct ComparisonTable {
    /// A heading printed above the rows.
    pub title: String,
    /// The rows in the order they were pushed.
    pub rows: Vec<ComparisonRow>,
}

impl ComparisonTable {
    /// An empty table with a heading.
    #[must_use]
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            rows: Vec::new(),
        }
    }

    /// Adds a row for `case` with the given deviation and relative tolerance.
    pub fn push(&mut self, case: impl Into<String>, deviation: Deviation, tolerance: f64) {
        let relative = deviation.relative();
        self.rows.push(ComparisonRow {
            case: case.into(),
            deviation: round_significant(relative, DEVIATION_DIGITS),
            identical: deviation.identical,
            tolerance,
            within: relative <= tolerance,
        });
    }

    /// Whether every row is within its tolerance.
    #[must_use]
    pub fn all_within(&self) -> bool {
        self.rows.iter().all(|r| r.within)
    }

    /// The rows outside their tolerance.
    #[must_use]
    pub fn failures(&self) -> Vec<&ComparisonRow> {
        self.rows.iter().filter(|r| !r.within).collect()
    }

    /// The largest rounded deviation in the table (0 for an empty table).
    #[must_use]
    pub fn max_deviation(&self) -> f64 {
        self.rows.iter().map(|r| r.deviation).fold(0.0, f64::max)
    }
}

impl fmt::Display for ComparisonTable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.title)?;
        let width = self
            .rows
            .iter()
            .map(|r| r.case.len())
            .chain(["case".len()])
            .max()
            .unwrap_or(4);
        writeln!(
            f,
            "{:<width$}  {:>13}  {:>9}  {:>9}  within",
            "case", "max dev/diag", "tolerance", "bits"
        )?;
        for r in &self.rows {
            writeln!(
                f,
                "{:<width$}  {:>13}  {:>9}  {:>9}  {}",
                r.case,
                format_significant(r.deviation, DEVIATION_DIGITS),
                format_significant(r.tolerance, DEVIATION_DIGITS),
                if r.identical { "identical" } else { "differ" },
                if r.within { "yes" } else { "NO" }
            )?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deviation_finds_the_worst_vertex() {
        let a = [DVec3::ZERO, DVec3::ZERO, DVec3::ZERO];
        let b = [DVec3::ZERO, DVec3::new(0.0, 3.0, 4.0), DVec3::X];
        let d = Deviation::between(&a, &b, 10.0);
        assert_eq!((d.max, d.worst_vertex, d.identical), (5.0, 1, false));
        assert_eq!(d.relative(), 0.5);
    }

    #[test]
    fn negative_zero_is_not_bit_identical_but_has_no_deviation() {
        let d = Deviation::between(&[DVec3::ZERO], &[DVec3::new(-0.0, 0.0, 0.0)], 1.0);
        assert_eq!(d.max, 0.0);
        assert!(!d.identical);
    }

    #[test]
    fn a_nan_is_the_worst_deviation_and_fails() {
        let d = Deviation::between(&[DVec3::ZERO, DVec3::ONE], &[DVec3::ONE, DVec3::NAN], 1.0);
        assert_eq!(d.worst_vertex, 1);
        let mut t = ComparisonTable::new("nan");
        t.push("nan", d, 1e-12);
        assert!(!t.all_within());
    }

    #[test]
    fn the_table_rounds_and_aligns() {
        let mut t = ComparisonTable::new("t");
        let a = [DVec3::ZERO];
        t.push(
            "a-long-case-name",
            Deviation::between(&a, &[DVec3::new(1.234_567e-15, 0.0, 0.0)], 1.0),
            1e-12,
        );
        t.push("b", Deviation::between(&a, &a, 1.0), 1e-12);
        assert_eq!(t.rows[0].deviation, 1.2e-15);
        assert_eq!(t.max_deviation(), 1.2e-15);
        let text = t.to_string();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4);
        assert!(lines[2].starts_with("a-long-case-name"));
        assert!(lines[2].contains("1.2e-15"));
        assert!(lines[3].contains("identical"));
        assert_eq!(lines[2].len(), lines[3].len());
    }
}
