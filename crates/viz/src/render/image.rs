//! An 8-bit RGB raster with PNG encoding, and the drawing helpers the grid needs.

use std::path::Path;

use crate::VizError;
use crate::font::TextStyle;

/// An 8-bit RGB image, rows top to bottom, three bytes per pixel.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height × 3` bytes: red, green, blue of each pixel, row by row from the
    /// top.
    pub rgb: Vec<u8>,
}

impl Image {
    /// A white image of `width × height` pixels.
    ///
    /// # Panics
    /// If `width × height × 3` bytes cannot be allocated (as any `Vec`).
    ///
    /// # Examples
    /// ```
    /// use beltrami_viz::render::Image;
    /// let image = Image::new(4, 3);
    /// assert_eq!(image.rgb.len(), 4 * 3 * 3);
    /// assert_eq!(image.pixel(3, 2), Some([255, 255, 255]));
    /// ```
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Self::filled(width, height, [255; 3])
    }

    /// An image of `width × height` pixels, all of `color`.
    ///
    /// # Panics
    /// If `width × height × 3` bytes cannot be allocated (as any `Vec`).
    #[must_use]
    pub fn filled(width: u32, height: u32, color: [u8; 3]) -> Self {
        let n = width as usize * height as usize;
        let mut rgb = Vec::with_capacity(n * 3);
        for _ in 0..n {
            rgb.extend_from_slice(&color);
        }
        Self { width, height, rgb }
    }

    /// The colour of pixel `(x, y)` (`x` to the right, `y` down), or `None` outside the
    /// image (or when `rgb` is too short).
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 3 * (y as usize * self.width as usize + x as usize);
        self.rgb.get(i..i + 3).map(|p| [p[0], p[1], p[2]])
    }

    /// Checks that `rgb` holds exactly `width × height` pixels and the image is not
    /// empty.
    ///
    /// # Errors
    /// [`VizError::Invalid`] naming the mismatch.
    pub fn validate(&self) -> Result<(), VizError> {
        let expected = self.width as usize * self.height as usize * 3;
        if self.width == 0 || self.height == 0 {
            return Err(VizError::Invalid {
                what: "image",
                reason: format!("size {}×{} is empty", self.width, self.height),
            });
        }
        if self.rgb.len() != expected {
            return Err(VizError::Invalid {
                what: "image",
                reason: format!(
                    "{} bytes for {}×{} pixels; expected {expected}",
                    self.rgb.len(),
                    self.width,
                    self.height
                ),
            });
        }
        Ok(())
    }

    /// The image encoded as PNG (8-bit RGB, no metadata, so equal images give equal
    /// bytes).
    ///
    /// # Errors
    /// [`VizError::Invalid`] as [`validate`](Self::validate); [`VizError::Draw`] when
    /// encoding fails.
    pub fn encode_png(&self) -> Result<Vec<u8>, VizError> {
        self.validate()?;
        let fail = |e: png::EncodingError| VizError::Draw {
            name: "PNG".to_owned(),
            reason: e.to_string(),
        };
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().map_err(fail)?;
        writer.write_image_data(&self.rgb).map_err(fail)?;
        writer.finish().map_err(fail)?;
        Ok(bytes)
    }

    /// Decodes PNG bytes holding an 8-bit RGB image, as [`encode_png`](Self::encode_png)
    /// writes them: to check a written figure, or to compare two.
    ///
    /// # Errors
    /// [`VizError::Invalid`] when the bytes are not a PNG image or not 8-bit RGB.
    ///
    /// # Examples
    /// ```
    /// use beltrami_viz::render::Image;
    /// let image = Image::filled(3, 2, [10, 20, 30]);
    /// assert_eq!(Image::decode_png(&image.encode_png()?)?, image);
    /// # Ok::<(), beltrami_viz::VizError>(())
    /// ```
    pub fn decode_png(bytes: &[u8]) -> Result<Self, VizError> {
        let invalid = |reason: String| VizError::Invalid {
            what: "PNG",
            reason,
        };
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().map_err(|e| invalid(e.to_string()))?;
        let (color, depth) = reader.output_color_type();
        if (color, depth) != (png::ColorType::Rgb, png::BitDepth::Eight) {
            return Err(invalid(format!(
                "{color:?} with {depth:?} bits per channel; expected 8-bit RGB"
            )));
        }
        let size = reader
            .output_buffer_size()
            .ok_or_else(|| invalid("the image is too large".to_owned()))?;
        let mut rgb = vec![0; size];
        let info = reader
            .next_frame(&mut rgb)
            .map_err(|e| invalid(e.to_string()))?;
        rgb.truncate(info.buffer_size());
        let image = Self {
            width: info.width,
            height: info.height,
            rgb,
        };
        image.validate()?;
        Ok(image)
    }

    /// Writes the image as PNG to `path`, atomically (a failed write leaves no partial
    /// file and an existing file untouched).
    ///
    /// # Errors
    /// As [`encode_png`](Self::encode_png), and [`VizError::Write`] when the file cannot
    /// be written.
    pub fn write_png(&self, path: &Path) -> Result<(), VizError> {
        let bytes = self.encode_png()?;
        beltrami_io::write_bytes_atomic(path, &bytes)?;
        Ok(())
    }

    /// Blends `color` over pixel `(x, y)` with opacity `alpha` in `[0, 1]`; pixels
    /// outside the image are ignored.
    pub(crate) fn blend(&mut self, x: i64, y: i64, color: [u8; 3], alpha: f32) {
        if x < 0 || y < 0 || x >= i64::from(self.width) || y >= i64::from(self.height) {
            return;
        }
        let alpha = alpha.clamp(0.0, 1.0);
        let i = 3 * (y as usize * self.width as usize + x as usize);
        if let Some(pixel) = self.rgb.get_mut(i..i + 3) {
            for (p, c) in pixel.iter_mut().zip(color) {
                let mixed = f32::from(*p) * (1.0 - alpha) + f32::from(c) * alpha;
                *p = mixed.round().clamp(0.0, 255.0) as u8;
            }
        }
    }

    /// Fills the rectangle `[x, x + w) × [y, y + h)` (clipped) with `color`.
    pub(crate) fn fill_rect(&mut self, x: i64, y: i64, w: i64, h: i64, color: [u8; 3]) {
        for yy in y.max(0)..(y + h).min(i64::from(self.height)) {
            for xx in x.max(0)..(x + w).min(i64::from(self.width)) {
                self.blend(xx, yy, color, 1.0);
            }
        }
    }

    /// The one-pixel outline of the rectangle `[x, x + w) × [y, y + h)`.
    pub(crate) fn outline_rect(&mut self, x: i64, y: i64, w: i64, h: i64, color: [u8; 3]) {
        self.fill_rect(x, y, w, 1, color);
        self.fill_rect(x, y + h - 1, w, 1, color);
        self.fill_rect(x, y, 1, h, color);
        self.fill_rect(x + w - 1, y, 1, h, color);
    }

    /// Copies `other` with its top-left corner at `(x, y)` (clipped).
    pub(crate) fn blit(&mut self, other: &Image, x: i64, y: i64) {
        let width = other.width as usize;
        if width == 0 {
            return;
        }
        for (row, source) in other.rgb.chunks_exact(width * 3).enumerate() {
            let yy = y + row as i64;
            if yy < 0 || yy >= i64::from(self.height) {
                continue;
            }
            for (col, p) in source.chunks_exact(3).enumerate() {
                let xx = x + col as i64;
                if xx < 0 || xx >= i64::from(self.width) {
                    continue;
                }
                let i = 3 * (yy as usize * self.width as usize + xx as usize);
                if let Some(target) = self.rgb.get_mut(i..i + 3) {
                    target.copy_from_slice(p);
                }
            }
        }
    }

    /// Draws `text` in `color` with its baseline starting at `(x, baseline)`.
    pub(crate) fn draw_text(
        &mut self,
        style: &TextStyle,
        text: &str,
        x: f32,
        baseline: f32,
        color: [u8; 3],
    ) {
        style.rasterise(text, x, baseline, |px, py, coverage| {
            self.blend(px, py, color, coverage);
        });
    }
}
