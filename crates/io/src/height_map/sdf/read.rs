//! SDF reader, ascii and binary.

use std::io::{BufRead, Read, Seek, SeekFrom};

use beltrami_halfedge::MAX_ELEMENTS;

use super::DataType;
use crate::error::IoError;
use crate::height_map::{HeightMap, LengthUnit};
use crate::text::{LineReader, has_binary_bytes, stream_len, token_text, tokens};

/// The size of a binary header: version 8, manufacturer 10, two dates of 12, two
/// `u16` counts, four `f64` scales, three `u8` codes.
const BINARY_HEADER: usize = 81;

/// Reads an ascii or binary SDF file into a height map in metres.
pub(crate) fn read_sdf<R: BufRead + Seek>(mut reader: R) -> Result<HeightMap, IoError> {
    let length = stream_len(&mut reader)?;
    if length == 0 {
        return Err(IoError::Empty);
    }
    let mut magic = Vec::with_capacity(8);
    reader
        .by_ref()
        .take(8)
        .read_to_end(&mut magic)
        .map_err(IoError::io("read the file"))?;
    reader
        .seek(SeekFrom::Start(0))
        .map_err(IoError::io("read the file"))?;
    if magic.len() == 8 && magic[0] == b'b' && is_version(&magic[1..]) {
        read_binary(reader, length)
    } else {
        read_ascii(reader, length)
    }
}

/// `BCR-1.0` or `ISO-1.0`, the versions after the `a`/`b` of the first line.
fn is_version(version: &[u8]) -> bool {
    version == b"BCR-1.0" || version == b"ISO-1.0"
}

fn header_error(line: Option<usize>, reason: String) -> IoError {
    IoError::SdfHeader { line, reason }
}

/// The header fields that the grid needs, as read, each with its line (and, in an
/// ASCII file, the `Compression` value, which must be 0).
#[derive(Default)]
struct Header {
    compression: Option<(u64, usize)>,
    num_points: Option<(u64, usize)>,
    num_profiles: Option<(u64, usize)>,
    x_scale: Option<(f64, usize)>,
    y_scale: Option<(f64, usize)>,
    z_scale: Option<(f64, usize)>,
    data_type: Option<(u64, usize)>,
}

fn read_ascii<R: BufRead>(reader: R, length: u64) -> Result<HeightMap, IoError> {
    let mut lines = LineReader::new(reader);
    read_version_line(&mut lines)?;
    let (header, header_end) = read_ascii_header(&mut lines)?;
    if let Some((code, line)) = header.compression
        && code != 0
    {
        return Err(header_error(
            Some(line),
            format!("Compression {code}: only uncompressed data (0) is read"),
        ));
    }
    let grid = Grid::from_header(&header, Some(header_end))?;
    let n = grid.points;
    // Each value takes at least two bytes (a digit and a separator).
    let remaining = length.saturating_sub(lines.bytes_read());
    if (n as u64).saturating_mul(2) > remaining.saturating_add(1) {
        return Err(header_error(
            Some(grid.count_line),
            format!(
                "NumPoints × NumProfiles = {n} values need at least {} bytes, but {remaining} follow the header",
                2 * n as u64 - 1
            ),
        ));
    }
    let z = read_ascii_values(&mut lines, &grid, header_end)?;
    grid.height_map(z)
}

/// Reads the version line of an ASCII file (after any blank lines): `aISO-1.0` or
/// `aBCR-1.0`.
fn read_version_line<R: BufRead>(lines: &mut LineReader<R>) -> Result<(), IoError> {
    let first = loop {
        match lines.next_line()? {
            None => return Err(IoError::Empty),
            Some(_) if lines.line().iter().all(u8::is_ascii_whitespace) => {}
            Some(line) => break line,
        }
    };
    let version = lines.line().trim_ascii();
    if !(version.len() == 8 && version[0] == b'a' && is_version(&version[1..])) {
        return Err(header_error(
            Some(first),
            format!(
                "expected the version line aISO-1.0 or aBCR-1.0 (bISO-1.0, bBCR-1.0 for binary), found {:?}",
                token_text(version)
            ),
        ));
    }
    Ok(())
}

/// Reads the `key = value` lines of an ASCII header up to the `*` line: the header and
/// the line number of the `*`.
fn read_ascii_header<R: BufRead>(lines: &mut LineReader<R>) -> Result<(Header, usize), IoError> {
    let mut header = Header::default();
    let header_end = loop {
        let Some(line) = lines.next_line()? else {
            return Err(header_error(
                None,
                "the file ends in the header (no \"*\" line after it)".into(),
            ));
        };
        let text = lines.line();
        if has_binary_bytes(text) {
            return Err(IoError::NotText { line });
        }
        let text = text.trim_ascii();
        if text.is_empty() {
            continue;
        }
        if text == b"*" {
            break line;
        }
        let Some(eq) = text.iter().position(|&b| b == b'=') else {
            return Err(header_error(
                Some(line),
                format!("expected \"key = value\", found {:?}", token_text(text)),
            ));
        };
        let key = String::from_utf8_lossy(text[..eq].trim_ascii()).to_ascii_lowercase();
        let value = text[eq + 1..].trim_ascii();
        let count = |what: &str| {
            std::str::from_utf8(value)
                .ok()
                .and_then(|v| v.parse::<u64>().ok())
                .map(|v| (v, line))
                .ok_or_else(|| {
                    header_error(
                        Some(line),
                        format!(
                            "{what}: expected a whole number, found {:?}",
                            token_text(value)
                        ),
                    )
                })
        };
        let scale = |what: &str| {
            std::str::from_utf8(value)
                .ok()
                .and_then(|v| v.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .map(|v| (v, line))
                .ok_or_else(|| {
                    header_error(
                        Some(line),
                        format!(
                            "{what}: expected a finite number, found {:?}",
                            token_text(value)
                        ),
                    )
                })
        };
        match key.as_str() {
            "numpoints" => header.num_points = Some(count("NumPoints")?),
            "numprofiles" => header.num_profiles = Some(count("NumProfiles")?),
            "xscale" => header.x_scale = Some(scale("Xscale")?),
            "yscale" => header.y_scale = Some(scale("Yscale")?),
            "zscale" => header.z_scale = Some(scale("Zscale")?),
            "datatype" => header.data_type = Some(count("DataType")?),
            "compression" => header.compression = Some(count("Compression")?),
            // ManufacID, CreateDate, ModDate, Zresolution, CheckType and anything else
            // describe the data without changing them.
            _ => {}
        }
    };
    Ok((header, header_end))
}

/// Reads the `grid.points` values after the header (`BAD` for a missing one), scaled
/// by `Zscale`, up to a `*` or the end of the file.
fn read_ascii_values<R: BufRead>(
    lines: &mut LineReader<R>,
    grid: &Grid,
    header_end: usize,
) -> Result<Vec<f64>, IoError> {
    let n = grid.points;
    let mut z = Vec::with_capacity(n);
    let mut last_line = header_end;
    'lines: while let Some(line) = lines.next_line()? {
        last_line = line;
        let text = lines.line();
        if has_binary_bytes(text) {
            return Err(IoError::NotText { line });
        }
        // A `*` ends the data, even right after a value.
        let (data, end) = match text.iter().position(|&b| b == b'*') {
            Some(star) => (&text[..star], true),
            None => (text, false),
        };
        for token in tokens(data) {
            if z.len() == n {
                return Err(IoError::SdfData {
                    line: Some(line),
                    index: n,
                    reason: format!(
                        "more values than NumPoints × NumProfiles = {n}, found {:?}",
                        token_text(token)
                    ),
                });
            }
            if token.eq_ignore_ascii_case(b"BAD") {
                z.push(f64::NAN);
                continue;
            }
            let value = std::str::from_utf8(token)
                .ok()
                .and_then(|t| t.parse::<f64>().ok())
                .filter(|v| v.is_finite())
                .ok_or_else(|| IoError::SdfData {
                    line: Some(line),
                    index: z.len(),
                    reason: format!(
                        "expected a finite number or BAD, found {:?}",
                        token_text(token)
                    ),
                })?;
            z.push(value * grid.z_scale);
        }
        if end {
            break 'lines;
        }
    }
    if z.len() != n {
        return Err(IoError::SdfData {
            line: Some(last_line),
            index: z.len(),
            reason: format!(
                "the data end after {} values, but NumPoints × NumProfiles = {n}",
                z.len()
            ),
        });
    }
    Ok(z)
}

/// The grid a header describes.
struct Grid {
    nx: usize,
    ny: usize,
    points: usize,
    dx: f64,
    dy: f64,
    z_scale: f64,
    data_type: DataType,
    /// The line of the count that makes the grid large (NumProfiles), for messages.
    count_line: usize,
}

impl Grid {
    fn from_header(header: &Header, end: Option<usize>) -> Result<Self, IoError> {
        let missing = |key: &str| header_error(end, format!("no {key} in the header"));
        let (nx, nx_line) = header.num_points.ok_or_else(|| missing("NumPoints"))?;
        let (ny, ny_line) = header.num_profiles.ok_or_else(|| missing("NumProfiles"))?;
        let (dx, dx_line) = header.x_scale.ok_or_else(|| missing("Xscale"))?;
        let (dy, dy_line) = header.y_scale.ok_or_else(|| missing("Yscale"))?;
        let (z_scale, z_line) = header.z_scale.ok_or_else(|| missing("Zscale"))?;
        let (code, code_line) = header.data_type.ok_or_else(|| missing("DataType"))?;
        let at = |line: usize| (line > 0).then_some(line);
        for (name, value, line) in [("NumPoints", nx, nx_line), ("NumProfiles", ny, ny_line)] {
            if value == 0 {
                return Err(header_error(at(line), format!("{name} is 0")));
            }
        }
        for (name, value, line) in [("Xscale", dx, dx_line), ("Yscale", dy, dy_line)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(header_error(
                    at(line),
                    format!("{name} {value}: expected a finite positive spacing (metres)"),
                ));
            }
        }
        if !(z_scale.is_finite() && z_scale != 0.0) {
            return Err(header_error(
                at(z_line),
                format!(
                    "Zscale {z_scale}: expected a finite number other than 0 (metres per unit)"
                ),
            ));
        }
        let data_type = DataType::from_code(code).ok_or_else(|| {
            header_error(
                at(code_line),
                format!("DataType {code}: expected 0 to 7 (uint8, uint16, uint32, float, int8, int16, int32, double)"),
            )
        })?;
        let too_many = || {
            header_error(
                at(ny_line),
                format!("NumPoints × NumProfiles = {nx} × {ny}, more points than a mesh can index"),
            )
        };
        let points = nx
            .checked_mul(ny)
            .filter(|&n| n <= MAX_ELEMENTS as u64)
            .ok_or_else(too_many)?;
        let to_usize = |v: u64| usize::try_from(v).map_err(|_| too_many());
        Ok(Self {
            nx: to_usize(nx)?,
            ny: to_usize(ny)?,
            points: to_usize(points)?,
            dx,
            dy,
            z_scale,
            data_type,
            count_line: ny_line,
        })
    }

    fn height_map(&self, z: Vec<f64>) -> Result<HeightMap, IoError> {
        if let Some(k) = z.iter().position(|z| z.is_infinite()) {
            return Err(IoError::SdfData {
                line: None,
                index: k,
                reason: "the height is beyond the range of a 64-bit float once scaled by Zscale"
                    .into(),
            });
        }
        HeightMap::new(self.nx, self.ny, self.dx, self.dy, z, LengthUnit::Metre)
    }
}

fn read_binary<R: Read>(mut reader: R, length: u64) -> Result<HeightMap, IoError> {
    if length < BINARY_HEADER as u64 {
        return Err(IoError::Truncated {
            element: "binary sdf header".into(),
            index: 0,
        });
    }
    let mut h = [0u8; BINARY_HEADER];
    reader
        .read_exact(&mut h)
        .map_err(IoError::io("read the file"))?;
    let u16_at = |k: usize| u64::from(u16::from_le_bytes([h[k], h[k + 1]]));
    let f64_at = |k: usize| f64::from_le_bytes(std::array::from_fn(|i| h[k + i]));
    // Lines do not exist in binary: fields are named instead, with line 0 for "none".
    let header = Header {
        num_points: Some((u16_at(42), 0)),
        num_profiles: Some((u16_at(44), 0)),
        x_scale: Some((f64_at(46), 0)),
        y_scale: Some((f64_at(54), 0)),
        z_scale: Some((f64_at(62), 0)),
        data_type: Some((u64::from(h[79]), 0)),
        compression: None,
    };
    if h[78] != 0 {
        return Err(header_error(
            None,
            format!("Compression {}: only uncompressed data (0) is read", h[78]),
        ));
    }
    let grid = Grid::from_header(&header, None)?;
    let size = grid.data_type.bytes();
    let needed = (grid.points as u64) * size as u64;
    let available = length - BINARY_HEADER as u64;
    if available < needed {
        return Err(IoError::Truncated {
            element: "sdf point".into(),
            index: usize::try_from(available / size as u64).unwrap_or(usize::MAX),
        });
    }
    let mut bytes = vec![0u8; usize::try_from(needed).unwrap_or(0)];
    reader
        .read_exact(&mut bytes)
        .map_err(IoError::io("read the file"))?;
    // What follows the data (a trailer of comments) is not read.
    let z = bytes
        .chunks_exact(size)
        .map(|b| {
            grid.data_type
                .decode(b)
                .map_or(f64::NAN, |v| v * grid.z_scale)
        })
        .collect();
    grid.height_map(z)
}
