#!/usr/bin/env bash
# Accuracy regression on the second scene source (docs/accuracy.md): small gen_scenes.py scenes of
# three styles, generated at test time, refined with the default flags (bk and cp); the properties
# are checked by bench/accuracy/regression.py. Needs python3-numpy and python3-scipy (scripts/setup)
# and ../shared/scenes/gen_scenes.py (AL_SCENES_GEN overrides); without them the test skips loudly,
# except under AL_REQUIRE_TEST_DATA=1 (CI), where it fails.
set -euo pipefail
BIN="$1"
SRC="${AL_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}"
GEN="${AL_SCENES_GEN:-$SRC/../shared/scenes/gen_scenes.py}"
missing=""
[ -f "$GEN" ] || missing="$GEN"
/usr/bin/python3 -c "import numpy, scipy" 2>/dev/null || missing="${missing:+$missing, }python3-numpy/python3-scipy"
if [ -n "$missing" ]; then
  if [ "${AL_REQUIRE_TEST_DATA:-0}" = "1" ]; then echo "FAIL: missing $missing"; exit 1; fi
  echo "SKIPPED (not a pass): missing $missing"
  exit 0
fi
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
OMP_NUM_THREADS=1 /usr/bin/python3 "$SRC/bench/accuracy/regression.py" "$BIN" "$GEN" "$T"
