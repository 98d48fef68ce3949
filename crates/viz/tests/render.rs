//! Mesh renders: projection and coverage, colours, depth, edge-on surfaces, errors.

mod common;

use beltrami_halfedge::{DVec3, HalfedgeMesh, primitives};
use beltrami_viz::VizError;
use beltrami_viz::render::{
    ColorMap, FRAME_MARGIN, Image, RenderOptions, View, render_mesh, render_mesh_with,
};
use common::{count, decode_png, non_white};

fn unit_box() -> Option<(DVec3, DVec3)> {
    Some((DVec3::splat(-1.0), DVec3::splat(1.0)))
}

fn render_sphere(scalars: Option<&[f64]>, width: u32, height: u32) -> Image {
    let sphere = primitives::icosphere(4);
    let mesh = sphere.mesh().unwrap();
    render_mesh(
        &mesh,
        &sphere.positions,
        scalars,
        &ColorMap::symmetric(1.0),
        &View::from_side(),
        unit_box(),
        width,
        height,
    )
    .unwrap()
}

#[test]
fn a_centred_sphere_covers_a_disc() {
    let (w, h) = (400, 300);
    let image = render_sphere(None, w, h);
    assert_eq!(image.rgb.len(), (w * h * 3) as usize);
    // The frame [-1, 1]³ fills the height less the margins: radius in pixels.
    let r = 0.5 * f64::from(h) * (1.0 - 2.0 * FRAME_MARGIN);
    let expected = std::f64::consts::PI * r * r / f64::from(w * h);
    let covered = count(&image, (0, w), (0, h), non_white) as f64 / f64::from(w * h);
    assert!(
        (covered - expected).abs() < 0.03 * expected,
        "covered {covered}, expected {expected}"
    );
    // Centred: the covered pixels balance around the image centre.
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
    for y in 0..h {
        for x in 0..w {
            if non_white(image.pixel(x, y).unwrap()) {
                sx += f64::from(x) + 0.5;
                sy += f64::from(y) + 0.5;
                n += 1.0;
            }
        }
    }
    assert!((sx / n - f64::from(w) / 2.0).abs() < 1.0);
    assert!((sy / n - f64::from(h) / 2.0).abs() < 1.0);
    // Shaded, not flat: the neutral grey varies over the disc.
    let centre = image.pixel(w / 2, h / 2).unwrap();
    let rim = image.pixel(w / 2 + (0.95 * r) as u32, h / 2).unwrap();
    assert!(centre[0] != rim[0], "centre {centre:?}, rim {rim:?}");
}

#[test]
fn height_colours_the_top_red_and_the_bottom_blue() {
    let sphere = primitives::icosphere(4);
    let z: Vec<f64> = sphere.positions.iter().map(|p| p.z).collect();
    let (w, h) = (200, 200);
    let image = render_sphere(Some(&z), w, h);
    let r = 0.5 * f64::from(h) * (1.0 - 2.0 * FRAME_MARGIN);
    let top = image
        .pixel(w / 2, (f64::from(h) / 2.0 - 0.7 * r) as u32)
        .unwrap();
    let bottom = image
        .pixel(w / 2, (f64::from(h) / 2.0 + 0.7 * r) as u32)
        .unwrap();
    assert!(top[0] > top[2] + 40, "top {top:?}");
    assert!(bottom[2] > bottom[0] + 40, "bottom {bottom:?}");
    // The equator (z = 0) is near white, shaded to grey: balanced channels.
    let middle = image.pixel(w / 2, h / 2).unwrap();
    assert!(middle[0].abs_diff(middle[2]) < 25, "middle {middle:?}");
}

/// A big triangle at z = 0 with scalar −1 and a small one at z = 1 with scalar +1, in
/// either face order.
fn two_layers(small_first: bool) -> (HalfedgeMesh, Vec<DVec3>, Vec<f64>) {
    let positions = vec![
        DVec3::new(-2.0, -2.0, 0.0),
        DVec3::new(2.0, -2.0, 0.0),
        DVec3::new(0.0, 2.0, 0.0),
        DVec3::new(-0.3, -0.3, 1.0),
        DVec3::new(0.3, -0.3, 1.0),
        DVec3::new(0.0, 0.3, 1.0),
    ];
    let scalars = vec![-1.0, -1.0, -1.0, 1.0, 1.0, 1.0];
    let faces: Vec<[u32; 3]> = if small_first {
        vec![[3, 4, 5], [0, 1, 2]]
    } else {
        vec![[0, 1, 2], [3, 4, 5]]
    };
    (
        HalfedgeMesh::from_polygons(6, &faces).unwrap(),
        positions,
        scalars,
    )
}

#[test]
fn the_depth_buffer_hides_what_is_behind() {
    for small_first in [false, true] {
        let (mesh, positions, scalars) = two_layers(small_first);
        let map = ColorMap::symmetric(1.0);
        let image = render_mesh(
            &mesh,
            &positions,
            Some(&scalars),
            &map,
            &View::from_above(),
            None,
            200,
            200,
        )
        .unwrap();
        let centre = image.pixel(100, 100).unwrap();
        assert!(centre[0] > centre[2] + 60, "small in front: {centre:?}");
        let aside = image.pixel(100, 150).unwrap();
        assert!(aside[2] > aside[0] + 60, "big behind: {aside:?}");
        // Seen from below, the big triangle hides the small one.
        let below = View::new(DVec3::Z, DVec3::Y);
        let image = render_mesh(
            &mesh,
            &positions,
            Some(&scalars),
            &map,
            &below,
            None,
            200,
            200,
        )
        .unwrap();
        let centre = image.pixel(100, 100).unwrap();
        assert!(centre[2] > centre[0] + 60, "from below: {centre:?}");
    }
}

#[test]
fn a_flat_grid_seen_edge_on_draws_nothing() {
    let plane = primitives::grid(8, 8);
    let mesh = plane.mesh().unwrap();
    let (w, h) = (200, 150);
    let image = render_mesh(
        &mesh,
        &plane.positions,
        None,
        &ColorMap::default(),
        &View::from_side(),
        None,
        w,
        h,
    )
    .unwrap();
    let drawn = count(&image, (0, w), (0, h), non_white);
    assert!(drawn <= (w * h / 200) as usize, "{drawn} pixels drawn");
    // Seen from above the same grid fills its frame.
    let image = render_mesh(
        &mesh,
        &plane.positions,
        None,
        &ColorMap::default(),
        &View::from_above(),
        None,
        w,
        h,
    )
    .unwrap();
    assert!(count(&image, (0, w), (0, h), non_white) > (w * h / 2) as usize);
}

#[test]
fn open_surfaces_are_lit_from_both_sides() {
    let plane = primitives::grid(2, 2);
    let mesh = plane.mesh().unwrap();
    let map = ColorMap::default();
    let above = render_mesh(
        &mesh,
        &plane.positions,
        None,
        &map,
        &View::from_above(),
        None,
        60,
        60,
    );
    let below = View::new(DVec3::Z, DVec3::Y);
    let below = render_mesh(&mesh, &plane.positions, None, &map, &below, None, 60, 60);
    let (above, below) = (above.unwrap(), below.unwrap());
    let (a, b) = (above.pixel(30, 30).unwrap(), below.pixel(30, 30).unwrap());
    assert!(non_white(a));
    assert_eq!(a, b);
}

#[test]
fn polygon_faces_are_fanned() {
    let cube = primitives::cube_quads();
    let mesh = cube.mesh().unwrap();
    let view = View::default_for(&cube.positions);
    let image = render_mesh(
        &mesh,
        &cube.positions,
        None,
        &ColorMap::default(),
        &view,
        None,
        120,
        100,
    )
    .unwrap();
    let drawn = count(&image, (0, 120), (0, 100), non_white);
    assert!(drawn > 120 * 100 / 4, "{drawn}");
}

#[test]
fn colour_map_ends_and_midpoint_are_exact() {
    let map = ColorMap::new(-2.0, 6.0);
    assert_eq!(map.color(-2.0), ColorMap::LOW);
    assert_eq!(map.color(2.0), ColorMap::MID);
    assert_eq!(map.color(6.0), ColorMap::HIGH);
    assert_eq!(ColorMap::MID, [255, 255, 255]);
    // Clamped outside, grey for NaN.
    assert_eq!(map.color(-100.0), ColorMap::LOW);
    assert_eq!(map.color(f64::INFINITY), ColorMap::HIGH);
    assert_eq!(map.color(f64::NEG_INFINITY), ColorMap::LOW);
    assert_eq!(map.color(f64::NAN), ColorMap::NAN);
    // Blue below the middle, red above, monotone in between.
    let low = map.color(0.0);
    let high = map.color(4.0);
    assert!(low[2] > low[0] && high[0] > high[2]);
    // A symmetric map is white at 0; an empty range gives the three colours.
    assert_eq!(ColorMap::symmetric(3e-4).color(0.0), ColorMap::MID);
    let empty = ColorMap::new(1.0, 1.0);
    assert_eq!(empty.color(0.0), ColorMap::LOW);
    assert_eq!(empty.color(1.0), ColorMap::MID);
    assert_eq!(empty.color(2.0), ColorMap::HIGH);
    assert_eq!(
        ColorMap::symmetric_for(&[0.1, -0.3, f64::NAN]),
        ColorMap::symmetric(0.3)
    );
    assert_eq!(ColorMap::symmetric_for(&[]), ColorMap::symmetric(1.0));
}

#[test]
fn identical_input_gives_identical_bytes() {
    let sphere = primitives::icosphere(4);
    let z: Vec<f64> = sphere.positions.iter().map(|p| p.z).collect();
    let png = || render_sphere(Some(&z), 160, 120).encode_png().unwrap();
    assert_eq!(png(), png());
    let image = render_sphere(None, 160, 120);
    assert_eq!(decode_png(&image.encode_png().unwrap()), image);
}

#[test]
fn invalid_input_is_reported() {
    let sphere = primitives::icosphere(1);
    let mesh = sphere.mesh().unwrap();
    let p = &sphere.positions;
    let map = ColorMap::default();
    let view = View::from_side();
    let invalid = |r: Result<Image, VizError>| matches!(r, Err(VizError::Invalid { .. }));
    assert!(invalid(render_mesh(
        &mesh,
        &p[1..],
        None,
        &map,
        &view,
        None,
        10,
        10
    )));
    let short = vec![0.0; p.len() - 1];
    assert!(invalid(render_mesh(
        &mesh,
        p,
        Some(&short),
        &map,
        &view,
        None,
        10,
        10
    )));
    let full = vec![0.0; p.len()];
    let bad_map = ColorMap::new(f64::NAN, 1.0);
    assert!(invalid(render_mesh(
        &mesh,
        p,
        Some(&full),
        &bad_map,
        &view,
        None,
        10,
        10
    )));
    assert!(invalid(render_mesh(
        &mesh, p, None, &map, &view, None, 0, 10
    )));
    assert!(invalid(render_mesh(
        &mesh, p, None, &map, &view, None, 10, 100_000
    )));
    let parallel = View::new(DVec3::Z, DVec3::NEG_Z);
    assert!(invalid(render_mesh(
        &mesh, p, None, &map, &parallel, None, 10, 10
    )));
    let zero = View::new(DVec3::ZERO, DVec3::Z);
    assert!(invalid(render_mesh(
        &mesh, p, None, &map, &zero, None, 10, 10
    )));
    let inverted = Some((DVec3::ONE, DVec3::ZERO));
    assert!(invalid(render_mesh(
        &mesh, p, None, &map, &view, inverted, 10, 10
    )));
    let options = RenderOptions::default().supersample(0);
    assert!(invalid(render_mesh_with(
        &mesh, p, None, &map, &view, None, 10, 10, &options
    )));
}

#[test]
fn non_finite_positions_skip_their_faces() {
    let sphere = primitives::icosphere(3);
    let mesh = sphere.mesh().unwrap();
    let mut positions = sphere.positions.clone();
    positions[0] = DVec3::new(f64::NAN, 0.0, 0.0);
    positions[1] = DVec3::splat(f64::INFINITY);
    let image = render_mesh(
        &mesh,
        &positions,
        None,
        &ColorMap::default(),
        &View::from_side(),
        None,
        100,
        100,
    )
    .unwrap();
    assert!(count(&image, (0, 100), (0, 100), non_white) > 2000);
}

#[test]
fn the_default_view_puts_the_thinnest_axis_up() {
    // A plate in the yz-plane: x is thin and goes up.
    let plate: Vec<DVec3> = [(0.0, 0.0), (4.0, 0.0), (0.0, 4.0), (4.0, 4.0)]
        .iter()
        .map(|&(y, z)| DVec3::new(0.1 * y / 4.0, y, z))
        .collect();
    let view = View::default_for(&plate);
    assert_eq!(view.up, DVec3::X);
    assert!(
        view.direction.x < 0.0,
        "looking down from above: {}",
        view.direction
    );
    // A sphere keeps z up, viewed from above the front.
    let view = View::default_for(&primitives::icosphere(2).positions);
    assert_eq!(view.up, DVec3::Z);
    assert!(view.direction.z < 0.0 && view.direction.y > 0.0);
}

#[test]
fn supersampling_smooths_edges_only() {
    let sphere = primitives::icosphere(3);
    let mesh = sphere.mesh().unwrap();
    let render = |supersample| {
        render_mesh_with(
            &mesh,
            &sphere.positions,
            None,
            &ColorMap::default(),
            &View::from_side(),
            unit_box(),
            100,
            100,
            &RenderOptions::default().supersample(supersample),
        )
        .unwrap()
    };
    let (sharp, smooth) = (render(1), render(2));
    // The neutral grey is at most 200 however it is lit: values between it and the
    // white background come only from pixels partly covered, at the silhouette.
    let blended = |p: [u8; 3]| p.iter().any(|&c| c > 200 && c < 255);
    let full = ((0, 100), (0, 100));
    assert_eq!(count(&sharp, full.0, full.1, blended), 0);
    let edge = count(&smooth, full.0, full.1, blended);
    assert!(edge > 30, "{edge} blended pixels");
    // Inside the disc, both agree closely.
    let (a, b) = (sharp.pixel(50, 50).unwrap(), smooth.pixel(50, 50).unwrap());
    assert!(
        a.iter().zip(b).all(|(x, y)| x.abs_diff(y) <= 3),
        "{a:?} {b:?}"
    );
}

#[test]
fn isolated_vertices_do_not_move_the_frame() {
    let faces = [[0u32, 1, 2]];
    let mut positions = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
    let alone = HalfedgeMesh::from_polygons(3, faces).unwrap();
    let with_isolated = HalfedgeMesh::from_polygons(4, faces).unwrap();
    let render = |mesh: &HalfedgeMesh, positions: &[DVec3]| {
        let view = View::from_above();
        render_mesh(
            mesh,
            positions,
            None,
            &ColorMap::default(),
            &view,
            None,
            80,
            80,
        )
        .unwrap()
    };
    let reference = render(&alone, &positions);
    positions.push(DVec3::new(100.0, 100.0, 0.0));
    assert_eq!(render(&with_isolated, &positions), reference);
}
