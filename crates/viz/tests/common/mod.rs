//! Helpers shared by the integration tests.

#![allow(dead_code)]

use beltrami_viz::render::Image;

/// Decodes PNG bytes into an RGB image, checking the format.
pub(crate) fn decode_png(bytes: &[u8]) -> Image {
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().expect("a PNG header");
    let mut rgb = vec![0; reader.output_buffer_size().expect("a buffer size")];
    let info = reader.next_frame(&mut rgb).expect("a PNG frame");
    assert_eq!(info.color_type, png::ColorType::Rgb);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    rgb.truncate(info.buffer_size());
    Image {
        width: info.width,
        height: info.height,
        rgb,
    }
}

/// The number of pixels in `[x0, x1) × [y0, y1)` for which `test` holds.
pub(crate) fn count(
    image: &Image,
    (x0, x1): (u32, u32),
    (y0, y1): (u32, u32),
    test: impl Fn([u8; 3]) -> bool,
) -> usize {
    let mut n = 0;
    for y in y0..y1.min(image.height) {
        for x in x0..x1.min(image.width) {
            if image.pixel(x, y).is_some_and(&test) {
                n += 1;
            }
        }
    }
    n
}

/// Not the white background.
pub(crate) fn non_white(p: [u8; 3]) -> bool {
    p != [255, 255, 255]
}

/// Dark enough to be text or an axis.
pub(crate) fn dark(p: [u8; 3]) -> bool {
    p.iter().all(|&c| c < 128)
}
