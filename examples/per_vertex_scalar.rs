//! A per-vertex value computed by walking one-rings, written as a PLY scalar: the
//! discrete Gaussian curvature of a mesh by the angle defect (Meyer, Desbrun, Schröder
//! and Barr 2003, "Discrete differential-geometry operators for triangulated
//! 2-manifolds", section 5):
//!
//! ```text
//! K_i = (2π − Σ_j θ_j) / A_i
//! ```
//!
//! with `θ_j` the corner angles of the triangles at vertex `i` and `A_i` its mixed
//! Voronoi area; boundary vertices get `(π − Σ θ_j) / A_i` (geodesic curvature of the
//! boundary folded in), isolated vertices 0. Units: 1/length² of the mesh's unit.
//!
//! ```sh
//! cargo run --release --example per_vertex_scalar -- fixtures/torus_12x8.ply curvature.ply
//! beltrami render curvature.ply curvature.png --scalar gaussian_curvature
//! ```
//!
//! The sum of `K_i A_i` over a closed mesh is `2π χ` (Gauss–Bonnet), which the example
//! prints as a check.

use std::f64::consts::{PI, TAU};
use std::path::PathBuf;

use beltrami::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args_os().skip(1).map(PathBuf::from);
    let (Some(input), Some(output)) = (args.next(), args.next()) else {
        eprintln!("usage: per_vertex_scalar IN OUT.ply");
        std::process::exit(2);
    };
    // Read any format, build the half-edge connectivity.
    let data = read_mesh(&input)?;
    let mesh = HalfedgeMesh::from_polygons(data.positions.len(), data.faces.iter())?;
    let geometry = Geometry::new(&mesh, &data.positions)?;
    let areas = geometry.vertex_areas(VertexAreaKind::MixedVoronoi)?;

    // Walk each vertex's one-ring: the corner angle at v of each face around it.
    let mut curvature = Vec::with_capacity(mesh.n_vertices());
    let mut total = 0.0;
    for v in mesh.vertices() {
        if mesh.is_isolated(v) {
            curvature.push(0.0);
            continue;
        }
        // `corner_angle(h)` is the angle at the end of `h`: the incoming halfedges
        // of v are the twins of its outgoing ones.
        let angle_sum: f64 = mesh
            .halfedges_around_vertex(v)
            .map(|h| geometry.corner_angle(h.twin()))
            .sum();
        let full = if mesh.is_boundary_vertex(v) { PI } else { TAU };
        let defect = full - angle_sum;
        total += defect;
        let area = areas[v];
        curvature.push(if area > 0.0 { defect / area } else { 0.0 });
    }
    if mesh.is_closed() {
        let expected = TAU * mesh.euler_characteristic() as f64;
        println!(
            "Gauss-Bonnet: sum of angle defects {total:.12} = 2 pi chi {expected:.12} (chi = {})",
            mesh.euler_characteristic()
        );
    }

    // Write the mesh with the value as `property double gaussian_curvature`.
    let attributes = VertexAttributes {
        scalars: vec![("gaussian_curvature".to_owned(), curvature)],
        colors: None,
    };
    write_ply(&output, &data, &attributes, &WriteOptions::default())?;
    println!(
        "{} vertices: gaussian_curvature -> {}",
        mesh.n_vertices(),
        output.display()
    );
    Ok(())
}
