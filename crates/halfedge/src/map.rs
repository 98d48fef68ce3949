//! Dense per-element attribute maps (`VertexMap<T>`, `FaceMap<T>` …).

use std::marker::PhantomData;
use std::ops::{Index, IndexMut};

use crate::ids::{EdgeId, ElementId, FaceId, HalfedgeId, VertexId};

/// A dense map from every element of one kind to a value: a `Vec<T>` indexed by typed
/// handles instead of `usize`.
///
/// Build one with [`IdMap::filled`], [`IdMap::from_vec`] or the mesh helpers
/// (`mesh.vertex_map(0.0)`), read it with `map[v]`.
///
/// # Examples
/// ```
/// use beltrami_halfedge::{HalfedgeMesh, VertexMap};
/// let mesh = HalfedgeMesh::from_polygons(3, &[[0u32, 1, 2]]).unwrap();
/// let mut valence: VertexMap<usize> = mesh.vertex_map(0);
/// for v in mesh.vertices() {
///     valence[v] = mesh.valence(v);
/// }
/// assert_eq!(valence.as_slice(), &[2, 2, 2]);
/// ```
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct IdMap<I, T> {
    values: Vec<T>,
    _kind: PhantomData<fn(I)>,
}

/// A value per vertex.
pub type VertexMap<T> = IdMap<VertexId, T>;
/// A value per halfedge.
pub type HalfedgeMap<T> = IdMap<HalfedgeId, T>;
/// A value per edge.
pub type EdgeMap<T> = IdMap<EdgeId, T>;
/// A value per face.
pub type FaceMap<T> = IdMap<FaceId, T>;

impl<I: ElementId, T> IdMap<I, T> {
    /// A map of `n` copies of `value`.
    #[must_use]
    pub fn filled(n: usize, value: T) -> Self
    where
        T: Clone,
    {
        Self::from_vec(vec![value; n])
    }

    /// A map whose value for element `i` is `values[i]`.
    #[must_use]
    pub fn from_vec(values: Vec<T>) -> Self {
        Self {
            values,
            _kind: PhantomData,
        }
    }

    /// The number of elements.
    #[must_use]
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether the map has no elements.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// The value of `id`, or `None` when `id` is out of range.
    #[must_use]
    pub fn get(&self, id: I) -> Option<&T> {
        self.values.get(id.index())
    }

    /// The values in index order.
    #[must_use]
    pub fn as_slice(&self) -> &[T] {
        &self.values
    }

    /// The values in index order, mutably.
    #[must_use]
    pub fn as_mut_slice(&mut self) -> &mut [T] {
        &mut self.values
    }

    /// The underlying vector.
    #[must_use]
    pub fn into_vec(self) -> Vec<T> {
        self.values
    }

    /// `(id, &value)` pairs in index order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (I, &T)> + '_ {
        self.values
            .iter()
            .enumerate()
            .map(|(i, v)| (I::from_index(i), v))
    }
}

impl<I: ElementId, T> Index<I> for IdMap<I, T> {
    type Output = T;
    #[inline]
    fn index(&self, id: I) -> &T {
        &self.values[id.index()]
    }
}

impl<I: ElementId, T> IndexMut<I> for IdMap<I, T> {
    #[inline]
    fn index_mut(&mut self, id: I) -> &mut T {
        &mut self.values[id.index()]
    }
}

impl<I, T: std::fmt::Debug> std::fmt::Debug for IdMap<I, T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.values.fmt(f)
    }
}
