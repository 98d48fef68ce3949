//! Timing done apart from the study's runs: per surface and scheme, the median over
//! repeated short runs of the weight computation and of the position update per
//! iteration, the schemes against each other, and the machine, thread count and commit
//! the numbers belong to. Timings never enter `results.csv` or `results.json`'s rows.

use std::ops::ControlFlow;
use std::path::Path;
use std::time::Instant;

use beltrami_smooth::{SmoothConfig, Smoother, Statistics};
use beltrami_weights::{LaplacianOptions, WeightScheme};
use serde::Serialize;

use crate::case::SurfaceCase;
use crate::config::StudyConfig;
use crate::error::StudyError;

/// Repeats per surface and scheme; the median is reported.
pub const TIMING_REPEATS: usize = 7;

/// Iterations of each timed run.
pub const TIMING_ITERATIONS: usize = 10;

/// One scheme's timing on one surface: medians over [`TIMING_REPEATS`] runs of
/// [`TIMING_ITERATIONS`] iterations, per iteration, in seconds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SchemeTiming {
    /// The surface's name.
    pub surface: String,
    /// The scheme's name.
    pub scheme: String,
    /// Median set-up of a run (the smoother's construction: checks, the first weights,
    /// the operator's structure), once per run, seconds.
    pub build_s: f64,
    /// Median weight recomputation per iteration (the run's weight time beyond the
    /// set-up, over the iterations after the first, which uses the first weights; 0 for
    /// weights that do not depend on the positions), seconds.
    pub weights_s: f64,
    /// Median position update per iteration, seconds.
    pub update_s: f64,
    /// Median of an iteration's work (weights + update), seconds.
    pub total_s: f64,
    /// The smallest and largest total over the repeats, seconds.
    pub total_range_s: (f64, f64),
}

/// Where the timings were measured.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MachineInfo {
    /// The CPU model (`/proc/cpuinfo`'s `model name`), or `"unknown"`.
    pub cpu: String,
    /// Operating system and architecture.
    pub os: String,
    /// Threads of the rayon pool the study ran with.
    pub threads: usize,
    /// The commit of the source (`BELTRAMI_COMMIT` in the environment, else read from
    /// the `.git` directory above the working directory), or `"unknown"`.
    pub commit: String,
    /// The 1-minute load average when measured (`/proc/loadavg`), if available: above
    /// the thread count, other processes shared the machine.
    pub load: Option<f64>,
}

impl MachineInfo {
    /// Whether the load average exceeded the thread count (other work shared the
    /// machine); `false` when unknown.
    #[must_use]
    pub fn shared(&self) -> bool {
        self.load.is_some_and(|l| l > self.threads as f64)
    }

    /// The load in words for the report.
    #[must_use]
    pub fn load_text(&self) -> String {
        match self.load {
            Some(l) if self.shared() => format!(
                "load average {l:.2} on {} threads: other processes shared the machine, so the times are disturbed",
                self.threads
            ),
            Some(l) => format!("load average {l:.2} on {} threads", self.threads),
            None => "load average unknown".into(),
        }
    }
}

/// The study's timings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Timings {
    /// Where they were measured.
    pub machine: MachineInfo,
    /// Repeats per surface and scheme.
    pub repeats: usize,
    /// Iterations per timed run.
    pub iterations: usize,
    /// Per surface and scheme, in the study's order.
    pub rows: Vec<SchemeTiming>,
}

impl Timings {
    /// The ratio of `num`'s median iteration time to `den`'s on `surface`, if both were
    /// timed and `den`'s is positive.
    #[must_use]
    pub fn ratio(&self, surface: &str, num: &str, den: &str) -> Option<f64> {
        let t = |scheme: &str| {
            self.rows
                .iter()
                .find(|r| r.surface == surface && r.scheme == scheme)
                .map(|r| r.total_s)
        };
        let (a, b) = (t(num)?, t(den)?);
        (b > 0.0).then_some(a / b)
    }
}

/// The median of `values` (the mean of the middle two for an even count); `None` when
/// empty or not all finite.
#[must_use]
pub fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() || values.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

/// Times every scheme of `schemes` on every case, one run after the other.
///
/// # Errors
/// [`StudyError::Smooth`] naming the surface and scheme.
pub(crate) fn time_schemes(
    cases: &[&SurfaceCase],
    schemes: &[std::sync::Arc<dyn WeightScheme>],
    config: &StudyConfig,
) -> Result<Timings, StudyError> {
    let smooth = SmoothConfig::new(config.lambda, TIMING_ITERATIONS)
        .boundary(config.boundary)
        .update(config.update)
        .statistics(Statistics::OnDemand)
        .laplacian(
            LaplacianOptions::new()
                .normalization(config.normalization)
                .negative(config.negative),
        );
    let mut rows = Vec::new();
    for case in cases {
        for scheme in schemes {
            let failed = |source| StudyError::Smooth {
                surface: format!("{} (timing)", case.clean.name),
                scheme: scheme.name().to_string(),
                source,
            };
            let smooth = crate::run::with_area_steps(
                &case.mesh,
                &case.noisy,
                scheme.as_ref(),
                smooth.clone(),
            )
            .map_err(failed)?;
            let (mut b, mut w, mut u, mut t) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            for _ in 0..TIMING_REPEATS {
                let start = Instant::now();
                let smoother =
                    Smoother::new(&case.mesh, &case.noisy, scheme.as_ref(), smooth.clone())
                        .map_err(failed)?;
                let build = start.elapsed().as_secs_f64();
                let done = smoother
                    .run(|_| ControlFlow::Continue(()))
                    .map_err(failed)?;
                let n = done.report.iterations.max(1) as f64;
                let refreshes = (done.report.iterations.max(2) - 1) as f64;
                let ws = (done.report.weight_time.as_secs_f64() - build).max(0.0) / refreshes;
                let us = done.report.update_time.as_secs_f64() / n;
                b.push(build);
                w.push(ws);
                u.push(us);
                t.push(ws + us);
            }
            let lo = t.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = t.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            rows.push(SchemeTiming {
                surface: case.clean.name.to_string(),
                scheme: scheme.name().to_string(),
                build_s: median(&b).unwrap_or(f64::NAN),
                weights_s: median(&w).unwrap_or(f64::NAN),
                update_s: median(&u).unwrap_or(f64::NAN),
                total_s: median(&t).unwrap_or(f64::NAN),
                total_range_s: (lo, hi),
            });
        }
    }
    Ok(Timings {
        machine: machine_info(),
        repeats: TIMING_REPEATS,
        iterations: TIMING_ITERATIONS,
        rows,
    })
}

/// The machine the study runs on.
#[must_use]
pub fn machine_info() -> MachineInfo {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| cpu_model(&text))
        .unwrap_or_else(|| "unknown".into());
    let commit = std::env::var("BELTRAMI_COMMIT")
        .ok()
        .map(|c| c.trim().to_string())
        .filter(|c| !c.is_empty())
        .or_else(|| std::env::current_dir().ok().and_then(|d| git_commit(&d)))
        .unwrap_or_else(|| "unknown".into());
    let load = std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|t| t.split_whitespace().next()?.parse::<f64>().ok())
        .filter(|l| l.is_finite());
    MachineInfo {
        cpu,
        os: format!("{} {}", std::env::consts::OS, std::env::consts::ARCH),
        threads: rayon::current_num_threads(),
        commit,
        load,
    }
}

/// The first `model name` of a `/proc/cpuinfo` text.
#[must_use]
pub fn cpu_model(cpuinfo: &str) -> Option<String> {
    cpuinfo.lines().find_map(|line| {
        let (key, value) = line.split_once(':')?;
        (key.trim() == "model name")
            .then(|| value.split_whitespace().collect::<Vec<_>>().join(" "))
            .filter(|v| !v.is_empty())
    })
}

/// The commit checked out in the repository at or above `dir` (a `.git` directory, or
/// a `.git` file pointing at a worktree's git directory): `HEAD`, following one
/// symbolic reference through a loose or packed ref, abbreviated to 12 hex digits.
#[must_use]
pub fn git_commit(dir: &Path) -> Option<String> {
    let mut at = Some(dir);
    while let Some(d) = at {
        let dot = d.join(".git");
        if dot.exists() {
            let git_dir = if dot.is_file() {
                let text = std::fs::read_to_string(&dot).ok()?;
                let rel = text.trim().strip_prefix("gitdir:")?.trim().to_string();
                d.join(rel)
            } else {
                dot
            };
            return head_commit(&git_dir);
        }
        at = d.parent();
    }
    None
}

fn is_hash(s: &str) -> bool {
    s.len() >= 40 && s.chars().all(|c| c.is_ascii_hexdigit())
}

fn head_commit(git_dir: &Path) -> Option<String> {
    let head = std::fs::read_to_string(git_dir.join("HEAD")).ok()?;
    let head = head.trim();
    let hash = if let Some(name) = head.strip_prefix("ref:") {
        let name = name.trim();
        // A worktree's refs live in the common directory.
        let common = std::fs::read_to_string(git_dir.join("commondir"))
            .ok()
            .map_or_else(|| git_dir.to_path_buf(), |c| git_dir.join(c.trim()));
        let loose = [git_dir.join(name), common.join(name)]
            .iter()
            .find_map(|p| std::fs::read_to_string(p).ok())
            .map(|s| s.trim().to_string());
        loose.or_else(|| {
            let packed = std::fs::read_to_string(common.join("packed-refs")).ok()?;
            packed.lines().find_map(|l| {
                let (hash, r) = l.split_once(' ')?;
                (r.trim() == name).then(|| hash.to_string())
            })
        })?
    } else {
        head.to_string()
    };
    is_hash(&hash).then(|| hash[..12].to_string())
}

fn ms(x: f64) -> String {
    if x.is_finite() {
        format!("{:.3}", 1e3 * x)
    } else {
        "–".into()
    }
}

/// The "Timing" section of the report: per surface and scheme the medians, and each
/// scheme against every other.
pub(crate) fn timing_section(s: &mut String, t: &Timings) {
    use std::fmt::Write as _;
    let _ = writeln!(
        s,
        "## Timing
"
    );
    let _ = writeln!(
        s,
        "Timed apart from the study's runs, one run after the other: per surface and scheme, {} runs of {} iterations on the noisy input of the first seed (weights recomputed every iteration, as in the study); the medians, in milliseconds, of a run's set-up (checks, the first weights, the operator's structure; once per run) and, per iteration, of the weight recomputation and of the position update, with the range of an iteration's total over the runs. The ratios compare an iteration's total. Machine: {}, {}, {} threads; commit {}; {}. The cumulative times of the tables and the time plots come from the study's single runs.\n",
        t.repeats,
        t.iterations,
        t.machine.cpu,
        t.machine.os,
        t.machine.threads,
        t.machine.commit,
        t.machine.load_text()
    );
    let mut schemes: Vec<&str> = Vec::new();
    for r in &t.rows {
        if !schemes.contains(&r.scheme.as_str()) {
            schemes.push(&r.scheme);
        }
    }
    let _ = write!(
        s,
        "| surface | scheme | set-up (ms) | weights (ms/iteration) | update (ms/iteration) | total (ms/iteration) [min–max] |"
    );
    for other in &schemes {
        let _ = write!(s, " × {other} (1) |");
    }
    let _ = writeln!(
        s,
        "\n|---|---|---|---|---|---|{}",
        "---|".repeat(schemes.len())
    );
    for r in &t.rows {
        let _ = write!(
            s,
            "| {} | {} | {} | {} | {} | {} [{}–{}] |",
            r.surface,
            r.scheme,
            ms(r.build_s),
            ms(r.weights_s),
            ms(r.update_s),
            ms(r.total_s),
            ms(r.total_range_s.0),
            ms(r.total_range_s.1)
        );
        for other in &schemes {
            let cell = if *other == r.scheme {
                "1".to_string()
            } else {
                t.ratio(&r.surface, &r.scheme, other)
                    .map_or_else(|| "–".into(), |x| format!("{x:.2}"))
            };
            let _ = write!(s, " {cell} |");
        }
        let _ = writeln!(s);
    }
    let _ = writeln!(s);
    if schemes.contains(&"cotangent") {
        let mut surfaces: Vec<&str> = Vec::new();
        for r in &t.rows {
            if !surfaces.contains(&r.surface.as_str()) {
                surfaces.push(&r.surface);
            }
        }
        let others: Vec<&str> = schemes
            .iter()
            .copied()
            .filter(|x| *x != "cotangent")
            .collect();
        let parts: Vec<String> = surfaces
            .iter()
            .map(|surface| {
                let ratios: Vec<String> = others
                    .iter()
                    .filter_map(|o| {
                        t.ratio(surface, "cotangent", o)
                            .map(|x| format!("{x:.2}× {o}"))
                    })
                    .collect();
                format!("{surface} {}", ratios.join(" and "))
            })
            .collect();
        let _ = writeln!(
            s,
            "Cotangent weights against the other schemes, per iteration (the paper: about 20× on the F-lens, 200× on the sphere and 10× on the block): {}.\n",
            parts.join("; ")
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(&[]), None);
        assert_eq!(median(&[1.0, f64::NAN]), None);
        // One outlier does not move the median.
        assert_eq!(median(&[1.0, 1.1, 0.9, 100.0, 1.0]), Some(1.0));
    }

    #[test]
    fn cpu_model_is_read_from_cpuinfo() {
        let text = "processor\t: 0\nvendor_id\t: X\nmodel name\t: Some  CPU @ 2.0GHz\n\nprocessor\t: 1\nmodel name\t: Other\n";
        assert_eq!(cpu_model(text).as_deref(), Some("Some CPU @ 2.0GHz"));
        assert_eq!(cpu_model("processor : 0\n"), None);
    }

    #[test]
    fn git_commit_follows_a_symbolic_ref_and_packed_refs() {
        let dir = tempfile::tempdir().unwrap();
        let git = dir.path().join(".git");
        std::fs::create_dir_all(git.join("refs/heads")).unwrap();
        let hash = "0123456789abcdef0123456789abcdef01234567";
        std::fs::write(git.join("HEAD"), "ref: refs/heads/main\n").unwrap();
        std::fs::write(git.join("refs/heads/main"), format!("{hash}\n")).unwrap();
        let sub = dir.path().join("a/b");
        std::fs::create_dir_all(&sub).unwrap();
        assert_eq!(git_commit(&sub).as_deref(), Some("0123456789ab"));
        std::fs::remove_file(git.join("refs/heads/main")).unwrap();
        std::fs::write(
            git.join("packed-refs"),
            format!("# pack-refs\n{hash} refs/heads/main\n"),
        )
        .unwrap();
        assert_eq!(git_commit(&sub).as_deref(), Some("0123456789ab"));
        std::fs::write(git.join("HEAD"), "garbage\n").unwrap();
        assert_eq!(git_commit(&sub), None);
    }

    #[test]
    fn timing_section_lists_every_scheme_against_the_others() {
        let row = |scheme: &str, total_s| SchemeTiming {
            surface: "sphere".into(),
            scheme: scheme.into(),
            build_s: 2.0 * total_s,
            weights_s: 0.25 * total_s,
            update_s: 0.75 * total_s,
            total_s,
            total_range_s: (total_s, 1.5 * total_s),
        };
        let t = Timings {
            machine: MachineInfo {
                cpu: "Test CPU".into(),
                os: "linux x86_64".into(),
                threads: 2,
                commit: "0123456789ab".into(),
                load: Some(3.5),
            },
            repeats: 7,
            iterations: 10,
            rows: vec![
                row("uniform", 1e-3),
                row("distance", 2e-3),
                row("cotangent", 4e-3),
            ],
        };
        let mut s = String::new();
        timing_section(&mut s, &t);
        assert!(s.contains("Test CPU"));
        assert!(s.contains("commit 0123456789ab"));
        assert!(s.contains("load average 3.50 on 2 threads: other processes shared the machine"));
        assert!(s.contains("| sphere | cotangent | 8.000 | 1.000 | 3.000 | 4.000 [4.000–6.000] | 4.00 | 2.00 | 1 |"), "{s}");
        assert!(s.contains("sphere 4.00× uniform and 2.00× distance"));
    }

    #[test]
    fn ratio_needs_both_schemes() {
        let row = |scheme: &str, total_s| SchemeTiming {
            surface: "s".into(),
            scheme: scheme.into(),
            build_s: 0.0,
            weights_s: 0.0,
            update_s: total_s,
            total_s,
            total_range_s: (total_s, total_s),
        };
        let t = Timings {
            machine: machine_info(),
            repeats: 1,
            iterations: 1,
            rows: vec![row("a", 2.0), row("b", 4.0), row("z", 0.0)],
        };
        assert_eq!(t.ratio("s", "b", "a"), Some(2.0));
        assert_eq!(t.ratio("s", "a", "z"), None);
        assert_eq!(t.ratio("s", "a", "missing"), None);
    }
}
