//! The rows' slots from the mesh: each row's neighbours (and, when needed, halfedges)
//! in counter-clockwise one-ring order, and which slots have a triangle on their left.

use beltrami_halfedge::{HalfedgeId, HalfedgeMesh, VertexId};
use rayon::prelude::*;

use crate::PAR_CHUNK;

/// Calls `visit(s, h)` for every slot `s` in `start..end` with its halfedge `h` (row
/// `i`'s slots are its outgoing halfedges, counter-clockwise from the mesh's outgoing
/// halfedge of `i`, at `offsets[i]..offsets[i + 1]`).
fn for_slots(
    mesh: &HalfedgeMesh,
    offsets: &[u32],
    start: usize,
    end: usize,
    mut visit: impl FnMut(usize, HalfedgeId),
) {
    if start >= end {
        return;
    }
    // The last row that starts at or before `start` (rows without slots share their
    // offset with the next row, which is the one that holds `start`).
    let mut row = offsets.partition_point(|&o| o as usize <= start) - 1;
    let mut s = offsets[row] as usize;
    while s < end {
        for h in mesh.halfedges_around_vertex(VertexId::new(row as u32)) {
            if (start..end).contains(&s) {
                visit(s, h);
            }
            s += 1;
        }
        row += 1;
    }
}

/// The row offsets (`n + 1` entries from 0) and every slot's neighbour, in parallel
/// with fixed chunks.
///
/// # Panics
/// Never: row offsets are sums of halfedge counts, which fit in `u32` as the ids do.
pub(super) fn rows(mesh: &HalfedgeMesh) -> (Vec<u32>, Vec<u32>) {
    let n = mesh.n_vertices();
    let valences: Vec<u32> = (0..n)
        .into_par_iter()
        .with_min_len(PAR_CHUNK)
        .map(|v| {
            mesh.halfedges_around_vertex(VertexId::new(v as u32))
                .count() as u32
        })
        .collect();
    let mut offsets = Vec::with_capacity(n + 1);
    let mut total: u32 = 0;
    offsets.push(0);
    for &d in &valences {
        total = total.checked_add(d).expect("halfedge ids are u32");
        offsets.push(total);
    }
    drop(valences);
    let mut neighbours = vec![0u32; total as usize];
    // Fixed-size chunks of slots; each fills the parts of the rows it overlaps.
    neighbours
        .par_chunks_mut(PAR_CHUNK)
        .enumerate()
        .for_each(|(c, nb)| {
            let start = c * PAR_CHUNK;
            for_slots(mesh, &offsets, start, start + nb.len(), |s, h| {
                nb[s - start] = mesh.to_vertex(h).raw();
            });
        });
    (offsets, neighbours)
}

/// Every slot's halfedge id, in parallel with fixed chunks.
pub(super) fn slot_halfedges(mesh: &HalfedgeMesh, offsets: &[u32]) -> Vec<u32> {
    slot_values(mesh, offsets, |h| h.raw())
}

/// `value(h)` of every slot's halfedge `h`, in parallel with fixed chunks.
pub(super) fn slot_values<T, F>(mesh: &HalfedgeMesh, offsets: &[u32], value: F) -> Vec<T>
where
    T: Copy + Default + Send,
    F: Fn(HalfedgeId) -> T + Sync,
{
    let total = offsets.last().map_or(0, |&t| t as usize);
    let mut values = vec![T::default(); total];
    values
        .par_chunks_mut(PAR_CHUNK)
        .enumerate()
        .for_each(|(c, out)| {
            let start = c * PAR_CHUNK;
            for_slots(mesh, offsets, start, start + out.len(), |s, h| {
                out[s - start] = value(h);
            });
        });
    values
}

/// Whether some row lists a neighbour twice (two vertices joined by more than one
/// edge), where a neighbour does not name the slot's halfedge.
pub(super) fn has_repeated_neighbour(offsets: &[u32], neighbours: &[u32]) -> bool {
    offsets
        .par_windows(2)
        .with_min_len(PAR_CHUNK)
        .any(|w| repeats(&neighbours[w[0] as usize..w[1] as usize]))
}

/// Whether `row` holds a value twice.
fn repeats(row: &[u32]) -> bool {
    if row.len() <= 32 {
        return row
            .iter()
            .enumerate()
            .any(|(k, j)| row[k + 1..].contains(j));
    }
    let mut sorted = row.to_vec();
    sorted.sort_unstable();
    sorted.windows(2).any(|w| w[0] == w[1])
}

/// Bit `s` (word `s / 64`, bit `s % 64`) set when the face on the left of slot `s`'s
/// halfedge is a triangle — on a mesh's triangle the third vertex after the row's
/// vertex and its neighbour `k` is its neighbour `k + 1` (cyclically), so this is all
/// the cotangent kernel needs besides the rows. In parallel with fixed chunks (of whole
/// words).
pub(super) fn ring_triangles(mesh: &HalfedgeMesh, offsets: &[u32]) -> Vec<u64> {
    const WORDS: usize = PAR_CHUNK / 64;
    let total = offsets.last().map_or(0, |&t| t as usize);
    let mut bits = vec![0u64; total.div_ceil(64)];
    bits.par_chunks_mut(WORDS)
        .enumerate()
        .for_each(|(c, words)| {
            let start = c * WORDS * 64;
            let end = (start + 64 * words.len()).min(total);
            for_slots(mesh, offsets, start, end, |s, h| {
                let triangle = mesh.face(h).is_some() && mesh.next(mesh.next(mesh.next(h))) == h;
                words[(s - start) / 64] |= u64::from(triangle) << ((s - start) % 64);
            });
        });
    bits
}

/// Whether bit `s` of `bits` is set (see [`ring_triangles`]).
#[inline(always)]
pub(super) fn bit(bits: &[u64], s: usize) -> bool {
    (bits[s / 64] >> (s % 64)) & 1 != 0
}

/// The code of a slot whose left face is not a triangle (see [`slot_corners`]).
pub(super) const NO_TRIANGLE: u8 = 3;

/// Two bits per slot `s` (word `s / 32`, bits `2 (s % 32)` and up): where the row's
/// vertex `i` stands in the face on the left of slot `s` — the triangle `i`, `n_k`,
/// `n_{k+1}` (its neighbours `k` and `k + 1`, cyclically; see [`ring_triangles`]) —
/// counted in face order from the face's first vertex: 0 (the face is `i, n_k,
/// n_{k+1}`), 1 (`n_{k+1}, i, n_k`) or 2 (`n_k, n_{k+1}, i`); [`NO_TRIANGLE`] when the
/// face is not a triangle or there is none. With the rows this gives every triangle
/// around a vertex in face order, which is what a vertex area needs without the mesh.
/// In parallel with fixed chunks (of whole words).
pub(super) fn slot_corners(mesh: &HalfedgeMesh, offsets: &[u32]) -> Vec<u64> {
    const WORDS: usize = PAR_CHUNK / 32;
    let total = offsets.last().map_or(0, |&t| t as usize);
    let mut bits = vec![0u64; total.div_ceil(32)];
    bits.par_chunks_mut(WORDS)
        .enumerate()
        .for_each(|(c, words)| {
            let start = c * WORDS * 32;
            let end = (start + 32 * words.len()).min(total);
            for_slots(mesh, offsets, start, end, |s, h| {
                let code = match mesh.face(h) {
                    Some(f) if mesh.next(mesh.next(mesh.next(h))) == h => {
                        let first = mesh.face_halfedge(f);
                        if first == mesh.prev(h) {
                            0
                        } else if first == mesh.next(h) {
                            1
                        } else {
                            2
                        }
                    }
                    _ => NO_TRIANGLE,
                };
                words[(s - start) / 32] |= u64::from(code) << (2 * ((s - start) % 32));
            });
        });
    bits
}

/// The two-bit code of slot `s` (see [`slot_corners`]).
#[inline(always)]
pub(super) fn corner_code(codes: &[u64], s: usize) -> u8 {
    ((codes[s / 32] >> (2 * (s % 32))) & 3) as u8
}

#[cfg(test)]
mod tests {
    use super::*;
    use beltrami_halfedge::primitives;

    #[test]
    fn repeated_neighbours_are_found_in_short_and_long_rows() {
        assert!(!repeats(&[1, 2, 3]));
        assert!(repeats(&[1, 2, 1]));
        let long: Vec<u32> = (0..100).collect();
        assert!(!repeats(&long));
        let mut twice = long.clone();
        twice.push(57);
        assert!(repeats(&twice));
    }

    /// On a triangle mesh a slot's left face is a triangle exactly when it is not a
    /// boundary halfedge, and its third vertex is the row's next neighbour.
    #[test]
    fn triangle_bits_mark_the_faces_of_the_ring() {
        for mesh in [
            primitives::grid(5, 4).mesh().unwrap(),
            primitives::icosphere(2).mesh().unwrap(),
        ] {
            let (offsets, neighbours) = rows(&mesh);
            let bits = ring_triangles(&mesh, &offsets);
            let halfedges = slot_halfedges(&mesh, &offsets);
            for i in 0..mesh.n_vertices() {
                let (a, b) = (offsets[i] as usize, offsets[i + 1] as usize);
                for s in a..b {
                    let h = HalfedgeId::new(halfedges[s]);
                    assert_eq!(neighbours[s], mesh.to_vertex(h).raw());
                    assert_eq!(bit(&bits, s), !mesh.is_boundary_halfedge(h));
                    if bit(&bits, s) {
                        let next = if s + 1 == b { a } else { s + 1 };
                        assert_eq!(mesh.to_vertex(mesh.next(h)).raw(), neighbours[next]);
                    }
                }
            }
        }
    }
}
