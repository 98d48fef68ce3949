//! The closed-form radius of a sphere under explicit diffusion, per weight scheme.
//!
//! On a sphere of radius r, a neighbour j of vertex i at chord length ℓᵢⱼ lies
//! ℓᵢⱼ²/(2r) below i's tangent plane. With weights normalised by their sum, the umbrella
//! Σⱼ wᵢⱼ (xⱼ − xᵢ) / Σⱼ wᵢⱼ therefore has the inward normal component
//! ⟨ℓ²⟩ᵢ,w / (2r), with the scheme's weighted mean squared edge length
//! ⟨ℓ²⟩ᵢ,w = Σⱼ wᵢⱼ ℓᵢⱼ² / Σⱼ wᵢⱼ; the tangential components cancel on a symmetric ring.
//! One step x ← x + λ L x scales the radius by 1 − λ⟨ℓ²⟩_w/(2r²), and as the sphere
//! shrinks the edges shrink with it (ℓ/r stays), so after n steps
//! r_n = r₀ (1 − λ⟨ℓ²⟩_w/(2r₀²))ⁿ, with ⟨ℓ²⟩_w the vertex average of ⟨ℓ²⟩ᵢ,w on the
//! clean sphere. Uniform weights give the plain mean of ℓ² over each ring, inverse
//! distance weights Σℓ / Σ(1/ℓ), cotangent weights Σ cot·ℓ² / Σ cot; every scheme's
//! weights are evaluated the same way, so a plug-in scheme gets its prediction too.
//! The noise is left out: the prediction is the clean sphere's shrink.

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_weights::{WeightContext, WeightScheme};

use crate::findings::sphere_closed_form;

/// The vertex average of the weighted mean squared edge length
/// ⟨ℓ²⟩ᵢ,w = Σⱼ wᵢⱼ ℓᵢⱼ² / Σⱼ wᵢⱼ of `scheme` on `positions`, in the positions' unit
/// squared; vertices whose weights sum to ≤ 0 or are not finite are left out. `None`
/// when no vertex counts or the positions do not match the mesh.
#[must_use]
pub fn weighted_mean_edge_sq(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    scheme: &dyn WeightScheme,
) -> Option<f64> {
    let geometry = Geometry::new(mesh, positions).ok()?;
    let ctx = WeightContext::new(geometry);
    let mut weights = vec![0.0; mesh.n_halfedges()];
    scheme.fill_weights(&ctx, &mut weights);
    let n = mesh.n_vertices();
    let (mut num, mut den) = (vec![0.0; n], vec![0.0; n]);
    for (h, &w) in mesh.halfedges().zip(&weights) {
        let (i, j) = (mesh.to_vertex(h.twin()), mesh.to_vertex(h));
        let l2 = positions[i.index()].distance_squared(positions[j.index()]);
        num[i.index()] += w * l2;
        den[i.index()] += w;
    }
    let per: Vec<f64> = num
        .iter()
        .zip(&den)
        .filter(|(a, d)| **d > 0.0 && a.is_finite() && d.is_finite())
        .map(|(a, d)| a / d)
        .collect();
    (!per.is_empty()).then(|| per.iter().sum::<f64>() / per.len() as f64)
}

/// The predicted radius after `n` iterations of a sphere of radius `r0` whose scheme
/// has the weighted mean squared edge length `mean_edge_sq` (same unit as `r0`,
/// squared): r₀ (1 − λ⟨ℓ²⟩_w/(2r₀²))ⁿ.
#[must_use]
pub fn predicted_radius(r0: f64, lambda: f64, mean_edge_sq: f64, n: usize) -> f64 {
    r0 * sphere_closed_form(lambda, mean_edge_sq / (r0 * r0), n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use beltrami_halfedge::primitives;
    use beltrami_weights::WeightRegistry;

    #[test]
    fn uniform_gives_the_plain_mean_and_schemes_differ_little_on_an_icosphere() {
        let s = primitives::icosphere(3);
        let mesh = s.mesh().unwrap();
        let registry = WeightRegistry::with_builtins();
        let mut plain = 0.0;
        let mut counts = vec![0usize; mesh.n_vertices()];
        let mut sums = vec![0.0; mesh.n_vertices()];
        for h in mesh.halfedges() {
            let (i, j) = (mesh.to_vertex(h.twin()), mesh.to_vertex(h));
            sums[i.index()] += s.positions[i.index()].distance_squared(s.positions[j.index()]);
            counts[i.index()] += 1;
        }
        for (a, c) in sums.iter().zip(&counts) {
            plain += a / *c as f64;
        }
        plain /= mesh.n_vertices() as f64;
        let u = weighted_mean_edge_sq(
            &mesh,
            &s.positions,
            registry.get("uniform").unwrap().as_ref(),
        )
        .unwrap();
        assert!((u - plain).abs() < 1e-15 * plain.max(1.0), "{u} vs {plain}");
        let d = weighted_mean_edge_sq(
            &mesh,
            &s.positions,
            registry.get("distance").unwrap().as_ref(),
        )
        .unwrap();
        // Inverse-distance weights favour short edges: a smaller weighted mean.
        assert!(d < u, "{d} !< {u}");
        assert!(d > 0.9 * u);
    }

    #[test]
    fn predicted_radius_matches_a_smoothed_sphere() {
        use beltrami_smooth::{SmoothConfig, smooth};
        use beltrami_weights::{LaplacianOptions, Normalization};
        let s = primitives::icosphere(3);
        let mesh = s.mesh().unwrap();
        let registry = WeightRegistry::with_builtins();
        for name in ["uniform", "distance", "cotangent"] {
            let scheme = registry.get(name).unwrap();
            let l2 = weighted_mean_edge_sq(&mesh, &s.positions, scheme.as_ref()).unwrap();
            let config = SmoothConfig::new(0.5, 20)
                .laplacian(LaplacianOptions::new().normalization(Normalization::WeightSum));
            let out = smooth(&mesh, &s.positions, scheme.as_ref(), config).unwrap();
            let r =
                out.positions.iter().map(|p| p.length()).sum::<f64>() / out.positions.len() as f64;
            let predicted = predicted_radius(1.0, 0.5, l2, 20);
            // The closed form holds to a small fraction of the shrink.
            let shrink = 1.0 - predicted;
            assert!(shrink > 0.01, "{name}: shrink {shrink}");
            assert!(
                (r - predicted).abs() < 0.05 * shrink,
                "{name}: mean radius {r}, predicted {predicted}"
            );
        }
        // Scaling: a sphere of radius 2 with four times ⟨ℓ²⟩ shrinks by the same factor.
        assert!(
            (predicted_radius(2.0, 0.8, 4.0 * 0.01, 7) - 2.0 * predicted_radius(1.0, 0.8, 0.01, 7))
                .abs()
                < 1e-15
        );
    }
}
