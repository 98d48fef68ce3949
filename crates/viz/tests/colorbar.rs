//! A single render with its colour bar: exact size, mesh above, bar and labels below.

mod common;

use beltrami_halfedge::primitives;
use beltrami_viz::VizError;
use beltrami_viz::render::{
    ColorBar, ColorBarTicks, ColorMap, Image, MIN_COLORBAR_RENDER_SIZE, RenderOptions, View,
    render_with_colorbar,
};
use common::{count, dark, decode_png, non_white};

fn sphere_with_bar(width: u32, height: u32) -> Result<Image, VizError> {
    let sphere = primitives::icosphere(3);
    let mesh = sphere.mesh().unwrap();
    let z: Vec<f64> = sphere.positions.iter().map(|p| 0.01 * p.z).collect();
    let bar = ColorBar::new(ColorMap::symmetric_for(&z), "signed distance (mm)")
        .with_ticks(ColorBarTicks::Ends);
    render_with_colorbar(
        &mesh,
        &sphere.positions,
        &z,
        &bar,
        &View::from_side(),
        width,
        height,
        &RenderOptions::default(),
    )
}

/// The first and last row holding the colour map's blue end.
fn bar_rows(image: &Image) -> (u32, u32) {
    let rows: Vec<u32> = (0..image.height)
        .filter(|&y| (0..image.width).any(|x| image.pixel(x, y) == Some(ColorMap::LOW)))
        .collect();
    (*rows.first().expect("a bar row"), *rows.last().unwrap())
}

#[test]
fn the_bar_sits_under_the_mesh_at_the_requested_size() {
    let (w, h) = (480, 360);
    let image = sphere_with_bar(w, h).unwrap();
    assert_eq!((image.width, image.height), (w, h));
    let (top, bottom) = bar_rows(&image);
    assert!(top > h / 2 && bottom < h, "bar rows {top}..{bottom}");
    // The bar runs from blue on the left through white to red on the right.
    let low = (0..w).find(|&x| image.pixel(x, top) == Some(ColorMap::LOW));
    let high = (0..w)
        .rev()
        .find(|&x| image.pixel(x, top) == Some(ColorMap::HIGH));
    let (low, high) = (low.unwrap(), high.expect("red at the bar's right end"));
    assert!(high > low + w / 2, "bar from {low} to {high}");
    let mid = image.pixel((low + high) / 2, top).unwrap();
    assert!(mid.iter().all(|&c| c > 240), "middle of the bar {mid:?}");
    // The mesh above the bar, tick labels and the label below it.
    assert!(count(&image, (0, w), (0, top), non_white) > 10_000);
    assert!(count(&image, (0, w), (bottom + 1, h), dark) > 200);
    // Labels stay inside the image: its outer columns are white.
    assert_eq!(count(&image, (0, 1), (0, h), non_white), 0);
    assert_eq!(count(&image, (w - 1, w), (0, h), non_white), 0);
}

#[test]
fn the_same_input_gives_the_same_bytes() {
    let a = sphere_with_bar(320, 240).unwrap().encode_png().unwrap();
    let b = sphere_with_bar(320, 240).unwrap().encode_png().unwrap();
    assert_eq!(a, b);
    assert_eq!(decode_png(&a), sphere_with_bar(320, 240).unwrap());
}

#[test]
fn sizes_below_the_minimum_are_invalid() {
    let (w, h) = MIN_COLORBAR_RENDER_SIZE;
    assert!(sphere_with_bar(w, h).is_ok());
    for (w, h) in [(w - 1, h), (w, h - 1), (0, 0)] {
        assert!(
            matches!(sphere_with_bar(w, h), Err(VizError::Invalid { .. })),
            "{w}×{h}"
        );
    }
}
