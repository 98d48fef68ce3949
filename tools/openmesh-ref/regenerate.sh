#!/usr/bin/env bash
# Regenerates the OpenMesh references: builds openmesh-ref, then for every fixture named
# in fixtures.txt runs it on fixtures/<name>.ply into OUT_ROOT/<name>/ (default:
# fixtures/openmesh, the committed references), passing the options that follow the name
# on its line.
#
#   tools/openmesh-ref/regenerate.sh [OUT_ROOT]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out_root="$(mkdir -p "${1:-$root/fixtures/openmesh}" && cd "${1:-$root/fixtures/openmesh}" && pwd)"
bin="$root/target/openmesh-ref/openmesh-ref"

"$here/build.sh" "$bin" >/dev/null

# Paths inside the references are relative to the repository root.
cd "$root"
grep -v -e '^#' -e '^[[:space:]]*$' "$here/fixtures.txt" | while read -r -a words; do
  name="${words[0]}"
  rm -rf "${out_root:?}/$name"
  "$bin" "fixtures/$name.ply" "$out_root/$name" "$name" "${words[@]:1}"
  echo "$out_root/$name"
done
