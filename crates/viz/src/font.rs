//! The bundled font (DejaVu Sans, Bitstream Vera licence, `assets/`): all text in PNG
//! output is rasterised from it, never from system fonts.

use std::sync::OnceLock;

use ab_glyph::{Font, FontRef, PxScale, ScaleFont, point};

use crate::VizError;

/// The bytes of DejaVu Sans.
pub(crate) static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// The parsed bundled font.
pub(crate) fn font() -> Result<&'static FontRef<'static>, VizError> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(FONT_BYTES).ok())
        .as_ref()
        .ok_or_else(|| VizError::Draw {
            name: "text".to_owned(),
            reason: "the bundled font cannot be parsed".to_owned(),
        })
}

/// Registers the bundled font with plotters under its generic family names
/// (`sans-serif`, `serif`, `monospace`), once per process.
pub(crate) fn register_with_plotters() -> Result<(), VizError> {
    use plotters::style::{FontStyle, register_font};
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        ["sans-serif", "serif", "monospace"].iter().all(|family| {
            [FontStyle::Normal, FontStyle::Bold]
                .into_iter()
                .all(|style| register_font(family, style, FONT_BYTES).is_ok())
        })
    });
    if ok {
        Ok(())
    } else {
        Err(VizError::Draw {
            name: "plot text".to_owned(),
            reason: "the bundled font cannot be registered".to_owned(),
        })
    }
}

/// Text metrics and rasterisation at one pixel size.
#[derive(Clone, Copy)]
pub(crate) struct TextStyle {
    font: &'static FontRef<'static>,
    scale: PxScale,
}

impl TextStyle {
    /// The bundled font at `px` pixels (ascent − descent).
    pub(crate) fn new(px: f32) -> Result<Self, VizError> {
        Ok(Self {
            font: font()?,
            scale: PxScale::from(px),
        })
    }

    /// The distance from the baseline up to the top of tall glyphs, in pixels.
    pub(crate) fn ascent(&self) -> f32 {
        self.font.as_scaled(self.scale).ascent()
    }

    /// The line height (ascent − descent), in pixels.
    pub(crate) fn height(&self) -> f32 {
        let scaled = self.font.as_scaled(self.scale);
        scaled.ascent() - scaled.descent()
    }

    /// The advance width of `text`, with kerning, in pixels.
    pub(crate) fn width(&self, text: &str) -> f32 {
        let scaled = self.font.as_scaled(self.scale);
        let mut caret = 0.0;
        let mut previous = None;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = previous {
                caret += scaled.kern(p, id);
            }
            caret += scaled.h_advance(id);
            previous = Some(id);
        }
        caret
    }

    /// Calls `paint(x, y, coverage)` for the pixels of `text` with its baseline starting
    /// at `(x, baseline)`; coverage is in `[0, 1]`.
    pub(crate) fn rasterise(
        &self,
        text: &str,
        x: f32,
        baseline: f32,
        mut paint: impl FnMut(i64, i64, f32),
    ) {
        let scaled = self.font.as_scaled(self.scale);
        let mut caret = x;
        let mut previous = None;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = previous {
                caret += scaled.kern(p, id);
            }
            let glyph = id.with_scale_and_position(self.scale, point(caret, baseline));
            caret += scaled.h_advance(id);
            previous = Some(id);
            if let Some(outline) = self.font.outline_glyph(glyph) {
                let bounds = outline.px_bounds();
                let (x0, y0) = (bounds.min.x as i64, bounds.min.y as i64);
                outline.draw(|gx, gy, coverage| {
                    paint(x0 + i64::from(gx), y0 + i64::from(gy), coverage);
                });
            }
        }
    }
}
