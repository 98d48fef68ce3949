//! A generated test surface.

use beltrami_halfedge::{DVec3, MeshData, PolygonList};

/// A generated surface: the workspace's [`MeshData`] (positions and counter-clockwise
/// faces; normals outwards for the closed surfaces, towards +z for the F-lens), with a
/// name and the unit its coordinates are in. It dereferences to its [`MeshData`], so
/// `surface.positions`, `surface.faces` and `surface.mesh()` read as on the data.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// The surface's name (`"flens"`, `"sphere"`, `"block"`, `"golfball"`).
    pub name: &'static str,
    /// Positions and faces.
    pub data: MeshData,
    /// The length unit of the coordinates (`"mm"`, or `"1"` for the unit sphere).
    pub unit: &'static str,
}

impl std::ops::Deref for Surface {
    type Target = MeshData;

    fn deref(&self) -> &MeshData {
        &self.data
    }
}

impl std::ops::DerefMut for Surface {
    fn deref_mut(&mut self) -> &mut MeshData {
        &mut self.data
    }
}

impl From<Surface> for MeshData {
    fn from(surface: Surface) -> Self {
        surface.data
    }
}

impl Surface {
    /// A surface named `name` with `positions` and `faces` in `unit`.
    #[must_use]
    pub fn new(
        name: &'static str,
        positions: Vec<DVec3>,
        faces: PolygonList,
        unit: &'static str,
    ) -> Self {
        Self {
            name,
            data: MeshData::new(positions, faces),
            unit,
        }
    }

    /// The same surface with its vertices renumbered in a seeded random order (a
    /// Fisher–Yates shuffle driven by [`NormalRng`](crate::NormalRng)'s uniform
    /// numbers, so the order is the same on every platform). Face `f` stays face `f`
    /// with the same first corner; its indices name the renumbered vertices. Benchmarks
    /// use it to measure how a method copes with a poor vertex order (a scan's order is
    /// often far from the mesh's connectivity).
    ///
    /// # Examples
    /// ```
    /// let s = beltrami_surfaces::sphere(1);
    /// let t = s.shuffled(3);
    /// assert_eq!(t.positions.len(), s.positions.len());
    /// let f = t.faces.get(0).unwrap();
    /// let g = s.faces.get(0).unwrap();
    /// for k in 0..3 {
    ///     assert_eq!(t.positions[f[k] as usize], s.positions[g[k] as usize]);
    /// }
    /// ```
    #[must_use]
    pub fn shuffled(&self, seed: u64) -> Self {
        let n = self.positions.len();
        let new_to_old = shuffle_order(n, seed);
        let mut old_to_new = vec![0u32; n];
        for (new, &old) in new_to_old.iter().enumerate() {
            old_to_new[old as usize] = new as u32;
        }
        let positions = new_to_old
            .iter()
            .map(|&old| self.positions[old as usize])
            .collect();
        let mut faces = PolygonList::with_capacity(self.faces.len(), self.faces.n_corners());
        let mut face = Vec::new();
        for f in self.faces.iter() {
            face.clear();
            face.extend(f.iter().map(|&v| old_to_new[v as usize]));
            faces.push(&face);
        }
        Self::new(self.name, positions, faces, self.unit)
    }
}

/// The vertex order of [`Surface::shuffled`] for `n` vertices and `seed`: entry `new` is
/// the old index of the vertex numbered `new` (apply it to per-vertex data that must
/// follow the renumbering, e.g. noisy positions of the same surface).
#[must_use]
pub fn shuffle_order(n: usize, seed: u64) -> Vec<u32> {
    let mut rng = crate::NormalRng::new(seed);
    let mut new_to_old: Vec<u32> = (0..n as u32).collect();
    for i in (1..n).rev() {
        // floor(u * (i + 1)) with u in [0, 1) lies in 0..=i (u < 1 - 2^-53 and
        // i + 1 < 2^32, so the product rounds below i + 1).
        let j = (rng.next_uniform() * (i + 1) as f64) as usize;
        new_to_old.swap(i, j.min(i));
    }
    new_to_old
}
