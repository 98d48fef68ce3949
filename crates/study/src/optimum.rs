//! The RMS-optimal iteration count: per surface and scheme, the number of iterations
//! after which the RMS distance to the clean surface is smallest.
//!
//! Explicit diffusion first removes the noise (the RMS falls) and then shrinks the
//! surface (the RMS grows again), so the RMS has a minimum. The study observes every
//! iteration from 0 to [`EARLY_ITERATIONS`](crate::EARLY_ITERATIONS) and then the
//! configured ones; the optimum is the smallest RMS over all of them, per seed.

use serde::Serialize;

use crate::findings::Spread;
use crate::run::RmsPoint;

/// The RMS-optimal iteration count of one scheme on one surface, over the seeds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Optimum {
    /// The surface's name.
    pub surface: String,
    /// The scheme's name.
    pub scheme: String,
    /// The smallest and largest optimal iteration count over the seeds.
    pub iterations: (usize, usize),
    /// The RMS at the optimum, over the seeds (surface's unit).
    pub rms: Spread,
    /// The RMS of the noisy input, over the seeds.
    pub input_rms: Spread,
    /// Whether the optimum is at the last observed iteration of a seed (the minimum
    /// may lie beyond the observed range).
    pub at_last_observed: bool,
}

/// The optimum of every surface and scheme of `curve`, in the order of first
/// appearance. `None` entries are skipped: a scheme needs at least one point per seed.
#[must_use]
pub fn optima(curve: &[RmsPoint]) -> Vec<Optimum> {
    let mut keys: Vec<(&str, &str)> = Vec::new();
    for p in curve.iter().filter(|p| p.scheme != "input") {
        if !keys.contains(&(p.surface.as_str(), p.scheme.as_str())) {
            keys.push((&p.surface, &p.scheme));
        }
    }
    let mut out = Vec::new();
    for (surface, scheme) in keys {
        let mut seeds: Vec<u64> = curve
            .iter()
            .filter(|p| p.surface == surface && p.scheme == scheme)
            .map(|p| p.seed)
            .collect();
        seeds.sort_unstable();
        seeds.dedup();
        let mut best_it = Vec::new();
        let mut best_rms = Vec::new();
        let mut inputs = Vec::new();
        let mut at_last = false;
        for seed in seeds {
            let points: Vec<&RmsPoint> = curve
                .iter()
                .filter(|p| p.surface == surface && p.seed == seed)
                .filter(|p| p.scheme == scheme)
                .collect();
            let Some(best) = points
                .iter()
                .copied()
                .reduce(|a, b| if b.rms < a.rms { b } else { a })
            else {
                continue;
            };
            let last = points.iter().map(|p| p.iteration).max().unwrap_or(0);
            at_last |= best.iteration == last;
            best_it.push(best.iteration);
            best_rms.push(best.rms);
            if let Some(input) = curve
                .iter()
                .find(|p| p.surface == surface && p.seed == seed && p.scheme == "input")
            {
                inputs.push(input.rms);
            }
        }
        let (Some(rms), Some(input_rms)) = (Spread::of(&best_rms), Spread::of(&inputs)) else {
            continue;
        };
        out.push(Optimum {
            surface: surface.to_string(),
            scheme: scheme.to_string(),
            iterations: (
                best_it.iter().copied().min().unwrap_or(0),
                best_it.iter().copied().max().unwrap_or(0),
            ),
            rms,
            input_rms,
            at_last_observed: at_last,
        });
    }
    out
}

impl Optimum {
    /// The optimal iteration count as text: `3` or `3–5` over the seeds.
    #[must_use]
    pub fn iterations_text(&self) -> String {
        if self.iterations.0 == self.iterations.1 {
            self.iterations.0.to_string()
        } else {
            format!("{}–{}", self.iterations.0, self.iterations.1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(scheme: &str, seed: u64, iteration: usize, rms: f64) -> RmsPoint {
        RmsPoint {
            surface: "s".into(),
            scheme: scheme.into(),
            seed,
            iteration,
            rms,
        }
    }

    #[test]
    fn the_optimum_is_the_smallest_rms_per_seed() {
        let curve = vec![
            p("input", 1, 0, 1.0),
            p("a", 1, 1, 0.5),
            p("a", 1, 3, 0.2),
            p("a", 1, 10, 0.4),
            p("input", 2, 0, 1.1),
            p("a", 2, 1, 0.6),
            p("a", 2, 5, 0.3),
            p("a", 2, 10, 0.35),
        ];
        let o = optima(&curve);
        assert_eq!(o.len(), 1);
        assert_eq!(o[0].iterations, (3, 5));
        assert_eq!(o[0].iterations_text(), "3–5");
        assert!((o[0].rms.mean - 0.25).abs() < 1e-12);
        assert!((o[0].input_rms.mean - 1.05).abs() < 1e-12);
        assert!(!o[0].at_last_observed);
        let o = optima(&[p("input", 1, 0, 1.0), p("a", 1, 1, 0.9), p("a", 1, 2, 0.8)]);
        assert!(o[0].at_last_observed);
    }
}
