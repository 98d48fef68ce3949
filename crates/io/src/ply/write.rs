//! PLY writer on top of `ply-rs-bw`.

use std::io::{BufWriter, Write};

use ply_rs_bw::ply::{
    Addable, ElementDef, Encoding as PlyEncoding, Header, PropertyAccess, PropertyDef,
    PropertyType, ScalarType,
};
use ply_rs_bw::writer::Writer;

use super::records::{FaceOut, VertexOut};
use crate::error::IoError;
use crate::format::{Encoding, Precision, VertexAttributes, WriteOptions};
use crate::validate::{check_faces, check_positions};
use beltrami_halfedge::MeshData;

/// Property names the writer uses itself.
const RESERVED: [&str; 6] = ["x", "y", "z", "red", "green", "blue"];

/// Writes a PLY file: `x y z` (double or float), the scalar attributes (double), the
/// colours (uchar), then the faces as `list uchar int vertex_indices` (`uint` counts
/// when a face has more than 255 vertices, `uint` indices beyond `i32::MAX`).
pub(crate) fn write_ply_to<W: Write>(
    writer: W,
    mesh: &MeshData,
    attributes: &VertexAttributes,
    options: &WriteOptions,
) -> Result<(), IoError> {
    let single = options.precision == Precision::Single;
    check_attributes(mesh, attributes, options.encoding)?;
    check_positions(&mesh.positions, single)?;
    check_faces(mesh, None)?;

    let (vertex_def, face_def) = element_defs(mesh, attributes, single);
    let mut header = Header::new();
    header.encoding = match options.encoding {
        Encoding::Ascii => PlyEncoding::Ascii,
        Encoding::BinaryLittleEndian => PlyEncoding::BinaryLittleEndian,
        Encoding::BinaryBigEndian => PlyEncoding::BinaryBigEndian,
    };
    header.elements.add(vertex_def.clone());
    header.elements.add(face_def.clone());

    let mut out = BufWriter::new(writer);
    let io = IoError::io("write the file");
    Writer::<VertexOut>::new()
        .write_header(&mut out, &header)
        .map_err(io)?;

    let big_endian = match options.encoding {
        Encoding::Ascii => {
            write_ascii(&mut out, mesh, attributes, &vertex_def, &face_def)?;
            return out.flush().map_err(IoError::io("write the file"));
        }
        Encoding::BinaryLittleEndian => false,
        Encoding::BinaryBigEndian => true,
    };
    let layout = BinaryLayout {
        single,
        wide_count: matches!(
            index_list_type(&face_def),
            Some(PropertyType::List(ScalarType::UInt, _))
        ),
        signed: matches!(
            index_list_type(&face_def),
            Some(PropertyType::List(_, ScalarType::Int))
        ),
    };
    if big_endian {
        write_binary::<true>(&mut out, mesh, attributes, layout)?;
    } else {
        write_binary::<false>(&mut out, mesh, attributes, layout)?;
    }
    out.flush().map_err(IoError::io("write the file"))
}

fn index_list_type(face_def: &ElementDef) -> Option<&PropertyType> {
    face_def
        .properties
        .get("vertex_indices")
        .map(|p| &p.data_type)
}

/// The types of a binary file's records, as [`element_defs`] declares them.
#[derive(Clone, Copy)]
struct BinaryLayout {
    /// `float` coordinates instead of `double`.
    single: bool,
    /// `uint` list lengths instead of `uchar`.
    wide_count: bool,
    /// `int` indices instead of `uint`.
    signed: bool,
}

/// Bytes gathered before each write to the output.
const CHUNK: usize = 1 << 20;

/// Writes the binary records, by hand rather than through `ply-rs-bw`: its writer
/// calls a getter by property name and a small `write` for every value, which took
/// most of the time of writing a large mesh. Here every record is encoded with
/// `to_le_bytes` / `to_be_bytes` into a buffer of about [`CHUNK`] bytes, which goes
/// to the output in one `write_all`. The bytes are the same as `ply-rs-bw` writes
/// for the header [`element_defs`] makes (a test compares them).
fn write_binary<const BIG: bool>(
    out: &mut impl Write,
    mesh: &MeshData,
    attributes: &VertexAttributes,
    layout: BinaryLayout,
) -> Result<(), IoError> {
    macro_rules! put {
        ($buffer:expr, $value:expr) => {
            $buffer.extend_from_slice(&if BIG {
                $value.to_be_bytes()
            } else {
                $value.to_le_bytes()
            })
        };
    }
    let mut buffer: Vec<u8> = Vec::with_capacity(CHUNK + (1 << 12));
    for (i, p) in mesh.positions.iter().enumerate() {
        if layout.single {
            #[allow(
                clippy::cast_possible_truncation,
                reason = "single precision output is asked for; the range was checked"
            )]
            for c in p.to_array() {
                put!(buffer, c as f32);
            }
        } else {
            for c in p.to_array() {
                put!(buffer, c);
            }
        }
        for (_, values) in &attributes.scalars {
            put!(buffer, values.get(i).copied().unwrap_or_default());
        }
        if let Some(colors) = &attributes.colors {
            buffer.extend_from_slice(&colors.get(i).copied().unwrap_or_default());
        }
        if buffer.len() >= CHUNK {
            out.write_all(&buffer)
                .map_err(IoError::io("write the file"))?;
            buffer.clear();
        }
    }
    for indices in mesh.faces.iter() {
        if layout.wide_count {
            put!(buffer, u32::try_from(indices.len()).unwrap_or(u32::MAX));
        } else {
            buffer.push(u8::try_from(indices.len()).unwrap_or(u8::MAX));
        }
        if layout.signed {
            for &i in indices {
                put!(buffer, i32::try_from(i).unwrap_or(i32::MAX));
            }
        } else {
            for &i in indices {
                put!(buffer, i);
            }
        }
        if buffer.len() >= CHUNK {
            out.write_all(&buffer)
                .map_err(IoError::io("write the file"))?;
            buffer.clear();
        }
    }
    out.write_all(&buffer)
        .map_err(IoError::io("write the file"))
}

/// Writes the ascii records through `ply-rs-bw` (its number formatting).
fn write_ascii(
    out: &mut impl Write,
    mesh: &MeshData,
    attributes: &VertexAttributes,
    vertex_def: &ElementDef,
    face_def: &ElementDef,
) -> Result<(), IoError> {
    let writer = Writer::<VertexOut>::new();
    let mut vertex = VertexOut {
        names: attributes.scalars.iter().map(|(n, _)| n.clone()).collect(),
        scalars: vec![0.0; attributes.scalars.len()],
        ..VertexOut::default()
    };
    for (i, p) in mesh.positions.iter().enumerate() {
        vertex.position = p.to_array();
        for (slot, (_, values)) in vertex.scalars.iter_mut().zip(&attributes.scalars) {
            *slot = values.get(i).copied().unwrap_or_default();
        }
        if let Some(colors) = &attributes.colors {
            vertex.color = colors.get(i).copied().unwrap_or_default();
        }
        write_element(&writer, out, &vertex, vertex_def, Encoding::Ascii)?;
    }

    let writer = Writer::<FaceOut>::new();
    let mut face = FaceOut::default();
    let signed = matches!(
        index_list_type(face_def),
        Some(PropertyType::List(_, ScalarType::Int))
    );
    for indices in mesh.faces.iter() {
        if signed {
            face.signed.clear();
            face.signed.extend(
                indices
                    .iter()
                    .map(|&i| i32::try_from(i).unwrap_or(i32::MAX)),
            );
        } else {
            face.unsigned.clear();
            face.unsigned.extend_from_slice(indices);
        }
        write_element(&writer, out, &face, face_def, Encoding::Ascii)?;
    }
    Ok(())
}

fn write_element<E: PropertyAccess, W: Write>(
    writer: &Writer<E>,
    out: &mut W,
    element: &E,
    def: &ElementDef,
    encoding: Encoding,
) -> Result<(), IoError> {
    match encoding {
        Encoding::Ascii => writer.write_ascii_element(out, element, def),
        Encoding::BinaryLittleEndian => writer.write_little_endian_element(out, element, def),
        Encoding::BinaryBigEndian => writer.write_big_endian_element(out, element, def),
    }
    .map(|_| ())
    .map_err(IoError::io("write the file"))
}

fn element_defs(
    mesh: &MeshData,
    attributes: &VertexAttributes,
    single: bool,
) -> (ElementDef, ElementDef) {
    let coordinate = if single {
        ScalarType::Float
    } else {
        ScalarType::Double
    };
    let mut vertex = ElementDef::new("vertex".to_owned());
    vertex.count = mesh.positions.len();
    for name in ["x", "y", "z"] {
        vertex.properties.add(PropertyDef::new(
            name.to_owned(),
            PropertyType::Scalar(coordinate.clone()),
        ));
    }
    for (name, _) in &attributes.scalars {
        vertex.properties.add(PropertyDef::new(
            name.clone(),
            PropertyType::Scalar(ScalarType::Double),
        ));
    }
    if attributes.colors.is_some() {
        for name in ["red", "green", "blue"] {
            vertex.properties.add(PropertyDef::new(
                name.to_owned(),
                PropertyType::Scalar(ScalarType::UChar),
            ));
        }
    }

    let longest = mesh.faces.iter().map(<[u32]>::len).max().unwrap_or(0);
    let count = if longest > usize::from(u8::MAX) {
        ScalarType::UInt
    } else {
        ScalarType::UChar
    };
    let fits_int = mesh
        .faces
        .max_index()
        .is_none_or(|max| i32::try_from(max).is_ok());
    let item = if fits_int {
        ScalarType::Int
    } else {
        ScalarType::UInt
    };
    let mut face = ElementDef::new("face".to_owned());
    face.count = mesh.faces.len();
    face.properties.add(PropertyDef::new(
        "vertex_indices".to_owned(),
        PropertyType::List(count, item),
    ));
    (vertex, face)
}

/// One value per vertex, valid and distinct names, and values that the encoding can
/// hold (ascii PLY readers do not accept `nan` or `inf`).
fn check_attributes(
    mesh: &MeshData,
    attributes: &VertexAttributes,
    encoding: Encoding,
) -> Result<(), IoError> {
    let n = mesh.positions.len();
    for (k, (name, values)) in attributes.scalars.iter().enumerate() {
        check_name(name)?;
        if attributes.scalars[..k]
            .iter()
            .any(|(other, _)| other == name)
        {
            return Err(IoError::AttributeName {
                name: name.clone(),
                reason: "the name is used twice",
            });
        }
        if values.len() != n {
            return Err(IoError::AttributeLength {
                attribute: name.clone(),
                expected: n,
                found: values.len(),
            });
        }
        if encoding == Encoding::Ascii
            && let Some((vertex, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite())
        {
            return Err(IoError::NonFiniteAttribute {
                attribute: name.clone(),
                vertex,
                value,
            });
        }
    }
    if let Some(colors) = &attributes.colors
        && colors.len() != n
    {
        return Err(IoError::AttributeLength {
            attribute: "colors".to_owned(),
            expected: n,
            found: colors.len(),
        });
    }
    Ok(())
}

/// A PLY identifier: a letter or `_`, then letters, digits, `_` or `-`.
fn check_name(name: &str) -> Result<(), IoError> {
    let refuse = |reason| {
        Err(IoError::AttributeName {
            name: name.to_owned(),
            reason,
        })
    };
    let mut chars = name.chars();
    match chars.next() {
        None => return refuse("the name is empty"),
        Some(c) if !(c.is_ascii_alphabetic() || c == '_') => {
            return refuse("a ply property name starts with a letter or '_'");
        }
        Some(_) => {}
    }
    if !chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
        return refuse("a ply property name holds only letters, digits, '_' and '-'");
    }
    if RESERVED.contains(&name) {
        return refuse("the name is used for positions or colours");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use beltrami_halfedge::PolygonList;
    use glam::DVec3;

    /// The file as `ply-rs-bw` writes it, record by record.
    fn reference(
        mesh: &MeshData,
        attributes: &VertexAttributes,
        options: &WriteOptions,
    ) -> Vec<u8> {
        let single = options.precision == Precision::Single;
        let (vertex_def, face_def) = element_defs(mesh, attributes, single);
        let mut header = Header::new();
        header.encoding = match options.encoding {
            Encoding::Ascii => PlyEncoding::Ascii,
            Encoding::BinaryLittleEndian => PlyEncoding::BinaryLittleEndian,
            Encoding::BinaryBigEndian => PlyEncoding::BinaryBigEndian,
        };
        header.elements.add(vertex_def.clone());
        header.elements.add(face_def.clone());
        let mut out = Vec::new();
        Writer::<VertexOut>::new()
            .write_header(&mut out, &header)
            .unwrap();
        let writer = Writer::<VertexOut>::new();
        let mut vertex = VertexOut {
            names: attributes.scalars.iter().map(|(n, _)| n.clone()).collect(),
            scalars: vec![0.0; attributes.scalars.len()],
            ..VertexOut::default()
        };
        for (i, p) in mesh.positions.iter().enumerate() {
            vertex.position = p.to_array();
            for (slot, (_, values)) in vertex.scalars.iter_mut().zip(&attributes.scalars) {
                *slot = values[i];
            }
            if let Some(colors) = &attributes.colors {
                vertex.color = colors[i];
            }
            write_element(&writer, &mut out, &vertex, &vertex_def, options.encoding).unwrap();
        }
        let writer = Writer::<FaceOut>::new();
        let mut face = FaceOut::default();
        for indices in mesh.faces.iter() {
            face.signed = indices.iter().map(|&i| i32::try_from(i).unwrap()).collect();
            write_element(&writer, &mut out, &face, &face_def, options.encoding).unwrap();
        }
        out
    }

    #[test]
    fn binary_records_are_the_bytes_ply_rs_writes() {
        let mut mesh = beltrami_halfedge::primitives::icosphere(2);
        mesh.positions[3] = DVec3::new(-0.0, 1e-310, 1.5e30);
        // A polygon of 300 vertices makes the list lengths `uint`.
        let n = mesh.positions.len() as u32;
        let mut wide = PolygonList::new();
        for face in mesh.faces.iter() {
            wide.push(face);
        }
        wide.push(&(0..300).map(|i| i % n).collect::<Vec<_>>());
        let scalars = vec![
            ("a".to_owned(), (0..n).map(|i| f64::from(i) * 0.1).collect()),
            ("b".to_owned(), (0..n).map(|i| -f64::from(i)).collect()),
        ];
        let colors = Some((0..n).map(|i| [i as u8, 7, 255 - i as u8]).collect());
        let attribute_sets = [
            VertexAttributes::default(),
            VertexAttributes { scalars, colors },
        ];
        let mut wide_mesh = mesh.clone();
        wide_mesh.faces = wide;
        for mesh in [&mesh, &wide_mesh] {
            for attributes in &attribute_sets {
                for encoding in [Encoding::BinaryLittleEndian, Encoding::BinaryBigEndian] {
                    for precision in [Precision::Double, Precision::Single] {
                        let options = WriteOptions::default()
                            .encoding(encoding)
                            .precision(precision);
                        let mut ours = Vec::new();
                        write_ply_to(&mut ours, mesh, attributes, &options).unwrap();
                        assert!(
                            ours == reference(mesh, attributes, &options),
                            "{encoding:?} {precision:?}"
                        );
                    }
                }
            }
        }
    }
}
