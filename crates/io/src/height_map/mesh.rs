//! A height map as a triangle mesh, and back.

use beltrami_halfedge::{DVec3, MAX_ELEMENTS, MeshData, PolygonList};

use super::{HeightMap, LengthUnit};
use crate::error::IoError;

/// What [`HeightMap::to_mesh`] left out.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GridStats {
    /// Points whose height is invalid (NaN): no vertex, and every cell they are a
    /// corner of left out.
    pub invalid_points: usize,
    /// Valid points that are a corner of no cell with four valid corners (islands
    /// among invalid points): left out of the mesh, which has no isolated vertices.
    pub unused_points: usize,
}

impl HeightMap {
    /// The triangle mesh of the grid: one vertex per valid point that is a corner of a
    /// cell with four valid corners, at `(i·dx, j·dy, z)`, numbered row by row (x
    /// running fastest, as in [`z`](Self::z)); two triangles per such cell, split along
    /// the same diagonal everywhere, from `(i, j)` to `(i + 1, j + 1)`, and oriented
    /// counter-clockwise seen from +z (normals up). A cell with an invalid corner is a
    /// hole.
    ///
    /// The vertex (barycentric) area of this triangulation is `dx·dy` inside the grid
    /// and `dx·dy/2` along its edges, so the lumped rule on it is the trapezoid rule
    /// of the grid, except at the four corners (`dx·dy/3` at the two the diagonal
    /// meets, `dx·dy/6` at the other two, where the trapezoid rule has `dx·dy/4`).
    ///
    /// # Examples
    /// ```
    /// use beltrami_io::{HeightMap, LengthUnit};
    /// let map = HeightMap::new(2, 2, 0.5, 0.25, vec![0.0, 1.0, 2.0, 3.0], LengthUnit::Metre)?;
    /// let (mesh, _) = map.to_mesh();
    /// assert_eq!(mesh.positions[3].to_array(), [0.5, 0.25, 3.0]);
    /// assert_eq!(mesh.faces.iter().collect::<Vec<_>>(), [&[0, 1, 3][..], &[0, 3, 2]]);
    /// # Ok::<(), beltrami_io::IoError>(())
    /// ```
    ///
    /// # Panics
    /// When the map breaks the invariants of [`HeightMap::new`] (`z` of another
    /// length than `nx·ny`), or has more used points than a mesh can index (`u32`).
    #[must_use]
    pub fn to_mesh(&self) -> (MeshData, GridStats) {
        let (nx, ny) = (self.nx, self.ny);
        assert_eq!(self.z.len(), nx * ny, "a height map holds nx·ny heights");
        let valid = |i: usize, j: usize| !self.z[i + nx * j].is_nan();
        let cell = |i: usize, j: usize| {
            valid(i, j) && valid(i + 1, j) && valid(i, j + 1) && valid(i + 1, j + 1)
        };
        // A point is used when one of the (up to) four cells around it is whole.
        let mut used = vec![false; nx * ny];
        let mut cells = 0usize;
        for j in 0..ny.saturating_sub(1) {
            for i in 0..nx.saturating_sub(1) {
                if cell(i, j) {
                    cells += 1;
                    for k in [
                        i + nx * j,
                        i + 1 + nx * j,
                        i + nx * (j + 1),
                        i + 1 + nx * (j + 1),
                    ] {
                        used[k] = true;
                    }
                }
            }
        }
        let mut index = vec![u32::MAX; nx * ny];
        let mut positions = Vec::with_capacity(used.iter().filter(|&&u| u).count());
        let mut stats = GridStats::default();
        for j in 0..ny {
            for i in 0..nx {
                let k = i + nx * j;
                let z = self.z[k];
                if z.is_nan() {
                    stats.invalid_points += 1;
                } else if used[k] {
                    index[k] = u32::try_from(positions.len())
                        .expect("a height map to mesh has at most u32::MAX used points");
                    positions.push(DVec3::new(i as f64 * self.dx, j as f64 * self.dy, z));
                } else {
                    stats.unused_points += 1;
                }
            }
        }
        let mut faces = PolygonList::with_capacity(2 * cells, 6 * cells);
        for j in 0..ny.saturating_sub(1) {
            for i in 0..nx.saturating_sub(1) {
                if cell(i, j) {
                    let a = index[i + nx * j];
                    let b = index[i + 1 + nx * j];
                    let c = index[i + 1 + nx * (j + 1)];
                    let d = index[i + nx * (j + 1)];
                    faces.push(&[a, b, c]);
                    faces.push(&[a, c, d]);
                }
            }
        }
        (MeshData::new(positions, faces), stats)
    }

    /// The height map whose grid the vertices of `mesh` lie on: the vertex `(x, y, z)`
    /// is the point `(i, j)` with `x = i·dx`, `y = j·dy` (to within `1e-6` of the
    /// spacings), and grid points without a vertex are invalid. The spacings are those
    /// of the vertices' distinct x and y values; the grid starts at the origin when
    /// the lowest x (or y) is a whole number of spacings from it (so a map read by
    /// [`HeightMap::to_mesh`] keeps its invalid leading rows and columns), else at the
    /// lowest x (y). The faces must tile the grid's whole cells — each cell whose four
    /// corners are vertices covered once, by two triangles on either diagonal or by one
    /// quadrilateral, counter-clockwise seen from +z — and every vertex must be in one:
    /// a height map stores the heights only, and reading it back splits each cell from
    /// `(i, j)` to `(i + 1, j + 1)` ([`HeightMap::to_mesh`]). A mesh written from a
    /// height map and smoothed in z only (positions moved along z) is still one.
    ///
    /// # Examples
    /// ```
    /// use beltrami_io::{HeightMap, LengthUnit};
    /// let map = HeightMap::new(3, 2, 0.5, 0.25, vec![0.0, 1.0, 2.0, f64::NAN, 4.0, 5.0], LengthUnit::Metre)?;
    /// let (mesh, _) = map.to_mesh();
    /// let back = HeightMap::from_mesh(&mesh, LengthUnit::Metre)?;
    /// // The corner point (0, 1) is invalid, and so is (0, 0): it is in no whole cell.
    /// assert_eq!((back.nx, back.ny, back.invalid_points()), (3, 2, 2));
    /// assert!(HeightMap::from_mesh(&beltrami_halfedge::primitives::cube().into(), LengthUnit::Metre).is_err());
    /// # Ok::<(), beltrami_io::IoError>(())
    /// ```
    ///
    /// # Errors
    /// [`IoError::NotAGrid`] for a mesh without vertices, with non-finite
    /// coordinates, with fewer than two distinct x or y values, with a vertex off
    /// the grid, or with two vertices on one grid point (a surface that folds over
    /// the xy plane, a closed surface); for faces that do not tile the whole cells (a
    /// face across cells or in a cell without its four corners, one facing down, a cell
    /// with four vertices not covered once) and for a vertex in no whole cell;
    /// [`IoError::FaceIndexOutOfRange`] for a face naming a vertex that does not exist.
    pub fn from_mesh(mesh: &MeshData, unit: LengthUnit) -> Result<Self, IoError> {
        let not_a_grid = |reason: String| IoError::NotAGrid { reason };
        crate::validate::check_faces(mesh, None)?;
        let positions = &mesh.positions;
        if positions.is_empty() {
            return Err(not_a_grid("the mesh has no vertices".into()));
        }
        if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
            return Err(not_a_grid(format!(
                "vertex {v} has a non-finite coordinate"
            )));
        }
        let xs: Vec<f64> = positions.iter().map(|p| p.x).collect();
        let ys: Vec<f64> = positions.iter().map(|p| p.y).collect();
        let x_axis = Axis::fit(&xs, "x", positions.len()).map_err(not_a_grid)?;
        let y_axis = Axis::fit(&ys, "y", positions.len()).map_err(not_a_grid)?;
        let (nx, ny) = (x_axis.count, y_axis.count);
        let n = nx
            .checked_mul(ny)
            .filter(|&n| n <= MAX_ELEMENTS)
            .ok_or_else(|| not_a_grid(format!("{nx} × {ny} grid points are too many")))?;
        let mut z = vec![f64::NAN; n];
        let mut owner = vec![u32::MAX; n];
        for (v, p) in positions.iter().enumerate() {
            let i = x_axis
                .index(p.x)
                .ok_or_else(|| off_grid(v, "x", p.x, &x_axis))?;
            let j = y_axis
                .index(p.y)
                .ok_or_else(|| off_grid(v, "y", p.y, &y_axis))?;
            let k = i + nx * j;
            if owner[k] != u32::MAX {
                return Err(not_a_grid(format!(
                    "vertices {} and {v} both lie on grid point ({i}, {j})",
                    owner[k]
                )));
            }
            // Vertex ids fit u32: the mesh data indexes them with u32.
            owner[k] = u32::try_from(v).unwrap_or(u32::MAX - 1);
            z[k] = p.z;
        }
        check_grid_faces(mesh, nx, ny, &owner).map_err(|reason| {
            not_a_grid(format!(
                "{reason}; a height map keeps the heights of whole grid cells only (write .ply, .obj or .off to keep these faces)"
            ))
        })?;
        Self::new(nx, ny, x_axis.spacing, y_axis.spacing, z, unit)
    }
}

/// Whether the faces of `mesh`, whose vertex on grid point `k` is `owner[k]`
/// (`u32::MAX` for none), tile the grid's whole cells — each cell whose four corners are
/// vertices covered once, by its two triangles on either diagonal or by one
/// quadrilateral, counter-clockwise seen from +z, and no other face — and every vertex
/// is in one of them; else what differs. Such a mesh is its heights: read back, each
/// cell is split from `(i, j)` to `(i + 1, j + 1)` ([`HeightMap::to_mesh`]).
fn check_grid_faces(mesh: &MeshData, nx: usize, ny: usize, owner: &[u32]) -> Result<(), String> {
    let mut point = vec![(0usize, 0usize); mesh.positions.len()];
    for (k, &v) in owner.iter().enumerate() {
        if v != u32::MAX {
            point[v as usize] = (k % nx, k / nx);
        }
    }
    let has = |i: usize, j: usize| owner[i + nx * j] != u32::MAX;
    let whole =
        |i: usize, j: usize| has(i, j) && has(i + 1, j) && has(i + 1, j + 1) && has(i, j + 1);
    let (cx, cy) = (nx.saturating_sub(1), ny.saturating_sub(1));
    // Per cell, which of its faces were seen: the triangles (a b c), (a c d) of the
    // diagonal a–c, (a b d), (b c d) of b–d, and the quadrilateral (a b c d), with a, b, c,
    // d its corners counter-clockwise from (i, j).
    let mut cover = vec![0u8; cx * cy];
    for (f, face) in mesh.faces.iter().enumerate() {
        let named = || {
            let list: Vec<String> = face.iter().map(u32::to_string).collect();
            format!("face {f} ({})", list.join(", "))
        };
        if !(3..=4).contains(&face.len()) {
            return Err(format!("face {f} has {} vertices", face.len()));
        }
        let points: Vec<(usize, usize)> = face.iter().map(|&v| point[v as usize]).collect();
        let i = points.iter().map(|p| p.0).min().unwrap_or(0);
        let j = points.iter().map(|p| p.1).min().unwrap_or(0);
        if i >= cx || j >= cy || points.iter().any(|p| p.0 > i + 1 || p.1 > j + 1) {
            return Err(format!("{} spans more than one grid cell", named()));
        }
        if !whole(i, j) {
            return Err(format!(
                "{} lies in the grid cell at point ({i}, {j}), which lacks a corner",
                named()
            ));
        }
        // The corners' places around the cell, counter-clockwise from (i, j).
        let place: Vec<u8> = points
            .iter()
            .map(|&(x, y)| match (x - i, y - j) {
                (0, 0) => 0,
                (1, 0) => 1,
                (1, 1) => 2,
                _ => 3,
            })
            .collect();
        let k = place.len();
        let start = (0..k).min_by_key(|&m| place[m]).unwrap_or(0);
        let rotated: Vec<u8> = (0..k).map(|m| place[(start + m) % k]).collect();
        let bit = match rotated[..] {
            [0, 1, 2] => 0,
            [0, 2, 3] => 1,
            [0, 1, 3] => 2,
            [1, 2, 3] => 3,
            [0, 1, 2, 3] => 4,
            _ => {
                return Err(format!(
                    "{} faces down (clockwise seen from +z; a height map's faces face up)",
                    named()
                ));
            }
        };
        let seen = &mut cover[i + cx * j];
        if *seen & (1 << bit) != 0 {
            return Err(format!(
                "{} repeats a face of the grid cell at point ({i}, {j})",
                named()
            ));
        }
        *seen |= 1 << bit;
    }
    for j in 0..cy {
        for i in 0..cx {
            if !whole(i, j) {
                continue;
            }
            match cover[i + cx * j] {
                0b00011 | 0b01100 | 0b10000 => {}
                0 => {
                    return Err(format!(
                        "the grid cell at point ({i}, {j}) has four vertices but no face"
                    ));
                }
                _ => {
                    return Err(format!(
                        "the faces of the grid cell at point ({i}, {j}) do not cover it once (two triangles on one diagonal, or one quadrilateral)"
                    ));
                }
            }
        }
    }
    // Every vertex is a corner of a whole cell, which faces cover.
    let mut in_a_cell = vec![false; mesh.positions.len()];
    for j in 0..cy {
        for i in 0..cx {
            if whole(i, j) {
                for (x, y) in [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)] {
                    in_a_cell[owner[x + nx * y] as usize] = true;
                }
            }
        }
    }
    if let Some(v) = in_a_cell.iter().position(|&used| !used) {
        return Err(format!(
            "vertex {v} is a corner of no grid cell whose four corners are vertices"
        ));
    }
    Ok(())
}

fn off_grid(vertex: usize, name: &str, value: f64, axis: &Axis) -> IoError {
    IoError::NotAGrid {
        reason: format!(
            "vertex {vertex} has {name} = {value}, which is not on the grid {} + k·{} of the other vertices",
            axis.origin, axis.spacing
        ),
    }
}

/// The grid of one coordinate: `origin + k·spacing` for `0 <= k < count`.
struct Axis {
    origin: f64,
    spacing: f64,
    count: usize,
}

/// How far, in spacings, a coordinate may lie from its grid line.
const GRID_TOLERANCE: f64 = 1e-6;

impl Axis {
    /// The grid through the distinct `values`: the median gap between neighbours sets
    /// the spacing (so that a few missing rows or columns, or a vertex off the grid,
    /// do not set it), refined over the whole range.
    fn fit(values: &[f64], name: &str, vertices: usize) -> Result<Self, String> {
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        sorted.dedup();
        let (lo, hi) = (sorted[0], sorted[sorted.len() - 1]);
        let mut gaps: Vec<f64> = sorted.windows(2).map(|w| w[1] - w[0]).collect();
        if gaps.is_empty() {
            return Err(format!(
                "every vertex has {name} = {lo}; a height map needs two distinct values along each axis"
            ));
        }
        let middle = gaps.len() / 2;
        let (_, &mut gap, _) = gaps.select_nth_unstable_by(middle, f64::total_cmp);
        let steps = ((hi - lo) / gap).round();
        // More grid lines than vertices along one axis: the values are not on a grid
        // (a mesh moved off it, or round-off), and the check below would say so.
        if !(steps.is_finite() && steps <= vertices as f64) {
            return Err(format!(
                "the {name} coordinates are not on a regular grid: their median gap, {gap:e}, divides their range, {:e}, into more steps than there are vertices (a mesh whose vertices moved in x or y?)",
                hi - lo
            ));
        }
        let spacing = (hi - lo) / steps;
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(format!("the {name} coordinates span no finite spacing"));
        }
        // The grid through the origin, when the lowest value is on it.
        let lead = (lo / spacing).round();
        let (origin, lead) = if lead >= 0.0
            && lead <= vertices as f64
            && (lo - lead * spacing).abs() <= GRID_TOLERANCE * spacing
        {
            (0.0, lead)
        } else {
            (lo, 0.0)
        };
        // Both are whole numbers no larger than the vertex count: the cast is exact.
        let count = (lead + steps) as usize + 1;
        Ok(Self {
            origin,
            spacing,
            count,
        })
    }

    /// The grid index of `value`, when it lies on a grid line.
    fn index(&self, value: f64) -> Option<usize> {
        let k = ((value - self.origin) / self.spacing).round();
        let on_line =
            (value - (self.origin + k * self.spacing)).abs() <= GRID_TOLERANCE * self.spacing;
        (on_line && k >= 0.0 && k < self.count as f64).then_some(k as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grid_with_holes_comes_back_with_its_leading_invalid_column() {
        let nan = f64::NAN;
        let z = vec![
            nan, 1.0, 2.0, 3.0, //
            nan, 5.0, 6.0, 7.0, //
            nan, 9.0, 10.0, nan,
        ];
        let map = HeightMap::new(4, 3, 0.1, 0.3, z, LengthUnit::Metre).unwrap();
        let (mesh, stats) = map.to_mesh();
        assert_eq!(stats.invalid_points, 4);
        assert_eq!(stats.unused_points, 0);
        assert_eq!(mesh.positions.len(), 8);
        assert_eq!(mesh.faces.len(), 2 * 3);
        let back = HeightMap::from_mesh(&mesh, LengthUnit::Metre).unwrap();
        assert_eq!((back.nx, back.ny), (4, 3));
        for (a, b) in back.z.iter().zip(&map.z) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }

    /// A mesh on the grid is a height map when its faces tile the whole cells once,
    /// facing up, on either diagonal or as quadrilaterals; not with a face across cells,
    /// facing down, a triangle missing or twice, or a vertex in no whole cell.
    #[test]
    fn the_faces_must_tile_the_grids_cells() {
        let map = HeightMap::new(3, 3, 1.0, 1.0, vec![0.0; 9], LengthUnit::Metre).unwrap();
        let (mesh, _) = map.to_mesh();
        assert!(HeightMap::from_mesh(&mesh, LengthUnit::Metre).is_ok());
        let faces: Vec<Vec<u32>> = mesh.faces.iter().map(<[u32]>::to_vec).collect();
        let on = |positions: Vec<DVec3>, faces: &[Vec<u32>]| {
            let mut list = PolygonList::new();
            for f in faces {
                list.push(f);
            }
            HeightMap::from_mesh(&MeshData::new(positions, list), LengthUnit::Metre)
        };
        let with = |faces: &[Vec<u32>]| on(mesh.positions.clone(), faces);
        let error = |faces: &[Vec<u32>]| with(faces).unwrap_err().to_string();
        // Rotated, each triangle is the same face.
        let rotated: Vec<Vec<u32>> = faces.iter().map(|f| vec![f[1], f[2], f[0]]).collect();
        assert!(with(&rotated).is_ok());
        // The first cell (points 0, 1, 4, 3) split along its other diagonal, or as a quad.
        assert_eq!(faces[..2], [vec![0, 1, 4], vec![0, 4, 3]]);
        let mut other = faces.clone();
        other[0] = vec![0, 1, 3];
        other[1] = vec![1, 4, 3];
        assert!(with(&other).is_ok());
        let mut quad = faces[1..].to_vec();
        quad[0] = vec![0, 1, 4, 3];
        assert!(with(&quad).is_ok());
        // Two triangles of different diagonals do not cover the cell once.
        let mut crossed = faces.clone();
        crossed[1] = vec![0, 1, 3];
        assert!(error(&crossed).contains("do not cover it once"));
        // Reversed (normals down).
        let reversed: Vec<Vec<u32>> = faces.iter().map(|f| vec![f[0], f[2], f[1]]).collect();
        assert!(error(&reversed).contains("faces down"));
        // Across two cells.
        let mut across = faces.clone();
        across[0] = vec![0, 2, 8];
        assert!(error(&across).contains("spans more than one grid cell"));
        // A triangle missing, or twice.
        assert!(error(&faces[1..]).contains("do not cover it once"));
        let mut twice = faces.clone();
        twice.push(faces[0].clone());
        assert!(error(&twice).contains("repeats a face"));
        // A vertex in no whole cell: point (2, 1) of a grid without point (2, 0).
        let square = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (2.0, 1.0)];
        let positions = square.map(|(x, y)| DVec3::new(x, y, 0.0)).to_vec();
        let e = on(positions.clone(), &[vec![0, 1, 3], vec![0, 3, 2]])
            .unwrap_err()
            .to_string();
        assert!(e.contains("vertex 4 is a corner of no grid cell"), "{e}");
        // And a face in that cell, which lacks a corner.
        let e = on(positions, &[vec![0, 1, 3], vec![0, 3, 2], vec![1, 4, 3]])
            .unwrap_err()
            .to_string();
        assert!(e.contains("which lacks a corner"), "{e}");
    }

    /// A face naming a vertex that does not exist is a typed error, not a panic.
    #[test]
    fn a_face_index_out_of_range_is_an_error() {
        let map = HeightMap::new(2, 2, 1.0, 1.0, vec![0.0; 4], LengthUnit::Metre).unwrap();
        let (mut mesh, _) = map.to_mesh();
        mesh.faces.push(&[0, 1, 9]);
        let e = HeightMap::from_mesh(&mesh, LengthUnit::Metre).unwrap_err();
        assert!(
            matches!(
                e,
                IoError::FaceIndexOutOfRange {
                    face: 2,
                    index: 9,
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn a_vertex_off_the_grid_is_named() {
        let map = HeightMap::new(3, 3, 1.0, 1.0, vec![0.0; 9], LengthUnit::Metre).unwrap();
        let (mut mesh, _) = map.to_mesh();
        mesh.positions[4].x += 0.25;
        let e = HeightMap::from_mesh(&mesh, LengthUnit::Metre).unwrap_err();
        assert!(matches!(e, IoError::NotAGrid { .. }), "{e}");
    }
}
