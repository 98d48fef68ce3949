//! Meshes far from unit size, run at a power of two times their size.
//!
//! Remeshing, decimation, hole filling, Delaunay flips and the quality figures compute
//! squared lengths, areas, cotangents, quadrics (up to fourth powers of the coordinates)
//! and closest points. Far from unit size these
//! leave the range of normal numbers: before this scaling, decimation changed its result
//! from coordinates of about 2⁻¹⁰⁰ and 2¹⁵⁰ on and collapsed nothing from 2⁻³⁰⁰,
//! remeshing called a sphere of size 2⁻³⁰⁰ flat and refused one of size 2²⁰⁰ (the
//! closest-point index takes coordinates up to 10⁶⁰), and hole filling filled no hole
//! of a sphere of size 2³⁰⁰, and the Delaunay flips found no negative weight at 2^±300.
//! Multiplying every coordinate by a power of two is exact, and
//! so is every sum, difference, product, quotient and square root of the scaled numbers
//! while they stay normal: a mesh whose largest coordinate lies outside
//! [`2⁻⁴⁰, 2⁴⁰`](UNSCALED) is run at `2^k` times its size, with `k` bringing that
//! coordinate into `[1, 2)`, and its results are scaled back, so that the result is the
//! unit-size run's times `2^-k`, bit for bit (but for a coordinate so much smaller than
//! the largest that it is subnormal in the run, which comes back rounded; the algorithms
//! that keep input positions copy those back). Inside that range the positions are used as
//! they are.
//!
//! The scaled run reads lengths given in the positions' unit (a target edge length, a
//! bound on the error) scaled alike, and its reports' lengths and areas are scaled back.
//! Only the largest coordinate of the vertices in a face counts: a small part far from
//! the origin keeps the precision its coordinates have, and an isolated vertex (a stray
//! point of a scan, which the algorithms leave where it is) neither sets the size nor is
//! scaled: it comes back with its own bits. Nor is one so far beyond a surface at its own
//! size (past 2^100) that the closest-point index would refuse it.

use beltrami_halfedge::{DVec3, HalfedgeMesh, VertexId};

/// The range of the largest absolute coordinate inside which a mesh is used at its own
/// size: well inside the range where the algorithms' results scale exactly with the
/// mesh (measured from 2⁻⁶⁰ to 2¹⁰⁰).
pub(crate) const UNSCALED: std::ops::RangeInclusive<f64> =
    9.094_947_017_729_282e-13..=1_099_511_627_776.0;

/// An algorithm's result: the new mesh, its positions and a report.
pub(crate) type Edited<R> = (HalfedgeMesh, Vec<DVec3>, R);

/// Runs `run` (an editing algorithm on `mesh`) at a power of two times the size of
/// `positions` when they are far from unit size ([`Scale::of_mesh`]), or at their own:
/// `run` gets the positions to use and the scale (`None`: the caller's own size), for
/// the lengths among its options; the result comes back at the caller's size (its
/// isolated vertices with their own bits), its report through `back`.
///
/// # Errors
/// `run`'s.
pub(crate) fn at_unit_size<R, E>(
    mesh: &HalfedgeMesh,
    positions: &[DVec3],
    run: impl FnOnce(&[DVec3], Option<&Scale>) -> Result<Edited<R>, E>,
    back: impl FnOnce(R, &Scale) -> R,
) -> Result<Edited<R>, E> {
    let Some(scale) = Scale::for_run(mesh, positions) else {
        return run(positions, None);
    };
    // (At the mesh's own size, `ONE`, only the isolated vertices are held aside: every
    // length multiplied by 1 is itself.)
    let x = scale.mesh_positions(mesh, positions);
    let (out, x, report) = run(&x, Some(&scale))?;
    let x = scale.restore_mesh((mesh, positions), x);
    Ok((out, x, back(report, &scale)))
}

/// The largest coordinate an isolated vertex may have for a run at the mesh's own size
/// to use it as it is (2^100); beyond it the vertex is held at its tag
/// ([`Scale::mesh_positions`]).
const STRAY: f64 = 1.267_650_600_228_229_4e30;

/// The scale of a run at the mesh's own size.
const ONE: Scale = Scale {
    to_run: 1.0,
    back: 1.0,
};

/// The largest absolute coordinate of `mesh`'s isolated vertices (0 without any).
fn largest_isolated(mesh: &HalfedgeMesh, positions: &[DVec3]) -> f64 {
    largest(
        positions
            .iter()
            .enumerate()
            .filter(|&(i, _)| mesh.is_isolated(VertexId::new(i as u32))),
    )
}

/// The power of two a run multiplies its positions by, and its inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Scale {
    /// `2^k`: positions and lengths into the run.
    to_run: f64,
    /// `2^-k`: positions and lengths out of it.
    back: f64,
}

/// Where a run holds an isolated vertex ([`Scale::mesh_positions`]): far from the run's
/// surface (within a few units of the origin) and within the closest-point index's
/// range of coordinates (10⁶⁰).
const TAG: f64 = 1e50;

/// The largest absolute coordinate of the points (0 for none).
fn largest<'a>(points: impl Iterator<Item = (usize, &'a DVec3)>) -> f64 {
    points
        .map(|(_, p)| p.abs().max_element())
        .fold(0.0_f64, f64::max)
}

/// The binary exponent of `x` (positive, finite): of its leading bit for a subnormal; 0
/// for 0.
fn exponent(x: f64) -> i32 {
    if x == 0.0 {
        return 0;
    }
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if biased == 0 {
        // Subnormal: 2^-1074 times the mantissa.
        -1074 + (63 - (bits & ((1 << 52) - 1)).leading_zeros() as i32)
    } else {
        biased - 1023
    }
}

/// `2^k` for `k` in `-1022..=1023`: a normal number, exactly.
fn power_of_two(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

impl Scale {
    /// The scale a run on `mesh` at `positions` takes: [`of_mesh`](Self::of_mesh)'s, or
    /// the mesh's own size with its isolated vertices held at their tags
    /// ([`mesh_positions`](Self::mesh_positions)) when one lies beyond 2^100 (past the
    /// closest-point index's range, say); `None`: the positions as they are.
    pub(crate) fn for_run(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Option<Self> {
        Self::of_mesh(mesh, positions)
            .or_else(|| (largest_isolated(mesh, positions) > STRAY).then_some(ONE))
    }

    /// The scale for `mesh` at `positions` (finite, one per vertex): from the largest
    /// absolute coordinate of the vertices in a face (an isolated vertex far away, a
    /// stray point of a scan, is no part of the surface and does not shrink it). `None`
    /// when that coordinate lies in [`UNSCALED`] or is zero (nothing to scale).
    pub(crate) fn of_mesh(mesh: &HalfedgeMesh, positions: &[DVec3]) -> Option<Self> {
        let in_face = |i: usize| !mesh.is_isolated(VertexId::new(i as u32));
        let surface = largest(positions.iter().enumerate().filter(|&(i, _)| in_face(i)));
        Self::power(surface).map(Self::with_power)
    }

    /// `mesh`'s positions at the run's size: the vertices in a face scaled, the
    /// isolated ones (no part of the surface, and left where they are by every algorithm
    /// here) not, so that one at another magnitude than the surface neither overflows
    /// nor loses its bits: the `j`-th of them is at `(TAG, j, 0)` in the run, a point no
    /// surface vertex of the run (all within a few units of the origin) is at, and
    /// [`restore_mesh`](Self::restore_mesh) puts it back where it was.
    pub(crate) fn mesh_positions(&self, mesh: &HalfedgeMesh, positions: &[DVec3]) -> Vec<DVec3> {
        let mut j = 0.0;
        positions
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                if mesh.is_isolated(VertexId::new(i as u32)) {
                    j += 1.0;
                    DVec3::new(TAG, j - 1.0, 0.0)
                } else {
                    p * self.to_run
                }
            })
            .collect()
    }

    /// The run's positions at the caller's size: each vertex scaled back, but an
    /// isolated vertex of `input` (`mesh` and its positions), found by the position
    /// [`mesh_positions`](Self::mesh_positions) gave it, at its own position.
    pub(crate) fn restore_mesh(
        &self,
        (mesh, positions): (&HalfedgeMesh, &[DVec3]),
        run: Vec<DVec3>,
    ) -> Vec<DVec3> {
        let isolated: Vec<DVec3> = (0..positions.len())
            .filter(|&i| mesh.is_isolated(VertexId::new(i as u32)))
            .map(|i| positions[i])
            .collect();
        run.into_iter()
            .map(|p| {
                let j = p.y as usize;
                if p.x == TAG && p.z == 0.0 && j as f64 == p.y && j < isolated.len() {
                    isolated[j]
                } else {
                    p * self.back
                }
            })
            .collect()
    }

    /// The scale for the points `positions` (finite): from their largest absolute
    /// coordinate, `None` when it lies in [`UNSCALED`] or is zero.
    pub(crate) fn of<'a>(positions: impl IntoIterator<Item = &'a DVec3>) -> Option<Self> {
        Self::power(largest(positions.into_iter().enumerate())).map(Self::with_power)
    }

    /// The `k` that brings `largest` into `[1, 2)`, limited so that `2^k` and `2^-k`
    /// are both normal; `None` when `largest` lies in [`UNSCALED`], is zero or is not
    /// finite.
    fn power(largest: f64) -> Option<i32> {
        if largest == 0.0 || !largest.is_finite() || UNSCALED.contains(&largest) {
            return None;
        }
        Some((-exponent(largest)).clamp(-1022, 1022))
    }

    fn with_power(k: i32) -> Self {
        Self {
            to_run: power_of_two(k),
            back: power_of_two(-k),
        }
    }

    /// The positions at the run's size.
    pub(crate) fn positions(&self, positions: &[DVec3]) -> Vec<DVec3> {
        positions.iter().map(|&p| p * self.to_run).collect()
    }

    /// The run's positions at the caller's size, in place (the tests' inverse of
    /// [`positions`](Self::positions)).
    #[cfg(test)]
    pub(crate) fn restore(&self, mut positions: Vec<DVec3>) -> Vec<DVec3> {
        for p in &mut positions {
            *p *= self.back;
        }
        positions
    }

    /// A length given in the caller's unit, in the run's: positive and finite stays so
    /// (one that underflows to 0 becomes the smallest positive number, one that
    /// overflows the largest finite one), anything else is scaled as it is.
    pub(crate) fn length(&self, x: f64) -> f64 {
        let y = x * self.to_run;
        if !(x.is_finite() && x > 0.0) {
            y
        } else if y == 0.0 {
            f64::from_bits(1)
        } else {
            y.min(f64::MAX)
        }
    }

    /// A length the run reports, in the caller's unit.
    pub(crate) fn length_back(&self, x: f64) -> f64 {
        x * self.back
    }

    /// An area the run reports, in the caller's unit.
    pub(crate) fn area_back(&self, x: f64) -> f64 {
        x * self.back * self.back
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_range_is_two_to_the_minus_and_plus_forty() {
        assert_eq!(*UNSCALED.start(), 2f64.powi(-40));
        assert_eq!(*UNSCALED.end(), 2f64.powi(40));
    }

    #[test]
    fn positions_in_the_range_are_used_as_they_are() {
        for x in [2f64.powi(-40), 1e-6, 1.0, 3.5e9, 2f64.powi(40)] {
            assert_eq!(Scale::of(&[DVec3::new(0.0, -x, 0.5 * x)]), None, "{x}");
        }
        assert_eq!(Scale::of(&[DVec3::ZERO]), None);
        assert_eq!(Scale::of(&[]), None);
    }

    /// The largest coordinate goes into [1, 2) and back, exactly, from subnormal
    /// coordinates to the largest finite ones (where the limit on `k` leaves it a little
    /// outside).
    #[test]
    fn the_largest_coordinate_goes_to_one_and_back() {
        for x in [
            2f64.powi(-41),
            1e-20,
            1e-300,
            f64::MIN_POSITIVE,
            1e-310,
            5e-324,
            2f64.powi(41) * 1.5,
            1e100,
            1e300,
            f64::MAX,
        ] {
            let p = [DVec3::new(-x, 0.25 * x, 0.0), DVec3::new(0.5 * x, x, -x)];
            let scale = Scale::of(&p).unwrap_or_else(|| panic!("{x} is scaled"));
            let run = scale.positions(&p);
            let largest = run[1].y;
            if (1e-300..=1e300).contains(&x) {
                assert!((1.0..2.0).contains(&largest), "{x} -> {largest}");
            } else {
                assert!(
                    largest.is_normal() && (2f64.powi(-60)..4.0).contains(&largest),
                    "{x} -> {largest}"
                );
            }
            assert_eq!(scale.restore(run), p, "{x}");
        }
    }

    /// Isolated vertices are not scaled: held at their tags in the run, they come back
    /// with their own bits wherever the run put them in its numbering (one at the tag
    /// position itself among them), while the surface's are scaled back.
    #[test]
    fn isolated_vertices_come_back_as_they_were() {
        let mesh = HalfedgeMesh::from_polygons(5, [[0u32, 1, 2]]).unwrap();
        let s = 2f64.powi(-500);
        let x = [
            DVec3::new(s, 0.0, 0.0),
            DVec3::new(0.0, 1.5 * s, 0.0),
            DVec3::new(0.0, 0.0, -s),
            DVec3::new(TAG, 0.0, 0.0),
            DVec3::new(1e10, -2.0, 5.0),
        ];
        let scale = Scale::of_mesh(&mesh, &x).unwrap();
        let run = scale.mesh_positions(&mesh, &x);
        assert_eq!(run[1], DVec3::new(0.0, 1.5, 0.0));
        assert_eq!(
            run[3..],
            [DVec3::new(TAG, 0.0, 0.0), DVec3::new(TAG, 1.0, 0.0)]
        );
        let moved = vec![run[4], run[0], run[3], run[1] * 2.0, run[2]];
        let back = scale.restore_mesh((&mesh, &x), moved);
        assert_eq!(back, [x[4], x[0], x[3], x[1] * 2.0, x[2]]);
        // Without isolated vertices in the face's range, their magnitude sets nothing.
        assert_eq!(
            Scale::of_mesh(&mesh, &[DVec3::ONE, DVec3::X, DVec3::Y, x[3], x[4]]),
            None
        );
    }

    #[test]
    fn lengths_and_areas_scale_by_the_power_and_its_square() {
        let scale = Scale::of(&[DVec3::new(3.0 * 2f64.powi(100), 0.0, 0.0)]).unwrap();
        assert_eq!(scale.length(2f64.powi(90)), 2f64.powi(-11));
        assert_eq!(scale.length_back(0.75), 0.75 * 2f64.powi(101));
        assert_eq!(scale.area_back(0.75), 0.75 * 2f64.powi(202));
        // A positive finite length stays positive and finite in the run.
        let tiny = Scale::of(&[DVec3::new(1e-300, 0.0, 0.0)]).unwrap();
        assert_eq!(tiny.length(f64::MAX), f64::MAX);
        let huge = Scale::of(&[DVec3::new(1e300, 0.0, 0.0)]).unwrap();
        // A subnormal length stays as it is; one that underflows becomes the smallest.
        let subnormal = huge.length(1e-10);
        assert!(subnormal > 0.0 && !subnormal.is_normal());
        assert_eq!(subnormal, 1e-10 * 2f64.powi(-996));
        assert_eq!(huge.length(1e-300), f64::from_bits(1));
        assert!(huge.length(-1.0) < 0.0 && huge.length(f64::NAN).is_nan());
    }
}
