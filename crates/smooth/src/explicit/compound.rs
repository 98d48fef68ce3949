//! The compound methods built from sweeps: Taubin's two steps, HC's push-back, the
//! volume rescale.

use std::time::Instant;

use beltrami_halfedge::geometry::{Geometry, TriangleGeometry};
use beltrami_halfedge::{DVec3, VertexId};
use rayon::prelude::*;

use super::{Explicit, Role, Want};
use crate::config::Method;
use crate::error::SmoothError;
use crate::numbering::CHUNK;
use crate::report::StepStats;

impl Explicit<'_> {
    /// One iteration of a method other than plain diffusion, or with a volume rescale:
    /// the sweeps, the corrections, then statistics measured from `start`.
    pub(super) fn compound_step(&mut self, method: Method) -> Result<StepStats, SmoothError> {
        let lambda = self.config.lambda;
        let stuck = match method {
            // The implicit engine runs implicit steps: here it means a plain sweep.
            Method::Laplacian | Method::Implicit { .. } => {
                self.sweep(lambda, Want::Nothing)?.stuck_vertices
            }
            Method::Taubin { mu } => {
                let first = self.sweep(lambda, Want::Nothing)?.stuck_vertices;
                first.max(self.sweep(mu, Want::Nothing)?.stuck_vertices)
            }
            Method::Hc { alpha, beta } => {
                let stuck = self.sweep(lambda, Want::Nothing)?.stuck_vertices;
                self.hc_correct(alpha, beta);
                stuck
            }
        };
        if self.config.preserve_volume {
            self.rescale_volume()?;
        }
        let start = Instant::now();
        let (before, after) = (&self.start, &self.positions);
        let partials: Vec<(f64, f64, Option<u32>)> = if let Some(perm) = &self.perm {
            // In the caller's order, so that the sum and the first bad index are the
            // unreordered run's.
            perm.old_to_new()
                .par_chunks(CHUNK)
                .enumerate()
                .map(|(c, ids)| {
                    let mut sum = 0.0;
                    let mut max: f64 = 0.0;
                    let mut bad = None;
                    for (k, &i) in ids.iter().enumerate() {
                        let (p, q) = (after[i as usize], before[i as usize]);
                        if !p.is_finite() && bad.is_none() {
                            bad = Some((c * CHUNK + k) as u32);
                        }
                        let d = beltrami_halfedge::geometry::distance(q, p);
                        sum += d;
                        max = max.max(d);
                    }
                    (sum, max, bad)
                })
                .collect()
        } else {
            after
                .par_chunks(CHUNK)
                .zip(before.par_chunks(CHUNK))
                .enumerate()
                .map(|(c, (a, b))| {
                    let mut sum = 0.0;
                    let mut max: f64 = 0.0;
                    let mut bad = None;
                    for (k, (p, q)) in a.iter().zip(b).enumerate() {
                        if !p.is_finite() && bad.is_none() {
                            bad = Some((c * CHUNK + k) as u32);
                        }
                        let d = beltrami_halfedge::geometry::distance(*q, *p);
                        sum += d;
                        max = max.max(d);
                    }
                    (sum, max, bad)
                })
                .collect()
        };
        self.update_time += start.elapsed();
        let mut stats = StepStats::default();
        let mut sum = 0.0;
        for (s, m, bad) in partials {
            if let Some(vertex) = bad {
                return Err(SmoothError::NonFinite {
                    vertex,
                    iteration: self.iteration,
                });
            }
            sum += s;
            stats.max_displacement = stats.max_displacement.max(m);
        }
        stats.stuck_vertices = stuck;
        let n = self.positions.len();
        stats.mean_displacement = if n == 0 { 0.0 } else { sum / n as f64 };
        Ok(stats)
    }

    /// The HC push-back (see [`Method::Hc`]): `positions` holds `p` (after the sweep),
    /// `next` holds `q` (before it).
    fn hc_correct(&mut self, alpha: f64, beta: f64) {
        let start = Instant::now();
        let (p, q, o) = (&self.positions, &self.next, &self.original);
        self.push_back
            .par_iter_mut()
            .zip(p.par_iter())
            .zip(q.par_iter().zip(o.par_iter()))
            .for_each(|((b, p), (q, o))| *b = *p - (*o * alpha + *q * (1.0 - alpha)));
        let b = &self.push_back;
        let (laplacian, roles) = (&self.laplacian, &self.roles);
        self.next
            .par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(c, out)| {
                for (k, slot) in out.iter_mut().enumerate() {
                    let i = c * CHUNK + k;
                    let pi = p[i];
                    *slot = if roles[i] == Role::Row {
                        // The plain neighbour average, as Vollmer et al.: weights
                        // that can be negative (cotangent) would amplify b.
                        let row = laplacian.row(VertexId::new(i as u32));
                        let n = row.len();
                        let s: DVec3 = row.map(|(j, _)| b[j.index()]).sum();
                        let mean = s / n as f64;
                        if n > 0 && mean.is_finite() {
                            pi - (b[i] * beta + mean * (1.0 - beta))
                        } else {
                            pi - b[i]
                        }
                    } else {
                        pi
                    };
                }
            });
        std::mem::swap(&mut self.positions, &mut self.next);
        self.update_time += start.elapsed();
    }

    /// Rescales about the surface centroid so that the volume is the input's.
    fn rescale_volume(&mut self) -> Result<(), SmoothError> {
        let start = Instant::now();
        let (volume, centre) = match &self.mesh {
            Some(mesh) => {
                let geometry = Geometry::new(mesh, &self.positions)
                    .map_err(beltrami_weights::WeightError::from)?;
                let volume = geometry
                    .volume()
                    .map_err(beltrami_weights::WeightError::from)?;
                (volume, geometry.surface_centroid())
            }
            None => {
                // Without the mesh: the same sums over its triangles (a closed mesh).
                let geometry = TriangleGeometry::new(&self.faces.triangles, &self.positions)
                    .map_err(beltrami_weights::WeightError::from)?;
                (geometry.volume(), geometry.surface_centroid())
            }
        };
        let centre = centre.unwrap_or(DVec3::ZERO);
        let beta = (self.volume / volume).cbrt();
        if !(volume > 0.0 && beta.is_finite()) {
            return Err(SmoothError::DegenerateVolume {
                volume,
                iteration: self.iteration,
            });
        }
        let (mesh, faces) = (self.mesh.as_deref(), &self.faces);
        self.positions
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, x)| {
                let isolated = match mesh {
                    Some(mesh) => mesh.is_isolated(VertexId::new(i as u32)),
                    None => faces.is_isolated(i),
                };
                if !isolated {
                    *x = centre + (*x - centre) * beta;
                }
            });
        self.update_time += start.elapsed();
        Ok(())
    }
}
