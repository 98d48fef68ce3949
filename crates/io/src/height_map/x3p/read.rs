//! X3P reader.

use std::io::{Read, Seek};

use beltrami_halfedge::MAX_ELEMENTS;
use md5::{Digest, Md5};
use roxmltree::{Document, Node};
use zip::ZipArchive;
use zip::result::ZipError;

use super::{CHECKSUM_FILE, MAIN_XML, VALID_BIN};
use crate::error::IoError;
use crate::height_map::{HeightMap, LengthUnit};

/// The most a deflate stream can expand (1032:1, plus a little for tiny entries):
/// an entry that claims more than this from its compressed size is refused before
/// anything is allocated for it.
const MAX_DEFLATE_RATIO: u64 = 1032;
/// The largest `main.xml` read (an inline point list of millions of points fits).
const MAX_XML_BYTES: u64 = 1 << 30;

/// How the values of an axis are stored (`DataType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum DataType {
    /// `I`: 16-bit signed integers.
    I16,
    /// `L`: 32-bit signed integers.
    I32,
    /// `F`: 32-bit floats.
    F32,
    /// `D`: 64-bit floats.
    F64,
}

impl DataType {
    fn bytes(self) -> usize {
        match self {
            Self::I16 => 2,
            Self::I32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    /// The value at the start of `bytes` (little-endian), as `f64`.
    fn decode(self, bytes: &[u8]) -> f64 {
        match self {
            Self::I16 => f64::from(i16::from_le_bytes([bytes[0], bytes[1]])),
            Self::I32 => f64::from(i32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])),
            Self::F32 => f64::from(f32::from_le_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])),
            Self::F64 => f64::from_le_bytes(std::array::from_fn(|k| bytes[k])),
        }
    }
}

/// What the reader found wrong with the checksums (with `lenient`), one line each.
pub(crate) type ChecksumNotes = Vec<String>;

/// Reads an X3P archive into a height map in metres. With `lenient`, checksums that
/// do not match are returned as notes instead of failing the read.
pub(crate) fn read_x3p<R: Read + Seek>(
    reader: R,
    lenient: bool,
) -> Result<(HeightMap, ChecksumNotes), IoError> {
    let mut archive = ZipArchive::new(reader).map_err(|e| archive_error(&e))?;
    let mut notes = Vec::new();
    let xml_bytes = read_main_xml(&mut archive, lenient, &mut notes)?;
    let doc = parse_main_xml(&xml_bytes)?;
    let description = Description::parse(&doc)?;
    let raw = match &description.data {
        Data::Inline(node) => inline_values(&doc, *node, &description)?,
        Data::Linked { entry, md5 } => {
            let bytes = read_point_data(&mut archive, entry, &description)?;
            if let Some(expected) = md5 {
                verify(entry, expected, &bytes, lenient, &mut notes)?;
            }
            linked_values(&bytes, entry, &description)?
        }
    };
    let mut z = heights(raw, &description)?;
    mask_invalid_points(&mut archive, &description, &mut z, lenient, &mut notes)?;
    let map = HeightMap::new(
        description.nx,
        description.ny,
        description.dx,
        description.dy,
        z,
        LengthUnit::Metre,
    )?;
    Ok((map, notes))
}

/// The bytes of `main.xml`, checked against `md5checksum.hex` when the archive has one.
fn read_main_xml<R: Read + Seek>(
    archive: &mut ZipArchive<R>,
    lenient: bool,
    notes: &mut ChecksumNotes,
) -> Result<Vec<u8>, IoError> {
    let xml_bytes =
        read_entry(archive, MAIN_XML, MAX_XML_BYTES)?.ok_or_else(|| IoError::X3pArchive {
            reason: format!("the archive has no {MAIN_XML}"),
        })?;
    if let Some(sums) = read_entry(archive, CHECKSUM_FILE, 4096)? {
        // `<32 hex digits> *main.xml`, or the digits alone.
        let text = String::from_utf8_lossy(&sums);
        let expected = text.split_whitespace().next().unwrap_or("");
        verify(MAIN_XML, expected, &xml_bytes, lenient, notes)?;
    }
    Ok(xml_bytes)
}

/// `main.xml` parsed as an XML document.
fn parse_main_xml(xml_bytes: &[u8]) -> Result<Document<'_>, IoError> {
    let xml = std::str::from_utf8(xml_bytes).map_err(|e| IoError::X3pXml {
        line: None,
        field: MAIN_XML.into(),
        reason: format!("not UTF-8 text ({e})"),
    })?;
    Document::parse(xml).map_err(|e| IoError::X3pXml {
        line: Some(e.pos().row as usize),
        field: MAIN_XML.into(),
        reason: e.to_string(),
    })
}

/// The bytes of the linked point data `entry`, at most the size the description gives.
fn read_point_data<R: Read + Seek>(
    archive: &mut ZipArchive<R>,
    entry: &str,
    description: &Description<'_, '_>,
) -> Result<Vec<u8>, IoError> {
    let size = description.z_type.bytes() as u64 * description.points as u64;
    read_entry(archive, entry, size)?.ok_or_else(|| IoError::X3pData {
        entry: entry.to_owned(),
        reason: "the archive has no such entry (named by Record3/DataLink/PointDataLink)".into(),
    })
}

/// The raw values of linked point data: exactly one value of the description's type
/// per point.
fn linked_values(
    bytes: &[u8],
    entry: &str,
    description: &Description<'_, '_>,
) -> Result<Vec<Option<f64>>, IoError> {
    let n = description.points;
    let size = description.z_type.bytes() as u64 * n as u64;
    if (bytes.len() as u64) < size {
        return Err(IoError::X3pData {
            entry: entry.to_owned(),
            reason: format!(
                "{} bytes, but SizeX·SizeY·SizeZ = {n} values of type {} need {size}",
                bytes.len(),
                description.z_type_name
            ),
        });
    }
    if bytes.len() as u64 > size {
        return Err(IoError::X3pData {
            entry: entry.to_owned(),
            reason: format!(
                "{} bytes, more than the {size} of SizeX·SizeY·SizeZ = {n} values of type {}",
                bytes.len(),
                description.z_type_name
            ),
        });
    }
    Ok(bytes
        .chunks_exact(description.z_type.bytes())
        .map(|b| Some(description.z_type.decode(b)))
        .collect())
}

/// The heights: the raw values scaled by the z axis's increment and offset, NaN for
/// invalid points; an infinite height is an error.
fn heights(raw: Vec<Option<f64>>, description: &Description<'_, '_>) -> Result<Vec<f64>, IoError> {
    // Without an increment or offset the values are the heights, bit for bit (-0 too).
    let scale = |v: f64| match (description.z_increment, description.z_offset) {
        (None, None) => v,
        (increment, offset) => offset.unwrap_or(0.0) + increment.unwrap_or(1.0) * v,
    };
    let z: Vec<f64> = raw
        .into_iter()
        .map(|value| value.map_or(f64::NAN, scale))
        .collect();
    if let Some(k) = z.iter().position(|z| z.is_infinite()) {
        return Err(IoError::X3pData {
            entry: description.data_name(),
            reason: format!("point {k} has the infinite height {}", z[k]),
        });
    }
    Ok(z)
}

/// Sets the heights of the points that the valid-points mask clears to NaN: the mask
/// the description links, or `bindata/valid.bin` when the archive has one.
fn mask_invalid_points<R: Read + Seek>(
    archive: &mut ZipArchive<R>,
    description: &Description<'_, '_>,
    z: &mut [f64],
    lenient: bool,
    notes: &mut ChecksumNotes,
) -> Result<(), IoError> {
    let (entry, valid_md5) = match &description.valid_link {
        Some((entry, md5)) => (entry.clone(), md5.clone()),
        None if archive.file_names().any(|name| name == VALID_BIN) => (VALID_BIN.to_owned(), None),
        None => return Ok(()),
    };
    let n = description.points;
    let size = n.div_ceil(8) as u64;
    // A mask may be padded; more than a few bytes beyond is not a mask of this grid.
    let mask = read_entry(archive, &entry, size + 64)?.ok_or_else(|| IoError::X3pData {
        entry: entry.clone(),
        reason: "the archive has no such entry (named by Record3/DataLink/ValidPointsLink)".into(),
    })?;
    if let Some(expected) = valid_md5 {
        verify(&entry, &expected, &mask, lenient, notes)?;
    }
    if (mask.len() as u64) < size {
        return Err(IoError::X3pData {
            entry,
            reason: format!(
                "{} bytes, but a mask of {n} points needs {size}",
                mask.len()
            ),
        });
    }
    for (k, z) in z.iter_mut().enumerate() {
        if mask[k / 8] & (1 << (k % 8)) == 0 {
            *z = f64::NAN;
        }
    }
    Ok(())
}

fn archive_error(e: &ZipError) -> IoError {
    IoError::X3pArchive {
        reason: e.to_string(),
    }
}

/// The bytes of the entry `name`, or `None` when the archive has no such entry. An
/// entry larger than `limit`, or larger than its compressed size can hold, is refused
/// before anything is allocated for it.
fn read_entry<R: Read + Seek>(
    archive: &mut ZipArchive<R>,
    name: &str,
    limit: u64,
) -> Result<Option<Vec<u8>>, IoError> {
    let entry_error = |reason: String| IoError::X3pData {
        entry: name.to_owned(),
        reason,
    };
    let file = match archive.by_name(name) {
        Ok(file) => file,
        Err(ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(entry_error(e.to_string())),
    };
    let size = file.size();
    let compressed = file.compressed_size();
    if size > limit {
        return Err(entry_error(format!(
            "{size} bytes, more than the {limit} the archive's description allows"
        )));
    }
    if size
        > compressed
            .saturating_mul(MAX_DEFLATE_RATIO)
            .saturating_add(1024)
    {
        return Err(entry_error(format!(
            "the archive claims {size} bytes from {compressed} compressed ones, more than deflate can hold"
        )));
    }
    let mut bytes = Vec::with_capacity(usize::try_from(size).unwrap_or(0));
    // Read one byte beyond the claim: an entry longer than its header says is an error.
    file.take(size.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| entry_error(format!("cannot decompress: {e}")))?;
    if bytes.len() as u64 != size {
        return Err(entry_error(format!(
            "holds {} bytes, but the archive's directory says {size}",
            bytes.len()
        )));
    }
    Ok(Some(bytes))
}

/// Compares the MD5 digest of `bytes` with `expected` (hex, any case).
fn verify(
    entry: &str,
    expected: &str,
    bytes: &[u8],
    lenient: bool,
    notes: &mut ChecksumNotes,
) -> Result<(), IoError> {
    let digest = Md5::digest(bytes);
    let found: String = digest.iter().map(|b| format!("{b:02x}")).collect();
    if found.eq_ignore_ascii_case(expected.trim()) {
        return Ok(());
    }
    let error = IoError::Checksum {
        entry: entry.to_owned(),
        expected: expected.trim().to_owned(),
        found,
    };
    if lenient {
        notes.push(error.to_string());
        Ok(())
    } else {
        Err(error)
    }
}

/// Where the point data are.
enum Data<'a, 'input> {
    /// `Record3/DataList`: one `Datum` per point.
    Inline(Node<'a, 'input>),
    /// `Record3/DataLink/PointDataLink`, with its MD5 checksum when given.
    Linked { entry: String, md5: Option<String> },
}

/// What `main.xml` says about the grid.
struct Description<'a, 'input> {
    nx: usize,
    ny: usize,
    points: usize,
    dx: f64,
    dy: f64,
    z_type: DataType,
    z_type_name: String,
    /// `CZ/Increment`, when given.
    z_increment: Option<f64>,
    /// `CZ/Offset`, when given.
    z_offset: Option<f64>,
    data: Data<'a, 'input>,
    /// `Record3/DataLink/ValidPointsLink` and its checksum.
    valid_link: Option<(String, Option<String>)>,
}

impl<'a, 'input> Description<'a, 'input> {
    fn parse(doc: &'a Document<'input>) -> Result<Self, IoError> {
        let xml = Xml { doc };
        let root = doc.root_element();
        let record1 = xml.surface_record(root)?;
        let axes = xml.child(record1, "Axes", "Record1/Axes")?;
        let dx = xml.increment(axes, "CX")?;
        let dy = xml.increment(axes, "CY")?;
        let ZAxis {
            z_type,
            z_type_name,
            z_increment,
            z_offset,
        } = xml.z_axis(axes)?;
        let record3 = xml.child(root, "Record3", "Record3")?;
        let (nx, ny, points) = xml.grid_size(record3)?;
        let (data, valid_link) = xml.data_location(record3)?;
        Ok(Self {
            nx,
            ny,
            points,
            dx,
            dy,
            z_type,
            z_type_name,
            z_increment,
            z_offset,
            data,
            valid_link,
        })
    }

    /// The name of the point data in messages.
    fn data_name(&self) -> String {
        match &self.data {
            Data::Inline(_) => format!("{MAIN_XML} (Record3/DataList)"),
            Data::Linked { entry, .. } => entry.clone(),
        }
    }
}

/// The raw values of `Record3/DataList`: one `Datum` per point, empty for an invalid
/// point.
fn inline_values(
    doc: &Document<'_>,
    list: Node<'_, '_>,
    description: &Description<'_, '_>,
) -> Result<Vec<Option<f64>>, IoError> {
    let xml = Xml { doc };
    let n = description.points;
    let mut values = Vec::new();
    for datum in list
        .children()
        .filter(|c| c.is_element() && c.tag_name().name() == "Datum")
    {
        if values.len() == n {
            return Err(xml.error(
                datum,
                "Record3/DataList/Datum",
                format!("more than SizeX·SizeY·SizeZ = {n} points"),
            ));
        }
        let text = xml.text(datum);
        if text.is_empty() {
            values.push(None);
            continue;
        }
        // With incremental x and y axes a point holds its height alone; a list of
        // x;y;z triples is read for its last value.
        let last = text
            .rsplit([';', ' ', '\t', '\n', '\r'])
            .next()
            .unwrap_or(text);
        let value = last
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                xml.error(
                    datum,
                    "Record3/DataList/Datum",
                    format!("point {}: {text:?} is not a finite number", values.len()),
                )
            })?;
        let integral = matches!(description.z_type, DataType::I16 | DataType::I32);
        if integral && value.fract() != 0.0 {
            return Err(xml.error(
                datum,
                "Record3/DataList/Datum",
                format!(
                    "point {}: {text:?} is not a whole number, as DataType {} needs",
                    values.len(),
                    description.z_type_name
                ),
            ));
        }
        values.push(Some(value));
    }
    if values.len() != n {
        return Err(xml.error(
            list,
            "Record3/DataList",
            format!("{} points, but SizeX·SizeY·SizeZ = {n}", values.len()),
        ));
    }
    Ok(values)
}

/// Element look-ups that name the offending field and line.
struct Xml<'a, 'input> {
    doc: &'a Document<'input>,
}

impl<'a, 'input> Xml<'a, 'input> {
    fn line(&self, node: Node<'_, '_>) -> usize {
        self.doc.text_pos_at(node.range().start).row as usize
    }

    fn error(&self, node: Node<'_, '_>, field: &str, reason: String) -> IoError {
        IoError::X3pXml {
            line: Some(self.line(node)),
            field: field.to_owned(),
            reason,
        }
    }

    /// The first child element of `node` with the local name `name`.
    fn find(&self, node: Node<'a, 'input>, name: &str) -> Option<Node<'a, 'input>> {
        node.children()
            .find(|c| c.is_element() && c.tag_name().name() == name)
    }

    fn child(
        &self,
        node: Node<'a, 'input>,
        name: &str,
        field: &str,
    ) -> Result<Node<'a, 'input>, IoError> {
        self.find(node, name)
            .ok_or_else(|| self.error(node, field, "missing".into()))
    }

    /// The text of an element, trimmed.
    fn text(&self, node: Node<'a, 'input>) -> &'a str {
        node.text().map_or("", str::trim)
    }

    fn optional_number(
        &self,
        node: Node<'a, 'input>,
        name: &str,
        field: &str,
    ) -> Result<Option<f64>, IoError> {
        let Some(child) = self.find(node, name) else {
            return Ok(None);
        };
        let text = self.text(child);
        text.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .map(Some)
            .ok_or_else(|| self.error(child, field, format!("{text:?} is not a finite number")))
    }

    /// The spacing of the incremental axis `axis` (`CX` or `CY`) in metres.
    fn increment(&self, axes: Node<'a, 'input>, axis: &str) -> Result<f64, IoError> {
        let node = self.child(axes, axis, &format!("Record1/Axes/{axis}"))?;
        let kind_field = format!("Record1/Axes/{axis}/AxisType");
        let kind = self.child(node, "AxisType", &kind_field)?;
        if self.text(kind) != "I" {
            return Err(self.error(
                kind,
                &kind_field,
                format!(
                    "{:?}: only incremental axes (I) give a grid; absolute axes (A) list each point's position",
                    self.text(kind)
                ),
            ));
        }
        let field = format!("Record1/Axes/{axis}/Increment");
        let increment = self.child(node, "Increment", &field)?;
        let text = self.text(increment);
        text.parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v > 0.0)
            .ok_or_else(|| {
                self.error(
                    increment,
                    &field,
                    format!("{text:?} is not a finite positive spacing"),
                )
            })
    }

    /// `Record3/MatrixDimension/<name>`, a count of at least 1.
    fn size(&self, dimension: Node<'a, 'input>, name: &str) -> Result<usize, IoError> {
        let field = format!("Record3/MatrixDimension/{name}");
        let node = self.child(dimension, name, &field)?;
        let text = self.text(node);
        text.parse::<usize>()
            .ok()
            .filter(|&n| n > 0)
            .ok_or_else(|| {
                self.error(
                    node,
                    &field,
                    format!("{text:?} is not a count of 1 or more"),
                )
            })
    }
}

/// What `Record1/Axes/CZ` says about the heights.
struct ZAxis {
    z_type: DataType,
    /// The type as written (`I`, `L`, `F` or `D`).
    z_type_name: String,
    /// `Increment`, when given (never 0).
    z_increment: Option<f64>,
    /// `Offset`, when given.
    z_offset: Option<f64>,
}

/// The steps of [`Description::parse`].
impl<'a, 'input> Xml<'a, 'input> {
    /// `Record1`, after checking that the root is `ISO5436_2` and the feature type is
    /// `SUR`.
    fn surface_record(&self, root: Node<'a, 'input>) -> Result<Node<'a, 'input>, IoError> {
        if root.tag_name().name() != "ISO5436_2" {
            return Err(self.error(
                root,
                root.tag_name().name(),
                "expected the root element ISO5436_2".into(),
            ));
        }
        let record1 = self.child(root, "Record1", "Record1")?;
        let feature = self.child(record1, "FeatureType", "Record1/FeatureType")?;
        let feature_type = self.text(feature);
        if feature_type != "SUR" {
            return Err(self.error(
                feature,
                "Record1/FeatureType",
                format!("{feature_type:?}: only SUR (an areal surface on a grid) is a height map"),
            ));
        }
        Ok(record1)
    }

    /// The z axis of `Record1/Axes`: its data type, increment and offset.
    fn z_axis(&self, axes: Node<'a, 'input>) -> Result<ZAxis, IoError> {
        let cz = self.child(axes, "CZ", "Record1/Axes/CZ")?;
        let type_node = self.child(cz, "DataType", "Record1/Axes/CZ/DataType")?;
        let z_type_name = self.text(type_node).to_owned();
        let z_type = match z_type_name.as_str() {
            "I" => DataType::I16,
            "L" => DataType::I32,
            "F" => DataType::F32,
            "D" => DataType::F64,
            other => {
                return Err(self.error(
                    type_node,
                    "Record1/Axes/CZ/DataType",
                    format!("{other:?}: expected I, L, F or D"),
                ));
            }
        };
        let z_increment = self.optional_number(cz, "Increment", "Record1/Axes/CZ/Increment")?;
        if z_increment == Some(0.0) {
            return Err(self.error(
                cz,
                "Record1/Axes/CZ/Increment",
                "0: heights would all be the offset".into(),
            ));
        }
        let z_offset = self.optional_number(cz, "Offset", "Record1/Axes/CZ/Offset")?;
        Ok(ZAxis {
            z_type,
            z_type_name,
            z_increment,
            z_offset,
        })
    }

    /// `SizeX`, `SizeY` and their product, the number of points, from
    /// `Record3/MatrixDimension` (one layer, indexable by a mesh).
    fn grid_size(&self, record3: Node<'a, 'input>) -> Result<(usize, usize, usize), IoError> {
        let dimension = self.child(record3, "MatrixDimension", "Record3/MatrixDimension")?;
        let nx = self.size(dimension, "SizeX")?;
        let ny = self.size(dimension, "SizeY")?;
        let nz_node = self.child(dimension, "SizeZ", "Record3/MatrixDimension/SizeZ")?;
        let nz = self.size(dimension, "SizeZ")?;
        if nz != 1 {
            return Err(self.error(
                nz_node,
                "Record3/MatrixDimension/SizeZ",
                format!("{nz}: a height map has one layer (SizeZ 1)"),
            ));
        }
        let points = nx
            .checked_mul(ny)
            .filter(|&n| n <= MAX_ELEMENTS)
            .ok_or_else(|| {
                self.error(
                    dimension,
                    "Record3/MatrixDimension",
                    format!("SizeX·SizeY = {nx}·{ny} points, more than the {MAX_ELEMENTS} a mesh can index"),
                )
            })?;
        Ok((nx, ny, points))
    }

    /// Where `Record3` keeps the point data, and the valid-points link with its
    /// checksum when it links one.
    #[allow(clippy::type_complexity)]
    fn data_location(
        &self,
        record3: Node<'a, 'input>,
    ) -> Result<(Data<'a, 'input>, Option<(String, Option<String>)>), IoError> {
        if let Some(link) = self.find(record3, "DataLink") {
            let entry_node = self.child(link, "PointDataLink", "Record3/DataLink/PointDataLink")?;
            let entry = self.text(entry_node).to_owned();
            let md5 = self
                .find(link, "MD5ChecksumPointData")
                .map(|n| self.text(n).to_owned());
            let valid = self.find(link, "ValidPointsLink").map(|n| {
                (
                    self.text(n).to_owned(),
                    self.find(link, "MD5ChecksumValidPoints")
                        .map(|m| self.text(m).to_owned()),
                )
            });
            Ok((Data::Linked { entry, md5 }, valid))
        } else if let Some(list) = self.find(record3, "DataList") {
            Ok((Data::Inline(list), None))
        } else {
            Err(self.error(
                record3,
                "Record3",
                "neither DataLink nor DataList: no point data".into(),
            ))
        }
    }
}
