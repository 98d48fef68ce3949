//! Layout of a plot: sizes scaled with the image, data split at skipped points, axis
//! ranges (equal aspect included), marker points and the legend corner.

use plotters::prelude::*;

use super::axis::Axis;
use super::{LinePlot, MAX_SIZE, Series};
use crate::VizError;
use crate::font::{self, TextStyle};
use crate::ticks;

/// Sizes in pixels, scaled with the image.
pub(super) struct Layout {
    /// Font size of the title.
    pub(super) title: f64,
    /// Font size of the axis labels.
    pub(super) label: f64,
    /// Font size of tick labels and the legend.
    pub(super) tick: f64,
    /// Margin around the chart.
    pub(super) margin: i32,
    /// Height of the band under the x axis (tick labels and axis label).
    pub(super) x_label_area: i32,
    /// Width of the band left of the y axis, fitted to the tick labels.
    pub(super) y_label_area: i32,
    /// Line width.
    pub(super) line: u32,
    /// Half-width of a marker.
    pub(super) marker: i32,
}

impl Layout {
    pub(super) fn new(width: u32, height: u32) -> Self {
        let s = (f64::from(width.min(height)) / 500.0).clamp(0.4, 4.0);
        Self {
            title: 22.0 * s,
            label: 17.0 * s,
            tick: 14.0 * s,
            margin: (14.0 * s).round() as i32,
            x_label_area: (48.0 * s).round() as i32,
            y_label_area: 0,
            line: (2.0 * s).round().max(1.0) as u32,
            marker: (3.5 * s).round().max(2.0) as i32,
        }
    }
}

/// The plot's data in drawing coordinates (y as log₁₀ y on a log plot), split at skipped
/// points, with axes, layout and legend position.
pub(super) struct Prepared {
    /// Per series, its unbroken runs of points.
    pub(super) runs: Vec<Vec<Vec<(f64, f64)>>>,
    /// Per series, the points that carry a marker.
    pub(super) markers: Vec<Vec<(f64, f64)>>,
    pub(super) x: Axis,
    pub(super) y: Axis,
    pub(super) layout: Layout,
    pub(super) legend: SeriesLabelPosition,
}

impl Prepared {
    pub(super) fn new(plot: &LinePlot, width: u32, height: u32) -> Result<Self, VizError> {
        if width == 0 || height == 0 || width > MAX_SIZE || height > MAX_SIZE {
            return Err(VizError::Invalid {
                what: "plot size",
                reason: format!("{width}×{height} pixels; each side must be in 1..={MAX_SIZE}"),
            });
        }
        font::register_with_plotters()?;
        let runs: Vec<Vec<Vec<(f64, f64)>>> = plot
            .series
            .iter()
            .map(|s| split_runs(s, plot.log_y))
            .collect();
        let mut bounds: Option<[f64; 4]> = None;
        for &(x, y) in runs.iter().flatten().flatten() {
            let b = bounds.get_or_insert([x, x, y, y]);
            *b = [b[0].min(x), b[1].max(x), b[2].min(y), b[3].max(y)];
        }
        let Some([x_min, x_max, y_min, y_max]) = bounds else {
            return Err(VizError::Invalid {
                what: "plot data",
                reason: format!(
                    "plot '{}' has no finite{} point",
                    plot.title,
                    if plot.log_y { " positive" } else { "" }
                ),
            });
        };
        let mut layout = Layout::new(width, height);
        let target_x = ((f64::from(width) / layout.tick / 6.0) as usize).clamp(3, 10);
        let target_y = ((f64::from(height) / layout.tick / 4.0) as usize).clamp(3, 10);
        let x_range = ticks::padded_range(x_min, x_max, 0.05);
        let mut y_range = ticks::padded_range(y_min, y_max, 0.05);
        if plot.log_y && y_max - y_min <= 0.0 {
            y_range = (y_min - 0.5, y_max + 0.5);
        }
        let make_y = |range| {
            if plot.log_y {
                Axis::log(range, target_y)
            } else {
                Axis::linear(range, target_y)
            }
        };
        let mut x = Axis::linear(x_range, target_x);
        let mut y = make_y(y_range);
        layout.y_label_area = y_label_area(&layout, &y)?;
        if plot.aspect_equal && !plot.log_y {
            // Widen the shorter range about its centre until one unit has the same
            // length on both axes. The y labels change with the range and so may the
            // room they need: grow the label area until they fit, then fit once more.
            let fit = |layout: &Layout| {
                let (w, h) = plot_area_size(layout, plot, width, height);
                let (x0, x1) = ticks::padded_range(x_min, x_max, 0.05);
                let (y0, y1) = ticks::padded_range(y_min, y_max, 0.05);
                let per_pixel = ((x1 - x0) / w).max((y1 - y0) / h);
                let (xc, yc) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
                let x_range = (xc - 0.5 * per_pixel * w, xc + 0.5 * per_pixel * w);
                let y_range = (yc - 0.5 * per_pixel * h, yc + 0.5 * per_pixel * h);
                (Axis::linear(x_range, target_x), make_y(y_range))
            };
            for _ in 0..3 {
                let needed = y_label_area(&layout, &fit(&layout).1)?;
                if needed <= layout.y_label_area {
                    break;
                }
                layout.y_label_area = needed;
            }
            (x, y) = fit(&layout);
        }
        let markers = runs
            .iter()
            .enumerate()
            .map(|(i, series_runs)| marker_points(series_runs, i, runs.len()))
            .collect();
        let legend = legend_corner(plot, &runs, &x, &y, &layout, width, height)?;
        Ok(Self {
            runs,
            markers,
            x,
            y,
            layout,
            legend,
        })
    }
}

/// The finite (and, on a log plot, positive) points of `series` in drawing
/// coordinates, split into runs at the points left out.
pub(super) fn split_runs(series: &Series, log_y: bool) -> Vec<Vec<(f64, f64)>> {
    let mut runs = Vec::new();
    let mut run = Vec::new();
    for &(x, y) in &series.points {
        let y = match (log_y, y > 0.0) {
            (false, _) => y,
            (true, true) => y.log10(),
            (true, false) => f64::NAN,
        };
        if x.is_finite() && y.is_finite() {
            run.push((x, y));
        } else if !run.is_empty() {
            runs.push(std::mem::take(&mut run));
        }
    }
    if !run.is_empty() {
        runs.push(run);
    }
    runs
}

/// The points of a series that carry a marker: all of them for up to 25 points,
/// otherwise about 12, staggered by series so that markers of series sharing their x
/// values do not sit on top of each other.
pub(super) fn marker_points(
    runs: &[Vec<(f64, f64)>],
    index: usize,
    count: usize,
) -> Vec<(f64, f64)> {
    let points: Vec<(f64, f64)> = runs.iter().flatten().copied().collect();
    if points.len() <= 25 {
        return points;
    }
    let stride = points.len().div_ceil(12);
    let offset = index * stride / count.max(1);
    points.into_iter().skip(offset).step_by(stride).collect()
}

/// The width of the y label area: the widest tick label, the gap and the rotated axis
/// label.
pub(super) fn y_label_area(layout: &Layout, y: &Axis) -> Result<i32, VizError> {
    // plotters passes the font size to ab_glyph as the pixel scale: measure alike.
    let tick = TextStyle::new(layout.tick as f32)?;
    let widest = y.labels.iter().map(|l| tick.width(l)).fold(0f32, f32::max);
    Ok((f64::from(widest) + 2.2 * layout.label + 0.8 * layout.tick).ceil() as i32)
}

/// The size of the plotting area (inside the axes) in pixels, as plotters lays it out:
/// the title band, then the chart margin on every side and the label areas.
pub(super) fn plot_area_size(
    layout: &Layout,
    plot: &LinePlot,
    width: u32,
    height: u32,
) -> (f64, f64) {
    let title = if plot.title.is_empty() {
        0
    } else {
        title_height(layout.title)
    };
    let w = i64::from(width) - 2 * i64::from(layout.margin) - i64::from(layout.y_label_area);
    let h =
        i64::from(height) - title - 2 * i64::from(layout.margin) - i64::from(layout.x_label_area);
    (w.max(1) as f64, h.max(1) as f64)
}

/// The height plotters' `titled` takes for a title of font size `size`: the text height
/// its ab_glyph support estimates (`size / 1.24`, truncated) plus twice a padding of
/// min(height / 2, 5).
pub(super) fn title_height(size: f64) -> i64 {
    let text_h = (size / 1.24) as i64;
    i64::from(title_offset(size)) + text_h + 2 * (text_h / 2).min(5)
}

/// The free band above the title, in pixels.
pub(super) fn title_offset(size: f64) -> i32 {
    (0.4 * size).round() as i32
}

/// The legend corner that covers the fewest data, preferring the upper right.
pub(super) fn legend_corner(
    plot: &LinePlot,
    runs: &[Vec<Vec<(f64, f64)>>],
    x: &Axis,
    y: &Axis,
    layout: &Layout,
    width: u32,
    height: u32,
) -> Result<SeriesLabelPosition, VizError> {
    let (w, h) = plot_area_size(layout, plot, width, height);
    let text = TextStyle::new(layout.tick as f32)?;
    let widest = plot
        .series
        .iter()
        .map(|s| text.width(&s.label))
        .fold(0f32, f32::max);
    // plotters' legend: the line sample, the text, margins; one row per series.
    let legend_w = (f64::from(widest) + 2.5 * layout.tick + 40.0) / w;
    let listed = plot.series.iter().filter(|s| s.in_legend).count();
    let legend_h = (listed as f64 * 1.4 * layout.tick + 20.0) / h;
    let (fx, fy) = (legend_w.min(1.0), legend_h.min(1.0));
    let corners = [
        (
            SeriesLabelPosition::UpperRight,
            (1.0 - fx, 1.0),
            (1.0 - fy, 1.0),
        ),
        (SeriesLabelPosition::UpperLeft, (0.0, fx), (1.0 - fy, 1.0)),
        (SeriesLabelPosition::LowerRight, (1.0 - fx, 1.0), (0.0, fy)),
        (SeriesLabelPosition::LowerLeft, (0.0, fx), (0.0, fy)),
    ];
    let normalise = |(px, py): (f64, f64)| {
        (
            (px - x.range.0) / (x.range.1 - x.range.0),
            (py - y.range.0) / (y.range.1 - y.range.0),
        )
    };
    // Sample every segment at 8 points, so that lines crossing a corner count too.
    let mut samples = Vec::new();
    for run in runs.iter().flatten() {
        for pair in run.windows(2) {
            let (a, b) = (normalise(pair[0]), normalise(pair[1]));
            for k in 0..8 {
                let t = f64::from(k) / 8.0;
                samples.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
            }
        }
        if let Some(&last) = run.last() {
            samples.push(normalise(last));
        }
    }
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (position, (x0, x1), (y0, y1)) in corners {
        let covered = samples
            .iter()
            .filter(|(sx, sy)| *sx >= x0 && *sx <= x1 && *sy >= y0 && *sy <= y1)
            .count();
        if covered < best.0 {
            best = (covered, position);
        }
    }
    Ok(best.1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::{chart, titled_area};

    /// The plotting area computed for equal aspect ratios is the one plotters lays out.
    #[test]
    fn plot_area_size_matches_plotters_layout() {
        for (width, height, title) in [(800, 500, "profile"), (1600, 1000, "t"), (333, 211, "")] {
            let mut plot = LinePlot::new(title, "x (mm)", "z (mm)");
            plot.series.push(Series::new("s", [(0.0, 0.0), (3.0, 1.0)]));
            let prepared = Prepared::new(&plot, width, height).unwrap();
            let expected = plot_area_size(&prepared.layout, &plot, width, height);
            let mut rgb = vec![255u8; width as usize * height as usize * 3];
            let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
            let area = titled_area(&root, &plot, &prepared.layout).unwrap();
            let chart = chart(&area, &prepared).unwrap();
            let (w, h) = chart.plotting_area().dim_in_pixel();
            assert_eq!(
                (f64::from(w), f64::from(h)),
                expected,
                "{width}×{height} {title:?}"
            );
        }
    }

    /// With equal aspect, one unit spans as many pixels on both axes.
    #[test]
    fn equal_aspect_gives_equal_units() {
        let mut plot = LinePlot::new("profile", "x (mm)", "z (mm)");
        plot.aspect_equal = true;
        plot.series
            .push(Series::new("s", [(-2.0, 0.0), (2.0, 0.5)]));
        let prepared = Prepared::new(&plot, 800, 500).unwrap();
        let (w, h) = plot_area_size(&prepared.layout, &plot, 800, 500);
        let (x, y) = (prepared.x.range, prepared.y.range);
        let (per_x, per_y) = ((x.1 - x.0) / w, (y.1 - y.0) / h);
        assert!((per_x - per_y).abs() < 1e-12 * per_x, "{per_x} {per_y}");
        assert!(x.0 < -2.0 && x.1 > 2.0 && y.0 < 0.0 && y.1 > 0.5);
    }

    /// The legend avoids the corner the data run through.
    #[test]
    fn the_legend_avoids_the_data() {
        let corner = |points: Vec<(f64, f64)>| {
            let mut plot = LinePlot::new("t", "x", "y");
            plot.series.push(Series::new("a series", points));
            Prepared::new(&plot, 800, 500).unwrap().legend
        };
        let falling = corner(
            (0..=20)
                .map(|i| (f64::from(i), (-f64::from(i)).exp()))
                .collect(),
        );
        assert!(matches!(falling, SeriesLabelPosition::UpperRight));
        let rising = corner((0..=20).map(|i| (f64::from(i), f64::from(i * i))).collect());
        assert!(!matches!(rising, SeriesLabelPosition::UpperRight));
    }
}
