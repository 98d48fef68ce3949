//! X3P (ISO 25178-72, the XML file format of ISO 5436-2): a zip archive holding
//! `main.xml`, which describes the axes and the grid, the point data (inline in
//! `main.xml` or in a binary entry such as `bindata/data.bin`), an optional bit mask
//! of valid points and MD5 checksums.

mod read;
mod write;

pub(crate) use read::read_x3p;
pub(crate) use write::write_x3p_to;

/// The entry that describes the archive.
const MAIN_XML: &str = "main.xml";
/// The entry holding the MD5 checksum of `main.xml`.
const CHECKSUM_FILE: &str = "md5checksum.hex";
/// Where the writer puts the heights.
const DATA_BIN: &str = "bindata/data.bin";
/// Where the writer puts the mask of valid points.
const VALID_BIN: &str = "bindata/valid.bin";
