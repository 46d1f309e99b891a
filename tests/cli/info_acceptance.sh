#!/usr/bin/env bash
# Acceptance: `al-refine info` on the real scene_9k.ply, and a clear error on a truncated copy.
# Usage: bash info_acceptance.sh /path/to/al-refine
set -u
BIN="$1"
DATA="${AL_TEST_DATA:-${AL_SOURCE_DIR:-$(cd "$(dirname "$0")/../.." && pwd)}/../shared/data}"
SCENE="$DATA/real_ply/scene_9k.ply"
if [ ! -f "$SCENE" ]; then
  echo "*** SKIP: shared test data not found ($SCENE); set AL_TEST_DATA ***"
  [ "${AL_REQUIRE_TEST_DATA:-0}" = "1" ] && exit 1
  exit 0
fi
fail() { echo "FAIL: $*"; exit 1; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

out=$("$BIN" info --scene "$SCENE" --json --out "$TMP/report") || fail "info exited $?"
echo "$out" | grep -q '"num_gaussians":9080' || fail "num_gaussians 9080 not in: $out"
echo "$out" | grep -q '"sh_degree":3' || fail "sh_degree 3 not in: $out"
for key in feature_dim feature_prefix bbox_min bbox_max scale_stats nonfinite; do
  echo "$out" | grep -q "\"$key\"" || fail "key $key missing"
done
[ "$(echo "$out" | wc -l)" -eq 1 ] || fail "--json must print exactly one line"
grep -q '"num_gaussians": 9080' "$TMP/report/report.json" || fail "report.json lacks the scene summary"
grep -q '"command": "info"' "$TMP/report/report.json" || fail "report.json lacks command"

# Human-readable form.
"$BIN" info --scene "$SCENE" | grep -q "9080" || fail "text output lacks the count"

# Truncated copy: non-zero exit (2), one line on stderr naming the file.
head -c 200000 "$SCENE" > "$TMP/truncated_9k.ply"
"$BIN" info --scene "$TMP/truncated_9k.ply" > "$TMP/stdout" 2> "$TMP/stderr"
rc=$?
[ $rc -eq 2 ] || fail "truncated file: exit $rc, expected 2"
[ "$(wc -l < "$TMP/stderr")" -eq 1 ] || fail "expected one stderr line, got: $(cat "$TMP/stderr")"
grep -q "truncated_9k.ply" "$TMP/stderr" || fail "error does not name the file: $(cat "$TMP/stderr")"

# Missing file and unknown extension are bad input too.
"$BIN" info --scene "$TMP/nope.ply" 2> /dev/null; [ $? -eq 2 ] || fail "missing file must exit 2"
echo "OK: info acceptance"
