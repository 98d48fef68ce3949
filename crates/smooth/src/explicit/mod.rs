//! The explicit engine: Jacobi sweeps, the compound methods built from them, and the
//! internal renumbering of large meshes (and of meshes in a poor order, for the
//! scattered sweep).

mod compound;
mod edges;
mod faces;
mod rows;
mod scatter;
mod sweep;

use std::borrow::Cow;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use beltrami_halfedge::geometry::Geometry;
use beltrami_halfedge::reorder::{VertexPermutation, bandwidth, rcm_order};
use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};
use beltrami_weights::{Laplacian, Normalization, WeightContext, WeightScheme};
use rayon::prelude::*;

use crate::config::{Boundary, Method, Reorder, SmoothConfig, Statistics, Summation};
use crate::duration::{Plan, area_rate, resolve_duration};
use crate::error::SmoothError;
use crate::numbering::{CHUNK, error_to_caller, permute_par, restore_par};
use crate::report::StepStats;

pub(crate) use sweep::Want;
use sweep::{FULL, MAX, NOTHING, Partial, RowSource, SweepInput};

/// How one vertex moves (one byte per vertex, so the sweep streams little).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    /// Never moves (fixed boundary, pinned, isolated).
    Still,
    /// Moves with its Laplacian row.
    Row,
    /// Moves along the boundary polyline towards its two boundary neighbours (see
    /// [`CurveRow`]).
    Curve,
}

/// A vertex that moves along the boundary polyline towards its two boundary
/// neighbours `a` and `b`; the weights are refreshed with the Laplacian.
#[derive(Clone, Copy, Debug, PartialEq)]
struct CurveRow {
    v: u32,
    a: u32,
    b: u32,
    wa: f64,
    wb: f64,
}

/// The explicit engine of a [`Smoother`](crate::Smoother): Jacobi sweeps
/// `x_i ← x_i + λ L x_i`, compound methods (Taubin, HC, volume rescale) built from
/// them, and the internal renumbering of large meshes (see [`Reorder`]).
pub(crate) struct Explicit<'a> {
    /// The mesh, renumbered when `perm` is set: the caller's own when given by value
    /// (renumbered in place), else borrowed or a renumbered copy. `None` when the run
    /// goes on without it ([`Faces`]).
    mesh: Option<Cow<'a, HalfedgeMesh>>,
    /// The connectivity a run without the mesh keeps instead (empty with the mesh).
    faces: Faces,
    /// Whether the caller gave the mesh by value (it is then handed back by
    /// [`finish`](Self::finish), in the caller's numbering, or its faces).
    mesh_given: bool,
    /// The internal numbering (new = internal, old = the caller's), when reordering.
    perm: Option<VertexPermutation>,
    /// Per-vertex displacements of the last sweep, internal numbering (reordering with
    /// full statistics only, allocated when first needed; summed in the caller's order
    /// for the mean).
    disp: Vec<f64>,
    /// Per-chunk results of a sweep, reused (no allocation per iteration).
    partials: Vec<Partial>,
    /// Per-chunk displacement sums in the caller's order, reused (reordering only).
    mean_partials: Vec<f64>,
    scheme: &'a dyn WeightScheme,
    config: SmoothConfig,
    laplacian: Laplacian,
    roles: Vec<Role>,
    /// The vertices whose role is not [`Role::Row`], in increasing order: a sweep moves
    /// every row alike, then puts these right.
    exceptions: Vec<u32>,
    curve: Vec<CurveRow>,
    positions: Vec<DVec3>,
    next: Vec<DVec3>,
    /// The positions at the start of a compound step (Taubin, HC, volume rescale);
    /// empty for plain diffusion.
    start: Vec<DVec3>,
    /// The input positions (HC only; empty otherwise).
    original: Vec<DVec3>,
    /// HC's per-vertex push-back `b`, reused every iteration (HC only; empty otherwise).
    push_back: Vec<DVec3>,
    /// The input volume (volume preservation only).
    volume: f64,
    iteration: usize,
    weights_fresh: bool,
    /// A scattered sweep declined once (an edge too short or too long for its plain
    /// products, or a weight sum not finite): the run sweeps gathered rows
    /// from then on (see [`sweep_scattered`](Self::sweep_scattered)).
    scatter_declined: bool,
    /// The triangles or edges in the order of that sweep, built on its first use.
    scatter_order: Option<ScatterOrder>,
    /// The power of two that sweep multiplies the corner positions by, once an edge was
    /// too short or too long for plain products ([`faces::cotangent_scale`]).
    cotangent_scale: Option<f64>,
    /// The iterations swept element by element (triangles or edges).
    scattered_sweeps: usize,
    /// The last sweep computed its weights itself (see [`sweep_fresh`](Self::sweep_fresh)):
    /// the stored operator's weights are older than that sweep's.
    operator_behind: bool,
    /// The operator of the last sweep when `operator_behind`, computed when first asked
    /// for (see [`laplacian`](Self::laplacian)).
    current: OnceLock<Laplacian>,
    weight_time: Duration,
    update_time: Duration,
}

impl std::fmt::Debug for Explicit<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Explicit")
            .field("scheme", &self.scheme.name())
            .field("config", &self.config)
            .field("iteration", &self.iteration)
            .finish_non_exhaustive()
    }
}

/// What a run without the half-edge mesh keeps of it (internal numbering): the
/// triangles in face order, three indices each (the volume, the surface centroid and the
/// output's faces; the operator keeps its own rows), and the isolated vertices (which a
/// volume rescale leaves in place), one bit each. Made when the caller gave the mesh by
/// value, every face is a triangle and the scheme is a built-in one
/// ([`Laplacian::detach`]); the 104 bytes per vertex of the mesh become 24.
#[derive(Debug, Default)]
struct Faces {
    triangles: Vec<u32>,
    isolated: Vec<u64>,
}

impl Faces {
    /// Whether vertex `i` is isolated.
    fn is_isolated(&self, i: usize) -> bool {
        (self.isolated[i / 64] >> (i % 64)) & 1 != 0
    }
}

/// What each vertex does in a sweep (in the smoother's numbering): isolated, fixed
/// boundary and pinned vertices stay, curve-boundary vertices follow their boundary,
/// the rest are rows of the operator.
fn vertex_roles(
    mesh: &HalfedgeMesh,
    config: &SmoothConfig,
    perm: Option<&VertexPermutation>,
) -> Vec<Role> {
    let mut roles: Vec<Role> = mesh
        .vertices()
        .map(|v| {
            if mesh.is_isolated(v) {
                return Role::Still;
            }
            match (mesh.is_boundary_vertex(v), config.boundary) {
                (false, _) | (true, Boundary::Free) => Role::Row,
                (true, Boundary::Fixed) => Role::Still,
                (true, Boundary::Curve) => Role::Curve,
            }
        })
        .collect();
    for &v in &config.pinned {
        let v = perm.map_or(v, |p| p.to_new(v));
        roles[v.index()] = Role::Still;
    }
    roles
}

/// The curve-boundary vertices with their two boundary neighbours, in increasing
/// vertex order (so that a sweep finds them with a cursor); weights come later.
fn curve_rows(mesh: &HalfedgeMesh, roles: &[Role]) -> Vec<CurveRow> {
    mesh.vertices()
        .filter(|v| roles[v.index()] == Role::Curve)
        .map(|v| {
            // Outgoing boundary halfedge v -> b; the boundary halfedge before it
            // comes from a.
            let out = mesh.outgoing_halfedge(v).expect("not isolated");
            CurveRow {
                v: v.raw(),
                a: mesh.from_vertex(mesh.prev(out)).raw(),
                b: mesh.to_vertex(out).raw(),
                wa: 0.0,
                wb: 0.0,
            }
        })
        .collect()
}

/// The enclosed volume volume preservation keeps.
///
/// # Errors
/// [`SmoothError::Weights`] when the positions do not match the mesh;
/// [`SmoothError::DegenerateVolume`] when the volume is not positive and finite.
fn input_volume(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Result<f64, SmoothError> {
    let volume = Geometry::new(mesh, positions)
        .and_then(|g| g.volume())
        .map_err(beltrami_weights::WeightError::from)?;
    if !(volume > 0.0 && volume.is_finite()) {
        return Err(SmoothError::DegenerateVolume {
            volume,
            iteration: 0,
        });
    }
    Ok(volume)
}

/// `config` with its [`duration`](SmoothConfig::duration), if any, turned into a step
/// and an iteration count on the first operator.
///
/// # Errors
/// [`SmoothError::InvalidDuration`] when the time cannot be turned into steps.
fn with_duration_resolved(
    mut config: SmoothConfig,
    perm: Option<&VertexPermutation>,
    positions: &[DVec3],
    laplacian: &Laplacian,
    roles: &[Role],
) -> Result<SmoothConfig, SmoothError> {
    if let Some(duration) = config.duration {
        let moves: Vec<bool> = roles.iter().map(|r| *r == Role::Row).collect();
        let plan = Plan {
            perm,
            positions,
            laplacian,
            moves: &moves,
            max_lambda: config.lambda,
            explicit: true,
        };
        let (lambda, iterations) = resolve_duration(&plan, duration.time())?;
        config.lambda = lambda;
        config.iterations = iterations;
    }
    Ok(config)
}

/// The compound methods' buffers: the positions at the start of a step (any compound
/// step), the input positions and the push-back (HC); empty when not needed.
fn compound_buffers(
    config: &SmoothConfig,
    positions: &[DVec3],
) -> (Vec<DVec3>, Vec<DVec3>, Vec<DVec3>) {
    let compound = config.method != Method::Laplacian || config.preserve_volume;
    let hc = matches!(config.method, Method::Hc { .. });
    let copy = |wanted: bool| {
        if wanted {
            positions.to_vec()
        } else {
            Vec::new()
        }
    };
    let push_back = if hc {
        vec![DVec3::ZERO; positions.len()]
    } else {
        Vec::new()
    };
    (copy(compound), copy(hc), push_back)
}

/// Whether a run's stale weights are computed inside the sweep: plain diffusion only
/// (a compound step reads the operator between its sweeps).
fn fuses(config: &SmoothConfig) -> bool {
    config.method == Method::Laplacian && !config.preserve_volume
}

/// The rows per work unit of a sweep that sums nothing: [`CHUNK`], or for a mesh of
/// fewer than `8 · CHUNK` vertices an eighth of it (at least 256), so that a small
/// mesh's sweep is shared by the cores. A function of the vertex count alone.
fn small_chunk(n: usize) -> usize {
    n.div_ceil(8).clamp(256, CHUNK)
}

/// The elements a scattered sweep computes its weights from, in its order.
enum ScatterOrder {
    /// Triangles: cotangent weights ([`faces`]).
    Triangles(faces::TriangleOrder),
    /// Edges: inverse-distance weights ([`edges`]).
    Edges(edges::EdgeOrder),
}

impl ScatterOrder {
    /// Whether its sweep takes the order's span (a mesh in an order far from its
    /// neighbourhoods is swept by gathered rows instead).
    fn fits(&self) -> bool {
        let span = match self {
            Self::Triangles(order) => order.span,
            Self::Edges(order) => order.span,
        };
        span <= scatter::MAX_SPAN
    }
}

/// A scattered sweep's input: what [`faces::sweep_triangles`] or
/// [`edges::sweep_edges`] reads.
enum Scattered<'a> {
    Triangles(faces::Scatter<'a>),
    Edges(edges::EdgeScatter<'a>),
}

impl Scattered<'_> {
    fn span(&self) -> usize {
        match self {
            Self::Triangles(s) => s.sweep.span,
            Self::Edges(s) => s.sweep.span,
        }
    }

    fn sweep(
        &self,
        first: usize,
        out: &mut [DVec3],
        unit: usize,
        stuck: &mut Vec<u32>,
        swept: &mut Vec<rows::RowSweep>,
    ) -> Result<(), scatter::Decline> {
        match self {
            Self::Triangles(s) => faces::sweep_triangles(s, first, out, unit, stuck, swept),
            Self::Edges(s) => edges::sweep_edges(s, first, out, unit, stuck, swept),
        }
    }
}

/// Runs the scattered sweep `scatter` over work units of [`scatter::block_rows`] rows in
/// parallel into `next`, each unit split into the statistics' chunks ([`CHUNK`] for
/// full statistics, as in [`sweep_chunks`]; the whole unit otherwise), with one
/// [`Partial`] per chunk; with `record` (and full statistics), also each displacement
/// into `disp`. Why it declined, when a unit did.
fn scatter_blocks(
    scatter: &Scattered<'_>,
    input: &SweepInput<'_>,
    want: Want,
    record: bool,
    next: &mut [DVec3],
    disp: &mut [f64],
) -> Result<Vec<Partial>, scatter::Decline> {
    let n = next.len();
    // Full statistics sum the displacements in the chunks of `sweep_chunks`, whose bits
    // must not depend on the split; the others combine by maxima and counts, so a work
    // unit is one chunk, and the units share the rows evenly.
    let (block, unit) = if want == Want::Full {
        (scatter::block_rows(CHUNK, scatter.span(), n), CHUNK)
    } else {
        let block = scatter::block_rows(1, scatter.span(), n);
        (block, block)
    };
    let disps: Vec<&mut [f64]> = if record {
        disp.chunks_mut(block).collect()
    } else {
        (0..n.div_ceil(block)).map(|_| &mut [][..]).collect()
    };
    let blocks: Vec<Result<Vec<Partial>, scatter::Decline>> = next
        .par_chunks_mut(block)
        .zip(disps)
        .enumerate()
        .map(|(b, (out, disp))| {
            let first = b * block;
            let (mut stuck, mut parts) = (Vec::new(), Vec::new());
            scatter.sweep(first, out, unit, &mut stuck, &mut parts)?;
            let is_stuck = |v: u32| stuck.binary_search(&v).is_ok();
            let mut partials = Vec::with_capacity(parts.len());
            let mut disp = Some(disp);
            for (k, (out, swept)) in out.chunks_mut(unit).zip(parts).enumerate() {
                let at = first + k * unit;
                let partial = match (want, record) {
                    (Want::Nothing, _) => {
                        input.put_right::<NOTHING, false>(at, out, &mut [], swept, is_stuck)
                    }
                    (Want::Max, _) => {
                        input.put_right::<MAX, false>(at, out, &mut [], swept, is_stuck)
                    }
                    (Want::Full, false) => {
                        input.put_right::<FULL, false>(at, out, &mut [], swept, is_stuck)
                    }
                    (Want::Full, true) => {
                        let d = disp.take().unwrap_or_default();
                        let (here, rest) = d.split_at_mut(out.len());
                        disp = Some(rest);
                        input.put_right::<FULL, true>(at, out, here, swept, is_stuck)
                    }
                };
                partials.push(partial);
            }
            Ok(partials)
        })
        .collect();
    let mut partials = Vec::new();
    for block in blocks {
        partials.extend(block?);
    }
    Ok(partials)
}

/// Runs `input`'s sweep over fixed chunks of [`CHUNK`] rows in parallel, into `next`,
/// one [`Partial`] per chunk into `partials` (and, with full statistics and `record`,
/// each displacement into `disp`, as long as `next`).
fn sweep_chunks(
    input: &SweepInput<'_>,
    source: RowSource<'_>,
    want: Want,
    record: bool,
    next: &mut [DVec3],
    disp: &mut [f64],
    partials: &mut Vec<Partial>,
) {
    // Without sums the chunking changes no result (maxima, counts and the first bad
    // vertex do not depend on it), so a small mesh is cut finer and both cores work.
    let fine = small_chunk(next.len());
    match (want, record) {
        (Want::Nothing, _) => next
            .par_chunks_mut(fine)
            .enumerate()
            .map(|(c, out)| input.chunk::<NOTHING, false>(source, c * fine, out, &mut []))
            .collect_into_vec(partials),
        (Want::Max, _) => next
            .par_chunks_mut(fine)
            .enumerate()
            .map(|(c, out)| input.chunk::<MAX, false>(source, c * fine, out, &mut []))
            .collect_into_vec(partials),
        (Want::Full, false) => next
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, out)| input.chunk::<FULL, false>(source, c * CHUNK, out, &mut []))
            .collect_into_vec(partials),
        (Want::Full, true) => next
            .par_chunks_mut(CHUNK)
            .enumerate()
            .zip(disp.par_chunks_mut(CHUNK))
            .map(|((c, out), disp)| input.chunk::<FULL, true>(source, c * CHUNK, out, disp))
            .collect_into_vec(partials),
    }
}

impl<'a> Explicit<'a> {
    /// Prepares a run on `positions` and computes the first weights; `config` has been
    /// validated (see [`Smoother::new`](crate::Smoother::new)). A borrowed mesh is
    /// copied when it is renumbered, a mesh given by value is renumbered in place;
    /// borrowed positions are copied, positions given by value become the smoother's
    /// own (replaced by their renumbered copy when reordering).
    ///
    /// # Errors
    /// [`SmoothError::Weights`] when the positions do not match the mesh or the scheme
    /// gives a non-finite weight; [`SmoothError::DegenerateVolume`];
    /// [`SmoothError::InvalidDuration`] when a time cannot be turned into steps.
    pub(crate) fn new(
        mesh: Cow<'a, HalfedgeMesh>,
        positions: Cow<'_, [DVec3]>,
        scheme: &'a dyn WeightScheme,
        config: SmoothConfig,
    ) -> Result<Self, SmoothError> {
        let start = Instant::now();
        let mesh_given = matches!(mesh, Cow::Owned(_));
        // With a mismatched position count the operator reports the error unreordered.
        let n = mesh.n_vertices();
        // The scattered sweep wants neighbours close in index on any mesh (cotangents
        // are scattered on triangle meshes only).
        let any: &dyn std::any::Any = scheme;
        let scattered = config.summation == Summation::Scatter
            && config.scatter_unmet(scheme).is_none()
            && config.reorder == Reorder::Auto
            && (mesh.is_triangle_mesh() || !any.is::<beltrami_weights::Cotangent>())
            && bandwidth(&mesh) > Reorder::SCATTER_MAX_BANDWIDTH;
        let perm = ((config.reorder.applies(n) || scattered) && positions.len() == n)
            .then(|| rcm_order(&mesh));
        // The input volume in the caller's numbering (the same bits either way), taken
        // before renumbering and reported after the operator's own errors.
        let volume = config
            .preserve_volume
            .then(|| input_volume(&mesh, &positions));
        let (mesh, positions): (Cow<'a, HalfedgeMesh>, Cow<'_, [DVec3]>) = match &perm {
            Some(p) => {
                let mesh = match mesh {
                    Cow::Borrowed(mesh) => Cow::Owned(p.apply_to_mesh(mesh)),
                    Cow::Owned(mut mesh) => {
                        p.apply_to_mesh_in_place(&mut mesh);
                        Cow::Owned(mesh)
                    }
                };
                let permuted = permute_par(p, &positions);
                // The caller's order is not needed any more (a large buffer of its own
                // goes back to the system: see `release`).
                if let Cow::Owned(given) = positions {
                    beltrami_halfedge::release(given);
                }
                (mesh, Cow::Owned(permuted))
            }
            None => (mesh, positions),
        };
        let to_caller = |e: SmoothError| match &perm {
            Some(p) => error_to_caller(e, p),
            None => e,
        };
        // A plain run whose weights change every iteration computes them inside each
        // sweep from the first on (`sweep_fresh`): the operator keeps no weight array
        // (8 bytes per slot). A duration is resolved from the weights, so it keeps them.
        let lean = fuses(&config) && config.operator_changes(scheme) && config.duration.is_none();
        // Any other run stores its weights: when the mesh will go once the operator is
        // built, only after it has gone (`refresh_weights` below, the same bits), so
        // that the weights (8 bytes per slot) and the mesh (104 bytes per vertex) are
        // never held together. A duration is resolved from the weights, before.
        let store_later = !lean
            && mesh_given
            && config.duration.is_none()
            && Laplacian::detaches(scheme)
            && mesh.is_triangle_mesh();
        let laplacian = if lean || store_later {
            Laplacian::new_without_weights(&mesh, &positions, scheme, config.laplacian)
        } else {
            Laplacian::new(&mesh, &positions, scheme, config.laplacian)
        }
        .map_err(|e| to_caller(e.into()))?;
        let roles = vertex_roles(&mesh, &config, perm.as_ref());
        let curve = curve_rows(&mesh, &roles);
        let volume = volume.transpose()?.unwrap_or(0.0);
        let config = with_duration_resolved(config, perm.as_ref(), &positions, &laplacian, &roles)?;
        // A mesh given by value is not needed past this point when the operator can
        // recompute its rows without it: it becomes its triangle list (in its own
        // buffers), before the second position buffer is made.
        let mut laplacian = laplacian;
        let (mesh, faces) = if mesh_given && laplacian.detach(&mesh, &positions, scheme) {
            let mut isolated = vec![0u64; mesh.n_vertices().div_ceil(64)];
            for v in mesh.vertices().filter(|&v| mesh.is_isolated(v)) {
                isolated[v.index() / 64] |= 1 << (v.index() % 64);
            }
            match mesh.into_owned().into_triangle_indices() {
                Ok(triangles) => (
                    None,
                    Faces {
                        triangles,
                        isolated,
                    },
                ),
                Err(mesh) => (Some(Cow::Owned(*mesh)), Faces::default()),
            }
        } else {
            (Some(mesh), Faces::default())
        };
        let n = positions.len();
        let eager_stats = config.statistics == Statistics::EveryIteration;
        let disp = if perm.is_some() && eager_stats {
            vec![0.0; n]
        } else {
            Vec::new()
        };
        let next = positions.to_vec();
        let (compound_start, original, push_back) = compound_buffers(&config, &positions);
        // A reordered copy is the smoother's own already: moved, not copied again.
        let positions = positions.into_owned();
        let mut smoother = Self {
            mesh,
            faces,
            mesh_given,
            disp,
            perm,
            partials: Vec::with_capacity(n.div_ceil(CHUNK)),
            mean_partials: Vec::with_capacity(n.div_ceil(CHUNK)),
            scheme,
            laplacian,
            exceptions: (0..n as u32)
                .filter(|&v| roles[v as usize] != Role::Row)
                .collect(),
            roles,
            curve,
            positions,
            next,
            start: compound_start,
            original,
            push_back,
            volume,
            config,
            iteration: 0,
            weights_fresh: true,
            scatter_declined: false,
            scatter_order: None,
            cotangent_scale: None,
            scattered_sweeps: 0,
            operator_behind: false,
            current: OnceLock::new(),
            weight_time: Duration::ZERO,
            update_time: Duration::ZERO,
        };
        if store_later {
            // The operator's weights and the curve weights, with the mesh or without.
            smoother.weight_time += start.elapsed();
            smoother.refresh_weights()?;
            return Ok(smoother);
        }
        smoother
            .refresh_curve_weights()
            .map_err(|e| smoother.to_caller(e))?;
        smoother.weight_time += start.elapsed();
        Ok(smoother)
    }

    /// Recomputes the 1-D weights of curve-boundary vertices from the current positions.
    fn refresh_curve_weights(&mut self) -> Result<(), SmoothError> {
        if self.config.boundary != Boundary::Curve {
            return Ok(());
        }
        let (scheme, x) = (self.scheme, &self.positions);
        // The weight of the curve neighbour `to` of `v`: the scheme's, on the mesh; a
        // built-in scheme's from the two positions without it (the same bits).
        let ctx = match &self.mesh {
            Some(mesh) => Some(WeightContext::new(
                Geometry::new(mesh, x).map_err(beltrami_weights::WeightError::from)?,
            )),
            None => None,
        };
        let weight = |v: u32, to: u32| match &ctx {
            Some(ctx) => {
                let mesh = ctx.geometry().mesh();
                let h = mesh
                    .find_halfedge(VertexId::new(v), VertexId::new(to))
                    .expect("boundary neighbour");
                scheme.curve_weight(ctx, h)
            }
            None => Laplacian::curve_weight_detached(scheme, x[v as usize], x[to as usize])
                .expect("a run without the mesh has a built-in scheme"),
        };
        let perm = self.perm.as_ref();
        let caller = |v: u32| perm.map_or(v, |p| p.new_to_old()[v as usize]);
        // The first bad row in the caller's numbering: (its vertex there, the error).
        let mut first_bad: Option<(u32, beltrami_weights::WeightError)> = None;
        for row in &mut self.curve {
            row.wa = weight(row.v, row.a);
            row.wb = weight(row.v, row.b);
            let key = caller(row.v);
            if first_bad.as_ref().is_some_and(|(k, _)| *k < key) {
                continue;
            }
            if let Some((w, to)) = [(row.wa, row.a), (row.wb, row.b)]
                .into_iter()
                .find(|(w, _)| !w.is_finite())
            {
                // Internal numbering; `to_caller` maps it back.
                let error = beltrami_weights::WeightError::NonFiniteWeight {
                    scheme: self.scheme.name().to_string(),
                    from: row.v,
                    to,
                    value: w,
                };
                first_bad = Some((key, error));
            }
        }
        match first_bad {
            Some((_, error)) => Err(error.into()),
            None => Ok(()),
        }
    }

    /// The mesh of a run without it, rebuilt from its triangles in the caller's
    /// numbering and renumbered as the run's (the halfedges of the mesh given, when it
    /// was built from its faces as [`HalfedgeMesh::from_polygons`] builds it): for the
    /// errors that name a halfedge, once.
    fn rebuilt_mesh(&self) -> HalfedgeMesh {
        let n = self.positions.len();
        let mesh = match &self.perm {
            Some(perm) => {
                let old = perm.new_to_old();
                let caller: Vec<u32> = self
                    .faces
                    .triangles
                    .iter()
                    .map(|&v| old[v as usize])
                    .collect();
                HalfedgeMesh::from_polygons(n, caller.chunks_exact(3)).map(|mut mesh| {
                    perm.apply_to_mesh_in_place(&mut mesh);
                    mesh
                })
            }
            None => HalfedgeMesh::from_polygons(n, self.faces.triangles.chunks_exact(3)),
        };
        mesh.expect("the faces of a valid mesh")
    }

    /// `e` with its vertex indices in the caller's numbering.
    fn to_caller(&self, e: SmoothError) -> SmoothError {
        match &self.perm {
            Some(p) => error_to_caller(e, p),
            None => e,
        }
    }

    /// Whether the weights must be recomputed before the next iteration.
    fn weights_stale(&self) -> bool {
        !self.weights_fresh && self.config.operator_changes(self.scheme)
    }

    /// One iteration, with the statistics `want` asks for (the others are 0; the stuck
    /// count is always there).
    pub(crate) fn iterate(&mut self, want: Want) -> Result<StepStats, SmoothError> {
        self.iteration += 1;
        let method = self.config.method;
        if method == Method::Laplacian && !self.config.preserve_volume {
            return self.sweep(self.config.lambda, want);
        }
        self.start.copy_from_slice(&self.positions);
        let result = self.compound_step(method);
        if result.is_err() {
            self.positions.copy_from_slice(&self.start);
        }
        result
    }

    /// One Jacobi sweep `x ← x + step · L x` over the moving vertices, refreshing the
    /// weights first when they are stale, with the statistics `want` asks for. On error
    /// the positions are unchanged.
    ///
    /// A plain run whose weights are recomputed every iteration computes each row's
    /// weights as the sweep reaches it ([`sweep_fresh`](Self::sweep_fresh)): the same
    /// bits as refreshing the operator first, without storing the weights.
    fn sweep(&mut self, lambda: f64, want: Want) -> Result<StepStats, SmoothError> {
        if want == Want::Full && self.perm.is_some() {
            // Once per run at most: with on-demand statistics only a `step()` needs it.
            self.disp.resize(self.positions.len(), 0.0);
        }
        // Rows summed element by element compute their weights in every sweep, the first of a
        // run whose operator was just assembled too (a duration plans the step with it).
        let scattered = self.fuses() && self.sweep_scattered(lambda, want);
        // Weights not kept (a lean operator, or released by a fused sweep, the scattered
        // one that just declined too) are stale too.
        let stale = self.weights_stale() || !self.laplacian.weights_stored();
        let fused = scattered || (self.fuses() && stale && self.sweep_fresh(lambda, want));
        if !fused {
            if stale {
                self.refresh_weights()?;
            }
            self.sweep_stored(lambda, want);
        }
        self.weights_fresh = false;
        self.sweep_result(want)
    }

    /// Whether stale weights are computed inside the sweep: plain diffusion only (a
    /// compound step reads the operator between its sweeps).
    fn fuses(&self) -> bool {
        fuses(&self.config)
    }

    /// Refreshes the operator and the curve weights at the current positions.
    fn refresh_weights(&mut self) -> Result<(), SmoothError> {
        let start = Instant::now();
        let updated = match &self.mesh {
            Some(mesh) => self.laplacian.update(mesh, &self.positions, self.scheme),
            None if self.laplacian.update_detached(&self.positions, self.scheme) => Ok(()),
            // A weight the rows cannot hold: the mesh, rebuilt, names its halfedge.
            None => {
                let mesh = self.rebuilt_mesh();
                self.laplacian.update(&mesh, &self.positions, self.scheme)
            }
        };
        let refreshed = match updated {
            Ok(()) => self.refresh_curve_weights(),
            Err(e) => Err(e.into()),
        };
        if let Err(e) = refreshed {
            return Err(self.to_caller(e));
        }
        self.operator_behind = false;
        self.weight_time += start.elapsed();
        Ok(())
    }

    /// A sweep of the stored operator into `next` and `partials`.
    fn sweep_stored(&mut self, lambda: f64, want: Want) {
        let start = Instant::now();
        let input = SweepInput {
            roles: &self.roles,
            exceptions: &self.exceptions,
            curve: &self.curve,
            old: &self.positions,
            lambda,
        };
        let (disp, record) = (&mut self.disp[..], self.perm.is_some());
        sweep_chunks(
            &input,
            RowSource::Stored(&self.laplacian),
            want,
            record,
            &mut self.next,
            disp,
            &mut self.partials,
        );
        self.update_time += start.elapsed();
    }

    /// A sweep into `next` and `partials` whose rows compute their weights at the
    /// current positions as it goes ([`Laplacian::fresh_rows`]); the stored operator is
    /// then behind (see [`laplacian`](Self::laplacian)). `false` when the rows cannot be
    /// computed that way or a row's weights are not finite: the caller refreshes the
    /// operator (which reports any error) and sweeps it instead.
    fn sweep_fresh(&mut self, lambda: f64, want: Want) -> bool {
        let start = Instant::now();
        // On error the stored path reports it, after the operator's own errors.
        if self.refresh_curve_weights().is_err() {
            return false;
        }
        let rows = match &self.mesh {
            Some(mesh) => self
                .laplacian
                .fresh_rows(mesh, &self.positions, self.scheme),
            None => self
                .laplacian
                .fresh_rows_detached(&self.positions, self.scheme),
        };
        let Some(rows) = rows else {
            return false;
        };
        let swept = Instant::now();
        self.weight_time += swept - start;
        let input = SweepInput {
            roles: &self.roles,
            exceptions: &self.exceptions,
            curve: &self.curve,
            old: &self.positions,
            lambda,
        };
        let (disp, record) = (&mut self.disp[..], self.perm.is_some());
        sweep_chunks(
            &input,
            RowSource::Fresh(&rows),
            want,
            record,
            &mut self.next,
            disp,
            &mut self.partials,
        );
        self.update_time += swept.elapsed();
        if self.partials.iter().any(|p| p.redo) {
            return false;
        }
        self.operator_behind = true;
        self.current = OnceLock::new();
        true
    }

    /// A sweep into `next` and `partials` that computes each element's weights once at
    /// the current positions and scatters them into its vertices' rows: each triangle's
    /// cotangents ([`Laplacian::scatters_cotangents`]: cotangent weights, weight-sum
    /// normalisation, negative weights kept, with either cotangent kernel), or each
    /// edge's inverse distance ([`Laplacian::scatters_distances`]: inverse-distance
    /// weights, weight-sum normalisation); the stored operator is then behind. `false`
    /// when the operator's rows are of neither kind, a face is not a triangle (for
    /// cotangents), the mesh's order leaves rows open too long ([`scatter::MAX_SPAN`]),
    /// or a row's weights are not finite or an edge is too short or too long for plain
    /// products (for cotangents, even on positions scaled by a power of two,
    /// [`faces::cotangent_scale`]); in these last three cases the run keeps to the
    /// gathered rows from then on. The caller then sweeps the gathered rows instead.
    ///
    /// The work units are [`scatter::block_rows`] long, each split into the statistics'
    /// chunks (see [`scatter_blocks`]), so full statistics are summed as in
    /// [`sweep_chunks`].
    fn sweep_scattered(&mut self, lambda: f64, want: Want) -> bool {
        let start = Instant::now();
        if self.config.summation != Summation::Scatter
            || self.config.scatter_unmet(self.scheme).is_some()
            || self.scatter_declined
            || self.refresh_curve_weights().is_err()
        {
            return false;
        }
        let triangles = if self.laplacian.scatters_cotangents(self.scheme) {
            true
        } else if self.laplacian.scatters_distances(self.scheme) {
            false
        } else {
            return false;
        };
        if self.scatter_order.is_none() {
            let n = self.positions.len();
            let order = if triangles {
                match &self.mesh {
                    Some(mesh) => faces::TriangleOrder::of_mesh(mesh),
                    None => faces::TriangleOrder::new(n, &self.faces.triangles),
                }
                .map(ScatterOrder::Triangles)
            } else {
                let lap = &self.laplacian;
                edges::EdgeOrder::new(n, |v| lap.neighbours(VertexId::new(v as u32)))
                    .map(ScatterOrder::Edges)
            };
            match order {
                Some(order) if order.fits() => {
                    self.scatter_order = Some(order);
                }
                _ => {
                    self.scatter_declined = true;
                    return false;
                }
            }
        }
        let Some(order) = &self.scatter_order else {
            return false;
        };
        let swept = Instant::now();
        self.weight_time += swept - start;
        let input = SweepInput {
            roles: &self.roles,
            exceptions: &self.exceptions,
            curve: &self.curve,
            old: &self.positions,
            lambda,
        };
        let record = want == Want::Full && self.perm.is_some();
        let mut pass = |scale: Option<f64>| {
            let scatter = match order {
                ScatterOrder::Triangles(sweep) => Scattered::Triangles(faces::Scatter {
                    sweep,
                    positions: &self.positions,
                    lambda,
                    scale,
                }),
                ScatterOrder::Edges(sweep) => Scattered::Edges(edges::EdgeScatter {
                    sweep,
                    positions: &self.positions,
                    lambda,
                }),
            };
            scatter_blocks(
                &scatter,
                &input,
                want,
                record,
                &mut self.next,
                &mut self.disp,
            )
        };
        let mut result = pass(self.cotangent_scale);
        if let ScatterOrder::Triangles(triangles) = order
            && result.as_ref().err() == Some(&scatter::Decline::Range)
            && self.cotangent_scale.is_none()
        {
            // Edges too short or too long for plain products: the same sweep, bit for bit,
            // on positions scaled by a power of two, for this and every later iteration.
            if let Some(scale) = faces::cotangent_scale(triangles, &self.positions) {
                self.cotangent_scale = Some(scale);
                result = pass(Some(scale));
            }
        }
        self.update_time += swept.elapsed();
        let Ok(partials) = result else {
            self.scatter_declined = true;
            return false;
        };
        self.partials = partials;
        self.scattered_sweeps += 1;
        self.operator_behind = true;
        self.current = OnceLock::new();
        true
    }

    /// The statistics of the sweep in `partials` (or its error, with the positions
    /// unchanged); the new positions become the current ones.
    fn sweep_result(&mut self, want: Want) -> Result<StepStats, SmoothError> {
        let mut stats = StepStats::default();
        let mut sum = 0.0;
        let mut squared: f64 = 0.0;
        for p in &self.partials {
            if let Some(vertex) = p.bad {
                return Err(self.non_finite(vertex));
            }
            sum += p.sum;
            stats.max_displacement = stats.max_displacement.max(p.max);
            squared = squared.max(p.max_squared);
            stats.stuck_vertices += p.stuck;
        }
        // Every plain displacement is the square root of its squared length, and the
        // square root is monotonic: the largest of them is the root of the largest square.
        stats.max_displacement = stats.max_displacement.max(squared.sqrt());
        if want == Want::Full && self.perm.is_some() {
            sum = self.displacement_sum_in_caller_order();
        }
        let n = self.positions.len();
        stats.mean_displacement = if n == 0 { 0.0 } else { sum / n as f64 };
        std::mem::swap(&mut self.positions, &mut self.next);
        Ok(stats)
    }

    /// The error of a sweep whose new position of `vertex` (internal numbering, the
    /// first bad one) is not finite; the sweep is undone.
    fn non_finite(&mut self, vertex: u32) -> SmoothError {
        // The smallest vertex in the caller's numbering, as without reordering.
        let vertex = match &self.perm {
            Some(perm) => self
                .next
                .par_iter()
                .zip(perm.new_to_old().par_iter())
                .filter(|(x, _)| !x.is_finite())
                .map(|(_, &old)| old)
                .min()
                .unwrap_or(vertex),
            None => vertex,
        };
        self.next.copy_from_slice(&self.positions);
        SmoothError::NonFinite {
            vertex,
            iteration: self.iteration,
        }
    }

    /// The sum of the last sweep's displacements in the caller's vertex order: the
    /// same chunks and order as without reordering, so the same bits.
    fn displacement_sum_in_caller_order(&mut self) -> f64 {
        let Some(perm) = &self.perm else {
            return 0.0;
        };
        let start = Instant::now();
        let disp = &self.disp;
        perm.old_to_new()
            .par_chunks(CHUNK)
            .map(|ids| {
                let mut sum = 0.0;
                for &i in ids {
                    sum += disp[i as usize];
                }
                sum
            })
            .collect_into_vec(&mut self.mean_partials);
        let mut sum = 0.0;
        for s in &self.mean_partials {
            sum += s;
        }
        self.update_time += start.elapsed();
        sum
    }

    /// The positions before the last iteration (internal numbering): `next` after a
    /// plain sweep, `start` after a compound step.
    pub(crate) fn before(&self) -> &[DVec3] {
        if self.config.method == Method::Laplacian && !self.config.preserve_volume {
            &self.next
        } else {
            &self.start
        }
    }

    /// The largest stable explicit step of an area-normalised operator on the current
    /// positions, in length² (a time per iteration): `1 / max_i (W_i / A_i)` over the
    /// moving vertices, with `W_i` the weight sum and `A_i` the vertex area. The step
    /// `x + λ M⁻¹ L x` has the eigenvalues of `λ M⁻¹ L` in `[−2 λ r, 0]` by
    /// Gershgorin's theorem (non-negative weights), so `λ ≤ 1 / r` keeps every
    /// frequency from growing. `None` with weight-sum normalisation (whose stable range
    /// is λ ≤ 1) or when no vertex moves. Weights recomputed every iteration move the
    /// limit a little as the mesh changes.
    ///
    /// A step from [`DiffusionTime`](crate::DiffusionTime) is chosen below half this
    /// limit; a step given directly is the caller's to check, e.g. to fail with
    /// [`SmoothError::UnstableStep`].
    #[must_use]
    pub(crate) fn stable_step_limit(&self) -> Option<f64> {
        if self.config.laplacian.normalization == Normalization::WeightSum {
            return None;
        }
        let moves: Vec<bool> = self.roles.iter().map(|r| *r == Role::Row).collect();
        let rate = area_rate(self.laplacian(), &moves);
        (rate > 0.0).then(|| 1.0 / rate)
    }

    /// The configuration of the run; with a [`duration`](SmoothConfig::duration),
    /// `lambda` and `iterations` are the step and count the smoother chose.
    #[must_use]
    pub(crate) fn config(&self) -> &SmoothConfig {
        &self.config
    }

    /// The current positions, in the caller's numbering: borrowed when the smoother
    /// works in that numbering, a restored copy (O(V) time and memory) when it reorders
    /// (see [`Reorder`](crate::Reorder) and [`permutation`](Self::permutation)).
    #[must_use]
    pub(crate) fn positions(&self) -> Cow<'_, [DVec3]> {
        match &self.perm {
            Some(perm) => {
                let mut out = vec![DVec3::ZERO; self.positions.len()];
                restore_par(perm, &self.positions, &mut out);
                Cow::Owned(out)
            }
            None => Cow::Borrowed(&self.positions),
        }
    }

    /// The scheme's name, for the report.
    pub(crate) fn scheme_name(&self) -> String {
        self.scheme.name().to_string()
    }

    /// The positions after the last iteration, internal numbering.
    pub(crate) fn internal_positions(&self) -> &[DVec3] {
        &self.positions
    }

    /// Ends the run: the positions in the caller's numbering, the configuration, the
    /// wall times and, when the caller gave it by value, the mesh in the caller's
    /// numbering — or, for a run that went on without it, its triangles (three indices
    /// each, face order, the caller's numbering).
    pub(crate) fn finish(mut self) -> (crate::smoother::Finished, Option<Vec<u32>>) {
        let positions = match &self.perm {
            Some(perm) => {
                // `next` is not needed any more: it takes the caller's order.
                let mut out = std::mem::take(&mut self.next);
                out.resize(self.positions.len(), DVec3::ZERO);
                restore_par(perm, &self.positions, &mut out);
                out
            }
            None => self.positions,
        };
        let mesh = match self.mesh {
            Some(Cow::Owned(mut mesh)) if self.mesh_given => {
                if let Some(perm) = &self.perm {
                    perm.restore_mesh_in_place(&mut mesh);
                }
                Some(mesh)
            }
            _ => None,
        };
        let mut triangles = self.faces.triangles;
        if let Some(perm) = &self.perm {
            let old = perm.new_to_old();
            triangles.par_iter_mut().for_each(|v| *v = old[*v as usize]);
        }
        let triangles = (self.mesh_given && mesh.is_none()).then_some(triangles);
        let finished = crate::smoother::Finished {
            positions,
            mesh,
            config: self.config,
            weight_time: self.weight_time,
            update_time: self.update_time,
            solver: None,
            scattered_sweeps: self.scattered_sweeps,
        };
        (finished, triangles)
    }

    /// The internal vertex numbering, when the smoother reorders: internal vertex `i`
    /// is the caller's vertex `new_to_old()[i]`. `None` when it works in the caller's
    /// numbering.
    #[must_use]
    pub(crate) fn permutation(&self) -> Option<&VertexPermutation> {
        self.perm.as_ref()
    }

    /// The number of iterations done.
    #[must_use]
    pub(crate) fn iteration(&self) -> usize {
        self.iteration
    }

    /// The operator as last assembled, in the internal numbering: its row `i` and its
    /// neighbour ids are internal vertex ids (the caller's when
    /// [`permutation`](Self::permutation) is `None`; map them with it otherwise).
    #[must_use]
    ///
    /// When the last sweep computed its weights itself, the operator of that sweep is
    /// computed on the first call (at its input positions, which a plain sweep keeps in
    /// `next`), so that this is always the operator the last sweep used.
    pub(crate) fn laplacian(&self) -> &Laplacian {
        if !self.operator_behind && self.laplacian.weights_stored() {
            return &self.laplacian;
        }
        self.current.get_or_init(|| {
            let mut laplacian = self.laplacian.clone();
            // After a fused sweep, that sweep's input positions (a plain sweep keeps
            // them in `next`): it computed every row of them, so this succeeds; on
            // error the operator is only older. Before the first sweep of a lean
            // operator (no weights kept), the current positions, which `new` accepted.
            let at = if self.operator_behind {
                &self.next
            } else {
                &self.positions
            };
            match &self.mesh {
                Some(mesh) => {
                    let _ = laplacian.update(mesh, at, self.scheme);
                }
                None => {
                    let _ = laplacian.update_detached(at, self.scheme);
                }
            }
            laplacian
        })
    }
}

#[cfg(test)]
mod tests {
    use std::borrow::Cow;

    use beltrami_halfedge::geometry::VertexAreaKind;
    use beltrami_halfedge::{DVec3, primitives};
    use beltrami_weights::{
        Cotangent, InverseDistance, LaplacianOptions, NegativeWeights, Normalization, Uniform,
        WeightScheme,
    };

    use super::{Explicit, Want};
    use crate::config::{DiffusionTime, Method, Reorder, SmoothConfig, Summation, WeightUpdate};

    /// After three iterations: whether the sweeps scattered triangles or edges (the order
    /// was built and never declined), and the scale they took.
    fn scattered(
        x: &[DVec3],
        scheme: &dyn WeightScheme,
        config: SmoothConfig,
    ) -> (bool, Option<f64>) {
        let sphere = primitives::icosphere(2);
        let mesh = sphere.mesh().unwrap();
        let mut e = Explicit::new(Cow::Borrowed(&mesh), Cow::Borrowed(x), scheme, config).unwrap();
        for want in [Want::Full, Want::Nothing, Want::Max] {
            e.iterate(want).unwrap();
        }
        let swept = e.scattered_sweeps == 3;
        assert_eq!(swept, e.scatter_order.is_some() && !e.scatter_declined);
        (swept, e.cotangent_scale)
    }

    /// `Reorder::Auto` renumbers a small mesh for the scattered sweep when its
    /// neighbours lie far apart in index (a subdivided sphere), not otherwise (a grid, a
    /// configuration the sweep does not apply to, the default summation).
    #[test]
    fn the_scatter_reorders_small_meshes_in_a_poor_order() {
        let sphere = primitives::icosphere(3);
        let grid = primitives::grid(30, 20);
        let renumbered = |p: &primitives::Primitive, scheme: &dyn WeightScheme, config| {
            let mesh = p.mesh().unwrap();
            let x = Cow::Borrowed(&p.positions[..]);
            Explicit::new(Cow::Borrowed(&mesh), x, scheme, config)
                .unwrap()
                .perm
                .is_some()
        };
        let scatter = SmoothConfig::new(0.5, 3).summation(Summation::Scatter);
        assert!(renumbered(&sphere, &InverseDistance, scatter.clone()));
        assert!(renumbered(&sphere, &Cotangent, scatter.clone()));
        assert!(!renumbered(&grid, &InverseDistance, scatter.clone()));
        assert!(!renumbered(&sphere, &Uniform, scatter.clone()));
        let never = scatter.clone().reorder(Reorder::Never);
        assert!(!renumbered(&sphere, &InverseDistance, never));
        assert!(!renumbered(
            &sphere,
            &InverseDistance,
            SmoothConfig::new(0.5, 3)
        ));
    }

    /// The scattered sweep takes exactly the runs `sums_by_scatter` (testkit) names, on
    /// either numbering, and far from unit scale through a power of two; a triangle
    /// collapsed to a point sends a cotangent run to the gathered rows, while inverse
    /// distances take any clamp and coincident vertices. The default sums rows.
    #[test]
    fn the_scatter_sweeps_where_it_applies() {
        let sphere = primitives::icosphere(2);
        let x = sphere.positions.clone();
        let rows = SmoothConfig::new(0.5, 3).update(WeightUpdate::Every);
        assert!(!scattered(&x, &Cotangent, rows.clone()).0);
        let every = rows.summation(Summation::Scatter);
        for reorder in [Reorder::Never, Reorder::Always] {
            let config = every.clone().reorder(reorder);
            assert_eq!(scattered(&x, &Cotangent, config.clone()), (true, None));
            assert_eq!(
                scattered(&x, &InverseDistance, config.clone()),
                (true, None)
            );
            assert!(!scattered(&x, &Uniform, config.clone()).0);
            let clamp = LaplacianOptions::new().negative(NegativeWeights::Clamp);
            assert!(!scattered(&x, &Cotangent, config.clone().laplacian(clamp)).0);
            let clamped = config.clone().laplacian(clamp);
            assert_eq!(scattered(&x, &InverseDistance, clamped), (true, None));
            let volume = config.clone().preserve_volume(true);
            assert!(!scattered(&x, &InverseDistance, volume).0);
            assert!(!scattered(&x, &Cotangent, config.clone().preserve_volume(true)).0);
            let once = config.clone().update(WeightUpdate::Once);
            assert!(!scattered(&x, &Cotangent, once).0);
            let area = LaplacianOptions::new()
                .normalization(Normalization::Area(VertexAreaKind::MixedVoronoi));
            let small = config.clone().lambda(1e-4).laplacian(area);
            assert!(!scattered(&x, &Cotangent, small.clone()).0);
            assert!(!scattered(&x, &InverseDistance, small).0);
            for method in [Method::taubin_or_pass_band(0.5, None), Method::hc()] {
                assert!(!scattered(&x, &Cotangent, config.clone().method(method)).0);
            }
            // A duration: every iteration, the first too.
            let timed = config.clone().duration(DiffusionTime::Time(1e-3));
            assert_eq!(scattered(&x, &Cotangent, timed), (true, None));
        }
        let huge: Vec<DVec3> = x.iter().map(|&p| p * 2f64.powi(700)).collect();
        let (yes, scale) = scattered(&huge, &Cotangent, every.clone());
        assert!(yes);
        // The sphere's edges are about 0.3 long: 2^-700 times a few.
        let scale = scale.unwrap();
        assert!(
            (2f64.powi(-700)..2f64.powi(-696)).contains(&scale),
            "{scale:e}"
        );
        let mut collapsed = x.clone();
        let f = sphere.faces.iter().nth(7).unwrap();
        let (a, b, c) = (f[0] as usize, f[1] as usize, f[2] as usize);
        collapsed[b] = collapsed[a];
        collapsed[c] = collapsed[a];
        assert!(!scattered(&collapsed, &Cotangent, every.clone()).0);
        // A run planned for a duration sweeps its first iteration with the operator it
        // assembled: when the scatter declines there, the gathered rows take it (the
        // weights the scatter released are recomputed, not read).
        let timed = every.clone().duration(DiffusionTime::Time(1e-3));
        assert!(!scattered(&collapsed, &Cotangent, timed.clone()).0);
        let mut far = x.clone();
        far[5] *= 1e200;
        assert!(!scattered(&far, &InverseDistance, timed).0);
        assert!(scattered(&collapsed, &InverseDistance, every.clone()).0);
        // Inverse distances far from unit scale: small edges keep to the scatter (their
        // weights are 1/ε either way); lengths whose squares overflow decline.
        let tiny: Vec<DVec3> = x.iter().map(|&p| p * 2f64.powi(-700)).collect();
        assert!(scattered(&tiny, &InverseDistance, every.clone()).0);
        let huge: Vec<DVec3> = x.iter().map(|&p| p * 2f64.powi(600)).collect();
        assert!(!scattered(&huge, &InverseDistance, every).0);
    }
}
