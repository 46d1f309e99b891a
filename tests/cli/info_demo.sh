#!/usr/bin/env bash
# `al-refine demo` on a small scene: synth → refine (bk, cp) → eval; the summary names both
# solvers, every stage's outputs exist, the run is deterministic, and `info` reads the demo scene.
set -u
BIN="$1"
fail() { echo "FAIL: $*"; exit 1; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
args=(--gaussians 20000 --views 3 --resolution 160x120 --quiet)
"$BIN" demo "${args[@]}" --out "$TMP/a" > "$TMP/a.txt" || fail "demo exited $?: $(cat "$TMP/a.txt")"
"$BIN" demo "${args[@]}" --out "$TMP/b" > /dev/null || fail "second demo exited $?"
for f in report.json scene/scene.ply scene/labels.npy refine_bk/report.json refine_cp/report.json \
         eval/report.json eval/metrics.csv eval/table.md eval/table.tex; do
  [ -s "$TMP/a/$f" ] || fail "demo wrote no $f"
done
ls "$TMP/a/eval/images/" | grep -q '_bk_added.png$' || fail "no pink overlay of the bk refinement"
grep -q '^gc+bk ' "$TMP/a.txt" || fail "summary lacks the bk row: $(cat "$TMP/a.txt")"
grep -q '^gc+cp ' "$TMP/a.txt" || fail "summary lacks the cp row"
grep -q 'miss_rec' "$TMP/a.txt" || fail "summary lacks misses recovered"
grep -q 'prec_add' "$TMP/a.txt" || fail "summary lacks the precision of the added"
grep -q 'images: ' "$TMP/a.txt" || fail "summary does not say where the images are"
cmp -s "$TMP/a/scene/scene.ply" "$TMP/b/scene/scene.ply" || fail "demo scene is not deterministic"
cmp -s "$TMP/a/eval/metrics.csv" "$TMP/b/eval/metrics.csv" || fail "demo metrics are not deterministic"
out=$("$BIN" info --scene "$TMP/a/scene/scene.ply" --json) || fail "info on the demo scene failed"
echo "$out" | grep -q '"num_gaussians":20000' || fail "expected 20000 Gaussians: $out"
echo "$out" | grep -q '"feature_prefix":"semantic_"' || fail "expected semantic_ features: $out"
"$BIN" info --scene "$TMP/a/scene/scene.ply" --features none --json | grep -q '"feature_dim":0' || fail "--features none"
echo "OK: demo + info"
