//! The error type of the readers and writers.

use std::fmt;

use crate::format::{Encoding, MeshFormat};

/// Everything that can go wrong while reading or writing a mesh file.
///
/// Messages are lowercase and never contain the file path: the caller knows the path
/// and prints it in front (`error: scan.ply: line 7: …`). Text formats report the
/// 1-based `line` where they know it.
///
/// Vertex, face and facet numbers in messages are 0-based positions in the mesh (the
/// numbering of [`MeshData`](crate::MeshData)); a vertex index quoted from a face is
/// quoted as written in the file (0-based in PLY, 1-based or negative in OBJ).
#[non_exhaustive]
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The operating system refused an operation.
    #[error("failed to {operation}: {source}")]
    Io {
        /// What was being done, e.g. `"read the file"`.
        operation: &'static str,
        /// The underlying error.
        source: std::io::Error,
    },

    /// The path has an extension that names no supported format.
    #[error(
        "unsupported file extension {extension:?} (expected .ply, .stl, .obj, .off, .x3p or .sdf)"
    )]
    UnsupportedExtension {
        /// The extension as written in the path, without the dot.
        extension: String,
    },

    /// The path has no extension, so the format is unknown.
    #[error("no file extension (expected .ply, .stl, .obj, .off, .x3p or .sdf)")]
    MissingExtension,

    /// The file has no bytes at all.
    #[error("the file is empty")]
    Empty,

    /// The PLY header is malformed.
    #[error("{}invalid ply header: {reason}", at(.line))]
    PlyHeader {
        /// Header line, when known.
        line: Option<usize>,
        /// What is wrong.
        reason: String,
    },

    /// The PLY header lacks an element the mesh needs.
    #[error("the ply header has no {element:?} element")]
    MissingElement {
        /// The missing element, e.g. `"vertex"`.
        element: &'static str,
    },

    /// A PLY element lacks a property the mesh needs.
    #[error("element {element:?} has no property {property:?}")]
    MissingProperty {
        /// The element, e.g. `"vertex"`.
        element: String,
        /// The missing property (or the accepted alternatives), e.g. `"z"`.
        property: String,
    },

    /// A PLY property has a type the mesh cannot use, e.g. a list where a coordinate
    /// should be.
    #[error(
        "property {property:?} of element {element:?} is declared as {found:?}, expected {expected}"
    )]
    PropertyType {
        /// The element.
        element: String,
        /// The property.
        property: String,
        /// The declared type, in header syntax (`"list uchar int"`).
        found: String,
        /// What is accepted.
        expected: &'static str,
    },

    /// The header declares more elements than the remaining bytes (binary) or lines
    /// (ascii) can possibly hold: a lying header or a truncated file.
    #[error(
        "header declares {declared} {} but the file holds at most {available}",
        plural(.element)
    )]
    CountExceedsFile {
        /// The element, e.g. `"vertex"`.
        element: String,
        /// The count in the header.
        declared: usize,
        /// The most the rest of the file can hold.
        available: usize,
    },

    /// The header declares more vertices than a mesh can index with `u32`.
    #[error("header declares {declared} vertices, more than the {max} a mesh can index")]
    TooManyVertices {
        /// The count in the header.
        declared: usize,
        /// The largest supported count.
        max: usize,
    },

    /// A binary file ends in the middle of an element.
    #[error("the file ends in the middle of {element} {index}")]
    Truncated {
        /// The element being read, e.g. `"face"`.
        element: String,
        /// Its 0-based index.
        index: usize,
    },

    /// A PLY element cannot be decoded (malformed number, too few values, …).
    #[error("{}cannot read {element} {index}: {reason}", at(.line))]
    PlyData {
        /// Line of an ascii file.
        line: Option<usize>,
        /// The element, e.g. `"vertex"`.
        element: String,
        /// Its 0-based index.
        index: usize,
        /// What is wrong.
        reason: String,
    },

    /// A vertex coordinate is NaN or infinite.
    #[error("{}vertex {vertex} has a non-finite coordinate ({value})", at(.line))]
    NonFiniteCoordinate {
        /// Line of a text file.
        line: Option<usize>,
        /// The vertex, 0-based.
        vertex: usize,
        /// The offending value.
        value: f64,
    },

    /// An STL facet has a NaN or infinite coordinate.
    #[error("{}facet {facet} has a non-finite coordinate ({value})", at(.line))]
    NonFiniteFacet {
        /// Line of an ascii file.
        line: Option<usize>,
        /// The facet, 0-based.
        facet: usize,
        /// The offending value.
        value: f64,
    },

    /// A face refers to a vertex that does not exist.
    #[error(
        "{}face {face} refers to vertex {index}, but only {} defined",
        at(.line),
        vertices_are(*.n_vertices)
    )]
    FaceIndexOutOfRange {
        /// Line of a text file.
        line: Option<usize>,
        /// The face, 0-based.
        face: usize,
        /// The vertex index as written in the file.
        index: i64,
        /// The number of vertices available to it.
        n_vertices: usize,
    },

    /// A PLY face holds a negative vertex index.
    #[error(
        "{}face {face} refers to vertex {index}; ply vertex indices must not be negative",
        at(.line)
    )]
    NegativeIndex {
        /// Line of an ascii file.
        line: Option<usize>,
        /// The face, 0-based.
        face: usize,
        /// The index as written in the file.
        index: i64,
    },

    /// An OBJ face holds the vertex index 0 (OBJ counts from 1).
    #[error("line {line}: face {face} refers to vertex 0, but obj indices start at 1")]
    ZeroIndex {
        /// The line.
        line: usize,
        /// The face, 0-based.
        face: usize,
    },

    /// A text file does not follow the grammar of its format.
    #[error("line {line}: expected {expected}, found {}", found_text(.found))]
    Syntax {
        /// The line.
        line: usize,
        /// What the grammar wants there.
        expected: &'static str,
        /// The token found, or `None` at the end of the line or file.
        found: Option<String>,
    },

    /// A text format holds control bytes: most likely a binary file with the wrong
    /// extension.
    #[error("line {line}: unexpected binary data; this does not look like a text file")]
    NotText {
        /// The line.
        line: usize,
    },

    /// A file read as OBJ has no vertex (`v`) lines and a line that starts with no OBJ
    /// statement: it is not an OBJ file, often a file of another format with the
    /// wrong extension.
    #[error("line {line}: {keyword:?} is not an obj statement{}", format_hint(.format))]
    NotObj {
        /// The line of the first word that is no OBJ statement.
        line: usize,
        /// That word.
        keyword: String,
        /// The format the file looks like, when its first word tells (`ply`, `solid`,
        /// `OFF`).
        format: Option<MeshFormat>,
    },

    /// The file holds more than its header declares: elements beyond the declared
    /// counts, or bytes after the last binary element.
    #[error(
        "{}{} after the {} the header declares",
        at(.line),
        unexpected(.bytes),
        counted(.element, *.count)
    )]
    TrailingData {
        /// The first line of the extra data in a text file.
        line: Option<usize>,
        /// The number of extra bytes in a binary file.
        bytes: Option<u64>,
        /// The last element of the header, e.g. `"face"`.
        element: String,
        /// Its declared count.
        count: usize,
    },

    /// A PLY file keeps its faces in an element this reader cannot read (only `face`
    /// and `tristrips` are read).
    #[error(
        "element {element:?} holds vertex indices but is no face element this reader supports (\"face\", \"tristrips\")"
    )]
    UnsupportedFaceElement {
        /// The element, e.g. `"range_grid"`.
        element: String,
    },

    /// The OFF header is malformed or names a variant that is not supported.
    #[error("{}invalid off header: {reason}", at(.line))]
    OffHeader {
        /// Header line, when known.
        line: Option<usize>,
        /// What is wrong.
        reason: String,
    },

    /// A weld tolerance that is negative, NaN or infinite.
    #[error("invalid weld tolerance {value}: expected a finite number, 0 or more")]
    WeldTolerance {
        /// The tolerance given.
        value: f64,
    },

    /// The triangle count in a binary STL header disagrees with the file length.
    #[error(
        "binary stl header declares {declared} triangles, which needs {} bytes, but the file has {file_length} bytes",
        84 + 50 * u64::from(*.declared)
    )]
    StlTriangleCount {
        /// The count in the header.
        declared: u32,
        /// The file length in bytes.
        file_length: usize,
    },

    /// The file is too short for a binary STL and does not start with `solid`.
    #[error(
        "the file has {file_length} bytes, too short for a binary stl (at least 84), and it does not start with \"solid\""
    )]
    StlTooShort {
        /// The file length in bytes.
        file_length: usize,
    },

    /// A vertex attribute to write does not have one value per vertex.
    #[error("attribute {attribute:?} has {found} values but the mesh has {expected} vertices")]
    AttributeLength {
        /// The attribute (`"colors"` for the colours).
        attribute: String,
        /// The number of vertices.
        expected: usize,
        /// The number of values given.
        found: usize,
    },

    /// A vertex attribute name cannot be used as a PLY property name.
    #[error("invalid attribute name {name:?}: {reason}")]
    AttributeName {
        /// The name.
        name: String,
        /// Why it is refused.
        reason: &'static str,
    },

    /// A non-finite attribute value cannot be written to an ascii PLY file.
    #[error(
        "attribute {attribute:?} is {value} at vertex {vertex}, which ascii ply cannot hold (use a binary encoding)"
    )]
    NonFiniteAttribute {
        /// The attribute.
        attribute: String,
        /// The vertex, 0-based.
        vertex: usize,
        /// The value.
        value: f64,
    },

    /// Two distinct corners of a face round to the same point in 32-bit floats, which
    /// an STL reader would join into one vertex.
    #[error(
        "face {face}: vertices {a} and {b} round to the same point in 32-bit floats (closer together than single precision resolves, or below its range), so an STL file cannot keep them apart; write PLY or OBJ, or scale the mesh"
    )]
    CornersCoincide {
        /// The face, 0-based.
        face: usize,
        /// Its first vertex of the pair.
        a: u32,
        /// Its second vertex of the pair.
        b: u32,
    },

    /// A coordinate is too large for a 32-bit float (STL, or single precision).
    #[error("vertex {vertex} has coordinate {value:e}, beyond the range of a 32-bit float")]
    CoordinateOutOfRange {
        /// The vertex, 0-based.
        vertex: usize,
        /// The coordinate.
        value: f64,
    },

    /// The format has no such encoding (STL is little-endian by definition).
    #[error("{format} has no {encoding} encoding")]
    UnsupportedEncoding {
        /// The format.
        format: MeshFormat,
        /// The requested encoding.
        encoding: Encoding,
    },

    /// An X3P file that is no readable zip archive (truncated, not a zip), or lacks
    /// `main.xml`.
    #[error("invalid x3p archive: {reason}")]
    X3pArchive {
        /// What is wrong.
        reason: String,
    },

    /// The `main.xml` of an X3P archive is malformed, lacks a field the grid needs, or
    /// holds a value that cannot be used.
    #[error("{}main.xml: {field}: {reason}", at(.line))]
    X3pXml {
        /// The line of `main.xml`, when known.
        line: Option<usize>,
        /// The field, as a path of elements (`"Record1/Axes/CX/Increment"`).
        field: String,
        /// What is wrong.
        reason: String,
    },

    /// An entry of an X3P archive (the point data, the mask of valid points) does not
    /// match what `main.xml` declares.
    #[error("{entry}: {reason}")]
    X3pData {
        /// The entry, e.g. `"bindata/data.bin"`.
        entry: String,
        /// What is wrong.
        reason: String,
    },

    /// An MD5 checksum stored in an X3P archive does not match its entry: the file was
    /// damaged or edited. With [`ReadOptions::lenient`](crate::ReadOptions::lenient)
    /// it is reported in [`ReadReport::checksum_mismatches`](crate::ReadReport::checksum_mismatches)
    /// instead.
    #[error("the md5 checksum of {entry} is {found}, but the archive records {expected}")]
    Checksum {
        /// The entry checked.
        entry: String,
        /// The checksum the archive records.
        expected: String,
        /// The checksum of the entry's bytes.
        found: String,
    },

    /// The header of an SDF file is malformed, lacks a field the grid needs, or holds
    /// a value that cannot be used.
    #[error("{}invalid sdf header: {reason}", at(.line))]
    SdfHeader {
        /// The line of an ascii file.
        line: Option<usize>,
        /// What is wrong.
        reason: String,
    },

    /// A value of an SDF file cannot be read, or there are more or fewer than the
    /// header declares.
    #[error("{}sdf value {index}: {reason}", at(.line))]
    SdfData {
        /// The line of an ascii file.
        line: Option<usize>,
        /// The value, 0-based in file order (row by row).
        index: usize,
        /// What is wrong.
        reason: String,
    },

    /// A height map that breaks its invariants (see
    /// [`HeightMap::new`](crate::HeightMap::new)).
    #[error("invalid height map: {reason}")]
    InvalidHeightMap {
        /// What is wrong.
        reason: String,
    },

    /// A mesh to write as a height map (X3P, SDF) whose vertices do not lie on a
    /// regular grid (see [`HeightMap::from_mesh`](crate::HeightMap::from_mesh)).
    #[error("not a height map: {reason}")]
    NotAGrid {
        /// What is wrong.
        reason: String,
    },

    /// A height-map function was given a mesh format.
    #[error("{format} files hold meshes, not height maps (expected .x3p or .sdf)")]
    NotHeightMapFormat {
        /// The format.
        format: MeshFormat,
    },

    /// More triangles than a binary STL file can count.
    #[error("{count} triangles are more than the {max} a binary stl can hold")]
    TooManyTriangles {
        /// The number of triangles after fan triangulation.
        count: usize,
        /// The limit, `u32::MAX`.
        max: usize,
    },
}

impl IoError {
    /// The 1-based line where the error was found, when the format is text and the
    /// line is known.
    #[must_use]
    pub fn line(&self) -> Option<usize> {
        match self {
            Self::PlyHeader { line, .. }
            | Self::OffHeader { line, .. }
            | Self::X3pXml { line, .. }
            | Self::SdfHeader { line, .. }
            | Self::SdfData { line, .. }
            | Self::TrailingData { line, .. }
            | Self::PlyData { line, .. }
            | Self::NonFiniteCoordinate { line, .. }
            | Self::NonFiniteFacet { line, .. }
            | Self::FaceIndexOutOfRange { line, .. }
            | Self::NegativeIndex { line, .. } => *line,
            Self::ZeroIndex { line, .. }
            | Self::Syntax { line, .. }
            | Self::NotText { line }
            | Self::NotObj { line, .. } => Some(*line),
            _ => None,
        }
    }

    pub(crate) fn io(operation: &'static str) -> impl FnOnce(std::io::Error) -> Self {
        move |source| Self::Io { operation, source }
    }
}

/// `"line 7: "` or nothing.
struct LinePrefix(Option<usize>);

impl fmt::Display for LinePrefix {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(line) => write!(f, "line {line}: "),
            None => Ok(()),
        }
    }
}

fn at(line: &Option<usize>) -> LinePrefix {
    LinePrefix(*line)
}

fn plural(element: &str) -> String {
    match element {
        "vertex" => "vertices".to_owned(),
        "face" => "faces".to_owned(),
        other => format!("{other:?} elements"),
    }
}

/// `"4 faces"`, `"1 vertex"`, `"2 \"edge\" elements"`.
fn counted(element: &str, n: usize) -> String {
    match (element, n) {
        ("vertex", 1) => "1 vertex".to_owned(),
        ("face", 1) => "1 face".to_owned(),
        (other, 1) => format!("1 {other:?} element"),
        _ => format!("{n} {}", plural(element)),
    }
}

fn unexpected(bytes: &Option<u64>) -> String {
    match bytes {
        None => "unexpected data".to_owned(),
        Some(1) => "1 unexpected byte".to_owned(),
        Some(n) => format!("{n} unexpected bytes"),
    }
}

fn format_hint(format: &Option<MeshFormat>) -> String {
    match format {
        Some(format) => {
            let article = if *format == MeshFormat::Ply {
                "a"
            } else {
                "an"
            };
            format!("; is this {article} {format} file? rename it to .{format}")
        }
        None => ", and the file has no vertex (\"v\") lines".to_owned(),
    }
}

fn vertices_are(n: usize) -> String {
    if n == 1 {
        "1 vertex is".to_owned()
    } else {
        format!("{n} vertices are")
    }
}

fn found_text(found: &Option<String>) -> String {
    match found {
        Some(token) => format!("{token:?}"),
        None => "nothing".to_owned(),
    }
}
