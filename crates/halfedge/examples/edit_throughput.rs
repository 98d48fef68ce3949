//! Edit throughput of [`EditMesh`]: a million random flips, edge splits and halfedge
//! collapses on an icosphere (level 8, 655 362 vertices, by default), each checked with
//! its `is_*_ok` first, then one garbage collection; ops per second and bytes per
//! element. For docs/performance.md.
//!
//! ```sh
//! cargo run --release -p beltrami-halfedge --example edit_throughput -- [LEVEL] [OPS]
//! ```

use std::time::Instant;

use beltrami_halfedge::{EdgeId, EditMesh, HalfedgeId, primitives};

/// SplitMix64: a small, seeded, portable generator (this example has no dependencies).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let level: u32 = args.next().map_or(Ok(8), |a| a.parse())?;
    let ops: usize = args.next().map_or(Ok(1_000_000), |a| a.parse())?;
    let sphere = primitives::icosphere(level);
    let mut mesh = EditMesh::from_mesh_data(&sphere)?;
    let (v0, e0, f0) = (mesh.n_vertices(), mesh.n_edges(), mesh.n_faces());
    let mut rng = Rng(1);
    let (mut done, mut refused) = ([0usize; 3], [0usize; 3]);
    let start = Instant::now();
    for _ in 0..ops {
        // A random live edge (deleted slots are skipped).
        let e = loop {
            let e = EdgeId::new(rng.below(mesh.edge_capacity()) as u32);
            if mesh.is_live_edge(e) {
                break e;
            }
        };
        let kind = rng.below(3);
        let ok = match kind {
            0 => mesh.is_flip_ok(e) && mesh.flip_edge(e).is_ok(),
            1 => {
                let [a, b] = mesh.edge_vertices(e);
                let mid = (mesh.position(a) + mesh.position(b)) * 0.5;
                mesh.is_split_edge_ok(e) && mesh.split_edge(e, mid).is_ok()
            }
            _ => {
                let h: HalfedgeId = e.halfedge(rng.below(2) as u32);
                mesh.is_collapse_ok(h) && mesh.collapse_edge(h).is_ok()
            }
        };
        if ok {
            done[kind] += 1;
        } else {
            refused[kind] += 1;
        }
    }
    let edit_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    mesh.garbage_collection();
    let gc_seconds = start.elapsed().as_secs_f64();
    mesh.check_integrity()?;
    let per_vertex = size_of::<u32>() + size_of::<beltrami_halfedge::DVec3>() + size_of::<bool>();
    let per_edge = 2 * 4 * size_of::<u32>() + size_of::<bool>();
    let per_face = size_of::<u32>() + size_of::<bool>();
    println!(
        "icosphere level {level}: {v0} vertices, {e0} edges, {f0} faces -> {} vertices, {} edges, {} faces",
        mesh.n_vertices(),
        mesh.n_edges(),
        mesh.n_faces()
    );
    println!(
        "{ops} random operations in {edit_seconds:.3} s: {:.2} million ops/s (checks included); \
         done flip {} split {} collapse {}, refused flip {} split {} collapse {}",
        ops as f64 / edit_seconds / 1e6,
        done[0],
        done[1],
        done[2],
        refused[0],
        refused[1],
        refused[2]
    );
    let max_valence = mesh.vertices().map(|v| mesh.valence(v)).max().unwrap_or(0);
    println!("garbage collection: {gc_seconds:.3} s; largest valence afterwards {max_valence}");
    println!(
        "bytes per element: vertex {per_vertex} (outgoing halfedge, position, deletion mark), \
         edge {per_edge} (two halfedges of target, next, prev, face; deletion mark), face {per_face}"
    );
    Ok(())
}
