//! Wall-clock timing of the PLY reader, the half-edge build and the PLY writer on one
//! file, for `docs/performance/io.md` (a benchmark aid, not a test):
//!
//! ```sh
//! cargo run --release -p beltrami-io --example ply_timing -- s8.ply 7
//! ```
//!
//! Prints the median and the range of each step over the given number of runs
//! (default 5). The machine is shared: compare medians of alternating runs.
//! `ply_timing --icosphere LEVEL OUT.ply` writes a test file instead.

use std::path::PathBuf;
use std::time::Instant;

use beltrami_halfedge::HalfedgeMesh;
use beltrami_io::{WriteOptions, read_mesh, write_mesh};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1).peekable();
    if args.next_if(|a| a == "--icosphere").is_some() {
        let level = args
            .next()
            .ok_or("usage: ply_timing --icosphere LEVEL OUT")?;
        let out = PathBuf::from(
            args.next()
                .ok_or("usage: ply_timing --icosphere LEVEL OUT")?,
        );
        let mesh = beltrami_halfedge::primitives::icosphere(level.parse()?);
        write_mesh(&out, &mesh, &WriteOptions::default())?;
        return Ok(());
    }
    let path = PathBuf::from(args.next().ok_or("usage: ply_timing FILE.ply [RUNS]")?);
    let runs: usize = args.next().map_or(Ok(5), |s| s.parse())?;
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("out.ply");
    let (mut parse, mut build, mut write) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..runs {
        let t = Instant::now();
        let data = read_mesh(&path)?;
        parse.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let mesh = HalfedgeMesh::from_polygon_list(data.positions.len(), &data.faces)?;
        build.push(t.elapsed().as_secs_f64());
        std::hint::black_box(&mesh);
        let t = Instant::now();
        write_mesh(&out, &data, &WriteOptions::default())?;
        write.push(t.elapsed().as_secs_f64());
    }
    for (name, times) in [("parse", parse), ("build", build), ("write", write)] {
        let mut t = times;
        t.sort_by(f64::total_cmp);
        println!(
            "{name:6} median {:.3} s  (min {:.3}, max {:.3}, {} runs)",
            t[t.len() / 2],
            t[0],
            t[t.len() - 1],
            t.len()
        );
    }
    Ok(())
}
