//! The diverging blue–white–red colour map for signed scalars.

use crate::VizError;

/// The anchors of the map from `min` (index 0) to `max` (index 8): ColorBrewer's RdBu
/// (9 classes) reversed, with pure white in the middle.
const ANCHORS: [[u8; 3]; 9] = [
    [33, 102, 172],
    [67, 147, 195],
    [146, 197, 222],
    [209, 229, 240],
    [255, 255, 255],
    [253, 219, 199],
    [244, 165, 130],
    [214, 96, 77],
    [178, 24, 43],
];

/// A diverging blue–white–red colour map over `[min, max]`: `min` is blue
/// ([`ColorMap::LOW`]), the midpoint white ([`ColorMap::MID`]), `max` red
/// ([`ColorMap::HIGH`]), piecewise linear through ColorBrewer's RdBu in between.
///
/// Values outside the range are clamped to its ends (±∞ included); NaN is grey
/// ([`ColorMap::NAN`]). For a signed distance, use a map symmetric about 0
/// ([`ColorMap::symmetric`]) so that white means "on the reference".
///
/// # Examples
/// ```
/// use beltrami_viz::render::ColorMap;
/// let map = ColorMap::symmetric(0.01);
/// assert_eq!(map.color(-0.01), ColorMap::LOW);
/// assert_eq!(map.color(0.0), ColorMap::MID);
/// assert_eq!(map.color(1.0), ColorMap::HIGH);
/// assert_eq!(map.color(f64::NAN), ColorMap::NAN);
/// ```
///
/// # References
/// C. A. Brewer: ColorBrewer 2.0, scheme RdBu (diverging).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColorMap {
    /// The value shown in blue.
    pub min: f64,
    /// The value shown in red.
    pub max: f64,
}

impl ColorMap {
    /// The colour of `min` and below.
    pub const LOW: [u8; 3] = ANCHORS[0];
    /// The colour of the midpoint.
    pub const MID: [u8; 3] = ANCHORS[4];
    /// The colour of `max` and above.
    pub const HIGH: [u8; 3] = ANCHORS[8];
    /// The colour of NaN.
    pub const NAN: [u8; 3] = [150, 150, 150];

    /// A map over `[min, max]`.
    #[must_use]
    pub fn new(min: f64, max: f64) -> Self {
        Self { min, max }
    }

    /// The map over `[-max_abs, max_abs]`: white at 0.
    #[must_use]
    pub fn symmetric(max_abs: f64) -> Self {
        Self {
            min: -max_abs.abs(),
            max: max_abs.abs(),
        }
    }

    /// The symmetric map reaching the largest finite absolute value in `values` (or
    /// `[-1, 1]` when there is none, or it is 0).
    #[must_use]
    pub fn symmetric_for(values: &[f64]) -> Self {
        let max_abs = values
            .iter()
            .filter(|v| v.is_finite())
            .fold(0f64, |m, v| m.max(v.abs()));
        Self::symmetric(if max_abs > 0.0 { max_abs } else { 1.0 })
    }

    /// The colour of `value`.
    #[must_use]
    pub fn color(&self, value: f64) -> [u8; 3] {
        if value.is_nan() {
            return Self::NAN;
        }
        // An empty (or inverted, or NaN) range: below, inside, above.
        if self.max.partial_cmp(&self.min) != Some(std::cmp::Ordering::Greater) {
            return if value < self.min {
                Self::LOW
            } else if value > self.max {
                Self::HIGH
            } else {
                Self::MID
            };
        }
        let t = self.fraction(value).clamp(0.0, 1.0);
        let t = if t.is_nan() { 0.5 } else { t };
        let f = t * (ANCHORS.len() - 1) as f64;
        let i = (f.floor() as usize).min(ANCHORS.len() - 2);
        let frac = f - i as f64;
        let (a, b) = (ANCHORS[i], ANCHORS[i + 1]);
        std::array::from_fn(|k| {
            let (a, b) = (f64::from(a[k]), f64::from(b[k]));
            (a + (b - a) * frac).round().clamp(0.0, 255.0) as u8
        })
    }

    /// Where `value` lies in the range: 0 at `min`, 1 at `max` (beyond them outside
    /// `[0, 1]`), NaN for an empty range. A range wider than the largest finite number
    /// (`[-1e308, 1e308]`) is measured in halves, which is exact for normal numbers.
    #[must_use]
    pub fn fraction(&self, value: f64) -> f64 {
        let span = self.max - self.min;
        if span.is_finite() {
            (value - self.min) / span
        } else {
            (value / 2.0 - self.min / 2.0) / (self.max / 2.0 - self.min / 2.0)
        }
    }

    /// The value at fraction `t` of the range (`min` at 0, `max` at 1), without the
    /// overflow of `min + t·(max − min)` for a range wider than the largest finite number.
    #[must_use]
    pub fn value_at(&self, t: f64) -> f64 {
        let span = self.max - self.min;
        if span.is_finite() {
            self.min + t * span
        } else {
            self.min * (1.0 - t) + self.max * t
        }
    }

    /// Checks that both ends are finite and `min ≤ max`.
    ///
    /// # Errors
    /// [`VizError::Invalid`] otherwise.
    pub fn validate(&self) -> Result<(), VizError> {
        if self.min.is_finite() && self.max.is_finite() && self.min <= self.max {
            Ok(())
        } else {
            Err(VizError::Invalid {
                what: "colour map",
                reason: format!(
                    "range [{}, {}] must be finite with min ≤ max",
                    self.min, self.max
                ),
            })
        }
    }
}

impl Default for ColorMap {
    /// The symmetric map over `[-1, 1]`.
    fn default() -> Self {
        Self::symmetric(1.0)
    }
}
