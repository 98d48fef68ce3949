//! The references `tools/openmesh-ref` writes, read back; and the beltrami settings that
//! reproduce OpenMesh's `JacobiLaplaceSmootherT`.
//!
//! A reference folder (`fixtures/openmesh/<fixture>/`) holds:
//!
//! | file | contents |
//! |---|---|
//! | `summary.json` | counts, boundary-loop lengths, bounding box, area, volume, the list of cases ([`ReferenceSummary`]) |
//! | `topology.txt` | per vertex: valence, boundary flag, outgoing halfedge, one-ring in order; per edge: its end points; per face: its halfedge and vertices; per boundary loop: first halfedge and length ([`ReferenceTopology`]) |
//! | `face_normals.f64`, `vertex_normals.f64`, `face_areas.f64` | raw little-endian doubles, 3 per face / 3 per vertex / 1 per face |
//! | `openmesh_smoother/<case>.{ply,json}` | OpenMesh's `JacobiLaplaceSmootherT` output positions and a summary ([`CaseSummary`]) |
//! | `paper/<case>.{ply,json}` | the paper's explicit smoothing written on OpenMesh's data structure |
//! | `subdivision/` | OpenMesh's `LoopT` and `Sqrt3T` results (`cases.txt`, `<scheme>_<steps>.f64` positions, `<scheme>_<steps>.faces.u32` triangles), read by `crates/algorithms/tests/openmesh.rs` |
//!
//! The `.ply` files hold vertex positions only (binary little-endian doubles, exact);
//! the faces are those of the input mesh.

use std::fs;
use std::path::{Path, PathBuf};

use beltrami_halfedge::DVec3;
use beltrami_smooth::{Boundary, SmoothConfig, WeightUpdate};
use beltrami_weights::{LaplacianOptions, OpenMeshCotangent, Uniform, WeightScheme};
use serde::Deserialize;

/// What went wrong reading a reference.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReferenceError {
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A JSON file does not have the expected fields.
    #[error("{path}: {source}")]
    Json {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: serde_json::Error,
    },
    /// A line of `topology.txt` or the size of a `.f64` file is wrong.
    #[error("{path}:{line}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// The 1-based line (0 for binary files).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A positions file could not be read as a mesh.
    #[error("{path}: {source}")]
    Mesh {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: beltrami_io::IoError,
    },
}

/// `summary.json` of a reference folder.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct ReferenceSummary {
    /// The fixture's name (the folder name).
    pub fixture: String,
    /// The input mesh, relative to the repository root.
    pub input: String,
    /// The OpenMesh version that wrote the reference.
    pub openmesh: String,
    /// Vertex count.
    pub vertices: usize,
    /// Edge count.
    pub edges: usize,
    /// Face count.
    pub faces: usize,
    /// Halfedge count.
    pub halfedges: usize,
    /// Halfedges without a face.
    pub boundary_halfedges: usize,
    /// Vertices OpenMesh calls boundary vertices.
    pub boundary_vertices: usize,
    /// Boundary-loop lengths, in the order of each loop's lowest halfedge.
    pub boundary_loops: Vec<usize>,
    /// Whether the mesh has no boundary.
    pub closed: bool,
    /// Bounding-box lower corner.
    pub bbox_min: [f64; 3],
    /// Bounding-box upper corner.
    pub bbox_max: [f64; 3],
    /// Bounding-box diagonal: the unit of every tolerance.
    pub bbox_diagonal: f64,
    /// Total area (sum of OpenMesh's `calc_sector_area` per face, compensated).
    pub surface_area: f64,
    /// Enclosed volume for a closed mesh.
    pub volume: Option<f64>,
    /// The cases, as `kind/name` (`openmesh_smoother/normal_c0_10`, `paper/…`).
    pub cases: Vec<String>,
}

/// One vertex of `topology.txt`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct VertexRecord {
    /// Number of neighbours.
    pub valence: usize,
    /// OpenMesh's `is_boundary(v)`.
    pub boundary: bool,
    /// OpenMesh's `halfedge_handle(v)`, `None` for an isolated vertex.
    pub halfedge: Option<u32>,
    /// The one-ring, counter-clockwise from the target of `halfedge`.
    pub ring: Vec<u32>,
}

/// One face of `topology.txt`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaceRecord {
    /// OpenMesh's `halfedge_handle(f)`.
    pub halfedge: u32,
    /// The vertices from the target of that halfedge, following `next`.
    pub vertices: Vec<u32>,
}

/// One boundary loop of `topology.txt`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoopRecord {
    /// The loop's lowest halfedge.
    pub first_halfedge: u32,
    /// Its length in edges.
    pub length: usize,
}

/// `topology.txt`: the connectivity exactly as OpenMesh numbers it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ReferenceTopology {
    /// One record per vertex.
    pub vertices: Vec<VertexRecord>,
    /// Per edge `e`: `[from_vertex(2e), to_vertex(2e)]`.
    pub edges: Vec<[u32; 2]>,
    /// One record per face.
    pub faces: Vec<FaceRecord>,
    /// Boundary loops in the order of their lowest halfedge.
    pub loops: Vec<LoopRecord>,
}

/// The JSON summary of one case.
#[derive(Clone, Debug, PartialEq, Deserialize)]
pub struct CaseSummary {
    /// `openmesh_smoother` or `paper`.
    pub kind: String,
    /// The case name.
    pub case: String,
    /// The iteration count.
    pub iterations: usize,
    /// The positions file, relative to the case's folder.
    pub positions: String,
    /// λ.
    pub lambda: f64,
    /// `every` or `once`.
    pub update: String,
    /// `fixed` or `free`.
    pub boundary: String,
    /// For `paper`: `uniform`, `distance` or `cotangent`.
    pub scheme: Option<String>,
    /// For `openmesh_smoother`: `tangential_and_normal` or `normal`.
    pub component: Option<String>,
    /// Vertices whose position changed.
    pub moved_vertices: usize,
    /// The largest displacement from the input.
    pub max_displacement: f64,
    /// The root-mean-square displacement from the input.
    pub rms_displacement: f64,
    /// For `paper`: vertices allowed to move (not fixed, not isolated).
    pub smoothed_vertices: Option<usize>,
    /// For `paper`: halfedges with a negative weight in the first iteration.
    pub negative_halfedge_weights_first_iteration: Option<usize>,
    /// For `paper`: the largest number of stuck vertices in an iteration.
    pub max_stuck_vertices: Option<usize>,
}

/// A case: its summary and its output positions.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceCase {
    /// `kind/name`.
    pub id: String,
    /// The JSON summary.
    pub summary: CaseSummary,
    /// The positions after smoothing, one per vertex.
    pub positions: Vec<DVec3>,
}

/// A reference folder, loaded (cases are loaded on demand by [`case`](Self::case)).
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    /// The folder.
    pub dir: PathBuf,
    /// `summary.json`.
    pub summary: ReferenceSummary,
    /// `topology.txt`.
    pub topology: ReferenceTopology,
    /// `face_normals.f64`: OpenMesh's `update_normals` face normals.
    pub face_normals: Vec<DVec3>,
    /// `vertex_normals.f64`: OpenMesh's `update_normals` vertex normals.
    pub vertex_normals: Vec<DVec3>,
    /// `face_areas.f64`: OpenMesh's `calc_sector_area` of each face's halfedge.
    pub face_areas: Vec<f64>,
}

fn read(path: &Path) -> Result<Vec<u8>, ReferenceError> {
    fs::read(path).map_err(|source| ReferenceError::Read {
        path: path.to_path_buf(),
        source,
    })
}

fn read_json<T: for<'de> Deserialize<'de>>(path: &Path) -> Result<T, ReferenceError> {
    serde_json::from_slice(&read(path)?).map_err(|source| ReferenceError::Json {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads a raw little-endian `f64` file.
///
/// # Errors
/// [`ReferenceError::Read`], or [`ReferenceError::Format`] when the size is not a
/// multiple of 8.
///
/// # Panics
/// Never: the length is checked to be a multiple of 8 before the chunks are converted.
pub fn read_f64s(path: &Path) -> Result<Vec<f64>, ReferenceError> {
    let bytes = read(path)?;
    if bytes.len() % 8 != 0 {
        return Err(ReferenceError::Format {
            path: path.to_path_buf(),
            line: 0,
            message: format!("{} bytes is not a whole number of doubles", bytes.len()),
        });
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect())
}

fn read_vectors(path: &Path, count: usize) -> Result<Vec<DVec3>, ReferenceError> {
    let xs = read_f64s(path)?;
    if xs.len() != 3 * count {
        return Err(ReferenceError::Format {
            path: path.to_path_buf(),
            line: 0,
            message: format!("{} doubles, expected {}", xs.len(), 3 * count),
        });
    }
    Ok(xs
        .chunks_exact(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect())
}

/// Parses the text of `topology.txt` (`path` is only for error messages).
///
/// # Errors
/// [`ReferenceError::Format`] naming the first malformed line.
pub fn parse_topology(text: &str, path: &Path) -> Result<ReferenceTopology, ReferenceError> {
    let mut topology = ReferenceTopology::default();
    for (i, line) in text.lines().enumerate() {
        let error = |message: &str| ReferenceError::Format {
            path: path.to_path_buf(),
            line: i + 1,
            message: message.to_string(),
        };
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        let (head, tail) = match line.split_once(" : ") {
            Some((h, t)) => (h, Some(t)),
            None => (line.strip_suffix(" :").unwrap_or(line), None),
        };
        let fields: Vec<&str> = head.split_whitespace().collect();
        let ints = |s: &str| -> Result<Vec<u32>, ReferenceError> {
            s.split_whitespace()
                .map(|x| x.parse::<u32>().map_err(|_| error("not an index")))
                .collect()
        };
        let int = |k: usize| -> Result<i64, ReferenceError> {
            fields
                .get(k)
                .and_then(|x| x.parse::<i64>().ok())
                .ok_or_else(|| error("missing or malformed number"))
        };
        let expect_index = |k: usize, expected: usize| -> Result<(), ReferenceError> {
            if int(k)? == expected as i64 {
                Ok(())
            } else {
                Err(error("records out of order"))
            }
        };
        match fields.first().copied() {
            Some("v") => {
                expect_index(1, topology.vertices.len())?;
                let halfedge = int(4)?;
                topology.vertices.push(VertexRecord {
                    valence: usize::try_from(int(2)?).map_err(|_| error("negative valence"))?,
                    boundary: int(3)? != 0,
                    halfedge: u32::try_from(halfedge).ok(),
                    ring: ints(tail.unwrap_or(""))?,
                });
            }
            Some("e") => {
                expect_index(1, topology.edges.len())?;
                let from = u32::try_from(int(2)?).map_err(|_| error("bad vertex"))?;
                let to = u32::try_from(int(3)?).map_err(|_| error("bad vertex"))?;
                topology.edges.push([from, to]);
            }
            Some("f") => {
                expect_index(1, topology.faces.len())?;
                topology.faces.push(FaceRecord {
                    halfedge: u32::try_from(int(2)?).map_err(|_| error("bad halfedge"))?,
                    vertices: ints(tail.ok_or_else(|| error("missing ':'"))?)?,
                });
            }
            Some("l") => topology.loops.push(LoopRecord {
                first_halfedge: u32::try_from(int(1)?).map_err(|_| error("bad halfedge"))?,
                length: usize::try_from(int(2)?).map_err(|_| error("bad length"))?,
            }),
            _ => return Err(error("unknown record")),
        }
    }
    Ok(topology)
}

impl Reference {
    /// Loads the reference folder `dir` (summary, topology and geometry).
    ///
    /// # Errors
    /// Any [`ReferenceError`]: a missing or malformed file, or arrays whose sizes do not
    /// match the counts of `summary.json`.
    pub fn load(dir: &Path) -> Result<Self, ReferenceError> {
        let summary: ReferenceSummary = read_json(&dir.join("summary.json"))?;
        let topology_path = dir.join("topology.txt");
        let text = String::from_utf8_lossy(&read(&topology_path)?).into_owned();
        let topology = parse_topology(&text, &topology_path)?;
        let areas_path = dir.join("face_areas.f64");
        let face_areas = read_f64s(&areas_path)?;
        if face_areas.len() != summary.faces {
            return Err(ReferenceError::Format {
                path: areas_path,
                line: 0,
                message: format!("{} areas for {} faces", face_areas.len(), summary.faces),
            });
        }
        Ok(Self {
            face_normals: read_vectors(&dir.join("face_normals.f64"), summary.faces)?,
            vertex_normals: read_vectors(&dir.join("vertex_normals.f64"), summary.vertices)?,
            face_areas,
            topology,
            summary,
            dir: dir.to_path_buf(),
        })
    }

    /// Loads case `id` (`kind/name`, one of [`ReferenceSummary::cases`]).
    ///
    /// # Errors
    /// Any [`ReferenceError`]; [`ReferenceError::Format`] when the positions do not have
    /// one entry per vertex.
    pub fn case(&self, id: &str) -> Result<ReferenceCase, ReferenceError> {
        let json = self.dir.join(format!("{id}.json"));
        let summary: CaseSummary = read_json(&json)?;
        let folder = json.parent().unwrap_or(&self.dir);
        let path = folder.join(&summary.positions);
        let mesh = beltrami_io::read_mesh(&path).map_err(|source| ReferenceError::Mesh {
            path: path.clone(),
            source,
        })?;
        if mesh.positions.len() != self.summary.vertices {
            return Err(ReferenceError::Format {
                path,
                line: 0,
                message: format!(
                    "{} positions for {} vertices",
                    mesh.positions.len(),
                    self.summary.vertices
                ),
            });
        }
        Ok(ReferenceCase {
            id: id.to_string(),
            summary,
            positions: mesh.positions,
        })
    }
}

/// The two components of OpenMesh's `JacobiLaplaceSmootherT` and the weights OpenMesh
/// hard-wires for each (`LaplaceSmootherT::initialize`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SmootherComponent {
    /// `Tangential_and_Normal`: uniform weights.
    TangentialAndNormal,
    /// `Normal`: cotangent weights, [`OpenMeshCotangent`]. Despite its name, OpenMesh
    /// 9.0 moves the vertex by the whole update, not only along the normal: only
    /// `Tangential` projects (onto the tangent plane).
    Normal,
}

impl SmootherComponent {
    /// The name of the reference cases (`tangential_and_normal`, `normal`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::TangentialAndNormal => "tangential_and_normal",
            Self::Normal => "normal",
        }
    }

    /// The component with the given case name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "tangential_and_normal" => Some(Self::TangentialAndNormal),
            "normal" => Some(Self::Normal),
            _ => None,
        }
    }

    /// The weight scheme OpenMesh uses for this component.
    #[must_use]
    pub fn scheme(self) -> &'static dyn WeightScheme {
        match self {
            Self::TangentialAndNormal => &Uniform,
            Self::Normal => &OpenMeshCotangent,
        }
    }
}

/// The configuration that reproduces `JacobiLaplaceSmootherT` with `C0` continuity:
/// λ = 0.5 (OpenMesh's fixed damping), weights computed once from the input, fixed
/// boundary, weight-sum normalisation, negative weights kept — with the scheme of
/// [`SmootherComponent::scheme`].
///
/// # Examples
/// ```
/// use beltrami_halfedge::primitives;
/// use beltrami_smooth::smooth;
/// use beltrami_testkit::openmesh::{smoother_config, SmootherComponent};
///
/// let sphere = primitives::icosphere(2);
/// let mesh = sphere.mesh()?;
/// let scheme = SmootherComponent::Normal.scheme();
/// let out = smooth(&mesh, &sphere.positions, scheme, smoother_config(10))?;
/// assert_eq!(out.report.iterations, 10);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[must_use]
pub fn smoother_config(iterations: usize) -> SmoothConfig {
    SmoothConfig::new(0.5, iterations)
        .boundary(Boundary::Fixed)
        .update(WeightUpdate::Once)
        .laplacian(LaplacianOptions::default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn topology_lines_parse() {
        let text = "# comment\nv 0 2 1 3 : 1 2\nv 1 0 1 -1 :\ne 0 0 1\nf 0 5 : 0 1 2\nl 3 4\n";
        let t = parse_topology(text, Path::new("t")).unwrap();
        assert_eq!(t.vertices[0].ring, [1, 2]);
        assert_eq!(t.vertices[0].halfedge, Some(3));
        assert!(t.vertices[1].ring.is_empty());
        assert_eq!(t.vertices[1].halfedge, None);
        assert_eq!(t.edges, [[0, 1]]);
        assert_eq!(t.faces[0].vertices, [0, 1, 2]);
        assert_eq!(
            t.loops,
            [LoopRecord {
                first_halfedge: 3,
                length: 4
            }]
        );
    }

    #[test]
    fn malformed_topology_names_the_line() {
        let err = parse_topology("v 0 2 1 3 : 1 2\nv 5 2 1 3 : 1 2\n", Path::new("t")).unwrap_err();
        assert_eq!(err.to_string(), "t:2: records out of order");
        let err = parse_topology("x\n", Path::new("t")).unwrap_err();
        assert_eq!(err.to_string(), "t:1: unknown record");
    }

    #[test]
    fn component_names_round_trip() {
        for c in [
            SmootherComponent::TangentialAndNormal,
            SmootherComponent::Normal,
        ] {
            assert_eq!(SmootherComponent::from_name(c.name()), Some(c));
        }
        assert_eq!(
            SmootherComponent::Normal.scheme().name(),
            "openmesh-cotangent"
        );
    }
}
