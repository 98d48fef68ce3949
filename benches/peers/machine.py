"""Prints, as JSON, what the report says about the machine and the conditions of the
run: CPU model, cores, caches, memory, date, load average, the busiest other
processes, toolchain and package versions, and the commit of the binary's checkout.

  machine.py BELTRAMI_BINARY REPO_ROOT start|end
  machine.py sample RUN_PID     (cores busy outside RUN_PID's process tree, one JSON line)"""
import datetime
import json
import os
import platform
import subprocess
import sys
import time


def sh(*cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, timeout=30).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""


def lscpu():
    info = {}
    for line in sh("lscpu").splitlines():
        key, _, value = line.partition(":")
        info[key.strip()] = value.strip()
    return info


def cpu_ticks():
    """{pid: (command, nice, user+system ticks, parent pid)} of every process, from /proc."""
    out = {}
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            stat = open(f"/proc/{pid}/stat").read()
        except OSError:
            continue
        command = stat[stat.index("(") + 1:stat.rindex(")")]
        fields = stat[stat.rindex(")") + 2:].split()
        out[pid] = (command, int(fields[16]), int(fields[11]) + int(fields[12]), fields[1])
    return out


def ours(procs, root):
    """The pids of `root` and its descendants (the benchmark run itself)."""
    mine, grew = {root}, True
    while grew:
        grew = False
        for pid, p in procs.items():
            if p[3] in mine and pid not in mine:
                mine.add(pid)
                grew = True
    return mine


def others_busy(seconds=3.0, n=6, root=None):
    """Cores kept busy over a short sample by processes outside the run (`root` and its
    descendants; this script by default), and the busiest of them."""
    hz = os.sysconf("SC_CLK_TCK")
    a = cpu_ticks()
    time.sleep(seconds)
    b = cpu_ticks()
    mine = ours(b, root or str(os.getpid()))
    used = []
    for pid, (command, nice, ticks, _) in b.items():
        if pid in a and pid not in mine:
            used.append((ticks - a[pid][2], command, nice))
    used.sort(reverse=True)
    total = sum(u for u, _, _ in used) / hz / seconds
    top = [dict(command=c, nice=nice, cores=round(u / hz / seconds, 2)) for u, c, nice in used[:n] if u > 0]
    return round(total, 2), top


def versions():
    out = {}
    for pkg in ("numpy", "scipy", "open3d", "trimesh", "pymeshlab", "libigl", "vtk"):
        try:
            from importlib.metadata import version
            out[pkg] = version(pkg)
        except Exception:  # not installed: the driver skips
            out[pkg] = None
    out["openmesh"] = sh("dpkg-query", "-W", "-f=${Version}", "libopenmesh-dev") or None
    return out


def main():
    if sys.argv[1] == "sample":  # machine.py sample RUN_PID: one line for out/conditions.jsonl
        cores, _ = others_busy(seconds=5.0, root=sys.argv[2])
        print(json.dumps(dict(time=time.strftime("%H:%M:%S"), other_processes_cores=cores,
                              load_1min=round(os.getloadavg()[0], 2))), flush=True)
        return
    binary, root, when = sys.argv[1], sys.argv[2], sys.argv[3]
    cpu = lscpu()
    load = os.getloadavg()
    info = dict(
        when=when,
        date=datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        load_average_1_5_15=[round(x, 2) for x in load],
    )
    info["other_processes_cores"], info["busiest_processes"] = others_busy()
    if when == "start":
        mem_kb = int(next(l.split()[1] for l in open("/proc/meminfo") if l.startswith("MemTotal")))
        info.update(
            cpu_model=cpu.get("Model name", platform.processor()),
            cores=os.cpu_count(),
            threads_per_core=cpu.get("Thread(s) per core"),
            l2=cpu.get("L2 cache"), l3=cpu.get("L3 cache"),
            hypervisor=cpu.get("Hypervisor vendor"),
            memory_gib=round(mem_kb / 2**20, 1),
            kernel=platform.release(),
            rustc=sh("rustc", "--version"),
            gcc=sh("gcc", "-dumpfullversion"),
            python=platform.python_version(),
            beltrami=binary,
            beltrami_commit=sh("git", "-C", root, "rev-parse", "--short", "HEAD"),
            beltrami_tree_dirty=bool(sh("git", "-C", root, "status", "--porcelain", "--untracked-files=no")),
            versions=versions(),
        )
    print(json.dumps(info, indent=1))


if __name__ == "__main__":
    main()
