#!/usr/bin/env bash
# Reliability (issue #14, docs/reliability.md): inputs are never touched. An input inside --out that
# a run would replace, a foreign file under a name a run writes, and an unwritable --out are refused
# with exit 2 before any computation; --force replaces foreign files; special files given as inputs
# (FIFO, device, folder) are refused at once, never read.
set -uo pipefail
BIN="$1"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
expect() {  # expect CODE MAX_SECONDS -- command...
  local code="$1" max="$2"; shift 3
  local t0=$EPOCHREALTIME
  timeout 20 "$@" >"$T/stdout" 2>"$T/stderr"; local rc=$?
  local dt; dt=$(awk -v a="$t0" -v b="$EPOCHREALTIME" 'BEGIN { print b - a }')
  [ "$rc" = "$code" ] || { cat "$T/stderr"; fail "expected exit $code, got $rc: $*"; }
  awk -v d="$dt" -v m="$max" 'BEGIN { exit !(d < m) }' || fail "took ${dt}s (limit ${max}s): $*"
}
"$BIN" synth --gaussians 12000 --seed 2 --views 2 --resolution 32x24 --quiet --out "$T/s" >/dev/null || fail synth
S="$T/s"

# refine reading its own earlier output from --out: refused, the input untouched.
"$BIN" refine --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --method fgs --quiet --out "$T/o" >/dev/null || fail refine
before=$(sha256sum "$T/o/refined.npy")
expect 2 5 -- "$BIN" refine --scene "$S/scene.ply" --removed "$T/o/refined.npy" --quiet --out "$T/o"
grep -q "lies inside it" "$T/stderr" || fail "no input-inside-out message: $(cat "$T/stderr")"
[ "$(sha256sum "$T/o/refined.npy")" = "$before" ] || fail "refine changed its input"

# eval with --object-masks inside --out (the issue's case): refused, the masks untouched.
mkdir -p "$T/e"; cp -r "$S/masks" "$T/e/masks"
sum_masks() { find "$T/e/masks" -type f -exec sha256sum {} + | sort; }
masks_before=$(sum_masks)
expect 2 5 -- "$BIN" eval --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --cameras "$S/cameras.json" \
  --object-masks "$T/e/masks" --quiet --out "$T/e"
[ "$(sum_masks)" = "$masks_before" ] || fail "eval changed the object masks"

# A foreign file under a name refine writes: refused (exit 2) unless --force; unrelated files kept.
mkdir -p "$T/f"; echo mine > "$T/f/refined.txt"; echo keep > "$T/f/notes.txt"
expect 2 5 -- "$BIN" refine --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --method fgs --quiet --out "$T/f"
grep -q "no al-refine manifest" "$T/stderr" || fail "no foreign-file message"
[ "$(cat "$T/f/refined.txt")" = mine ] || fail "foreign file replaced without --force"
expect 0 30 -- "$BIN" refine --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --method fgs --quiet --force --out "$T/f"
[ "$(cat "$T/f/notes.txt")" = keep ] || fail "--force touched a file the run does not write"
"$BIN" info --verify "$T/f" >/dev/null || fail "set with a foreign file beside it does not verify"

# Unwritable --out: found at start (exit 2, fast), not after the computation.
echo x > "$T/file"
expect 2 3 -- "$BIN" refine --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --method fgs --quiet --out "$T/file"
expect 2 3 -- "$BIN" render --scene "$S/scene.ply" --cameras "$S/cameras.json" --out "$T/file/sub"
expect 2 3 -- "$BIN" eval --scene "$S/scene.ply" --removed "$S/removed_fgs.npy" --cameras "$S/cameras.json" \
  --object-masks "$S/masks" --quiet --out /proc/al_refine_out

# Special files as inputs: refused at once with a message naming what they are.
mkfifo "$T/fifo.ply" "$T/fifo.json" "$T/fifo.npy"
expect 2 2 -- "$BIN" info --scene "$T/fifo.ply"
grep -q "FIFO" "$T/stderr" || fail "FIFO not named: $(cat "$T/stderr")"
expect 2 2 -- "$BIN" refine --scene "$T/fifo.ply" --removed "$S/removed_fgs.npy" --quiet --out "$T/x"
expect 2 2 -- "$BIN" refine --scene "$S/scene.ply" --removed "$T/fifo.npy" --quiet --out "$T/x"
expect 2 2 -- "$BIN" render --scene "$S/scene.ply" --cameras "$T/fifo.json" --out "$T/x"
mkdir -p "$T/shard"; : > "$T/shard/results.jsonl"; mkfifo "$T/shard/shard.json"
expect 2 2 -- "$BIN" merge "$T/shard" --out "$T/x"
grep -q "FIFO" "$T/stderr" || fail "FIFO shard.json not named: $(cat "$T/stderr")"
expect 2 2 -- "$BIN" info --scene /dev/zero
expect 2 2 -- "$BIN" info --scene "$S"
[ ! -e "$T/x" ] || fail "a refused run left an output folder"
ls -a "$T" | grep -q "al-staging" && fail "a refused run left staging behind"
echo "reliability inputs OK"
