//! Series colours and marker shapes, and the element that draws a marker (with a line
//! sample in the legend).

use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::{BackendCoord, DrawingErrorKind};

/// The Okabe–Ito colours (yellow left out: too light on white), then grey.
pub(super) const PALETTE: [RGBColor; 8] = [
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
pub(super) enum Marker {
    Circle,
    Square,
    Triangle,
    Diamond,
    Cross,
    OpenCircle,
    OpenSquare,
}

pub(super) const MARKERS: [Marker; 7] = [
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
pub(super) struct Glyph<C> {
    pub(super) at: C,
    pub(super) kind: Marker,
    /// Half-width of the marker in pixels.
    pub(super) size: i32,
    pub(super) color: RGBColor,
    /// Line width in pixels.
    pub(super) stroke: u32,
    /// For a legend entry: the length of the line sample, the marker in its middle.
    pub(super) sample: Option<i32>,
    /// For a legend entry of a dashed series: the sample is dashed and has no marker.
    pub(super) dashed: bool,
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
        if let (Some(length), true) = (self.sample, self.dashed) {
            let dash = (length / 5).max(2);
            let mut at = x;
            while at < x + length {
                backend.draw_line((at, y), ((at + dash).min(x + length), y), &line)?;
                at += 2 * dash;
            }
            return Ok(());
        }
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
