//! Every areal parameter of a residual in one call, as `beltrami residual` reports them:
//! the height and hybrid parameters, the material-ratio and stratified (Sk) families,
//! the volume parameters, Sxp, requested points of the material-ratio curve, and the
//! spatial parameters on the residual resampled onto a grid.

use std::str::FromStr;

use beltrami_halfedge::geometry::Geometry;

use super::areal::{ArealOptions, ArealParameters, Datum, areal_parameters};
use super::form::Form;
use super::grid::{ResampleOptions, resample_to_grid};
use super::material::{MaterialRatioCurve, StratifiedParameters, VolumeParameters};
use super::spatial::{SpatialOptions, spatial_parameters};
use crate::MetricsError;
use crate::fits::MAX_POLYNOMIAL_DEGREE;

/// The material ratios, in %, between which Sxp is the height difference (ISO 25178-2
/// §4.4.5 defaults).
pub const SXP_RATIOS: (f64, f64) = (2.5, 50.0);

/// The material ratios, in %, of the volume parameters Vmp, Vmc, Vvc, Vvv (ISO 25178-3
/// defaults).
pub const VOLUME_RATIOS: (f64, f64) = (10.0, 80.0);

/// What [`surface_texture`] computes besides the fixed parameters.
///
/// # Examples
/// ```
/// use beltrami_metrics::residual::{Datum, TextureOptions};
/// let options = TextureOptions::default()
///     .datum(Datum::Mean)
///     .smc_ratios(vec![10.0, 50.0]);
/// assert_eq!(options.areal.datum, Datum::Mean);
/// ```
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct TextureOptions {
    /// The datum and the quadrature of the height parameters.
    pub areal: ArealOptions,
    /// Heights (from the datum, in length units) at which to read the material ratio
    /// Smr(c).
    pub smr_heights: Vec<f64>,
    /// Material ratios (in %, 0 to 100) at which to read the height Smc(mr).
    pub smc_ratios: Vec<f64>,
    /// The autocorrelation threshold of Sal and Str.
    pub spatial: SpatialOptions,
    /// How the residual is resampled onto a grid for the spatial parameters.
    pub resample: ResampleOptions,
}

impl TextureOptions {
    /// Sets the datum heights are measured from ([`ArealOptions::datum`]).
    #[must_use]
    pub fn datum(mut self, datum: Datum) -> Self {
        self.areal.datum = datum;
        self
    }

    /// Sets [`areal`](Self::areal).
    #[must_use]
    pub fn areal(mut self, areal: ArealOptions) -> Self {
        self.areal = areal;
        self
    }

    /// Sets [`smr_heights`](Self::smr_heights).
    #[must_use]
    pub fn smr_heights(mut self, heights: Vec<f64>) -> Self {
        self.smr_heights = heights;
        self
    }

    /// Sets [`smc_ratios`](Self::smc_ratios).
    #[must_use]
    pub fn smc_ratios(mut self, ratios: Vec<f64>) -> Self {
        self.smc_ratios = ratios;
        self
    }

    /// Sets [`spatial`](Self::spatial).
    #[must_use]
    pub fn spatial(mut self, spatial: SpatialOptions) -> Self {
        self.spatial = spatial;
        self
    }

    /// Sets [`resample`](Self::resample).
    #[must_use]
    pub fn resample(mut self, resample: ResampleOptions) -> Self {
        self.resample = resample;
        self
    }
}

/// The spatial parameters and the grid they were computed on; `unavailable` says why
/// they are missing when they are.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SpatialSummary {
    /// The grid spacing, in length units; `None` when the residual could not be
    /// resampled.
    pub step: Option<f64>,
    /// Grid points along the plane's first axis.
    pub nx: Option<usize>,
    /// Grid points along its second axis.
    pub ny: Option<usize>,
    /// Grid points with a height.
    pub valid_points: Option<usize>,
    /// The autocorrelation threshold `s` used.
    pub threshold: f64,
    /// Whether the autocorrelation fell to `s` in every direction (else Str is an upper
    /// bound).
    pub decays_in_every_direction: bool,
    /// Why Sal, Str and Std are missing, if they are.
    pub unavailable: Option<String>,
    /// Sal, the autocorrelation length, in length units.
    pub sal: Option<f64>,
    /// Str, the texture aspect ratio.
    pub str: Option<f64>,
    /// Std, the texture direction, in degrees.
    pub std: Option<f64>,
}

/// Everything [`surface_texture`] computes.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct SurfaceTexture {
    /// The height and hybrid parameters (Sa … Sdr, the mean and the area).
    pub areal: ArealParameters,
    /// The Sk family.
    pub stratified: StratifiedParameters,
    /// Vmp, Vmc, Vvc, Vvv at [`VOLUME_RATIOS`].
    pub volume: VolumeParameters,
    /// Sxp between [`SXP_RATIOS`].
    pub sxp: f64,
    /// `(c, Smr(c))` for each of [`TextureOptions::smr_heights`], the ratio in %.
    pub smr: Vec<(f64, f64)>,
    /// `(Smc(mr), mr)` for each of [`TextureOptions::smc_ratios`].
    pub smc: Vec<(f64, f64)>,
    /// Sal, Str, Std and their grid.
    pub spatial: SpatialSummary,
    /// The residual from the datum, one height per vertex (what the spatial parameters
    /// were computed on): the residual itself, or minus its mean with [`Datum::Mean`].
    pub heights: Vec<f64>,
}

/// Every areal parameter of `residual` (one height per vertex of `geometry`, the
/// reference surface): see the functions it calls ([`areal_parameters`],
/// [`MaterialRatioCurve`], [`resample_to_grid`], [`spatial_parameters`]) and
/// docs/metrics.md for the definitions. Heights are in the positions' length unit.
///
/// The spatial parameters are computed on the residual minus the datum, resampled
/// onto a grid in the reference surface's best-fit plane; when the surface is no height
/// field over that plane (it folds over it) or nothing can be resampled, they are `None`
/// and [`SpatialSummary::unavailable`] says why, while everything else is still
/// returned.
///
/// # Errors
/// Those of [`areal_parameters`] and [`MaterialRatioCurve::from_mesh`] (a bad residual
/// or mesh); [`MetricsError::InvalidParameter`] for a material ratio outside 0 to 100 in
/// `smc_ratios`.
///
/// # Examples
/// ```
/// use beltrami_halfedge::geometry::Geometry;
/// use beltrami_halfedge::primitives;
/// use beltrami_metrics::residual::{TextureOptions, surface_texture};
///
/// let grid = primitives::grid(40, 40);
/// let mesh = grid.mesh()?;
/// let z: Vec<f64> = grid.positions.iter().map(|p| (p.x / 3.0).sin()).collect();
/// let t = surface_texture(&Geometry::new(&mesh, &grid.positions)?, &z, &TextureOptions::default())?;
/// assert!(t.areal.sq > 0.6 && t.areal.sq < 0.8); // a sine's RMS is 1/√2
/// assert!(t.spatial.sal.is_some());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn surface_texture(
    geometry: &Geometry<'_>,
    residual: &[f64],
    options: &TextureOptions,
) -> Result<SurfaceTexture, MetricsError> {
    let areal = areal_parameters(geometry, residual, &options.areal)?;
    let curve = MaterialRatioCurve::from_mesh(geometry, residual, &options.areal)?;
    let stratified = curve.stratified();
    let volume = curve.volume(VOLUME_RATIOS.0, VOLUME_RATIOS.1)?;
    let sxp = curve.sxp(SXP_RATIOS.0, SXP_RATIOS.1)?;
    let smr = options
        .smr_heights
        .iter()
        .map(|&c| (c, curve.smr(c)))
        .collect();
    let smc = options
        .smc_ratios
        .iter()
        .map(|&mr| Ok((curve.smc(mr)?, mr)))
        .collect::<Result<Vec<_>, MetricsError>>()?;
    // The autocorrelation removes the grid's mean anyway; the shift keeps the resampled
    // heights those of the datum.
    let shift = if options.areal.datum == Datum::Mean {
        areal.mean
    } else {
        0.0
    };
    let heights: Vec<f64> = residual.iter().map(|r| r - shift).collect();
    let threshold = options.spatial.threshold;
    // A grid with too few points inside the surface (pieces far apart, small against
    // their spread) is as unavailable as one that cannot be made.
    let spatial = match resample_to_grid(geometry, &heights, &options.resample)
        .and_then(|grid| Ok((spatial_parameters(&grid.grid, &options.spatial)?, grid)))
    {
        Ok((p, grid)) => {
            SpatialSummary {
                step: Some(grid.step),
                nx: Some(grid.grid.nx()),
                ny: Some(grid.grid.ny()),
                valid_points: Some(grid.grid.valid_count()),
                threshold,
                decays_in_every_direction: p.decays_in_every_direction,
                unavailable: p.sal.is_none().then(|| {
                    "the autocorrelation does not fall to s within the sampled lags, or the heights are constant".to_string()
                }),
                sal: p.sal,
                str: p.str,
                std: p.std,
            }
        }
        Err(e @ (MetricsError::NotAHeightField { .. } | MetricsError::Empty { .. })) => {
            SpatialSummary {
                step: None,
                nx: None,
                ny: None,
                valid_points: None,
                threshold,
                decays_in_every_direction: false,
                unavailable: Some(e.to_string()),
                sal: None,
                str: None,
                std: None,
            }
        }
        Err(e) => return Err(e),
    };
    Ok(SurfaceTexture {
        areal,
        stratified,
        volume,
        sxp,
        smr,
        smc,
        spatial,
        heights,
    })
}

impl FromStr for Form {
    type Err = String;

    /// A form by the name the command line uses: `plane`, `poly:N` (N = 1 to
    /// [`MAX_POLYNOMIAL_DEGREE`]), `sphere` or `cylinder`. The error is a sentence for
    /// the user.
    fn from_str(text: &str) -> Result<Self, String> {
        match text {
            "plane" => Ok(Form::Plane),
            "sphere" => Ok(Form::Sphere),
            "cylinder" => Ok(Form::Cylinder),
            _ => {
                let degree = text
                    .strip_prefix("poly:")
                    .ok_or_else(|| "expected plane, poly:N, sphere or cylinder".to_string())?;
                match degree.parse::<u32>() {
                    Ok(degree) if (1..=MAX_POLYNOMIAL_DEGREE).contains(&degree) => {
                        Ok(Form::Polynomial { degree })
                    }
                    _ => Err(format!(
                        "the degree of poly:N is a whole number from 1 to {MAX_POLYNOMIAL_DEGREE}, got '{degree}'"
                    )),
                }
            }
        }
    }
}
