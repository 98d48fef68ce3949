//! Splitting a polygon into triangles by ear clipping in its own plane.
//!
//! A polygon of `k` corners becomes `k − 2` triangles between its corners (no new
//! vertex), wound as the polygon is. The polygon is projected onto the plane of its
//! Newell normal, and ears are clipped one at a time: a corner whose angle is convex
//! (turning the polygon's way) and whose triangle holds no reflex corner. Of the ears,
//! the one with the shortest new edge goes first (on a tie, the one whose new edge joins
//! the lower vertex ids), so a quadrilateral is split along its shorter diagonal when
//! both diagonals lie inside it, and along the one inside it when it is not convex. A
//! polygon without an ear (all corners on one line, a polygon crossing itself,
//! coincident corners) is split as a fan around its lowest vertex. The computation
//! starts at the polygon's lowest vertex id, so the result depends only on the cycle of
//! vertices, not on where a face list starts it. O(k²) time: after a clip only the two
//! neighbours' ear status changes.
//!
//! # References
//! - D. Eberly, *Triangulation by ear clipping*, Geometric Tools (2002, updated 2015).
//! - M. E. Newell's polygon normal, as in F. S. Hill, *The pleasures of "perp dot"
//!   products*, Graphics Gems IV (1994).

use glam::{DVec2, DVec3};

/// How an ear is chosen: the squared length of its new edge, then the edge's vertex ids
/// (lower first).
type EarKey = (f64, (u32, u32));

/// The triangles of the polygon `face` (vertex indices into `positions`, in order),
/// appended to `out`: `face.len() − 2` of them (none for fewer than three corners).
///
/// # Panics
/// If an index of `face` is out of `positions`.
pub fn triangulate_polygon(positions: &[DVec3], face: &[u32], out: &mut Vec<[u32; 3]>) {
    let k = face.len();
    if k < 3 {
        return;
    }
    // The cycle from its lowest vertex id: nothing below depends on where it started.
    let first = (0..k).min_by_key(|&i| face[i]).unwrap_or(0);
    let face: Vec<u32> = (0..k).map(|i| face[(first + i) % k]).collect();
    if k == 3 {
        out.push([face[0], face[1], face[2]]);
        return;
    }
    let p: Vec<DVec3> = face.iter().map(|&v| positions[v as usize]).collect();
    // Newell's normal: exact for a planar polygon, the best-fitting direction else.
    let mut normal = DVec3::ZERO;
    for i in 0..k {
        let (a, b) = (p[i], p[(i + 1) % k]);
        normal += DVec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    let fan = |out: &mut Vec<[u32; 3]>| {
        for i in 1..k - 1 {
            out.push([face[0], face[i], face[i + 1]]);
        }
    };
    let n = normal.normalize_or_zero();
    if n == DVec3::ZERO || !n.is_finite() {
        fan(out);
        return;
    }
    // Coordinates in the plane, counter-clockwise seen from the normal's side.
    let u = n.any_orthonormal_vector();
    let w = n.cross(u);
    let q: Vec<DVec2> = p.iter().map(|&x| DVec2::new(x.dot(u), x.dot(w))).collect();
    let cross = |a: usize, b: usize, c: usize| (q[b] - q[a]).perp_dot(q[c] - q[a]);
    // The remaining polygon as a ring of corners.
    let mut prev: Vec<usize> = (0..k).map(|i| (i + k - 1) % k).collect();
    let mut next: Vec<usize> = (0..k).map(|i| (i + 1) % k).collect();
    let mut reflex: Vec<bool> = (0..k).map(|i| cross(prev[i], i, next[i]) <= 0.0).collect();
    // Corner `i` is an ear: convex, and no reflex corner in (or on) its triangle.
    let is_ear = |i: usize, prev: &[usize], next: &[usize], reflex: &[bool], alive: &[bool]| {
        let (a, c) = (prev[i], next[i]);
        if reflex[i] {
            return false;
        }
        !(0..k).any(|r| {
            alive[r]
                && reflex[r]
                && r != a
                && r != c
                && cross(a, i, r) >= 0.0
                && cross(i, c, r) >= 0.0
                && cross(c, a, r) >= 0.0
        })
    };
    let mut alive = vec![true; k];
    let mut ear: Vec<bool> = (0..k)
        .map(|i| is_ear(i, &prev, &next, &reflex, &alive))
        .collect();
    // The new edge of an ear at `i`, for the choice: its squared length, then its ids.
    let key = |i: usize, prev: &[usize], next: &[usize]| -> EarKey {
        let (a, c) = (prev[i], next[i]);
        let ids = (face[a].min(face[c]), face[a].max(face[c]));
        (p[a].distance_squared(p[c]), ids)
    };
    let start = out.len();
    let mut left = k;
    let mut at = 0;
    while left > 3 {
        // The best ear of the ring.
        let mut best: Option<(EarKey, usize)> = None;
        let mut i = at;
        for _ in 0..left {
            if ear[i] {
                let candidate = key(i, &prev, &next);
                if best.is_none_or(|(b, _)| {
                    candidate.0 < b.0 || (candidate.0 == b.0 && candidate.1 < b.1)
                }) {
                    best = Some((candidate, i));
                }
            }
            i = next[i];
        }
        let Some((_, i)) = best else {
            // No ear: not a simple polygon in its plane.
            out.truncate(start);
            fan(out);
            return;
        };
        let (a, c) = (prev[i], next[i]);
        out.push([face[a], face[i], face[c]]);
        alive[i] = false;
        next[a] = c;
        prev[c] = a;
        left -= 1;
        at = a;
        for j in [a, c] {
            reflex[j] = cross(prev[j], j, next[j]) <= 0.0;
        }
        for j in [a, c] {
            ear[j] = is_ear(j, &prev, &next, &reflex, &alive);
        }
    }
    out.push([face[prev[at]], face[at], face[next[at]]]);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(positions: &[DVec3], face: &[u32]) -> Vec<[u32; 3]> {
        let mut out = Vec::new();
        triangulate_polygon(positions, face, &mut out);
        out
    }

    /// Twice the area of a triangle, signed along `n`.
    fn area(positions: &[DVec3], t: [u32; 3], n: DVec3) -> f64 {
        let [a, b, c] = t.map(|v| positions[v as usize]);
        (b - a).cross(c - a).dot(n)
    }

    #[test]
    fn a_quad_is_split_along_its_shorter_diagonal() {
        // A rhombus: the diagonal 1–3 is the shorter.
        let rhombus = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, -0.5, 0.0),
            DVec3::new(4.0, 0.0, 0.0),
            DVec3::new(2.0, 0.5, 0.0),
        ];
        let t = split(&rhombus, &[0, 1, 2, 3]);
        assert_eq!(t.len(), 2);
        assert!(t.iter().all(|t| t.contains(&1) && t.contains(&3)), "{t:?}");
        // The same from any starting corner and numbering.
        let t = split(&rhombus, &[1, 2, 3, 0]);
        assert!(t.iter().all(|t| t.contains(&1) && t.contains(&3)), "{t:?}");
        for t in &t {
            assert!(area(&rhombus, *t, DVec3::Z) > 0.0, "{t:?}");
        }
    }

    #[test]
    fn a_dart_is_split_along_the_diagonal_inside_it() {
        // Concave at corner 2: the diagonal 0–2 is inside, 1–3 outside (and shorter).
        let dart = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(2.0, -2.0, 0.0),
            DVec3::new(0.5, 0.0, 0.0),
            DVec3::new(2.0, 2.0, 0.0),
        ];
        let t = split(&dart, &[0, 1, 2, 3]);
        assert!(t.iter().all(|t| t.contains(&0) && t.contains(&2)), "{t:?}");
        for t in &t {
            assert!(area(&dart, *t, DVec3::Z) > 0.0, "{t:?}");
        }
    }

    #[test]
    fn a_polygon_keeps_its_winding_and_area_in_any_plane() {
        // An L-shaped hexagon, tilted out of every coordinate plane, both windings.
        let flat = [
            (0.0, 0.0),
            (3.0, 0.0),
            (3.0, 1.0),
            (1.0, 1.0),
            (1.0, 3.0),
            (0.0, 3.0),
        ];
        let (u, w) = (
            DVec3::new(1.0, 2.0, 2.0) / 3.0,
            DVec3::new(2.0, 1.0, -2.0) / 3.0,
        );
        let n = u.cross(w);
        let positions: Vec<DVec3> = flat
            .iter()
            .map(|&(x, y)| DVec3::new(5.0, -1.0, 2.0) + x * u + y * w)
            .collect();
        for (face, sign) in [
            (vec![0, 1, 2, 3, 4, 5], 1.0),
            (vec![5, 4, 3, 2, 1, 0], -1.0),
        ] {
            let t = split(&positions, &face);
            assert_eq!(t.len(), 4);
            let total: f64 = t.iter().map(|&t| area(&positions, t, n) * sign).sum();
            assert!((total - 2.0 * 5.0).abs() < 1e-12, "{total}");
            assert!(
                t.iter().all(|&t| area(&positions, t, n) * sign > 0.0),
                "{t:?}"
            );
        }
    }

    #[test]
    fn a_polygon_without_an_ear_becomes_a_fan() {
        let line: Vec<DVec3> = (0..5).map(|i| DVec3::new(f64::from(i), 0.0, 0.0)).collect();
        assert_eq!(
            split(&line, &[0, 1, 2, 3, 4]),
            [[0, 1, 2], [0, 2, 3], [0, 3, 4]]
        );
        assert_eq!(split(&line, &[0, 1]), Vec::<[u32; 3]>::new());
        assert_eq!(split(&line, &[2, 0, 1]), [[0, 1, 2]]);
    }

    /// The triangles depend on the cycle of vertices only, not on where it starts: a
    /// square (whose diagonals tie), a convex and a concave polygon, in every rotation.
    #[test]
    fn the_split_does_not_depend_on_the_first_corner() {
        let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
        let star = [
            (0.0, 0.0),
            (2.0, -1.0),
            (1.5, 0.5),
            (3.0, 1.0),
            (1.0, 1.2),
            (0.5, 3.0),
            (0.3, 1.0),
        ];
        let heptagon: Vec<(f64, f64)> = (0..7)
            .map(|i| {
                let t = std::f64::consts::TAU * f64::from(i) / 7.0;
                (t.cos(), 0.7 * t.sin())
            })
            .collect();
        for points in [&square[..], &star[..], &heptagon[..]] {
            let positions: Vec<DVec3> =
                points.iter().map(|&(x, y)| DVec3::new(x, y, 0.0)).collect();
            let k = positions.len() as u32;
            // Vertex ids not in order around the polygon.
            let ids: Vec<u32> = (0..k).map(|i| (3 * i + 1) % k).collect();
            let mut positions_by_id = vec![DVec3::ZERO; k as usize];
            for (corner, &id) in ids.iter().enumerate() {
                positions_by_id[id as usize] = positions[corner];
            }
            let canonical = |mut t: Vec<[u32; 3]>| {
                for t in &mut t {
                    let m = (0..3).min_by_key(|&i| t[i]).unwrap();
                    *t = [t[m], t[(m + 1) % 3], t[(m + 2) % 3]];
                }
                t.sort_unstable();
                t
            };
            let first = canonical(split(&positions_by_id, &ids));
            assert_eq!(first.len(), points.len() - 2);
            for r in 1..ids.len() {
                let rotated: Vec<u32> = (0..ids.len()).map(|i| ids[(i + r) % ids.len()]).collect();
                assert_eq!(
                    canonical(split(&positions_by_id, &rotated)),
                    first,
                    "rotation {r}"
                );
            }
            for t in &first {
                assert!(area(&positions_by_id, *t, DVec3::Z) > 0.0, "{t:?}");
            }
        }
    }

    /// A polygon of thousands of corners (a CAD cylinder's cap) is split, every
    /// triangle wound as the polygon, the area kept.
    #[test]
    fn a_large_polygon_is_split() {
        let k = 3000u32;
        let positions: Vec<DVec3> = (0..k)
            .map(|i| {
                let t = std::f64::consts::TAU * f64::from(i) / f64::from(k);
                DVec3::new(t.cos(), t.sin(), 0.0)
            })
            .collect();
        let face: Vec<u32> = (0..k).collect();
        let t = split(&positions, &face);
        assert_eq!(t.len(), k as usize - 2);
        let total: f64 = t.iter().map(|&t| area(&positions, t, DVec3::Z)).sum();
        let polygon = f64::from(k) * (std::f64::consts::TAU / f64::from(k)).sin();
        assert!((total - polygon).abs() < 1e-9, "{total} against {polygon}");
        assert!(t.iter().all(|&t| area(&positions, t, DVec3::Z) > 0.0));
    }
}
