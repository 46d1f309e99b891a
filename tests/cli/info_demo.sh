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
# The summary leads with residual_gt, and says for each refinement whether it leaves less of the
# object; a refinement with a higher F1 must leave less (issue 32: acc_Δdepth said the opposite).
head -20 "$TMP/a.txt" | grep -q '^removal *residual_gt' || fail "summary does not lead with residual_gt"
verdicts=$(grep -c ': leaves .* of the object than gc (residual_gt' "$TMP/a.txt")
[ "$verdicts" -eq 2 ] || fail "expected a verdict per refinement: $(cat "$TMP/a.txt")"
grep ': leaves .* of the object than gc' "$TMP/a.txt" | while read -r line; do
  f1=$(echo "$line" | sed -n 's/.*F1 \([0-9.]*\) -> \([0-9.]*\)).*/\1 \2/p')
  awk -v f="$f1" 'BEGIN { split(f, a, " "); exit !(a[2] > a[1]) }' || continue
  echo "$line" | grep -q 'leaves less' || { echo "FAIL: higher F1 but not less left: $line"; exit 1; }
done || fail "a refinement with a higher F1 does not leave less"
cmp -s "$TMP/a/scene/scene.ply" "$TMP/b/scene/scene.ply" || fail "demo scene is not deterministic"
cmp -s "$TMP/a/eval/metrics.csv" "$TMP/b/eval/metrics.csv" || fail "demo metrics are not deterministic"
out=$("$BIN" info --scene "$TMP/a/scene/scene.ply" --json) || fail "info on the demo scene failed"
echo "$out" | grep -q '"num_gaussians":20000' || fail "expected 20000 Gaussians: $out"
echo "$out" | grep -q '"feature_prefix":"semantic_"' || fail "expected semantic_ features: $out"
"$BIN" info --scene "$TMP/a/scene/scene.ply" --features none --json | grep -q '"feature_dim":0' || fail "--features none"
echo "OK: demo + info"
