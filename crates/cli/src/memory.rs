//! The memory a `beltrami smooth` run needs, estimated from element counts and the
//! kind of run, and the `--max-memory` size syntax.
//!
//! The estimate is the sum of the buffers the run holds at its peak, counted structure
//! by structure per vertex, per face corner and per face, plus a margin:
//!
//! ```text
//! bytes = BASE_BYTES + 5/4 · (v · V + c · C + f · F + steps + factor)
//! ```
//!
//! with `V` vertices, `C` face corners (the sum of the face sizes: `3 F` for a
//! triangle mesh; each corner stands for one halfedge, the same count in a closed
//! mesh) and `F` faces. The coefficients `v`, `c`, `f` depend on the method, the
//! solver, the weight scheme and the options ([`Run`]); `steps` is what the run keeps
//! per iteration (its statistics, the `--report` rows); `factor` is the Cholesky
//! factor of `--solver cholesky`, whose fill grows faster than the mesh
//! ([`cholesky_nonzeros`]). The margin covers the allocator's slack: the measured peak
//! resident memory is up to 11 % above the live heap, which the count bounds
//! (`docs/reliability.md`, section 6, has the measurements and the table of
//! coefficients).

use std::fmt;

use beltrami_smooth::Reorder;
use beltrami_weights::{Cotangent, InverseDistance, Uniform, WeightScheme};

/// Resident memory of the process before any mesh data (code, runtime, thread
/// stacks, allocator arenas, I/O buffers), in bytes. A run on a tiny mesh peaks at
/// about 6 MiB on 2 cores; more cores mean more threads and arenas.
pub(crate) const BASE_BYTES: u64 = 16 << 20;

/// The margin over the counted bytes, in percent: the peak resident memory measured
/// on spheres of 40 962 to 2 621 442 vertices is at most 11 % above the live heap.
pub(crate) const MARGIN_PERCENT: u64 = 125;

/// Vertex count above which `beltrami smooth` prints its estimate without
/// `--verbose`.
pub(crate) const LARGE_RUN_VERTICES: usize = 1_000_000;

/// Bytes per vertex, per face corner (standing for a halfedge) and per face of a group
/// of buffers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct PerElement {
    pub(crate) vertex: u64,
    pub(crate) corner: u64,
    pub(crate) face: u64,
}

impl PerElement {
    const fn new(vertex: u64, corner: u64, face: u64) -> Self {
        Self {
            vertex,
            corner,
            face,
        }
    }

    #[must_use]
    const fn plus(self, other: Self) -> Self {
        Self {
            vertex: self.vertex + other.vertex,
            corner: self.corner + other.corner,
            face: self.face + other.face,
        }
    }

    /// The bytes for `vertices`, `corners` and `faces` (saturating).
    fn bytes(self, vertices: usize, faces: usize, corners: usize) -> u64 {
        self.vertex
            .saturating_mul(vertices as u64)
            .saturating_add(self.corner.saturating_mul(corners as u64))
            .saturating_add(self.face.saturating_mul(faces as u64))
    }
}

/// The half-edge mesh: outgoing halfedge per vertex (4), target, next, previous and
/// face per halfedge (16), one halfedge per face (4). The face list as read is dropped
/// once it is built, and the input positions that the summary's mean displacement
/// needs wait in a temporary file (in memory only below 65 536 vertices or when none can
/// be written, within the margin). An explicit run with a built-in scheme on a triangle mesh replaces the mesh
/// by its triangle list (12 per face) once the operator is built, before its second
/// position buffer is made: the mesh stands for both.
const MESH: PerElement = PerElement::new(4, 16, 4);
/// An explicit smoother on 50 000 vertices or more (and, summed element by element, on
/// a smaller mesh in a poor order) renumbers them for locality: the permutation both
/// ways (8). The mesh it is given is renumbered in place, and the
/// positions' renumbered copy replaces them.
const REORDERED: PerElement = PerElement::new(8, 0, 0);
/// The operator: row offsets and valences (8), weight sums and scales (16) per vertex;
/// neighbour and halfedge ids (8) and the weight (8) per row slot (halfedge).
const LAPLACIAN: PerElement = PerElement::new(24, 16, 0);
/// The cotangent kernel's plan: counting-sort table (4 per vertex), two cotangent
/// indices per slot (8) and a temporary per-halfedge index (4), per triangle its
/// vertices (12), three cotangents (24) and, while the plan is built, its sort key (4).
const COTANGENT_PLAN: PerElement = PerElement::new(4, 12, 28);
/// The one-ring cotangent kernel's bit per row slot (counted as a byte).
const RING_BITS: PerElement = PerElement::new(0, 1, 0);
/// Cotangent rows summed by triangles (`--summation scatter`): the triangles sorted by
/// their smallest vertex (12 per face), where each vertex's triangles start and how far
/// back a sweep from it begins (8 per vertex).
const TRIANGLE_ORDER: PerElement = PerElement::new(8, 0, 12);
/// Inverse-distance rows summed by edges (`--summation scatter`): each edge's two
/// vertices (8 per edge, 4 per halfedge) grouped by the smaller, and the same two
/// tables per vertex (8).
const EDGE_ORDER: PerElement = PerElement::new(8, 4, 0);
/// A scheme without a built-in kernel (`bilateral`, a scheme of your own) fills a
/// per-halfedge weight buffer (8)...
const HALFEDGE_WEIGHTS: PerElement = PerElement::new(0, 8, 0);
/// ...and `bilateral` compares vertex normals: the cotangent fill's per-face buffer
/// (56), the face normals (24) and the vertex normals (24 per vertex). Counted for
/// every scheme without a kernel.
const NORMALS: PerElement = PerElement::new(24, 0, 80);
/// Area normalisation: the vertex areas of each assembly (8), and the implicit
/// smoother's copy (8).
const AREAS: PerElement = PerElement::new(16, 0, 0);
/// The explicit smoother's positions (given to it) and its second position buffer.
const EXPLICIT: PerElement = PerElement::new(48, 0, 0);
/// The positions at the start of a compound step (Taubin, HC, `--preserve-volume`).
const COMPOUND: PerElement = PerElement::new(24, 0, 0);
/// HC: the input positions and the push-back vectors.
const HC: PerElement = PerElement::new(48, 0, 0);
/// Per-vertex displacements of a reordered run that keeps every iteration's statistics.
const DISPLACEMENTS: PerElement = PerElement::new(8, 0, 0);
/// The implicit smoother: positions (given to it), next positions (48) and
/// displacements (8); the system's Dirichlet, free and coupled flags (3), mass and
/// diagonal (16) per vertex, twin slot (4) and off-diagonal entry (8) per slot. The
/// system reads the operator's own offsets, neighbours and weights.
const IMPLICIT: PerElement = PerElement::new(48 + 8 + 19, 12, 0);
/// Conjugate gradient: three vectors of three coordinates (residual, direction,
/// matrix product).
const CG: PerElement = PerElement::new(72, 0, 0);
/// Sparse Cholesky besides the factor: the upper triangle's column pointers, diagonal
/// positions (16), row indices and values (16 per vertex, 8 per slot), the slot map (8
/// per slot), the right-hand sides (24), faer's symbolic structure and work space (at
/// most 80 each, measured).
const CHOLESKY: PerElement = PerElement::new(16 + 16 + 24 + 160, 16, 0);
/// A fixed work buffer of faer's numeric factorisation.
const CHOLESKY_FIXED_BYTES: u64 = 4 << 20;
/// Bytes per non-zero of the Cholesky factor (its values; faer's supernodal structure
/// holds its row indices per supernode, within [`CHOLESKY`]).
const FACTOR_BYTES_PER_NONZERO: u64 = 8;
/// The fill coefficient of [`cholesky_nonzeros`]: the measured non-zeros per vertex
/// over `log2(V)²` are at most 0.353 on icospheres of 642 to 2 621 442 vertices.
const FILL: f64 = 0.36;

/// Per planned iteration of an explicit run with `--report`: its statistics (24).
const STEP_STATS_BYTES: u64 = 24;
/// Per step of an implicit run: the solver's statistics (56) and their copy (24).
const IMPLICIT_STEP_BYTES: u64 = 56 + 24;
/// Per iteration listed in the `--report` JSON: the report's row (40) and its
/// pretty-printed text (at most 176).
const REPORT_STEP_BYTES: u64 = 40 + 176;

/// The method of a run, with the solver of an implicit one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Method {
    /// Plain explicit diffusion.
    Explicit,
    /// Taubin's λ|μ.
    Taubin,
    /// HC.
    Hc,
    /// Implicit steps by conjugate gradient.
    ImplicitCg,
    /// Implicit steps by sparse Cholesky.
    ImplicitCholesky,
}

/// How the weights are computed, as far as memory goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Weights {
    /// A kernel that computes each row from the positions (uniform, inverse distance).
    Rows,
    /// The cotangent kernel, with its per-face plan.
    Cotangent,
    /// The cotangent kernel from each vertex's one-ring: a bit per row slot, no plan.
    CotangentRing,
    /// A scheme's own `fill_weights` (bilateral, a registered scheme): a per-halfedge
    /// buffer, and what bilateral needs for its normals.
    Halfedges,
}

impl Weights {
    /// The path `scheme` takes.
    pub(crate) fn of(scheme: &dyn WeightScheme) -> Self {
        // The operator recognises its built-in schemes by type, and so does this.
        let any: &dyn std::any::Any = scheme;
        if any.is::<Cotangent>() {
            Self::Cotangent
        } else if any.is::<Uniform>() || any.is::<InverseDistance>() {
            Self::Rows
        } else {
            Self::Halfedges
        }
    }
}

/// What a smoothing run does, as far as its memory goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Run {
    pub(crate) method: Method,
    pub(crate) weights: Weights,
    /// `--preserve-volume` (explicit methods).
    pub(crate) preserve_volume: bool,
    /// Area normalisation.
    pub(crate) area: bool,
    /// The planned iterations (steps of an implicit run); 0 when they are known only
    /// once the operator is built (an explicit run for `--time` or `--cutoff`).
    pub(crate) iterations: usize,
    /// Whether the `--report` JSON lists every iteration.
    pub(crate) report_steps: bool,
    /// Rows summed element by element (`--summation scatter`): by triangles for
    /// cotangent weights, by edges for the others (inverse distance).
    pub(crate) scatter: bool,
}

impl Run {
    /// The buffers of this run on `vertices` vertices, per element, before the margin.
    pub(crate) fn per_element(&self, vertices: usize) -> PerElement {
        let mut sum = MESH.plus(LAPLACIAN);
        sum = match self.weights {
            Weights::Rows => sum,
            Weights::Cotangent => sum.plus(COTANGENT_PLAN),
            Weights::CotangentRing => sum.plus(RING_BITS),
            Weights::Halfedges => sum.plus(HALFEDGE_WEIGHTS).plus(NORMALS),
        };
        if self.area {
            sum = sum.plus(AREAS);
        }
        if self.scatter {
            sum = sum.plus(match self.weights {
                Weights::Cotangent | Weights::CotangentRing => TRIANGLE_ORDER,
                _ => EDGE_ORDER,
            });
        }
        match self.method {
            Method::ImplicitCg => sum.plus(IMPLICIT).plus(CG),
            Method::ImplicitCholesky => sum.plus(IMPLICIT).plus(CHOLESKY),
            Method::Explicit | Method::Taubin | Method::Hc => {
                sum = sum.plus(EXPLICIT);
                // A run summed element by element may renumber a smaller mesh too
                // (when its neighbours lie far apart in index), which the file does not
                // tell beforehand: counted whenever it is asked for, an upper bound.
                let reordered = Reorder::default().applies(vertices) || self.scatter;
                if reordered {
                    sum = sum.plus(REORDERED);
                    if self.report_steps {
                        sum = sum.plus(DISPLACEMENTS);
                    }
                }
                if self.method != Method::Explicit || self.preserve_volume {
                    sum = sum.plus(COMPOUND);
                }
                if self.method == Method::Hc {
                    sum = sum.plus(HC);
                }
                sum
            }
        }
    }

    /// The bytes kept per planned iteration.
    fn bytes_per_iteration(&self) -> u64 {
        let report = if self.report_steps {
            REPORT_STEP_BYTES
        } else {
            0
        };
        match self.method {
            Method::ImplicitCg | Method::ImplicitCholesky => IMPLICIT_STEP_BYTES + report,
            _ if self.report_steps => STEP_STATS_BYTES + report,
            _ => 0,
        }
    }
}

/// An upper bound of the non-zeros of the Cholesky factor (diagonal included) of a
/// mesh with `vertices` vertices: `0.36 · V · log2(V)²`, at least `V`.
///
/// The fill of a 2-manifold under a minimum-degree or nested-dissection ordering grows
/// faster than `V`; on icospheres faer's approximate-minimum-degree factor holds
/// `0.31 – 0.35 · log2(V)²` non-zeros per vertex from 10 242 to 2 621 442 vertices
/// (150.6 per vertex at 2 621 442), an open grid patch about half as many.
pub(crate) fn cholesky_nonzeros(vertices: usize) -> u64 {
    #[allow(clippy::cast_precision_loss, reason = "an estimate")]
    let v = vertices as f64;
    let log = v.max(1.0).log2();
    let bound = (FILL * v * log * log).ceil();
    #[allow(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "non-negative; saturates"
    )]
    let bound = bound as u64;
    bound.max(vertices as u64)
}

/// The estimated peak memory of a smoothing run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct MemoryEstimate {
    /// Vertices (for an STL before welding: an estimate, see [`Self::for_triangle_soup`]).
    pub(crate) vertices: usize,
    /// Faces.
    pub(crate) faces: usize,
    /// Face corners (the sum of the face sizes).
    pub(crate) corners: usize,
    /// The estimate, in bytes.
    pub(crate) bytes: u64,
}

impl MemoryEstimate {
    /// The estimate of `run` on `vertices` vertices and `faces` faces with `corners`
    /// corners in all.
    pub(crate) fn new(run: &Run, vertices: usize, faces: usize, corners: usize) -> Self {
        let mut counted = run.per_element(vertices).bytes(vertices, faces, corners);
        counted = counted.saturating_add(
            run.bytes_per_iteration()
                .saturating_mul(run.iterations as u64),
        );
        if run.method == Method::ImplicitCholesky {
            counted = counted.saturating_add(CHOLESKY_FIXED_BYTES).saturating_add(
                FACTOR_BYTES_PER_NONZERO.saturating_mul(cholesky_nonzeros(vertices)),
            );
        }
        let bytes = BASE_BYTES.saturating_add(with_margin(counted));
        Self {
            vertices,
            faces,
            corners,
            bytes,
        }
    }

    /// The estimate for a file that declares `faces` triangles but not its vertices
    /// (an STL): a closed triangle mesh has about half as many vertices as faces.
    pub(crate) fn for_triangle_soup(run: &Run, faces: usize) -> Self {
        Self::new(run, faces / 2 + 2, faces, faces.saturating_mul(3))
    }
}

/// `bytes` plus the margin ([`MARGIN_PERCENT`]), saturating.
fn with_margin(bytes: u64) -> u64 {
    let scaled = u128::from(bytes) * u128::from(MARGIN_PERCENT) / 100;
    u64::try_from(scaled).unwrap_or(u64::MAX)
}

impl fmt::Display for MemoryEstimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "about {} ({} vertices, {} faces)",
            Size(self.bytes),
            self.vertices,
            self.faces
        )
    }
}

/// A byte count printed with a binary unit: `512.0 MiB`, `1.50 GiB`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Size(pub(crate) u64);

impl fmt::Display for Size {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
        #[allow(clippy::cast_precision_loss, reason = "printed with 3 digits")]
        let mut value = self.0 as f64;
        let mut unit = 0;
        while value >= 1024.0 && unit + 1 < UNITS.len() {
            value /= 1024.0;
            unit += 1;
        }
        if unit == 0 {
            write!(f, "{} B", self.0)
        } else if value < 10.0 {
            write!(f, "{value:.2} {}", UNITS[unit])
        } else {
            write!(f, "{value:.1} {}", UNITS[unit])
        }
    }
}

/// Which limit stops a run of `estimate` bytes, if any: `--max-memory` when given
/// (the user's limit, even above what the machine has), otherwise the memory the
/// machine has available. `None`: the run goes ahead.
pub(crate) fn exceeded_limit(
    estimate: u64,
    max_memory: Option<u64>,
    available: Option<u64>,
) -> Option<Limit> {
    match (max_memory, available) {
        (Some(limit), _) if estimate > limit => Some(Limit::Given(limit)),
        (None, Some(available)) if estimate > available => Some(Limit::Available(available)),
        _ => None,
    }
}

/// The limit a run's estimate exceeded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Limit {
    /// `--max-memory`, in bytes.
    Given(u64),
    /// The machine's available memory and free swap, in bytes
    /// ([`beltrami_io::available_memory`]).
    Available(u64),
}

/// Parses a size for `--max-memory`: a number of bytes, optionally with a decimal
/// fraction and a binary unit `K`, `M`, `G` or `T` (powers of 1024; `KB`, `KiB` and
/// lower case are accepted too): `512M`, `2G`, `1.5GiB`, `1000000`.
pub(crate) fn parse_size(text: &str) -> Result<u64, String> {
    let text = text.trim();
    let split = text
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(text.len());
    let (number, unit) = text.split_at(split);
    let shift = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 0,
        "k" | "kb" | "kib" => 10,
        "m" | "mb" | "mib" => 20,
        "g" | "gb" | "gib" => 30,
        "t" | "tb" | "tib" => 40,
        _ => return Err(format!("unknown unit {unit:?} (use K, M, G or T)")),
    };
    let value: f64 = number
        .parse()
        .map_err(|_| format!("{text:?} is not a size (e.g. 512M, 2G)"))?;
    #[allow(clippy::cast_precision_loss, reason = "powers of two are exact")]
    let bytes = value * (1u64 << shift) as f64;
    if !bytes.is_finite() || bytes < 1.0 || bytes >= 2f64.powi(64) {
        return Err(format!("{text:?} is not a size between 1 byte and 16 EiB"));
    }
    #[allow(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "range checked above"
    )]
    Ok(bytes as u64)
}

#[cfg(test)]
mod tests {

    #[test]
    fn the_given_limit_wins_over_the_available_memory() {
        // Without --max-memory the machine's available memory stops the run.
        assert_eq!(
            exceeded_limit(101, None, Some(100)),
            Some(Limit::Available(100))
        );
        assert_eq!(exceeded_limit(100, None, Some(100)), None);
        // Unknown availability: no default limit.
        assert_eq!(exceeded_limit(u64::MAX, None, None), None);
        // --max-memory decides alone, below or above what is available.
        assert_eq!(
            exceeded_limit(101, Some(100), Some(1000)),
            Some(Limit::Given(100))
        );
        assert_eq!(exceeded_limit(500, Some(1000), Some(100)), None);
    }

    use super::*;

    fn run(method: Method, weights: Weights) -> Run {
        Run {
            method,
            weights,
            preserve_volume: false,
            area: false,
            iterations: 10,
            report_steps: false,
            scatter: false,
        }
    }

    /// Bytes per vertex of a closed triangle mesh (`C = 6 V`, `F = 2 V`), before the
    /// margin.
    fn per_vertex(run: &Run, vertices: usize) -> u64 {
        let p = run.per_element(vertices);
        p.vertex + 6 * p.corner + 2 * p.face
    }

    #[test]
    fn sizes_parse_with_binary_units() {
        assert_eq!(parse_size("512M"), Ok(512 << 20));
        assert_eq!(parse_size("2G"), Ok(2 << 30));
        assert_eq!(parse_size("2g"), Ok(2 << 30));
        assert_eq!(parse_size("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_size("64KB"), Ok(64 << 10));
        assert_eq!(parse_size("1000"), Ok(1000));
        assert_eq!(parse_size("1T"), Ok(1 << 40));
        for bad in ["", "M", "12X", "-1G", "0", "1..2M", "nanG"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn sizes_print_with_binary_units() {
        assert_eq!(Size(512).to_string(), "512 B");
        assert_eq!(Size(512 << 20).to_string(), "512.0 MiB");
        assert_eq!(Size(3 << 29).to_string(), "1.50 GiB");
    }

    #[test]
    fn the_estimate_is_the_counted_bytes_with_a_quarter_more() {
        // The default run on a small closed mesh: the mesh, the operator, the
        // cotangent plan, the smoother's two position buffers.
        let r = run(Method::Explicit, Weights::Cotangent);
        assert_eq!(r.per_element(1000), PerElement::new(80, 44, 32));
        let e = MemoryEstimate::new(&r, 1000, 2000, 6000);
        assert_eq!(
            e.bytes,
            BASE_BYTES + (80 * 1000 + 44 * 6000 + 32 * 2000) * 5 / 4
        );
        let soup = MemoryEstimate::for_triangle_soup(&r, 2000);
        assert_eq!((soup.vertices, soup.corners), (1002, 6000));
        assert_eq!(
            MemoryEstimate::new(&r, usize::MAX, 0, usize::MAX).bytes,
            u64::MAX
        );
        // The icosphere of `tests/overwrite_and_limits.rs`.
        assert_eq!(
            Size(MemoryEstimate::new(&r, 642, 1280, 3840).bytes).to_string(),
            "16.3 MiB"
        );
    }

    #[test]
    fn the_coefficients_per_method_are_the_documented_ones() {
        // Bytes per vertex of a closed triangle mesh before the margin, as in
        // docs/reliability.md: (method, weights, small mesh, 50 000 vertices or more).
        let table = [
            (Method::Explicit, Weights::Cotangent, 408, 416),
            (Method::Explicit, Weights::CotangentRing, 282, 290),
            (Method::Taubin, Weights::Cotangent, 432, 440),
            (Method::Hc, Weights::Cotangent, 480, 488),
            (Method::Explicit, Weights::Rows, 276, 284),
            (Method::Explicit, Weights::Halfedges, 508, 516),
            (Method::ImplicitCg, Weights::Cotangent, 579, 579),
            (Method::ImplicitCholesky, Weights::Cotangent, 819, 819),
        ];
        for (method, weights, small, large) in table {
            let r = run(method, weights);
            assert_eq!(per_vertex(&r, 49_999), small, "{method:?} {weights:?}");
            assert_eq!(per_vertex(&r, 50_000), large, "{method:?} {weights:?}");
        }
        let explicit = run(Method::Explicit, Weights::Cotangent);
        let volume = Run {
            preserve_volume: true,
            ..explicit
        };
        assert_eq!(per_vertex(&volume, 10) - per_vertex(&explicit, 10), 24);
        let area = Run {
            area: true,
            ..explicit
        };
        assert_eq!(per_vertex(&area, 10) - per_vertex(&explicit, 10), 16);
        // Summed by triangles: 8 per vertex and 12 per face (24 per vertex), and the
        // permutation (8) on a small mesh too, which may be renumbered for the sweep.
        let triangles = Run {
            scatter: true,
            ..explicit
        };
        assert_eq!(per_vertex(&triangles, 10) - per_vertex(&explicit, 10), 40);
        assert_eq!(
            per_vertex(&triangles, 50_000) - per_vertex(&explicit, 50_000),
            32
        );
        // Inverse distances summed by edges: 8 per vertex and 8 per edge (24 per vertex).
        let distance = run(Method::Explicit, Weights::Rows);
        let edges = Run {
            scatter: true,
            ..distance
        };
        assert_eq!(
            per_vertex(&edges, 50_000) - per_vertex(&distance, 50_000),
            32
        );
        // Reordered runs keeping every iteration's statistics hold the displacements.
        let stats = Run {
            report_steps: true,
            ..explicit
        };
        assert_eq!(per_vertex(&stats, 10), per_vertex(&explicit, 10));
        assert_eq!(
            per_vertex(&stats, 100_000) - per_vertex(&explicit, 100_000),
            8
        );
    }

    #[test]
    fn every_method_and_scheme_costs_what_it_holds() {
        let (v, f, c) = (2562, 5120, 15_360);
        let bytes = |method, weights| MemoryEstimate::new(&run(method, weights), v, f, c).bytes;
        let cot = |method| bytes(method, Weights::Cotangent);
        assert!(cot(Method::ImplicitCholesky) > cot(Method::ImplicitCg));
        assert!(cot(Method::ImplicitCg) > cot(Method::Hc));
        assert!(cot(Method::Hc) > cot(Method::Taubin));
        assert!(cot(Method::Taubin) > cot(Method::Explicit));
        let explicit = |weights| bytes(Method::Explicit, weights);
        assert!(explicit(Weights::Halfedges) > explicit(Weights::Cotangent));
        assert!(explicit(Weights::Cotangent) > explicit(Weights::Rows));
    }

    #[test]
    fn iterations_cost_what_their_statistics_and_report_rows_hold() {
        let (v, f, c) = (642, 1280, 3840);
        let estimate = |r: Run| MemoryEstimate::new(&r, v, f, c).bytes;
        // The margin is taken of the sum: a difference may round either way.
        let about = |a: u64, b: u64| a.abs_diff(b) <= 1;
        let explicit = run(Method::Explicit, Weights::Cotangent);
        let with = |r: Run, iterations, report_steps| Run {
            iterations,
            report_steps,
            ..r
        };
        // Without --report an explicit run keeps nothing per iteration.
        assert_eq!(estimate(with(explicit, 100_000, false)), estimate(explicit));
        assert!(about(
            estimate(with(explicit, 100_000, true)) - estimate(with(explicit, 0, true)),
            with_margin(100_000 * (STEP_STATS_BYTES + REPORT_STEP_BYTES))
        ));
        // An implicit run keeps its steps' statistics anyway.
        let cg = run(Method::ImplicitCg, Weights::Cotangent);
        assert!(about(
            estimate(with(cg, 100_000, false)) - estimate(with(cg, 0, false)),
            with_margin(100_000 * IMPLICIT_STEP_BYTES)
        ));
        assert!(about(
            estimate(with(cg, 100_000, true)) - estimate(with(cg, 0, true)),
            with_margin(100_000 * (IMPLICIT_STEP_BYTES + REPORT_STEP_BYTES))
        ));
    }

    #[test]
    fn the_cholesky_fill_bound_holds_on_measured_factors() {
        // Non-zeros of faer's factor of icospheres of levels 3 to 9
        // (`beltrami smooth --method implicit --solver cholesky --report`).
        let measured = [
            (642, 14_527),
            (2562, 84_765),
            (10_242, 642_230),
            (40_962, 3_112_088),
            (163_842, 15_166_587),
            (655_362, 76_850_161),
            (2_621_442, 394_818_789),
        ];
        for (vertices, nonzeros) in measured {
            let bound = cholesky_nonzeros(vertices);
            assert!(bound >= nonzeros, "{vertices}: {bound} < {nonzeros}");
            assert!(
                bound * 2 < nonzeros * 3,
                "{vertices}: {bound} is loose for {nonzeros}"
            );
        }
        assert_eq!(cholesky_nonzeros(0), 0);
        assert_eq!(cholesky_nonzeros(1), 1);
        assert_eq!(cholesky_nonzeros(usize::MAX), u64::MAX);
        // The factor dominates large runs: at level 9 it is more than half.
        let r = run(Method::ImplicitCholesky, Weights::Cotangent);
        let all = MemoryEstimate::new(&r, 2_621_442, 5_242_880, 15_728_640).bytes;
        assert!(with_margin(8 * cholesky_nonzeros(2_621_442)) * 2 > all);
    }
}
