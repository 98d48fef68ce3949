//! Line plots: content of the SVG, decoded PNG, determinism, skipped points, errors.

mod common;

use beltrami_viz::VizError;
use beltrami_viz::plot::{LinePlot, Series, plot_png, plot_svg};
use common::{count, dark, decode_png, non_white};

fn sample() -> LinePlot {
    let mut plot = LinePlot::new("RMS distance to the reference", "iterations", "RMS (mm)");
    for (k, name) in ["uniform", "cotangent", "mean value"].iter().enumerate() {
        let rate = 0.02 * (k + 1) as f64;
        let points = (0..=50).map(|i| {
            let t = f64::from(i);
            (t, 1e-4 + 3e-4 * (-rate * t).exp())
        });
        plot.series.push(Series::new(*name, points));
    }
    plot
}

#[test]
fn svg_names_title_axes_and_every_series() {
    let mut plot = sample();
    plot.series
        .push(Series::new("a < b & c", [(0.0, 1e-4), (50.0, 2e-4)]));
    let svg = plot_svg(&plot, 800, 500).unwrap();
    assert!(svg.starts_with("<svg"));
    for text in [
        "RMS distance to the reference",
        "iterations",
        "RMS (mm)",
        "uniform",
        "cotangent",
        "mean value",
        "a &lt; b &amp; c",
    ] {
        assert!(svg.contains(text), "the SVG lacks {text:?}");
    }
    // Legend order = series order.
    let at = |s: &str| svg.find(&format!("\n{s}\n")).unwrap();
    assert!(at("uniform") < at("cotangent") && at("cotangent") < at("mean value"));
    // Small values get readable tick labels.
    assert!(
        svg.contains("2e-4") || svg.contains("2.0e-4"),
        "tick labels: {svg}"
    );
}

#[test]
fn png_decodes_to_the_requested_size_with_data_and_title() {
    let (w, h) = (640, 400);
    let image = decode_png(&plot_png(&sample(), w, h).unwrap());
    assert_eq!((image.width, image.height), (w, h));
    assert_eq!(image.rgb.len(), (w * h * 3) as usize);
    // Coloured line pixels inside the plot area (not grey, not black).
    let coloured = |p: [u8; 3]| {
        let (lo, hi) = (*p.iter().min().unwrap(), *p.iter().max().unwrap());
        hi - lo > 60
    };
    let lines = count(&image, (w / 5, w * 9 / 10), (h / 6, h * 5 / 6), coloured);
    assert!(lines > 500, "{lines} coloured pixels in the plot area");
    // Text pixels where the title is: the top band, around the centre.
    let title = count(&image, (w / 4, w * 3 / 4), (0, h / 12), dark);
    assert!(title > 100, "{title} dark pixels in the title band");
    // The title is not cut off at the top edge.
    assert_eq!(count(&image, (0, w), (0, 1), non_white), 0);
    // Some white remains: the background.
    assert!(count(&image, (0, w), (0, h), |p| !non_white(p)) > (w * h / 2) as usize);
}

#[test]
fn identical_input_gives_identical_bytes() {
    let plot = sample();
    assert_eq!(
        plot_png(&plot, 500, 300).unwrap(),
        plot_png(&plot, 500, 300).unwrap()
    );
    assert_eq!(
        plot_svg(&plot, 500, 300).unwrap(),
        plot_svg(&plot, 500, 300).unwrap()
    );
}

#[test]
fn non_finite_points_are_skipped() {
    let mut plot = LinePlot::new("gaps", "x", "y");
    plot.series.push(Series::new(
        "with gaps",
        [
            (0.0, 1.0),
            (1.0, f64::NAN),
            (2.0, 2.0),
            (f64::INFINITY, 3.0),
            (3.0, f64::NEG_INFINITY),
            (4.0, 1.5),
        ],
    ));
    let svg = plot_svg(&plot, 400, 300).unwrap();
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
    // The range follows the finite points only: ticks from 0 to 4, not beyond.
    assert!(svg.contains("\n4\n") || svg.contains("\n4.0\n"), "{svg}");
    assert!(!svg.contains("\n10\n"));
    let image = decode_png(&plot_png(&plot, 400, 300).unwrap());
    assert_eq!((image.width, image.height), (400, 300));
}

#[test]
fn a_plot_without_finite_points_is_invalid() {
    let empty = LinePlot::new("empty", "x", "y");
    assert!(matches!(
        plot_svg(&empty, 400, 300),
        Err(VizError::Invalid { .. })
    ));
    let mut nan = LinePlot::new("nan", "x", "y");
    nan.series
        .push(Series::new("nan", [(f64::NAN, 1.0), (1.0, f64::NAN)]));
    assert!(matches!(
        plot_png(&nan, 400, 300),
        Err(VizError::Invalid { .. })
    ));
    let mut log = LinePlot::new("log", "x", "y");
    log.log_y = true;
    log.series
        .push(Series::new("not positive", [(0.0, 0.0), (1.0, -1.0)]));
    let err = plot_svg(&log, 400, 300).unwrap_err();
    assert!(err.to_string().contains("positive"), "{err}");
}

#[test]
fn zero_or_huge_sizes_are_invalid() {
    let plot = sample();
    assert!(matches!(
        plot_png(&plot, 0, 300),
        Err(VizError::Invalid { .. })
    ));
    assert!(matches!(
        plot_svg(&plot, 300, 0),
        Err(VizError::Invalid { .. })
    ));
    assert!(matches!(
        plot_png(&plot, 100_000, 300),
        Err(VizError::Invalid { .. })
    ));
}

#[test]
fn log_axis_has_decade_ticks() {
    let mut plot = LinePlot::new("time", "vertices", "time (s)");
    plot.log_y = true;
    plot.series.push(Series::new(
        "cotangent",
        [(1e3, 1e-3), (1e4, 2e-2), (1e5, 0.4), (1e6, 0.0)],
    ));
    let svg = plot_svg(&plot, 600, 400).unwrap();
    for label in ["\n0.001\n", "\n0.01\n", "\n0.1\n"] {
        assert!(svg.contains(label), "missing {label:?}");
    }
    let png = decode_png(&plot_png(&plot, 600, 400).unwrap());
    assert_eq!((png.width, png.height), (600, 400));
}

#[test]
fn single_points_and_equal_aspect_plots_draw() {
    let mut plot = LinePlot::new("profile", "x (mm)", "z (mm)");
    plot.aspect_equal = true;
    plot.series.push(Series::new(
        "profile",
        (0..=40).map(|i| {
            let x = -1.0 + f64::from(i) / 20.0;
            (x, 0.1 * x * x)
        }),
    ));
    plot.series.push(Series::new("one point", [(0.0, 0.5)]));
    let image = decode_png(&plot_png(&plot, 600, 400).unwrap());
    assert!(count(&image, (0, 600), (0, 400), non_white) > 1000);
    let mut flat = LinePlot::new("constant", "x", "y");
    flat.series.push(Series::new("c", [(1.0, 2.0), (1.0, 2.0)]));
    assert!(plot_svg(&flat, 400, 300).is_ok());
}

#[test]
fn a_fixed_style_keeps_a_series_colour_and_dashed_series_have_no_markers() {
    // Alone in a plot, a series styled as slot 2 gets slot 2's colour, not slot 0's.
    let mut plot = LinePlot::new("t", "x", "y");
    plot.series
        .push(Series::new("cotangent", [(0.0, 1.0), (1.0, 2.0)]).with_style(2));
    let svg = plot_svg(&plot, 800, 500).unwrap();
    assert!(svg.contains("#009E73"), "slot 2 is green");
    assert!(!svg.contains("#0072B2"), "slot 0's blue is not used");
    // A dashed series draws more, shorter segments than the same series solid, and
    // no marker.
    let solid = {
        let mut p = LinePlot::new("t", "x", "y");
        p.series.push(Series::new("a", [(0.0, 0.0), (10.0, 10.0)]));
        plot_svg(&p, 800, 500).unwrap()
    };
    let dashed = {
        let mut p = LinePlot::new("t", "x", "y");
        p.series
            .push(Series::new("a", [(0.0, 0.0), (10.0, 10.0)]).dashed());
        plot_svg(&p, 800, 500).unwrap()
    };
    let blue = |svg: &str| svg.matches("#0072B2").count();
    assert!(
        blue(&dashed) > blue(&solid) + 5,
        "{} vs {}",
        blue(&dashed),
        blue(&solid)
    );
    assert!(solid.contains("<circle"), "the first marker is a circle");
    assert!(!dashed.contains("<circle"));
}
