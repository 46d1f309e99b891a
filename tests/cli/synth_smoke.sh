#!/usr/bin/env bash
# `al-refine synth` writes the documented layout, is deterministic in the seed, and rejects bad flags.
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
args=(synth --preset counter --gaussians 12000 --seed 5 --views 4 --resolution 64x48 --quiet)
"$BIN" "${args[@]}" --out "$T/a" > /dev/null
"$BIN" "${args[@]}" --out "$T/b" > /dev/null
for f in scene.ply labels.npy target.json cameras.json report.json removed_fgs.npy removed_sags.npy \
         removed_gg.npy removed_gc.npy masks/view_000.png masks/view_003.png; do
  [ -s "$T/a/$f" ] || { echo "missing $f"; exit 1; }
done
for f in scene.ply labels.npy removed_fgs.npy removed_sags.npy removed_gg.npy removed_gc.npy masks/view_001.png; do
  cmp -s "$T/a/$f" "$T/b/$f" || { echo "not deterministic: $f"; exit 1; }
done
grep -q '"object_id"' "$T/a/target.json" || { echo "target.json lacks object_id"; exit 1; }
grep -q 'element vertex 12000' "$T/a/scene.ply" || { echo "wrong vertex count"; exit 1; }
grep -aq 'property float semantic_15' "$T/a/scene.ply" || { echo "no semantic_15"; exit 1; }
grep -q '"status": "ok"' "$T/a/report.json" || { echo "report status"; exit 1; }
# A different seed gives a different scene.
"$BIN" synth --preset counter --gaussians 12000 --seed 6 --views 4 --resolution 64x48 --quiet --out "$T/c" > /dev/null
if cmp -s "$T/a/scene.ply" "$T/c/scene.ply"; then echo "seed ignored"; exit 1; fi
# Bad input: unknown preset and bad resolution are usage errors, nothing written.
set +e
"$BIN" synth --preset kitchen --gaussians 12000 --out "$T/d" 2> /dev/null; rc1=$?
"$BIN" synth --preset room --gaussians 12000 --resolution 64by48 --out "$T/e" 2> /dev/null; rc2=$?
"$BIN" synth --preset room --gaussians 12000 --feature-dim 600 --out "$T/f" 2> /dev/null; rc3=$?
set -e
[ "$rc1" -ne 0 ] && [ "$rc2" -ne 0 ] && [ "$rc3" -ne 0 ] || { echo "bad flags accepted: $rc1 $rc2 $rc3"; exit 1; }
[ ! -e "$T/e/scene.ply" ] && [ ! -e "$T/f/scene.ply" ] || { echo "output written on error"; exit 1; }
echo ok
