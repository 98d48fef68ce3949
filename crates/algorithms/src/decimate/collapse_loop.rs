//! The collapse loop: the queue of candidate collapses, cheapest first, and what a
//! collapse changes.

use std::ops::ControlFlow;

use beltrami_halfedge::{DVec3, ElementId, HalfedgeId, HalfedgeMesh, VertexId};
use rayon::prelude::*;

use super::evaluate::{Candidate, Decimator, End, Refusal, bound_between};
use super::{DecimateError, NOT_KEYED, Placement};

/// Collapses between two calls of the progress closure of [`Decimator::run`], and
/// between two looks at how many entries went back into the heap
/// ([`Decimator::key_queued_bounds`]).
const PROGRESS_EVERY: u32 = 4096;

/// Entries sent back per collapse, over the last [`PROGRESS_EVERY`] collapses, above
/// which the queued bounds are replaced by full keys ([`Decimator::key_queued_bounds`]).
const SENT_BACK_PER_COLLAPSE: u32 = 2;

/// Windows of [`PROGRESS_EVERY`] collapses that must pass between two rounds of
/// [`Decimator::key_queued_bounds`], which cost a pass over the whole heap.
const WINDOWS_BETWEEN_KEYINGS: u32 = 8;

impl Decimator<'_> {
    /// Queues the collapse of `h` with its current priority, or parks it (removed from
    /// the heap) and counts the refusal.
    fn queue(&mut self, h: HalfedgeId) {
        if !self.mesh.is_live_halfedge(h) {
            self.park(h, false);
            self.heap.remove(h.raw());
            return;
        }
        let bound = self.bound(h).map(|(key, symmetric, position)| {
            self.placed[h.index()] = (position, symmetric);
            key
        });
        self.queue_with(h, bound);
    }

    /// Queues the live halfedge `h` with its [`Decimator::bound`] `bound`, or parks it.
    fn queue_with(&mut self, h: HalfedgeId, bound: Result<f64, Refusal>) {
        self.park(h, false);
        self.keyed_at[h.index()] = NOT_KEYED;
        match bound {
            Ok(key) => self.heap.set(h.raw(), key),
            Err(r) => {
                self.heap.remove(h.raw());
                self.refuse(h, r);
            }
        }
    }

    /// Queues both halfedges of `h`'s edge ([`Decimator::queue`]), as one entry when
    /// their priorities are the same.
    fn queue_edge(&mut self, h: HalfedgeId) {
        if !self.mesh.is_live_halfedge(h) {
            self.queue(h);
            self.queue(h.twin());
            return;
        }
        match self.bound(h) {
            Ok((key, true, position)) => {
                // One entry for the edge, under its even halfedge; both directions are
                // tried when it comes to the top.
                let (even, odd) = if h.index().is_multiple_of(2) {
                    (h, h.twin())
                } else {
                    (h.twin(), h)
                };
                self.park(even, false);
                self.park(odd, false);
                self.keyed_at[even.index()] = NOT_KEYED;
                self.keyed_at[odd.index()] = NOT_KEYED;
                // A symmetric bound is the same from either end.
                self.placed[even.index()] = (position, true);
                self.heap.set(even.raw(), key);
                self.heap.remove(odd.raw());
            }
            bound => {
                let bound = bound.map(|(key, symmetric, position)| {
                    self.placed[h.index()] = (position, symmetric);
                    key
                });
                self.queue_with(h, bound);
                self.queue(h.twin());
            }
        }
    }

    /// Counts the refusal of `h` and parks it until its neighbourhood changes. The
    /// boundary and error refusals change only with the two vertices' quadrics and
    /// positions, and a change of those queues the halfedge again anyway.
    fn refuse(&mut self, h: HalfedgeId, r: Refusal) {
        self.refused.count(r);
        self.park(h, !matches!(r, Refusal::Boundary | Refusal::Error));
    }

    /// Sets whether `h` is parked, keeping [`Decimator::n_parked`].
    fn park(&mut self, h: HalfedgeId, parked: bool) {
        let was = std::mem::replace(&mut self.parked[h.index()], parked);
        match (was, parked) {
            (false, true) => self.n_parked += 1,
            (true, false) => self.n_parked -= 1,
            _ => {}
        }
    }

    /// Collapses until `target` vertices are left or the heap is empty; returns the
    /// largest RMS error of a collapse done.
    ///
    /// The heap holds halfedges keyed by a lower bound of their priority
    /// ([`Decimator::bound`]); the full key with the shape penalty
    /// ([`Decimator::full_key`]) and legality are evaluated when one comes to the top
    /// (lazily, as most queued collapses are never done). A full key larger than the
    /// entry's goes back into the heap; since every other entry's key is at most its
    /// own full key, the entry collapsed is the one of the smallest full key among those
    /// whose key is up to date. A full key stays valid until a collapse changes the
    /// one-ring of either end. A refused halfedge is parked until a collapse changes
    /// its neighbourhood.
    ///
    /// `progress(done, planned)` is called every [`PROGRESS_EVERY`] collapses and once
    /// at the end, with the collapses done and those planned (down to `target`); a
    /// [`ControlFlow::Break`] before the end stops the run with
    /// [`DecimateError::Stopped`].
    pub(super) fn run(
        &mut self,
        input: &HalfedgeMesh,
        target: usize,
        mut progress: impl FnMut(usize, usize) -> ControlFlow<()>,
    ) -> Result<f64, DecimateError> {
        self.fill_queue(input);
        let planned = self.mesh.n_vertices().saturating_sub(target);
        let mut max_rms: f64 = 0.0;
        let mut keyed_window = None;
        let mut window = 0;
        while self.mesh.n_vertices() > target {
            let Some((key, raw)) = self.heap.peek() else {
                break;
            };
            let Some((directions, placed)) = self.take_top(key, raw) else {
                continue;
            };
            let Some(done) = self.collapse_first(directions, placed) else {
                continue;
            };
            max_rms = max_rms.max(done.candidate.rms);
            self.apply(done);
            if self.collapses.is_multiple_of(PROGRESS_EVERY) {
                if progress(self.collapses as usize, planned).is_break() {
                    return Err(DecimateError::Stopped {
                        done: self.collapses as usize,
                        planned,
                    });
                }
                window += 1;
                let sent_back = std::mem::take(&mut self.sent_back);
                if sent_back > SENT_BACK_PER_COLLAPSE * PROGRESS_EVERY
                    && keyed_window.is_none_or(|w| window >= w + WINDOWS_BETWEEN_KEYINGS)
                {
                    keyed_window = Some(window);
                    self.key_queued_bounds();
                }
            }
        }
        // The last call reports where the run ended; stopping there changes nothing.
        let _ = progress(self.collapses as usize, planned);
        Ok(max_rms)
    }

    /// The initial heap: every halfedge by its [`Decimator::bound`], a symmetric pair
    /// as one entry under its even halfedge; refusals are parked. The bounds are
    /// computed on rayon's threads from `input`, the mesh the decimator's was copied
    /// from (the same ids), and taken in id order, so the heap does not depend on the
    /// thread count.
    fn fill_queue(&mut self, input: &HalfedgeMesh) {
        debug_assert_eq!(input.n_halfedges(), 2 * self.mesh.edge_capacity());
        let (options, floor) = (self.options, self.error_floor);
        let (positions, quadrics) = (self.input, &self.quadrics);
        let bound = |h: HalfedgeId| {
            let (v0, v1) = (input.from_vertex(h), input.to_vertex(h));
            let end = |v: VertexId| End {
                position: positions[v.index()],
                boundary: input.is_boundary_vertex(v),
                quadric: &quadrics[v.index()],
            };
            bound_between(options, floor, end(v0), end(v1))
        };
        // Per edge: its even halfedge's bound, and the odd one's unless the pair is
        // symmetric (one entry).
        let bounds: Vec<_> = (0..input.n_edges())
            .into_par_iter()
            .map(|e| {
                let even = HalfedgeId::from_index(2 * e);
                let first = bound(even);
                let second = match first {
                    Ok((_, true, _)) => None,
                    _ => Some(bound(even.twin()).map(|(key, _, _)| key)),
                };
                // Only the keys travel back (a small element for the collection).
                (first.map(|(key, _, _)| key), second)
            })
            .collect();
        let mut entries = Vec::with_capacity(input.n_halfedges());
        for (e, (first, second)) in bounds.into_iter().enumerate() {
            let even = HalfedgeId::from_index(2 * e);
            for (h, b) in [(even, Some(first)), (even.twin(), second)] {
                match b {
                    Some(Ok(key)) => entries.push((key, h.raw())),
                    Some(Err(r)) => self.refuse(h, r),
                    None => {}
                }
            }
        }
        self.heap.fill(&entries);
    }

    /// Replaces the key of every queued entry whose key is its bound (not a full key
    /// computed since it was queued) by its full key, computed on rayon's threads in
    /// halfedge order, and builds the heap again.
    ///
    /// The collapse loop calls this when many entries go back into the heap (more
    /// than [`SENT_BACK_PER_COLLAPSE`] per collapse over [`PROGRESS_EVERY`] collapses):
    /// once a generation of collapses has used up the edges whose collapse leaves
    /// well-shaped triangles, the bound of most remaining entries is far below their
    /// penalised key, and each would come to the top, be evaluated and sink again one
    /// by one (2.5 entries per collapse on the level-8 sphere). Keying them all at once
    /// costs one pass in memory order instead. The keys and the heap do not depend on
    /// the thread count; the collapses chosen afterwards can differ from a lazy run's
    /// where a full key goes stale before its entry reaches the top.
    fn key_queued_bounds(&mut self) {
        if self.options.quality_threshold <= 0.0 {
            return;
        }
        self.keyings += 1;
        let mut entries = self.heap.drain();
        entries.sort_unstable_by_key(|&(_, raw)| raw);
        let this = &*self;
        let keys: Vec<Option<f64>> = entries
            .par_iter()
            .map(|&(key, raw)| {
                let h = HalfedgeId::new(raw);
                if this.keyed_at[h.index()] != NOT_KEYED || !this.mesh.is_live_halfedge(h) {
                    return None;
                }
                // A queued entry's key is its bound; an initial entry has no recorded
                // position (computed again here; `take_top` records it).
                let (position, _) = this.placed[h.index()];
                let position = if position.is_nan() {
                    this.bound(h).ok()?.2
                } else {
                    position
                };
                this.full_key(h, key, position).ok()
            })
            .collect();
        for (entry, full) in entries.iter_mut().zip(keys) {
            if let Some(full) = full {
                entry.0 = full;
                self.keyed_at[entry.1 as usize] = self.collapses;
            }
        }
        self.heap.fill(&entries);
    }

    /// Looks at the top entry `(key, raw)`: returns the directions to try and the kept
    /// vertex's position (when computed) and takes the entry out of the heap; or `None`
    /// when the entry was dropped (a removed edge, a refusal) or went back with a
    /// larger full key.
    fn take_top(&mut self, key: f64, raw: u32) -> Option<([Option<HalfedgeId>; 2], Option<DVec3>)> {
        let h = HalfedgeId::new(raw);
        if !self.mesh.is_live_halfedge(h) {
            self.heap.remove(raw);
            return None;
        }
        let mut directions = [Some(h), None];
        let mut placed = None;
        let optimal = self.options.placement == Placement::Optimal;
        let recheck = self.options.quality_threshold > 0.0;
        if optimal || recheck {
            let fresh = self.fresh(h);
            let (position, symmetric) = self.placed[h.index()];
            let current = if optimal
                && !position.is_nan()
                && (fresh || self.keyed_at[h.index()] == NOT_KEYED)
            {
                // The bound the entry was queued with is still its bound; its key is
                // that bound unless a full key was computed since (then it is fresh,
                // and the bound is not needed).
                debug_assert!(
                    self.bound(h).is_ok_and(|(bound, s, p)| {
                        s == symmetric && p == position && (fresh || bound == key)
                    }),
                    "the queued bound of {h:?} is out of date"
                );
                if recheck && !fresh {
                    self.full_key(h, key, position)
                        .map(|full| (Some(full), symmetric, position))
                } else {
                    Ok((None, symmetric, position))
                }
            } else {
                match self.bound(h) {
                    Ok((bound, symmetric, position)) => {
                        if optimal {
                            self.placed[h.index()] = (position, symmetric);
                        }
                        if recheck && !fresh {
                            self.full_key(h, bound, position)
                                .map(|full| (Some(full), symmetric, position))
                        } else {
                            Ok((None, symmetric, position))
                        }
                    }
                    Err(r) => Err(r),
                }
            };
            if let Ok((Some(_), _, _)) = current {
                self.keyed_at[h.index()] = self.collapses;
            }
            match current {
                Ok((Some(full), _, _)) if full > key => {
                    // The entry's key was a lower bound, or the neighbourhood has
                    // changed since: it goes back with its full key.
                    self.heap.set(raw, full);
                    self.sent_back += 1;
                    return None;
                }
                Ok((_, symmetric, position)) => {
                    placed = Some(position);
                    if symmetric && h.index().is_multiple_of(2) {
                        directions[1] = Some(h.twin());
                    } else if h.index().is_multiple_of(2) && !self.heap.contains(h.twin().raw()) {
                        // The edge's entry stood for both directions; no longer.
                        self.queue(h.twin());
                    }
                }
                Err(r) => {
                    self.heap.remove(raw);
                    self.refuse(h, r);
                    return None;
                }
            }
        }
        self.heap.remove(raw);
        Some((directions, placed))
    }

    /// Collapses the first of `directions` the checks allow. `EditMesh`'s own
    /// topological checks (the link condition) run once, in the collapse, which leaves
    /// the mesh unchanged when it refuses.
    fn collapse_first(
        &mut self,
        directions: [Option<HalfedgeId>; 2],
        placed: Option<DVec3>,
    ) -> Option<Collapsed> {
        let optimal = self.options.placement == Placement::Optimal;
        for g in directions.into_iter().flatten() {
            let candidate = match self.evaluate(g, placed) {
                Ok(c) => c,
                Err(r) => {
                    self.refuse(g, r);
                    continue;
                }
            };
            let v0 = self.mesh.from_vertex(g);
            if !optimal {
                self.support.clear();
                self.support.extend(self.mesh.vertices_around_vertex(v0));
            }
            // The edge and one other edge of each triangle at it are removed; their
            // entries leave the heap now (a removal deep in the heap is cheap, one that
            // surfaces at the top later costs a full sift).
            let doomed = [
                g,
                self.mesh.next(g),
                self.mesh.prev(g),
                self.mesh.next(g.twin()),
                self.mesh.prev(g.twin()),
            ];
            match self.mesh.collapse_edge(g) {
                Ok(v1) => {
                    return Some(Collapsed {
                        v0,
                        v1,
                        candidate,
                        doomed,
                    });
                }
                Err(_) => self.refuse(g, Refusal::Topology),
            }
        }
        None
    }

    /// Brings the state up to date after a collapse: the removed edges leave the heap,
    /// the kept vertex moves and takes the removed one's quadric, the bounds' state
    /// (normal cones, assigned input vertices) follows, and the changed collapses are
    /// queued again.
    fn apply(&mut self, done: Collapsed) {
        let Collapsed {
            v0,
            v1,
            candidate,
            doomed,
        } = done;
        for g in doomed {
            if !self.mesh.is_live_halfedge(g) {
                self.heap.remove(g.raw());
                self.heap.remove(g.twin().raw());
                self.park(g, false);
                self.park(g.twin(), false);
            }
        }
        self.mesh.set_position(v1, candidate.position);
        self.collapses += 1;
        // The one-rings of `v1` and its neighbours changed: their full keys are out of
        // date.
        self.spokes.clear();
        self.spokes.extend(self.mesh.halfedges_around_vertex(v1));
        self.changed_at[v1.index()] = self.collapses;
        for k in 0..self.spokes.len() {
            let u = self.mesh.to_vertex(self.spokes[k]);
            self.changed_at[u.index()] = self.collapses;
        }
        let q0 = self.quadrics[v0.index()];
        self.quadrics[v1.index()].add(&q0);
        for (f, cone) in candidate.cones {
            self.cones[f.index()] = cone;
        }
        for f in candidate.cleared {
            self.points[f.index()].clear();
        }
        for (f, list) in candidate.assigned {
            self.points[f.index()] = list;
        }
        if self.options.placement == Placement::Optimal {
            self.requeue_around();
        } else {
            self.requeue_openmesh();
        }
    }

    /// Queues the edges at `v1` (the kept vertex, in [`Decimator::spokes`]) with their
    /// new keys, and the parked edges around its neighbours again (when any halfedge is
    /// parked at all: on most surfaces none ever is, and the walk is skipped).
    fn requeue_around(&mut self) {
        for k in 0..self.spokes.len() {
            let g = self.spokes[k];
            self.queue_edge(g);
        }
        if self.n_parked == 0 {
            return;
        }
        for k in 0..self.spokes.len() {
            let u = self.mesh.to_vertex(self.spokes[k]);
            let start = self.mesh.outgoing_halfedge(u);
            let mut g = start;
            while let Some(e) = g {
                if self.parked[e.index()] || self.parked[e.twin().index()] {
                    self.queue_edge(e);
                }
                let next = self.mesh.cw_rotated(e);
                g = (Some(next) != start).then_some(next);
            }
        }
    }

    /// `DecimaterT`'s update: the outgoing collapses of `v0`'s former neighbours (in
    /// [`Decimator::support`], `v1` among them) are evaluated again; those of `v1`'s
    /// other neighbours keep their keys until their own neighbourhood changes.
    fn requeue_openmesh(&mut self) {
        for k in 0..self.support.len() {
            let u = self.support[k];
            self.spokes.clear();
            self.spokes.extend(self.mesh.halfedges_around_vertex(u));
            for j in 0..self.spokes.len() {
                self.queue(self.spokes[j]);
            }
        }
    }
}

/// A collapse done: the removed and the kept vertex, what was checked, and the
/// halfedges of the edges that may have gone with it.
struct Collapsed {
    v0: VertexId,
    v1: VertexId,
    candidate: Candidate,
    doomed: [HalfedgeId; 5],
}
