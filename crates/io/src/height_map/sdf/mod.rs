//! SDF (ISO 25178-71, the Surface Data File of the BCR project): an ascii header of
//! `key = value` lines after a version line (`aISO-1.0`, or `aBCR-1.0` before the
//! standard), then the heights as text, each section closed by a `*` line; or the
//! binary variant (`bISO-1.0`, `bBCR-1.0`), a fixed 81-byte header followed by
//! little-endian values.

mod read;
mod write;

pub(crate) use read::read_sdf;
pub(crate) use write::write_sdf_to;

/// The value types of the `DataType` field, by code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DataType {
    U8,
    U16,
    U32,
    F32,
    I8,
    I16,
    I32,
    F64,
}

impl DataType {
    fn from_code(code: u64) -> Option<Self> {
        Some(match code {
            0 => Self::U8,
            1 => Self::U16,
            2 => Self::U32,
            3 => Self::F32,
            4 => Self::I8,
            5 => Self::I16,
            6 => Self::I32,
            7 => Self::F64,
            _ => return None,
        })
    }

    fn bytes(self) -> usize {
        match self {
            Self::U8 | Self::I8 => 1,
            Self::U16 | Self::I16 => 2,
            Self::U32 | Self::I32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    /// The little-endian value at the start of `b`; `None` for the invalid-point
    /// markers of binary files: NaN and the largest finite magnitudes (`±f32::MAX`,
    /// `±f64::MAX`, which some writers put there) for floats, the most negative value
    /// of signed integers (unsigned integers have none).
    fn decode(self, b: &[u8]) -> Option<f64> {
        let value = match self {
            Self::U8 => f64::from(b[0]),
            Self::I8 => {
                let v = i8::from_le_bytes([b[0]]);
                (v != i8::MIN).then_some(f64::from(v))?
            }
            Self::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Self::I16 => {
                let v = i16::from_le_bytes([b[0], b[1]]);
                (v != i16::MIN).then_some(f64::from(v))?
            }
            Self::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Self::I32 => {
                let v = i32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                (v != i32::MIN).then_some(f64::from(v))?
            }
            Self::F32 => {
                let v = f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
                (v.abs() != f32::MAX).then_some(f64::from(v))?
            }
            Self::F64 => {
                let v = f64::from_le_bytes(std::array::from_fn(|k| b[k]));
                (v.abs() != f64::MAX).then_some(v)?
            }
        };
        (!value.is_nan()).then_some(value)
    }
}
