//! Typed records that `ply-rs-bw` decodes into and encodes from (its
//! `PropertyAccess` path, which avoids a hash map per element).

use ply_rs_bw::ply::{BeginList, PropertyAccess, PropertyAccessResult};

/// Whether a face property holds the vertex indices.
pub(super) fn is_index_list_name(name: &str) -> bool {
    name == "vertex_indices" || name == "vertex_index"
}

/// One decoded vertex: `x`, `y`, `z` of any numeric type, other properties ignored.
#[derive(Debug, Default)]
pub(super) struct VertexRecord {
    pub(super) position: [f64; 3],
}

impl VertexRecord {
    fn set(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        let axis = match name {
            "x" => 0,
            "y" => 1,
            "z" => 2,
            _ => return PropertyAccessResult::Ignored,
        };
        self.position[axis] = value;
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for VertexRecord {
    fn new() -> Self {
        Self::default()
    }
    fn set_char(&mut self, name: &str, value: i8) -> PropertyAccessResult {
        self.set(name, f64::from(value))
    }
    fn set_uchar(&mut self, name: &str, value: u8) -> PropertyAccessResult {
        self.set(name, f64::from(value))
    }
    fn set_short(&mut self, name: &str, value: i16) -> PropertyAccessResult {
        self.set(name, f64::from(value))
    }
    fn set_ushort(&mut self, name: &str, value: u16) -> PropertyAccessResult {
        self.set(name, f64::from(value))
    }
    fn set_int(&mut self, name: &str, value: i32) -> PropertyAccessResult {
        self.set(name, f64::from(value))
    }
    fn set_uint(&mut self, name: &str, value: u32) -> PropertyAccessResult {
        self.set(name, f64::from(value))
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.set(name, f64::from(value))
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        self.set(name, value)
    }
}

/// The index list of one face, in the integer type the header declares.
#[derive(Debug, Default)]
pub(super) enum IndexList {
    /// No index list was decoded (yet).
    #[default]
    Unset,
    I8(Vec<i8>),
    U8(Vec<u8>),
    I16(Vec<i16>),
    U16(Vec<u16>),
    I32(Vec<i32>),
    U32(Vec<u32>),
}

impl IndexList {
    /// Appends the indices as `u32`; a negative index is returned as the error.
    pub(super) fn append_to(&self, out: &mut Vec<u32>) -> Result<(), i64> {
        fn append<T: Copy + Into<i64>>(values: &[T], out: &mut Vec<u32>) -> Result<(), i64> {
            for &value in values {
                let value: i64 = value.into();
                out.push(u32::try_from(value).map_err(|_| value)?);
            }
            Ok(())
        }
        match self {
            Self::Unset => Ok(()),
            Self::I8(v) => append(v, out),
            Self::U8(v) => append(v, out),
            Self::I16(v) => append(v, out),
            Self::U16(v) => append(v, out),
            Self::I32(v) => append(v, out),
            Self::U32(v) => append(v, out),
        }
    }
}

impl IndexList {
    /// Appends the indices as `i64`, negative ones included.
    pub(super) fn append_signed_to(&self, out: &mut Vec<i64>) {
        fn append<T: Copy + Into<i64>>(values: &[T], out: &mut Vec<i64>) {
            out.extend(values.iter().map(|&v| v.into()));
        }
        match self {
            Self::Unset => {}
            Self::I8(v) => append(v, out),
            Self::U8(v) => append(v, out),
            Self::I16(v) => append(v, out),
            Self::U16(v) => append(v, out),
            Self::I32(v) => append(v, out),
            Self::U32(v) => append(v, out),
        }
    }
}

/// One decoded face: the first `vertex_indices` or `vertex_index` list; other
/// properties ignored.
#[derive(Debug, Default)]
pub(super) struct FaceRecord {
    pub(super) indices: IndexList,
}

/// `begin_list_*` for one integer type: the parser fills the list in place.
macro_rules! begin_index_list {
    ($method:ident, $t:ty, $variant:ident) => {
        fn $method(&mut self, name: &str, _len: usize) -> BeginList<'_, $t> {
            if !is_index_list_name(name) || !matches!(self.indices, IndexList::Unset) {
                return BeginList::UseSetter;
            }
            self.indices = IndexList::$variant(Vec::new());
            match &mut self.indices {
                IndexList::$variant(list) => BeginList::Fill(list),
                _ => BeginList::UseSetter,
            }
        }
    };
}

impl PropertyAccess for FaceRecord {
    fn new() -> Self {
        Self::default()
    }
    begin_index_list!(begin_list_char, i8, I8);
    begin_index_list!(begin_list_uchar, u8, U8);
    begin_index_list!(begin_list_short, i16, I16);
    begin_index_list!(begin_list_ushort, u16, U16);
    begin_index_list!(begin_list_int, i32, I32);
    begin_index_list!(begin_list_uint, u32, U32);
}

/// A record that is decoded only to move past it.
#[derive(Debug, Default)]
pub(super) struct Skip;

impl PropertyAccess for Skip {
    fn new() -> Self {
        Self
    }
}

/// The vertex record the writer encodes from; reused for every vertex.
#[derive(Debug, Default)]
pub(super) struct VertexOut {
    pub(super) position: [f64; 3],
    pub(super) names: Vec<String>,
    pub(super) scalars: Vec<f64>,
    pub(super) color: [u8; 3],
}

impl PropertyAccess for VertexOut {
    fn new() -> Self {
        Self::default()
    }
    fn get_double(&self, name: &str) -> Option<f64> {
        match name {
            "x" => Some(self.position[0]),
            "y" => Some(self.position[1]),
            "z" => Some(self.position[2]),
            _ => {
                let k = self.names.iter().position(|n| n == name)?;
                self.scalars.get(k).copied()
            }
        }
    }
    #[allow(
        clippy::cast_possible_truncation,
        reason = "single precision output is asked for; the range was checked"
    )]
    fn get_float(&self, name: &str) -> Option<f32> {
        match name {
            "x" => Some(self.position[0] as f32),
            "y" => Some(self.position[1] as f32),
            "z" => Some(self.position[2] as f32),
            _ => None,
        }
    }
    fn get_uchar(&self, name: &str) -> Option<u8> {
        match name {
            "red" => Some(self.color[0]),
            "green" => Some(self.color[1]),
            "blue" => Some(self.color[2]),
            _ => None,
        }
    }
}

/// The face record the writer encodes from; reused for every face.
#[derive(Debug, Default)]
pub(super) struct FaceOut {
    pub(super) signed: Vec<i32>,
    pub(super) unsigned: Vec<u32>,
}

impl PropertyAccess for FaceOut {
    fn new() -> Self {
        Self::default()
    }
    fn get_list_int(&self, name: &str) -> Option<&[i32]> {
        (name == "vertex_indices").then_some(&self.signed[..])
    }
    fn get_list_uint(&self, name: &str) -> Option<&[u32]> {
        (name == "vertex_indices").then_some(&self.unsigned[..])
    }
}
