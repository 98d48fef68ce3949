//! Building a [`HalfedgeMesh`] from its raw connectivity arrays, validated in O(n).

use std::sync::atomic::{AtomicU32, Ordering};

use rayon::prelude::*;

use crate::build::check_count;
use crate::error::TopologyError;
use crate::ids::{ElementId, HalfedgeId};
use crate::integrity::{Strictness, validate};
use crate::mesh::{HalfedgeMesh, INVALID};

/// The connectivity arrays of a half-edge mesh, for code that computes a mesh's
/// connectivity directly (a subdivision step, a converter) instead of through a face
/// list. [`HalfedgeMesh::from_raw_parts`] validates them into a mesh;
/// [`HalfedgeMesh::into_raw_parts`] gives them back.
///
/// Every link is a `u32` index; [`RawConnectivity::NONE`] marks an absent one. The
/// conventions are those of [`HalfedgeMesh`]:
/// - edge `e` owns halfedges `2e` and `2e + 1`, twins of each other, so the edges are
///   implicit and `h_to` has an even length;
/// - `h_to[h]` is the vertex `h` points to, so `h` starts at `h_to[h ^ 1]`;
/// - `h_next[h]` is the next halfedge along the face of `h`, or along its boundary loop
///   (the previous-halfedge links are derived);
/// - `h_face[h]` is the face of `h`, `NONE` for a boundary halfedge;
/// - `f_he[f]` is one halfedge of face `f`: the face's first vertex is the one it
///   points to ([`HalfedgeMesh::vertices_around_face`] starts after it);
/// - `v_out[v]` is a halfedge leaving `v`, a boundary one if `v` has one, `NONE` for an
///   isolated vertex.
///
/// The arrays are public: a value of this type is just data, and carries no promise.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RawConnectivity {
    /// An outgoing halfedge per vertex (`NONE` for an isolated vertex).
    pub v_out: Vec<u32>,
    /// The target vertex per halfedge.
    pub h_to: Vec<u32>,
    /// The next halfedge per halfedge.
    pub h_next: Vec<u32>,
    /// The face per halfedge (`NONE` on the boundary).
    pub h_face: Vec<u32>,
    /// One halfedge per face, the one that ends at the face's first vertex.
    pub f_he: Vec<u32>,
}

impl RawConnectivity {
    /// The absent link: an isolated vertex's `v_out`, a boundary halfedge's `h_face`.
    pub const NONE: u32 = INVALID;
}

impl HalfedgeMesh {
    /// Builds a mesh from raw connectivity arrays, checking every invariant a
    /// [`HalfedgeMesh`] promises, in O(n): the arrays are accepted exactly when they
    /// describe an oriented 2-manifold mesh (with boundary) that
    /// [`from_polygons`](Self::from_polygons) could also build from a face list.
    ///
    /// The invariants, checked in passes in this order (each pass names its
    /// lowest-numbered element at fault, whatever the number of threads):
    /// 1. counts fit in `u32` handles; `h_to`, `h_next` and `h_face` have the same even
    ///    length; no two halfedges have the same `next` (so `next` is a permutation, and
    ///    `prev` is derived as its inverse);
    /// 2. every link is in range;
    /// 3. per halfedge: `next(h)` starts where `h` ends and lies in the same face (or on
    ///    the boundary too); `h` joins two different vertices; an edge has a face on at
    ///    least one side;
    /// 4. per face: `f_he[f]` lies in face `f`; the face's cycle has at least 3
    ///    halfedges and lists each vertex once; every halfedge of a face lies on that
    ///    face's cycle;
    /// 5. per vertex: `v_out[v]` starts at `v`; circulating `v` visits all its outgoing
    ///    halfedges (one fan); `v_out[v]` is a boundary halfedge when `v` has one, and `v`
    ///    has at most one; no two edges join the same two vertices; `v_out[v]` is `NONE`
    ///    exactly for a vertex without edges.
    ///
    /// Nothing else is required: any numbering of vertices, edges and faces, either
    /// direction of an edge as `2e`, any outgoing halfedge of an interior vertex is a
    /// valid mesh. A builder that wants the result of
    /// [`from_polygons`](Self::from_polygons) must follow its numbering rules itself
    /// (edges by first appearance in the face list, `f_he` ending at each face's first
    /// vertex, an interior vertex's `v_out` in its last face).
    ///
    /// # Errors
    /// [`TopologyError::TooManyElements`] for more elements than `u32` handles address;
    /// otherwise [`TopologyError::Integrity`] naming the element (`"halfedge 12"`,
    /// `"face 3"`, `"vertex 7"` or `"mesh"`) and the invariant that fails.
    ///
    /// # Complexity
    /// O(V + H + F) time and memory (valences above 16 add a sort of their ring). The
    /// `prev` links are derived and the checks run on rayon's threads; the result, and
    /// the error on bad input, do not depend on their number.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{HalfedgeMesh, RawConnectivity, TopologyError};
    ///
    /// let quad = HalfedgeMesh::from_polygons(4, [[0u32, 1, 2], [0, 2, 3]])?;
    /// let raw = quad.clone().into_raw_parts();
    /// assert_eq!(HalfedgeMesh::from_raw_parts(raw.clone())?, quad);
    ///
    /// // A halfedge that points back to where it starts is refused.
    /// let mut bad = raw;
    /// bad.h_to[0] = bad.h_to[1];
    /// assert!(matches!(
    ///     HalfedgeMesh::from_raw_parts(bad),
    ///     Err(TopologyError::Integrity { .. })
    /// ));
    /// # Ok::<(), TopologyError>(())
    /// ```
    pub fn from_raw_parts(raw: RawConnectivity) -> Result<Self, TopologyError> {
        let RawConnectivity {
            v_out,
            h_to,
            h_next,
            h_face,
            f_he,
        } = raw;
        check_count("vertices", v_out.len())?;
        check_count("halfedges", h_to.len())?;
        check_count("faces", f_he.len())?;
        let nh = h_to.len();
        if h_next.len() != nh || h_face.len() != nh {
            return Err(TopologyError::Integrity {
                element: "mesh".into(),
                invariant: "every halfedge array has one entry per halfedge",
            });
        }
        if nh % 2 != 0 {
            return Err(TopologyError::Integrity {
                element: "mesh".into(),
                invariant: "the number of halfedges is even",
            });
        }
        let h_prev = invert_next(&h_next);
        let mesh = HalfedgeMesh {
            v_out,
            h_to,
            h_next,
            h_prev,
            h_face,
            f_he,
        };
        if let Err(err) = validate(&mesh, Strictness::Raw) {
            // When `next` is no permutation, `invert_next` guessed; name that fault.
            check_next(&mesh.h_next)?;
            return Err(err);
        }
        Ok(mesh)
    }

    /// The connectivity arrays of this mesh (the `prev` links, derived, are dropped).
    /// [`from_raw_parts`](Self::from_raw_parts) of the result gives this mesh back.
    ///
    /// # Complexity
    /// O(1): the arrays are moved.
    #[must_use]
    pub fn into_raw_parts(self) -> RawConnectivity {
        RawConnectivity {
            v_out: self.v_out,
            h_to: self.h_to,
            h_next: self.h_next,
            h_face: self.h_face,
            f_he: self.f_he,
        }
    }
}

/// The inverse of `next`, in parallel: `prev[next[h]] = h`, an out-of-range `next` left
/// out. Exact when `next` is a permutation; otherwise some entries stay `INVALID` (the
/// halfedges that are nobody's `next`), which validation reports, and
/// [`check_next`] then names the real fault.
pub(crate) fn invert_next(h_next: &[u32]) -> Vec<u32> {
    let nh = h_next.len();
    let prev: Vec<AtomicU32> = (0..nh).map(|_| AtomicU32::new(INVALID)).collect();
    h_next
        .par_iter()
        .enumerate()
        .with_min_len(1 << 12)
        .for_each(|(h, &n)| {
            if let Some(p) = prev.get(n as usize) {
                // Each slot is written once when `next` is a permutation; otherwise one
                // of the writers wins, and the fault is found after validation.
                p.store(h as u32, Ordering::Relaxed);
            }
        });
    prev.into_iter().map(AtomicU32::into_inner).collect()
}

/// The first halfedge whose `next` is out of range or also the `next` of a lower one.
fn check_next(h_next: &[u32]) -> Result<(), TopologyError> {
    let mut taken = vec![false; h_next.len()];
    for (h, &n) in h_next.iter().enumerate() {
        let invariant = match taken.get_mut(n as usize) {
            None => "links are in range",
            Some(true) => "no two halfedges have the same next",
            Some(t) => {
                *t = true;
                continue;
            }
        };
        return Err(TopologyError::Integrity {
            element: format!("{} {}", HalfedgeId::KIND, h),
            invariant,
        });
    }
    Ok(())
}
