//! Exact vertex welding for triangle soups.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hash, Hasher};

use beltrami_halfedge::MAX_ELEMENTS;
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
