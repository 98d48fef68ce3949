//! Files are written atomically: complete files on success, nothing on failure.

use beltrami_viz::VizError;
use beltrami_viz::plot::{LinePlot, PNG_SIZE, Series, write_plot};
use beltrami_viz::render::Image;

fn plot() -> LinePlot {
    let mut plot = LinePlot::new("RMS", "iterations", "RMS (mm)");
    plot.series
        .push(Series::new("uniform", [(0.0, 2e-4), (10.0, 1e-4)]));
    plot
}

fn entries(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn write_plot_writes_svg_and_png_beside_each_other() {
    let dir = tempfile::tempdir().unwrap();
    write_plot(&plot(), &dir.path().join("fig.rms")).unwrap();
    assert_eq!(entries(dir.path()), ["fig.rms.png", "fig.rms.svg"]);
    let svg = std::fs::read_to_string(dir.path().join("fig.rms.svg")).unwrap();
    assert!(svg.contains("RMS (mm)"));
    let png = std::fs::read(dir.path().join("fig.rms.png")).unwrap();
    let info = png::Decoder::new(std::io::Cursor::new(png))
        .read_info()
        .unwrap();
    assert_eq!((info.info().width, info.info().height), PNG_SIZE);
}

#[test]
fn a_missing_directory_fails_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing");
    let err = write_plot(&plot(), &missing.join("rms")).unwrap_err();
    assert!(matches!(err, VizError::Write(_)), "{err}");
    let err = Image::new(4, 4)
        .write_png(&missing.join("x.png"))
        .unwrap_err();
    assert!(matches!(err, VizError::Write(_)), "{err}");
    assert!(!missing.exists());
    assert!(entries(dir.path()).is_empty());
}

#[test]
fn write_png_replaces_a_file_whole() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("panel.png");
    std::fs::write(&path, b"old").unwrap();
    let image = Image::filled(3, 2, [10, 20, 30]);
    image.write_png(&path).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), image.encode_png().unwrap());
    assert_eq!(entries(dir.path()), ["panel.png"]);
    // A malformed image writes nothing and keeps the old file.
    let broken = Image {
        width: 3,
        height: 2,
        rgb: vec![0; 4],
    };
    assert!(matches!(
        broken.write_png(&path),
        Err(VizError::Invalid { .. })
    ));
    assert_eq!(std::fs::read(&path).unwrap(), image.encode_png().unwrap());
}
