#!/usr/bin/env bash
# The interim demo writes a deterministic scene that `info` reads back (no shared data needed).
set -u
BIN="$1"
fail() { echo "FAIL: $*"; exit 1; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
"$BIN" demo --out "$TMP/a" > "$TMP/a.txt" || fail "demo exited $?"
"$BIN" demo --out "$TMP/b" > /dev/null || fail "second demo exited $?"
cmp -s "$TMP/a/scene.ply" "$TMP/b/scene.ply" || fail "demo scene is not deterministic"
[ -f "$TMP/a/report.json" ] || fail "demo wrote no report.json"
out=$("$BIN" info --scene "$TMP/a/scene.ply" --json) || fail "info on the demo scene failed"
echo "$out" | grep -q '"num_gaussians":2000' || fail "expected 2000 Gaussians: $out"
echo "$out" | grep -q '"sh_degree":1' || fail "expected SH degree 1: $out"
echo "$out" | grep -q '"feature_prefix":"semantic_"' || fail "expected semantic_ features: $out"
"$BIN" info --scene "$TMP/a/scene.ply" --features none --json | grep -q '"feature_dim":0' || fail "--features none"
echo "OK: demo + info"
