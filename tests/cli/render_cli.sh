#!/usr/bin/env bash
# CLI test of `al-refine render`: outputs on the real 9k scene (when the shared data exists),
# resize, removed set, and error exit codes on bad input.
set -u
BIN="$1"
fail() { echo "FAIL: $*" >&2; exit 1; }
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT

# Bad input: missing scene file -> exit 2; bad --bg -> usage error 1.
"$BIN" render --scene "$OUT/missing.ply" --cameras "$OUT/none.json" --out "$OUT/x" 2>/dev/null
[ $? -eq 2 ] || fail "missing scene should exit 2"

DATA="${AL_TEST_DATA:-${AL_SOURCE_DIR:-.}/../shared/data}"
if [ ! -f "$DATA/real_ply/scene_9k.ply" ]; then
  if [ "${AL_REQUIRE_TEST_DATA:-0}" = "1" ]; then fail "shared data not found"; fi
  echo "*** SKIPPED: shared test data not found (set AL_TEST_DATA) ***"
  exit 0
fi
SCENE="$DATA/real_ply/scene_9k.ply"
CAMS="$DATA/refs_9k/cameras.json"

"$BIN" render --scene "$SCENE" --cameras "$CAMS" --bg 0,x,1 --out "$OUT/bad" 2>/dev/null
[ $? -eq 1 ] || fail "bad --bg should exit 1"
"$BIN" render --scene "$SCENE" --cameras "$CAMS" --views nosuchview --out "$OUT/bad" 2>/dev/null
[ $? -eq 2 ] || fail "unknown view should exit 2"

"$BIN" render --scene "$SCENE" --cameras "$CAMS" --views all --npy --out "$OUT/full" 2>/dev/null || fail "full render failed"
for v in cam0 cam1; do
  for f in rgb.png depth.png depth_vis.png alpha.png rgb.npy depth.npy alpha.npy radii.npy; do
    [ -s "$OUT/full/${v}_$f" ] || fail "missing ${v}_$f"
  done
done
[ -s "$OUT/full/report.json" ] || fail "missing report.json"
grep -q '"status": "ok"' "$OUT/full/report.json" || fail "status not ok"
grep -q '"depth_png_scale"' "$OUT/full/report.json" || fail "no depth scale in report"
# rgb.npy: 240 x 320 x 3 float32 = 921600 bytes of data + 128-byte header.
[ "$(stat -c %s "$OUT/full/cam0_rgb.npy")" -eq $((240 * 320 * 3 * 4 + 128)) ] || fail "rgb.npy size"
# radii: one int32 per Gaussian (9080) without a removed set.
[ "$(stat -c %s "$OUT/full/cam0_radii.npy")" -eq $((9080 * 4 + 128)) ] || fail "radii.npy size"

# Removed set: radii only for the 6842 kept Gaussians.
"$BIN" render --scene "$SCENE" --cameras "$CAMS" --removed "$DATA/refs_9k/masks/random25.npy" --views cam1 --npy \
  --bg 1 --out "$OUT/minus" 2>/dev/null || fail "render with removed set failed"
[ "$(stat -c %s "$OUT/minus/cam1_radii.npy")" -eq $((6842 * 4 + 128)) ] || fail "kept radii size"
[ ! -e "$OUT/minus/cam0_rgb.png" ] || fail "--views cam1 rendered cam0"

# Resize keeps the FoV: half size.
"$BIN" render --scene "$SCENE" --cameras "$CAMS" --views cam0 --width 160 --npy --out "$OUT/small" 2>/dev/null || fail "resize failed"
[ "$(stat -c %s "$OUT/small/cam0_alpha.npy")" -eq $((120 * 160 * 4 + 128)) ] || fail "resized alpha.npy size"
echo "render CLI OK"
