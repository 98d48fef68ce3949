//! Garbage collection: removes the elements marked deleted, compacts every array and
//! every property, and returns the old → new id maps.

use super::storage::EditMesh;
use crate::ids::{EdgeId, ElementId, FaceId, HalfedgeId, VertexId};
use crate::map::IdMap;
use crate::mesh::INVALID;

/// The id maps of one [`garbage_collection`](EditMesh::garbage_collection): for every
/// element slot before it, the element's new id, or `None` if it was deleted. Live
/// elements keep their relative order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GarbageMaps {
    /// Old vertex → new vertex.
    pub vertices: IdMap<VertexId, Option<VertexId>>,
    /// Old halfedge → new halfedge (`2e + i` → `2e' + i`: a halfedge keeps its side).
    pub halfedges: IdMap<HalfedgeId, Option<HalfedgeId>>,
    /// Old edge → new edge.
    pub edges: IdMap<EdgeId, Option<EdgeId>>,
    /// Old face → new face.
    pub faces: IdMap<FaceId, Option<FaceId>>,
}

impl GarbageMaps {
    /// Whether nothing moved: every old id maps to itself.
    #[must_use]
    pub fn is_identity(&self) -> bool {
        fn same<I: ElementId>(m: &IdMap<I, Option<I>>) -> bool {
            m.iter().all(|(old, new)| *new == Some(old))
        }
        same(&self.vertices) && same(&self.halfedges) && same(&self.edges) && same(&self.faces)
    }
}

/// Old → new raw indices for one kind (`INVALID` for deleted slots).
fn compaction(deleted: &[bool]) -> Vec<u32> {
    let mut next = 0u32;
    deleted
        .iter()
        .map(|&d| {
            if d {
                INVALID
            } else {
                next += 1;
                next - 1
            }
        })
        .collect()
}

fn remap(raw: u32, map: &[u32]) -> u32 {
    if raw == INVALID {
        INVALID
    } else {
        map[raw as usize]
    }
}

fn to_ids<I: ElementId>(map: &[u32]) -> IdMap<I, Option<I>> {
    IdMap::from_vec(
        map.iter()
            .map(|&r| (r != INVALID).then(|| I::from_index(r as usize)))
            .collect(),
    )
}

/// The live connectivity renumbered `0..n`, and the raw old → new maps.
pub(crate) struct Compacted {
    pub(crate) v_out: Vec<u32>,
    pub(crate) v_pos: Vec<glam::DVec3>,
    pub(crate) h_to: Vec<u32>,
    pub(crate) h_next: Vec<u32>,
    pub(crate) h_prev: Vec<u32>,
    pub(crate) h_face: Vec<u32>,
    pub(crate) f_he: Vec<u32>,
    vmap: Vec<u32>,
    hmap: Vec<u32>,
    emap: Vec<u32>,
    fmap: Vec<u32>,
}

impl EditMesh {
    /// The live connectivity and positions, renumbered; the mesh is not changed.
    pub(crate) fn compacted(&self) -> Compacted {
        let vmap = compaction(&self.v_deleted);
        let emap = compaction(&self.e_deleted);
        let fmap = compaction(&self.f_deleted);
        let hmap: Vec<u32> = emap
            .iter()
            .flat_map(|&e| {
                if e == INVALID {
                    [INVALID, INVALID]
                } else {
                    [2 * e, 2 * e + 1]
                }
            })
            .collect();
        let keep_v: Vec<bool> = self.v_deleted.iter().map(|d| !d).collect();
        let keep_h: Vec<bool> = self.e_deleted.iter().flat_map(|&d| [!d, !d]).collect();
        let keep_f: Vec<bool> = self.f_deleted.iter().map(|d| !d).collect();
        Compacted {
            v_out: retain_mapped(&self.v_out, &keep_v, &hmap),
            v_pos: retain(&self.v_pos, &keep_v),
            h_to: retain_mapped(&self.h_to, &keep_h, &vmap),
            h_next: retain_mapped(&self.h_next, &keep_h, &hmap),
            h_prev: retain_mapped(&self.h_prev, &keep_h, &hmap),
            h_face: retain_mapped(&self.h_face, &keep_h, &fmap),
            f_he: retain_mapped(&self.f_he, &keep_f, &hmap),
            vmap,
            hmap,
            emap,
            fmap,
        }
    }

    /// Removes every element marked deleted: the live elements are renumbered
    /// `0..n` in their previous order, all links, positions and property values move
    /// with them, and the returned maps tell where each old id went. Property handles
    /// keep working; ids held outside the mesh must be translated through the maps.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{DVec3, EditMesh, VertexId};
    /// let mut mesh = EditMesh::new();
    /// let v: Vec<VertexId> = (0..4).map(|i| mesh.add_vertex(DVec3::splat(i as f64))).collect();
    /// let f = mesh.add_face(&[v[0], v[1], v[2]])?;
    /// mesh.add_face(&[v[0], v[2], v[3]])?;
    /// mesh.delete_face(f)?; // vertex 1 is left isolated and goes too
    /// let maps = mesh.garbage_collection();
    /// assert_eq!(maps.vertices[v[1]], None);
    /// assert_eq!(maps.vertices[v[3]], Some(VertexId::new(2)));
    /// assert_eq!(mesh.position(VertexId::new(2)), DVec3::splat(3.0));
    /// # Ok::<(), beltrami_halfedge::EditError>(())
    /// ```
    ///
    /// # Complexity
    /// O(V + E + F) plus the size of the properties.
    pub fn garbage_collection(&mut self) -> GarbageMaps {
        let c = self.compacted();
        let maps = GarbageMaps {
            vertices: to_ids(&c.vmap),
            halfedges: to_ids(&c.hmap),
            edges: to_ids(&c.emap),
            faces: to_ids(&c.fmap),
        };
        if !self.has_garbage() {
            return maps;
        }
        let keep_v: Vec<bool> = self.v_deleted.iter().map(|d| !d).collect();
        let keep_e: Vec<bool> = self.e_deleted.iter().map(|d| !d).collect();
        let keep_h: Vec<bool> = keep_e.iter().flat_map(|&k| [k, k]).collect();
        let keep_f: Vec<bool> = self.f_deleted.iter().map(|d| !d).collect();
        self.props.vertex().retain(&keep_v);
        self.props.halfedge().retain(&keep_h);
        self.props.edge().retain(&keep_e);
        self.props.face().retain(&keep_f);

        self.v_deleted = vec![false; c.v_out.len()];
        self.e_deleted = vec![false; c.h_to.len() / 2];
        self.f_deleted = vec![false; c.f_he.len()];
        self.v_out = c.v_out;
        self.v_pos = c.v_pos;
        self.h_to = c.h_to;
        self.h_next = c.h_next;
        self.h_prev = c.h_prev;
        self.h_face = c.h_face;
        self.f_he = c.f_he;
        self.deleted_vertices = 0;
        self.deleted_edges = 0;
        self.deleted_faces = 0;
        maps
    }
}

fn retain<T: Copy>(values: &[T], keep: &[bool]) -> Vec<T> {
    values
        .iter()
        .zip(keep)
        .filter_map(|(v, &k)| k.then_some(*v))
        .collect()
}

fn retain_mapped(values: &[u32], keep: &[bool], map: &[u32]) -> Vec<u32> {
    values
        .iter()
        .zip(keep)
        .filter(|&(_, &k)| k)
        .map(|(&v, _)| remap(v, map))
        .collect()
}
