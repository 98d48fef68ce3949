//! The memory a `beltrami smooth` run needs, estimated from element counts, and the
//! `--max-memory` size syntax.
//!
//! The estimate is linear in the counts:
//!
//! ```text
//! bytes = BASE_BYTES + BYTES_PER_VERTEX · V + BYTES_PER_CORNER · C
//! ```
//!
//! with `V` vertices and `C` face corners (the sum of the face sizes: `3 F` for a
//! triangle mesh). The constants are the live data of a run counted structure by
//! structure and checked against the peak resident memory of measured runs
//! (`docs/reliability.md`), which they bound from above.

use std::fmt;

/// Resident memory of the process before any mesh data (code, runtime, thread
/// stacks, buffers), in bytes.
pub(crate) const BASE_BYTES: u64 = 16 << 20;

/// Bytes per vertex: input positions (24), the smoother's two position buffers (48),
/// the result (24), the outgoing halfedge (4), Laplacian row offset, weight sum and
/// scale (20), role (1), rounded up.
pub(crate) const BYTES_PER_VERTEX: u64 = 128;

/// Bytes per face corner (each corner is one inner halfedge): the face list as read,
/// kept for the output (4 per corner, 8 per face); four `u32` links per halfedge,
/// both halves of an edge (32); the Laplacian's neighbour and halfedge ids (8), its
/// weight (8) and the per-halfedge scratch (16, both halves); the per-face cotangent
/// buffer (8); rounded up. Measured peaks (`docs/reliability.md`) grow by about
/// 490 bytes per vertex of a closed triangle mesh (6 corners per vertex), which
/// `128 + 6 · 80 = 608` bounds with a fifth to spare.
pub(crate) const BYTES_PER_CORNER: u64 = 80;

/// Vertex count above which `beltrami smooth` prints its estimate without
/// `--verbose`.
pub(crate) const LARGE_RUN_VERTICES: usize = 1_000_000;

/// The estimated peak memory of a smoothing run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct MemoryEstimate {
    /// Vertices (for an STL before welding: an estimate, see [`Self::for_triangle_soup`]).
    pub(crate) vertices: usize,
    /// Faces.
    pub(crate) faces: usize,
    /// Face corners (the sum of the face sizes).
    pub(crate) corners: usize,
    /// The estimate, in bytes.
    pub(crate) bytes: u64,
}

impl MemoryEstimate {
    /// The estimate for `vertices` vertices and `faces` faces with `corners` corners
    /// in all.
    pub(crate) fn new(vertices: usize, faces: usize, corners: usize) -> Self {
        let bytes = BASE_BYTES
            .saturating_add(BYTES_PER_VERTEX.saturating_mul(vertices as u64))
            .saturating_add(BYTES_PER_CORNER.saturating_mul(corners as u64));
        Self {
            vertices,
            faces,
            corners,
            bytes,
        }
    }

    /// The estimate for a file that declares `faces` triangles but not its vertices
    /// (an STL): a closed triangle mesh has about half as many vertices as faces.
    pub(crate) fn for_triangle_soup(faces: usize) -> Self {
        Self::new(faces / 2 + 2, faces, faces.saturating_mul(3))
    }
}

impl fmt::Display for MemoryEstimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "about {} ({} vertices, {} faces)",
            Size(self.bytes),
            self.vertices,
            self.faces
        )
    }
}

/// A byte count printed with a binary unit: `512.0 MiB`, `1.50 GiB`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Size(pub(crate) u64);

impl fmt::Display for Size {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const UNITS: [&str; 5] = ["B", "KiB", "MiB", "GiB", "TiB"];
        #[allow(clippy::cast_precision_loss, reason = "printed with 3 digits")]
        let mut value = self.0 as f64;
        let mut unit = 0;
        while value >= 1024.0 && unit + 1 < UNITS.len() {
            value /= 1024.0;
            unit += 1;
        }
        if unit == 0 {
            write!(f, "{} B", self.0)
        } else if value < 10.0 {
            write!(f, "{value:.2} {}", UNITS[unit])
        } else {
            write!(f, "{value:.1} {}", UNITS[unit])
        }
    }
}

/// Parses a size for `--max-memory`: a number of bytes, optionally with a decimal
/// fraction and a binary unit `K`, `M`, `G` or `T` (powers of 1024; `KB`, `KiB` and
/// lower case are accepted too): `512M`, `2G`, `1.5GiB`, `1000000`.
pub(crate) fn parse_size(text: &str) -> Result<u64, String> {
    let text = text.trim();
    let split = text
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(text.len());
    let (number, unit) = text.split_at(split);
    let shift = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 0,
        "k" | "kb" | "kib" => 10,
        "m" | "mb" | "mib" => 20,
        "g" | "gb" | "gib" => 30,
        "t" | "tb" | "tib" => 40,
        _ => return Err(format!("unknown unit {unit:?} (use K, M, G or T)")),
    };
    let value: f64 = number
        .parse()
        .map_err(|_| format!("{text:?} is not a size (e.g. 512M, 2G)"))?;
    #[allow(clippy::cast_precision_loss, reason = "powers of two are exact")]
    let bytes = value * (1u64 << shift) as f64;
    if !bytes.is_finite() || bytes < 1.0 || bytes >= 2f64.powi(64) {
        return Err(format!("{text:?} is not a size between 1 byte and 16 EiB"));
    }
    #[allow(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "range checked above"
    )]
    Ok(bytes as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_units() {
        assert_eq!(parse_size("512M"), Ok(512 << 20));
        assert_eq!(parse_size("2G"), Ok(2 << 30));
        assert_eq!(parse_size("2g"), Ok(2 << 30));
        assert_eq!(parse_size("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_size("64KB"), Ok(64 << 10));
        assert_eq!(parse_size("1000"), Ok(1000));
        assert_eq!(parse_size("1T"), Ok(1 << 40));
        for bad in ["", "M", "12X", "-1G", "0", "1..2M", "nanG"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn sizes_print_with_binary_units() {
        assert_eq!(Size(512).to_string(), "512 B");
        assert_eq!(Size(512 << 20).to_string(), "512.0 MiB");
        assert_eq!(Size(3 << 29).to_string(), "1.50 GiB");
    }

    #[test]
    fn the_estimate_is_linear_in_the_counts() {
        let e = MemoryEstimate::new(1000, 2000, 6000);
        assert_eq!(
            e.bytes,
            BASE_BYTES + 1000 * BYTES_PER_VERTEX + 6000 * BYTES_PER_CORNER
        );
        let soup = MemoryEstimate::for_triangle_soup(2000);
        assert_eq!((soup.vertices, soup.corners), (1002, 6000));
        assert_eq!(
            MemoryEstimate::new(usize::MAX, 0, usize::MAX).bytes,
            u64::MAX
        );
    }
}
