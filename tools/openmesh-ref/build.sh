#!/usr/bin/env bash
# Builds openmesh-ref against Debian's libopenmesh-dev (installing the package when its
# headers are missing) into target/openmesh-ref/openmesh-ref, or into the path given as
# the first argument.
#
#   tools/openmesh-ref/build.sh [OUTPUT_BINARY]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${1:-$root/target/openmesh-ref/openmesh-ref}"

if [ ! -f /usr/include/OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh ]; then
  echo "openmesh-ref: installing libopenmesh-dev" >&2
  sudo=""
  if [ "$(id -u)" != 0 ]; then sudo="sudo"; fi
  $sudo apt-get install -y libopenmesh-dev ||
    { $sudo apt-get update && $sudo apt-get install -y libopenmesh-dev; }
fi

mkdir -p "$(dirname "$out")"
# -ffp-contract=off: no fused multiply-add, so every operation rounds as written (the
# references must not depend on the compiler's choice of instructions).
g++ -O2 -std=c++17 -ffp-contract=off -Wall -Wextra \
  -o "$out" "$here"/*.cc -lOpenMeshTools -lOpenMeshCore
echo "$out"
