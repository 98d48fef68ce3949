//! `beltrami.study`: the whole comparison study, as `beltrami study` runs it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use beltrami_halfedge::geometry::VertexAreaKind;
use beltrami_io::stage_dir;
use beltrami_smooth::{Boundary, WeightUpdate};
use beltrami_study::{
    Countermeasure, OutDirError, StudyConfig, StudyError, Verdict, run_study, write_study,
};
use beltrami_surfaces::{NoiseLevel, Size, SurfaceKind};
use beltrami_weights::{NegativeWeights, Normalization, WeightScheme};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::{io_error, no_panic};
use crate::weights::{all_schemes, scheme};

/// Refuses an output directory that holds anything but an earlier study, before the
/// study runs (`ValueError`), and one that cannot be written (`OSError`).
fn check_out_dir(dir: &Path) -> PyResult<()> {
    // Either kind of earlier study may be replaced, as on the command line.
    beltrami_study::check_out_dir(dir, beltrami_study::is_any_study_entry).map_err(|e| match e {
        OutDirError::Unwritable(source) => io_error(dir, &source),
        e => PyValueError::new_err(format!("out {e}")),
    })
}

/// Every file under `dir`, sorted, as paths starting with `dir`.
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(d) = pending.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

fn verdict_word(v: Verdict) -> &'static str {
    match v {
        Verdict::Reproduced => "reproduced",
        Verdict::Contradicted => "contradicted",
        Verdict::Inconclusive => "inconclusive",
        _ => "not evaluated",
    }
}

/// A failed study: the configuration is `ValueError`, a file that cannot be written
/// `OSError`, anything else (a run that failed) `RuntimeError`.
fn study_error(e: &StudyError) -> PyErr {
    match e {
        StudyError::Config(message) => PyValueError::new_err(message.clone()),
        StudyError::Write { path, source } => io_error(path, source),
        StudyError::CreateDir { path, source } => pyo3::exceptions::PyOSError::new_err(format!(
            "{}: cannot create the directory: {source}",
            path.display()
        )),
        e => PyRuntimeError::new_err(e.to_string()),
    }
}

// The defaults written out in `study`'s text signature are the library's.
const _: () = assert!(beltrami_study::DEFAULT_SEEDS == 3);

/// Runs the whole comparison study, as `beltrami study` does, and writes its report,
/// tables, plots and renders into `out`.
///
/// The options are `beltrami study`'s, with the same words and defaults (`--lambda` →
/// `lam`, `-` → `_`): the paper's four surfaces, every registered weight scheme
/// (schemes registered with `register_weight` included), the iteration counts 10, 20,
/// …, 100 and 200, λ = 0.8, noise σ = 0.2 × the mean edge length (absolute, in the
/// surfaces' length unit, with `absolute_noise=True`), `seeds` noise seeds counted up
/// from `seed`, a free boundary, weights recomputed every iteration, the paper's sizes
/// (`small=True`: small variants, a quick look), and the shrinkage counter-measure runs
/// with `countermeasure_weights` unless `no_countermeasures`; negative weights kept
/// (`cotangent_negative`: `"keep"`, `"clamp"`, `"abs"`), rows normalised by the weight
/// sum (`normalize="area"` divides by the `vertex_area`, `"mixed"` or
/// `"barycentric"`, and takes `lam` as the fraction of each run's largest stable
/// explicit step), and the remeshing comparison at each clean mesh's mean edge
/// length (`remesh` in the surfaces' unit, `remesh_relative` as a multiple of the mean,
/// `no_remesh=True` to skip it), and the worked example of `study --input` on the noisy
/// block (`no_scan_example=True` to skip it).
///
/// `out` must be new, empty, or hold an earlier study, which is replaced as a whole
/// once the new one has been written (a failed run leaves it as it was).
///
/// Returns a dict: `out` and `report` (the paths of the directory and its report.md),
/// `files` (every file written, sorted), `surfaces` and `schemes` (the names run),
/// `observations` (rows of results.csv), `wall_time_s`, `findings` (one dict per
/// statement of the paper checked: `id`, `claim`, `verdict` — `"reproduced"`,
/// `"contradicted"`, `"inconclusive"` or `"not evaluated"` — `evidence`,
/// `tolerance`), and `verdicts` (the count of each verdict).
///
/// Raises `ValueError` for an unknown surface or scheme or a bad option, `OSError`
/// when `out` cannot be written, and what a Python weight scheme raised. The study runs
/// without the GIL (a Python scheme takes it for its calls) and cannot be interrupted
/// before it ends.
#[pyfunction]
#[pyo3(signature = (
    out = None,
    *,
    surfaces = vec!["flens".to_string(), "sphere".to_string(), "block".to_string(), "golfball".to_string()],
    weights = None,
    iterations = beltrami_study::paper_iterations().into_iter().map(|n| n as i128).collect(),
    lam = 0.8,
    noise = 0.2,
    absolute_noise = false,
    seed = 1,
    seeds = beltrami_study::DEFAULT_SEEDS as i128,
    boundary = "free",
    update = "every",
    small = false,
    countermeasure_weights = "cotangent",
    no_countermeasures = false,
    cotangent_negative = "keep",
    normalize = "sum",
    vertex_area = "mixed",
    remesh = None,
    remesh_relative = None,
    no_remesh = false,
    no_scan_example = false,
),
// The defaults written out (an expression shows as `Ellipsis` in `inspect.signature`);
// the assertion above `study`'s documentation and a Python test keep them the library's.
text_signature = "(out='study', *, surfaces=('flens', 'sphere', 'block', 'golfball'), weights=None, iterations=(10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 200), lam=0.8, noise=0.2, absolute_noise=False, seed=1, seeds=3, boundary='free', update='every', small=False, countermeasure_weights='cotangent', no_countermeasures=False, cotangent_negative='keep', normalize='sum', vertex_area='mixed', remesh=None, remesh_relative=None, no_remesh=False, no_scan_example=False)"
)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn study<'py>(
    py: Python<'py>,
    out: Option<&Bound<'py, PyAny>>,
    surfaces: Vec<String>,
    weights: Option<Vec<String>>,
    iterations: Vec<i128>,
    lam: f64,
    noise: f64,
    absolute_noise: bool,
    seed: i128,
    seeds: i128,
    boundary: &str,
    update: &str,
    small: bool,
    countermeasure_weights: &str,
    no_countermeasures: bool,
    cotangent_negative: &str,
    normalize: &str,
    vertex_area: &str,
    remesh: Option<f64>,
    remesh_relative: Option<f64>,
    no_remesh: bool,
    no_scan_example: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let out = match out {
        Some(out) => crate::errors::path_arg("out", out)?,
        None => PathBuf::from("study"),
    };
    let iterations = iterations
        .into_iter()
        .map(|n| crate::errors::nonnegative::<usize>("iterations", n))
        .collect::<PyResult<Vec<_>>>()?;
    let seed: u64 = crate::errors::nonnegative("seed", seed)?;
    let seeds: usize = crate::errors::nonnegative("seeds", seeds)?;
    let negative = negative_weights(cotangent_negative)?;
    let normalization = normalization_of(normalize, vertex_area)?;
    let remesh = remesh_options(no_remesh, remesh, remesh_relative)?;
    let surfaces = surfaces
        .iter()
        .map(|s| SurfaceKind::from_name(s).map_err(|e| PyValueError::new_err(e.to_string())))
        .collect::<PyResult<Vec<_>>>()?;
    let schemes: Vec<Arc<dyn WeightScheme>> = match &weights {
        None => all_schemes()?,
        Some(names) => names.iter().map(|w| scheme(w)).collect::<PyResult<_>>()?,
    };
    let boundary = boundary_of(boundary)?;
    let update = weight_update(update)?;
    let config = StudyConfig::default()
        .surfaces(surfaces)
        .size(if small { Size::Small } else { Size::Paper })
        .schemes(schemes)
        .iterations(iterations)
        .lambda(lam)
        .noise(if absolute_noise {
            NoiseLevel::Absolute(noise)
        } else {
            NoiseLevel::RelativeToMeanEdge(noise)
        })
        .seed(seed)
        .seeds(seeds)
        .boundary(boundary)
        .update(update)
        .negative(negative)
        .normalization(normalization)
        .countermeasures(if no_countermeasures {
            Vec::new()
        } else {
            Countermeasure::defaults(lam)
        })
        .countermeasure_scheme(if no_countermeasures {
            None
        } else {
            Some(scheme(countermeasure_weights)?)
        })
        .edge_comparison(scheme("bilateral").ok().zip(scheme("cotangent").ok()))
        .remesh(remesh)
        .timing(true)
        .scan_example(!no_scan_example);
    config
        .validate()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    check_out_dir(&out)?;
    let names: Vec<String> = config
        .schemes
        .iter()
        .map(|s| s.name().to_string())
        .collect();
    // The slots of the schemes this run holds (see `failure_slot`).
    let failures: Vec<_> = names
        .iter()
        .map(String::as_str)
        .chain((!no_countermeasures).then_some(countermeasure_weights))
        .map(crate::scheme::failure_slot)
        .collect();
    let written = py.detach(|| {
        no_panic(|| {
            let results = run_study(&config, &mut |_| {}).map_err(|e| study_error(&e))?;
            let staged = stage_dir(&out).map_err(|e| io_error(&out, &e))?;
            let written = write_study(&results, staged.path()).map_err(|e| study_error(&e))?;
            staged.commit().map_err(|e| io_error(&out, &e))?;
            Ok((results.wall_time_s, written))
        })
    });
    // Every scheme's failure is taken (the countermeasures' scheme's too), so that none
    // is left for a later call to raise; the first is raised.
    let first = failures
        .iter()
        .filter_map(|slot| crate::scheme::take(slot.as_ref()))
        .reduce(|first, _| first);
    if let Some(e) = first {
        return Err(e);
    }
    let (wall_time_s, written) = written?;

    result_dict(py, &out, &config, names, wall_time_s, &written)
}

/// `cotangent_negative`: `"keep"`, `"clamp"` or `"abs"`.
pub(crate) fn negative_weights(cotangent_negative: &str) -> PyResult<NegativeWeights> {
    let value = match cotangent_negative {
        "keep" => NegativeWeights::Keep,
        "clamp" => NegativeWeights::Clamp,
        "abs" => NegativeWeights::Abs,
        _ => {
            return Err(PyValueError::new_err(format!(
                "cotangent_negative must be one of 'keep', 'clamp', 'abs', got '{cotangent_negative}'"
            )));
        }
    };
    Ok(value)
}

/// `normalize` (`"sum"` or `"area"`) with `vertex_area` (`"mixed"` or `"barycentric"`).
fn normalization_of(normalize: &str, vertex_area: &str) -> PyResult<Normalization> {
    let value = match (normalize, vertex_area) {
        ("sum", "mixed" | "barycentric") => Normalization::WeightSum,
        ("area", "mixed") => Normalization::Area(VertexAreaKind::MixedVoronoi),
        ("area", "barycentric") => Normalization::Area(VertexAreaKind::Barycentric),
        ("sum" | "area", _) => {
            return Err(PyValueError::new_err(format!(
                "vertex_area must be one of 'mixed', 'barycentric', got '{vertex_area}'"
            )));
        }
        _ => {
            return Err(PyValueError::new_err(format!(
                "normalize must be one of 'sum', 'area', got '{normalize}'"
            )));
        }
    };
    Ok(value)
}

/// The remeshing comparison: at most one of `remesh` (a target edge length),
/// `remesh_relative` (a multiple of the mean edge length) and `no_remesh`.
fn remesh_options(
    no_remesh: bool,
    remesh: Option<f64>,
    remesh_relative: Option<f64>,
) -> PyResult<Option<beltrami_algorithms::RemeshOptions>> {
    let positive = |name: &str, x: f64| {
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(PyValueError::new_err(format!(
                "{name} must be a positive number, got {x}"
            )))
        }
    };
    let value = match (no_remesh, remesh, remesh_relative) {
        (true, None, None) => None,
        (true, ..) | (false, Some(_), Some(_)) => {
            return Err(PyValueError::new_err(
                "give at most one of remesh, remesh_relative and no_remesh",
            ));
        }
        (false, Some(l), None) => {
            Some(beltrami_study::default_remesh().edge_length(positive("remesh", l)?))
        }
        (false, None, Some(r)) => Some(
            beltrami_study::default_remesh().relative_edge_length(positive("remesh_relative", r)?),
        ),
        (false, None, None) => Some(beltrami_study::default_remesh()),
    };
    Ok(value)
}

/// `boundary`: `"fixed"`, `"free"` or `"curve"`.
fn boundary_of(boundary: &str) -> PyResult<Boundary> {
    let value = match boundary {
        "fixed" => Boundary::Fixed,
        "free" => Boundary::Free,
        "curve" => Boundary::Curve,
        _ => {
            return Err(PyValueError::new_err(format!(
                "boundary must be one of 'fixed', 'free', 'curve', got '{boundary}'"
            )));
        }
    };
    Ok(value)
}

/// `update`: `"every"` or `"once"`.
fn weight_update(update: &str) -> PyResult<WeightUpdate> {
    let value = match update {
        "every" => WeightUpdate::Every,
        "once" => WeightUpdate::Once,
        _ => {
            return Err(PyValueError::new_err(format!(
                "update must be one of 'every', 'once', got '{update}'"
            )));
        }
    };
    Ok(value)
}

/// The dict `study` returns (see there).
fn result_dict<'py>(
    py: Python<'py>,
    out: &Path,
    config: &StudyConfig,
    names: Vec<String>,
    wall_time_s: f64,
    written: &beltrami_study::Written,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("out", out)?;
    d.set_item("report", out.join("report.md"))?;
    d.set_item("files", files_under(out))?;
    d.set_item(
        "surfaces",
        config
            .surfaces
            .iter()
            .map(|s| s.name().to_string())
            .collect::<Vec<_>>(),
    )?;
    d.set_item("schemes", names)?;
    d.set_item("observations", written.rows.len())?;
    d.set_item("wall_time_s", wall_time_s)?;
    let findings = PyList::empty(py);
    let verdicts = PyDict::new(py);
    for word in [
        "reproduced",
        "contradicted",
        "inconclusive",
        "not evaluated",
    ] {
        verdicts.set_item(word, 0)?;
    }
    for f in &written.findings {
        let word = verdict_word(f.verdict);
        let finding = PyDict::new(py);
        finding.set_item("id", f.id)?;
        finding.set_item("claim", f.claim)?;
        finding.set_item("verdict", word)?;
        finding.set_item("evidence", &f.evidence)?;
        finding.set_item("tolerance", &f.tolerance)?;
        findings.append(finding)?;
        let count: usize = verdicts.get_item(word)?.map_or(Ok(0), |c| c.extract())?;
        verdicts.set_item(word, count + 1)?;
    }
    d.set_item("findings", findings)?;
    d.set_item("verdicts", verdicts)?;
    Ok(d)
}
