#!/usr/bin/env bash
# `al-refine eval` on a small synthetic scene: every output of SPEC §6 exists, the 8-bit depth pairs
# it writes re-score to the same acc_delta_depth with `al-refine metrics`, and bad input gives a
# one-line error naming the file, exit code 2 and no output folder.
set -u
BIN="$1"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$BIN" synth --preset room --gaussians 20000 --seed 3 --views 3 --resolution 160x120 --quiet --out "$TMP/s" \
  >/dev/null || fail "synth failed"
S="$TMP/s"
"$BIN" eval --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --refined "$S/removed_gc.npy" \
  --cameras "$S/cameras.json" --labels "$S/labels.npy" --export-renders --quiet --out "$TMP/e" >"$TMP/out.txt" \
  || fail "eval exited $?: $(cat "$TMP/out.txt")"
for f in report.json metrics.csv table.md table.tex; do
  [ -s "$TMP/e/$f" ] || fail "missing $f"
done
views=$(ls "$TMP/e/masks" | sed 's/\.png$//')
[ -n "$views" ] || fail "no view was evaluated"
for v in $views; do
  for k in before after refined depthdiff added refined_depthdiff; do
    [ -s "$TMP/e/images/${v}_$k.png" ] || fail "missing images/${v}_$k.png"
  done
  for d in renders/before renders/after renders/refined depth/after/before depth/after/after; do
    [ -s "$TMP/e/$d/$v.png" ] || fail "missing $d/$v.png"
  done
done
[ "$(wc -l < "$TMP/e/metrics.csv")" -eq 4 ] || fail "metrics.csv should have a header and 3 view rows"
grep -q 'room-' "$TMP/e/table.md" || fail "table row is not named after the synth target"
grep -q '\\textbf{' "$TMP/e/table.tex" || fail "table.tex marks no best value"
grep -q '"command": "eval"' "$TMP/e/report.json" || fail "report.json lacks command"
grep -q '"iou_drop"' "$TMP/e/report.json" || fail "report.json does not list iou_drop as skipped"
ls "$TMP" | grep -q 'eval-tmp' && fail "staging folder left behind"

# Feature metrics with no external input: report, CSV, table, one image per view and column.
grep -q '"mean_residual"' "$TMP/e/report.json" || fail "report.json lacks the feature metrics"
grep -q '"feature_segmentation"' "$TMP/e/report.json" || fail "report.json lacks feature_segmentation"
head -1 "$TMP/e/metrics.csv" | grep -q 'after_residual_feat' || fail "metrics.csv lacks residual_feat"
grep -q 'residual_feat' "$TMP/e/table.md" || fail "table.md lacks residual_feat"
grep -q 'resid_ft' "$TMP/out.txt" || fail "eval does not print the feature metrics"
for v in $views; do
  for k in featseg refined_featseg; do
    [ -s "$TMP/e/images/${v}_$k.png" ] || fail "missing images/${v}_$k.png"
  done
done
# Residuals: with --labels and --refined, residual_gt leads (report, CSV, table, printout, overlay),
# residual_est takes the refined render as its ideal, residual_px runs from the masks.
for k in residual_gt residual_est residual_px; do
  grep -q "\"$k\"" "$TMP/e/report.json" || fail "report.json lacks $k"
  head -1 "$TMP/e/metrics.csv" | grep -q "after_$k" || fail "metrics.csv lacks after_$k"
done
grep -q '"headline": "residual_gt"' "$TMP/e/report.json" || fail "residual_gt is not the headline with labels"
head -1 "$TMP/e/table.md" | grep -q '^| Scene-Object | residual_gt ↓' || fail "table.md does not lead with residual_gt"
grep -q 'residual_gt' "$TMP/out.txt" || fail "eval does not print residual_gt"
for v in $views; do
  for k in after_residual refined_residual ideal; do
    [ -s "$TMP/e/images/${v}_$k.png" ] || fail "missing images/${v}_$k.png"
  done
done
"$BIN" eval --help | grep -q -- '--px-colour-tol' || fail "--help lacks the residual_px tolerances"
"$BIN" eval --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --cameras "$S/cameras.json" --labels "$S/labels.npy" \
  --residual-min-pixels 0 --quiet --out "$TMP/u4" >/dev/null 2>&1
[ $? -eq 1 ] || fail "--residual-min-pixels 0 should exit 1"
[ ! -e "$TMP/u4" ] || fail "output written on a usage error"
# Without labels the prototype comes from the removed set (object masks from synth's masks/).
"$BIN" eval --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --cameras "$S/cameras.json" \
  --object-masks "$S/masks" --no-images --quiet --out "$TMP/e2" >/dev/null || fail "eval without labels failed"
grep -q '"source": "removed set"' "$TMP/e2/report.json" || fail "prototype not from the removed set"
# ... and without labels or a refinement the headline is residual_px; residual_gt and residual_est
# are skipped with the reason.
grep -q '"headline": "residual_px"' "$TMP/e2/report.json" || fail "residual_px is not the headline from masks alone"
grep -q '"metric": "residual_est"' "$TMP/e2/report.json" || fail "residual_est is not listed as skipped"
grep -q '"metric": "residual_gt"' "$TMP/e2/report.json" || fail "residual_gt is not listed as skipped"
# Impossible or contradictory feature options: usage errors (exit 1), nothing written.
printf '\x93NUMPY' > "$TMP/none.npy"
"$BIN" eval --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --cameras "$S/cameras.json" --labels "$S/labels.npy" \
  --prompt-embeddings "$TMP/none.npy" --quiet --out "$TMP/u2" >/dev/null 2>&1
[ $? -eq 1 ] || fail "--prompt-embeddings without --positive should exit 1"
"$BIN" eval --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --cameras "$S/cameras.json" --labels "$S/labels.npy" \
  --feature-min-sim 2 --quiet --out "$TMP/u3" >/dev/null 2>&1
[ $? -eq 1 ] || fail "--feature-min-sim 2 should exit 1"
[ ! -e "$TMP/u2" ] && [ ! -e "$TMP/u3" ] || fail "output written on a usage error"

# The published-mode depth pairs written by eval re-score identically with `al-refine metrics`.
"$BIN" metrics --dir "$TMP/e" --object-masks masks --depth-before depth/after/before --depth-after depth/after/after \
  --out "$TMP/m" >/dev/null || fail "metrics on eval's depth pairs failed"
a=$(grep -o '"mean_acc_delta_depth": [0-9.e-]*' "$TMP/e/report.json" | head -1 | awk '{print $2}')
b=$(grep -o '"mean_acc_delta_depth": [0-9.e-]*' "$TMP/m/report.json" | head -1 | awk '{print $2}')
[ -n "$a" ] && [ "$a" = "$b" ] || fail "acc_delta_depth differs: eval $a, metrics $b"

check_bad() {  # name, expected text in the error, then the eval arguments
  local name="$1" text="$2"
  shift 2
  "$BIN" eval "$@" --quiet --out "$TMP/$name" >/dev/null 2>"$TMP/$name.err"
  local rc=$?
  [ $rc -eq 2 ] || fail "$name: expected exit 2, got $rc ($(cat "$TMP/$name.err"))"
  grep -q -- "$text" "$TMP/$name.err" || fail "$name: error does not name '$text': $(cat "$TMP/$name.err")"
  [ "$(wc -l < "$TMP/$name.err")" -eq 1 ] || fail "$name: error is not one line"
  [ ! -e "$TMP/$name" ] || fail "$name: output folder written on failure"
}
base=(--scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --cameras "$S/cameras.json")
check_bad nocams "nope.json" --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --cameras "$TMP/nope.json" \
  --labels "$S/labels.npy"
printf 'garbage' > "$TMP/bad.npy"
check_bad badrefined "bad.npy" "${base[@]}" --labels "$S/labels.npy" --refined "$TMP/bad.npy"
check_bad shortlabels "removed_gc.npy" "${base[@]}" --labels "$S/removed_gc.npy"
check_bad nomasks "no_masks" "${base[@]}" --object-masks "$TMP/no_masks"
# A corrupt object mask part-way through the views: the run fails and leaves nothing behind.
mkdir -p "$TMP/masks"
cp "$S"/masks/*.png "$TMP/masks/"
last=$(ls "$TMP/masks" | sort | tail -1)
printf 'garbage' > "$TMP/masks/$last"
check_bad corruptmask "$last" "${base[@]}" --object-masks "$TMP/masks"
ls "$TMP" | grep -q 'eval-tmp' && fail "staging folder left behind after a failure"

# Neither --object-masks nor --labels: usage error.
"$BIN" eval "${base[@]}" --out "$TMP/u" >/dev/null 2>&1
[ $? -eq 1 ] || fail "missing object source should exit 1"
echo "OK: eval CLI"
