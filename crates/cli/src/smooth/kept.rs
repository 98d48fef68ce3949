//! The input positions through a run, for the summary's mean displacement: in a
//! temporary file rather than in memory, so that the run does not hold a third position
//! buffer (24 bytes per vertex), except on small meshes, where the file's creation,
//! writing and reading back cost more than the memory is worth.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Seek, SeekFrom, Write};

use beltrami_halfedge::DVec3;

/// Meshes of fewer vertices keep their input positions in memory (at most 1.5 MiB,
/// well inside the memory estimate's fixed part, `memory::BASE_BYTES`). On the paper's
/// F-lens and block the temporary file, the release of the positions and their reading
/// back took 0.1–0.3 ms of a 6–10 ms run.
pub(crate) const IN_MEMORY_BELOW: usize = 1 << 16;

/// The input positions, kept until the run is over.
pub(crate) enum KeptPositions {
    /// In an unnamed temporary file, each coordinate's eight bytes (little-endian, the
    /// exact bits): it has no name in any directory (Linux's `O_TMPFILE`, or removed at
    /// once where that is missing; deleted on close on Windows), so nothing is left
    /// behind however the process ends.
    File { file: File, n: usize },
    /// In memory, when no temporary file could be written.
    Memory(Vec<DVec3>),
}

impl KeptPositions {
    /// Keeps a copy of `positions`: in memory below [`IN_MEMORY_BELOW`] vertices, else
    /// written to a new file in the system's temporary directory (in memory when that
    /// fails).
    pub(crate) fn keep(positions: &[DVec3]) -> Self {
        if positions.len() < IN_MEMORY_BELOW {
            return Self::Memory(positions.to_vec());
        }
        Self::in_file_or_memory(positions)
    }

    /// `positions` in a new temporary file, or in memory when none can be written.
    fn in_file_or_memory(positions: &[DVec3]) -> Self {
        match spill(positions) {
            Ok(file) => Self::File {
                file,
                n: positions.len(),
            },
            Err(_) => Self::Memory(positions.to_vec()),
        }
    }

    /// Whether the positions are in a file (not in memory).
    pub(crate) fn in_file(&self) -> bool {
        matches!(self, Self::File { .. })
    }

    /// The kept positions, read back (or copied from memory).
    ///
    /// # Errors
    /// When the temporary file cannot be read back.
    pub(crate) fn read_all(&mut self) -> std::io::Result<Vec<DVec3>> {
        match self {
            Self::Memory(positions) => Ok(positions.clone()),
            Self::File { file, n, .. } => {
                file.seek(SeekFrom::Start(0))?;
                let mut reader = BufReader::with_capacity(1 << 16, &*file);
                let mut out = Vec::with_capacity(*n);
                let mut buf = [0u8; 24];
                for _ in 0..*n {
                    reader.read_exact(&mut buf)?;
                    out.push(decode(&buf));
                }
                Ok(out)
            }
        }
    }

    /// The mean of `|a_i − b_i|` over the kept positions `a` and `after`, summed in
    /// vertex order (the bits of the same sum over positions kept in memory); 0 for no
    /// vertices.
    ///
    /// # Errors
    /// When the temporary file cannot be read back.
    pub(crate) fn mean_displacement(&mut self, after: &[DVec3]) -> std::io::Result<f64> {
        match self {
            Self::Memory(positions) => Ok(mean_distance(positions.iter().copied(), after)),
            Self::File { file, n, .. } => {
                file.seek(SeekFrom::Start(0))?;
                let mut reader = BufReader::with_capacity(1 << 16, &*file);
                let mut error = None;
                let mut buf = [0u8; 24];
                let read = (0..*n).map_while(|_| match reader.read_exact(&mut buf) {
                    Ok(()) => Some(decode(&buf)),
                    Err(e) => {
                        error = Some(e);
                        None
                    }
                });
                let mean = mean_distance(read, &after[..(*n).min(after.len())]);
                match error {
                    Some(e) => Err(e),
                    None => Ok(mean),
                }
            }
        }
    }
}

/// The error of positions that could not be read back from their temporary file,
/// reported with the input file `path` they came from.
pub(crate) fn read_back_error(
    path: &std::path::Path,
    source: std::io::Error,
) -> crate::error::CliError {
    crate::error::CliError::Io {
        path: path.to_path_buf(),
        source: beltrami_io::IoError::Io {
            operation: "read back the input positions from a temporary file",
            source,
        },
    }
}

/// The position whose three coordinates are the little-endian bytes of `buf`.
fn decode(buf: &[u8; 24]) -> DVec3 {
    let c = |k: usize| {
        let mut b = [0u8; 8];
        b.copy_from_slice(&buf[8 * k..8 * k + 8]);
        f64::from_le_bytes(b)
    };
    DVec3::new(c(0), c(1), c(2))
}

/// `Σ |a_i − b_i| / max(n, 1)` in order, `n` the length of `after`.
fn mean_distance(before: impl Iterator<Item = DVec3>, after: &[DVec3]) -> f64 {
    let n = after.len().max(1);
    before.zip(after).map(|(a, b)| a.distance(*b)).sum::<f64>() / n as f64
}

/// `positions` written to a new unnamed temporary file in the system's temporary
/// directory (`tempfile::tempfile`, which never gives the file a name that a killed
/// process could leave behind where the system supports it).
fn spill(positions: &[DVec3]) -> std::io::Result<File> {
    let file = tempfile::tempfile()?;
    let mut writer = BufWriter::with_capacity(1 << 16, &file);
    for p in positions {
        for c in [p.x, p.y, p.z] {
            writer.write_all(&c.to_le_bytes())?;
        }
    }
    writer.flush()?;
    drop(writer);
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Positions kept in a file give the bits of positions kept in memory.
    #[test]
    fn the_file_gives_the_bits_of_memory() {
        let before: Vec<DVec3> = (0..5000)
            .map(|i| {
                let t = f64::from(i);
                DVec3::new(t.sin(), (0.3 * t).cos() * 1e-7, t * 1e3)
            })
            .collect();
        let after: Vec<DVec3> = before
            .iter()
            .map(|p| *p + DVec3::new(1e-3, -2e-9, 0.5))
            .collect();
        let mut memory = KeptPositions::keep(&before);
        assert!(
            matches!(memory, KeptPositions::Memory(_)),
            "a small mesh stays in memory"
        );
        let mut file = KeptPositions::in_file_or_memory(&before);
        assert!(matches!(file, KeptPositions::File { .. }));
        let a = memory.mean_displacement(&after).unwrap();
        let b = file.mean_displacement(&after).unwrap();
        assert_eq!(a.to_bits(), b.to_bits());
        let bits = |p: &[DVec3]| -> Vec<[u64; 3]> {
            p.iter().map(|p| p.to_array().map(f64::to_bits)).collect()
        };
        assert_eq!(bits(&file.read_all().unwrap()), bits(&before));
        assert_eq!(bits(&memory.read_all().unwrap()), bits(&before));
        assert!(file.in_file() && !memory.in_file());
        let mut empty = KeptPositions::keep(&[]);
        assert_eq!(empty.mean_displacement(&[]).unwrap(), 0.0);
    }
}
