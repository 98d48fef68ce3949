//! X3P writer.

use std::fmt::Write as _;
use std::io::{Cursor, Write};

use md5::{Digest, Md5};
use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, ZipWriter};

use super::{CHECKSUM_FILE, DATA_BIN, MAIN_XML, VALID_BIN};
use crate::error::IoError;
use crate::height_map::{HeightMap, LengthUnit};

/// Writes `map` as an X3P archive: `main.xml` (Record1: a SUR feature, incremental x
/// and y axes with the spacings in metres, an absolute z axis of doubles; Record3:
/// the grid size and links to the data with their MD5 checksums; Record4: the
/// checksum file), `bindata/data.bin` (the heights in metres, little-endian `f64`,
/// NaN at invalid points), `bindata/valid.bin` when a point is invalid (one bit per
/// point, least significant bit first, 1 for valid) and `md5checksum.hex`. Entries
/// are deflated and carry no time stamp (the zip epoch), so the same map gives the
/// same bytes.
pub(crate) fn write_x3p_to<W: Write>(mut writer: W, map: &HeightMap) -> Result<(), IoError> {
    map.check()?;
    let map = map.to_unit(LengthUnit::Metre)?;
    let n = map.z.len();
    let data: Vec<u8> = map.z.iter().flat_map(|z| z.to_le_bytes()).collect();
    let invalid = map.z.iter().any(|z| z.is_nan());
    let mask = invalid.then(|| {
        let mut mask = vec![0u8; n.div_ceil(8)];
        for (k, z) in map.z.iter().enumerate() {
            if !z.is_nan() {
                mask[k / 8] |= 1 << (k % 8);
            }
        }
        mask
    });
    let xml = main_xml(&map, &data, mask.as_deref());
    let archive = (|| {
        let mut zip = ZipWriter::new(Cursor::new(Vec::new()));
        let options = SimpleFileOptions::default().compression_method(CompressionMethod::Deflated);
        zip.start_file(MAIN_XML, options)?;
        zip.write_all(xml.as_bytes())?;
        zip.start_file(DATA_BIN, options)?;
        zip.write_all(&data)?;
        if let Some(mask) = &mask {
            zip.start_file(VALID_BIN, options)?;
            zip.write_all(mask)?;
        }
        zip.start_file(CHECKSUM_FILE, options)?;
        writeln!(zip, "{} *{MAIN_XML}", md5_hex(xml.as_bytes()))?;
        Ok::<_, zip::result::ZipError>(zip.finish()?.into_inner())
    })()
    .map_err(|e| IoError::X3pArchive {
        reason: format!("cannot build the archive: {e}"),
    })?;
    writer
        .write_all(&archive)
        .and_then(|()| writer.flush())
        .map_err(IoError::io("write the file"))
}

fn md5_hex(bytes: &[u8]) -> String {
    Md5::digest(bytes).iter().fold(String::new(), |mut s, b| {
        let _ = write!(s, "{b:02x}");
        s
    })
}

/// `main.xml` for `map` (in metres), with the checksums of `data` and `mask`.
fn main_xml(map: &HeightMap, data: &[u8], mask: Option<&[u8]>) -> String {
    // `{:e}` is the shortest decimal that reads back to the same f64.
    let mut xml = format!(
        r#"<?xml version="1.0" encoding="UTF-8" standalone="no" ?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:schemaLocation="http://www.opengps.eu/2008/ISO5436_2 http://www.opengps.eu/2008/ISO5436_2/ISO5436_2.xsd">
  <Record1>
    <Revision>ISO5436 - 2000</Revision>
    <FeatureType>SUR</FeatureType>
    <Axes>
      <CX>
        <AxisType>I</AxisType>
        <DataType>D</DataType>
        <Increment>{dx:e}</Increment>
        <Offset>0</Offset>
      </CX>
      <CY>
        <AxisType>I</AxisType>
        <DataType>D</DataType>
        <Increment>{dy:e}</Increment>
        <Offset>0</Offset>
      </CY>
      <CZ>
        <AxisType>A</AxisType>
        <DataType>D</DataType>
      </CZ>
    </Axes>
  </Record1>
  <Record3>
    <MatrixDimension>
      <SizeX>{nx}</SizeX>
      <SizeY>{ny}</SizeY>
      <SizeZ>1</SizeZ>
    </MatrixDimension>
    <DataLink>
      <PointDataLink>{DATA_BIN}</PointDataLink>
      <MD5ChecksumPointData>{data_md5}</MD5ChecksumPointData>
"#,
        dx = map.dx,
        dy = map.dy,
        nx = map.nx,
        ny = map.ny,
        data_md5 = md5_hex(data),
    );
    if let Some(mask) = mask {
        let _ = write!(
            xml,
            "      <ValidPointsLink>{VALID_BIN}</ValidPointsLink>\n      <MD5ChecksumValidPoints>{}</MD5ChecksumValidPoints>\n",
            md5_hex(mask)
        );
    }
    xml.push_str(
        "    </DataLink>\n  </Record3>\n  <Record4>\n    <ChecksumFile>md5checksum.hex</ChecksumFile>\n  </Record4>\n</p:ISO5436_2>\n",
    );
    xml
}
