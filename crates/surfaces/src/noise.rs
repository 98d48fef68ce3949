//! Seeded Gaussian noise along vertex normals, identical on every platform.

use beltrami_halfedge::geometry::{Geometry, NormalWeighting};
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};

use crate::error::SurfaceError;

/// A seeded generator of uniform and standard normal numbers whose output is the same
/// on every platform: ChaCha8 (a portable stream cipher) for the bits, the Marsaglia
/// polar method for normals, with the logarithm from the pure-Rust `libm` crate rather
/// than the platform's C library (whose last bits may differ between systems).
///
/// # Examples
/// ```
/// use beltrami_surfaces::NormalRng;
/// let mut a = NormalRng::new(7);
/// let mut b = NormalRng::new(7);
/// assert_eq!(a.next_normal().to_bits(), b.next_normal().to_bits());
/// ```
#[derive(Clone, Debug)]
pub struct NormalRng {
    rng: ChaCha8Rng,
    spare: Option<f64>,
}

impl NormalRng {
    /// A generator for `seed`.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self {
            rng: ChaCha8Rng::seed_from_u64(seed),
            spare: None,
        }
    }

    /// A uniform number in [0, 1) with 53 random bits.
    pub fn next_uniform(&mut self) -> f64 {
        (self.rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A standard normal number (mean 0, variance 1).
    pub fn next_normal(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        loop {
            let u = 2.0 * self.next_uniform() - 1.0;
            let v = 2.0 * self.next_uniform() - 1.0;
            let s = u * u + v * v;
            if s > 0.0 && s < 1.0 {
                let f = (-2.0 * libm::log(s) / s).sqrt();
                self.spare = Some(v * f);
                return u * f;
            }
        }
    }
}

/// The standard deviation of the noise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum NoiseLevel {
    /// σ in the mesh's length unit.
    Absolute(f64),
    /// σ as a multiple of the mean edge length (the convention of mesh-denoising
    /// benchmarks: levels 0.2 … 0.7).
    RelativeToMeanEdge(f64),
}

/// Moves every vertex along its unit vertex normal (area-weighted face normals) by a
/// Gaussian amount of standard deviation σ: `x_i + σ z_i n_i`, with `z_i` the i-th
/// number of [`NormalRng::new(seed)`](NormalRng). Boundary vertices are moved too.
/// Vertices without a normal (isolated, or all faces degenerate) stay put but still
/// consume their number, so vertex `i` always gets `z_i`.
///
/// Returns the noisy positions and σ in length units.
///
/// # Errors
/// [`SurfaceError::InvalidNoise`] for a negative or non-finite level, or one so large
/// that a noisy position overflows (σ near the largest number);
/// [`SurfaceError::Topology`] when the positions do not match the mesh.
///
/// # References
/// The noise model of the mesh-denoising benchmarks (Gaussian along vertex normals,
/// σ relative to the mean edge length), e.g. Zhang et al., "Guided mesh normal
/// filtering", 2015.
pub fn add_normal_noise(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    level: NoiseLevel,
    seed: u64,
) -> Result<(Vec<DVec3>, f64), SurfaceError> {
    let geometry = Geometry::new(mesh, positions)?;
    let sigma = match level {
        NoiseLevel::Absolute(s) => s,
        NoiseLevel::RelativeToMeanEdge(r) => r * geometry.mean_edge_length().unwrap_or(0.0),
    };
    if !(sigma >= 0.0 && sigma.is_finite()) {
        return Err(SurfaceError::InvalidNoise { sigma });
    }
    let normals = geometry.vertex_normals(NormalWeighting::Area);
    let mut rng = NormalRng::new(seed);
    let noisy: Vec<DVec3> = positions
        .iter()
        .zip(normals.as_slice())
        .map(|(&p, &n)| p + n * (sigma * rng.next_normal()))
        .collect();
    if !noisy.iter().all(|p| p.is_finite()) {
        return Err(SurfaceError::InvalidNoise { sigma });
    }
    Ok((noisy, sigma))
}
