#!/usr/bin/env python3
"""Measures beltrami against the performance targets of docs/performance.md, in one run.

    benches/targets.py                 # build the release binary, measure, print the table
    REPS=5 benches/targets.py          # more repetitions (default 3; the table gives medians)
    LEVEL10=1 benches/targets.py       # also the 10.5M-vertex icosphere (about 4 min more)
    LEVEL11=1 benches/targets.py       # also the 41.9M-vertex icosphere, 10 iterations (needs
                                       # about 6 GB of disk and the machine's memory; minutes)
    BELTRAMI=/path/to/beltrami benches/targets.py

Everything runs through the `beltrami` binary, timed from its own `--report`/`--json`
figures (so file reading and writing are separate from smoothing), and peak memory from
the kernel's maximum resident set size of the child process. Meshes are written by
`beltrami generate` into `benches/targets-out/` (ignored by git): the noisy icosphere of
level 8 (655 362 vertices; the same file as the peer comparison's `sphere8`), the same
mesh with its vertices shuffled, and the paper's four surfaces. The results go to
stdout as Markdown and to `benches/targets-out/results.md` and `results.json`.

Needs only Python 3 (standard library) and a Rust toolchain. Never asserts a time: the
figures are for reading, beside the machine's load, which is recorded.
"""

import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "benches" / "targets-out"
REPS = int(os.environ.get("REPS", "3"))
ITER = 100


def die(msg):
    print(f"error: {msg}", file=sys.stderr)
    sys.exit(1)


def binary():
    if "BELTRAMI" in os.environ:
        return os.environ["BELTRAMI"]
    r = subprocess.run(["cargo", "build", "--release", "-q", "-p", "beltrami-cli"], cwd=ROOT)
    if r.returncode != 0:
        die("cargo build --release -p beltrami-cli failed")
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return str(target / "release" / "beltrami")


BIN = binary()


def isolated(args, json_out=None, may_fail=False):
    """Runs one case in a fresh Python child so that its peak RSS is its own.

    With `may_fail`, a failing command gives `(wall, rss, None, stderr)` instead of ending
    the run (for the cases that may not fit the machine)."""
    code = (
        "import json,resource,subprocess,sys,time;"
        "t=time.perf_counter();r=subprocess.run(sys.argv[1:],capture_output=True,text=True);"
        "w=time.perf_counter()-t;"
        "print(json.dumps({'rc':r.returncode,'wall':w,'stdout':r.stdout,'stderr':r.stderr,"
        "'maxrss_kb':resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss}))"
    )
    r = subprocess.run([sys.executable, "-c", code, BIN, *args], capture_output=True, text=True)
    rec = json.loads(r.stdout)
    if rec["rc"] != 0:
        if may_fail:
            return rec["wall"], rec["maxrss_kb"] * 1024, None, rec["stderr"].strip()
        die(f"beltrami {' '.join(args)}: {rec['stderr'].strip()}")
    data = None
    if json_out == "-":
        data = json.loads(rec["stdout"])
    elif json_out is not None:
        data = json.loads(Path(json_out).read_text())
    if may_fail:
        return rec["wall"], rec["maxrss_kb"] * 1024, data, None
    return rec["wall"], rec["maxrss_kb"] * 1024, data


def load():
    try:
        return os.getloadavg()[0]
    except OSError:
        return float("nan")


def mesh(name, surface, seed, extra=()):
    path = OUT / f"{name}.ply"
    clean = OUT / f"{name}_clean.ply"
    if not (path.exists() and clean.exists()):
        args = ["generate", surface, str(path), "--noise", "0.2", "--relative", "--seed", str(seed),
                "--clean", str(clean), *extra]
        isolated(args)
    return path, clean


def vertices(path):
    _, _, info = isolated(["info", str(path), "--json"], "-")
    return info["vertices"]


def median(xs):
    return statistics.median(xs) if xs else float("nan")


def smooth_case(path, n, weights, update, extra=(), reps=REPS):
    """ns per vertex-iteration (weights + updates), peak RSS per vertex and whole-process
    seconds, medians."""
    report = OUT / "report.json"
    ns, mem, seconds, walls = [], [], [], []
    for _ in range(reps):
        wall, rss, rep = isolated(
            ["smooth", str(path), str(OUT / "out.ply"), "--weights", weights, "--update", update,
             "--iterations", str(ITER), "--lambda", "0.8", "--boundary", "free",
             "--report", str(report), "--no-step-stats", "--force", *extra],
            str(report),
        )
        s = rep["seconds"]
        ns.append((s["weights"] + s["updates"]) / (n * ITER) * 1e9)
        mem.append(rss / n)
        seconds.append(s)
        walls.append(wall)
    return {"ns": median(ns), "range": [min(ns), max(ns)], "bytes_per_vertex": median(mem),
            "seconds": seconds, "wall": median(walls)}


def level11():
    """The level-11 icosphere (41.9M vertices): 10 cotangent iterations with the weights
    recomputed every iteration, whole process, once. The noisy mesh is written without
    its clean copy (2 GB less disk). A run the machine cannot hold is recorded with the
    command's own message, not ended."""
    path = OUT / "sphere11.ply"
    if not path.exists():
        isolated(["generate", "sphere", str(path), "--level", "11", "--noise", "0.2",
                  "--relative", "--seed", "111"])
    n = vertices(path)
    iterations = 10
    report = OUT / "report11.json"
    wall, rss, rep, err = isolated(
        ["smooth", str(path), str(OUT / "out11.ply"), "--weights", "cotangent", "--update",
         "every", "--iterations", str(iterations), "--lambda", "0.8", "--boundary", "free",
         "--report", str(report), "--no-step-stats", "--force"],
        str(report), may_fail=True)
    rec = {"vertices": n, "iterations": iterations, "wall": wall, "bytes_per_vertex": rss / n,
           "error": err}
    if rep is not None:
        s = rep["seconds"]
        rec["seconds"] = s
        rec["ns"] = (s["weights"] + s["updates"]) / (n * iterations) * 1e9
    return rec


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    version = subprocess.run([BIN, "--version"], capture_output=True, text=True).stdout.strip()
    start = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    loads = [load()]
    res = {"version": version, "date": start, "machine": platform.processor() or platform.machine(),
           "cpus": os.cpu_count(), "reps": REPS, "iterations": ITER}

    s8, s8c = mesh("sphere8", "sphere", 18, ["--level", "8"])
    sh, _ = mesh("sphere8_shuffled", "sphere", 18, ["--level", "8", "--shuffle", "1"])
    n8 = vertices(s8)

    rows = {}
    for weights in ("uniform", "distance", "cotangent"):
        for update in ("every", "once"):
            rows[(weights, update, "ordered")] = smooth_case(s8, n8, weights, update)
            loads.append(load())
            rows[(weights, update, "shuffled")] = smooth_case(sh, n8, weights, update)
            loads.append(load())
    # Cotangent rows summed by triangles and inverse-distance rows by edges
    # (`--summation scatter`), the same meshes.
    scatter = ["--summation", "scatter"]
    for weights in ("distance", "cotangent"):
        for order, m in (("ordered", s8), ("shuffled", sh)):
            rows[(weights, "every", f"{order}/scatter")] = smooth_case(m, n8, weights, "every",
                                                                       scatter)
        loads.append(load())
    res["sphere8"] = {f"{w}/{u}/{o}": v for (w, u, o), v in rows.items()}

    # The paper's surfaces: cotangent / uniform with weights recomputed every iteration.
    paper = {}
    for name, seed in (("flens", 11), ("sphere", 16), ("block", 12), ("golfball", 13)):
        path, _ = mesh(f"paper_{name}", name, seed)
        n = vertices(path)
        u = smooth_case(path, n, "uniform", "every")
        c = smooth_case(path, n, "cotangent", "every")
        paper[name] = {"vertices": n, "uniform_ns": u["ns"], "cotangent_ns": c["ns"],
                       "ratio": c["ns"] / u["ns"]}
    res["paper"] = paper
    loads.append(load())

    # One implicit cotangent step (area normalisation, one step of a diffusion time),
    # and later steps with the operator frozen.
    implicit = {}
    # The command line's default solver (conjugate gradient), then sparse Cholesky.
    for label, extra in (("first step", ["--iterations", "1"]),
                         ("5 steps, frozen", ["--iterations", "5", "--update", "once"]),
                         ("first step, Cholesky", ["--iterations", "1", "--solver", "cholesky"]),
                         ("5 steps, frozen, Cholesky",
                          ["--iterations", "5", "--update", "once", "--solver", "cholesky"])):
        walls = []
        for _ in range(REPS):
            report = OUT / "implicit.json"
            _, rss, rep = isolated(["smooth", str(s8), str(OUT / "out.ply"), "--method", "implicit",
                                    "--lambda", "0.8", "--report", str(report), "--force", *extra],
                                   str(report))
            s = rep["seconds"]
            walls.append({"smoothing": s["weights"] + s["updates"], "implicit": rep.get("implicit"),
                          "bytes_per_vertex": rss / n8})
        implicit[label] = walls
    res["implicit"] = implicit
    loads.append(load())

    # Closest-point distances and IO.
    comp = []
    for _ in range(REPS):
        wall, rss, rep = isolated(["compare", str(s8), str(s8c), "--json"], "-")
        comp.append({"wall": wall, "seconds": rep.get("seconds"), "bytes_per_vertex": rss / n8})
    res["compare"] = comp
    io = rows[("uniform", "once", "ordered")]["seconds"]
    res["io"] = {k: median([s[k] for s in io]) for k in ("read", "parse", "build", "write")}

    if os.environ.get("LEVEL10"):
        s10, _ = mesh("sphere10", "sphere", 110, ["--level", "10"])
        n10 = vertices(s10)
        c = smooth_case(s10, n10, "cotangent", "every", reps=1)
        res["sphere10"] = {"vertices": n10, **c}
        t = smooth_case(s10, n10, "cotangent", "every", ["--summation", "scatter"], reps=1)
        res["sphere10_scatter"] = {"vertices": n10, **t}

    if os.environ.get("LEVEL11"):
        res["sphere11"] = level11()

    loads.append(load())
    res["load"] = loads
    (OUT / "results.json").write_text(json.dumps(res, indent=1))
    md = report_md(res)
    (OUT / "results.md").write_text(md)
    print(md)


def report_md(res):
    r8 = res["sphere8"]
    L = [f"# beltrami against the performance targets",
         "",
         f"{res['version']}, {res['date']}, {res['cpus']} CPUs ({res['machine']}), medians of "
         f"{res['reps']}, {res['iterations']} iterations, λ = 0.8, free boundary. Load average "
         f"during the run: {min(res['load']):.1f}–{max(res['load']):.1f}.",
         "",
         "Noisy icosphere, level 8 (655 362 vertices), ns per vertex-iteration (weights + updates "
         "from `smooth --report`; reading and writing excluded), and peak resident memory:",
         "",
         "| scheme | weights | ordered | shuffled | shuffled ÷ ordered | peak memory, B/vertex |",
         "|---|---|---:|---:|---:|---:|"]
    for w in ("uniform", "distance", "cotangent"):
        for u in ("every", "once"):
            o, s = r8[f"{w}/{u}/ordered"], r8[f"{w}/{u}/shuffled"]
            L.append(f"| {w} | {u} | {o['ns']:.1f} ({o['range'][0]:.1f}–{o['range'][1]:.1f}) | "
                     f"{s['ns']:.1f} ({s['range'][0]:.1f}–{s['range'][1]:.1f}) | "
                     f"{s['ns'] / o['ns']:.2f} | {o['bytes_per_vertex']:.0f} |")
    for w in ("distance", "cotangent"):
        o, s = r8[f"{w}/every/ordered/scatter"], r8[f"{w}/every/shuffled/scatter"]
        L.append(f"| {w}, `--summation scatter` | every | {o['ns']:.1f} "
                 f"({o['range'][0]:.1f}–{o['range'][1]:.1f}) | {s['ns']:.1f} "
                 f"({s['range'][0]:.1f}–{s['range'][1]:.1f}) | {s['ns'] / o['ns']:.2f} | "
                 f"{o['bytes_per_vertex']:.0f} |")
    L += ["", "Cotangent ÷ uniform, weights recomputed every iteration (paper's surfaces):", "",
          "| surface | vertices | uniform ns | cotangent ns | ratio |", "|---|---:|---:|---:|---:|"]
    for name, p in res["paper"].items():
        L.append(f"| {name} | {p['vertices']} | {p['uniform_ns']:.1f} | {p['cotangent_ns']:.1f} | "
                 f"{p['ratio']:.2f} |")
    L += ["", "Implicit cotangent steps on sphere8 (seconds of `weights` + `updates`):", ""]
    for label, runs in res["implicit"].items():
        secs = [r["smoothing"] for r in runs]
        L.append(f"- {label}: median {median(secs):.3f} s (range {min(secs):.3f}–{max(secs):.3f}); "
                 f"peak {median([r['bytes_per_vertex'] for r in runs]):.0f} B/vertex; "
                 f"solver figures of the last run: {json.dumps(runs[-1]['implicit'])}")
    walls = [c["wall"] for c in res["compare"]]
    # The closest-point target: the reference's index and one query pass of every point
    # (`compare` makes two passes: `queries` is both).
    cp = [c["seconds"]["index_build"] + c["seconds"]["queries"] / 2
          for c in res["compare"] if c.get("seconds")]
    if cp:
        L += ["", f"Closest points of sphere8 against the clean sphere8 (index build + one query "
              f"pass, from `compare`'s timings): median {median(cp):.3f} s "
              f"(range {min(cp):.3f}–{max(cp):.3f})."]
    L += ["", f"`compare` sphere8 against the clean sphere8 (both directions, every metric): "
          f"median {median(walls):.2f} s whole process; timings of the last run: "
          f"{json.dumps(res['compare'][-1]['seconds'])}",
          "", f"Binary PLY on sphere8 (32.8 MB), medians: parse {res['io']['parse']:.3f} s, "
          f"half-edge build and validation {res['io']['build']:.3f} s, write (atomic, with fsync) "
          f"{res['io']['write']:.3f} s."]
    for key, how in (("sphere10", ""), ("sphere10_scatter", ", `--summation scatter`")):
        if key not in res:
            continue
        s = res[key]
        secs = s["seconds"][0]
        L += ["", f"Icosphere level 10 ({s['vertices']} vertices), 100 cotangent iterations, weights "
              f"recomputed every iteration{how}: {secs['weights'] + secs['updates']:.1f} s smoothing "
              f"({s['ns']:.1f} ns per vertex-iteration), read {secs['read']:.1f} s, write "
              f"{secs['write']:.1f} s, peak {s['bytes_per_vertex']:.0f} B/vertex "
              f"({s['bytes_per_vertex'] * s['vertices'] / 2**30:.1f} GiB); whole process "
              f"{s['wall']:.1f} s."]
    if "sphere11" in res:
        s = res["sphere11"]
        head = (f"Icosphere level 11 ({s['vertices']} vertices), {s['iterations']} cotangent "
                f"iterations, weights recomputed every iteration: ")
        if s["error"] is None:
            secs = s["seconds"]
            L += ["", head + f"whole process {s['wall']:.1f} s (smoothing "
                  f"{secs['weights'] + secs['updates']:.1f} s, {s['ns']:.1f} ns per "
                  f"vertex-iteration; read {secs['read']:.1f} s, write {secs['write']:.1f} s), peak "
                  f"{s['bytes_per_vertex']:.0f} B/vertex "
                  f"({s['bytes_per_vertex'] * s['vertices'] / 2**30:.1f} GiB)."]
        else:
            L += ["", head + f"did not run: `{s['error']}` (after {s['wall']:.1f} s, peak "
                  f"{s['bytes_per_vertex'] * s['vertices'] / 2**30:.1f} GiB)."]
    return "\n".join(L) + "\n"


if __name__ == "__main__":
    main()
