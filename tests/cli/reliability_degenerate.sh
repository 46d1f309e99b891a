#!/usr/bin/env bash
# Reliability (issue #14, docs/reliability.md): degenerate inputs stay fast and never silently wrong.
# 100k coincident Gaussians refine in < 5 s (kNN ties); zero-norm features are counted in a warning;
# quaternions scaled by 1e20 render exactly like their unit versions; a PLY without opacity renders
# with a warning naming it; view names with NUL, '/' or repeats get safe, unique file names.
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
fail() { echo "FAIL: $*"; exit 1; }
MK="python3 $HERE/make_degenerate.py"

$MK ply "$T/coincident.ply" 100000 --coincident
$MK mask "$T/removed.npy" 100000 0 10000
t0=$EPOCHREALTIME
"$BIN" refine --scene "$T/coincident.ply" --removed "$T/removed.npy" --quiet --out "$T/c" >/dev/null || fail "coincident refine"
dt=$(awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { print b - a }')
awk -v d="$dt" 'BEGIN { exit !(d < 5) }' || fail "100k coincident Gaussians took ${dt}s (limit 5 s)"
echo "100k coincident Gaussians refined in ${dt}s"

$MK ply "$T/zero.ply" 20000 --zero-features
$MK mask "$T/removed20k.npy" 20000 0 2000
"$BIN" refine --scene "$T/zero.ply" --removed "$T/removed20k.npy" --quiet --out "$T/z" >/dev/null 2>&1 || true
python3 -c "
import json, sys
w = json.load(open('$T/z/report.json'))['warnings']
sys.exit(0 if any('zero-norm features' in x and x.split()[0].isdigit() for x in w) else 1)" ||
  fail "no warning counting zero-norm features"

# Quaternion overflow: q * 1e20 must render like q (same seed, same everything else).
$MK cameras "$T/cams.json" a b
$MK ply "$T/q1.ply" 3000 --seed 7
$MK ply "$T/q20.ply" 3000 --seed 7 --quat-scale 1e20
"$BIN" render --scene "$T/q1.ply" --cameras "$T/cams.json" --out "$T/r1" >/dev/null 2>&1 || fail "render q1"
"$BIN" render --scene "$T/q20.ply" --cameras "$T/cams.json" --out "$T/r20" >/dev/null 2>&1 || fail "render q20"
cmp -s "$T/r1/a_rgb.png" "$T/r20/a_rgb.png" || fail "quaternions scaled by 1e20 render differently"

# Missing opacity: rendered with a warning that names the property (stderr and report.json).
$MK ply "$T/noop.ply" 3000 --no-opacity
"$BIN" render --scene "$T/noop.ply" --cameras "$T/cams.json" --out "$T/rn" >/dev/null 2>"$T/err" || fail "render noop"
grep -q "'opacity'" "$T/err" || fail "missing opacity not named on stderr"
grep -q "'opacity'" "$T/rn/report.json" || fail "missing opacity not in report.json"

# View names: NUL, '/', a repeat. Every view gets its own safe file, none overwritten.
$MK cameras "$T/names.json" 'a/b' 'c\0d' 'a_b' 'x' 'x' '..'
"$BIN" render --scene "$T/q1.ply" --cameras "$T/names.json" --out "$T/rv" >/dev/null 2>"$T/err" || fail "render names"
n=$(ls "$T/rv"/*_rgb.png | wc -l)
[ "$n" = 6 ] || fail "6 views with colliding names gave $n RGB images: $(ls "$T/rv")"
grep -q "not a safe file name" "$T/err" || fail "unsafe view name not reported"
grep -q "occurs more than once" "$T/err" || fail "repeated view name not reported"
echo "reliability degenerate OK"
