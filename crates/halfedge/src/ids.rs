//! Typed element handles: `u32` newtypes for vertices, halfedges, edges and faces.

use std::fmt;

/// An element handle that can be stored in an [`IdMap`](crate::IdMap).
///
/// Implemented by [`VertexId`], [`HalfedgeId`], [`EdgeId`] and [`FaceId`].
pub trait ElementId: Copy + Eq + Ord + fmt::Debug {
    /// The element kind in words, for error messages (`"vertex"`, `"face"` …).
    const KIND: &'static str;
    /// The position of this element in dense per-element arrays.
    fn index(self) -> usize;
    /// The handle at a dense array position.
    ///
    /// # Panics
    /// If `index` does not fit in `u32` (a mesh never holds that many elements).
    fn from_index(index: usize) -> Self;
}

macro_rules! define_id {
    ($(#[$meta:meta])* $name:ident, $kind:literal, $prefix:literal) => {
        $(#[$meta])*
        #[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
        #[repr(transparent)]
        pub struct $name(u32);

        impl $name {
            /// The handle with the given raw index.
            #[inline]
            #[must_use]
            pub const fn new(raw: u32) -> Self {
                Self(raw)
            }

            /// The position of this element in dense per-element arrays.
            #[inline]
            #[must_use]
            pub const fn index(self) -> usize {
                self.0 as usize
            }

            /// The raw `u32` index.
            #[inline]
            #[must_use]
            pub const fn raw(self) -> u32 {
                self.0
            }
        }

        impl ElementId for $name {
            const KIND: &'static str = $kind;
            #[inline]
            fn index(self) -> usize {
                self.0 as usize
            }
            #[inline]
            fn from_index(index: usize) -> Self {
                Self(u32::try_from(index).expect(concat!($kind, " index exceeds u32")))
            }
        }

        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, concat!($prefix, "{}"), self.0)
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, concat!($kind, " {}"), self.0)
            }
        }

        impl From<$name> for usize {
            #[inline]
            fn from(id: $name) -> usize {
                id.index()
            }
        }
    };
}

define_id!(
    /// A vertex handle.
    VertexId,
    "vertex",
    "v"
);
define_id!(
    /// A halfedge handle. Halfedges `2e` and `2e + 1` form edge `e`, so the twin is
    /// implicit: [`HalfedgeId::twin`] is `h ^ 1`.
    HalfedgeId,
    "halfedge",
    "h"
);
define_id!(
    /// An (undirected) edge handle, owning halfedges `2e` and `2e + 1`.
    EdgeId,
    "edge",
    "e"
);
define_id!(
    /// A face handle.
    FaceId,
    "face",
    "f"
);

impl HalfedgeId {
    /// The oppositely directed halfedge of the same edge (`h ^ 1`).
    #[inline]
    #[must_use]
    pub const fn twin(self) -> Self {
        Self(self.0 ^ 1)
    }

    /// The edge this halfedge belongs to (`h >> 1`).
    #[inline]
    #[must_use]
    pub const fn edge(self) -> EdgeId {
        EdgeId(self.0 >> 1)
    }
}

impl EdgeId {
    /// Both halfedges of this edge, `[2e, 2e + 1]`.
    #[inline]
    #[must_use]
    pub const fn halfedges(self) -> [HalfedgeId; 2] {
        [HalfedgeId(self.0 << 1), HalfedgeId((self.0 << 1) | 1)]
    }

    /// Halfedge `i` (0 or 1) of this edge.
    ///
    /// # Panics
    /// If `i > 1`.
    #[inline]
    #[must_use]
    pub const fn halfedge(self, i: u32) -> HalfedgeId {
        assert!(i < 2, "an edge has two halfedges");
        HalfedgeId((self.0 << 1) | i)
    }
}

/// An iterator over all handles of one kind, `0..n` in index order.
#[derive(Clone, Debug)]
pub struct IdRange<I> {
    range: std::ops::Range<u32>,
    _kind: std::marker::PhantomData<I>,
}

impl<I: ElementId> IdRange<I> {
    pub(crate) fn new(n: usize) -> Self {
        // Meshes never hold more than u32::MAX elements (checked when built).
        let end = u32::try_from(n).unwrap_or(u32::MAX);
        Self {
            range: 0..end,
            _kind: std::marker::PhantomData,
        }
    }
}

impl<I: ElementId> Iterator for IdRange<I> {
    type Item = I;
    #[inline]
    fn next(&mut self) -> Option<I> {
        self.range.next().map(|i| I::from_index(i as usize))
    }
    #[inline]
    fn size_hint(&self) -> (usize, Option<usize>) {
        self.range.size_hint()
    }
}

impl<I: ElementId> DoubleEndedIterator for IdRange<I> {
    #[inline]
    fn next_back(&mut self) -> Option<I> {
        self.range.next_back().map(|i| I::from_index(i as usize))
    }
}

impl<I: ElementId> ExactSizeIterator for IdRange<I> {}
impl<I: ElementId> std::iter::FusedIterator for IdRange<I> {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn twin_and_edge_are_implicit() {
        let h = HalfedgeId::new(7);
        assert_eq!(h.twin(), HalfedgeId::new(6));
        assert_eq!(h.twin().twin(), h);
        assert_eq!(h.edge(), EdgeId::new(3));
        assert_eq!(EdgeId::new(3).halfedges(), [HalfedgeId::new(6), h]);
        assert_eq!(format!("{h:?} {}", VertexId::new(2)), "h7 vertex 2");
    }

    #[test]
    fn id_range_counts() {
        let mut r: IdRange<FaceId> = IdRange::new(3);
        assert_eq!(r.len(), 3);
        assert_eq!(r.next_back(), Some(FaceId::new(2)));
    }
}
