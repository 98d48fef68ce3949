//! `beltrami render` as a user runs it: a mesh file in, a PNG picture out.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use beltrami_halfedge::{PolygonList, primitives};
use beltrami_io::{Encoding, VertexAttributes, WriteOptions, write_ply};
use beltrami_viz::render::{ColorMap, Image};
use common::{beltrami, error_line, s, write};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(name)
}

/// Runs `args`, expecting success; returns the one line on stdout with the temporary
/// directory removed.
fn run(args: &[&str], dir: &Path) -> String {
    let out = beltrami(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stderr.is_empty());
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(stdout.lines().count(), 1, "one summary line: {stdout:?}");
    stdout
        .trim_end()
        .replace(&format!("{}/", dir.display()), "")
}

/// Checks the PNG signature and the size in the IHDR chunk, then decodes the image.
fn png(path: &Path, width: u32, height: u32) -> Image {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR");
    assert_eq!(bytes[16..20], width.to_be_bytes(), "IHDR width");
    assert_eq!(bytes[20..24], height.to_be_bytes(), "IHDR height");
    let image = Image::decode_png(&bytes).unwrap();
    assert_eq!((image.width, image.height), (width, height));
    image
}

fn pixels(image: &Image) -> impl Iterator<Item = [u8; 3]> + '_ {
    image.rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2]])
}

/// How much redder than blue a pixel is (negative: bluer).
fn redness([r, _, b]: [u8; 3]) -> i32 {
    i32::from(r) - i32::from(b)
}

/// Clearly red or clearly blue: a colour, not a shade of grey.
fn coloured(p: [u8; 3]) -> bool {
    redness(p).abs() > 40
}

/// The first and last row (from `below` down) holding the colour map's blue end.
fn bar_rows(image: &Image, below: u32) -> Option<(u32, u32)> {
    let rows: Vec<u32> = (below..image.height)
        .filter(|&y| (0..image.width).any(|x| image.pixel(x, y) == Some(ColorMap::LOW)))
        .collect();
    Some((*rows.first()?, *rows.last()?))
}

/// A noisy level-3 sphere and its clean reference, written by `beltrami generate`.
fn noisy_sphere(dir: &Path) -> (PathBuf, PathBuf) {
    let (noisy, clean) = (dir.join("noisy.ply"), dir.join("clean.ply"));
    let out = beltrami(&[
        "generate",
        "sphere",
        s(&noisy),
        "--level",
        "3",
        "--noise",
        "0.01",
        "--clean",
        s(&clean),
    ]);
    assert!(out.status.success());
    (noisy, clean)
}

fn failure(args: &[&str], dir: &Path, code: i32) -> String {
    let out: Output = beltrami(args);
    assert_eq!(out.status.code(), Some(code), "{args:?}");
    error_line(&out, dir)
}

#[test]
fn every_view_frames_the_mesh_at_the_requested_size() {
    let dir = tempfile::tempdir().unwrap();
    let lens = fixture("flens_68x33.ply");
    let mut images = Vec::new();
    for view in ["iso", "top", "front", "side"] {
        let out = dir.path().join(format!("{view}.png"));
        let line = run(
            &[
                "render",
                s(&lens),
                s(&out),
                "--view",
                view,
                "--size",
                "320x200",
            ],
            dir.path(),
        );
        assert!(line.starts_with("rendered "), "{line}");
        assert!(
            line.ends_with(&format!(
                "(2244 vertices, 4288 faces) from the {view} view, shaded grey -> {view}.png (320x200)"
            )),
            "{line}"
        );
        let image = png(&out, 320, 200);
        // Shaded grey on white: every pixel is a grey, and the mesh covers a good part
        // of the image but never touches its border (the frame has a margin).
        assert!(pixels(&image).all(|[r, g, b]| r == g && g == b));
        let covered = pixels(&image).filter(|&p| p != [255; 3]).count();
        assert!(covered > 320 * 200 / 20, "{view}: {covered} pixels");
        for x in 0..320 {
            assert_eq!(image.pixel(x, 0), Some([255; 3]), "{view}");
            assert_eq!(image.pixel(x, 199), Some([255; 3]), "{view}");
        }
        images.push(image);
    }
    for (i, a) in images.iter().enumerate() {
        for b in &images[i + 1..] {
            assert_ne!(a, b, "two views gave the same image");
        }
    }
    // The defaults: the iso view at 1200×900.
    let out = dir.path().join("sphere.png");
    let line = run(
        &["render", s(&fixture("icosphere_2.ply")), s(&out)],
        dir.path(),
    );
    assert!(line.contains("from the iso view"), "{line}");
    assert!(line.ends_with("-> sphere.png (1200x900)"), "{line}");
    png(&out, 1200, 900);
}

#[test]
fn distance_to_a_reference_colours_the_surface_and_draws_a_colour_bar() {
    let dir = tempfile::tempdir().unwrap();
    let (noisy, clean) = noisy_sphere(dir.path());
    let out = dir.path().join("distance.png");
    let args = [
        "render",
        s(&noisy),
        s(&out),
        "--distance-to",
        s(&clean),
        "--size",
        "480x360",
    ];
    let line = run(&args, dir.path());
    assert!(
        line.starts_with(
            "rendered noisy.ply (642 vertices, 1280 faces) from the iso view, \
             coloured by signed distance to clean.ply (mesh units) in [-"
        ),
        "{line}"
    );
    assert!(line.contains("(colour bar ±"), "{line}");
    assert!(line.ends_with("-> distance.png (480x360)"), "{line}");
    let image = png(&out, 480, 360);
    let (top, bottom) = bar_rows(&image, 180).expect("a colour bar in the lower half");
    // Above the bar: the sphere, with red (outside) and blue (inside) patches.
    let above = Image {
        width: 480,
        height: top,
        rgb: image.rgb[..(480 * top * 3) as usize].to_vec(),
    };
    let colours = pixels(&above).filter(|&p| coloured(p)).count();
    assert!(colours > 2000, "{colours} coloured pixels");
    assert!(pixels(&above).any(|p| redness(p) > 60));
    assert!(pixels(&above).any(|p| redness(p) < -60));
    // The bar runs from full blue to full red, with tick labels and its label below.
    let row = |x| image.pixel(x, top).unwrap();
    let low = (0..480).find(|&x| row(x) == ColorMap::LOW).unwrap();
    let high = (0..480).rev().find(|&x| row(x) == ColorMap::HIGH).unwrap();
    assert!(high > low + 200, "bar from {low} to {high}");
    let text = (bottom + 1..360)
        .flat_map(|y| (0..480).map(move |x| (x, y)))
        .filter(|&(x, y)| image.pixel(x, y).unwrap().iter().all(|&c| c < 100))
        .count();
    assert!(text > 300, "{text} dark pixels of text under the bar");

    // The same command gives the same bytes.
    let again = dir.path().join("again.png");
    let mut second = args;
    second[2] = s(&again);
    run(&second, dir.path());
    assert_eq!(std::fs::read(&out).unwrap(), std::fs::read(&again).unwrap());
}

#[test]
fn scalar_colours_by_a_vertex_property_of_a_ply_file() {
    let dir = tempfile::tempdir().unwrap();
    let (noisy, clean) = noisy_sphere(dir.path());
    // `compare --scalars` writes the signed distances `--distance-to` computes: the
    // picture of the surface is the same, only the bar's label differs.
    let scalars = dir.path().join("scalars.ply");
    assert!(
        beltrami(&["compare", s(&noisy), s(&clean), "--scalars", s(&scalars)])
            .status
            .success()
    );
    let by_name = dir.path().join("by_name.png");
    let line = run(
        &[
            "render",
            s(&scalars),
            s(&by_name),
            "--scalar",
            "signed_distance",
            "--size",
            "400x300",
        ],
        dir.path(),
    );
    assert!(line.contains("coloured by signed_distance in [-"), "{line}");
    let by_distance = dir.path().join("by_distance.png");
    run(
        &[
            "render",
            s(&noisy),
            s(&by_distance),
            "--distance-to",
            s(&clean),
            "--size",
            "400x300",
        ],
        dir.path(),
    );
    let (a, b) = (png(&by_name, 400, 300), png(&by_distance, 400, 300));
    let (top, _) = bar_rows(&a, 150).unwrap();
    assert_eq!(bar_rows(&b, 150).unwrap().0, top);
    let above = (top * 400 * 3) as usize;
    assert_eq!(a.rgb[..above], b.rgb[..above], "the same surface colours");
    assert_ne!(a, b, "the bar labels differ");

    // Ascii and big-endian files give the same picture; one-signed values get a bar
    // from their minimum to their maximum.
    let sphere = primitives::icosphere(2);
    let height: Vec<f64> = sphere.positions.iter().map(|p| p.z + 2.0).collect();
    let mut images = Vec::new();
    for (name, encoding) in [
        ("ascii.ply", Encoding::Ascii),
        ("big.ply", Encoding::BinaryBigEndian),
    ] {
        let path = dir.path().join(name);
        write_ply(
            &path,
            &sphere.clone(),
            &VertexAttributes {
                scalars: vec![
                    ("height".to_owned(), height.clone()),
                    ("depth".to_owned(), height.iter().map(|h| h - 3.0).collect()),
                ],
                colors: None,
            },
            &WriteOptions::default().encoding(encoding),
        )
        .unwrap();
        let out = dir.path().join(format!("{name}.png"));
        let line = run(
            &[
                "render",
                s(&path),
                s(&out),
                "--scalar",
                "height",
                "--size",
                "320x240",
                "--view",
                "front",
            ],
            dir.path(),
        );
        assert!(
            line.contains("coloured by height in [1, 3] (colour bar 1 to 3)"),
            "{line}"
        );
        images.push(std::fs::read(&out).unwrap());
    }
    assert_eq!(images[0], images[1]);
    // Values reaching 0 are read as signed: white at 0.
    let line = run(
        &[
            "render",
            s(&dir.path().join("ascii.ply")),
            s(&dir.path().join("depth.png")),
            "--scalar",
            "depth",
            "--size",
            "320x240",
        ],
        dir.path(),
    );
    assert!(
        line.contains("coloured by depth in [-2, 0] (colour bar ±2)"),
        "{line}"
    );
    // Seen from the front, the top (z = 1, red) and the bottom (z = -1, blue).
    let image = Image::decode_png(&images[0]).unwrap();
    let column: Vec<[u8; 3]> = (0..240).filter_map(|y| image.pixel(160, y)).collect();
    let first = column.iter().position(|&p| p != [255; 3]).unwrap();
    assert!(
        redness(column[first + 3]) > 40,
        "red at the top: {:?}",
        column[first + 3]
    );
}

#[test]
fn bad_input_and_usage_fail_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (noisy, clean) = noisy_sphere(d);
    let out = d.join("out.png");
    let sphere = s(&noisy);

    // A missing input: exit 1.
    let line = failure(&["render", s(&d.join("missing.ply")), s(&out)], d, 1);
    assert!(
        line.starts_with("error: missing.ply: failed to read the file: "),
        "{line}"
    );
    // Bad sizes: exit 2, from the argument parser.
    for (size, message) in [
        (
            "0x10",
            "the width must be a whole number of pixels from 1 to 8192, got '0'",
        ),
        ("abc", "expected WIDTHxHEIGHT in pixels, e.g. 1200x900"),
        (
            "640x",
            "the height must be a whole number of pixels from 1 to 8192, got ''",
        ),
        (
            "9000x10",
            "the width must be a whole number of pixels from 1 to 8192, got '9000'",
        ),
        (
            "8192x8192",
            "8192x8192 is 67108864 pixels, more than the limit of 33554432",
        ),
    ] {
        let line = failure(&["render", sphere, s(&out), "--size", size], d, 2);
        assert_eq!(
            line,
            format!(
                "error: invalid value '{size}' for '--size <WxH>': {message}\n\nFor more information, try '--help'."
            )
        );
    }
    assert_eq!(
        failure(
            &[
                "render",
                sphere,
                s(&out),
                "--distance-to",
                s(&clean),
                "--size",
                "100x100"
            ],
            d,
            2
        ),
        "error: --size 100x100 is too small for an image with a colour bar (at least 160x120) \
         (see 'beltrami --help')"
    );
    // An unknown scalar lists the ones the file has.
    assert_eq!(
        failure(&["render", sphere, s(&out), "--scalar", "quality"], d, 2),
        "error: noisy.ply: no scalar vertex property 'quality' (the file has: x, y, z) \
         (see 'beltrami --help')"
    );
    let stl = d.join("noisy.stl");
    assert!(
        beltrami(&["generate", "sphere", s(&stl), "--level", "1"])
            .status
            .success()
    );
    assert_eq!(
        failure(&["render", s(&stl), s(&out), "--scalar", "x"], d, 2),
        "error: --scalar reads a vertex property of a PLY file, but 'noisy.stl' is not .ply \
         (see 'beltrami --help')"
    );
    // A mesh without faces (and a reference without faces): exit 1.
    let points = write(
        d,
        "points.ply",
        primitives::icosphere(1).positions,
        PolygonList::new(),
    );
    assert_eq!(
        failure(&["render", s(&points), s(&out)], d, 1),
        "error: points.ply: the mesh has 42 vertices but no faces (points or lines only; render needs a surface of triangles)"
    );
    assert_eq!(
        failure(
            &["render", sphere, s(&out), "--distance-to", s(&points)],
            d,
            1
        ),
        "error: points.ply: the mesh has 42 vertices but no faces (points or lines only; render --distance-to needs a surface of triangles)"
    );
    // The output must be a PNG file and not an input: exit 2, nothing written.
    let before = std::fs::read(&noisy).unwrap();
    assert_eq!(
        failure(&["render", sphere, sphere], d, 2),
        "error: noisy.ply: OUT is the input file noisy.ply, which it would replace; give OUT \
         a file of its own (see 'beltrami --help')"
    );
    assert_eq!(
        failure(
            &["render", sphere, s(&clean), "--distance-to", s(&clean)],
            d,
            2
        ),
        "error: clean.ply: OUT is the input file clean.ply, which it would replace; give OUT \
         a file of its own (see 'beltrami --help')"
    );
    assert_eq!(
        failure(&["render", sphere, s(&d.join("out.ply"))], d, 2),
        "error: render writes a PNG image: OUT must end in .png, got 'out.ply' \
         (see 'beltrami --help')"
    );
    let link = d.join("link.png");
    std::fs::hard_link(&noisy, &link).unwrap();
    // A picture never replaces an input, also through a link and with --force (which
    // lets only a command's result mesh replace its input mesh).
    for force in [&[][..], &["--force"][..]] {
        let mut args = vec!["render", sphere, s(&link)];
        args.extend_from_slice(force);
        assert_eq!(
            failure(&args, d, 2),
            "error: link.png: OUT is the input file noisy.ply, which it would replace; give OUT a \
             file of its own (see 'beltrami --help')"
        );
    }
    assert_eq!(std::fs::read(&noisy).unwrap(), before);
    assert_eq!(std::fs::read(&link).unwrap(), before);
    assert!(!out.exists());
    // --scalar and --distance-to exclude each other.
    let line = failure(
        &[
            "render",
            sphere,
            s(&out),
            "--scalar",
            "x",
            "--distance-to",
            s(&clean),
        ],
        d,
        2,
    );
    assert!(line.contains("cannot be used with"), "{line}");
}

#[test]
fn help_shows_the_defaults() {
    let out = beltrami(&["render", "--help"]);
    assert!(out.status.success());
    let help = String::from_utf8(out.stdout).unwrap();
    for text in [
        "Usage: beltrami render [OPTIONS] <MESH> <OUT.png>",
        "[default: iso]",
        "[default: 1200x900]",
        "--scalar <NAME>",
        "--distance-to <REF>",
        "--force",
    ] {
        assert!(help.contains(text), "{text:?} in\n{help}");
    }
}
