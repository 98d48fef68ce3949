//! Line plots of metrics against iterations (one series per weight scheme), as SVG and
//! PNG, drawn with [plotters].
//!
//! Text in PNG output is rasterised from the bundled DejaVu Sans (registered with
//! plotters' `ab_glyph` support), so plots look the same on machines without fonts; SVG
//! output names the `sans-serif` family and leaves the font to the viewer. Output is
//! deterministic: the same plot gives the same bytes.
//!
//! Each series gets a colour (Okabe–Ito palette) and a marker shape; markers are drawn at
//! every point of short series and at about a dozen staggered points of long ones. The
//! legend lists the series in order, in the corner of the plot that covers the fewest
//! data. Axis ranges enclose the data with a 5 % margin; ticks fall on round values and
//! small values get readable labels (`2.5e-4`).
//!
//! # Examples
//! ```
//! use beltrami_viz::plot::{LinePlot, Series, plot_png, plot_svg};
//!
//! let mut plot = LinePlot::new("RMS distance to the reference", "iterations", "RMS (mm)");
//! plot.series.push(Series::new("uniform", [(0.0, 4e-4), (10.0, 2e-4), (20.0, 1.5e-4)]));
//! plot.series.push(Series::new("cotangent", [(0.0, 4e-4), (10.0, 1e-4), (20.0, 0.6e-4)]));
//! let svg = plot_svg(&plot, 640, 400)?;
//! assert!(svg.contains("cotangent"));
//! let png = plot_png(&plot, 640, 400)?;
//! assert_eq!(&png[1..4], b"PNG");
//! # Ok::<(), beltrami_viz::VizError>(())
//! ```

use std::path::Path;

use plotters::coord::Shift;
use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};
use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters::style::{FontFamily, FontStyle};
use plotters_backend::{BackendCoord, DrawingErrorKind};

use crate::VizError;
use crate::font::{self, TextStyle};
use crate::ticks;

/// One line of a plot: a label for the legend and `(x, y)` points in order.
///
/// Points with a non-finite coordinate are skipped, and the line breaks there; on a
/// log-scale plot points with `y ≤ 0` are skipped the same way.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Series {
    /// The label shown in the legend.
    pub label: String,
    /// The points, joined in this order.
    pub points: Vec<(f64, f64)>,
}

impl Series {
    /// A series named `label` through `points`.
    #[must_use]
    pub fn new(label: impl Into<String>, points: impl IntoIterator<Item = (f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points: points.into_iter().collect(),
        }
    }
}

/// A line plot: title, axis labels and series (legend order = series order).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinePlot {
    /// The title above the plot.
    pub title: String,
    /// The label of the x axis (with its unit).
    pub x_label: String,
    /// The label of the y axis (with its unit).
    pub y_label: String,
    /// The series, drawn and listed in the legend in this order.
    pub series: Vec<Series>,
    /// A logarithmic y axis (decades); points with `y ≤ 0` are skipped.
    pub log_y: bool,
    /// One unit on the x axis as long as one unit on the y axis (cross-section
    /// profiles): the shorter range is widened. Ignored with `log_y`.
    pub aspect_equal: bool,
}

impl LinePlot {
    /// A plot without series, linear axes and free aspect ratio.
    #[must_use]
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Self::default()
        }
    }
}

/// The size of the SVG written by [`write_plot`], in pixels.
pub const SVG_SIZE: (u32, u32) = (800, 500);
/// The size of the PNG written by [`write_plot`], in pixels (twice [`SVG_SIZE`], for
/// sharp figures in documents).
pub const PNG_SIZE: (u32, u32) = (1600, 1000);
/// The largest accepted width or height, in pixels.
pub const MAX_SIZE: u32 = 8192;

/// The plot as an SVG document of `width × height` pixels.
///
/// # Errors
/// [`VizError::Invalid`] when no series has a finite point (or a positive one with
/// `log_y`), or a size is 0 or above [`MAX_SIZE`]; [`VizError::Draw`] when drawing fails.
pub fn plot_svg(plot: &LinePlot, width: u32, height: u32) -> Result<String, VizError> {
    let prepared = Prepared::new(plot, width, height)?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        draw(&root, plot, &prepared).map_err(|e| draw_error(plot, e))?;
        root.present().map_err(|e| draw_error(plot, e))?;
    }
    Ok(svg)
}

/// The plot as an encoded PNG image of `width × height` pixels (8-bit RGB).
///
/// # Errors
/// As [`plot_svg`].
pub fn plot_png(plot: &LinePlot, width: u32, height: u32) -> Result<Vec<u8>, VizError> {
    let prepared = Prepared::new(plot, width, height)?;
    let mut rgb = vec![255u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        draw(&root, plot, &prepared).map_err(|e| draw_error(plot, e))?;
        root.present().map_err(|e| draw_error(plot, e))?;
    }
    crate::render::Image { width, height, rgb }.encode_png()
}

/// Writes the plot to `stem.svg` ([`SVG_SIZE`]) and `stem.png` ([`PNG_SIZE`]), each
/// atomically (a failed write leaves no partial file). The extensions are appended, so
/// a stem `fig.rms` gives `fig.rms.svg`.
///
/// # Errors
/// As [`plot_svg`], and [`VizError::Write`] when a file cannot be written; both images
/// are drawn before either file is written.
pub fn write_plot(plot: &LinePlot, stem: &Path) -> Result<(), VizError> {
    let svg = plot_svg(plot, SVG_SIZE.0, SVG_SIZE.1)?;
    let png = plot_png(plot, PNG_SIZE.0, PNG_SIZE.1)?;
    beltrami_io::write_bytes_atomic(&with_suffix(stem, ".svg"), svg.as_bytes())?;
    beltrami_io::write_bytes_atomic(&with_suffix(stem, ".png"), &png)?;
    Ok(())
}

/// `stem` with `suffix` appended to its file name.
fn with_suffix(stem: &Path, suffix: &str) -> std::path::PathBuf {
    let mut name = stem.as_os_str().to_owned();
    name.push(suffix);
    name.into()
}

fn draw_error(plot: &LinePlot, error: impl std::fmt::Display) -> VizError {
    VizError::Draw {
        name: plot.title.clone(),
        reason: error.to_string(),
    }
}

/// The Okabe–Ito colours (yellow left out: too light on white), then grey.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(136, 136, 136),
];

/// Marker shapes, cycled through by series (7 shapes against 8 colours, so that the
/// combinations repeat only after 56 series).
#[derive(Clone, Copy)]
enum Marker {
    Circle,
    Square,
    Triangle,
    Diamond,
    Cross,
    OpenCircle,
    OpenSquare,
}

const MARKERS: [Marker; 7] = [
    Marker::Circle,
    Marker::Square,
    Marker::Triangle,
    Marker::Diamond,
    Marker::Cross,
    Marker::OpenCircle,
    Marker::OpenSquare,
];

/// A marker at `at` (a data point, or a legend entry's left end), optionally with a
/// line sample through it for the legend. One element type for every shape, drawn
/// straight on the backend.
#[derive(Clone, Copy)]
struct Glyph<C> {
    at: C,
    kind: Marker,
    /// Half-width of the marker in pixels.
    size: i32,
    color: RGBColor,
    /// Line width in pixels.
    stroke: u32,
    /// For a legend entry: the length of the line sample, the marker in its middle.
    sample: Option<i32>,
}

impl<'a, C: 'a> PointCollection<'a, C> for &'a Glyph<C> {
    type Point = &'a C;
    type IntoIter = std::iter::Once<&'a C>;

    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<C, DB: DrawingBackend> Drawable<DB> for Glyph<C> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut points: I,
        backend: &mut DB,
        _parent: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some((mut x, y)) = points.next() else {
            return Ok(());
        };
        let line = self.color.stroke_width(self.stroke);
        if let Some(length) = self.sample {
            backend.draw_line((x, y), (x + length, y), &line)?;
            x += length / 2;
        }
        let r = self.size;
        let filled = self.color.filled();
        let outline = self.color.stroke_width((self.stroke / 2).max(1));
        match self.kind {
            Marker::Circle => backend.draw_circle((x, y), r as u32, &filled, true),
            Marker::OpenCircle => backend.draw_circle((x, y), r as u32, &outline, false),
            Marker::Square => backend.draw_rect((x - r, y - r), (x + r, y + r), &filled, true),
            Marker::OpenSquare => {
                backend.draw_rect((x - r, y - r), (x + r, y + r), &outline, false)
            }
            Marker::Triangle => {
                let h = r + r / 3 + 1;
                backend.fill_polygon([(x, y - h), (x + h, y + r), (x - h, y + r)], &filled)
            }
            Marker::Diamond => {
                let h = r + r / 3 + 1;
                backend.fill_polygon([(x, y - h), (x + h, y), (x, y + h), (x - h, y)], &filled)
            }
            Marker::Cross => {
                let stroke = self.color.stroke_width(self.stroke.max(2));
                backend.draw_line((x - r, y - r), (x + r, y + r), &stroke)?;
                backend.draw_line((x - r, y + r), (x + r, y - r), &stroke)
            }
        }
    }
}

/// Sizes in pixels, scaled with the image.
struct Layout {
    title: f64,
    label: f64,
    tick: f64,
    margin: i32,
    x_label_area: i32,
    y_label_area: i32,
    line: u32,
    marker: i32,
}

impl Layout {
    fn new(width: u32, height: u32) -> Self {
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

/// One axis: range, tick positions and labels; plotters asks it for both.
#[derive(Clone)]
struct Axis {
    range: (f64, f64),
    ticks: Vec<f64>,
    labels: Vec<String>,
}

impl Axis {
    fn linear(range: (f64, f64), target: usize) -> Self {
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

    fn log(range: (f64, f64), target: usize) -> Self {
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

/// The plot's data in drawing coordinates (y as log₁₀ y on a log plot), split at skipped
/// points, with axes, layout and legend position.
struct Prepared {
    /// Per series, its unbroken runs of points.
    runs: Vec<Vec<Vec<(f64, f64)>>>,
    /// Per series, the points that carry a marker.
    markers: Vec<Vec<(f64, f64)>>,
    x: Axis,
    y: Axis,
    layout: Layout,
    legend: SeriesLabelPosition,
}

impl Prepared {
    fn new(plot: &LinePlot, width: u32, height: u32) -> Result<Self, VizError> {
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
        let mut x_range = ticks::padded_range(x_min, x_max, 0.05);
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
            // length on both axes; the y labels may change with the range, so settle
            // the label area in a few rounds.
            for _ in 0..3 {
                let (w, h) = plot_area_size(&layout, plot, width, height);
                let (x0, x1) = ticks::padded_range(x_min, x_max, 0.05);
                let (y0, y1) = ticks::padded_range(y_min, y_max, 0.05);
                let per_pixel = ((x1 - x0) / w).max((y1 - y0) / h);
                let (xc, yc) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
                x_range = (xc - 0.5 * per_pixel * w, xc + 0.5 * per_pixel * w);
                y_range = (yc - 0.5 * per_pixel * h, yc + 0.5 * per_pixel * h);
                x = Axis::linear(x_range, target_x);
                y = make_y(y_range);
                let area = y_label_area(&layout, &y)?;
                if area == layout.y_label_area {
                    break;
                }
                layout.y_label_area = area;
            }
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
fn split_runs(series: &Series, log_y: bool) -> Vec<Vec<(f64, f64)>> {
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
fn marker_points(runs: &[Vec<(f64, f64)>], index: usize, count: usize) -> Vec<(f64, f64)> {
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
fn y_label_area(layout: &Layout, y: &Axis) -> Result<i32, VizError> {
    // plotters passes the font size to ab_glyph as the pixel scale: measure alike.
    let tick = TextStyle::new(layout.tick as f32)?;
    let widest = y.labels.iter().map(|l| tick.width(l)).fold(0f32, f32::max);
    Ok((f64::from(widest) + 2.2 * layout.label + 0.8 * layout.tick).ceil() as i32)
}

/// The size of the plotting area (inside the axes) in pixels, as plotters lays it out:
/// the title band, then the chart margin on every side and the label areas.
fn plot_area_size(layout: &Layout, plot: &LinePlot, width: u32, height: u32) -> (f64, f64) {
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
fn title_height(size: f64) -> i64 {
    let text_h = (size / 1.24) as i64;
    i64::from(title_offset(size)) + text_h + 2 * (text_h / 2).min(5)
}

/// The free band above the title, in pixels.
fn title_offset(size: f64) -> i32 {
    (0.4 * size).round() as i32
}

/// The legend corner that covers the fewest data, preferring the upper right.
fn legend_corner(
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
    // plotters' legend: a 30 px sample, the text, margins; one row per series.
    let legend_w = (f64::from(widest) + 2.5 * layout.tick + 40.0) / w;
    let legend_h = (plot.series.len() as f64 * 1.4 * layout.tick + 20.0) / h;
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

fn font(size: f64) -> FontDesc<'static> {
    FontDesc::new(FontFamily::SansSerif, size, FontStyle::Normal)
}

/// Draws the title and returns the area below it.
fn titled_area<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: &LinePlot,
    layout: &Layout,
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    if plot.title.is_empty() {
        Ok(root.clone())
    } else {
        // plotters' ab_glyph text sits higher than its top anchor: leave room above.
        root.margin(title_offset(layout.title), 0, 0, 0)
            .titled(&plot.title, font(layout.title).color(&BLACK))
    }
}

/// A chart with our axes.
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<Axis, Axis>>;

/// The chart on `area`, with margins and label areas; draws nothing.
fn chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    prepared: &Prepared,
) -> Result<Chart<'a, DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    let layout = &prepared.layout;
    ChartBuilder::on(area)
        .margin(layout.margin)
        .x_label_area_size(layout.x_label_area)
        .y_label_area_size(layout.y_label_area)
        .build_cartesian_2d(prepared.x.clone(), prepared.y.clone())
}

fn draw<'a, DB: DrawingBackend + 'a>(
    root: &'a DrawingArea<DB, Shift>,
    plot: &LinePlot,
    prepared: &Prepared,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let layout = &prepared.layout;
    root.fill(&WHITE)?;
    let area = titled_area(root, plot, layout)?;
    let mut chart = chart(&area, prepared)?;
    chart
        .configure_mesh()
        .x_desc(plot.x_label.as_str())
        .y_desc(plot.y_label.as_str())
        .label_style(font(layout.tick).color(&BLACK))
        .axis_desc_style(font(layout.label).color(&BLACK))
        .bold_line_style(RGBColor(0, 0, 0).mix(0.12))
        .light_line_style(TRANSPARENT)
        .axis_style(BLACK.stroke_width(layout.line.div_ceil(2)))
        .draw()?;
    let (layout_marker, layout_line) = (layout.marker, layout.line);
    for (i, (series, runs)) in plot.series.iter().zip(&prepared.runs).enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        let kind = MARKERS[i % MARKERS.len()];
        let style = color.stroke_width(layout.line);
        for run in runs {
            chart.draw_series(LineSeries::new(run.iter().copied(), style))?;
        }
        let glyph = |at| Glyph {
            at,
            kind,
            size: layout.marker,
            color,
            stroke: layout.line,
            sample: None,
        };
        chart.draw_series(prepared.markers[i].iter().map(|&p| glyph(p)))?;
        let sample = (layout.tick * 2.2).round() as i32;
        chart
            .draw_series(LineSeries::new(std::iter::empty(), style))?
            .label(series.label.as_str())
            .legend(move |at: BackendCoord| Glyph {
                at,
                kind,
                size: layout_marker,
                color,
                stroke: layout_line,
                sample: Some(sample),
            });
    }
    chart
        .configure_series_labels()
        .position(prepared.legend.clone())
        .margin(layout.margin)
        .legend_area_size((layout.tick * 2.6).round() as i32)
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(0, 0, 0).mix(0.4))
        .label_font(font(layout.tick).color(&BLACK))
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
