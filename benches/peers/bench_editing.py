#!/usr/bin/env python3
"""Remeshing, decimation and hole filling: beltrami against the peers, same run, same files.

    pip install -r benches/peers/requirements-editing.txt
    bench_editing.py [remesh|decimate|fill-holes|all] [--surfaces LIST] [--reps N]
                     [--beltrami BIN] [--out DIR] [--openmesh-decimate BIN]

Surfaces (written by `beltrami generate` into DIR, default benches/peers/out/editing):
  sphere6    the paper's icosphere, level 6 (40 962 vertices)
  golfball   the dimpled ball (mm)
  block      the genus-3 part with sharp edges (mm): features matter
  scan       sphere6 with every vertex moved tangentially by up to 0.4 of an edge and
             put back on the sphere: the same surface, triangles as uneven as a scan's
             (skinny ones, valences 3 to 9), seeded
The level-8 sphere is left out by default: gpytoolbox and CGAL take minutes on it;
`--surfaces sphere8` adds it.

Tasks and peers (each skipped with a note when it does not install or fails):
  remesh      target edge length L = the input's mean edge length, 10 iterations
              (block: features above 45 degrees where the tool has the option)
              beltrami `remesh --edge-length L --iterations 10 [--features 45]`
              PyMeshLab meshing_isotropic_explicit_remeshing (targetlen, iterations,
                featuredeg), CGAL Polygon_mesh_processing.isotropic_remeshing,
              gpytoolbox remesh_botsch, MeshLib remesh
  decimate    to 10 % of the vertices
              beltrami `decimate --ratio 0.1 --no-distance`
              PyMeshLab meshing_decimation_quadric_edge_collapse (targetfacenum, normal
                check), fast-simplification, MeshLib decimateMesh, OpenMesh DecimaterT
                + ModQuadricT (openmesh_decimate.cpp, built here with g++)
  fill-holes  five holes cut into the surface (the faces within 4 mean edge lengths of
              five seeded vertices), filled and compared with the uncut surface
              beltrami `fill-holes`, PyMeshLab meshing_close_holes,
              CGAL triangulate_refine_and_fair_hole, MeshLib fillHole

Every output is measured by beltrami itself: `compare OUT REFERENCE --json`
(Hausdorff over the vertices and 10^6 area-uniform surface samples both ways; "area
RMS", the output's vertices' distances to the input weighted by their areas; and
"surface RMS", the RMS distance of the surface samples to the other surface, the larger
of the two ways (Metro's error: face interiors count, so vertices placed on the input
do not hide faces that cut below it) — all against the input, the uncut surface for
fill-holes) and `info OUT --quality --json` (smallest angle, share of
regular vertices, edge-length coefficient of variation); on the sphere surfaces (sphere*,
scan) also the exact Hausdorff distance to the unit sphere they approximate ("to the
sphere"), the surface the input's own triangles only approximate; on those and on the
golf ball the RMS distance of 10^6 area-uniform samples of the output to the true
surface ("true RMS": the unit sphere, or the analytic dimpled ball of crates/surfaces,
radially). Times are the algorithm alone
(peers: the call in this process, input already in memory; beltrami: the `seconds` of
its `--json` summary, which excludes reading, writing and the report's measurements —
`decimate` runs with `--no-distance`, as its output is measured here anyway), medians of
--reps runs.
Prints one Markdown table per task and surface, and writes them to DIR/results.md.
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
FEATURE_DEG = 45.0


# Surface samples per surface for `compare --samples` (Hausdorff and surface RMS).
SAMPLES = 1_000_000


def run(cmd, **kw):
    return subprocess.run([str(c) for c in cmd], check=True, capture_output=True, text=True, **kw)


def load(path):
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    m = ms.current_mesh()
    return m.vertex_matrix().astype(np.float64), m.face_matrix().astype(np.int64)


def save(path, v, f):
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=np.asarray(v, np.float64),
                               face_matrix=np.asarray(f, np.int32)))
    ms.save_current_mesh(str(path), binary=True, save_vertex_color=False,
                         save_vertex_normal=False, save_face_color=False) if str(path).endswith(
        ".ply") else ms.save_current_mesh(str(path))


def mean_edge(beltrami, path):
    return json.loads(run([beltrami, "info", path, "--json"]).stdout)["mean_edge_length"]


def on_sphere(name):
    """Whether surface `name` is (a triangulation of) the unit sphere."""
    return name.startswith("sphere") or name == "scan"


def make_surfaces(beltrami, out, names):
    paths = {}
    for name in names:
        path = out / f"{name}.ply"
        if name.startswith("sphere") or name == "scan":
            level = 6 if name in ("sphere6", "scan") else int(name[len("sphere"):])
            src = out / f"sphere{level}.ply"
            if not src.exists():
                run([beltrami, "generate", "sphere", src, "--level", level, "--force"])
            if name == "scan":
                v, f = load(src)
                h = mean_edge(beltrami, src)
                rng = np.random.default_rng(20261126)
                n = v / np.linalg.norm(v, axis=1, keepdims=True)
                step = rng.uniform(-1.0, 1.0, v.shape) * 0.4 * h
                step -= (step * n).sum(1, keepdims=True) * n
                v = v + step
                v /= np.linalg.norm(v, axis=1, keepdims=True)
                save(path, v, f)
            paths[name] = path
        else:
            if not path.exists():
                run([beltrami, "generate", name, path, "--force"])
            paths[name] = path
    return paths


def cut_holes(beltrami, path, out):
    """The surface with five holes: faces within 4 mean edge lengths of five seeded
    vertices removed (unreferenced vertices dropped)."""
    v, f = load(path)
    h = mean_edge(beltrami, path)
    rng = np.random.default_rng(7)
    centres = v[rng.choice(len(v), 5, replace=False)]
    centroid = v[f].mean(axis=1)
    keep = np.ones(len(f), bool)
    for c in centres:
        keep &= np.linalg.norm(centroid - c, axis=1) > 4.0 * h
    f = f[keep]
    used = np.unique(f)
    remap = -np.ones(len(v), np.int64)
    remap[used] = np.arange(len(used))
    holed = out / f"{path.stem}-holes.ply"
    save(holed, v[used], remap[f])
    return holed


def measure(beltrami, output, reference):
    """beltrami's measures of `output` against `reference`. An output that beltrami
    does not read as a valid mesh (e.g. a non-manifold edge) is measured after
    `--repair`, and the first line of the refusal is returned as `defect`."""
    defect, repair = None, []
    try:
        c = json.loads(run([beltrami, "compare", output, reference, "--json",
                            "--samples", str(SAMPLES)]).stdout)
    except subprocess.CalledProcessError as e:
        defect = (e.stderr or "").strip().splitlines()[0] if e.stderr else str(e)
        repair = ["--repair"]
        c = json.loads(run([beltrami, "compare", output, reference, "--json",
                            "--samples", str(SAMPLES), *repair]).stdout)
    q = json.loads(run([beltrami, "info", output, "--json", "--quality", *repair]).stdout)
    quality = q.get("quality") or {}
    return {
        "defect": defect,
        "vertices": q["vertices"],
        "hausdorff": c["hausdorff"],
        "area_rms": c["area_rms"],
        "surface_rms": c["surface_rms"]["symmetric"],
        "min_angle": quality.get("min_angle_degrees"),
        "regular": quality.get("regular_share"),
        "cv": quality.get("edge_length_cv"),
        "boundary_loops": q["boundary_loops"],
    }


def sphere_distance(path):
    """The Hausdorff distance between the mesh at `path` and the unit sphere it
    approximates (sphere* and scan are unit spheres), exactly: a flat triangle's
    farthest points outside the sphere are its vertices (|x| is convex), its deepest point
    is its closest point to the centre; with the triangles near the sphere, the sphere's
    farthest point from the mesh lies over one of those deepest points."""
    import trimesh

    mesh = trimesh.load(str(path), process=False)
    v, f = np.asarray(mesh.vertices, np.float64), np.asarray(mesh.faces)
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    h = (a * n).sum(1)
    p = h[:, None] * n  # the centre's projection onto each triangle's plane
    inside = np.ones(len(f), bool)
    for x, y in ((a, b), (b, c), (c, a)):
        inside &= (np.cross(y - x, p - x) * n).sum(1) >= 0

    def segment(x, y):
        d = y - x
        t = np.clip(-(x * d).sum(1) / np.maximum((d * d).sum(1), 1e-300), 0.0, 1.0)
        return np.linalg.norm(x + t[:, None] * d, axis=1)

    nearest = np.where(inside, np.abs(h),
                       np.minimum(np.minimum(segment(a, b), segment(b, c)), segment(c, a)))
    outside = np.linalg.norm(v, axis=1).max() - 1.0
    return float(max(outside, (1.0 - nearest).max(), 0.0))


def surface_samples(path, samples=1_000_000, seed=7):
    """`samples` points spread uniformly by area over the mesh at `path` (a fixed
    seed)."""
    import trimesh

    mesh = trimesh.load(str(path), process=False)
    v, f = np.asarray(mesh.vertices, np.float64), np.asarray(mesh.faces)
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    rng = np.random.default_rng(seed)
    face = rng.choice(len(f), samples, p=area / area.sum())
    r1, r2 = np.sqrt(rng.random(samples)), rng.random(samples)
    return (a[face] * (1 - r1)[:, None] + b[face] * (r1 * (1 - r2))[:, None]
            + c[face] * (r1 * r2)[:, None])


def sphere_rms(path):
    """The RMS distance of 10^6 points spread uniformly by area over the mesh at `path`
    to the unit sphere it approximates, `| |p| - 1 |`: the surface RMS against the true
    surface rather than against the input's triangles."""
    p = surface_samples(path)
    return float(np.sqrt(np.mean((np.linalg.norm(p, axis=1) - 1.0) ** 2)))


# The golf ball of `beltrami generate golfball` (crates/surfaces, GolfBallParams::default):
# diameter, dimple chord diameter and depth in mm, dimple layout frequency.
GOLF = dict(diameter=42.67, dimple_diameter=3.8, dimple_depth=0.18, dimple_frequency=6)


def golf_axes(beltrami, out):
    """The unit dimple axes of the golf ball: the vertices of the class-I geodesic sphere
    of frequency 6 on beltrami's icosahedron (`generate sphere --level 0`), as
    `geodesic_sphere` in crates/surfaces builds them."""
    import trimesh

    path = Path(out) / "icosahedron.ply"
    run([beltrami, "generate", "sphere", str(path), "--level", "0", "--force"])
    ico = trimesh.load(str(path), process=False)
    corners, faces = np.asarray(ico.vertices, np.float64), np.asarray(ico.faces)
    n = GOLF["dimple_frequency"]
    points = {}
    for a, b, c in corners[faces]:
        for j in range(n + 1):
            for i in range(n + 1 - j):
                p = a + (b - a) * (i / n) + (c - a) * (j / n)
                p /= np.linalg.norm(p)
                points.setdefault(tuple(np.round(p, 9)), p)
    axes = np.array(list(points.values()))
    assert len(axes) == 10 * n * n + 2, len(axes)
    return axes


def golf_radius(u, axes):
    """The golf ball's surface distance from its centre along unit directions `u`
    (`GolfBallParams::radial_distance`): the ball radius, or nearer where a dimple's cap
    sphere cuts in."""
    r = GOLF["diameter"] / 2
    d, depth = GOLF["dimple_diameter"], GOLF["dimple_depth"]
    rho = (d * d / 4 + depth * depth) / (2 * depth)
    centre = r + rho - depth
    cos_rim = np.clip((r * r + centre * centre - rho * rho) / (2 * r * centre), -1, 1)
    best = np.full(len(u), r)
    for lo in range(0, len(u), 50_000):
        cosines = u[lo:lo + 50_000] @ axes.T
        uc = cosines * centre
        disc = uc * uc - centre * centre + rho * rho
        cand = np.where((cosines >= cos_rim) & (disc >= 0),
                        uc - np.sqrt(np.maximum(disc, 0)), np.inf)
        best[lo:lo + 50_000] = np.minimum(r, cand.min(axis=1))
    return best


def golf_rms(path, axes):
    """The RMS radial distance of 10^6 area-uniform points of the mesh at `path` to the
    true golf ball, `| |p| - R(p/|p|) |` (at least the distance to the surface, and
    within 2 % of it: the dimples' walls lean at most 11° from the sphere)."""
    p = surface_samples(path)
    length = np.linalg.norm(p, axis=1)
    return float(np.sqrt(np.mean((length - golf_radius(p / length[:, None], axes)) ** 2)))


def timed(reps, call):
    times, result = [], None
    for _ in range(reps):
        t0 = time.perf_counter()
        result = call()
        times.append(time.perf_counter() - t0)
    return times, result


# ---- beltrami ---------------------------------------------------------------------

def beltrami_cmd(beltrami, reps, args, out_path):
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        summary = json.loads(run([beltrami, *args, "--json", "--force"]).stdout)
        wall = time.perf_counter() - t0
        times.append(summary.get("seconds", wall))
    return times, out_path


# ---- peers ------------------------------------------------------------------------

def pymeshlab_filter(path, out_path, reps, name, **params):
    import pymeshlab

    times = []
    for _ in range(reps):
        ms = pymeshlab.MeshSet()
        ms.load_new_mesh(str(path))
        t0 = time.perf_counter()
        ms.apply_filter(name, **params)
        times.append(time.perf_counter() - t0)
    ms.save_current_mesh(str(out_path))
    return times, out_path


def cgal_polyhedron(path, tmp):
    from CGAL.CGAL_Polyhedron_3 import Polyhedron_3

    off = Path(tmp) / (path.stem + ".off")
    v, f = load(path)
    with open(off, "w") as fh:
        fh.write(f"OFF\n{len(v)} {len(f)} 0\n")
        np.savetxt(fh, v, fmt="%.17g")
        np.savetxt(fh, np.hstack([np.full((len(f), 1), 3), f]), fmt="%d")
    return Polyhedron_3(str(off))


def cgal_remesh(path, out_path, reps, length):
    from CGAL import CGAL_Polygon_mesh_processing as pmp

    times = []
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(reps):
            p = cgal_polyhedron(path, tmp)
            faces = list(p.facets())
            t0 = time.perf_counter()
            pmp.isotropic_remeshing(faces, length, p, 10)
            times.append(time.perf_counter() - t0)
        p.write_to_file(str(out_path.with_suffix(".off")))
    return times, out_path.with_suffix(".off")


def cgal_fill(path, out_path, reps):
    from CGAL import CGAL_Polygon_mesh_processing as pmp

    times = []
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(reps):
            p = cgal_polyhedron(path, tmp)
            t0 = time.perf_counter()
            seen = True
            while seen:  # fill one hole at a time: each fill changes the halfedges
                seen = False
                for h in p.halfedges():
                    if h.is_border():
                        faces, vertices = [], []
                        pmp.triangulate_refine_and_fair_hole(p, h, faces, vertices)
                        seen = True
                        break
            times.append(time.perf_counter() - t0)
        p.write_to_file(str(out_path.with_suffix(".off")))
    return times, out_path.with_suffix(".off")


def gpytoolbox_remesh(path, out_path, reps, length):
    import gpytoolbox as gp

    v, f = load(path)
    times, (u, g) = timed(reps, lambda: gp.remesh_botsch(v, f.astype(np.int32), i=10, h=length))
    save(out_path, u, g)
    return times, out_path


def fast_simplification(path, out_path, reps, ratio):
    import fast_simplification as fs

    v, f = load(path)
    times, (u, g) = timed(reps, lambda: fs.simplify(v, f, target_reduction=1.0 - ratio))
    save(out_path, u, g)
    return times, out_path


def meshlib_mesh(path):
    import meshlib.mrmeshpy as mr

    return mr.loadMesh(str(path))


def meshlib_decimate(path, out_path, reps, ratio):
    import meshlib.mrmeshpy as mr

    times = []
    for _ in range(reps):
        mesh = meshlib_mesh(path)
        settings = mr.DecimateSettings()
        n = mesh.topology.numValidVerts()
        settings.maxDeletedVertices = int(n - round(ratio * n))
        settings.maxError = float("inf")
        t0 = time.perf_counter()
        mr.decimateMesh(mesh, settings)
        times.append(time.perf_counter() - t0)
    mesh.pack()
    mr.saveMesh(mesh, str(out_path))
    return times, out_path


def meshlib_remesh(path, out_path, reps, length):
    import meshlib.mrmeshpy as mr

    times = []
    for _ in range(reps):
        mesh = meshlib_mesh(path)
        settings = mr.RemeshSettings()
        settings.targetEdgeLen = float(length)
        t0 = time.perf_counter()
        mr.remesh(mesh, settings)
        times.append(time.perf_counter() - t0)
    mesh.pack()
    mr.saveMesh(mesh, str(out_path))
    return times, out_path


def meshlib_fill(path, out_path, reps):
    import meshlib.mrmeshpy as mr

    times = []
    for _ in range(reps):
        mesh = meshlib_mesh(path)
        t0 = time.perf_counter()
        for e in mesh.topology.findHoleRepresentiveEdges():
            mr.fillHole(mesh, e, mr.FillHoleParams())
        times.append(time.perf_counter() - t0)
    mesh.pack()
    mr.saveMesh(mesh, str(out_path))
    return times, out_path


def openmesh_decimate(binary, path, out_path, reps, ratio):
    if binary is None:
        binary = Path(tempfile.mkdtemp()) / "openmesh_decimate"
        run(["g++", "-O2", "-DNDEBUG", "-std=c++17", "-o", binary,
             HERE / "openmesh_decimate.cpp", "-lOpenMeshCore", "-lOpenMeshTools"])
    out = json.loads(run([binary, path, out_path, ratio, reps]).stdout)
    return out["seconds"], out_path


# ---- the tasks --------------------------------------------------------------------

def tasks(args, surfaces, out):
    for task in (["remesh", "decimate", "fill-holes"] if args.task == "all" else [args.task]):
        for name, path in surfaces.items():
            length = mean_edge(args.beltrami, path)
            o = lambda tool: out / f"{task}-{name}-{tool}.ply"
            reference = path
            if task == "remesh":
                extra = ["--features", str(FEATURE_DEG)] if name == "block" else []
                feature = FEATURE_DEG if name == "block" else 0.0
                runs = [
                    ("beltrami", lambda: beltrami_cmd(
                        args.beltrami, args.reps,
                        ["remesh", path, o("beltrami"), "--edge-length", repr(length),
                         "--iterations", "10", *extra], o("beltrami"))),
                    ("PyMeshLab", lambda: pymeshlab_filter(
                        path, o("pymeshlab"), args.reps, "meshing_isotropic_explicit_remeshing",
                        targetlen=__import__("pymeshlab").PureValue(length), iterations=10,
                        featuredeg=feature or 180.0)),
                    ("CGAL", lambda: cgal_remesh(path, o("cgal"), args.reps, length)),
                    ("gpytoolbox", lambda: gpytoolbox_remesh(path, o("gpytoolbox"), args.reps, length)),
                    ("MeshLib", lambda: meshlib_remesh(path, o("meshlib"), args.reps, length)),
                ]
            elif task == "decimate":
                ratio = 0.1
                _, f = load(path)
                runs = [
                    ("beltrami", lambda: beltrami_cmd(
                        args.beltrami, args.reps,
                        ["decimate", path, o("beltrami"), "--ratio", str(ratio),
                         "--no-distance"], o("beltrami"))),
                    ("PyMeshLab", lambda: pymeshlab_filter(
                        path, o("pymeshlab"), args.reps, "meshing_decimation_quadric_edge_collapse",
                        targetfacenum=int(round(ratio * len(f))), preservenormal=True,
                        preserveboundary=True, planarquadric=False)),
                    ("fast-simplification", lambda: fast_simplification(
                        path, o("fast"), args.reps, ratio)),
                    ("MeshLib", lambda: meshlib_decimate(path, o("meshlib"), args.reps, ratio)),
                    ("OpenMesh", lambda: openmesh_decimate(
                        args.openmesh_decimate, path, o("openmesh"), args.reps, ratio)),
                ]
            else:
                holed = cut_holes(args.beltrami, path, out)
                runs = [
                    ("beltrami", lambda: beltrami_cmd(
                        args.beltrami, args.reps,
                        ["fill-holes", holed, o("beltrami"), "--all"], o("beltrami"))),
                    ("PyMeshLab", lambda: pymeshlab_filter(
                        holed, o("pymeshlab"), args.reps, "meshing_close_holes",
                        maxholesize=100000, refinehole=True)),
                    ("CGAL", lambda: cgal_fill(holed, o("cgal"), args.reps)),
                    ("MeshLib", lambda: meshlib_fill(holed, o("meshlib"), args.reps)),
                ]
            yield task, name, reference, runs


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("task", nargs="?", default="all",
                    choices=["remesh", "decimate", "fill-holes", "all"])
    ap.add_argument("--surfaces", default="sphere6,golfball,block,scan")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--beltrami", default=str(ROOT / "target/release/beltrami"))
    ap.add_argument("--out", default=str(HERE / "out/editing"))
    ap.add_argument("--openmesh-decimate")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    surfaces = make_surfaces(args.beltrami, out, args.surfaces.split(","))
    axes = golf_axes(args.beltrami, out) if "golfball" in surfaces else None
    if axes is not None:
        # The generated golf ball's vertices lie on the true surface: a check of the port.
        v = load(surfaces["golfball"])[0]
        length = np.linalg.norm(v, axis=1)
        off = np.abs(length - golf_radius(v / length[:, None], axes)).max()
        assert off < 1e-9, f"the golf ball's vertices are {off} off its true surface"
    lines = []
    for task, name, reference, runs in tasks(args, surfaces, out):
        lines += [f"\n### {task}: {name}\n",
                  "| tool | median s | vertices | Hausdorff | area RMS | surface RMS | to the sphere | true RMS | min angle ° | regular % | edge CV | boundary loops |",
                  "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        defects = []
        for tool, call in runs:
            try:
                times, output = call()
                m = measure(args.beltrami, output, reference)
                m["sphere"] = sphere_distance(output) if on_sphere(name) else None
                m["sphere_rms"] = (sphere_rms(output) if on_sphere(name)
                                   else golf_rms(output, axes) if name == "golfball" else None)
            except Exception as e:  # a peer that is missing or fails is reported, not fatal
                print(f"skipped {tool} on {task} {name}: {e}", file=sys.stderr)
                continue
            fmt = lambda x, spec: "-" if x is None else format(x, spec)
            label = tool
            if m["defect"] is not None:
                label = f"{tool} (repaired)"
                defects.append(f"- {tool}: its output is not a valid mesh "
                               f"(`{m['defect']}`); measured after `--repair`.")
            lines.append(
                f"| {label} | {statistics.median(times):.3f} | {m['vertices']} | "
                f"{m['hausdorff']:.3g} | {m['area_rms']:.3g} | {m['surface_rms']:.3g} | "
                f"{fmt(m['sphere'], '.3g')} | {fmt(m['sphere_rms'], '.3g')} | "
                f"{fmt(m['min_angle'], '.1f')} | "
                f"{fmt(None if m['regular'] is None else 100 * m['regular'], '.1f')} | "
                f"{fmt(m['cv'], '.3f')} | {m['boundary_loops']} |")
            print(lines[-1], flush=True)
        if defects:
            lines += [""] + defects
    text = "\n".join(lines) + "\n"
    (out / "results.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
