//! An axis with our own ticks and labels, as a plotters coordinate.

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};

use crate::ticks;

/// One axis: range, tick positions and labels; plotters asks it for both.
#[derive(Clone)]
pub(super) struct Axis {
    pub(super) range: (f64, f64),
    pub(super) ticks: Vec<f64>,
    pub(super) labels: Vec<String>,
}

impl Axis {
    pub(super) fn linear(range: (f64, f64), target: usize) -> Self {
        let (ticks, step) = ticks::linear_ticks(range.0, range.1, target);
        let magnitude = ticks.iter().fold(0f64, |m, t| m.max(t.abs()));
        let labels = ticks
            .iter()
            .map(|&t| ticks::format_tick(t, step, magnitude))
            .collect();
        Self {
            range,
            ticks,
            labels,
        }
    }

    pub(super) fn log(range: (f64, f64), target: usize) -> Self {
        let ticks = ticks::log_ticks(range.0, range.1, target);
        let labels = ticks.iter().map(|&t| ticks::format_log_tick(t)).collect();
        Self {
            range,
            ticks,
            labels,
        }
    }

    fn label_of(&self, value: f64) -> String {
        self.ticks
            .iter()
            .position(|&t| t == value)
            .and_then(|i| self.labels.get(i).cloned())
            .unwrap_or_default()
    }
}

impl Ranged for Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let t = (value - self.range.0) / (self.range.1 - self.range.0);
        let length = f64::from(limit.1) - f64::from(limit.0);
        // `as` saturates: far-away points stay far away instead of wrapping.
        (f64::from(limit.0) + (length * t + 1e-3).floor()) as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.ticks.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.range.0..self.range.1
    }
}

impl ValueFormatter<f64> for Axis {
    fn format(value: &f64) -> String {
        format!("{value}")
    }

    fn format_ext(&self, value: &f64) -> String {
        self.label_of(*value)
    }
}
