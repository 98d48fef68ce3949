//! Figure grids: panels in rows and columns with a title, labels and a colour bar.

use super::colorbar::Bar;
use super::{ColorMap, Image};
use crate::VizError;
use crate::font::TextStyle;

/// The largest accepted grid width or height, in pixels.
pub const MAX_GRID_SIZE: u32 = 16384;

const TEXT: [u8; 3] = [0, 0, 0];
const FRAME: [u8; 3] = [190, 190, 190];

/// Lays out `panels` (all of one size) row by row in `columns` columns, with `title` on
/// top, `column_labels` above the columns, `row_labels` left of the rows, and an optional
/// horizontal colour bar with ticks and its label (with unit) below — a paper's figure
/// grid with rows = weight schemes and columns = iteration counts. Empty slots of the
/// last row stay white; each panel gets a thin grey frame.
///
/// Text is rasterised from the bundled DejaVu Sans at a size that follows the panel
/// height. Labels may be left out (empty slices, empty title).
///
/// # Errors
/// [`VizError::Invalid`] when there are no panels, `columns` is 0, the panels differ in
/// size or are malformed, `column_labels` is neither empty nor one per column,
/// `row_labels` neither empty nor one per row, the colour map is not finite with
/// `min ≤ max`, or the result would exceed [`MAX_GRID_SIZE`].
///
/// # Examples
/// ```
/// use beltrami_viz::render::{ColorMap, Image, grid};
/// let panels = vec![Image::new(40, 30); 4];
/// let figure = grid(
///     &panels,
///     2,
///     &["10 it.".into(), "100 it.".into()],
///     &["uniform".into(), "cotangent".into()],
///     "Smoothed lens",
///     Some((&ColorMap::symmetric(0.01), "signed distance (mm)")),
/// )?;
/// assert!(figure.width > 80 && figure.height > 60);
/// # Ok::<(), beltrami_viz::VizError>(())
/// ```
pub fn grid(
    panels: &[Image],
    columns: usize,
    column_labels: &[String],
    row_labels: &[String],
    title: &str,
    colorbar: Option<(&ColorMap, &str)>,
) -> Result<Image, VizError> {
    let spec = GridSpec {
        panels,
        columns,
        column_labels,
        row_labels,
        title,
        colorbar,
    };
    let rows = spec.check()?;
    let layout = spec.layout(rows)?;
    Ok(spec.draw(&layout))
}

/// The arguments of [`grid`].
struct GridSpec<'a> {
    panels: &'a [Image],
    columns: usize,
    column_labels: &'a [String],
    row_labels: &'a [String],
    title: &'a str,
    colorbar: Option<(&'a ColorMap, &'a str)>,
}

/// The sizes and positions of a grid's parts, in pixels.
struct GridLayout<'a> {
    /// Panel width and height.
    pw: i64,
    ph: i64,
    /// Labels' and title's text.
    text: TextStyle,
    title_text: TextStyle,
    /// Margin, and the gap between panels.
    pad: i64,
    gap: i64,
    /// The panels' block.
    grid_w: i64,
    grid_h: i64,
    /// The row labels' column, margin included (0 without labels).
    row_label_w: i64,
    /// Row labels and panels together.
    content_w: i64,
    /// The title's and the column labels' bands, margins included (0 when absent).
    title_h: i64,
    column_label_h: i64,
    bar: Option<Bar<'a>>,
    /// The whole figure.
    width: i64,
    height: i64,
}

impl<'a> GridSpec<'a> {
    /// Checks the panels, labels and colour map; returns the number of rows.
    fn check(&self) -> Result<usize, VizError> {
        let Some(first) = self.panels.first() else {
            return Err(invalid_grid("no panels".to_owned()));
        };
        if self.columns == 0 {
            return Err(invalid_grid("0 columns".to_owned()));
        }
        for (i, panel) in self.panels.iter().enumerate() {
            panel.validate()?;
            if (panel.width, panel.height) != (first.width, first.height) {
                return Err(invalid_grid(format!(
                    "panel {i} is {}×{}, panel 0 is {}×{}",
                    panel.width, panel.height, first.width, first.height
                )));
            }
        }
        let (columns, column_labels, row_labels) =
            (self.columns, self.column_labels, self.row_labels);
        let rows = self.panels.len().div_ceil(columns);
        if !column_labels.is_empty() && column_labels.len() != columns {
            return Err(invalid_grid(format!(
                "{} column labels for {columns} columns",
                column_labels.len()
            )));
        }
        if !row_labels.is_empty() && row_labels.len() != rows {
            return Err(invalid_grid(format!(
                "{} row labels for {rows} rows",
                row_labels.len()
            )));
        }
        if let Some((map, _)) = self.colorbar {
            map.validate()?;
        }
        Ok(rows)
    }

    /// Measures the text and places the parts of a checked grid of `rows` rows.
    fn layout(&self, rows: usize) -> Result<GridLayout<'a>, VizError> {
        let (title, columns) = (self.title, self.columns);
        let first = &self.panels[0];
        let (pw, ph) = (i64::from(first.width), i64::from(first.height));
        let base = (ph as f32 / 16.0).clamp(12.0, 28.0);
        let text = TextStyle::new(base)?;
        let title_text = TextStyle::new(base * 1.35)?;
        let pad = (base * 0.7).round() as i64;
        let gap = (pad / 2).max(2);
        let line = |style: &TextStyle| style.height().ceil() as i64;

        let grid_w = columns as i64 * pw + (columns as i64 - 1) * gap;
        let grid_h = rows as i64 * ph + (rows as i64 - 1) * gap;
        let row_label_w = self
            .row_labels
            .iter()
            .map(|l| text.width(l).ceil() as i64)
            .max()
            .map_or(0, |w| w + pad);
        let title_w = title_text.width(title).ceil() as i64;
        let content_w = row_label_w + grid_w;

        let title_h = if title.is_empty() {
            0
        } else {
            line(&title_text) + pad
        };
        let column_label_h = if self.column_labels.is_empty() {
            0
        } else {
            line(&text) + gap
        };
        let bar = self
            .colorbar
            .map(|(map, label)| Bar::for_grid(map, label, grid_w, base, &text));
        let bar_h = bar.as_ref().map_or(0, |b| pad + b.height(&text));

        let width = content_w.max(title_w) + 2 * pad;
        let height = pad + title_h + column_label_h + grid_h + bar_h + pad;
        if width > i64::from(MAX_GRID_SIZE) || height > i64::from(MAX_GRID_SIZE) {
            return Err(invalid_grid(format!(
                "the figure would be {width}×{height} pixels, above {MAX_GRID_SIZE}"
            )));
        }
        Ok(GridLayout {
            pw,
            ph,
            text,
            title_text,
            pad,
            gap,
            grid_w,
            grid_h,
            row_label_w,
            content_w,
            title_h,
            column_label_h,
            bar,
            width,
            height,
        })
    }

    /// Draws the title, column labels, framed panels, row labels and colour bar.
    fn draw(&self, layout: &GridLayout<'_>) -> Image {
        let GridLayout {
            pw,
            ph,
            ref text,
            ref title_text,
            pad,
            gap,
            grid_w,
            grid_h,
            row_label_w,
            content_w,
            title_h,
            column_label_h,
            ref bar,
            width,
            height,
        } = *layout;
        let (title, columns) = (self.title, self.columns);
        let mut image = Image::new(width as u32, height as u32);

        let left = (width - content_w) / 2;
        let grid_x = left + row_label_w;
        let mut y = pad;
        if !title.is_empty() {
            let x = (width as f32 - title_text.width(title)) / 2.0;
            image.draw_text(title_text, title, x, y as f32 + title_text.ascent(), TEXT);
            y += title_h;
        }
        if !self.column_labels.is_empty() {
            for (c, label) in self.column_labels.iter().enumerate() {
                let centre = grid_x + c as i64 * (pw + gap) + pw / 2;
                let x = centre as f32 - text.width(label) / 2.0;
                image.draw_text(text, label, x, y as f32 + text.ascent(), TEXT);
            }
            y += column_label_h;
        }
        let grid_y = y;
        for (i, panel) in self.panels.iter().enumerate() {
            let (r, c) = ((i / columns) as i64, (i % columns) as i64);
            let (px, py) = (grid_x + c * (pw + gap), grid_y + r * (ph + gap));
            image.blit(panel, px, py);
            image.outline_rect(px - 1, py - 1, pw + 2, ph + 2, FRAME);
        }
        for (r, label) in self.row_labels.iter().enumerate() {
            let centre = grid_y + r as i64 * (ph + gap) + ph / 2;
            let x = (grid_x - pad) as f32 - text.width(label);
            let baseline = centre as f32 + text.ascent() / 2.0 - text.height() * 0.12;
            image.draw_text(text, label, x, baseline, TEXT);
        }
        if let Some(bar) = bar {
            let top = grid_y + grid_h + pad;
            let x0 = grid_x + (grid_w - bar.width) / 2;
            bar.draw(&mut image, text, x0, top);
        }
        image
    }
}

/// The error of an invalid grid.
fn invalid_grid(reason: String) -> VizError {
    VizError::Invalid {
        what: "grid",
        reason,
    }
}
