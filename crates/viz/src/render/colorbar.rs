//! Horizontal colour bars (gradient, tick marks, tick labels, label), for figure grids
//! and for a single render with its colour bar ([`render_with_colorbar`]).

use beltrami_halfedge::HalfedgeMesh;
use glam::DVec3;

use super::{ColorMap, Image, RenderOptions, View, render_mesh_with};
use crate::VizError;
use crate::font::TextStyle;
use crate::ticks;

const TEXT: [u8; 3] = [0, 0, 0];
const OUTLINE: [u8; 3] = [90, 90, 90];

/// The smallest `(width, height)` in pixels that [`render_with_colorbar`] accepts: below
/// it, the bar's labels would not leave room for the mesh.
pub const MIN_COLORBAR_RENDER_SIZE: (u32, u32) = (160, 120);

/// Which values a colour bar labels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum ColorBarTicks {
    /// Round values (1, 2, 2.5 or 5 × 10ᵏ) inside the range, at least three, about one
    /// per four label widths. The ends of the range need not be labelled.
    #[default]
    Round,
    /// Both ends of the range, labelled with their values to three significant digits
    /// (`-0.0123`, `0.0123`: what full blue and full red stand for), and round values
    /// in between where their labels keep clear of the others (0 included, when inside).
    Ends,
}

/// A horizontal colour bar: the map, the label under it (the scalar's name, with its
/// unit), and the choice of ticks.
///
/// # Examples
/// ```
/// use beltrami_viz::render::{ColorBar, ColorBarTicks, ColorMap};
/// let bar = ColorBar::new(ColorMap::symmetric(0.01), "signed distance (mm)")
///     .with_ticks(ColorBarTicks::Ends);
/// assert_eq!(bar.ticks, ColorBarTicks::Ends);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColorBar<'a> {
    /// The colour map shown, from `min` on the left to `max` on the right.
    pub map: ColorMap,
    /// The text under the tick labels; may be empty.
    pub label: &'a str,
    /// Which values get a tick and a label.
    pub ticks: ColorBarTicks,
}

impl<'a> ColorBar<'a> {
    /// A bar for `map` labelled `label`, with [`ColorBarTicks::Round`] ticks.
    #[must_use]
    pub fn new(map: ColorMap, label: &'a str) -> Self {
        Self {
            map,
            label,
            ticks: ColorBarTicks::Round,
        }
    }

    /// The bar with `ticks`.
    #[must_use]
    pub fn with_ticks(self, ticks: ColorBarTicks) -> Self {
        Self { ticks, ..self }
    }

    /// The labelled values of a bar `width` pixels long with labels in `text`, in
    /// increasing order.
    fn tick_labels(&self, width: i64, text: &TextStyle) -> Vec<(f64, String)> {
        let map = &self.map;
        if map.max <= map.min {
            let magnitude = map.min.abs();
            let step = if magnitude > 0.0 { magnitude } else { 1.0 };
            let label = match self.ticks {
                ColorBarTicks::Round => ticks::format_tick(map.min, step, magnitude),
                ColorBarTicks::Ends => ticks::format_significant(map.min, 3),
            };
            return vec![(map.min, label)];
        }
        // About one tick per four label widths, at least three.
        let sample = ticks::format_tick(map.max, map.max / 4.0 - map.min / 4.0, map.max.abs());
        let room = (width as f32 / (4.0 * text.width(&sample).max(1.0))) as usize;
        // At least three ticks: a finer step when round values miss the ends.
        let mut target = room.clamp(3, 8);
        let (mut values, mut step) = ticks::linear_ticks(map.min, map.max, target);
        while values.len() < 3 && target < 16 {
            target += 1;
            (values, step) = ticks::linear_ticks(map.min, map.max, target);
        }
        let magnitude = values.iter().fold(0f64, |m, v| m.max(v.abs()));
        let round = values
            .into_iter()
            .map(|v| (v, ticks::format_tick(v, step, magnitude)));
        match self.ticks {
            ColorBarTicks::Round => round.collect(),
            ColorBarTicks::Ends => {
                let mut chosen: Vec<(f64, String)> = [map.min, map.max]
                    .into_iter()
                    .map(|v| (v, ticks::format_significant(v, 3)))
                    .collect();
                // A round value stays when its label keeps a line height clear of the
                // labels already chosen (the ends first).
                let gap = text.height();
                let centre = |v: f64| position(map, width, v) as f32;
                for (value, label) in round {
                    let half = 0.5 * text.width(&label);
                    let clear = chosen.iter().all(|(v, l)| {
                        (centre(value) - centre(*v)).abs() >= half + 0.5 * text.width(l) + gap
                    });
                    if clear {
                        chosen.push((value, label));
                    }
                }
                chosen.sort_by(|a, b| a.0.total_cmp(&b.0));
                chosen
            }
        }
    }
}

/// The x pixel, within a bar `width` pixels long, of `value`.
fn position(map: &ColorMap, width: i64, value: f64) -> i64 {
    let t = if map.max > map.min {
        map.fraction(value)
    } else {
        0.5
    };
    (t * (width - 1) as f64).round() as i64
}

/// A colour bar laid out at one size: gradient, tick marks, tick labels, label.
pub(crate) struct Bar<'a> {
    map: &'a ColorMap,
    label: &'a str,
    pub(crate) width: i64,
    thickness: i64,
    tick: i64,
    ticks: Vec<(f64, String)>,
}

impl<'a> Bar<'a> {
    /// The bar of a figure grid `grid_w` pixels wide with text of `base` pixels: 60 % of
    /// the grid's width (at least 160 pixels or the grid's width, at most 1200), round
    /// ticks.
    pub(crate) fn for_grid(
        map: &'a ColorMap,
        label: &'a str,
        grid_w: i64,
        base: f32,
        text: &TextStyle,
    ) -> Self {
        let width = ((grid_w as f32 * 0.6) as i64).clamp(grid_w.min(160), 1200);
        Self::new(map, label, ColorBarTicks::Round, width, base, text)
    }

    /// A bar `width` pixels long with text of `base` pixels.
    pub(crate) fn new(
        map: &'a ColorMap,
        label: &'a str,
        ticks: ColorBarTicks,
        width: i64,
        base: f32,
        text: &TextStyle,
    ) -> Self {
        let thickness = (base * 0.9).round() as i64;
        let tick = (base * 0.35).round().max(3.0) as i64;
        let ticks = ColorBar {
            map: *map,
            label,
            ticks,
        }
        .tick_labels(width, text);
        Self {
            map,
            label,
            width,
            thickness,
            tick,
            ticks,
        }
    }

    /// The height of the bar with its labels, in pixels.
    pub(crate) fn height(&self, text: &TextStyle) -> i64 {
        let line = text.height().ceil() as i64;
        let label = if self.label.is_empty() { 0 } else { line };
        self.thickness + self.tick + 2 + line + label
    }

    /// Draws the bar with its top-left corner at `(x0, top)`. Labels that would cross
    /// the image's left or right edge are moved inside it.
    pub(crate) fn draw(&self, image: &mut Image, text: &TextStyle, x0: i64, top: i64) {
        for i in 0..self.width {
            let t = i as f64 / (self.width - 1).max(1) as f64;
            let value = self.map.value_at(t);
            image.fill_rect(x0 + i, top, 1, self.thickness, self.map.color(value));
        }
        image.outline_rect(x0 - 1, top - 1, self.width + 2, self.thickness + 2, OUTLINE);
        let tick_top = top + self.thickness;
        let baseline = (tick_top + self.tick + 2) as f32 + text.ascent();
        let image_w = image.width as f32;
        let inside = |x: f32, w: f32| x.min(image_w - w).max(0.0);
        for (value, label) in &self.ticks {
            let x = x0 + position(self.map, self.width, *value);
            image.fill_rect(x, tick_top, 1, self.tick, TEXT);
            let w = text.width(label);
            let lx = inside(x as f32 - w / 2.0, w);
            image.draw_text(text, label, lx, baseline, TEXT);
        }
        if !self.label.is_empty() {
            let w = text.width(self.label);
            let lx = inside((x0 + self.width / 2) as f32 - w / 2.0, w);
            image.draw_text(text, self.label, lx, baseline + text.height(), TEXT);
        }
    }
}

/// Renders `mesh` coloured by `scalars` through `bar.map`, with the colour bar under
/// it, as one image of exactly `width × height` pixels: what a reader needs to read the
/// colours of a single render.
///
/// The mesh is drawn as by [`render_mesh_with`] (no frame: its own extent fills the
/// area) in the full width and the height above the bar. The bar is centred below it,
/// 60 % of the width long, with its tick labels and `bar.label` underneath; the text is
/// rasterised from the bundled DejaVu Sans at a size that follows the image (1/40 of
/// its height, or of ¾ of its width when that is smaller; at least 10 pixels).
///
/// # Errors
/// [`VizError::Invalid`] when the size is below [`MIN_COLORBAR_RENDER_SIZE`], or as
/// [`render_mesh_with`] (sizes, scalars, view, colour map).
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_viz::render::{
///     ColorBar, ColorBarTicks, ColorMap, RenderOptions, View, render_with_colorbar,
/// };
///
/// let sphere = primitives::icosphere(3);
/// let mesh = sphere.mesh()?;
/// let z: Vec<f64> = sphere.positions.iter().map(|p| p.z).collect();
/// let bar = ColorBar::new(ColorMap::symmetric_for(&z), "z (mm)").with_ticks(ColorBarTicks::Ends);
/// let view = View::default_for(&sphere.positions);
/// let image =
///     render_with_colorbar(&mesh, &sphere.positions, &z, &bar, &view, 320, 240, &RenderOptions::default())?;
/// assert_eq!((image.width, image.height), (320, 240));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[allow(clippy::too_many_arguments)]
pub fn render_with_colorbar(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    scalars: &[f64],
    bar: &ColorBar<'_>,
    view: &View,
    width: u32,
    height: u32,
    options: &RenderOptions,
) -> Result<Image, VizError> {
    let (min_w, min_h) = MIN_COLORBAR_RENDER_SIZE;
    if width < min_w || height < min_h {
        return Err(VizError::Invalid {
            what: "render size",
            reason: format!(
                "{width}×{height} pixels is too small for a colour bar (at least {min_w}×{min_h})"
            ),
        });
    }
    bar.map.validate()?;
    let (w, h) = (i64::from(width), i64::from(height));
    let base = ((height as f32).min(width as f32 * 0.75) / 40.0).max(10.0);
    let text = TextStyle::new(base)?;
    let pad = (base * 0.7).round() as i64;
    let bar_w = ((w as f32 * 0.6) as i64).max((w - 2 * pad).min(160));
    let laid_out = Bar::new(&bar.map, bar.label, bar.ticks, bar_w, base, &text);
    let band = pad + laid_out.height(&text) + pad;
    let mesh_h = u32::try_from(h - band)
        .ok()
        .filter(|&m| m >= height / 2)
        .ok_or_else(|| VizError::Invalid {
            what: "render size",
            reason: format!("{width}×{height} pixels leave no room for the colour bar"),
        })?;
    let panel = render_mesh_with(
        mesh,
        positions,
        Some(scalars),
        &bar.map,
        view,
        None,
        width,
        mesh_h,
        options,
    )?;
    let mut image = Image::new(width, height);
    image.blit(&panel, 0, 0);
    laid_out.draw(&mut image, &text, (w - bar_w) / 2, i64::from(mesh_h) + pad);
    Ok(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(map: ColorMap, ticks: ColorBarTicks, width: i64) -> Vec<String> {
        let text = TextStyle::new(16.0).unwrap();
        ColorBar::new(map, "d")
            .with_ticks(ticks)
            .tick_labels(width, &text)
            .into_iter()
            .map(|(_, label)| label)
            .collect()
    }

    #[test]
    fn end_ticks_label_both_ends_and_zero() {
        let map = ColorMap::symmetric(0.012345);
        let ends = labels(map, ColorBarTicks::Ends, 600);
        assert_eq!(ends.first().map(String::as_str), Some("-0.0123"));
        assert_eq!(ends.last().map(String::as_str), Some("0.0123"));
        assert!(ends.iter().any(|l| l == "0"), "{ends:?}");
        // Round ticks alone stop short of the ends.
        let round = labels(map, ColorBarTicks::Round, 600);
        assert!(!round.iter().any(|l| l.contains("0123")), "{round:?}");
        // A short bar keeps the ends and drops what would overlap them.
        let short = labels(map, ColorBarTicks::Ends, 120);
        assert!(short.len() >= 2 && short.len() < ends.len(), "{short:?}");
        assert_eq!(short.first().map(String::as_str), Some("-0.0123"));
        assert_eq!(short.last().map(String::as_str), Some("0.0123"));
    }

    #[test]
    fn a_one_sided_or_empty_range_is_labelled_at_its_values() {
        let ends = labels(ColorMap::new(3.2, 255.0), ColorBarTicks::Ends, 600);
        assert_eq!(ends.first().map(String::as_str), Some("3.2"));
        assert_eq!(ends.last().map(String::as_str), Some("255"));
        assert_eq!(
            labels(ColorMap::new(2.5e-4, 2.5e-4), ColorBarTicks::Ends, 600),
            ["2.5e-4"]
        );
    }

    /// A range wider than the largest finite number (values of ±1e308) still has its
    /// colours and labels: the bar runs blue to red, the labels are distinct and in
    /// order, zero is white.
    #[test]
    fn a_range_beyond_the_largest_finite_span_is_drawn() {
        let map = ColorMap::symmetric(1e308);
        assert!((map.fraction(0.0) - 0.5).abs() < 1e-15);
        assert_eq!(map.color(0.0), ColorMap::MID);
        assert_eq!(map.color(-1e308), ColorMap::LOW);
        assert_eq!(map.color(1e308), ColorMap::HIGH);
        assert_eq!(map.value_at(0.0), -1e308);
        assert_eq!(map.value_at(1.0), 1e308);
        assert_eq!(map.value_at(0.5), 0.0);
        let text = TextStyle::new(16.0).unwrap();
        let ticks = ColorBar::new(map, "q")
            .with_ticks(ColorBarTicks::Ends)
            .tick_labels(600, &text);
        assert!(ticks.len() >= 3, "{ticks:?}");
        assert!(ticks.windows(2).all(|w| w[0].0 < w[1].0), "{ticks:?}");
        assert!(ticks.iter().any(|(v, _)| *v == 0.0), "{ticks:?}");
        assert!(ticks.iter().all(|(v, _)| v.is_finite()), "{ticks:?}");
        // The ordinary ranges keep their bits: halving is exact for normal numbers.
        let m = ColorMap::new(-0.3, 0.7);
        assert_eq!(
            m.fraction(0.2).to_bits(),
            ((0.2_f64 - -0.3) / (0.7 - -0.3)).to_bits()
        );
    }
}
