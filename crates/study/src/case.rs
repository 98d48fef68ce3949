//! [`SurfaceCase`]: a surface as the study uses it, shared by the runs and the
//! measurements.

use beltrami_halfedge::{DVec3, HalfedgeMesh};
use beltrami_surfaces::{Surface, SurfaceKind};

/// A surface as the study uses it: clean reference, noisy input, connectivity.
#[derive(Debug)]
pub struct SurfaceCase {
    /// Which surface.
    pub kind: SurfaceKind,
    /// The clean surface (the reference).
    pub clean: Surface,
    /// The noisy input every scheme smooths.
    pub noisy: Vec<DVec3>,
    /// The noise's standard deviation, in the surface's unit.
    pub sigma: f64,
    /// The connectivity (shared by clean, noisy and smoothed positions).
    pub mesh: HalfedgeMesh,
    /// The seed of the noise.
    pub seed: u64,
}
