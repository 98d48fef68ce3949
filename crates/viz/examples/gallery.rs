//! Writes a sample of every figure kind into a directory:
//!
//! - `rms.svg` / `rms.png`: RMS distance against iterations, one series per scheme;
//! - `time.svg` / `time.png`: run time against mesh size on a log axis;
//! - `profile.svg` / `profile.png`: a cross-section profile with equal axis scales;
//! - `sphere-grid.png`: a noisy sphere smoothed by two schemes, coloured by signed
//!   distance to the unit sphere (rows = schemes, columns = iterations);
//! - `lens.png`: an open height field from the default three-quarter view.
//!
//! ```text
//! cargo run --release -p beltrami-viz --example gallery -- target/gallery
//! ```

use std::error::Error;
use std::path::PathBuf;

use beltrami_halfedge::{DVec3, HalfedgeMesh, primitives};
use beltrami_viz::plot::{LinePlot, Series, write_plot};
use beltrami_viz::render::{ColorMap, View, grid, render_mesh};

fn main() -> Result<(), Box<dyn Error>> {
    let Some(dir) = std::env::args_os().nth(1).map(PathBuf::from) else {
        eprintln!("usage: gallery OUTPUT_DIRECTORY");
        std::process::exit(2);
    };
    std::fs::create_dir_all(&dir)?;
    plots(&dir)?;
    sphere_grid(&dir)?;
    lens(&dir)?;
    println!("wrote the gallery to {}", dir.display());
    Ok(())
}

fn plots(dir: &std::path::Path) -> Result<(), Box<dyn Error>> {
    let schemes = [
        ("uniform", 0.02, 1.6e-4),
        ("inverse distance", 0.035, 1.2e-4),
        ("cotangent", 0.06, 0.7e-4),
        ("mean value", 0.05, 0.8e-4),
    ];
    let mut rms = LinePlot::new(
        "RMS distance to the reference",
        "iterations",
        "RMS distance (mm)",
    );
    for (name, rate, floor) in schemes {
        let points = (0..=100).map(|i| {
            let t = f64::from(i);
            (t, floor + 3.0e-4 * (-rate * t).exp())
        });
        rms.series.push(Series::new(name, points));
    }
    write_plot(&rms, &dir.join("rms"))?;

    let mut time = LinePlot::new("Time per iteration", "vertices", "time (s)");
    time.log_y = true;
    for (k, (name, _, _)) in schemes.iter().enumerate() {
        let points = [1e3, 4e3, 16e3, 64e3, 256e3]
            .map(|n: f64| (n, 2e-7 * (1.0 + 0.4 * k as f64) * n * n.ln()));
        time.series.push(Series::new(*name, points));
    }
    write_plot(&time, &dir.join("time"))?;

    let mut profile = LinePlot::new("Cross-section at y = 0", "x (mm)", "z (mm)");
    profile.aspect_equal = true;
    let lens = |x: f64| 2.0 - (4.0 - x * x).max(0.0).sqrt();
    profile.series.push(Series::new(
        "reference",
        (0..=80).map(|i| {
            let x = -1.6 + 3.2 * f64::from(i) / 80.0;
            (x, lens(x))
        }),
    ));
    profile.series.push(Series::new(
        "smoothed (cotangent, 20 it.)",
        (0..=80).map(|i| {
            let x = -1.6 + 3.2 * f64::from(i) / 80.0;
            (x, lens(x) + 0.03 * (9.0 * x).sin() * (-x * x).exp())
        }),
    ));
    write_plot(&profile, &dir.join("profile"))?;
    Ok(())
}

/// A deterministic bumpy field on the sphere.
fn bumps(p: DVec3) -> f64 {
    0.03 * (9.0 * p.x).sin() * (7.0 * p.y).cos()
        + 0.02 * (13.0 * p.z + 1.0).sin()
        + 0.01 * (31.0 * p.x + 17.0 * p.y).sin()
}

/// One explicit Laplacian step with weights `weight(p_i, p_j)`, step size `lambda`.
fn smooth_step(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    lambda: f64,
    weight: impl Fn(DVec3, DVec3) -> f64,
) -> Vec<DVec3> {
    mesh.vertices()
        .map(|v| {
            let p = positions[v.index()];
            let (mut sum, mut total) = (DVec3::ZERO, 0.0);
            for u in mesh.vertices_around_vertex(v) {
                let q = positions[u.index()];
                let w = weight(p, q);
                sum += w * q;
                total += w;
            }
            if total > 0.0 {
                p + lambda * (sum / total - p)
            } else {
                p
            }
        })
        .collect()
}

fn sphere_grid(dir: &std::path::Path) -> Result<(), Box<dyn Error>> {
    let sphere = primitives::icosphere(4);
    let mesh = sphere.mesh()?;
    let noisy: Vec<DVec3> = sphere
        .positions
        .iter()
        .map(|&p| p * (1.0 + bumps(p)))
        .collect();
    let distance =
        |positions: &[DVec3]| -> Vec<f64> { positions.iter().map(|p| p.length() - 1.0).collect() };
    let map = ColorMap::symmetric_for(&distance(&noisy));
    let frame = Some((DVec3::splat(-1.08), DVec3::splat(1.08)));
    let view = View::default_for(&noisy);
    let iterations = [0, 10, 50];
    type Weight = fn(DVec3, DVec3) -> f64;
    let schemes: [(&str, Weight); 2] = [
        ("uniform", |_, _| 1.0),
        ("inverse distance", |p, q| 1.0 / (p - q).length().max(1e-12)),
    ];
    let mut panels = Vec::new();
    for (_, weight) in schemes {
        let mut positions = noisy.clone();
        let mut done = 0;
        for &target in &iterations {
            while done < target {
                positions = smooth_step(&mesh, &positions, 0.5, weight);
                done += 1;
            }
            let d = distance(&positions);
            panels.push(render_mesh(
                &mesh,
                &positions,
                Some(&d),
                &map,
                &view,
                frame,
                360,
                300,
            )?);
        }
    }
    let figure = grid(
        &panels,
        iterations.len(),
        &iterations.map(|n| format!("{n} iterations")),
        &schemes.map(|(name, _)| name.to_owned()),
        "Noisy sphere: signed distance to the unit sphere",
        Some((&map, "signed distance (mm)")),
    )?;
    figure.write_png(&dir.join("sphere-grid.png"))?;
    Ok(())
}

fn lens(dir: &std::path::Path) -> Result<(), Box<dyn Error>> {
    let n = 60;
    let plane = primitives::grid(n, n);
    let mesh = plane.mesh()?;
    let positions: Vec<DVec3> = plane
        .positions
        .iter()
        .map(|p| {
            let (x, y) = (
                2.0 * p.x / f64::from(n) - 1.0,
                2.0 * p.y / f64::from(n) - 1.0,
            );
            DVec3::new(
                x,
                y,
                0.25 * (x * x + y * y) + 0.02 * (9.0 * x).sin() * (7.0 * y).cos(),
            )
        })
        .collect();
    let residual: Vec<f64> = positions
        .iter()
        .map(|p| p.z - 0.25 * (p.x * p.x + p.y * p.y))
        .collect();
    let map = ColorMap::symmetric_for(&residual);
    let view = View::default_for(&positions);
    let image = render_mesh(
        &mesh,
        &positions,
        Some(&residual),
        &map,
        &view,
        None,
        640,
        480,
    )?;
    let figure = grid(
        &[image],
        1,
        &[],
        &[],
        "Height field: residual to the fitted paraboloid",
        Some((&map, "residual (mm)")),
    )?;
    figure.write_png(&dir.join("lens.png"))?;
    Ok(())
}
