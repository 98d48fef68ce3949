//! User properties: typed per-element data stored beside the connectivity and updated
//! by every operator.

use std::any::Any;
use std::marker::PhantomData;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::{DVec2, DVec3};

use super::error::EditError;
use super::storage::EditMesh;
use crate::ids::{EdgeId, ElementId, FaceId, HalfedgeId, VertexId};

/// A value that can be stored as a property of an [`EditMesh`](crate::EditMesh).
///
/// The one method says whether the type can be interpolated: when an edge is split, a
/// new vertex gets `interpolate(a, b, t)` of the values at the edge's end points, or
/// the property's default when it returns `None` (the provided implementation). Types
/// that have a meaningful linear blend (`f64`, `f32`, [`DVec2`], [`DVec3`]) implement it;
/// flags, labels and integers keep the default.
///
/// Values are `Send + Sync`, so that a mesh with properties can be read from several
/// threads at once (an algorithm's per-vertex pass on rayon's threads, say).
///
/// # Examples
/// A user type that is not interpolated (a feature label):
/// ```
/// use beltrami_halfedge::edit::PropertyValue;
/// #[derive(Clone, Debug, Default, PartialEq)]
/// struct Label(u8);
/// impl PropertyValue for Label {}
/// ```
pub trait PropertyValue: Clone + Send + Sync + 'static {
    /// The value at parameter `t ∈ [0, 1]` between `a` (`t = 0`) and `b` (`t = 1`), or
    /// `None` when the type has no meaningful blend.
    #[must_use]
    fn interpolate(a: &Self, b: &Self, t: f64) -> Option<Self> {
        let _ = (a, b, t);
        None
    }
}

macro_rules! not_interpolated {
    ($($t:ty),*) => { $(impl PropertyValue for $t {})* };
}
not_interpolated!(
    bool, u8, u16, u32, u64, usize, i8, i16, i32, i64, isize, char, String
);

impl PropertyValue for f64 {
    fn interpolate(a: &Self, b: &Self, t: f64) -> Option<Self> {
        Some(a + (b - a) * t)
    }
}

impl PropertyValue for f32 {
    fn interpolate(a: &Self, b: &Self, t: f64) -> Option<Self> {
        Some((f64::from(*a) + (f64::from(*b) - f64::from(*a)) * t) as f32)
    }
}

impl PropertyValue for DVec3 {
    fn interpolate(a: &Self, b: &Self, t: f64) -> Option<Self> {
        Some(a.lerp(*b, t))
    }
}

impl PropertyValue for DVec2 {
    fn interpolate(a: &Self, b: &Self, t: f64) -> Option<Self> {
        Some(a.lerp(*b, t))
    }
}

impl<T: PropertyValue> PropertyValue for Option<T> {}

/// A typed handle to a property of the elements of kind `I` holding values of type `T`.
///
/// Returned by `add_*_property`; read and write through
/// [`EditMesh::get`](crate::EditMesh::get), [`EditMesh::set`](crate::EditMesh::set),
/// [`EditMesh::get_mut`](crate::EditMesh::get_mut) and
/// [`EditMesh::values`](crate::EditMesh::values). A handle stays valid across every
/// operator and across garbage collection (the values are remapped with the elements),
/// until the property is removed. A handle works on the mesh that made it and on clones
/// of that mesh; on any other mesh the accessors panic.
pub struct Property<I, T> {
    pub(crate) slot: usize,
    pub(crate) key: u64,
    _kind: PhantomData<fn(I) -> T>,
}

impl<I, T> Property<I, T> {
    fn new(slot: usize, key: u64) -> Self {
        Self {
            slot,
            key,
            _kind: PhantomData,
        }
    }
}

impl<I, T> Clone for Property<I, T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<I, T> Copy for Property<I, T> {}
impl<I, T> PartialEq for Property<I, T> {
    fn eq(&self, other: &Self) -> bool {
        self.key == other.key
    }
}
impl<I, T> Eq for Property<I, T> {}
impl<I, T> std::fmt::Debug for Property<I, T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Property(#{})", self.key)
    }
}

/// A per-vertex property handle.
pub type VertexProperty<T> = Property<VertexId, T>;
/// A per-halfedge property handle.
pub type HalfedgeProperty<T> = Property<HalfedgeId, T>;
/// A per-edge property handle.
pub type EdgeProperty<T> = Property<EdgeId, T>;
/// A per-face property handle.
pub type FaceProperty<T> = Property<FaceId, T>;

/// One property column, type-erased so that operators can update all of them.
trait Column: Any + Send + Sync {
    fn name(&self) -> &str;
    fn len(&self) -> usize;
    fn push_default(&mut self);
    fn copy(&mut self, from: usize, to: usize);
    /// `to` gets the interpolation of `a` and `b` at `t`, or the default.
    fn interpolate(&mut self, a: usize, b: usize, t: f64, to: usize);
    /// Keeps the entries whose `keep` flag is set, in order.
    fn retain(&mut self, keep: &[bool]);
    fn as_any(&self) -> &dyn Any;
    fn as_any_mut(&mut self) -> &mut dyn Any;
    fn clone_box(&self) -> Box<dyn Column>;
}

struct TypedColumn<T> {
    name: String,
    default: T,
    values: Vec<T>,
}

impl<T: PropertyValue> Column for TypedColumn<T> {
    fn name(&self) -> &str {
        &self.name
    }
    fn len(&self) -> usize {
        self.values.len()
    }
    fn push_default(&mut self) {
        self.values.push(self.default.clone());
    }
    fn copy(&mut self, from: usize, to: usize) {
        self.values[to] = self.values[from].clone();
    }
    fn interpolate(&mut self, a: usize, b: usize, t: f64, to: usize) {
        self.values[to] = T::interpolate(&self.values[a], &self.values[b], t)
            .unwrap_or_else(|| self.default.clone());
    }
    fn retain(&mut self, keep: &[bool]) {
        let mut i = 0;
        self.values.retain(|_| {
            i += 1;
            keep[i - 1]
        });
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn Any {
        self
    }
    fn clone_box(&self) -> Box<dyn Column> {
        Box::new(Self {
            name: self.name.clone(),
            default: self.default.clone(),
            values: self.values.clone(),
        })
    }
}

/// The properties of one element kind: columns of equal length (the number of element
/// slots, deleted ones included).
pub(crate) struct PropertyStore {
    columns: Vec<Option<(u64, Box<dyn Column>)>>,
    len: usize,
}

impl Clone for PropertyStore {
    fn clone(&self) -> Self {
        Self {
            columns: self
                .columns
                .iter()
                .map(|c| c.as_ref().map(|(k, col)| (*k, col.clone_box())))
                .collect(),
            len: self.len,
        }
    }
}

impl std::fmt::Debug for PropertyStore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list()
            .entries(self.columns.iter().flatten().map(|(_, c)| c.name()))
            .finish()
    }
}

impl PropertyStore {
    pub(crate) fn new(len: usize) -> Self {
        Self {
            columns: Vec::new(),
            len,
        }
    }

    fn live(&mut self) -> impl Iterator<Item = &mut Box<dyn Column>> {
        self.columns.iter_mut().flatten().map(|(_, c)| c)
    }

    pub(crate) fn names(&self) -> impl Iterator<Item = &str> {
        self.columns.iter().flatten().map(|(_, c)| c.name())
    }

    /// Adds a column of `default`s; `None` when the name is taken.
    pub(crate) fn add<I, T: PropertyValue>(
        &mut self,
        name: &str,
        default: T,
        key: u64,
    ) -> Option<Property<I, T>> {
        if self.names().any(|n| n == name) {
            return None;
        }
        let column = TypedColumn {
            name: name.to_owned(),
            values: vec![default.clone(); self.len],
            default,
        };
        let slot = match self.columns.iter().position(Option::is_none) {
            Some(free) => free,
            None => {
                self.columns.push(None);
                self.columns.len() - 1
            }
        };
        self.columns[slot] = Some((key, Box::new(column)));
        Some(Property::new(slot, key))
    }

    /// The handle of the property named `name`, if it exists and holds `T`.
    pub(crate) fn find<I, T: PropertyValue>(&self, name: &str) -> Option<Property<I, T>> {
        self.columns.iter().enumerate().find_map(|(slot, c)| {
            let (key, col) = c.as_ref()?;
            (col.name() == name && col.as_any().is::<TypedColumn<T>>())
                .then(|| Property::new(slot, *key))
        })
    }

    pub(crate) fn remove<I, T>(&mut self, p: Property<I, T>) -> bool {
        match self.columns.get(p.slot) {
            Some(Some((key, _))) if *key == p.key => {
                self.columns[p.slot] = None;
                true
            }
            _ => false,
        }
    }

    pub(crate) fn contains<I, T>(&self, p: Property<I, T>) -> bool {
        matches!(self.columns.get(p.slot), Some(Some((key, _))) if *key == p.key)
    }

    fn column<I, T: PropertyValue>(&self, p: Property<I, T>) -> &[T] {
        match self.columns.get(p.slot) {
            Some(Some((key, col))) if *key == p.key => {
                &col.as_any()
                    .downcast_ref::<TypedColumn<T>>()
                    .expect("a property handle's type matches its column")
                    .values
            }
            _ => panic!("the property was removed from this mesh (or belongs to another mesh)"),
        }
    }

    fn column_mut<I, T: PropertyValue>(&mut self, p: Property<I, T>) -> &mut [T] {
        match self.columns.get_mut(p.slot) {
            Some(Some((key, col))) if *key == p.key => {
                &mut col
                    .as_any_mut()
                    .downcast_mut::<TypedColumn<T>>()
                    .expect("a property handle's type matches its column")
                    .values
            }
            _ => panic!("the property was removed from this mesh (or belongs to another mesh)"),
        }
    }

    pub(crate) fn values<I, T: PropertyValue>(&self, p: Property<I, T>) -> &[T] {
        self.column(p)
    }

    pub(crate) fn values_mut<I, T: PropertyValue>(&mut self, p: Property<I, T>) -> &mut [T] {
        self.column_mut(p)
    }

    /// A new element slot: every column gets its default.
    pub(crate) fn push(&mut self) {
        self.len += 1;
        for c in self.live() {
            c.push_default();
        }
    }

    /// Element `to` gets the values of element `from`.
    pub(crate) fn copy(&mut self, from: usize, to: usize) {
        for c in self.live() {
            c.copy(from, to);
        }
    }

    /// Element `to` gets the values interpolated between `a` and `b` at `t` (or the
    /// defaults, for types that do not interpolate).
    pub(crate) fn interpolate(&mut self, a: usize, b: usize, t: f64, to: usize) {
        for c in self.live() {
            c.interpolate(a, b, t, to);
        }
    }

    /// Keeps the slots flagged in `keep`, in order.
    pub(crate) fn retain(&mut self, keep: &[bool]) {
        debug_assert_eq!(keep.len(), self.len);
        let len = keep.iter().filter(|&&k| k).count();
        self.len = len;
        for c in self.live() {
            c.retain(keep);
            debug_assert_eq!(c.len(), len);
        }
    }
}

/// The element kinds an [`EditMesh`](crate::EditMesh) stores properties for:
/// [`VertexId`], [`HalfedgeId`], [`EdgeId`] and [`FaceId`]. Sealed.
pub trait PropertyElement: ElementId + sealed::Sealed {
    /// The position of this kind's store in [`Properties`].
    #[doc(hidden)]
    const SLOT: usize;
}

#[allow(unreachable_pub)]
mod sealed {
    pub trait Sealed {}
    impl Sealed for super::VertexId {}
    impl Sealed for super::HalfedgeId {}
    impl Sealed for super::EdgeId {}
    impl Sealed for super::FaceId {}
}

impl PropertyElement for VertexId {
    const SLOT: usize = 0;
}
impl PropertyElement for HalfedgeId {
    const SLOT: usize = 1;
}
impl PropertyElement for EdgeId {
    const SLOT: usize = 2;
}
impl PropertyElement for FaceId {
    const SLOT: usize = 3;
}

/// The property stores of the four element kinds, indexed by
/// [`PropertyElement::SLOT`].
#[derive(Clone, Debug)]
pub(crate) struct Properties {
    stores: [PropertyStore; 4],
}

impl Properties {
    pub(crate) fn new(nv: usize, ne: usize, nf: usize) -> Self {
        Self {
            stores: [
                PropertyStore::new(nv),
                PropertyStore::new(2 * ne),
                PropertyStore::new(ne),
                PropertyStore::new(nf),
            ],
        }
    }

    pub(crate) fn of<I: PropertyElement>(&self) -> &PropertyStore {
        &self.stores[I::SLOT]
    }

    pub(crate) fn of_mut<I: PropertyElement>(&mut self) -> &mut PropertyStore {
        &mut self.stores[I::SLOT]
    }

    pub(crate) fn vertex(&mut self) -> &mut PropertyStore {
        &mut self.stores[VertexId::SLOT]
    }

    pub(crate) fn halfedge(&mut self) -> &mut PropertyStore {
        &mut self.stores[HalfedgeId::SLOT]
    }

    pub(crate) fn edge(&mut self) -> &mut PropertyStore {
        &mut self.stores[EdgeId::SLOT]
    }

    pub(crate) fn face(&mut self) -> &mut PropertyStore {
        &mut self.stores[FaceId::SLOT]
    }

    /// A key no property has had before, in any mesh, so that a handle used on a mesh
    /// that did not make it (or a clone of it) is caught instead of reading a column
    /// that happens to sit in the same slot.
    pub(crate) fn fresh_key() -> u64 {
        static NEXT: AtomicU64 = AtomicU64::new(1);
        NEXT.fetch_add(1, Ordering::Relaxed)
    }
}

impl EditMesh {
    fn add_property<I: PropertyElement, T: PropertyValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<Property<I, T>, EditError> {
        let key = Properties::fresh_key();
        self.props
            .of_mut::<I>()
            .add(name, default, key)
            .ok_or_else(|| EditError::PropertyExists {
                kind: I::KIND,
                name: name.to_owned(),
            })
    }

    /// Adds a per-vertex property named `name`, every vertex holding `default`.
    ///
    /// Rules (`docs/editing.md`): a vertex made by [`split_edge`](Self::split_edge) gets
    /// the values of the edge's end points interpolated ([`PropertyValue`]), by
    /// [`split_face`](Self::split_face) the face's corner values blended by the
    /// barycentric coordinates of its position; any other new vertex gets `default`; a
    /// collapse keeps the surviving vertex's value; garbage collection remaps.
    ///
    /// # Errors
    /// [`EditError::PropertyExists`] when a vertex property of this name exists.
    pub fn add_vertex_property<T: PropertyValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<VertexProperty<T>, EditError> {
        self.add_property(name, default)
    }

    /// Adds a per-halfedge property (corner data: a halfedge's value belongs to the face
    /// on its left, at its target vertex). Halves of a split edge copy their parent's
    /// value; a halfedge that takes the place of a removed one in a face after a
    /// collapse takes its value; other new halfedges get `default`.
    ///
    /// # Errors
    /// [`EditError::PropertyExists`] when a halfedge property of this name exists.
    pub fn add_halfedge_property<T: PropertyValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<HalfedgeProperty<T>, EditError> {
        self.add_property(name, default)
    }

    /// Adds a per-edge property (e.g. a feature-edge flag). Both halves of a split edge
    /// keep its value; a flipped edge keeps its value; of the two edges a collapse merges
    /// the one at the surviving vertex keeps its value; new edges get `default`.
    ///
    /// # Errors
    /// [`EditError::PropertyExists`] when an edge property of this name exists.
    pub fn add_edge_property<T: PropertyValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<EdgeProperty<T>, EditError> {
        self.add_property(name, default)
    }

    /// Adds a per-face property (e.g. a region label). Faces cut from a face by a split
    /// copy its value; faces made by [`add_face`](Self::add_face) get `default`; the
    /// two faces of a flipped edge keep their values.
    ///
    /// # Errors
    /// [`EditError::PropertyExists`] when a face property of this name exists.
    pub fn add_face_property<T: PropertyValue>(
        &mut self,
        name: &str,
        default: T,
    ) -> Result<FaceProperty<T>, EditError> {
        self.add_property(name, default)
    }

    /// The handle of the property of kind `I` named `name` holding `T`, if there is one.
    ///
    /// # Examples
    /// ```
    /// use beltrami_halfedge::{EditMesh, VertexId};
    /// let mut mesh = EditMesh::new();
    /// mesh.add_vertex_property("curvature", 0.0_f64)?;
    /// assert!(mesh.find_property::<VertexId, f64>("curvature").is_some());
    /// assert!(mesh.find_property::<VertexId, u32>("curvature").is_none());
    /// # Ok::<(), beltrami_halfedge::EditError>(())
    /// ```
    #[must_use]
    pub fn find_property<I: PropertyElement, T: PropertyValue>(
        &self,
        name: &str,
    ) -> Option<Property<I, T>> {
        self.props.of::<I>().find(name)
    }

    /// The names of the properties of kind `I`.
    pub fn property_names<I: PropertyElement>(&self) -> impl Iterator<Item = &str> + '_ {
        self.props.of::<I>().names()
    }

    /// Removes a property; its handle (and copies of it) stop working. Returns whether
    /// it was there.
    pub fn remove_property<I: PropertyElement, T: PropertyValue>(
        &mut self,
        property: Property<I, T>,
    ) -> bool {
        self.props.of_mut::<I>().remove(property)
    }

    /// Whether `property` belongs to this mesh and has not been removed.
    #[must_use]
    pub fn has_property<I: PropertyElement, T: PropertyValue>(
        &self,
        property: Property<I, T>,
    ) -> bool {
        self.props.of::<I>().contains(property)
    }

    /// The value of `property` at `id`.
    ///
    /// # Panics
    /// If the property was removed, or `id` is out of range.
    #[must_use]
    pub fn get<I: PropertyElement, T: PropertyValue>(&self, property: Property<I, T>, id: I) -> &T {
        &self.props.of::<I>().values(property)[id.index()]
    }

    /// The value of `property` at `id`, mutably.
    ///
    /// # Panics
    /// If the property was removed, or `id` is out of range.
    pub fn get_mut<I: PropertyElement, T: PropertyValue>(
        &mut self,
        property: Property<I, T>,
        id: I,
    ) -> &mut T {
        &mut self.props.of_mut::<I>().values_mut(property)[id.index()]
    }

    /// Sets the value of `property` at `id`.
    ///
    /// # Panics
    /// If the property was removed, or `id` is out of range.
    pub fn set<I: PropertyElement, T: PropertyValue>(
        &mut self,
        property: Property<I, T>,
        id: I,
        value: T,
    ) {
        *self.get_mut(property, id) = value;
    }

    /// All values of `property` by element index, deleted slots included. After
    /// [`garbage_collection`](Self::garbage_collection) the slots are exactly the live
    /// elements, in the order of [`to_mesh`](Self::to_mesh).
    ///
    /// # Panics
    /// If the property was removed.
    #[must_use]
    pub fn values<I: PropertyElement, T: PropertyValue>(&self, property: Property<I, T>) -> &[T] {
        self.props.of::<I>().values(property)
    }

    /// All values of `property` by element index, mutably.
    ///
    /// # Panics
    /// If the property was removed.
    #[must_use]
    pub fn values_mut<I: PropertyElement, T: PropertyValue>(
        &mut self,
        property: Property<I, T>,
    ) -> &mut [T] {
        self.props.of_mut::<I>().values_mut(property)
    }
}
