//! PLY reader on top of `ply-rs-bw`, with guards against lying headers.
//!
//! `ply-rs-bw` parses the header and decodes one element at a time; this module
//! checks the schema, checks that the declared counts fit in the file before any
//! element is decoded, and turns each element into a position or a face directly
//! (no intermediate `Vec` of records).

use std::io::{BufRead, ErrorKind, Read, Seek, SeekFrom};

use beltrami_halfedge::{MAX_ELEMENTS, PolygonList};
use glam::DVec3;
use ply_rs_bw::parser::{ParseError, Parser, Reader};
use ply_rs_bw::ply::{ElementDef, Encoding, Header, PropertyType, ScalarType};

use super::fast::{self, FaceLayout, VertexLayout};
use super::records::{FaceRecord, Skip, VertexRecord, is_index_list_name};
use crate::error::IoError;
use crate::read_options::ReadReport;
use crate::text::{
    BOM, LineReader, Lines, count_lines_in, is_blank_stream, stream_len, token_text, tokens,
};
use crate::validate::check_faces;
use beltrami_halfedge::MeshData;

/// Reads a PLY file from `reader`, element by element.
///
/// Faces come from the `face` element and from triangle strips (`tristrips`). The
/// file must hold exactly what the header declares: more elements (ascii) or bytes
/// (binary) after the last one are an error; whitespace after the last ascii line is
/// not. A UTF-8 byte order mark before `ply` is skipped.
pub(crate) fn read_ply<R: BufRead + Seek>(
    mut reader: R,
    lenient: bool,
) -> Result<(MeshData, ReadReport), IoError> {
    let mut report = ReadReport::default();
    let length = stream_len(&mut reader)?;
    if length == 0 {
        return Err(IoError::Empty);
    }
    if let Err(e) = check_magic(&mut reader) {
        seek_to(&mut reader, 0)?;
        return Err(if is_blank_stream(&mut reader)? {
            IoError::Empty
        } else {
            e
        });
    }
    let mut ply_reader = Reader::new(reader);
    let header = Parser::<Skip>::new().read_header(&mut ply_reader);
    let mut reader = ply_reader.into_inner();
    let header = match header {
        Ok(header) => header,
        Err(e) => {
            let text = e.line().and_then(|n| header_line(&mut reader, n));
            return Err(header_error(&e, text));
        }
    };
    let header_length = reader
        .stream_position()
        .map_err(IoError::io("read the file"))?;
    let payload = usize::try_from(length - header_length).unwrap_or(usize::MAX);
    check_unique_names(&mut reader, header_length)?;
    check_schema(&header)?;
    if header.elements.is_empty() {
        // A header that declares no element at all: an empty mesh, as with
        // `element vertex 0`; anything after the header is data no element holds.
        let mut rest = Vec::new();
        reader
            .take(4096)
            .read_to_end(&mut rest)
            .map_err(IoError::io("read the file"))?;
        if rest.iter().any(|b| !b.is_ascii_whitespace()) {
            return Err(IoError::MissingElement { element: "vertex" });
        }
        return Ok((MeshData::default(), report));
    }
    let mut mesh = MeshData::default();
    let face_line = match header.encoding {
        Encoding::Ascii => {
            seek_to(&mut reader, 0)?;
            let header_lines = count_lines_in(&mut (&mut reader).take(header_length))?;
            check_counts(&header, count_lines_in(&mut reader)?, |_| 1)?;
            seek_to(&mut reader, header_length)?;
            read_ascii(
                &header,
                reader,
                payload,
                header_lines,
                &mut mesh,
                lenient.then_some(&mut report),
            )?
        }
        Encoding::BinaryLittleEndian | Encoding::BinaryBigEndian => {
            check_counts(&header, payload, min_record_size)?;
            let big_endian = header.encoding == Encoding::BinaryBigEndian;
            let left = read_binary(&header, reader, payload, big_endian, &mut mesh)?;
            if left > 0 {
                if !lenient {
                    return Err(trailing_data(&header, None, Some(left as u64)));
                }
                report.ignored_trailing_bytes = left as u64;
            }
            None
        }
    };
    // Faces from triangle strips are not one per line.
    let face_line = face_line.filter(|_| !header.elements.contains_key(TRISTRIPS));
    check_faces(&mesh, face_line)?;
    Ok((mesh, report))
}

/// The element of triangle strips: index lists in which `-1` ends a strip.
const TRISTRIPS: &str = "tristrips";

/// An [`IoError::TrailingData`] after the last element of `header`.
fn trailing_data(header: &Header, line: Option<usize>, bytes: Option<u64>) -> IoError {
    let (element, count) = header
        .elements
        .values()
        .last()
        .map_or((String::new(), 0), |e| (e.name.clone(), e.count));
    IoError::TrailingData {
        line,
        bytes,
        element,
        count,
    }
}

fn seek_to(reader: &mut impl Seek, position: u64) -> Result<(), IoError> {
    reader
        .seek(SeekFrom::Start(position))
        .map(drop)
        .map_err(IoError::io("read the file"))
}

/// Line `n` (1-based) of the file, as quoted in an error; at most 64 KiB of each line
/// is read.
fn header_line<R: BufRead + Seek>(reader: &mut R, n: usize) -> Option<String> {
    seek_to(reader, 0).ok()?;
    let mut line = Vec::new();
    for _ in 0..n {
        line.clear();
        let mut limited = reader.by_ref().take(64 << 10);
        if limited.read_until(b'\n', &mut line).ok()? == 0 {
            return None;
        }
        if line.last() != Some(&b'\n') {
            // Skip the rest of an overlong line.
            let mut rest = Vec::new();
            reader.read_until(b'\n', &mut rest).ok()?;
        }
    }
    let text = line.strip_suffix(b"\n").unwrap_or(&line);
    let text = text.strip_suffix(b"\r").unwrap_or(text);
    let text = if n == 1 {
        text.strip_prefix(BOM).unwrap_or(text)
    } else {
        text
    };
    Some(token_text(text))
}

/// The vertex and face counts of a PLY header, read from the start of `reader`
/// without decoding any element. The face count of a file with triangle strips only
/// is 0 (their triangles are known only once read).
pub(crate) fn declared_counts<R: BufRead + Seek>(
    reader: &mut R,
) -> Result<crate::read::DeclaredCounts, IoError> {
    check_magic(reader)?;
    let mut ply_reader = Reader::new(&mut *reader);
    let header = Parser::<Skip>::new()
        .read_header(&mut ply_reader)
        .map_err(|e| header_error(&e, None))?;
    let header_length = reader
        .stream_position()
        .map_err(IoError::io("read the file"))?;
    check_unique_names(reader, header_length)?;
    check_schema(&header)?;
    let count = |name| header.elements.get(name).map(|e| e.count);
    Ok(crate::read::DeclaredCounts {
        vertices: count("vertex").or(Some(0)),
        faces: count("face").unwrap_or(0),
    })
}

/// The first line must be `ply`: anything else is not a PLY file at all. Looks at the
/// start of the buffer without consuming it, except a byte order mark before `ply`.
fn check_magic(reader: &mut impl BufRead) -> Result<(), IoError> {
    let mut bytes = reader.fill_buf().map_err(IoError::io("read the file"))?;
    let marked = bytes.starts_with(BOM);
    if marked {
        bytes = &bytes[BOM.len()..];
    }
    let first = Lines::new(bytes).next().map_or(&b""[..], |(_, line)| line);
    if first.trim_ascii_end() != b"ply" {
        return Err(IoError::PlyHeader {
            line: Some(1),
            reason: "not a ply file (the first line must be \"ply\")".to_owned(),
        });
    }
    // `ply`, then `\r` and no `\n`: the line endings of classic Mac OS.
    let ending = &bytes[first.len()..];
    if ending.first() == Some(&b'\r') && ending.get(1) != Some(&b'\n') {
        return Err(IoError::PlyHeader {
            line: Some(1),
            reason: "the lines end with a bare carriage return (classic Mac OS); convert the line endings to \\n or \\r\\n".to_owned(),
        });
    }
    if marked {
        reader.consume(BOM.len());
    }
    Ok(())
}

/// Every element name once, every property name once within its element: the header
/// parser keeps only the last of equal names, which would shift the values of a
/// record. Reads the `header_length` bytes of the header from the start of `reader`.
fn check_unique_names<R: BufRead + Seek>(
    reader: &mut R,
    header_length: u64,
) -> Result<(), IoError> {
    let end = reader
        .stream_position()
        .map_err(IoError::io("read the file"))?;
    seek_to(reader, 0)?;
    let mut lines = LineReader::new((&mut *reader).take(header_length));
    let mut elements: Vec<Vec<u8>> = Vec::new();
    let mut properties: Vec<Vec<u8>> = Vec::new();
    while let Some(line) = lines.next_line()? {
        let words: Vec<&[u8]> = tokens(lines.line()).collect();
        let twice = |what: &str, name: &[u8], of: Option<&[u8]>| IoError::PlyHeader {
            line: Some(line),
            reason: match of {
                Some(element) => format!(
                    "{what} {:?} of element {:?} is declared twice",
                    token_text(name),
                    token_text(element)
                ),
                None => format!("{what} {:?} is declared twice", token_text(name)),
            },
        };
        match words[..] {
            [b"element", name, ..] => {
                if elements.iter().any(|e| e == name) {
                    return Err(twice("element", name, None));
                }
                elements.push(name.to_vec());
                properties.clear();
            }
            [b"property", .., name] => {
                if properties.iter().any(|p| p == name) {
                    let element = elements.last().map(Vec::as_slice);
                    return Err(twice("property", name, element));
                }
                properties.push(name.to_vec());
            }
            _ => {}
        }
    }
    seek_to(reader, end)
}

/// The `vertex` element with scalar `x`, `y`, `z`; `face` and `tristrips` elements,
/// when present, with an integer list `vertex_indices` (or `vertex_index`). Without
/// either, no other element (but `edge`) may hold such a list: its faces would be
/// silently lost.
fn check_schema(header: &Header) -> Result<(), IoError> {
    if header.elements.is_empty() {
        return Ok(());
    }
    let vertex = header
        .elements
        .get("vertex")
        .ok_or(IoError::MissingElement { element: "vertex" })?;
    for name in ["x", "y", "z"] {
        let property = vertex
            .properties
            .get(name)
            .ok_or_else(|| IoError::MissingProperty {
                element: "vertex".to_owned(),
                property: name.to_owned(),
            })?;
        if let PropertyType::List(..) = property.data_type {
            return Err(type_error("vertex", name, &property.data_type, "a number"));
        }
    }
    if vertex.count > MAX_ELEMENTS {
        return Err(IoError::TooManyVertices {
            declared: vertex.count,
            max: MAX_ELEMENTS,
        });
    }
    let mut has_faces = false;
    for name in ["face", TRISTRIPS] {
        let Some(face) = header.elements.get(name) else {
            continue;
        };
        has_faces = true;
        let property = face
            .properties
            .values()
            .find(|p| is_index_list_name(&p.name))
            .ok_or_else(|| IoError::MissingProperty {
                element: name.to_owned(),
                property: "vertex_indices".to_owned(),
            })?;
        let integer_list = matches!(
            &property.data_type,
            PropertyType::List(count, item) if is_integer(count) && is_integer(item)
        );
        if !integer_list {
            return Err(type_error(
                name,
                &property.name,
                &property.data_type,
                "a list of integers",
            ));
        }
    }
    if !has_faces {
        let other = header.elements.values().find(|e| {
            e.name != "vertex"
                && e.name != "edge"
                && e.properties.values().any(|p| {
                    is_index_list_name(&p.name) && matches!(p.data_type, PropertyType::List(..))
                })
        });
        if let Some(element) = other {
            return Err(IoError::UnsupportedFaceElement {
                element: element.name.clone(),
            });
        }
    }
    Ok(())
}

fn type_error(
    element: &str,
    property: &str,
    found: &PropertyType,
    expected: &'static str,
) -> IoError {
    IoError::PropertyType {
        element: element.to_owned(),
        property: property.to_owned(),
        found: type_name(found),
        expected,
    }
}

fn is_integer(t: &ScalarType) -> bool {
    !matches!(t, ScalarType::Float | ScalarType::Double)
}

fn scalar_name(t: &ScalarType) -> &'static str {
    match t {
        ScalarType::Char => "char",
        ScalarType::UChar => "uchar",
        ScalarType::Short => "short",
        ScalarType::UShort => "ushort",
        ScalarType::Int => "int",
        ScalarType::UInt => "uint",
        ScalarType::Float => "float",
        ScalarType::Double => "double",
    }
}

/// A property type in header syntax, e.g. `list uchar int`.
fn type_name(t: &PropertyType) -> String {
    match t {
        PropertyType::Scalar(s) => scalar_name(s).to_owned(),
        PropertyType::List(count, item) => {
            format!("list {} {}", scalar_name(count), scalar_name(item))
        }
    }
}

fn scalar_size(t: &ScalarType) -> usize {
    match t {
        ScalarType::Char | ScalarType::UChar => 1,
        ScalarType::Short | ScalarType::UShort => 2,
        ScalarType::Int | ScalarType::UInt | ScalarType::Float => 4,
        ScalarType::Double => 8,
    }
}

/// The fewest bytes one binary record of `element` can take (lists empty).
fn min_record_size(element: &ElementDef) -> usize {
    element
        .properties
        .values()
        .map(|p| match &p.data_type {
            PropertyType::Scalar(t) | PropertyType::List(t, _) => scalar_size(t),
        })
        .sum()
}

/// Checks, before anything is decoded or allocated, that every declared element fits
/// in what is left of the file: `units` is the number of bytes (binary) or lines
/// (ascii) after the header, `cost` the fewest units one record takes.
fn check_counts(
    header: &Header,
    units: usize,
    cost: impl Fn(&ElementDef) -> usize,
) -> Result<(), IoError> {
    let mut remaining = units;
    for element in header.elements.values() {
        let cost = cost(element);
        if cost == 0 {
            continue;
        }
        let available = remaining / cost;
        if element.count > available {
            return Err(IoError::CountExceedsFile {
                element: element.name.clone(),
                declared: element.count,
                available,
            });
        }
        remaining -= element.count * cost;
    }
    Ok(())
}

/// Reads the ascii payload; returns the line of the first face, if any.
fn read_ascii(
    header: &Header,
    reader: impl BufRead,
    payload: usize,
    header_lines: usize,
    mesh: &mut MeshData,
    mut lenient: Option<&mut ReadReport>,
) -> Result<Option<usize>, IoError> {
    let vertex_parser = Parser::<VertexRecord>::new();
    let face_parser = Parser::<FaceRecord>::new();
    let mut scratch = Vec::new();
    let mut strip = Vec::new();
    let mut face_line = None;
    let mut lines = LineReader::mid_file(reader);
    for element in header.elements.values() {
        let name = element.name.as_str();
        if name == "face" {
            face_line = Some(header_lines + lines.lines_read() + 1);
        }
        if name == "vertex" {
            // Capacities are hints bounded by the file size: "0 0 0" and "3 0 1 2"
            // are the shortest lines a vertex and a triangle take.
            mesh.positions.reserve_exact(element.count.min(payload / 6));
        } else if name == "face" && mesh.faces.is_empty() {
            let faces = element.count.min(payload / 8);
            mesh.faces = PolygonList::with_capacity(faces, 3 * faces);
        }
        let decoded = matches!(name, "vertex" | "face" | TRISTRIPS);
        for index in 0..element.count {
            // The line count was checked against the header before.
            let Some(number) = lines.next_line()? else {
                return Err(IoError::Truncated {
                    element: element.name.clone(),
                    index,
                });
            };
            let line = lines.line();
            let line_number = Some(header_lines + number);
            if !decoded {
                continue;
            }
            let text = std::str::from_utf8(line).map_err(|_| IoError::PlyData {
                line: line_number,
                element: element.name.clone(),
                index,
                reason: "the line is not valid text".to_owned(),
            })?;
            let mut extra_values = |()| match (extra_values(text, element), &mut lenient) {
                (None, _) => Ok(()),
                (Some(_), Some(report)) => {
                    report.lines_with_extra_values.push(header_lines + number);
                    Ok(())
                }
                (Some(reason), None) => Err(IoError::PlyData {
                    line: line_number,
                    element: element.name.clone(),
                    index,
                    reason,
                }),
            };
            if name == "vertex" {
                let record = vertex_parser
                    .read_ascii_element(text, element)
                    .map_err(|e| element_error(&e, line_number, name, index, text))?;
                extra_values(())?;
                push_vertex(&mut mesh.positions, &record, line_number)?;
            } else {
                let record = face_parser
                    .read_ascii_element(text, element)
                    .map_err(|e| element_error(&e, line_number, name, index, text))?;
                extra_values(())?;
                if name == TRISTRIPS {
                    push_strips(&mut mesh.faces, &mut strip, &record, line_number, index)?;
                } else {
                    push_face(&mut mesh.faces, &mut scratch, &record, line_number)?;
                }
            }
        }
    }
    // Nothing but whitespace may follow the last element.
    while let Some(number) = lines.next_line()? {
        if !lines.line().iter().all(u8::is_ascii_whitespace) {
            match &mut lenient {
                Some(report) => report.ignored_trailing_lines += 1,
                None => return Err(trailing_data(header, Some(header_lines + number), None)),
            }
        }
    }
    Ok(face_line)
}

/// What is wrong when an ascii record that was decoded holds more values than the
/// properties of `element` take (the decoder ignores them): a line of another element,
/// or a file that does not follow its header.
fn extra_values(text: &str, element: &ElementDef) -> Option<String> {
    let mut words = text.split_ascii_whitespace();
    let mut taken = 0_usize;
    for property in element.properties.values() {
        taken += 1;
        let word = words.next();
        if let PropertyType::List(..) = property.data_type {
            let n: usize = word?.parse().ok()?;
            if n > 0 {
                words.nth(n - 1)?;
            }
            taken += n;
        }
    }
    let extra = words.count();
    (extra > 0).then(|| {
        format!(
            "the line holds {} values, but the properties of the element take {taken}",
            taken + extra
        )
    })
}

/// Reads the binary payload; returns the number of its bytes after the last element.
fn read_binary<R: BufRead + Seek>(
    header: &Header,
    mut cursor: R,
    payload: usize,
    big_endian: bool,
    mesh: &mut MeshData,
) -> Result<usize, IoError> {
    let start = cursor
        .stream_position()
        .map_err(IoError::io("read the file"))?;
    // Bytes of the payload not yet read.
    let mut remaining = payload;
    for element in header.elements.values() {
        let name = element.name.as_str();
        match name {
            "vertex" => {
                // Capacities are hints bounded by the file size: 12 and 13 bytes are
                // the usual smallest vertex (3 floats) and triangle records.
                mesh.positions
                    .reserve_exact(element.count.min(payload / 12));
                if let Some(layout) = VertexLayout::of(element).filter(|_| fast::enabled()) {
                    fast::read_vertices(
                        &mut cursor,
                        element.count,
                        &layout,
                        big_endian,
                        &mut mesh.positions,
                    )?;
                } else {
                    read_vertices_generic(&mut cursor, element, big_endian, &mut mesh.positions)?;
                }
            }
            "face" => {
                if mesh.faces.is_empty() {
                    let faces = element.count.min(payload / 13);
                    mesh.faces = PolygonList::with_capacity(faces, 3 * faces);
                }
                if let Some(layout) = FaceLayout::of(element).filter(|_| fast::enabled()) {
                    fast::read_faces(
                        &mut cursor,
                        element.count,
                        &layout,
                        big_endian,
                        remaining,
                        &mut mesh.faces,
                    )?;
                } else {
                    read_faces_generic(&mut cursor, element, big_endian, &mut mesh.faces)?;
                }
            }
            TRISTRIPS => read_strips(&mut cursor, element, big_endian, &mut mesh.faces)?,
            _ => skip_binary_element(&mut cursor, remaining, element, big_endian)?,
        }
        let read = cursor
            .stream_position()
            .map_err(IoError::io("read the file"))?;
        let read = usize::try_from(read.saturating_sub(start)).unwrap_or(usize::MAX);
        remaining = payload.saturating_sub(read);
    }
    Ok(remaining)
}

/// The vertex element through `ply-rs-bw`, for layouts [`VertexLayout`] does not cover.
fn read_vertices_generic(
    cursor: &mut impl Read,
    element: &ElementDef,
    big_endian: bool,
    positions: &mut Vec<DVec3>,
) -> Result<(), IoError> {
    let parser = Parser::<VertexRecord>::new();
    for index in 0..element.count {
        let record = read_binary_element(&parser, cursor, element, big_endian)
            .map_err(|e| element_error(&e, None, "vertex", index, ""))?;
        push_vertex(positions, &record, None)?;
    }
    Ok(())
}

/// The face element through `ply-rs-bw`, for layouts [`FaceLayout`] does not cover.
fn read_faces_generic(
    cursor: &mut impl Read,
    element: &ElementDef,
    big_endian: bool,
    faces: &mut PolygonList,
) -> Result<(), IoError> {
    let mut scratch = Vec::new();
    let parser = Parser::<FaceRecord>::new();
    for index in 0..element.count {
        let record = read_binary_element(&parser, cursor, element, big_endian)
            .map_err(|e| element_error(&e, None, "face", index, ""))?;
        push_face(faces, &mut scratch, &record, None)?;
    }
    Ok(())
}

/// The triangle strips element through `ply-rs-bw` (rare: no fast path).
fn read_strips(
    cursor: &mut impl Read,
    element: &ElementDef,
    big_endian: bool,
    faces: &mut PolygonList,
) -> Result<(), IoError> {
    let mut strip = Vec::new();
    let parser = Parser::<FaceRecord>::new();
    for index in 0..element.count {
        let record = read_binary_element(&parser, cursor, element, big_endian)
            .map_err(|e| element_error(&e, None, TRISTRIPS, index, ""))?;
        push_strips(faces, &mut strip, &record, None, index)?;
    }
    Ok(())
}

fn read_binary_element<E: ply_rs_bw::ply::PropertyAccess>(
    parser: &Parser<E>,
    cursor: &mut impl Read,
    element: &ElementDef,
    big_endian: bool,
) -> Result<E, ParseError> {
    if big_endian {
        parser.read_big_endian_element(cursor, element)
    } else {
        parser.read_little_endian_element(cursor, element)
    }
}

/// Skips an element the mesh does not use: in one step when its records have a
/// fixed size, else record by record. `remaining` bytes of the payload are unread.
fn skip_binary_element<R: BufRead + Seek>(
    cursor: &mut R,
    remaining: usize,
    element: &ElementDef,
    big_endian: bool,
) -> Result<(), IoError> {
    let has_lists = element
        .properties
        .values()
        .any(|p| matches!(p.data_type, PropertyType::List(..)));
    if has_lists {
        let parser = Parser::<Skip>::new();
        for index in 0..element.count {
            read_binary_element(&parser, cursor, element, big_endian)
                .map_err(|e| element_error(&e, None, &element.name, index, ""))?;
        }
    } else {
        let size = min_record_size(element);
        let bytes = element.count.saturating_mul(size);
        if bytes > remaining {
            return Err(IoError::Truncated {
                element: element.name.clone(),
                index: remaining / size.max(1),
            });
        }
        let bytes = i64::try_from(bytes).map_err(|_| IoError::Truncated {
            element: element.name.clone(),
            index: 0,
        })?;
        cursor
            .seek_relative(bytes)
            .map_err(IoError::io("read the file"))?;
    }
    Ok(())
}

fn push_vertex(
    positions: &mut Vec<DVec3>,
    record: &VertexRecord,
    line: Option<usize>,
) -> Result<(), IoError> {
    if let Some(&value) = record.position.iter().find(|c| !c.is_finite()) {
        return Err(IoError::NonFiniteCoordinate {
            line,
            vertex: positions.len(),
            value,
        });
    }
    positions.push(DVec3::from_array(record.position));
    Ok(())
}

fn push_face(
    faces: &mut PolygonList,
    scratch: &mut Vec<u32>,
    record: &FaceRecord,
    line: Option<usize>,
) -> Result<(), IoError> {
    scratch.clear();
    record
        .indices
        .append_to(scratch)
        .map_err(|index| IoError::NegativeIndex {
            line,
            face: faces.len(),
            index,
        })?;
    faces.push(scratch);
    Ok(())
}

/// Appends the triangles of the strips in record `index` of the `tristrips` element.
///
/// The index list holds strips separated by `-1`. In each strip, triangle `k` has the
/// corners `k, k+1, k+2`, with the first two swapped for odd `k` so that all
/// triangles have the orientation of the first (as OpenGL's `GL_TRIANGLE_STRIP`).
/// Triangles with a repeated corner join strips and are no faces: they are skipped.
fn push_strips(
    faces: &mut PolygonList,
    strip: &mut Vec<i64>,
    record: &FaceRecord,
    line: Option<usize>,
    index: usize,
) -> Result<(), IoError> {
    strip.clear();
    record.indices.append_signed_to(strip);
    if let Some(&negative) = strip.iter().find(|&&i| i < -1) {
        return Err(IoError::PlyData {
            line,
            element: TRISTRIPS.to_owned(),
            index,
            reason: format!(
                "vertex index {negative} (only -1, which ends a strip, may be negative)"
            ),
        });
    }
    for run in strip.split(|&i| i == -1) {
        for (k, corners) in run.windows(3).enumerate() {
            // Every value is in 0..=u32::MAX here (the list types are at most 32 bits).
            let vertex = |i: i64| u32::try_from(i).unwrap_or(u32::MAX);
            let [a, b, c] = [corners[0], corners[1], corners[2]].map(vertex);
            if a == b || b == c || a == c {
                continue;
            }
            let triangle = if k % 2 == 0 { [a, b, c] } else { [b, a, c] };
            faces.push(&triangle);
        }
    }
    Ok(())
}

/// The message of a `ply-rs-bw` error without its `Line N:` prefix.
fn message(e: &ParseError) -> String {
    let text = e.to_string();
    match e.line() {
        Some(line) => text
            .strip_prefix(&format!("Line {line}: "))
            .map_or_else(|| text.clone(), str::to_owned),
        None => text,
    }
}

/// The first line of a `ply-rs-bw` message, lowercase first letter, no final period.
pub(super) fn sanitize(message: &str) -> String {
    let first = message.lines().next().unwrap_or("").trim();
    let first = first.strip_suffix('.').unwrap_or(first);
    let mut chars = first.chars();
    match chars.next() {
        Some(c) => c.to_lowercase().chain(chars).collect(),
        None => "malformed data".to_owned(),
    }
}

/// Maps a header error; `line_text` is the offending line, when known.
fn header_error(e: &ParseError, line_text: Option<String>) -> IoError {
    let line = e.line();
    if e.kind() == ErrorKind::InvalidData {
        return IoError::PlyHeader {
            line,
            reason: "the header is not valid text".to_owned(),
        };
    }
    let message = message(e);
    let reason =
        if message.starts_with("Couldn't parse line") || message.starts_with("Invalid element") {
            match line_text {
                Some(text) => format!("cannot parse {text:?}"),
                None => "cannot parse a header line".to_owned(),
            }
        } else if message.starts_with("Unexpected end of file while reading header") {
            "the file ends before \"end_header\"".to_owned()
        } else if message.starts_with("No format line") {
            "no \"format\" line".to_owned()
        } else {
            sanitize(&message)
        };
    IoError::PlyHeader { line, reason }
}

/// Maps an element decoding error; an early end of file is a truncated file. `text`
/// is the line of an ascii element.
fn element_error(
    e: &ParseError,
    line: Option<usize>,
    element: &str,
    index: usize,
    text: &str,
) -> IoError {
    if e.kind() == ErrorKind::UnexpectedEof {
        return IoError::Truncated {
            element: element.to_owned(),
            index,
        };
    }
    let message = message(e);
    let reason = if message.starts_with("Couldn't parse element line") {
        match text.split_ascii_whitespace().find(|w| !is_ply_number(w)) {
            Some(word) => format!("{:?} is not a number", token_text(word.as_bytes())),
            None => "expected numbers separated by spaces".to_owned(),
        }
    } else if message.starts_with("Expected element of type") {
        "too few values on the line".to_owned()
    } else if let Some(rest) = message.strip_prefix("Couldn't parse element at index ") {
        let entry: String = rest.chars().take_while(char::is_ascii_digit).collect();
        format!("cannot parse list entry {entry} as the declared type")
    } else if let Some(value) = message
        .strip_prefix("Parse error.")
        .and_then(|rest| rest.split('\'').nth(1))
    {
        format!("cannot parse {value:?} as the declared type")
    } else {
        sanitize(&message)
    };
    IoError::PlyData {
        line,
        element: element.to_owned(),
        index,
        reason,
    }
}

/// Whether `word` is a number in the ascii PLY grammar of `ply-rs-bw`:
/// `[+-]digits[.digits][(e|E)[+-]digits]` (no `nan`, `inf`, `.5` or `5.`).
fn is_ply_number(word: &str) -> bool {
    fn digits(s: &[u8]) -> usize {
        s.iter().take_while(|b| b.is_ascii_digit()).count()
    }
    let mut s = word.as_bytes();
    if let [b'+' | b'-', rest @ ..] = s {
        s = rest;
    }
    let n = digits(s);
    if n == 0 {
        return false;
    }
    s = &s[n..];
    if let [b'.', rest @ ..] = s {
        let n = digits(rest);
        if n == 0 {
            return false;
        }
        s = &rest[n..];
    }
    if let [b'e' | b'E', rest @ ..] = s {
        s = rest;
        if let [b'+' | b'-', rest @ ..] = s {
            s = rest;
        }
        let n = digits(s);
        if n == 0 {
            return false;
        }
        s = &s[n..];
    }
    s.is_empty()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sanitize_lowercases_and_drops_the_period() {
        assert_eq!(
            sanitize("List length cannot be negative (i8).\n\tmore"),
            "list length cannot be negative (i8)"
        );
        assert_eq!(sanitize(""), "malformed data");
    }

    #[test]
    fn ply_numbers_follow_the_grammar() {
        for ok in ["0", "-1", "+2.5", "1e-7", "1.5E+10", "-0.0"] {
            assert!(is_ply_number(ok), "{ok}");
        }
        for bad in ["nan", "inf", ".5", "5.", "1e", "--1", "", "1.0.0"] {
            assert!(!is_ply_number(bad), "{bad}");
        }
    }

    #[test]
    fn type_names_use_header_syntax() {
        let t = PropertyType::List(ScalarType::UChar, ScalarType::Int);
        assert_eq!(type_name(&t), "list uchar int");
        assert_eq!(
            type_name(&PropertyType::Scalar(ScalarType::Double)),
            "double"
        );
    }
}
