//! Shrinkage counter-measures measured beside plain diffusion: Taubin λ|μ, the HC
//! push-back and the volume-preserving rescale, with one weight scheme, on the surfaces
//! where shrinkage shows (sphere: radius; block: volume; F-lens: boundary distortion).

use beltrami_smooth::Method;
use beltrami_surfaces::SurfaceKind;

/// One way of smoothing that the study compares with plain diffusion.
#[derive(Clone, Debug, PartialEq)]
pub struct Countermeasure {
    /// A short label for tables and CSV (`"plain"`, `"taubin"`, `"hc"`, `"volume"`).
    pub label: String,
    /// The step λ of the (first) sweep.
    pub lambda: f64,
    /// The method.
    pub method: Method,
    /// Whether the volume-preserving rescale runs after each iteration (closed
    /// surfaces only; the counter-measure is skipped on open ones).
    pub preserve_volume: bool,
    /// Whether the weights are computed once, from the noisy input, instead of by the
    /// study's policy (recomputing position-dependent weights every iteration folds the
    /// block's sharp edges and the F-lens's free boundary with cotangent weights).
    pub weights_once: bool,
}

impl Countermeasure {
    /// The default set: plain diffusion with the study's λ; Taubin with λ = 0.6307,
    /// μ = −0.6732 (pass band k_PB = 0.1, the values of Desbrun et al. 1999; the
    /// study's λ = 0.8 admits no stable μ with that pass band); HC with α = 0.1,
    /// β = 0.6 and the study's λ; plain diffusion with the volume rescale; plain
    /// diffusion with weights computed once (`"once"`).
    #[must_use]
    pub fn defaults(lambda: f64) -> Vec<Self> {
        vec![
            Self {
                label: "plain".into(),
                lambda,
                method: Method::Laplacian,
                preserve_volume: false,
                weights_once: false,
            },
            Self {
                label: "taubin".into(),
                lambda: 0.6307,
                method: Method::Taubin { mu: -0.6732 },
                preserve_volume: false,
                weights_once: false,
            },
            Self {
                label: "hc".into(),
                lambda,
                method: Method::hc(),
                preserve_volume: false,
                weights_once: false,
            },
            Self {
                label: "volume".into(),
                lambda,
                method: Method::Laplacian,
                preserve_volume: true,
                weights_once: false,
            },
            Self {
                label: "once".into(),
                lambda,
                method: Method::Laplacian,
                preserve_volume: false,
                weights_once: true,
            },
        ]
    }

    /// Whether this counter-measure applies to a surface that is closed or not.
    #[must_use]
    pub fn applies(&self, closed: bool) -> bool {
        closed || !self.preserve_volume
    }
}

/// The surfaces on which the counter-measures are measured, and the metric that shows
/// each one's shrinkage.
#[must_use]
pub fn countermeasure_surface(kind: SurfaceKind) -> bool {
    matches!(
        kind,
        SurfaceKind::Sphere | SurfaceKind::Block | SurfaceKind::FLens
    )
}
