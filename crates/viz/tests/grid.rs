//! Figure grids: size, placement of panels, labels and colour bar; errors.

mod common;

use beltrami_viz::VizError;
use beltrami_viz::render::{ColorMap, Image, grid};
use common::{count, dark, non_white};

/// Six 80×60 panels of distinct flat colours (no black, no white).
fn panels() -> Vec<Image> {
    (0..6u8)
        .map(|k| Image::filled(80, 60, [40 + 30 * k, 200 - 20 * k, 120]))
        .collect()
}

fn strings(items: &[&str]) -> Vec<String> {
    items.iter().map(|s| (*s).to_owned()).collect()
}

fn find(image: &Image, color: [u8; 3]) -> Option<(u32, u32, u32, u32)> {
    let mut bounds: Option<(u32, u32, u32, u32)> = None;
    for y in 0..image.height {
        for x in 0..image.width {
            if image.pixel(x, y) == Some(color) {
                let b = bounds.get_or_insert((x, y, x, y));
                *b = (b.0.min(x), b.1.min(y), b.2.max(x), b.3.max(y));
            }
        }
    }
    bounds
}

#[test]
fn bare_grid_places_panels_row_by_row() {
    let panels = panels();
    let figure = grid(&panels, 3, &[], &[], "", None).unwrap();
    assert!(
        figure.width >= 3 * 80 && figure.width < 3 * 80 + 60,
        "{}",
        figure.width
    );
    assert!(
        figure.height >= 2 * 60 && figure.height < 2 * 60 + 50,
        "{}",
        figure.height
    );
    let boxes: Vec<_> = panels
        .iter()
        .map(|p| find(&figure, p.pixel(0, 0).unwrap()).unwrap())
        .collect();
    for (i, b) in boxes.iter().enumerate() {
        // Each panel is copied whole (its outer pixels may carry the frame).
        assert!(
            b.2 - b.0 + 1 >= 78 && b.3 - b.1 + 1 >= 58,
            "panel {i}: {b:?}"
        );
    }
    // Row by row: 0 1 2 on top, 3 4 5 below.
    assert!(boxes[0].0 < boxes[1].0 && boxes[1].0 < boxes[2].0);
    assert_eq!(boxes[0].1, boxes[2].1);
    assert!(boxes[3].1 > boxes[0].3);
    assert_eq!(boxes[3].0, boxes[0].0);
}

#[test]
fn labels_title_and_colour_bar_are_drawn() {
    let panels = panels();
    let bare = grid(&panels, 3, &[], &[], "", None).unwrap();
    let map = ColorMap::symmetric(2e-3);
    let figure = grid(
        &panels,
        3,
        &strings(&["0 it.", "10 it.", "100 it."]),
        &strings(&["uniform", "cotangent"]),
        "Smoothed lens",
        Some((&map, "signed distance (mm)")),
    )
    .unwrap();
    assert!(figure.width > bare.width && figure.height > bare.height);
    let first = find(&figure, panels[0].pixel(0, 0).unwrap()).unwrap();
    let last = find(&figure, panels[5].pixel(0, 0).unwrap()).unwrap();
    let (w, h) = (figure.width, figure.height);
    // Title and column labels above the panels, row labels to their left.
    assert!(count(&figure, (0, w), (0, first.1), dark) > 100);
    assert!(count(&figure, (0, first.0), (first.1, last.3), dark) > 100);
    // The colour bar below: blue on the left, white in the middle, red on the right.
    let below = last.3 + 2;
    let bar_row = (below..h)
        .find(|&y| (0..w).any(|x| figure.pixel(x, y) == Some(ColorMap::LOW)))
        .expect("a colour bar row");
    let row: Vec<u32> = (0..w)
        .filter(|&x| {
            let p = figure.pixel(x, bar_row).unwrap();
            p == ColorMap::LOW || p == ColorMap::HIGH || p == ColorMap::MID
        })
        .collect();
    let low = (0..w)
        .find(|&x| figure.pixel(x, bar_row) == Some(ColorMap::LOW))
        .unwrap();
    let high = (0..w)
        .rev()
        .find(|&x| figure.pixel(x, bar_row) == Some(ColorMap::HIGH))
        .unwrap();
    assert!(low < high && !row.is_empty());
    let mid = figure.pixel((low + high) / 2, bar_row).unwrap();
    assert!(mid.iter().all(|&c| c > 240), "middle of the bar {mid:?}");
    // Tick labels and the bar label under the bar.
    assert!(count(&figure, (0, w), (bar_row + 2, h), dark) > 100);
    assert_eq!(
        grid(&panels, 3, &[], &[], "t", Some((&map, "d"))).unwrap(),
        grid(&panels, 3, &[], &[], "t", Some((&map, "d"))).unwrap()
    );
    assert!(count(&figure, (0, w), (0, h), non_white) > 6 * 80 * 60);
}

#[test]
fn a_short_last_row_leaves_blank_slots() {
    let panels = panels();
    let figure = grid(&panels[..4], 3, &[], &[], "", None).unwrap();
    let three = grid(&panels[..3], 3, &[], &[], "", None).unwrap();
    assert_eq!(figure.width, three.width);
    assert!(figure.height > three.height);
    assert!(find(&figure, panels[4].pixel(0, 0).unwrap()).is_none());
}

#[test]
fn inconsistent_input_is_invalid() {
    let panels = panels();
    let invalid = |r: Result<Image, VizError>| matches!(r, Err(VizError::Invalid { .. }));
    assert!(invalid(grid(&[], 2, &[], &[], "", None)));
    assert!(invalid(grid(&panels, 0, &[], &[], "", None)));
    assert!(invalid(grid(
        &panels,
        3,
        &strings(&["a", "b"]),
        &[],
        "",
        None
    )));
    assert!(invalid(grid(
        &panels,
        3,
        &[],
        &strings(&["a", "b", "c"]),
        "",
        None
    )));
    let mut mixed = panels.clone();
    mixed.push(Image::new(10, 10));
    assert!(invalid(grid(&mixed, 3, &[], &[], "", None)));
    let broken = Image {
        width: 4,
        height: 4,
        rgb: vec![0; 5],
    };
    assert!(invalid(grid(&[broken], 1, &[], &[], "", None)));
    let bad = ColorMap::new(1.0, f64::INFINITY);
    assert!(invalid(grid(&panels, 3, &[], &[], "", Some((&bad, "x")))));
}
