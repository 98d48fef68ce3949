//! What a study runs.

use std::sync::Arc;

use beltrami_smooth::{Boundary, WeightUpdate};
use beltrami_surfaces::{NoiseLevel, Size, SurfaceKind};
use beltrami_weights::{NegativeWeights, Normalization, WeightRegistry, WeightScheme};

use crate::countermeasures::Countermeasure;
use crate::error::StudyError;

/// The parameters of a study: which surfaces, schemes and iteration counts, and how
/// every run smooths. The defaults reproduce the paper's set-up.
///
/// # Examples
/// ```
/// use beltrami_study::StudyConfig;
/// use beltrami_surfaces::Size;
/// use beltrami_weights::WeightRegistry;
/// let config = StudyConfig::paper(&WeightRegistry::with_builtins())
///     .size(Size::Small)
///     .iterations(vec![2, 5, 10])
///     .seeds(1);
/// assert_eq!(config.max_iterations(), 10);
/// assert_eq!(config.lambda, 0.8);
/// config.validate()?;
/// # Ok::<(), beltrami_study::StudyError>(())
/// ```
#[derive(Clone)]
#[non_exhaustive]
pub struct StudyConfig {
    /// The surfaces, in order (default: F-lens, sphere, block, golf ball).
    pub surfaces: Vec<SurfaceKind>,
    /// Paper-sized surfaces or small variants (for tests and quick looks).
    pub size: Size,
    /// The schemes, in order (default: every scheme of the registry, so a registered
    /// plug-in scheme appears without further code).
    pub schemes: Vec<Arc<dyn WeightScheme>>,
    /// The iteration counts at which each run is observed, ascending (default: 10, 20,
    /// …, 100 and 200, the paper's). One run per surface and scheme goes to the largest.
    pub iterations: Vec<usize>,
    /// The step λ (default 0.8, the paper's).
    pub lambda: f64,
    /// The noise added to each clean surface (default σ = 0.2 × mean edge length).
    pub noise: NoiseLevel,
    /// The seed of the noise (default 1): of the first input, whose runs give the plots,
    /// renders, counter-measures and comparisons.
    pub seed: u64,
    /// The number of noise seeds (`seed`, `seed + 1`, …; default [`DEFAULT_SEEDS`]).
    /// The paper's schemes (see [`seed_schemes`](Self::seed_schemes)) run on each
    /// seed's input; tables give the mean and the range over the seeds, and the verdicts
    /// take the range into account.
    pub seeds: usize,
    /// The boundary mode of every run (default free: the paper's F-lens loses its
    /// outline, which only a free boundary does).
    pub boundary: Boundary,
    /// The weight-update policy (default every iteration, as the paper times).
    pub update: WeightUpdate,
    /// The negative-weight policy (default keep).
    pub negative: NegativeWeights,
    /// The row normalisation (default the weight sum, paper Eq. 2). Dividing by the
    /// vertex area (paper Eq. 6) makes λ a time in length², stable only below a limit
    /// that follows each mesh's unit and density; the study then reads
    /// [`lambda`](Self::lambda) (and a Taubin μ) as the fraction of each run's largest
    /// stable explicit step.
    pub normalization: Normalization,
    /// Shrinkage counter-measures run beside plain diffusion on the sphere, the block
    /// and the F-lens (empty: none), with [`countermeasure_scheme`](Self::countermeasure_scheme).
    pub countermeasures: Vec<Countermeasure>,
    /// The weight scheme of the counter-measure runs (`None`: skip them).
    pub countermeasure_scheme: Option<Arc<dyn WeightScheme>>,
    /// An edge-preserving scheme and the reference it is compared with on the block at
    /// equal smoothness of the flat sides (see
    /// [`edge_preservation`](crate::edge_preservation)); `None`, or no block among the
    /// surfaces: skipped.
    pub edge_comparison: Option<(Arc<dyn WeightScheme>, Arc<dyn WeightScheme>)>,
    /// Remeshing before smoothing (the paper's MeshLab step): each clean surface is
    /// remeshed with these options, gets noise of the same level and first seed, and
    /// the cotangent scheme smooths it beside the original input (see
    /// [`RemeshComparison`](crate::RemeshComparison)); `None`, or no `cotangent` among
    /// the schemes: skipped. Default: [`default_remesh`](crate::default_remesh).
    pub remesh: Option<beltrami_algorithms::RemeshOptions>,
    /// Time every scheme apart from the study's runs: medians of repeated short runs,
    /// weights apart from updates (see [`Timings`](crate::Timings)). Default `true`.
    pub timing: bool,
    /// Run the study of a given surface (`study --input`'s machinery,
    /// [`run_scan`](crate::run_scan)) on the first seed's noisy block against the clean
    /// block, with the paper's schemes, as a worked example (report section and the
    /// `scan/` directory); skipped without the block. Default `true`.
    pub scan_example: bool,
}

impl std::fmt::Debug for StudyConfig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StudyConfig")
            .field("surfaces", &self.surfaces)
            .field("size", &self.size)
            .field(
                "schemes",
                &self.schemes.iter().map(|s| s.name()).collect::<Vec<_>>(),
            )
            .field("iterations", &self.iterations)
            .field("lambda", &self.lambda)
            .field("noise", &self.noise)
            .field("seed", &self.seed)
            .field("seeds", &self.seeds)
            .field("boundary", &self.boundary)
            .field("update", &self.update)
            .field("negative", &self.negative)
            .field("normalization", &self.normalization)
            .field("countermeasures", &self.countermeasures)
            .field(
                "countermeasure_scheme",
                &self
                    .countermeasure_scheme
                    .as_ref()
                    .map(|s| s.name().to_string()),
            )
            .field("remesh", &self.remesh)
            .field("timing", &self.timing)
            .field("scan_example", &self.scan_example)
            .finish()
    }
}

/// The paper's three weight schemes, by registry name.
pub const PAPER_SCHEMES: [&str; 3] = ["uniform", "distance", "cotangent"];

/// The largest iteration count a study observes: a million (the paper's longest run is
/// 200; each observed count keeps a row per surface and scheme).
pub const MAX_STUDY_ITERATIONS: usize = 1_000_000;

/// The largest relative noise level a study adds: σ of 10 mean edge lengths (the
/// paper's is 0.2, mesh-denoising benchmarks go to 0.7); beyond it the noisy surface
/// has nothing left of the clean one.
pub const MAX_RELATIVE_NOISE: f64 = 10.0;

/// The default number of noise seeds: 3, chosen so that the default study still takes
/// about a minute on two cores (each further seed adds the scheme runs and their
/// metrics, about a third of the study's time).
pub const DEFAULT_SEEDS: usize = 3;

/// The paper's iteration counts: 10, 20, …, 100 and 200.
#[must_use]
pub fn paper_iterations() -> Vec<usize> {
    let mut it: Vec<usize> = (1..=10).map(|k| 10 * k).collect();
    it.push(200);
    it
}

impl Default for StudyConfig {
    /// The paper's set-up with the built-in schemes
    /// ([`WeightRegistry::with_builtins`]: uniform, distance, cotangent), so without an
    /// edge comparison (which needs a `bilateral` scheme).
    fn default() -> Self {
        Self::paper(&WeightRegistry::with_builtins())
    }
}

impl StudyConfig {
    /// The paper's set-up with every scheme of `registry`.
    #[must_use]
    pub fn paper(registry: &WeightRegistry) -> Self {
        Self {
            surfaces: SurfaceKind::ALL.to_vec(),
            size: Size::Paper,
            schemes: registry.iter().cloned().collect(),
            iterations: paper_iterations(),
            lambda: 0.8,
            noise: NoiseLevel::RelativeToMeanEdge(0.2),
            seed: 1,
            seeds: DEFAULT_SEEDS,
            boundary: Boundary::Free,
            update: WeightUpdate::Every,
            negative: NegativeWeights::Keep,
            normalization: Normalization::WeightSum,
            countermeasures: Countermeasure::defaults(0.8),
            countermeasure_scheme: registry.get("cotangent").ok(),
            edge_comparison: registry
                .get("bilateral")
                .ok()
                .zip(registry.get("cotangent").ok()),
            remesh: Some(crate::remeshing::default_remesh()),
            timing: true,
            scan_example: true,
        }
    }

    /// Sets the surfaces, in order (see [`surfaces`](Self::surfaces)).
    #[must_use]
    pub fn surfaces(mut self, surfaces: Vec<SurfaceKind>) -> Self {
        self.surfaces = surfaces;
        self
    }

    /// Sets paper-sized surfaces or small variants (see [`size`](Self::size)).
    #[must_use]
    pub fn size(mut self, size: Size) -> Self {
        self.size = size;
        self
    }

    /// Sets the schemes, in order (see [`schemes`](Self::schemes)).
    #[must_use]
    pub fn schemes(mut self, schemes: Vec<Arc<dyn WeightScheme>>) -> Self {
        self.schemes = schemes;
        self
    }

    /// Sets the iteration counts at which each run is observed, ascending (see [`iterations`](Self::iterations)).
    #[must_use]
    pub fn iterations(mut self, iterations: Vec<usize>) -> Self {
        self.iterations = iterations;
        self
    }

    /// Sets the step λ (see [`lambda`](Self::lambda)).
    #[must_use]
    pub fn lambda(mut self, lambda: f64) -> Self {
        self.lambda = lambda;
        self
    }

    /// Sets the noise added to each clean surface (see [`noise`](Self::noise)).
    #[must_use]
    pub fn noise(mut self, noise: NoiseLevel) -> Self {
        self.noise = noise;
        self
    }

    /// Sets the seed of the first input's noise (see [`seed`](Self::seed)).
    #[must_use]
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Sets the number of noise seeds (see [`seeds`](Self::seeds)).
    #[must_use]
    pub fn seeds(mut self, seeds: usize) -> Self {
        self.seeds = seeds;
        self
    }

    /// Sets the boundary mode of every run (see [`boundary`](Self::boundary)).
    #[must_use]
    pub fn boundary(mut self, boundary: Boundary) -> Self {
        self.boundary = boundary;
        self
    }

    /// Sets the weight-update policy (see [`update`](Self::update)).
    #[must_use]
    pub fn update(mut self, update: WeightUpdate) -> Self {
        self.update = update;
        self
    }

    /// Sets the negative-weight policy (see [`negative`](Self::negative)).
    #[must_use]
    pub fn negative(mut self, negative: NegativeWeights) -> Self {
        self.negative = negative;
        self
    }

    /// Sets the row normalisation (see [`normalization`](Self::normalization)).
    #[must_use]
    pub fn normalization(mut self, normalization: Normalization) -> Self {
        self.normalization = normalization;
        self
    }

    /// Sets the shrinkage counter-measures (empty: none) (see [`countermeasures`](Self::countermeasures)).
    #[must_use]
    pub fn countermeasures(mut self, countermeasures: Vec<Countermeasure>) -> Self {
        self.countermeasures = countermeasures;
        self
    }

    /// Sets the weight scheme of the counter-measure runs (`None`: skip them) (see [`countermeasure_scheme`](Self::countermeasure_scheme)).
    #[must_use]
    pub fn countermeasure_scheme(
        mut self,
        countermeasure_scheme: Option<Arc<dyn WeightScheme>>,
    ) -> Self {
        self.countermeasure_scheme = countermeasure_scheme;
        self
    }

    /// Sets the edge-preserving scheme and its reference (`None`: skip the comparison) (see [`edge_comparison`](Self::edge_comparison)).
    #[must_use]
    pub fn edge_comparison(
        mut self,
        edge_comparison: Option<(Arc<dyn WeightScheme>, Arc<dyn WeightScheme>)>,
    ) -> Self {
        self.edge_comparison = edge_comparison;
        self
    }

    /// Sets the remeshing before smoothing (`None`: skip it) (see [`remesh`](Self::remesh)).
    #[must_use]
    pub fn remesh(mut self, remesh: Option<beltrami_algorithms::RemeshOptions>) -> Self {
        self.remesh = remesh;
        self
    }

    /// Sets whether every scheme is timed apart from the study's runs (see [`timing`](Self::timing)).
    #[must_use]
    pub fn timing(mut self, timing: bool) -> Self {
        self.timing = timing;
        self
    }

    /// Sets whether the worked example of a given-surface study runs (see [`scan_example`](Self::scan_example)).
    #[must_use]
    pub fn scan_example(mut self, scan_example: bool) -> Self {
        self.scan_example = scan_example;
        self
    }

    /// Checks the configuration: at least one surface and scheme, none given twice,
    /// iteration counts positive, strictly ascending and at most
    /// [`MAX_STUDY_ITERATIONS`], a noise level finite, not negative and (relative) at most
    /// [`MAX_RELATIVE_NOISE`], λ in (0, 1], a remeshing target length positive and
    /// finite.
    ///
    /// # Errors
    /// [`StudyError::Config`] saying what is wrong.
    pub fn validate(&self) -> Result<(), StudyError> {
        if self.surfaces.is_empty() {
            return Err(StudyError::Config("no surface selected".into()));
        }
        if self.schemes.is_empty() {
            return Err(StudyError::Config("no weight scheme selected".into()));
        }
        if self.iterations.is_empty() || self.iterations[0] == 0 {
            return Err(StudyError::Config(
                "iteration counts must be positive".into(),
            ));
        }
        if self.iterations.windows(2).any(|w| w[1] <= w[0]) {
            return Err(StudyError::Config(
                "iteration counts must be strictly ascending".into(),
            ));
        }
        if self.max_iterations() > MAX_STUDY_ITERATIONS {
            return Err(StudyError::Config(format!(
                "iteration counts must be at most {MAX_STUDY_ITERATIONS}, got {} (the paper's longest run is 200 iterations)",
                self.max_iterations()
            )));
        }
        for (i, s) in self.surfaces.iter().enumerate() {
            if self.surfaces[..i].contains(s) {
                return Err(StudyError::Config(format!(
                    "surface '{}' given twice",
                    s.name()
                )));
            }
        }
        for (i, s) in self.schemes.iter().enumerate() {
            if self.schemes[..i].iter().any(|t| t.name() == s.name()) {
                return Err(StudyError::Config(format!(
                    "weight scheme '{}' given twice",
                    s.name()
                )));
            }
        }
        match self.noise {
            NoiseLevel::Absolute(sigma) | NoiseLevel::RelativeToMeanEdge(sigma)
                if !(sigma.is_finite() && sigma >= 0.0) =>
            {
                return Err(StudyError::Config(format!(
                    "the noise level must be finite and not negative, got {}",
                    beltrami_halfedge::exact_number(sigma)
                )));
            }
            NoiseLevel::RelativeToMeanEdge(sigma) if sigma > MAX_RELATIVE_NOISE => {
                return Err(StudyError::Config(format!(
                    "the noise level must be at most {MAX_RELATIVE_NOISE} mean edge lengths (the paper's is 0.2; more leaves nothing of the surface to recover), got {}",
                    beltrami_halfedge::exact_number(sigma)
                )));
            }
            _ => {}
        }
        if self.seeds == 0 {
            return Err(StudyError::Config(
                "the number of noise seeds must be at least 1".into(),
            ));
        }
        if !(self.lambda > 0.0 && self.lambda <= 1.0) {
            return Err(StudyError::Config(format!(
                "lambda must be in (0, 1], got {}",
                beltrami_halfedge::exact_number(self.lambda)
            )));
        }
        if let Some(r) = &self.remesh {
            let length = match r.edge_length {
                beltrami_algorithms::EdgeLength::Absolute(l)
                | beltrami_algorithms::EdgeLength::Relative(l) => Some(l),
                _ => None,
            };
            if length.is_some_and(|l| !(l.is_finite() && l > 0.0)) {
                return Err(StudyError::Config(format!(
                    "the remeshing target edge length must be positive and finite, got {}",
                    beltrami_halfedge::exact_number(length.unwrap_or(f64::NAN))
                )));
            }
        }
        for c in &self.countermeasures {
            if !(c.lambda > 0.0 && c.lambda <= 1.0) {
                return Err(StudyError::Config(format!(
                    "counter-measure '{}': lambda must be in (0, 1], got {}",
                    c.label,
                    beltrami_halfedge::exact_number(c.lambda)
                )));
            }
        }
        Ok(())
    }

    /// The schemes that run on the further noise seeds: the paper's three (uniform,
    /// distance, cotangent) among the configured ones, which the verdicts are about, or
    /// every configured scheme when none of them is. Other schemes (such as the
    /// edge-preserving `bilateral`, which costs many times their time together) run on
    /// the first seed only.
    #[must_use]
    pub fn seed_schemes(&self) -> Vec<Arc<dyn WeightScheme>> {
        let paper: Vec<Arc<dyn WeightScheme>> = self
            .schemes
            .iter()
            .filter(|s| PAPER_SCHEMES.contains(&s.name()))
            .cloned()
            .collect();
        if paper.is_empty() {
            self.schemes.clone()
        } else {
            paper
        }
    }

    /// The largest iteration count (the length of every run).
    #[must_use]
    pub fn max_iterations(&self) -> usize {
        self.iterations.last().copied().unwrap_or(0)
    }
}
