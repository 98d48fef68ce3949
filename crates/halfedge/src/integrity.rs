//! `check_integrity`: every half-edge invariant, checked element by element.
//!
//! The checks run on rayon's threads in passes (ranges, halfedges, faces, vertices);
//! each pass reports its lowest-numbered element at fault, so the error does not depend
//! on the number of threads. The same passes, with the stricter rules of
//! [`Strictness::Raw`], validate the arrays given to
//! [`HalfedgeMesh::from_raw_parts`](crate::HalfedgeMesh::from_raw_parts).

use rayon::prelude::*;

use crate::error::TopologyError;
use crate::ids::{ElementId, FaceId, HalfedgeId, VertexId};
use crate::mesh::{HalfedgeMesh, INVALID};

/// About how many elements one parallel task checks.
const CHUNK: usize = 1 << 12;

fn fail<I: ElementId>(id: I, invariant: &'static str) -> Result<(), TopologyError> {
    Err(TopologyError::Integrity {
        element: format!("{} {}", I::KIND, id.index()),
        invariant,
    })
}

/// Which invariants [`validate`] checks.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(crate) enum Strictness {
    /// Those of [`HalfedgeMesh::check_integrity`].
    Links,
    /// Those, and what a mesh built from a face list also has: every halfedge lies on
    /// the cycle of its face, a face lists each vertex once, a vertex has at most one
    /// outgoing boundary halfedge (one fan), two vertices share at most one edge.
    Raw,
}

/// The first fault of a pass: the element index and the invariant, lowest index wins.
type Fault = Option<(usize, &'static str)>;

fn first(a: Fault, b: Fault) -> Fault {
    match (a, b) {
        (Some(x), Some(y)) => Some(if y.0 < x.0 { y } else { x }),
        (x, None) => x,
        (None, y) => y,
    }
}

/// The first `i` in `0..n` for which `check` finds a fault. The range is cut into chunks
/// of a fixed size, each scanned in order on one of rayon's threads; the lowest fault
/// wins, so the answer does not depend on the number of threads.
fn first_fault(n: usize, check: impl Fn(usize) -> Option<&'static str> + Sync) -> Fault {
    (0..n.div_ceil(CHUNK)).into_par_iter().find_map_first(|c| {
        (c * CHUNK..n.min((c + 1) * CHUNK)).find_map(|i| check(i).map(|inv| (i, inv)))
    })
}

/// The sum of `check` over `0..n` and its first fault (chunked as [`first_fault`]). A
/// chunk stops at its first fault, so the sum is meaningful only without one.
fn sum_or_fault(
    n: usize,
    check: impl Fn(usize, &mut Vec<u32>) -> Result<usize, &'static str> + Sync,
) -> (usize, Fault) {
    (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut buf = Vec::new();
            let mut sum = 0;
            for i in c * CHUNK..n.min((c + 1) * CHUNK) {
                match check(i, &mut buf) {
                    Ok(len) => sum += len,
                    Err(inv) => return (sum, Some((i, inv))),
                }
            }
            (sum, None)
        })
        .reduce(|| (0, None), |a, b| (a.0 + b.0, first(a.1, b.1)))
}

/// Whether `items` has a repeated entry (quadratic for short lists, sorting otherwise).
fn has_repeat(items: &mut [u32]) -> bool {
    if items.len() <= 16 {
        (1..items.len()).any(|i| items[..i].contains(&items[i]))
    } else {
        items.sort_unstable();
        items.windows(2).any(|w| w[0] == w[1])
    }
}

/// The first invariant of halfedge `h` that does not hold (links already in range).
#[inline]
fn halfedge_fault(m: &HalfedgeMesh, h: usize) -> Option<&'static str> {
    let n = m.h_next[h] as usize;
    if m.h_prev[n] as usize != h {
        return Some("prev(next(h)) == h");
    }
    if m.h_to[n ^ 1] != m.h_to[h] {
        return Some("next(h) starts where h ends");
    }
    if m.h_face[n] != m.h_face[h] {
        return Some("next(h) lies in the face of h");
    }
    if m.h_to[h] == m.h_to[h ^ 1] {
        return Some("a halfedge joins two different vertices");
    }
    if m.h_face[h] == INVALID && m.h_face[h ^ 1] == INVALID {
        return Some("an edge has at least one face");
    }
    None
}

/// Checks face `f`: its halfedge belongs to it and its cycle is long enough (and, for
/// [`Strictness::Raw`], lists each vertex once). Returns the cycle's length.
fn face_check(
    m: &HalfedgeMesh,
    f: usize,
    strictness: Strictness,
    buf: &mut Vec<u32>,
) -> Result<usize, &'static str> {
    let nh = m.n_halfedges();
    let start = m.f_he[f];
    if m.h_face[start as usize] as usize != f {
        return Err("the face's halfedge belongs to the face");
    }
    buf.clear();
    let mut h = start;
    let mut len = 0;
    loop {
        len += 1;
        if strictness == Strictness::Raw {
            buf.push(m.h_to[h as usize]);
        }
        h = m.h_next[h as usize];
        if h == start || len > nh {
            break;
        }
    }
    if !(3..=nh).contains(&len) {
        return Err("a face has at least 3 halfedges");
    }
    if strictness == Strictness::Raw && has_repeat(buf) {
        return Err("a face lists each vertex once");
    }
    Ok(len)
}

/// Checks vertex `v` by circulating it from its outgoing halfedge. Returns the number
/// of outgoing halfedges met (0 for an isolated vertex).
fn vertex_check(
    m: &HalfedgeMesh,
    v: usize,
    strictness: Strictness,
    buf: &mut Vec<u32>,
) -> Result<usize, &'static str> {
    let nh = m.n_halfedges();
    let start = m.v_out[v];
    if start == INVALID {
        return Ok(0);
    }
    if m.h_to[start as usize ^ 1] as usize != v {
        return Err("the outgoing halfedge starts at the vertex");
    }
    buf.clear();
    let mut h = start;
    let mut len = 0;
    let mut boundary = 0;
    loop {
        len += 1;
        boundary += usize::from(m.h_face[h as usize] == INVALID);
        if strictness == Strictness::Raw {
            buf.push(m.h_to[h as usize]);
        }
        h = m.h_prev[h as usize] ^ 1;
        if h == start || len > nh {
            break;
        }
    }
    if boundary > 0 && m.h_face[start as usize] != INVALID {
        return Err("a boundary vertex's outgoing halfedge is a boundary one");
    }
    if strictness == Strictness::Raw {
        if boundary > 1 {
            return Err("a vertex has at most one outgoing boundary halfedge");
        }
        if has_repeat(buf) {
            return Err("two vertices are joined by at most one edge");
        }
    }
    Ok(len)
}

/// Checks the invariants of `strictness`, reporting the first element at fault.
///
/// Passes, each over all elements of one kind, in this order: the arrays' lengths;
/// links in range (halfedges, faces, vertices); per halfedge; per face; per vertex.
/// O(H) work (O(H log H) at worst for [`Strictness::Raw`] on vertices of valence above
/// 16), in parallel.
pub(crate) fn validate(m: &HalfedgeMesh, strictness: Strictness) -> Result<(), TopologyError> {
    check_lengths(m)?;
    // Ranges first, so that the structural checks below never index out of bounds.
    check_ranges(m)?;
    // Per halfedge. Afterwards `next` is a permutation with inverse `prev` (prev ∘ next
    // is the identity on a finite set), so every walk below closes.
    if let Some((h, invariant)) = first_fault(m.n_halfedges(), |h| halfedge_fault(m, h)) {
        return fail(HalfedgeId::from_index(h), invariant);
    }
    check_faces(m, strictness)?;
    check_vertices(m, strictness)
}

/// The arrays' lengths: an even number of halfedges, one entry per halfedge in each
/// halfedge array.
fn check_lengths(m: &HalfedgeMesh) -> Result<(), TopologyError> {
    let nh = m.n_halfedges();
    if !nh.is_multiple_of(2) {
        return Err(TopologyError::Integrity {
            element: "mesh".into(),
            invariant: "the number of halfedges is even",
        });
    }
    if m.h_next.len() != nh || m.h_prev.len() != nh || m.h_face.len() != nh {
        return Err(TopologyError::Integrity {
            element: "mesh".into(),
            invariant: "every halfedge array has one entry per halfedge",
        });
    }
    Ok(())
}

/// Every link in range: halfedges, then faces, then vertices.
fn check_ranges(m: &HalfedgeMesh) -> Result<(), TopologyError> {
    let nh = m.n_halfedges();
    let (nv, nf) = (m.n_vertices(), m.n_faces());
    let in_range = |i: usize| {
        let ok = (m.h_to[i] as usize) < nv
            && (m.h_next[i] as usize) < nh
            && (m.h_prev[i] as usize) < nh
            && (m.h_face[i] == INVALID || (m.h_face[i] as usize) < nf);
        (!ok).then_some("links are in range")
    };
    // The common case (all in range) is settled by maxima, which vectorise; the
    // element-by-element scan runs only to name the culprit.
    let max = |a: &[u32]| {
        a.par_chunks(CHUNK)
            .map(|c| c.iter().copied().max().unwrap_or(0))
            .max()
    };
    // A boundary halfedge's face is `INVALID`, which wraps to 0.
    let max_face = m
        .h_face
        .par_chunks(CHUNK)
        .map(|c| c.iter().map(|f| f.wrapping_add(1)).max().unwrap_or(0))
        .max();
    let all_in_range = max(&m.h_to).is_none_or(|x| (x as usize) < nv)
        && max(&m.h_next).is_none_or(|x| (x as usize) < nh)
        && max(&m.h_prev).is_none_or(|x| (x as usize) < nh)
        && max_face.is_none_or(|x| x as usize <= nf);
    if !all_in_range && let Some((h, invariant)) = first_fault(nh, in_range) {
        return fail(HalfedgeId::from_index(h), invariant);
    }
    if let Some((f, invariant)) = first_fault(nf, |f| {
        (m.f_he[f] as usize >= nh).then_some("links are in range")
    }) {
        return fail(FaceId::from_index(f), invariant);
    }
    if let Some((v, invariant)) = first_fault(nv, |v| {
        (m.v_out[v] != INVALID && m.v_out[v] as usize >= nh).then_some("links are in range")
    }) {
        return fail(VertexId::from_index(v), invariant);
    }

    Ok(())
}

/// Per face (the first fault in order), then with [`Strictness::Raw`] that every
/// halfedge lies on the cycle of the face it names.
fn check_faces(m: &HalfedgeMesh, strictness: Strictness) -> Result<(), TopologyError> {
    let nh = m.n_halfedges();
    let nf = m.n_faces();
    // Per face, with the total length of the face cycles.
    let (cycles, fault) = sum_or_fault(nf, |f, buf| face_check(m, f, strictness, buf));
    if let Some((f, invariant)) = fault {
        return fail(FaceId::from_index(f), invariant);
    }
    if strictness == Strictness::Raw {
        let inner = m.h_face.par_iter().filter(|&&f| f != INVALID).count();
        if cycles != inner {
            // Some halfedge names a face whose cycle does not pass through it.
            let mut on_cycle = vec![false; nh];
            for f in 0..nf {
                let start = m.f_he[f];
                let mut h = start;
                loop {
                    on_cycle[h as usize] = true;
                    h = m.h_next[h as usize];
                    if h == start {
                        break;
                    }
                }
            }
            let h = (0..nh)
                .find(|&h| m.h_face[h] != INVALID && !on_cycle[h])
                .unwrap_or(0);
            return fail(
                HalfedgeId::from_index(h),
                "a halfedge lies on the cycle of its face",
            );
        }
    }

    Ok(())
}

/// Per vertex: the circulations cover every vertex's outgoing halfedges, by the rules
/// of `strictness`.
fn check_vertices(m: &HalfedgeMesh, strictness: Strictness) -> Result<(), TopologyError> {
    let nh = m.n_halfedges();
    let nv = m.n_vertices();
    // Per vertex. Rotating an outgoing halfedge is a permutation of the halfedges, and
    // distinct vertices have disjoint circulations, so the circulations cover every
    // halfedge exactly when each vertex's covers all its outgoing halfedges.
    let (covered, fault) = sum_or_fault(nv, |v, buf| vertex_check(m, v, strictness, buf));
    if covered != nh || fault.is_some() {
        // Find the first vertex at fault by the element-by-element rules.
        sequential_vertex_check(m)?;
        let (v, invariant) =
            fault.unwrap_or((0, "circulation visits every outgoing halfedge once"));
        return fail(VertexId::from_index(v), invariant);
    }
    Ok(())
}

/// The vertex rules of [`HalfedgeMesh::check_integrity`] one vertex at a time, with
/// every vertex's degree: the first vertex at fault in index order.
fn sequential_vertex_check(m: &HalfedgeMesh) -> Result<(), TopologyError> {
    let nv = m.n_vertices();
    let mut degree = vec![0usize; nv];
    let mut has_boundary_out = vec![false; nv];
    for h in m.halfedges() {
        let v = m.from_vertex(h).index();
        degree[v] += 1;
        has_boundary_out[v] |= m.is_boundary_halfedge(h);
    }
    for v in m.vertices() {
        match m.outgoing_halfedge(v) {
            None if degree[v.index()] == 0 => {}
            None => return fail(v, "a vertex with edges has an outgoing halfedge"),
            Some(h) => {
                if m.from_vertex(h) != v {
                    return fail(v, "the outgoing halfedge starts at the vertex");
                }
                if has_boundary_out[v.index()] && !m.is_boundary_halfedge(h) {
                    return fail(v, "a boundary vertex's outgoing halfedge is a boundary one");
                }
                let d = degree[v.index()];
                if m.halfedges_around_vertex(v).take(d + 1).count() != d {
                    return fail(v, "circulation visits every outgoing halfedge once");
                }
            }
        }
    }
    Ok(())
}

impl HalfedgeMesh {
    /// Checks every invariant of the structure. A mesh built by this crate always
    /// passes; the check exists for tests and for code that extends the crate.
    ///
    /// Invariants: links are in range; `next` and `prev` are inverse; a halfedge and its
    /// successor share a face (or are both boundary) and meet at a vertex; twins run
    /// between the same two vertices in opposite directions and are never both boundary;
    /// every face's halfedge belongs to it and its cycle has at least 3 halfedges; every
    /// non-isolated vertex's outgoing halfedge starts at it, and is a boundary halfedge
    /// whenever the vertex has one; circulating a vertex visits all its outgoing halfedges.
    ///
    /// The check runs on rayon's threads; the element it names does not depend on their
    /// number.
    ///
    /// # Errors
    /// [`TopologyError::Integrity`] naming the first element that breaks an invariant.
    ///
    /// # Complexity
    /// O(V + H + F).
    pub fn check_integrity(&self) -> Result<(), TopologyError> {
        validate(self, Strictness::Links)
    }
}

#[cfg(test)]
mod tests {
    use crate::HalfedgeMesh;
    use crate::error::TopologyError;

    fn quad() -> HalfedgeMesh {
        HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [0, 2, 3]]).unwrap()
    }

    fn message(mesh: &HalfedgeMesh) -> String {
        match mesh.check_integrity() {
            Err(e @ TopologyError::Integrity { .. }) => e.to_string(),
            other => panic!("expected an integrity error, got {other:?}"),
        }
    }

    #[test]
    fn a_valid_mesh_passes() {
        quad().check_integrity().unwrap();
    }

    #[test]
    fn broken_next_is_found() {
        let mut m = quad();
        m.h_next.swap(0, 2);
        assert_eq!(
            message(&m),
            "integrity violated at halfedge 0: prev(next(h)) == h"
        );
    }

    #[test]
    fn interior_outgoing_at_a_boundary_vertex_is_found() {
        let mut m = quad();
        // Vertex 0 is on the boundary; point it at its interior outgoing halfedge 0 -> 1.
        m.v_out[0] = 0;
        assert_eq!(
            message(&m),
            "integrity violated at vertex 0: a boundary vertex's outgoing halfedge is a boundary one"
        );
    }

    #[test]
    fn wrong_face_halfedge_is_found() {
        let mut m = quad();
        m.f_he[0] = m.f_he[1];
        assert_eq!(
            message(&m),
            "integrity violated at face 0: the face's halfedge belongs to the face"
        );
    }

    #[test]
    fn out_of_range_links_are_found_without_panicking() {
        let mut m = quad();
        m.h_to[3] = 99;
        assert_eq!(
            message(&m),
            "integrity violated at halfedge 3: links are in range"
        );
        let mut m = quad();
        m.h_next[5] = 1000;
        assert_eq!(
            message(&m),
            "integrity violated at halfedge 5: links are in range"
        );
        let mut m = quad();
        m.v_out[2] = 1000;
        assert_eq!(
            message(&m),
            "integrity violated at vertex 2: links are in range"
        );
    }
}
