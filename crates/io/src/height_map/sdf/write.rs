//! SDF writer (ascii).

use std::io::{BufWriter, Write};
use std::time::{SystemTime, UNIX_EPOCH};

use crate::error::IoError;
use crate::height_map::{HeightMap, LengthUnit};

/// Writes `map` as an ascii SDF file (`aISO-1.0`): the twelve header fields of ISO
/// 25178-71 (spacings in metres, `Zscale = 1`, `DataType = 7`, double, the dates the
/// current UTC time), `*`, one line of heights in metres per profile (the shortest
/// decimal that reads back to the same `f64`; `BAD` at invalid points), `*`, an
/// empty trailer, `*`.
///
/// The counts of the binary variant are `u16`; ascii has no such limit.
pub(crate) fn write_sdf_to<W: Write>(writer: W, map: &HeightMap) -> Result<(), IoError> {
    map.check()?;
    let map = map.to_unit(LengthUnit::Metre)?;
    let now = date(SystemTime::now());
    let mut out = BufWriter::new(writer);
    (|| {
        writeln!(out, "aISO-1.0")?;
        writeln!(out, "ManufacID = beltrami")?;
        writeln!(out, "CreateDate = {now}")?;
        writeln!(out, "ModDate = {now}")?;
        writeln!(out, "NumPoints = {}", map.nx)?;
        writeln!(out, "NumProfiles = {}", map.ny)?;
        writeln!(out, "Xscale = {:e}", map.dx)?;
        writeln!(out, "Yscale = {:e}", map.dy)?;
        writeln!(out, "Zscale = 1")?;
        writeln!(out, "Zresolution = -1")?;
        writeln!(out, "Compression = 0")?;
        writeln!(out, "DataType = 7")?;
        writeln!(out, "CheckType = 0")?;
        writeln!(out, "*")?;
        for row in map.z.chunks(map.nx.max(1)) {
            for (i, z) in row.iter().enumerate() {
                let separator = if i == 0 { "" } else { " " };
                if z.is_nan() {
                    write!(out, "{separator}BAD")?;
                } else {
                    write!(out, "{separator}{z:e}")?;
                }
            }
            writeln!(out)?;
        }
        writeln!(out, "*")?;
        writeln!(out, "*")?;
        out.flush()
    })()
    .map_err(IoError::io("write the file"))
}

/// `ddmmyyyyhhmm` in UTC, as the SDF header dates are written.
fn date(time: SystemTime) -> String {
    let seconds = time.duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let days = i64::try_from(seconds / 86_400).unwrap_or(0);
    let minutes = seconds % 86_400 / 60;
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{day:02}{month:02}{year:04}{:02}{:02}",
        minutes / 60,
        minutes % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn dates_are_day_month_year_hour_minute() {
        assert_eq!(date(UNIX_EPOCH), "010119700000");
        // 2024-02-29 13:45 UTC.
        let leap = UNIX_EPOCH + Duration::from_secs(1_709_214_300);
        assert_eq!(date(leap), "290220241345");
    }
}
