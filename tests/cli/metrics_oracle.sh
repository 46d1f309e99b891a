#!/usr/bin/env bash
# `al-refine metrics --dir` against an independent numpy re-implementation of the released
# Remove360 evaluator's per-image formulas (tests/metrics/released_reference.py, written from
# spec/METRICS.md): generated scenes with depth holes before / after / both, a 16-bit depth PNG,
# missing files and no detector folders; every semantic and depth figure must agree to 1e-6, in
# both --depth-holes rules. Needs python3 with numpy and Pillow (scripts/setup installs them).
set -u
BIN="$1"
SRC="${AL_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"
T="$(mktemp -d)"
trap 'rm -rf "$T"' EXIT
PY=""
for p in python3 /usr/bin/python3; do
  if "$p" -c "import numpy, PIL" >/dev/null 2>&1; then PY="$p"; break; fi
done
[ -n "$PY" ] || { echo "FAIL: no python3 with numpy and Pillow (apt-get install python3-numpy python3-pil)"; exit 1; }
"$PY" "$SRC/tests/metrics/released_reference.py" compare "$BIN" "$T" 2>"$T/stderr" || { cat "$T/stderr"; exit 1; }
# Unknown rule: usage error.
"$BIN" metrics --dir "$T/scene_det" --depth-holes after --out "$T/bad" >/dev/null 2>&1
[ $? -eq 1 ] || { echo "FAIL: --depth-holes after accepted"; exit 1; }
