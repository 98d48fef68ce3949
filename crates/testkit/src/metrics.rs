//! [`MetricsTable`]: named measurements with units, rounded for snapshots.

use std::fmt;

use serde::Serialize;

use crate::round::{SUMMARY_DIGITS, format_significant, round_significant};

/// One measurement of a [`MetricsTable`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MetricRow {
    /// What was measured (`rms distance to reference`, `volume ratio`, …).
    pub name: String,
    /// The value, rounded to [`SUMMARY_DIGITS`] significant digits.
    pub value: f64,
    /// The unit (`mm`, `deg`, `` for a ratio).
    pub unit: String,
}

/// A table of named measurements — the metrics of a smoothing study, a fit, a distance
/// computation — each rounded to [`SUMMARY_DIGITS`] significant digits so that a snapshot
/// of it changes only when a result really changes.
///
/// It holds plain numbers, so it works with any metric (those of `beltrami-metrics` or
/// your own). `Display` prints aligned `name  value unit` lines under a title; `serde`
/// gives the rows.
///
/// # Examples
/// ```
/// use beltrami_testkit::MetricsTable;
/// let mut table = MetricsTable::new("sphere after 10 iterations");
/// table.push("fitted radius", 0.987_654_321, "mm");
/// table.push("volume ratio", 0.962_962_96, "");
/// assert_eq!(table.rows[0].value, 0.987654);
/// assert_eq!(table.get("volume ratio"), Some(0.962963));
/// assert!(table.to_string().contains("fitted radius  0.987654 mm"));
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MetricsTable {
    /// A heading printed above the rows.
    pub title: String,
    /// The rows in the order they were pushed.
    pub rows: Vec<MetricRow>,
}

impl MetricsTable {
    /// An empty table with a heading.
    #[must_use]
    pub fn new(title: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            rows: Vec::new(),
        }
    }

    /// Adds a measurement (rounded on the way in).
    pub fn push(&mut self, name: impl Into<String>, value: f64, unit: impl Into<String>) {
        self.rows.push(MetricRow {
            name: name.into(),
            value: round_significant(value, SUMMARY_DIGITS),
            unit: unit.into(),
        });
    }

    /// The (rounded) value of the first row called `name`.
    #[must_use]
    pub fn get(&self, name: &str) -> Option<f64> {
        self.rows.iter().find(|r| r.name == name).map(|r| r.value)
    }
}

impl fmt::Display for MetricsTable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.title)?;
        let width = self.rows.iter().map(|r| r.name.len()).max().unwrap_or(0);
        for r in &self.rows {
            let value = format_significant(r.value, SUMMARY_DIGITS);
            let line = format!("{:<width$}  {value} {}", r.name, r.unit);
            writeln!(f, "{}", line.trim_end())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_rounded_and_aligned() {
        let mut t = MetricsTable::new("m");
        t.push("a", 1.234_567_89e-9, "mm");
        t.push("longer name", 42.0, "");
        assert_eq!(t.rows[0].value, 1.234_57e-9);
        let text = t.to_string();
        assert_eq!(text, "m\na            1.23457e-9 mm\nlonger name  42\n");
        assert_eq!(t.get("missing"), None);
    }

    #[test]
    fn serialises_the_rounded_rows() {
        let mut t = MetricsTable::new("m");
        t.push("x", 2.0 / 3.0, "");
        let json = serde_json::to_string(&t).unwrap();
        assert_eq!(
            json,
            r#"{"title":"m","rows":[{"name":"x","value":0.666667,"unit":""}]}"#
        );
    }
}
