#!/usr/bin/env bash
# Regenerates the OpenMesh references into a temporary folder and checks that they are
# byte for byte the committed ones in fixtures/openmesh (so that no reference can be
# edited by hand, and a change of a fixture or of the generator cannot go unnoticed).
#
#   tools/openmesh-ref/check.sh
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

"$here/regenerate.sh" "$tmp" >/dev/null
if ! diff -r -q "$tmp" "$root/fixtures/openmesh"; then
  echo >&2
  echo "error: the OpenMesh references in fixtures/openmesh differ from what" >&2
  echo "tools/openmesh-ref generates now (the files listed above)." >&2
  echo "If a fixture or the generator changed on purpose, run" >&2
  echo "  tools/openmesh-ref/regenerate.sh" >&2
  echo "and commit fixtures/openmesh; never edit a reference by hand." >&2
  exit 1
fi
echo "OpenMesh references are up to date ($(ls "$tmp" | wc -l) fixtures)"
