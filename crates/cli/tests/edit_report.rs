//! The mesh quality before and after that `remesh`, `decimate` and `fill-holes` report:
//! the printed table, `--json` and `--report FILE.json` carry the same figures as
//! `info --quality --json` of the input and of the written result, and a `--report`
//! that cannot be written leaves no mesh behind.

mod common;

use std::fs;
use std::path::Path;

use common::{beltrami, error_line, json, s};
use serde_json::Value;

/// `info MESH --quality --json`'s quality object.
fn quality_of(mesh: &Path) -> Value {
    json(&["info", s(mesh), "--quality", "--json"])["quality"].clone()
}

/// `a` and `b` hold the same keys and counts, and numbers equal to 1e-12 relative: the
/// result's figures are summed in the order of the mesh in memory, `info`'s in the
/// order of the mesh rebuilt from the written file.
fn assert_same(a: &Value, b: &Value, what: &str) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            assert_eq!(
                x.keys().collect::<Vec<_>>(),
                y.keys().collect::<Vec<_>>(),
                "{what}"
            );
            for (k, v) in x {
                assert_same(v, &y[k], &format!("{what}.{k}"));
            }
        }
        (Value::Array(x), Value::Array(y)) => {
            assert_eq!(x.len(), y.len(), "{what}");
            for (i, (v, w)) in x.iter().zip(y).enumerate() {
                assert_same(v, w, &format!("{what}[{i}]"));
            }
        }
        (Value::Number(x), Value::Number(y)) if x.is_f64() || y.is_f64() => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            assert!(
                (x - y).abs() <= 1e-12 * x.abs().max(y.abs()),
                "{what}: {x} against {y}"
            );
        }
        _ => assert_eq!(a, b, "{what}"),
    }
}

/// A noisy sphere with one hole cut into it, so that every command has work to do.
fn input(dir: &Path) -> std::path::PathBuf {
    let noisy = dir.join("noisy.ply");
    let o = beltrami(&[
        "generate",
        "sphere",
        s(&noisy),
        "--level",
        "3",
        "--noise",
        "0.1",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // Cut the faces around vertex 0 by rewriting the file without them.
    let mesh = beltrami_io::read_mesh(&noisy).unwrap();
    let data = beltrami_io::MeshData {
        faces: mesh.faces.iter().filter(|f| !f.contains(&0)).collect(),
        positions: mesh.positions,
    };
    let holed = dir.join("holed.ply");
    beltrami_io::write_mesh(&holed, &data, &beltrami_io::WriteOptions::default()).unwrap();
    holed
}

const COMMANDS: [(&str, &[&str]); 3] = [
    ("remesh", &["--edge-length-relative", "1.5"]),
    ("decimate", &["--ratio", "0.5"]),
    ("fill-holes", &["--all"]),
];

#[test]
fn json_and_report_carry_the_quality_of_input_and_result() {
    let dir = tempfile::tempdir().unwrap();
    let src = input(dir.path());
    let before = quality_of(&src);
    for (command, extra) in COMMANDS {
        let out = dir.path().join(format!("{command}.ply"));
        let report = dir.path().join(format!("{command}.json"));
        let mut args = vec![command, s(&src), s(&out)];
        args.extend_from_slice(extra);
        args.extend(["--json", "--report", s(&report)]);
        let printed = json(&args);
        let after = quality_of(&out);
        assert_same(&printed["quality_before"], &before, command);
        assert_same(&printed["quality_after"], &after, command);
        // The edit changed the mesh, so the two differ.
        assert_ne!(before, after, "{command}");
        let mut written: Value = serde_json::from_slice(&fs::read(&report).unwrap()).unwrap();
        let mut printed = printed;
        // Identical apart from the wall-clock time of each run.
        written["seconds"] = Value::Null;
        printed["seconds"] = Value::Null;
        assert_eq!(written, printed, "{command}");
    }
}

#[test]
fn the_sentence_is_followed_by_a_before_after_table() {
    let dir = tempfile::tempdir().unwrap();
    let src = input(dir.path());
    let before = quality_of(&src);
    for (command, extra) in COMMANDS {
        let out = dir.path().join(format!("{command}.ply"));
        let mut args = vec![command, s(&src), s(&out)];
        args.extend_from_slice(extra);
        let o = beltrami(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = String::from_utf8(o.stdout).unwrap();
        let after = quality_of(&out);
        let lines: Vec<&str> = text.lines().collect();
        let header = lines
            .iter()
            .position(|l| {
                l.split_whitespace().collect::<Vec<_>>() == ["quality", "before", "after"]
            })
            .unwrap_or_else(|| panic!("{command}: no quality table in\n{text}"));
        let row = |name: &str| -> Vec<String> {
            let line = lines[header..]
                .iter()
                .find(|l| l.starts_with(name))
                .unwrap_or_else(|| panic!("{command}: no row {name} in\n{text}"));
            line[name.len()..]
                .split_whitespace()
                .map(str::to_string)
                .collect()
        };
        // The table prints 6 significant digits of the JSON's numbers.
        let close = |cell: &str, value: &Value, scale: f64| {
            let cell: f64 = cell.trim_end_matches(['°', '%']).parse().unwrap();
            let value = value.as_f64().unwrap() * scale;
            assert!(
                (cell - value).abs() <= 1e-5 * value.abs().max(1e-300),
                "{command}: table {cell} against {value}"
            );
        };
        let angle = row("smallest angle");
        close(&angle[0], &before["min_angle_degrees"], 1.0);
        close(&angle[1], &after["min_angle_degrees"], 1.0);
        let cv = row("edge length CV");
        close(&cv[0], &before["edge_length_cv"], 1.0);
        close(&cv[1], &after["edge_length_cv"], 1.0);
        let regular = row("regular vertices");
        close(&regular[0], &before["regular_share"], 100.0);
        close(&regular[1], &after["regular_share"], 100.0);
    }
}

#[test]
fn a_report_that_cannot_be_written_leaves_no_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let src = input(dir.path());
    for (command, extra) in COMMANDS {
        let out = dir.path().join(format!("{command}.ply"));
        // The report in a directory that does not exist: refused before any work.
        let missing = dir.path().join("missing").join("r.json");
        let mut args = vec![command, s(&src), s(&out)];
        args.extend_from_slice(extra);
        args.extend(["--report", s(&missing)]);
        let o = beltrami(&args);
        assert_eq!(o.status.code(), Some(1), "{command}");
        let line = error_line(&o, dir.path());
        assert!(
            line.contains("--report") || line.contains("r.json"),
            "{command}: {line}"
        );
        assert!(
            !out.exists(),
            "{command}: wrote the mesh without its report"
        );
        // The report naming the output mesh itself: a usage error, nothing written.
        let mut args = vec![command, s(&src), s(&out)];
        args.extend_from_slice(extra);
        args.extend(["--report", s(&out)]);
        let o = beltrami(&args);
        assert_eq!(o.status.code(), Some(2), "{command}");
        assert!(!out.exists(), "{command}");
    }
}

/// An OUTPUT whose extension names no format is refused before the input is read (the
/// input here does not exist, and the error names the output), so a long run is not
/// spent on a result that cannot be written; `smooth` and `subdivide` check the same.
#[test]
fn an_output_of_no_known_format_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no-such-input.ply");
    let out = dir.path().join("result.xyz");
    let commands: [(&str, &[&str]); 5] = [
        COMMANDS[0],
        COMMANDS[1],
        COMMANDS[2],
        ("smooth", &[]),
        ("subdivide", &[]),
    ];
    for (command, extra) in commands {
        let mut args = vec![command, s(&missing), s(&out)];
        args.extend_from_slice(extra);
        let o = beltrami(&args);
        // A bad OUTPUT name is a usage error, as a height map's name is (exit 2), and
        // the message lists what the command writes, not the height maps it reads.
        assert_eq!(o.status.code(), Some(2), "{command}");
        let line = error_line(&o, dir.path());
        assert!(
            line.contains("result.xyz") && line.contains("unsupported file extension"),
            "{command}: {line}"
        );
        assert!(
            line.contains(".ply, .stl, .obj or .off") && !line.contains(".x3p"),
            "{command}: {line}"
        );
        assert!(!out.exists(), "{command}");
    }
}

/// The three commands on a mesh far from unit size (the holed sphere times 2^±400):
/// each runs, and its figures are the unit-size run's scaled, lengths by 2^k, areas by
/// 2^2k, angles and shares unchanged (before the runs' own scaling decimation collapsed
/// nothing at 2^-400 and failed at 2^400, remeshing failed at both, and the angles of
/// the quality table were blank). The output meshes are the unit-size ones times 2^k.
#[test]
fn far_from_unit_size_the_figures_are_the_unit_sizes_scaled() {
    use beltrami_io::read_mesh;
    let dir = tempfile::tempdir().unwrap();
    let unit = dir.path().join("holed.ply");
    let o = beltrami(&[
        "generate",
        "sphere",
        s(&unit),
        "--level",
        "4",
        "--holes",
        "3",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // The reference at 0.75 of the unit sphere's size, so that the runs far from unit
    // size, brought to [1, 2), are computed at another size than the reference's.
    let mut mesh = read_mesh(&unit).unwrap();
    for p in &mut mesh.positions {
        *p *= 0.75;
    }
    let unit = common::write(
        dir.path(),
        "reference.ply",
        mesh.positions.clone(),
        mesh.faces.clone(),
    );
    // Each command, its options, and the JSON pointers of its lengths and its areas.
    type Run<'a> = (&'a str, &'a [&'a str], &'a [&'a str], &'a [&'a str]);
    let runs: [Run; 3] = [
        (
            "decimate",
            &["--ratio", "0.3"],
            &["/hausdorff", "/fit_rms_after", "/max_quadric_error"],
            &[],
        ),
        (
            "remesh",
            &["--iterations", "3"],
            &["/target_edge_length", "/mean_edge_length", "/hausdorff"],
            &[],
        ),
        (
            "fill-holes",
            &["--all"],
            &["/filled/0/perimeter", "/filled/1/perimeter"],
            &["/filled/0/area", "/filled/1/area"],
        ),
    ];
    for k in [-400, 400] {
        let scale = 2f64.powi(k);
        let positions = mesh.positions.iter().map(|&p| p * scale).collect();
        let far = common::write(
            dir.path(),
            &format!("far{k}.ply"),
            positions,
            mesh.faces.clone(),
        );
        for (command, options, lengths, areas) in runs {
            let run = |input: &Path, out: &str| {
                let out = dir.path().join(out);
                let mut args = vec![command, s(input), s(&out), "--json", "--force"];
                args.extend_from_slice(options);
                (json(&args), read_mesh(&out).unwrap())
            };
            let (a, mesh_a) = run(&unit, "unit.ply");
            let (b, mesh_b) = run(&far, "far.ply");
            let what = format!("{command} at 2^{k}");
            let at = |v: &Value, key: &str| {
                common::f(v.pointer(key).unwrap_or_else(|| panic!("{what}: {key}")))
            };
            for key in lengths {
                assert_eq!(at(&b, key), at(&a, key) * scale, "{what}: {key}");
            }
            for key in areas {
                assert_eq!(at(&b, key), at(&a, key) * scale * scale, "{what}: {key}");
            }
            for key in ["quality_before", "quality_after"] {
                for angle in [
                    "min_angle_degrees",
                    "mean_min_angle_degrees",
                    "max_aspect_ratio",
                ] {
                    assert!(b[key][angle].is_f64(), "{what}: {key}.{angle}: {}", b[key]);
                    assert_eq!(b[key][angle], a[key][angle], "{what}: {key}.{angle}");
                }
            }
            assert_eq!(mesh_b.faces, mesh_a.faces, "{what}");
            let expected: Vec<_> = mesh_a.positions.iter().map(|&p| p * scale).collect();
            assert_eq!(mesh_b.positions, expected, "{what}");
        }
        // The loop left open is told to span the same share of the surface (its vector
        // area over the surface's, which underflowed to 0 % at 2^-400).
        let share = |input: &Path| {
            let out = dir.path().join("open.ply");
            let o = beltrami(&["fill-holes", s(input), s(&out), "--force"]);
            let text = String::from_utf8(o.stdout).unwrap();
            text.split("spans only ")
                .nth(1)
                .and_then(|t| t.split('%').next())
                .unwrap_or_else(|| panic!("{text}"))
                .to_owned()
        };
        let (a, b) = (share(&unit), share(&far));
        assert!(a.parse::<f64>().unwrap() > 0.0, "{a}");
        assert_eq!(b, a, "2^{k}");
    }
}
