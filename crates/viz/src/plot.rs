//! Line plots of metrics against iterations (one series per weight scheme), as SVG and
//! PNG, drawn with [plotters].
//!
//! Text in PNG output is rasterised from the bundled DejaVu Sans (registered with
//! plotters' `ab_glyph` support for measuring, and laid out with kerning and side
//! bearings by a thin backend wrapper), so plots look the same on machines without fonts; SVG
//! output names the `sans-serif` family and leaves the font to the viewer. Output is
//! deterministic: the same plot gives the same bytes.
//!
//! Each series gets a colour (Okabe–Ito palette) and a marker shape, by its position or
//! by a fixed palette slot ([`Series::style`]); dashed series have no markers. Markers are drawn at
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
use plotters::prelude::*;
use plotters::style::{FontFamily, FontStyle};
use plotters_backend::BackendCoord;

use crate::VizError;

mod axis;
mod backend;
mod glyph;
mod layout;

use axis::Axis;
use backend::FontBackend;
use glyph::{Glyph, MARKERS, PALETTE};
use layout::{Layout, Prepared, title_offset};

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
    /// The palette slot (colour and marker shape) of the series; `None`: its position
    /// in the plot. Fixing it keeps one colour per quantity (a weight scheme) across
    /// plots that show different subsets.
    pub style: Option<usize>,
    /// Draw the line dashed and without markers (a prediction or reference beside the
    /// data).
    pub dashed: bool,
    /// List the series in the legend (default); `false` for a companion line, e.g. the
    /// bounds of a spread drawn beside its mean.
    pub in_legend: bool,
}

impl Series {
    /// A series named `label` through `points`.
    #[must_use]
    pub fn new(label: impl Into<String>, points: impl IntoIterator<Item = (f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points: points.into_iter().collect(),
            style: None,
            dashed: false,
            in_legend: true,
        }
    }

    /// Sets the palette slot (see [`style`](Self::style)).
    #[must_use]
    pub fn with_style(mut self, slot: usize) -> Self {
        self.style = Some(slot);
        self
    }

    /// Draws the series dashed, without markers.
    #[must_use]
    pub fn dashed(mut self) -> Self {
        self.dashed = true;
        self
    }

    /// Leaves the series out of the legend (see [`in_legend`](Self::in_legend)).
    #[must_use]
    pub fn without_legend(mut self) -> Self {
        self.in_legend = false;
        self
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
        let bitmap = BitMapBackend::with_buffer(&mut rgb, (width, height));
        let root = FontBackend(bitmap).into_drawing_area();
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
    beltrami_io::write_bytes_atomic(with_suffix(stem, ".svg"), svg.as_bytes())?;
    beltrami_io::write_bytes_atomic(with_suffix(stem, ".png"), &png)?;
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
        let slot = series.style.unwrap_or(i);
        let color = PALETTE[slot % PALETTE.len()];
        let kind = MARKERS[slot % MARKERS.len()];
        // A companion line (left out of the legend) is drawn at half the width.
        let width = if series.in_legend {
            layout.line
        } else {
            (layout.line / 2).max(1)
        };
        let style = color.stroke_width(width);
        for run in runs {
            if series.dashed {
                let dash = (layout.tick * 0.8).round().max(2.0) as i32;
                chart.draw_series(DashedLineSeries::new(
                    run.iter().copied(),
                    dash,
                    dash,
                    style,
                ))?;
            } else {
                chart.draw_series(LineSeries::new(run.iter().copied(), style))?;
            }
        }
        let glyph = |at| Glyph {
            at,
            kind,
            size: layout.marker,
            color,
            stroke: layout.line,
            sample: None,
            dashed: false,
        };
        if !series.dashed {
            chart.draw_series(prepared.markers[i].iter().map(|&p| glyph(p)))?;
        }
        if !series.in_legend {
            continue;
        }
        let sample = (layout.tick * 2.2).round() as i32;
        let dashed = series.dashed;
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
                dashed,
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
