//! Fast binary decoding of the `vertex` and `face` elements, written by hand.
//!
//! Why not `ply-rs-bw` here: its binary parser reads one scalar at a time through
//! `Read` (a `read_exact` per value), calls a setter by property name for each one and
//! allocates a `Vec` per face list. On a scan of a million faces that is most of the
//! read time. This module decodes the records straight from the `BufRead` buffer with
//! `from_le_bytes` / `from_be_bytes`, using a layout computed once from the header
//! (offsets and types), and appends positions and indices directly to the mesh.
//!
//! It is a drop-in for the `ply-rs-bw` path and gives the same mesh and the same errors
//! for the same bytes: records are decoded in header order, a list length is checked
//! as `ply-rs-bw` checks it (a negative length of a signed count type is an error with
//! its message), an early end of file is [`IoError::Truncated`] naming the record it
//! cuts, a negative face index is [`IoError::NegativeIndex`] once the whole record has
//! been read, and a non-finite coordinate is [`IoError::NonFiniteCoordinate`]. Headers
//! are still parsed by `ply-rs-bw`; layouts this module does not cover (a list inside
//! the vertex element, a list length of a floating-point type) go through
//! `ply-rs-bw` as before.

use std::io::{BufRead, ErrorKind, Read};

use beltrami_halfedge::PolygonList;
use glam::DVec3;
use ply_rs_bw::ply::{ElementDef, PropertyType, ScalarType};

use super::records::is_index_list_name;
use crate::error::IoError;

#[cfg(test)]
thread_local! {
    /// Set by tests to read through `ply-rs-bw` only, for comparison.
    static GENERIC_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether the fast path is used (always, except in tests that compare it with the
/// `ply-rs-bw` path).
pub(super) fn enabled() -> bool {
    #[cfg(test)]
    if GENERIC_ONLY.with(std::cell::Cell::get) {
        return false;
    }
    true
}

/// A PLY scalar type (a `Copy` mirror of `ply-rs-bw`'s `ScalarType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Num {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Num {
    fn of(t: &ScalarType) -> Self {
        match t {
            ScalarType::Char => Self::I8,
            ScalarType::UChar => Self::U8,
            ScalarType::Short => Self::I16,
            ScalarType::UShort => Self::U16,
            ScalarType::Int => Self::I32,
            ScalarType::UInt => Self::U32,
            ScalarType::Float => Self::F32,
            ScalarType::Double => Self::F64,
        }
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    fn is_float(self) -> bool {
        matches!(self, Self::F32 | Self::F64)
    }
}

/// `N` bytes of `bytes` from `at` (the caller has checked the length).
#[inline(always)]
fn bytes_at<const N: usize>(bytes: &[u8], at: usize) -> [u8; N] {
    let mut out = [0; N];
    out.copy_from_slice(&bytes[at..at + N]);
    out
}

/// Decodes a number as `f64` (exact for every PLY type).
#[inline(always)]
fn float_at(bytes: &[u8], at: usize, t: Num, big: bool) -> f64 {
    macro_rules! get {
        ($t:ty) => {{
            let b = bytes_at(bytes, at);
            f64::from(if big {
                <$t>::from_be_bytes(b)
            } else {
                <$t>::from_le_bytes(b)
            })
        }};
    }
    match t {
        Num::I8 => get!(i8),
        Num::U8 => get!(u8),
        Num::I16 => get!(i16),
        Num::U16 => get!(u16),
        Num::I32 => get!(i32),
        Num::U32 => get!(u32),
        Num::F32 => get!(f32),
        Num::F64 => get!(f64),
    }
}

/// Decodes an integer as `i64` (`t` is an integer type).
#[inline(always)]
fn int_at(bytes: &[u8], at: usize, t: Num, big: bool) -> i64 {
    macro_rules! get {
        ($t:ty) => {{
            let b = bytes_at(bytes, at);
            i64::from(if big {
                <$t>::from_be_bytes(b)
            } else {
                <$t>::from_le_bytes(b)
            })
        }};
    }
    match t {
        Num::I8 => get!(i8),
        Num::U8 => get!(u8),
        Num::I16 => get!(i16),
        Num::U16 => get!(u16),
        Num::I32 => get!(i32),
        Num::U32 => get!(u32),
        // Not reached: list lengths and indices are integers (checked by the layouts).
        Num::F32 | Num::F64 => 0,
    }
}

/// The record of a vertex element without lists: its size and where `x`, `y`, `z` are.
#[derive(Debug)]
pub(super) struct VertexLayout {
    stride: usize,
    axes: [(usize, Num); 3],
}

impl VertexLayout {
    /// The layout of `element`, or `None` when a property is a list (records of
    /// varying size, left to `ply-rs-bw`).
    pub(super) fn of(element: &ElementDef) -> Option<Self> {
        let mut stride = 0;
        let mut axes = [None; 3];
        for p in element.properties.values() {
            let PropertyType::Scalar(t) = &p.data_type else {
                return None;
            };
            let t = Num::of(t);
            let axis = match p.name.as_str() {
                "x" => Some(0),
                "y" => Some(1),
                "z" => Some(2),
                _ => None,
            };
            if let Some(axis) = axis {
                axes[axis] = Some((stride, t));
            }
            stride += t.size();
        }
        Some(Self {
            stride,
            axes: [axes[0]?, axes[1]?, axes[2]?],
        })
    }

    #[inline(always)]
    fn decode(&self, record: &[u8], big: bool) -> [f64; 3] {
        if let [(x, Num::F64), (y, Num::F64), (z, Num::F64)] = self.axes {
            // The common layout of scans written in double precision.
            let get = |at| {
                let b = bytes_at(record, at);
                if big {
                    f64::from_be_bytes(b)
                } else {
                    f64::from_le_bytes(b)
                }
            };
            return [get(x), get(y), get(z)];
        }
        self.axes.map(|(at, t)| float_at(record, at, t, big))
    }
}

fn push_position(positions: &mut Vec<DVec3>, p: [f64; 3]) -> Result<(), IoError> {
    if let Some(&value) = p.iter().find(|c| !c.is_finite()) {
        return Err(IoError::NonFiniteCoordinate {
            line: None,
            vertex: positions.len(),
            value,
        });
    }
    positions.push(DVec3::from_array(p));
    Ok(())
}

/// Reads the `count` records of a vertex element with `layout` and appends their
/// positions: whole buffers of records at a time, a record split across the end of
/// the reader's buffer through a small copy.
pub(super) fn read_vertices<R: BufRead>(
    reader: &mut R,
    count: usize,
    layout: &VertexLayout,
    big: bool,
    positions: &mut Vec<DVec3>,
) -> Result<(), IoError> {
    let stride = layout.stride;
    let end = positions.len() + count;
    let mut record = vec![0; stride];
    while positions.len() < end {
        let buffer = reader.fill_buf().map_err(IoError::io("read the file"))?;
        let n = (buffer.len() / stride).min(end - positions.len());
        if n > 0 {
            for bytes in buffer[..n * stride].chunks_exact(stride) {
                push_position(positions, layout.decode(bytes, big))?;
            }
            reader.consume(n * stride);
        } else {
            let index = positions.len() + count - end;
            read_exact(reader, &mut record, "vertex", index)?;
            push_position(positions, layout.decode(&record, big))?;
        }
    }
    Ok(())
}

fn read_exact(
    reader: &mut impl Read,
    bytes: &mut [u8],
    element: &str,
    index: usize,
) -> Result<(), IoError> {
    reader.read_exact(bytes).map_err(|e| {
        if e.kind() == ErrorKind::UnexpectedEof {
            IoError::Truncated {
                element: element.to_owned(),
                index,
            }
        } else {
            IoError::io("read the file")(e)
        }
    })
}

/// One property of a face record.
#[derive(Clone, Copy, Debug)]
enum FaceProperty {
    /// A scalar of this many bytes, skipped.
    Scalar(usize),
    /// A list with an integer length type and items of any type, skipped.
    List(Num, Num),
    /// The vertex index list: integer length and item types.
    Indices(Num, Num),
}

/// The record of a face element: its properties in header order.
#[derive(Debug)]
pub(super) struct FaceLayout {
    properties: Vec<FaceProperty>,
    /// For records that are only a `uchar` count and `int` or `uint` indices (what
    /// most writers produce), the index type: a triangle's record is then the count 3
    /// and three indices, 13 bytes, decoded without the general loop.
    plain: Option<Num>,
}

impl FaceLayout {
    /// The layout of `element`, or `None` when a list length is of a floating-point
    /// type (an error that `ply-rs-bw` reports in its own words) or the index list is
    /// not a list of integers (refused by the schema check before).
    pub(super) fn of(element: &ElementDef) -> Option<Self> {
        let mut indices_seen = false;
        let mut properties = Vec::new();
        for p in element.properties.values() {
            properties.push(match &p.data_type {
                PropertyType::Scalar(t) => FaceProperty::Scalar(Num::of(t).size()),
                PropertyType::List(count, item) => {
                    let (count, item) = (Num::of(count), Num::of(item));
                    if count.is_float() {
                        return None;
                    }
                    if !indices_seen && is_index_list_name(&p.name) {
                        // The first index list is decoded (as `FaceRecord` does); any
                        // other list is skipped.
                        indices_seen = true;
                        if item.is_float() {
                            return None;
                        }
                        FaceProperty::Indices(count, item)
                    } else {
                        FaceProperty::List(count, item)
                    }
                }
            });
        }
        let plain = match properties[..] {
            [FaceProperty::Indices(Num::U8, item @ (Num::I32 | Num::U32))] => Some(item),
            _ => None,
        };
        Some(Self { properties, plain })
    }
}

/// The three indices of a plain triangle record (`3` and three 4-byte indices of type
/// `item`) at the start of `bytes`, or `None` when the record is anything else (not
/// whole, not a triangle, a negative index): the general decoding then handles it.
#[inline(always)]
fn plain_triangle(bytes: &[u8], item: Num, big: bool) -> Option<[u32; 3]> {
    let record: &[u8; 13] = bytes.get(..13)?.try_into().ok()?;
    if record[0] != 3 {
        return None;
    }
    let index = |i: usize| {
        let b = bytes_at(record, 1 + 4 * i);
        if big {
            u32::from_be_bytes(b)
        } else {
            u32::from_le_bytes(b)
        }
    };
    let face = [index(0), index(1), index(2)];
    // An `int` index with the sign bit set is negative.
    if item == Num::I32 && face.iter().any(|&i| i > i32::MAX as u32) {
        return None;
    }
    Some(face)
}

/// What is wrong with a face record that was decoded whole.
enum FaceProblem {
    /// A list length of a signed type is negative: `ply-rs-bw`'s message.
    NegativeLength(&'static str),
}

/// The length of a list, as `ply-rs-bw` reads it.
fn list_length(bytes: &[u8], at: usize, t: Num, big: bool) -> Result<usize, FaceProblem> {
    let n = int_at(bytes, at, t, big);
    usize::try_from(n).map_err(|_| {
        FaceProblem::NegativeLength(match t {
            Num::I8 => "List length cannot be negative (i8).",
            Num::I16 => "List length cannot be negative (i16).",
            _ => "List length cannot be negative (i32).",
        })
    })
}

/// Decodes the face record at the start of `bytes`, appending its indices to `out`
/// and remembering the first negative one in `negative`. Returns the record's size,
/// or `None` when `bytes` holds only a part of it.
#[inline(always)]
fn decode_face(
    bytes: &[u8],
    layout: &FaceLayout,
    big: bool,
    out: &mut Vec<u32>,
    negative: &mut Option<i64>,
) -> Result<Option<usize>, FaceProblem> {
    let mut at = 0;
    for property in &layout.properties {
        match *property {
            FaceProperty::Scalar(size) => at += size,
            FaceProperty::List(count, item) | FaceProperty::Indices(count, item) => {
                if at + count.size() > bytes.len() {
                    return Ok(None);
                }
                let n = list_length(bytes, at, count, big)?;
                at += count.size();
                let Some(end) = n
                    .checked_mul(item.size())
                    .and_then(|len| len.checked_add(at))
                    .filter(|&end| end <= bytes.len())
                else {
                    return Ok(None);
                };
                if let FaceProperty::Indices(..) = property {
                    decode_indices(&bytes[at..end], item, big, out, negative);
                }
                at = end;
            }
        }
    }
    Ok((at <= bytes.len()).then_some(at))
}

#[inline(always)]
fn decode_indices(bytes: &[u8], item: Num, big: bool, out: &mut Vec<u32>, neg: &mut Option<i64>) {
    let mut push = |value: i64| match u32::try_from(value) {
        Ok(v) => out.push(v),
        // Only negative values get here (every other value of an integer type fits
        // in `u32`); the first one is reported.
        Err(_) => {
            if neg.is_none() {
                *neg = Some(value);
            }
        }
    };
    macro_rules! each {
        ($t:ty) => {
            for chunk in bytes.chunks_exact(size_of::<$t>()) {
                let b = bytes_at(chunk, 0);
                push(i64::from(if big {
                    <$t>::from_be_bytes(b)
                } else {
                    <$t>::from_le_bytes(b)
                }));
            }
        };
    }
    match item {
        Num::I8 => each!(i8),
        Num::U8 => each!(u8),
        Num::I16 => each!(i16),
        Num::U16 => each!(u16),
        Num::I32 => each!(i32),
        Num::U32 => each!(u32),
        // Not reached: the layout refuses floating-point indices.
        Num::F32 | Num::F64 => {}
    }
}

/// Reads the `count` records of a face element with `layout` and appends their index
/// lists to `faces`. `remaining` is the number of unread payload bytes, so that a list
/// longer than the rest of the file fails before anything is allocated for it.
pub(super) fn read_faces<R: BufRead>(
    reader: &mut R,
    count: usize,
    layout: &FaceLayout,
    big: bool,
    remaining: usize,
    faces: &mut PolygonList,
) -> Result<(), IoError> {
    let first = faces.len();
    let mut scratch = Vec::new();
    let mut record = Vec::new();
    let mut remaining = remaining;
    let mut index = 0;
    while index < count {
        let buffer = reader.fill_buf().map_err(IoError::io("read the file"))?;
        let mut at = 0;
        while index < count {
            if let Some(item) = layout.plain
                && let Some(face) = plain_triangle(&buffer[at..], item, big)
            {
                faces.push(&face);
                at += 13;
                index += 1;
                continue;
            }
            scratch.clear();
            let mut negative = None;
            let decoded = decode_face(&buffer[at..], layout, big, &mut scratch, &mut negative)
                .map_err(|p| face_error(p, index))?;
            let Some(size) = decoded else { break };
            finish_face(faces, &scratch, negative, first + index)?;
            at += size;
            index += 1;
        }
        reader.consume(at);
        remaining = remaining.saturating_sub(at);
        if at == 0 && index < count {
            // The record is split across the end of the buffer (or the file): read it
            // field by field into `record`, then decode it from there.
            let size = read_face_record(reader, layout, big, remaining, &mut record, index)?;
            remaining = remaining.saturating_sub(size);
            scratch.clear();
            let mut negative = None;
            let decoded = decode_face(&record, layout, big, &mut scratch, &mut negative)
                .map_err(|p| face_error(p, index))?;
            debug_assert_eq!(decoded, Some(size));
            finish_face(faces, &scratch, negative, first + index)?;
            index += 1;
        }
    }
    Ok(())
}

fn finish_face(
    faces: &mut PolygonList,
    indices: &[u32],
    negative: Option<i64>,
    face: usize,
) -> Result<(), IoError> {
    if let Some(index) = negative {
        return Err(IoError::NegativeIndex {
            line: None,
            face,
            index,
        });
    }
    faces.push(indices);
    Ok(())
}

fn face_error(problem: FaceProblem, index: usize) -> IoError {
    match problem {
        FaceProblem::NegativeLength(message) => IoError::PlyData {
            line: None,
            element: "face".to_owned(),
            index,
            reason: super::read::sanitize(message),
        },
    }
}

/// Reads one whole face record into `record` (replacing its content) and returns its
/// size. Fails as `ply-rs-bw` would: a negative list length is an error, an early end
/// of the file is [`IoError::Truncated`]; a list that needs more bytes than `remaining`
/// is truncated without reading (or allocating) it.
fn read_face_record(
    reader: &mut impl Read,
    layout: &FaceLayout,
    big: bool,
    remaining: usize,
    record: &mut Vec<u8>,
    index: usize,
) -> Result<usize, IoError> {
    let truncated = || IoError::Truncated {
        element: "face".to_owned(),
        index,
    };
    record.clear();
    for property in &layout.properties {
        let at = record.len();
        match *property {
            FaceProperty::Scalar(size) => {
                record.resize(at + size, 0);
                read_exact(reader, &mut record[at..], "face", index)?;
            }
            FaceProperty::List(count, item) | FaceProperty::Indices(count, item) => {
                record.resize(at + count.size(), 0);
                read_exact(reader, &mut record[at..], "face", index)?;
                let n = list_length(record, at, count, big).map_err(|p| face_error(p, index))?;
                let len = n.checked_mul(item.size()).ok_or_else(truncated)?;
                if len > remaining.saturating_sub(record.len()) {
                    return Err(truncated());
                }
                let at = record.len();
                record.resize(at + len, 0);
                read_exact(reader, &mut record[at..], "face", index)?;
            }
        }
    }
    Ok(record.len())
}

#[cfg(test)]
mod tests {
    use std::io::{BufReader, Cursor};

    use super::*;
    use crate::ply::read::read_ply;

    /// One value of a record.
    #[derive(Clone, Copy)]
    enum V {
        I8(i8),
        U8(u8),
        I16(i16),
        U16(u16),
        I32(i32),
        U32(u32),
        F32(f32),
        F64(f64),
    }

    fn encode(values: &[V], big: bool) -> Vec<u8> {
        let mut out = Vec::new();
        macro_rules! put {
            ($v:expr) => {
                out.extend_from_slice(&if big {
                    $v.to_be_bytes()
                } else {
                    $v.to_le_bytes()
                })
            };
        }
        for &v in values {
            match v {
                V::I8(v) => put!(v),
                V::U8(v) => put!(v),
                V::I16(v) => put!(v),
                V::U16(v) => put!(v),
                V::I32(v) => put!(v),
                V::U32(v) => put!(v),
                V::F32(v) => put!(v),
                V::F64(v) => put!(v),
            }
        }
        out
    }

    fn file(elements: &str, values: &[V], big: bool) -> Vec<u8> {
        let format = if big {
            "binary_big_endian"
        } else {
            "binary_little_endian"
        };
        let mut bytes = format!("ply\nformat {format} 1.0\n{elements}end_header\n").into_bytes();
        bytes.extend(encode(values, big));
        bytes
    }

    /// The result of reading `bytes` as `Debug` text, through the fast path with
    /// readers of several buffer sizes; they must all agree, and agree with the
    /// `ply-rs-bw` path.
    fn check_same(bytes: &[u8]) {
        GENERIC_ONLY.with(|g| g.set(true));
        let generic = format!("{:?}", read_ply(Cursor::new(bytes), false));
        GENERIC_ONLY.with(|g| g.set(false));
        let whole = format!("{:?}", read_ply(Cursor::new(bytes), false));
        assert_eq!(whole, generic, "{bytes:?}");
        for capacity in [4, 5, 8, 13, 64, 1000] {
            let buffered = format!(
                "{:?}",
                read_ply(
                    BufReader::with_capacity(capacity, Cursor::new(bytes)),
                    false
                )
            );
            assert_eq!(buffered, generic, "capacity {capacity}: {bytes:?}");
        }
    }

    /// Every prefix of the file and every byte replaced by a few values.
    fn check_variants(bytes: &[u8]) {
        check_same(bytes);
        let header = bytes
            .windows(11)
            .position(|w| w == b"end_header\n")
            .unwrap()
            + 11;
        for len in header..bytes.len() {
            check_same(&bytes[..len]);
        }
        let mut copy = bytes.to_vec();
        for at in header..bytes.len() {
            for value in [0x00, 0x7f, 0x80, 0xff] {
                copy[at] = value;
                check_same(&copy);
            }
            copy[at] = bytes[at];
        }
    }

    fn tetrahedron_corners() -> [[i64; 3]; 4] {
        [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
    }

    #[test]
    fn plain_double_layout_matches_ply_rs() {
        let elements = "element vertex 4\nproperty double x\nproperty double y\nproperty double z\nelement face 4\nproperty list uchar int vertex_indices\n";
        let mut values = Vec::new();
        for v in 0..4 {
            values.extend([
                V::F64(f64::from(v)),
                V::F64(0.5),
                V::F64(-1.25 * f64::from(v)),
            ]);
        }
        for face in tetrahedron_corners() {
            values.push(V::U8(3));
            values.extend(face.map(|i| V::I32(i32::try_from(i).unwrap())));
        }
        for big in [false, true] {
            check_variants(&file(elements, &values, big));
        }
    }

    #[test]
    fn mixed_layouts_match_ply_rs() {
        let elements = "element vertex 4\nproperty float nx\nproperty float x\nproperty uchar red\nproperty float y\nproperty short z\nproperty int extra\n\
            element face 4\nproperty uchar flags\nproperty list uchar float texcoord\nproperty list char ushort vertex_index\nproperty list uchar int vertex_indices\nproperty double quality\n\
            element edge 1\nproperty int v1\nproperty int v2\n";
        let mut values = Vec::new();
        for v in 0..4_i16 {
            values.extend([
                V::F32(9.0),
                V::F32(f32::from(v)),
                V::U8(200),
                V::F32(0.25),
                V::I16(-v),
                V::I32(-7),
            ]);
        }
        for (k, face) in tetrahedron_corners().into_iter().enumerate() {
            values.extend([V::U8(1), V::U8(2), V::F32(0.5), V::F32(1.5), V::I8(3)]);
            values.extend(face.map(|i| V::U16(u16::try_from(i).unwrap())));
            // A second index list, ignored; a polygon of 4 in the last face.
            values.push(V::U8(if k == 3 { 4 } else { 2 }));
            values.extend([V::I32(5), V::I32(6)]);
            if k == 3 {
                values.extend([V::I32(7), V::I32(8)]);
            }
            values.push(V::F64(0.125));
        }
        values.extend([V::I32(0), V::I32(1)]);
        for big in [false, true] {
            check_variants(&file(elements, &values, big));
        }
    }

    #[test]
    fn signed_and_wide_lists_match_ply_rs() {
        let elements = "element vertex 4\nproperty double x\nproperty double y\nproperty double z\nelement face 4\nproperty list short char vertex_indices\n";
        let wide = "element vertex 4\nproperty double x\nproperty double y\nproperty double z\nelement face 4\nproperty list int uint vertex_indices\n";
        for big in [false, true] {
            let mut values = Vec::new();
            for v in 0..4 {
                values.extend([V::F64(f64::from(v)), V::F64(1.0), V::F64(2.0)]);
            }
            let mut narrow = values.clone();
            let mut long = values;
            for face in tetrahedron_corners() {
                narrow.push(V::I16(3));
                narrow.extend(face.map(|i| V::I8(i8::try_from(i).unwrap())));
                long.push(V::I32(3));
                long.extend(face.map(|i| V::U32(u32::try_from(i).unwrap())));
            }
            check_variants(&file(elements, &narrow, big));
            check_variants(&file(wide, &long, big));
        }
    }

    #[test]
    fn bytes_after_the_last_element_are_refused_on_both_paths() {
        let elements = "element vertex 2\nproperty double x\nproperty float y\nproperty double z\n\
            element face 1\nproperty list uchar int vertex_indices\n";
        let mut values = Vec::new();
        for v in 0..2 {
            values.extend([V::F64(f64::from(v)), V::F32(0.5), V::F64(2.0)]);
        }
        values.extend([V::U8(2), V::I32(0), V::I32(1)]);
        for big in [false, true] {
            let mut bytes = file(elements, &values, big);
            assert!(read_ply(Cursor::new(&bytes[..]), false).is_ok());
            bytes.extend([0, 1, 2]);
            check_same(&bytes);
            assert!(matches!(
                read_ply(Cursor::new(&bytes[..]), false),
                Err(IoError::TrailingData { bytes: Some(3), .. })
            ));
            // Read leniently, the declared data and the 3 bytes ignored.
            let (mesh, report) = read_ply(Cursor::new(&bytes[..]), true).unwrap();
            assert_eq!(mesh.faces.len(), 1);
            assert_eq!(report.ignored_trailing_bytes, 3);
        }
    }

    #[test]
    fn vertex_lists_and_float_lengths_use_ply_rs() {
        let listed = "element vertex 1\nproperty double x\nproperty double y\nproperty double z\nproperty list uchar int ids\n";
        let element = |text: &str| {
            let bytes = file(text, &[], false);
            let header = ply_rs_bw::parser::Parser::<ply_rs_bw::ply::DefaultElement>::new()
                .read_header(&mut ply_rs_bw::parser::Reader::new(Cursor::new(bytes)))
                .unwrap();
            header.elements.values().next().unwrap().clone()
        };
        assert!(VertexLayout::of(&element(listed)).is_none());
        let float_length = "element face 1\nproperty list float int vertex_indices\n";
        assert!(FaceLayout::of(&element(float_length)).is_none());
    }
}
