//! Vertex welding for triangle soups: exact, then within a tolerance.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};

use beltrami_halfedge::{MAX_ELEMENTS, PolygonList};
use glam::DVec3;

use crate::error::IoError;

/// Merges corners with identical coordinates into one vertex.
///
/// Two corners are the same vertex when their `f32` coordinates have the same bit
/// patterns, except that `-0.0` and `0.0` are the same. Vertex ids follow the order
/// of first appearance; the stored position is the first corner's (with `0.0` for
/// `-0.0`). No tolerance: near-coincident corners stay apart, as the file says.
pub(super) struct Welder {
    ids: HashMap<Key, u32, BuildHasherDefault<KeyHasher>>,
    positions: Vec<DVec3>,
}

impl Welder {
    /// A welder with room for `vertices` vertices.
    pub(super) fn with_capacity(vertices: usize) -> Self {
        Self {
            ids: HashMap::with_capacity_and_hasher(vertices, BuildHasherDefault::default()),
            positions: Vec::with_capacity(vertices),
        }
    }

    /// The id of the vertex at `p` (finite coordinates), new if not seen before.
    pub(super) fn insert(&mut self, p: [f32; 3]) -> Result<u32, IoError> {
        // `c + 0.0` turns -0.0 into 0.0 and leaves every other value unchanged.
        let p = p.map(|c| c + 0.0);
        let key = Key(p.map(f32::to_bits));
        if let Some(&id) = self.ids.get(&key) {
            return Ok(id);
        }
        let id = u32::try_from(self.positions.len())
            .ok()
            .filter(|&id| (id as usize) < MAX_ELEMENTS)
            .ok_or(IoError::TooManyVertices {
                declared: self.positions.len() + 1,
                max: MAX_ELEMENTS,
            })?;
        self.ids.insert(key, id);
        self.positions.push(DVec3::new(
            f64::from(p[0]),
            f64::from(p[1]),
            f64::from(p[2]),
        ));
        Ok(id)
    }

    /// The welded positions, in id order.
    pub(super) fn into_positions(self) -> Vec<DVec3> {
        self.positions
    }
}

/// The result of [`weld_within`].
pub(super) struct Welded {
    /// The kept vertices, in order of first appearance.
    pub(super) positions: Vec<DVec3>,
    /// The triangles on the kept vertices, collapsed ones left out.
    pub(super) faces: PolygonList,
    /// The number of vertices merged into others.
    pub(super) merged: usize,
    /// The triangles (0-based, input order) that collapsed.
    pub(super) dropped: Vec<usize>,
}

/// Merges exactly welded vertices that lie within `distance` (> 0) of each other:
/// in id order, each vertex joins the earliest kept vertex within `distance`
/// (Euclidean), else it is kept. Triangles follow; a triangle with distinct vertices
/// that ends up with a repeated one is dropped (triangles that repeated a vertex
/// before are kept).
///
/// The coordinates are `f32` values (STL), which the neighbour search relies on:
/// kept vertices are hashed by cubic cells of side `4 × distance`, and a vertex
/// looks in the 8 cells that hold every point within `distance` of it. Cell numbers
/// `floor(x / cell)` are exact enough below `2^49`, where a rounding error is at most
/// `1/16` of a cell; beyond, `distance` is below `2^-51 |x|`, less than the spacing of
/// `f32` values near `x`, so that coordinates within `distance` are equal and fall in
/// the same cell. A cell holds at most a few dozen kept vertices, which are more than
/// `distance` apart, and cells that share a hash slot only share a list: the merge
/// takes linear time. Memory beyond the result: 16 bytes per vertex at most.
///
/// # Complexity
/// O(V + T) expected for V vertices and T triangles.
pub(super) fn weld_within(
    mut positions: Vec<DVec3>,
    triangles: &[[u32; 3]],
    distance: f64,
) -> Welded {
    /// No next vertex in a slot's list.
    const END: u32 = u32::MAX;
    let n = positions.len();
    let cell = 4.0 * distance;
    // Hash slots of cells: `slots[h]` is the last kept vertex in a cell hashed to
    // `h`, `next[k]` the kept vertex before `k` in its slot.
    let mask = (2 * n).next_power_of_two().max(16) - 1;
    let mut slots = vec![END; mask + 1];
    let mut next: Vec<u32> = Vec::with_capacity(n);
    let mut map: Vec<u32> = Vec::with_capacity(n);
    let mut kept = 0_usize;
    let mut candidates = Vec::with_capacity(8);
    for i in 0..n {
        let p = positions[i];
        let axes = p.to_array().map(|x| CellRange::of(x, cell));
        candidates.clear();
        for corner in 0..8 {
            let key = CellKey([
                axes[0].key(corner & 1),
                axes[1].key((corner >> 1) & 1),
                axes[2].key(corner >> 2),
            ]);
            let slot = key.slot(mask);
            if !candidates.contains(&slot) {
                candidates.push(slot);
            }
        }
        let mut earliest: Option<u32> = None;
        for &slot in &candidates {
            let mut at = slots[slot];
            while at != END {
                let within = (positions[at as usize] - p).length() <= distance;
                if within && earliest.is_none_or(|e| at < e) {
                    earliest = Some(at);
                }
                at = next[at as usize];
            }
        }
        let id = earliest.unwrap_or_else(|| {
            // Kept vertices move to the front, in order: `kept <= i`.
            positions[kept] = p;
            // Fewer kept vertices than exact ones, which are numbered by `u32`.
            let id = u32::try_from(kept).unwrap_or(END);
            let own = CellKey([axes[0].key(0), axes[1].key(0), axes[2].key(0)]).slot(mask);
            next.push(slots[own]);
            slots[own] = id;
            kept += 1;
            id
        });
        map.push(id);
    }
    drop(slots);
    drop(next);
    positions.truncate(kept);
    let mut faces = PolygonList::with_capacity(triangles.len(), 3 * triangles.len());
    let mut dropped = Vec::new();
    for (t, triangle) in triangles.iter().enumerate() {
        let welded = triangle.map(|v| map[v as usize]);
        if is_degenerate(welded) && !is_degenerate(*triangle) {
            dropped.push(t);
        } else {
            faces.push(&welded);
        }
    }
    Welded {
        positions,
        faces,
        merged: n - kept,
        dropped,
    }
}

fn is_degenerate([a, b, c]: [u32; 3]) -> bool {
    a == b || b == c || a == c
}

/// The cells of one axis that hold every point within a quarter cell of `x`: its own
/// and the nearer neighbour.
#[derive(Clone, Copy)]
struct CellRange {
    /// The cell number `floor(x / cell)`, or `None` when it overflows (a tolerance
    /// tiny against the coordinate: then only equal coordinates are within it).
    floor: Option<f64>,
    /// The neighbour on the side `x` is nearer: -1 or +1.
    side: f64,
    /// The coordinate's bits, the key when `floor` overflows.
    bits: u64,
}

impl CellRange {
    fn of(x: f64, cell: f64) -> Self {
        let q = x / cell;
        let floor = q.floor();
        Self {
            floor: floor.is_finite().then_some(floor),
            side: if q - floor >= 0.5 { 1.0 } else { -1.0 },
            bits: (x + 0.0).to_bits(),
        }
    }

    /// The key of its own cell (`i = 0`) or of the nearer neighbour (`i = 1`).
    fn key(self, i: usize) -> u64 {
        match self.floor {
            // `+ 0.0` makes -0.0 the key of 0.0.
            Some(floor) => (floor + if i == 0 { 0.0 } else { self.side } + 0.0).to_bits(),
            None => self.bits,
        }
    }
}

/// A cell of the grid of [`weld_within`]: per axis, the bits of its number.
#[derive(Clone, Copy, PartialEq, Eq)]
struct CellKey([u64; 3]);

impl CellKey {
    /// Its slot in a table of `mask + 1` slots (a power of two).
    fn slot(self, mask: usize) -> usize {
        let mut hasher = KeyHasher::default();
        for word in self.0 {
            hasher.write_u64(word);
        }
        // The low bits of the finished hash depend on every input bit.
        (hasher.finish() as usize) & mask
    }
}

/// Coordinate bit patterns.
#[derive(Clone, Copy, PartialEq, Eq)]
struct Key([u32; 3]);

impl Hash for Key {
    fn hash<H: Hasher>(&self, state: &mut H) {
        state.write_u64(u64::from(self.0[0]) | (u64::from(self.0[1]) << 32));
        state.write_u32(self.0[2]);
    }
}

/// A fast hasher for [`Key`]: multiply-rotate mixing, then the MurmurHash3
/// finaliser so that the low bits (the table index) depend on every input bit —
/// coordinates such as `1.0` or `0.5` have all-zero low mantissa bits.
#[derive(Default)]
struct KeyHasher(u64);

impl KeyHasher {
    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(23) ^ word).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
}

impl Hasher for KeyHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.add(u64::from(b));
        }
    }
    fn write_u32(&mut self, word: u32) {
        self.add(u64::from(word));
    }
    fn write_u64(&mut self, word: u64) {
        self.add(word);
    }
    fn finish(&self) -> u64 {
        let mut h = self.0;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ (h >> 33)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn welds_identical_bits_and_signed_zeros() -> Result<(), IoError> {
        let mut w = Welder::with_capacity(4);
        assert_eq!(w.insert([0.0, 1.0, 2.0])?, 0);
        assert_eq!(w.insert([1.0, 1.0, 2.0])?, 1);
        assert_eq!(w.insert([-0.0, 1.0, 2.0])?, 0);
        // The next float after 1.0 is a different vertex: no tolerance.
        assert_eq!(
            w.insert([f32::from_bits(1.0f32.to_bits() + 1), 1.0, 2.0])?,
            2
        );
        let positions = w.into_positions();
        assert_eq!(positions.len(), 3);
        assert!(positions[0].x.is_sign_positive());
        Ok(())
    }
}
