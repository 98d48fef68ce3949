//! The decimator's state and the evaluation of one candidate collapse: placement, its
//! quadric error, the shape penalty and every legality check.

use beltrami_halfedge::{DVec3, EditMesh, FaceId, HalfedgeId, VertexId};
use beltrami_metrics::distance::closest_point_on_triangle;

use super::geometry::{NormalCone, Quadric, aspect_ratio, cross, shape_quality_squared, smaller};
use super::heap::Heap;
use super::{BOUNDARY_WEIGHT, DecimateOptions, NOT_KEYED, Placement, RefusalCounts};

/// Why a candidate collapse was refused.
#[derive(Clone, Copy, Debug)]
pub(super) enum Refusal {
    Topology,
    Boundary,
    Error,
    Flip,
    NormalDeviation,
    AspectRatio,
    Distance,
}

impl RefusalCounts {
    pub(super) fn count(&mut self, r: Refusal) {
        let c = match r {
            Refusal::Topology => &mut self.topology,
            Refusal::Boundary => &mut self.boundary,
            Refusal::Error => &mut self.error,
            Refusal::Flip => &mut self.normal_flip,
            Refusal::NormalDeviation => &mut self.normal_deviation,
            Refusal::AspectRatio => &mut self.aspect_ratio,
            Refusal::Distance => &mut self.distance,
        };
        *c += 1;
    }
}

/// A legal collapse and what it changes.
pub(super) struct Candidate {
    /// The same as a distance, `sqrt(Q(p) / ΣA)`.
    pub(super) rms: f64,
    /// The kept vertex's new position.
    pub(super) position: DVec3,
    /// The new normal cones of the changed faces (with a normal bound).
    pub(super) cones: Vec<(FaceId, NormalCone)>,
    /// Faces whose input vertices are reassigned, and the new assignment (with a
    /// distance bound).
    pub(super) cleared: Vec<FaceId>,
    pub(super) assigned: Vec<(FaceId, Vec<u32>)>,
}

pub(super) struct Decimator<'a> {
    pub(super) mesh: EditMesh,
    pub(super) options: &'a DecimateOptions,
    pub(super) input: &'a [DVec3],
    /// The centre of the input's bounding box, which the quadrics are relative to (see
    /// [`Quadric`]).
    pub(super) origin: DVec3,
    pub(super) quadrics: Vec<Quadric>,
    /// The unit normal of every face when the decimation started (zero if degenerate).
    pub(super) input_normals: Vec<DVec3>,
    pub(super) cones: Vec<NormalCone>,
    pub(super) points: Vec<Vec<u32>>,
    /// Per halfedge: refused when last looked at, to be queued again when its
    /// neighbourhood changes.
    pub(super) parked: Vec<bool>,
    /// How many halfedges are parked (live ones; a removed edge's halfedges are
    /// unparked).
    pub(super) n_parked: usize,
    pub(super) heap: Heap,
    /// Per halfedge: the collapse count when its full key was computed, or
    /// [`NOT_KEYED`] when its heap key is the lower bound.
    pub(super) keyed_at: Vec<u32>,
    /// Per halfedge, with [`Placement::Optimal`]: the kept vertex's position and the
    /// symmetry of the [`Decimator::bound`] it was last queued with (a NaN position:
    /// not known, as for the initial queue's entries). Every edge at a vertex whose
    /// quadric or position changes is queued again, so a queued halfedge's bound is
    /// always the one it was queued with; with endpoint placement the update queues
    /// fewer, and this is not used.
    pub(super) placed: Vec<(DVec3, bool)>,
    /// Per vertex: the collapse count when its one-ring last changed.
    pub(super) changed_at: Vec<u32>,
    /// Collapses done so far.
    pub(super) collapses: u32,
    /// Entries sent back into the heap with a larger full key since the collapse loop
    /// last looked ([`Decimator::run`]).
    pub(super) sent_back: u32,
    /// Rounds of [`Decimator::key_queued_bounds`] so far.
    pub(super) keyings: u32,
    /// Scratch: the outgoing halfedges of the kept vertex of a collapse.
    pub(super) spokes: Vec<HalfedgeId>,
    /// Scratch: the neighbours of the removed vertex of a collapse.
    pub(super) support: Vec<VertexId>,
    pub(super) refused: RefusalCounts,
    /// The smallest quadric error the shape penalty divides (see
    /// [`DecimateOptions::quality_threshold`]): `10⁻¹² ℓ̄⁴` for the mean input edge
    /// length `ℓ̄`, so that flat regions are still ordered by shape.
    pub(super) error_floor: f64,
}

impl<'a> Decimator<'a> {
    pub(super) fn new(mesh: EditMesh, options: &'a DecimateOptions, input: &'a [DVec3]) -> Self {
        let nv = mesh.vertex_capacity();
        let nf = mesh.face_capacity();
        let nh = 2 * mesh.edge_capacity();
        // The surface's box: an isolated vertex far away (a stray point of a scan at the
        // machine's origin) would take the origin away from the part.
        let origin = bounding_box_centre(
            mesh.vertices()
                .filter(|&v| !mesh.is_isolated(v))
                .map(|v| input[v.index()]),
        );
        let mut d = Self {
            mesh,
            options,
            input,
            origin,
            quadrics: vec![Quadric::zero(origin); nv],
            input_normals: vec![DVec3::ZERO; nf],
            cones: Vec::new(),
            points: Vec::new(),
            parked: vec![false; nh],
            n_parked: 0,
            heap: Heap::with_capacity(nh),
            keyed_at: vec![NOT_KEYED; nh],
            placed: vec![(DVec3::NAN, false); nh],
            changed_at: vec![0; nv],
            collapses: 0,
            sent_back: 0,
            keyings: 0,
            spokes: Vec::new(),
            support: Vec::new(),
            refused: RefusalCounts::default(),
            error_floor: 0.0,
        };
        let mean_area = d.add_face_quadrics();
        // The floor is in the quadric's unit: length⁴ with area weights, length² without.
        d.error_floor = d.mean_edge_length().map_or(0.0, |mean| {
            if options.area_weighted {
                1e-12 * mean.powi(4)
            } else {
                1e-12 * mean * mean
            }
        });
        if options.stabilizer > 0.0 {
            let unit = if options.area_weighted {
                mean_area
            } else {
                1.0
            };
            d.add_stabilizer(options.stabilizer * unit);
        }
        if !options.keep_boundary {
            d.add_boundary_quadrics();
        }
        if options.max_normal_deviation.is_some() {
            d.start_normal_cones();
        }
        if options.max_distance.is_some() {
            d.assign_input_vertices();
        }
        d
    }

    /// Every face's input normal, and its plane (weighted by area or by 1, see
    /// [`DecimateOptions::area_weighted`]) added to the quadrics of its three vertices;
    /// returns the mean triangle area (0 without faces).
    fn add_face_quadrics(&mut self) -> f64 {
        let (mut area, mut count) = (0.0, 0usize);
        for f in self.mesh.faces() {
            let vs = self.face_vertices(f);
            let n = cross(vs.map(|v| self.mesh.position(v)));
            let twice = n.length();
            self.input_normals[f.index()] = n.try_normalize().unwrap_or(DVec3::ZERO);
            area += 0.5 * twice;
            count += 1;
            // OpenMesh: a triangle of (almost) no area adds (almost) nothing; MeshLib's
            // unit weights skip it too (it has no plane).
            if twice > f64::from(f32::MIN_POSITIVE) {
                let n = n / twice;
                let w = if self.options.area_weighted {
                    0.5 * twice
                } else {
                    1.0
                };
                let q = Quadric::plane_through(n, self.mesh.position(vs[0]), w, self.origin);
                for v in vs {
                    self.quadrics[v.index()].add(&q);
                }
            }
        }
        if count > 0 { area / count as f64 } else { 0.0 }
    }

    /// `w |x − p_v|²` added to every vertex's quadric (its plane weight unchanged).
    fn add_stabilizer(&mut self, w: f64) {
        for v in self.mesh.vertices() {
            let pull = Quadric::point(self.mesh.position(v), w, self.origin);
            self.quadrics[v.index()].add(&pull);
        }
    }

    /// The mean edge length of the input, `None` without edges.
    fn mean_edge_length(&self) -> Option<f64> {
        let (mut sum, mut count) = (0.0, 0usize);
        for e in self.mesh.edges() {
            let [a, b] = self.mesh.edge_vertices(e);
            sum += (self.mesh.position(b) - self.mesh.position(a)).length();
            count += 1;
        }
        (count > 0).then(|| sum / count as f64)
    }

    /// Every boundary edge's constraint plane (through the edge, perpendicular to its
    /// triangle, weighted by the squared edge length) added to its two vertices.
    fn add_boundary_quadrics(&mut self) {
        let boundary: Vec<HalfedgeId> = self
            .mesh
            .halfedges()
            .filter(|&h| self.mesh.is_boundary_halfedge(h))
            .collect();
        for h in boundary {
            let (a, b) = (self.mesh.from_vertex(h), self.mesh.to_vertex(h));
            let Some(f) = self.mesh.face(h.twin()) else {
                continue;
            };
            let normal = cross(self.face_vertices(f).map(|v| self.mesh.position(v)));
            let e = self.mesh.position(b) - self.mesh.position(a);
            if let Some(m) = e.cross(normal).try_normalize() {
                let w = if self.options.area_weighted {
                    BOUNDARY_WEIGHT * e.length_squared()
                } else {
                    BOUNDARY_WEIGHT
                };
                let q = Quadric::plane_through(m, self.mesh.position(a), w, self.origin);
                self.quadrics[a.index()].add(&q);
                self.quadrics[b.index()].add(&q);
            }
        }
    }

    /// Every face's normal cone: its own normal, of opening 0.
    fn start_normal_cones(&mut self) {
        let mut cones = vec![NormalCone::new(DVec3::Z); self.mesh.face_capacity()];
        for f in self.mesh.faces() {
            let n = cross(self.face_vertices(f).map(|v| self.mesh.position(v)));
            cones[f.index()] = NormalCone::new(n.try_normalize().unwrap_or(DVec3::Z));
        }
        self.cones = cones;
    }

    /// Every input vertex assigned to the incident face of the smallest id.
    fn assign_input_vertices(&mut self) {
        let mut points = vec![Vec::new(); self.mesh.face_capacity()];
        for v in self.mesh.vertices() {
            if let Some(f) = self.mesh.faces_around_vertex(v).min() {
                points[f.index()].push(v.raw());
            }
        }
        self.points = points;
    }

    pub(super) fn face_vertices(&self, f: FaceId) -> [VertexId; 3] {
        let h = self.mesh.face_halfedge(f);
        let a = self.mesh.to_vertex(h);
        let h = self.mesh.next(h);
        let b = self.mesh.to_vertex(h);
        let c = self.mesh.to_vertex(self.mesh.next(h));
        [a, b, c]
    }

    /// The topological checks of OpenMesh's `is_collapse_legal`, and `keep_boundary`;
    /// `EditMesh`'s collapse rules (the link condition) are checked by the collapse
    /// itself.
    pub(super) fn check_topology(&self, h: HalfedgeId) -> Result<(), Refusal> {
        let m = &self.mesh;
        if !m.is_live_halfedge(h) {
            return Err(Refusal::Topology);
        }
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        let b0 = m.is_boundary_vertex(v0);
        if b0 && self.options.keep_boundary {
            return Err(Refusal::Boundary);
        }
        let (vl, vr) = (m.opposite_vertex(h), m.opposite_vertex(h.twin()));
        if b0 && (!m.is_boundary_vertex(v1) || (vl.is_some() && vr.is_some())) {
            return Err(Refusal::Topology);
        }
        if m.cw_rotated(m.cw_rotated(h)) == h {
            return Err(Refusal::Topology);
        }
        if m.collapse_flattens_tetrahedron(h) {
            return Err(Refusal::Topology);
        }
        Ok(())
    }

    /// The kept vertex's position for the collapse of `h` and the summed quadric.
    pub(super) fn placement(&self, h: HalfedgeId) -> (DVec3, Quadric) {
        let m = &self.mesh;
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        let q = self.quadrics[v0.index()].sum(&self.quadrics[v1.index()]);
        let (position, _) = place(
            self.options,
            &q,
            m.position(v0),
            m.position(v1),
            m.is_boundary_vertex(v1),
        );
        (position, q)
    }

    /// The triangles the collapse of `h` changes, as `(face, new corners, old corners)`
    /// in the face's order: those around
    /// `v0` and, when the kept vertex moves, those around `v1`, without the (one or two)
    /// triangles at the edge, which are removed.
    pub(super) fn changed_triangles(
        &self,
        h: HalfedgeId,
        position: DVec3,
        mut visit: impl FnMut(FaceId, [DVec3; 3], [DVec3; 3]) -> bool,
    ) -> bool {
        let m = &self.mesh;
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        let removed = [m.face(h), m.face(h.twin())];
        let moved = position != m.position(v1);
        let centres: &[VertexId] = if moved { &[v0, v1] } else { &[v0] };
        for &c in centres {
            for g in m.halfedges_around_vertex(c) {
                let Some(f) = m.face(g) else {
                    continue;
                };
                if removed.contains(&Some(f)) {
                    continue;
                }
                let n = m.next(g);
                let (a, b) = (m.to_vertex(g), m.to_vertex(n));
                let at = |v: VertexId| {
                    if v == v0 || v == v1 {
                        position
                    } else {
                        m.position(v)
                    }
                };
                let before = [m.position(c), m.position(a), m.position(b)];
                if !visit(f, [position, at(a), at(b)], before) {
                    return false;
                }
            }
        }
        true
    }

    /// A lower bound of the heap key of collapsing `h` ([`Decimator::full_key`]): its
    /// quadric error (at least the error floor when the shape penalty is on), whether
    /// the twin's is bit for bit the same (both move the kept vertex to the same
    /// minimiser, neither end point is on the boundary, and they change the same
    /// triangles), and the kept vertex's position. Refuses what depends only on the two
    /// vertices' quadrics and positions (`keep_boundary`, `max_error`).
    ///
    /// The bound needs the two quadrics alone, so it is what a changed neighbourhood
    /// queues; the shape penalty, which needs every triangle the collapse makes, is
    /// evaluated when the entry reaches the top of the heap.
    pub(super) fn bound(&self, h: HalfedgeId) -> Result<(f64, bool, DVec3), Refusal> {
        let m = &self.mesh;
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        bound_between(
            self.options,
            self.error_floor,
            End {
                position: m.position(v0),
                boundary: m.is_boundary_vertex(v0),
                quadric: &self.quadrics[v0.index()],
            },
            End {
                position: m.position(v1),
                boundary: m.is_boundary_vertex(v1),
                quadric: &self.quadrics[v1.index()],
            },
        )
    }

    /// The heap key of collapsing `h` to `position`, given its [`Decimator::bound`]: the
    /// bound divided by the shape penalty when the worst new triangle's quality is
    /// below the threshold (never smaller than the bound). Refuses a collapse that
    /// makes a degenerate triangle.
    pub(super) fn full_key(
        &self,
        h: HalfedgeId,
        bound: f64,
        position: DVec3,
    ) -> Result<f64, Refusal> {
        let threshold = self.options.quality_threshold;
        if threshold <= 0.0 {
            return Ok(bound);
        }
        let mut worst = f64::INFINITY;
        self.changed_triangles(h, position, |_, t, _| {
            worst = smaller(worst, shape_quality_squared(t));
            worst > 0.0
        });
        if worst <= 0.0 {
            return Err(Refusal::Flip);
        }
        Ok(bound / (worst.sqrt() / threshold).min(1.0))
    }

    /// Whether the full key of `h` computed last is still its key: no collapse has
    /// changed the one-ring of either end since.
    pub(super) fn fresh(&self, h: HalfedgeId) -> bool {
        let at = self.keyed_at[h.index()];
        at != NOT_KEYED
            && self.changed_at[self.mesh.from_vertex(h).index()] <= at
            && self.changed_at[self.mesh.to_vertex(h).index()] <= at
    }

    /// Everything [`decimate`](super::decimate) checks for the collapse of `h`, and
    /// what it would change.
    ///
    /// `placed` is the kept vertex's position when the caller has just computed it
    /// ([`Decimator::bound`]).
    pub(super) fn evaluate(
        &self,
        h: HalfedgeId,
        placed: Option<DVec3>,
    ) -> Result<Candidate, Refusal> {
        self.check_topology(h)?;
        let m = &self.mesh;
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        let (position, q) = match placed {
            Some(p) => (p, self.quadrics[v0.index()].sum(&self.quadrics[v1.index()])),
            None => self.placement(h),
        };
        let rms = q.rms(position);
        if self.options.max_error.is_some_and(|e| rms > e) {
            return Err(Refusal::Error);
        }
        let changed = self.check_flips(h, position)?;
        let cones = match self.options.max_normal_deviation {
            Some(max) => self.merged_cones(h, &changed, max)?,
            None => Vec::new(),
        };
        if let Some(max) = self.options.max_aspect_ratio {
            self.check_aspect_ratio(h, &changed, position, max)?;
        }
        let (cleared, assigned) = match self.options.max_distance {
            Some(max) => self.reassign_input_vertices(h, position, max)?,
            None => (Vec::new(), Vec::new()),
        };
        Ok(Candidate {
            rms,
            position,
            cones,
            cleared,
            assigned,
        })
    }

    /// Refuses the collapse of `h` to `position` when a changed triangle degenerates
    /// or its normal turns by 90° or more, from its current normal or from its input
    /// normal; returns the changed faces and their new unit normals when a normal or
    /// aspect-ratio bound needs them (empty otherwise).
    fn check_flips(&self, h: HalfedgeId, position: DVec3) -> Result<Vec<(FaceId, DVec3)>, Refusal> {
        let keep_changed =
            self.options.max_normal_deviation.is_some() || self.options.max_aspect_ratio.is_some();
        let mut changed: Vec<(FaceId, DVec3)> = Vec::new();
        let mut flipped = false;
        self.changed_triangles(h, position, |f, t, before| {
            let old = cross(before);
            let Some(new) = cross(t).try_normalize() else {
                flipped = true;
                return false;
            };
            let input = self.input_normals[f.index()];
            if (old.dot(new) <= 0.0 && old != DVec3::ZERO)
                || (input.dot(new) <= 0.0 && input != DVec3::ZERO)
            {
                flipped = true;
                return false;
            }
            if keep_changed {
                changed.push((f, new));
            }
            true
        });
        if flipped {
            Err(Refusal::Flip)
        } else {
            Ok(changed)
        }
    }

    /// The changed faces' normal cones after the collapse of `h` (the `changed` faces
    /// with their new normals); refuses when one opens wider than `max` (radians).
    fn merged_cones(
        &self,
        h: HalfedgeId,
        changed: &[(FaceId, DVec3)],
        max: f64,
    ) -> Result<Vec<(FaceId, NormalCone)>, Refusal> {
        let m = &self.mesh;
        let removed = [m.face(h), m.face(h.twin())];
        // The face across `vl–v0` takes the place of the removed face `fl`, the face
        // across `v0–vr` that of `fr` (pmp-library): they inherit its cone.
        let heirs = [
            removed[0].and(m.face(m.prev(h).twin())),
            removed[1].and(m.face(m.next(h.twin()).twin())),
        ];
        let mut cones = Vec::with_capacity(changed.len());
        for &(f, n) in changed {
            let mut cone = self.cones[f.index()].merge(NormalCone::new(n));
            for (heir, r) in heirs.into_iter().zip(removed) {
                if let (Some(heir), Some(r)) = (heir, r)
                    && heir == f
                {
                    cone = cone.merge(self.cones[r.index()]);
                }
            }
            if cone.angle > 0.5 * max {
                return Err(Refusal::NormalDeviation);
            }
            cones.push((f, cone));
        }
        Ok(cones)
    }

    /// The corners of face `f` after the collapse of `h` to `position`.
    fn new_triangle(&self, h: HalfedgeId, f: FaceId, position: DVec3) -> [DVec3; 3] {
        let (v0, v1) = (self.mesh.from_vertex(h), self.mesh.to_vertex(h));
        self.face_vertices(f).map(|v| {
            if v == v0 || v == v1 {
                position
            } else {
                self.mesh.position(v)
            }
        })
    }

    /// Refuses the collapse of `h` to `position` when its worst new triangle (among
    /// the `changed` faces) has an aspect ratio above `max` and worse than the worst
    /// triangle it replaces.
    fn check_aspect_ratio(
        &self,
        h: HalfedgeId,
        changed: &[(FaceId, DVec3)],
        position: DVec3,
        max: f64,
    ) -> Result<(), Refusal> {
        let m = &self.mesh;
        let removed = [m.face(h), m.face(h.twin())];
        let old_triangle = |f: FaceId| self.face_vertices(f).map(|v| m.position(v));
        let worst_new = changed
            .iter()
            .map(|&(f, _)| aspect_ratio(self.new_triangle(h, f, position)))
            .fold(0.0f64, f64::max);
        let worst_old = changed
            .iter()
            .map(|&(f, _)| f)
            .chain(removed.into_iter().flatten())
            .map(|f| aspect_ratio(old_triangle(f)))
            .fold(0.0f64, f64::max);
        if worst_new > max && worst_new > worst_old {
            Err(Refusal::AspectRatio)
        } else {
            Ok(())
        }
    }

    /// The input vertices assigned to the faces around `v0` and `v1`, reassigned to
    /// the closest of the faces left after the collapse of `h` to `position`: the
    /// faces cleared and the new lists. Refuses when one would be farther than `max`.
    #[allow(clippy::type_complexity)]
    fn reassign_input_vertices(
        &self,
        h: HalfedgeId,
        position: DVec3,
        max: f64,
    ) -> Result<(Vec<FaceId>, Vec<(FaceId, Vec<u32>)>), Refusal> {
        let m = &self.mesh;
        let (v0, v1) = (m.from_vertex(h), m.to_vertex(h));
        let removed = [m.face(h), m.face(h.twin())];
        let mut cleared: Vec<FaceId> = m
            .faces_around_vertex(v0)
            .chain(m.faces_around_vertex(v1))
            .collect();
        cleared.sort_unstable();
        cleared.dedup();
        let targets: Vec<(FaceId, [DVec3; 3])> = cleared
            .iter()
            .filter(|&&f| !removed.contains(&Some(f)))
            .map(|&f| (f, self.new_triangle(h, f, position)))
            .collect();
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); targets.len()];
        for &f in &cleared {
            for &v in &self.points[f.index()] {
                let p = self.input[v as usize];
                let mut best: Option<(f64, usize)> = None;
                for (i, (_, t)) in targets.iter().enumerate() {
                    let d = closest_point_on_triangle(p, *t).distance_squared;
                    if best.is_none_or(|(bd, _)| d < bd) {
                        best = Some((d, i));
                    }
                }
                match best {
                    Some((d, i)) if d <= max * max => lists[i].push(v),
                    _ => return Err(Refusal::Distance),
                }
            }
        }
        let assigned = targets.iter().map(|(f, _)| *f).zip(lists).collect();
        Ok((cleared, assigned))
    }
}

/// One end of a candidate collapse: its position, whether it is on the boundary, and
/// its quadric.
pub(super) struct End<'q> {
    pub(super) position: DVec3,
    pub(super) boundary: bool,
    pub(super) quadric: &'q Quadric,
}

/// [`Decimator::bound`] of the collapse `from → to` for these `options` and error floor:
/// a function of the two ends alone, so that the initial queue is computed on several
/// threads (from the input mesh, which has the same ids).
#[inline]
pub(super) fn bound_between(
    options: &DecimateOptions,
    error_floor: f64,
    from: End<'_>,
    to: End<'_>,
) -> Result<(f64, bool, DVec3), Refusal> {
    if options.keep_boundary && from.boundary {
        return Err(Refusal::Boundary);
    }
    let (p0, p1) = (from.position, to.position);
    let q = from.quadric.sum(to.quadric);
    let (position, known) = place(options, &q, p0, p1, to.boundary);
    let error = known.unwrap_or_else(|| q.eval(position));
    if options.max_error.is_some_and(|e| q.rms_of(error) > e) {
        return Err(Refusal::Error);
    }
    let symmetric = options.placement == Placement::Optimal
        && position != p0
        && position != p1
        && !from.boundary
        && !to.boundary;
    let key = if options.quality_threshold > 0.0 {
        error.max(error_floor)
    } else {
        error
    };
    Ok((key, symmetric, position))
}

/// Where the kept vertex goes for the summed quadric `q` of a collapse `p0 → p1` (`b1`:
/// `p1` is on the boundary), and `q` there when it was computed on the way.
fn place(
    options: &DecimateOptions,
    q: &Quadric,
    p0: DVec3,
    p1: DVec3,
    b1: bool,
) -> (DVec3, Option<f64>) {
    if options.placement != Placement::Optimal || b1 {
        return (p1, None);
    }
    if let Some(x) = q
        .minimiser()
        .filter(|x| (*x - 0.5 * (p0 + p1)).length() <= 2.0 * (p1 - p0).length())
    {
        return (x, None);
    }
    let (e0, e1) = (q.eval(p0), q.eval(p1));
    if e0 < e1 {
        (p0, Some(e0))
    } else {
        (p1, Some(e1))
    }
}

/// The centre of the bounding box of `points` (finite), halfway between its corners
/// without overflow; the origin for no points.
fn bounding_box_centre(mut points: impl Iterator<Item = DVec3>) -> DVec3 {
    let Some(first) = points.next() else {
        return DVec3::ZERO;
    };
    let (lo, hi) = points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p)));
    0.5 * lo + 0.5 * hi
}
