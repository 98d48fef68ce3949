//! Splitting a polygon into triangles by ear clipping in its own plane.
//!
//! A polygon of `k` corners becomes `k − 2` triangles between its corners (no new
//! vertex), wound as the polygon is. The polygon is projected onto the plane of its
//! Newell normal, and ears are clipped one at a time: a corner whose angle is convex
//! (turning the polygon's way) and whose triangle holds no other remaining corner. Of
//! the ears, the one with the shortest new edge goes first (the lowest corner on a
//! tie), so a quadrilateral is split along its shorter diagonal when both diagonals lie
//! inside it, and along the one inside it when it is not convex. A polygon without an
//! ear (all corners on one line, a polygon crossing itself, coincident corners) is
//! split as a fan around its first corner. The result depends only on the polygon.
//!
//! # References
//! - D. Eberly, *Triangulation by ear clipping*, Geometric Tools (2002, updated 2015).
//! - M. E. Newell's polygon normal, as in F. S. Hill, *The pleasures of "perp dot"
//!   products*, Graphics Gems IV (1994).

use glam::{DVec2, DVec3};

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
    let cross = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
    let mut left: Vec<usize> = (0..k).collect();
    let start = out.len();
    while left.len() > 3 {
        let m = left.len();
        let mut best: Option<(f64, usize)> = None;
        for j in 0..m {
            let (a, b, c) = (left[(j + m - 1) % m], left[j], left[(j + 1) % m]);
            if cross(q[a], q[b], q[c]) <= 0.0 {
                continue;
            }
            let inside = left.iter().any(|&r| {
                r != a
                    && r != b
                    && r != c
                    && cross(q[a], q[b], q[r]) >= 0.0
                    && cross(q[b], q[c], q[r]) >= 0.0
                    && cross(q[c], q[a], q[r]) >= 0.0
            });
            if inside {
                continue;
            }
            let diagonal = p[a].distance_squared(p[c]);
            if best.is_none_or(|(d, _)| diagonal < d) {
                best = Some((diagonal, j));
            }
        }
        let Some((_, j)) = best else {
            // No ear: not a simple polygon in its plane.
            out.truncate(start);
            fan(out);
            return;
        };
        let (a, b, c) = (left[(j + m - 1) % m], left[j], left[(j + 1) % m]);
        out.push([face[a], face[b], face[c]]);
        left.remove(j);
    }
    out.push([face[left[0]], face[left[1]], face[left[2]]]);
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
        assert_eq!(split(&line, &[2, 0, 1]), [[2, 0, 1]]);
    }
}
