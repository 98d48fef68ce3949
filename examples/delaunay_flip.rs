//! Edge flips until every interior edge is Delaunay, on the editable mesh: the
//! cotangent weight `cot α + cot β` of an edge (α, β the angles opposite it) is negative
//! exactly when the edge is not locally Delaunay, and flipping such an edge (Lawson
//! 1977) makes the weights of a planar mesh all non-negative — the problem of negative
//! cotangent weights solved at the mesh, not by clamping the weight.
//!
//! ```sh
//! cargo run --release --example delaunay_flip -- fixtures/flens_68x33.ply flipped.ply
//! beltrami render flipped.ply flipped.png --scalar height
//! ```
//!
//! The vertex set stays the same, so a per-vertex scalar (here the height `z`, attached
//! as a property) is carried through unchanged and written as a PLY property. On a
//! curved surface a flip changes the surface slightly; this example does not bound that
//! (a metrology pipeline would cap the dihedral angle of a flip).

use std::collections::VecDeque;
use std::path::PathBuf;

use beltrami::halfedge::EditMesh;
use beltrami::prelude::*;

/// `cot` of the angle opposite `h` in its triangle; 0 on the boundary or for a
/// degenerate triangle.
fn opposite_cot(mesh: &EditMesh, h: HalfedgeId) -> f64 {
    let Some(o) = mesh.opposite_vertex(h) else {
        return 0.0;
    };
    let u = mesh.position(mesh.from_vertex(h)) - mesh.position(o);
    let v = mesh.position(mesh.to_vertex(h)) - mesh.position(o);
    let sin = u.cross(v).length();
    if sin > 0.0 { u.dot(v) / sin } else { 0.0 }
}

/// Whether an interior edge is not locally Delaunay (its cotangent weight is negative).
fn needs_flip(mesh: &EditMesh, e: EdgeId) -> bool {
    let [h, t] = e.halfedges();
    !mesh.is_boundary_edge(e) && opposite_cot(mesh, h) + opposite_cot(mesh, t) < -1e-12
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args_os().skip(1).map(PathBuf::from);
    let (Some(input), Some(output)) = (args.next(), args.next()) else {
        eprintln!("usage: delaunay_flip IN OUT.ply");
        std::process::exit(2);
    };
    let mut mesh = EditMesh::from_mesh_data(&read_mesh(&input)?)?;
    let height = mesh.add_vertex_property("height", 0.0)?;
    for v in mesh.vertices().collect::<Vec<_>>() {
        let z = mesh.position(v).z;
        mesh.set(height, v, z);
    }
    let count = |m: &EditMesh| m.edges().filter(|&e| needs_flip(m, e)).count();
    let before = count(&mesh);

    // Lawson's algorithm: flip a bad edge, then re-check the four edges around it.
    // A cap on the number of flips guards against cycles on curved surfaces.
    let mut queue: VecDeque<EdgeId> = mesh.edges().collect();
    let (mut flips, cap) = (0, 10 * mesh.n_edges());
    while let Some(e) = queue.pop_front() {
        if flips == cap || !needs_flip(&mesh, e) || !mesh.is_flip_ok(e) {
            continue;
        }
        mesh.flip_edge(e)?;
        flips += 1;
        for h in e.halfedges() {
            queue.push_back(mesh.next(h).edge());
            queue.push_back(mesh.prev(h).edge());
        }
    }
    let after = count(&mesh);
    mesh.check_integrity()?;

    // Compact (a no-op after flips alone, needed after collapses or deletions), then
    // write positions, faces and the carried scalar.
    mesh.garbage_collection();
    let attributes = VertexAttributes {
        scalars: vec![("height".to_owned(), mesh.values(height).to_vec())],
        colors: None,
    };
    write_ply(
        &output,
        &mesh.to_mesh_data(),
        &attributes,
        &WriteOptions::default(),
    )?;
    println!(
        "{flips} flips: {before} -> {after} edges with a negative cotangent weight; height -> {}",
        output.display()
    );
    Ok(())
}
