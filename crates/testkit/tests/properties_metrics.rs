//! Property tests of the study's per-run metrics: every number the study measures is
//! finite, and every measure that does not apply is an explicit `None` (`null` in the
//! JSON, empty in the CSV) — through the study's own API on random study configurations,
//! and through the metrics functions the study calls on random meshes, degenerate ones
//! included.

mod props_common;

use beltrami_halfedge::DVec3;
use beltrami_halfedge::geometry::{Geometry, VertexAreaKind};
use beltrami_metrics::MetricsError;
use beltrami_metrics::distance::{DistanceStats, SurfaceIndex};
use beltrami_metrics::distortion::{boundary_displacement, error_by_ring, feature_edge_distortion};
use beltrami_metrics::fits::{FitOptions, FitPoints, fit_sphere};
use beltrami_metrics::normals::normal_deviation;
use beltrami_smooth::{Boundary, SmoothConfig, WeightUpdate, smooth};
use beltrami_study::{FEATURE_THRESHOLD_DEG, StudyConfig, run_study};
use beltrami_surfaces::{NoiseLevel, Size, SurfaceKind};
use beltrami_weights::{NegativeWeights, WeightRegistry};
use props_common::{MeshSpec, RandomMesh, config, degenerate_mesh, well_shaped_mesh};
use proptest::prelude::*;

fn finite(name: &str, x: f64) -> Result<(), TestCaseError> {
    prop_assert!(x.is_finite(), "{} is {}", name, x);
    Ok(())
}

fn finite_or_none(name: &str, x: Option<f64>) -> Result<(), TestCaseError> {
    if let Some(x) = x {
        finite(name, x)?;
    }
    Ok(())
}

fn study_config() -> impl Strategy<Value = StudyConfig> {
    (
        prop::sample::subsequence(SurfaceKind::ALL.to_vec(), 1..=2),
        prop::sample::subsequence(vec![1usize, 2, 3, 5], 1..=2),
        0.05f64..=1.0,
        prop_oneof![
            (0.0f64..0.7).prop_map(NoiseLevel::RelativeToMeanEdge),
            (0.0f64..0.05).prop_map(NoiseLevel::Absolute),
        ],
        any::<u64>(),
        prop::sample::select(vec![Boundary::Fixed, Boundary::Free, Boundary::Curve]),
        prop::sample::select(vec![WeightUpdate::Every, WeightUpdate::Once]),
        prop::sample::select(vec![
            NegativeWeights::Keep,
            NegativeWeights::Clamp,
            NegativeWeights::Abs,
        ]),
    )
        .prop_map(
            |(surfaces, iterations, lambda, noise, seed, boundary, update, negative)| {
                let mut config = StudyConfig::paper(&WeightRegistry::with_builtins());
                config.surfaces = surfaces;
                config.size = Size::Small;
                config.iterations = iterations;
                config.lambda = lambda;
                config.noise = noise;
                config.seed = seed;
                config.boundary = boundary;
                config.update = update;
                config.negative = negative;
                config
            },
        )
}

proptest! {
    #![proptest_config(config(32))]

    /// The study on small surfaces with random step, noise, seed, boundary mode, update
    /// and negative-weight policy: every row's numbers are finite, and the measures that
    /// do not apply to a surface are `None` (volume on open surfaces, boundary
    /// displacement on closed ones, the sphere fit off the sphere and the golf ball, the
    /// feature angle off the block).
    #[test]
    fn study_rows_are_finite_or_none(config in study_config()) {
        let results = run_study(&config, &mut |_| {})
            .map_err(|e| TestCaseError::fail(format!("study failed: {e}")))?;
        prop_assert_eq!(results.surfaces.len(), config.surfaces.len());
        for surface in &results.surfaces {
            let kind = surface.case.kind;
            let closed = surface.case.mesh.is_closed();
            prop_assert_eq!(
                surface.measured.len(),
                1 + config.schemes.len() * config.iterations.len(),
                "one row for the noisy input and one per scheme and snapshot"
            );
            for measured in &surface.measured {
                let row = &measured.row;
                for (name, x) in [
                    ("time_s", row.time_s),
                    ("rms", row.rms),
                    ("mean", row.mean),
                    ("max", row.max),
                    ("area_rms", row.area_rms),
                    ("normal_mean_deg", row.normal_mean_deg),
                    ("normal_rms_deg", row.normal_rms_deg),
                ] {
                    finite(name, x)?;
                }
                for (name, x) in [
                    ("volume", row.volume),
                    ("volume_ratio", row.volume_ratio),
                    ("sphere_radius", row.sphere_radius),
                    ("boundary_mean", row.boundary_mean),
                    ("boundary_max", row.boundary_max),
                    ("feature_dihedral_deg", row.feature_dihedral_deg),
                ] {
                    finite_or_none(name, x)?;
                }
                prop_assert_eq!(row.volume.is_some(), closed);
                prop_assert_eq!(row.volume_ratio.is_some(), closed);
                prop_assert_eq!(row.boundary_mean.is_some(), !closed);
                prop_assert_eq!(row.boundary_max.is_some(), !closed);
                prop_assert_eq!(measured.rings.is_some(), !closed);
                prop_assert_eq!(
                    row.sphere_radius.is_some(),
                    matches!(kind, SurfaceKind::Sphere | SurfaceKind::GolfBall)
                );
                prop_assert_eq!(row.feature_dihedral_deg.is_some(), kind == SurfaceKind::Block);
                if let Some(rings) = &measured.rings {
                    for ring in &rings.rings {
                        finite("ring mean", ring.mean)?;
                        finite("ring rms", ring.rms)?;
                        finite("ring max", ring.max)?;
                    }
                }
                // The CSV has an empty field, never "NaN" or "inf".
                let csv = row.to_csv();
                prop_assert!(!csv.contains("NaN") && !csv.contains("inf"), "{}", csv);
            }
        }
    }
}

/// The study's measures of one snapshot (`smoothed`, from `noisy`), computed with the
/// metrics functions the study calls, in the same way; `Ok` holds every value that
/// the study would write.
fn measure_like_the_study(
    random: &RandomMesh,
    noisy: &[DVec3],
    smoothed: &[DVec3],
) -> Result<Vec<(&'static str, Option<f64>)>, MetricsError> {
    let RandomMesh {
        mesh,
        positions: clean,
    } = random;
    let index = SurfaceIndex::new(mesh, clean)?;
    let geometry = Geometry::new(mesh, smoothed)?;
    let clean_geometry = Geometry::new(mesh, clean)?;
    let distances = index.distances(smoothed)?;
    let areas = geometry.vertex_areas(VertexAreaKind::Barycentric)?;
    let stats = DistanceStats::new(&distances, areas.as_slice())?;
    let normals = normal_deviation(mesh, smoothed, mesh, clean)?;
    let (volume, clean_volume) = if mesh.is_closed() {
        (Some(geometry.volume()?), Some(clean_geometry.volume()?))
    } else {
        (None, None)
    };
    // The study fits spheres to its closed surfaces only (the sphere and the golf ball).
    let sphere_radius = if mesh.is_closed() {
        Some(fit_sphere(&FitPoints::new(smoothed), &FitOptions::default())?.radius)
    } else {
        None
    };
    let mut values = vec![
        ("rms", Some(stats.rms)),
        ("mean", Some(stats.mean)),
        ("max", Some(stats.max)),
        ("area_rms", Some(stats.area_weighted_rms)),
        ("normal_mean_deg", Some(normals.mean_deg)),
        ("normal_rms_deg", Some(normals.rms_deg)),
        ("volume", volume),
        ("sphere_radius", sphere_radius),
    ];
    // The study divides by the clean volume; its surfaces all enclose one. Here it is
    // only taken when the clean volume is not zero.
    if let (Some(v), Some(c)) = (volume, clean_volume)
        && c != 0.0
    {
        values.push(("volume_ratio", Some(v / c)));
    }
    if !mesh.is_closed() {
        let input = Geometry::new(mesh, noisy)?;
        let b = boundary_displacement(&input, &geometry)?;
        values.push(("boundary_mean", Some(b.mean)));
        values.push(("boundary_max", Some(b.max)));
        for ring in error_by_ring(mesh, &distances)?.rings {
            values.push(("ring rms", Some(ring.rms)));
            values.push(("ring max", Some(ring.max)));
        }
    }
    let features = feature_edge_distortion(&clean_geometry, &geometry, FEATURE_THRESHOLD_DEG)?;
    values.push(("feature_dihedral_deg", Some(features.smoothed.mean)));
    Ok(values)
}

/// Noisy positions (seeded, up to `amplitude` in each coordinate) and their smoothing
/// with cotangent weights, free boundary (the study's defaults).
fn noisy_and_smoothed(
    random: &RandomMesh,
    noise: &[[f64; 3]],
    amplitude: f64,
    iterations: usize,
) -> (Vec<DVec3>, Option<Vec<DVec3>>) {
    let noisy: Vec<DVec3> = random
        .positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if noise.is_empty() {
                *p
            } else {
                *p + DVec3::from_array(noise[i % noise.len()]) * amplitude
            }
        })
        .collect();
    let scheme = WeightRegistry::with_builtins()
        .get("cotangent")
        .expect("built-in scheme");
    let config = SmoothConfig::new(0.8, iterations).boundary(Boundary::Free);
    let smoothed = smooth(&random.mesh, &noisy, scheme.as_ref(), config)
        .ok()
        .map(|out| out.positions);
    (noisy, smoothed)
}

fn noise() -> impl Strategy<Value = Vec<[f64; 3]>> {
    prop::collection::vec([-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0], 1..32)
}

fn check_measures(
    spec: &MeshSpec,
    noise: &[[f64; 3]],
    amplitude: f64,
    iterations: usize,
    must_succeed: bool,
) -> Result<(), TestCaseError> {
    let random = spec.realise();
    // Removing faces can leave none: the metrics then rightly report an empty mesh.
    let must_succeed = must_succeed && random.mesh.n_faces() > 0;
    let (noisy, smoothed) = noisy_and_smoothed(&random, noise, amplitude, iterations);
    let Some(smoothed) = smoothed else {
        prop_assert!(!must_succeed, "smoothing failed on a well-shaped mesh");
        return Ok(());
    };
    match measure_like_the_study(&random, &noisy, &smoothed) {
        Ok(values) => {
            for (name, x) in values {
                finite_or_none(name, x)?;
            }
        }
        Err(e) => {
            prop_assert!(!e.to_string().is_empty());
            // On a well-shaped mesh the only admissible failure is an empty set: a tiny
            // open mesh (a tetrahedron less a face) that free-boundary smoothing
            // collapses until every face is degenerate.
            prop_assert!(
                !must_succeed || matches!(e, MetricsError::Empty { .. }),
                "metrics failed on a well-shaped mesh: {}",
                e
            );
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(512))]

    /// On well-shaped random triangle meshes (open and closed, genus 0 and 1), every
    /// measure of the study succeeds and is finite (or, when smoothing has collapsed
    /// every face of a tiny mesh, reports an empty set).
    #[test]
    fn study_measures_are_finite_on_random_meshes(
        spec in well_shaped_mesh(),
        noise in noise(),
        amplitude in 0.0f64..0.2,
        iterations in 1usize..8,
    ) {
        check_measures(&spec, &noise, amplitude, iterations, true)?;
    }

    /// On degenerate random meshes (coincident vertices, zero-area and needle faces,
    /// flattened, quads), every measure is finite or the metrics give a typed error.
    #[test]
    fn study_measures_are_finite_or_an_error_on_degenerate_meshes(
        spec in degenerate_mesh(),
        noise in noise(),
        amplitude in 0.0f64..0.2,
        iterations in 1usize..8,
    ) {
        check_measures(&spec, &noise, amplitude, iterations, false)?;
    }
}
