#!/usr/bin/env bash
# Peer comparison of explicit Laplacian smoothing: beltrami against Open3D, trimesh,
# PyMeshLab, libigl, VTK (Python wheels) and OpenMesh (C++), plus a memory-bandwidth
# probe, closest-point distances and binary PLY IO. One command:
#
#   benches/peers/run.sh
#
# writes benches/peers/results.md and results.csv (see docs/performance/peers.md).
#
# Environment (all optional):
#   BELTRAMI=/path/to/beltrami   binary to measure (default: cargo build --release -p beltrami-cli)
#   MESHES="flens block sphere6 golfball sphere8"   meshes to run (sphere8 = 655 362 vertices)
#   PEERS="beltrami openmesh open3d trimesh pymeshlab igl vtk"   tools to run
#   REPS=3                       repetitions per case (a run over LONG_RUN_SECONDS is not repeated)
#   LONG_RUN_SECONDS=40
#   ITERATIONS=100
#   ONE_THREAD_MESHES=sphere8    meshes on which beltrami is also run on one thread
#   PYTHON=python3.11            interpreter for the virtual environment
# Needs: a Rust toolchain, Python 3.11 with venv, gcc/g++; root (or sudo) for
# apt-get install libopenmesh-dev. A peer that cannot be installed is skipped with a
# note in the output and in results.md; the run goes on.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
OUT="$HERE/out"
MESH_DIR="$HERE/meshes"
VENV="$HERE/.venv"
MESHES="${MESHES:-flens block sphere6 golfball sphere8}"
PEERS="${PEERS:-beltrami openmesh open3d trimesh pymeshlab igl vtk}"
PYTHON="${PYTHON:-python3.11}"
export REPS="${REPS:-3}" LONG_RUN_SECONDS="${LONG_RUN_SECONDS:-40}" ITERATIONS="${ITERATIONS:-100}"
export ONE_THREAD_MESHES="${ONE_THREAD_MESHES:-sphere8}"
export PEERS_OUT_DIR="$OUT" PEERS_MESH_DIR="$MESH_DIR"

die() { echo "error: $*" >&2; exit 1; }
step() { echo; echo "== $*"; }
# A peer that cannot run is noted (printed, and listed in results.md), never fatal.
skip() { echo "skipped: $*" | tee -a "$OUT/skipped.txt"; }

mkdir -p "$OUT/bin" "$MESH_DIR"
: > "$OUT/records.jsonl"
: > "$OUT/skipped.txt"
exec > >(tee "$OUT/run.log") 2>&1

command -v "$PYTHON" >/dev/null || PYTHON=python3
command -v "$PYTHON" >/dev/null || die "python3 not found (Python 3.11 with venv is needed)"
command -v cargo >/dev/null || [ -n "${BELTRAMI:-}" ] || die "cargo not found and BELTRAMI not set"

# --- the binary under test -----------------------------------------------------------
step "beltrami binary"
if [ -z "${BELTRAMI:-}" ]; then
  (cd "$ROOT" && cargo build --release -p beltrami-cli) || die "cargo build --release -p beltrami-cli failed"
  BELTRAMI="${CARGO_TARGET_DIR:-$ROOT/target}/release/beltrami"
fi
[ -x "$BELTRAMI" ] || die "BELTRAMI=$BELTRAMI is not an executable"
export BELTRAMI
echo "measuring $BELTRAMI"

# --- Python environment ---------------------------------------------------------------
step "Python environment ($VENV)"
if [ ! -x "$VENV/bin/python" ]; then
  "$PYTHON" -m venv "$VENV" || die "cannot create a venv with $PYTHON (install python3-venv)"
fi
PY="$VENV/bin/python"
"$PY" -m pip install -q --upgrade pip >/dev/null || true
if ! "$PY" -m pip install -q -r "$HERE/requirements.txt"; then
  # Install what can be installed, one pin at a time; the drivers of missing tools skip.
  while read -r pin; do
    case "$pin" in ''|\#*) continue ;; esac
    "$PY" -m pip install -q "$pin" || skip "pip install $pin failed"
  done < "$HERE/requirements.txt"
fi
"$PY" -c "import numpy, scipy" 2>/dev/null || die "numpy/scipy did not install in $VENV"

# --- Debian packages: OpenMesh (C++ peer) and libusb (Open3D's wheel links it) -------------
step "Debian packages"
need=()
[ -d /usr/include/OpenMesh ] || need+=(libopenmesh-dev)
ldconfig -p 2>/dev/null | grep -q 'libusb-1.0.so.0' || need+=(libusb-1.0-0)
if [ "${#need[@]}" -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  echo "apt-get install ${need[*]}"
  { $SUDO apt-get update -qq && $SUDO apt-get install -y -qq "${need[@]}"; } >/dev/null 2>&1 \
    || echo "apt-get install ${need[*]} failed; the peers that need them are skipped"
fi
if [[ " $PEERS " == *" openmesh "* ]]; then
  if [ -d /usr/include/OpenMesh ] && g++ -O2 -DNDEBUG -std=c++17 -o "$OUT/bin/openmesh_smooth" \
       "$HERE/openmesh_smooth.cpp" -lOpenMeshCore -lOpenMeshTools; then
    echo "built $OUT/bin/openmesh_smooth (OpenMesh $(dpkg-query -W -f='${Version}' libopenmesh-dev 2>/dev/null || echo '?'))"
  else
    skip "openmesh: libopenmesh-dev not installable or openmesh_smooth.cpp did not compile"
    PEERS="${PEERS//openmesh/}"
  fi
fi

# --- meshes ----------------------------------------------------------------------------
# Same files for every tool: binary little-endian PLY, double coordinates, Gaussian
# noise along the vertex normals with sigma = 0.2 x mean edge length, fixed seeds.
step "meshes ($MESH_DIR)"
gen() {  # gen NAME SURFACE SEED
  [ -f "$MESH_DIR/$1.ply" ] && [ -f "$MESH_DIR/$1_clean.ply" ] && return 0
  "$BELTRAMI" generate "$2" "$MESH_DIR/$1.ply" --noise 0.2 --relative --seed "$3" \
    --clean "$MESH_DIR/$1_clean.ply"
}
sphere() {  # sphere NAME LEVEL SEED: the icosphere at any level (0 to 10)
  [ -f "$MESH_DIR/$1.ply" ] && [ -f "$MESH_DIR/$1_clean.ply" ] && return 0
  "$BELTRAMI" generate sphere "$MESH_DIR/$1.ply" --level "$2" --noise 0.2 --relative \
    --seed "$3" --clean "$MESH_DIR/$1_clean.ply"
}
for m in $MESHES; do
  case "$m" in
    flens) gen flens flens 11 ;;
    block) gen block block 12 ;;
    golfball) gen golfball golfball 13 ;;
    sphere6) gen sphere6 sphere 16 ;;   # the paper's sphere: icosphere level 6
    sphere[0-9]|sphere10) sphere "$m" "${m#sphere}" "1${m#sphere}" ;;
    *) die "unknown mesh $m (flens, block, golfball, sphere0..sphere10)" ;;
  esac
done
ls -l "$MESH_DIR"

# --- machine and conditions ----------------------------------------------------------------
step "machine"
"$PY" "$HERE/machine.py" "$BELTRAMI" "$ROOT" start > "$OUT/machine.json"
cat "$OUT/machine.json"

# How busy the machine is meanwhile: every minute, the cores used by processes outside
# this run (out/conditions.jsonl). Stopped on exit.
: > "$OUT/conditions.jsonl"
( while :; do "$PY" "$HERE/machine.py" sample $$ >> "$OUT/conditions.jsonl" || true; sleep 55; done ) &
SAMPLER=$!
trap 'kill "$SAMPLER" 2>/dev/null || true' EXIT

# --- memory bandwidth (roofline) --------------------------------------------------------------
# Run at the start and again at the end; the report takes the best figure.
: > "$OUT/triad.txt"
TRIAD=""
gcc -O2 -fopenmp -o "$OUT/bin/triad" "$HERE/triad.c" && TRIAD="$OUT/bin/triad" \
  || skip "roofline: gcc -fopenmp could not build triad.c"
triad() {
  [ -n "$TRIAD" ] || return 0
  step "memory bandwidth (triad, $1)"
  # 3 x 512 MiB (beyond any last-level cache) and 3 x 32 MiB (about the sweep's
  # working set on sphere8: 655 362 vertices x 124 B).
  for n in 67108864 4194304; do
    for t in 1 2; do
      echo "size=$n $(OMP_NUM_THREADS=$t OMP_PROC_BIND=spread "$TRIAD" "$n" 30)" | tee -a "$OUT/triad.txt"
    done
  done
}
triad start

# --- smoothing, tool by tool ---------------------------------------------------------------------
# beltrami first: the others compare their output with beltrami's where semantics agree.
module_of() {  # the Python module a driver needs (none for beltrami and OpenMesh)
  case "$1" in open3d|trimesh|pymeshlab|igl|vtk) echo "$1" ;; *) echo "" ;; esac
}
for peer in $PEERS; do
  step "smoothing: $peer"
  mod="$(module_of "$peer")"
  if [ -n "$mod" ] && ! err="$("$PY" -c "import $mod" 2>&1)"; then
    skip "$peer: cannot import $mod ($(echo "$err" | tail -n 1))"
    continue
  fi
  # shellcheck disable=SC2086
  if ! (cd "$HERE" && "$PY" "bench_$peer.py" $MESHES); then
    skip "$peer: its driver failed (see out/run.log)"
  fi
done

step "closest-point distances and PLY IO"
if [[ " $MESHES " == *" sphere8 "* ]]; then
  (cd "$HERE" && "$PY" bench_metrics_io.py sphere8) || skip "distances/IO: driver failed (see out/run.log)"
else
  (cd "$HERE" && "$PY" bench_metrics_io.py "${MESHES##* }") || skip "distances/IO: driver failed"
fi

triad end

step "report"
"$PY" "$HERE/machine.py" "$BELTRAMI" "$ROOT" end > "$OUT/machine_end.json"
"$PY" "$HERE/report.py"
echo "wrote $HERE/results.md and $HERE/results.csv"
