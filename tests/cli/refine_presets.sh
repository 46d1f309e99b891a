#!/usr/bin/env bash
# refine on a small generated scene: outputs, refinement only adds, ground-truth scores, each
# preset's input conventions (GG remaining PLY, SAGS removed-subset PLY, GC float polarity),
# the empty-graph exit code, and the FGS derived mask on a hand-made case.
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
jget() { python3 -c "import json,sys; r=json.load(open('$1')); print(eval('r'+sys.argv[1]))" "$2"; }
# Pure-Python .npy writer: npyw FILE DTYPE(b1|f8|f4) VALUES... [--shape R,C]
npyw() {
  python3 - "$@" <<'PY'
import struct, sys
path, dt, *vals = sys.argv[1:]
shape = None
if '--shape' in vals:
    i = vals.index('--shape'); shape = tuple(int(x) for x in vals[i+1].split(',')); vals = vals[:i]
shape = shape or (len(vals),)
fmt = {'b1': '?', 'f8': 'd', 'f4': 'f'}[dt]
conv = (lambda v: v == '1') if dt == 'b1' else float
descr = '|b1' if dt == 'b1' else '<' + dt
hdr = "{'descr': '%s', 'fortran_order': False, 'shape': %s, }" % (descr, str(shape) if len(shape) > 1 else '(%d,)' % shape[0])
hdr += ' ' * (63 - (10 + len(hdr)) % 64) + '\n'
with open(path, 'wb') as f:
    f.write(b'\x93NUMPY\x01\x00' + struct.pack('<H', len(hdr)) + hdr.encode())
    f.write(struct.pack('<%d%s' % (len(vals), fmt), *[conv(v) for v in vals]))
PY
}
# Reads a bool .npy mask and prints its indices (one line, space separated) or a count.
npy_true() {
  python3 - "$1" "${2:-list}" <<'PY'
import sys
b = open(sys.argv[1], 'rb').read(); n = int.from_bytes(b[8:10], 'little'); d = b[10 + n:]
idx = [i for i, v in enumerate(d) if v]
print(len(idx) if sys.argv[2] == 'count' else ' '.join(map(str, idx)))
PY
}

"$BIN" synth --preset room --gaussians 20000 --seed 3 --views 2 --resolution 32x24 --no-masks --quiet --out "$T/s" >/dev/null

# Out-of-range values are refused before any file is read (exit 1, the table's words), and no
# output folder appears.
for bad in "--threshold -1" "--knn-checks -5" "--k 0" "--hops 101" "--kl-smoothing 1" "--delta-mode cos" \
           "--second-object-tolerance 2" "--feature-group-tolerance -0.5" "--feature-group-bound maybe" \
           "--restore-window maybe" "--restore-window-mads -1"; do
  set +e
  msg=$("$BIN" --scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" $bad --out "$T/bad" 2>&1 >/dev/null)
  rc=$?
  set -e
  [ "$rc" = 1 ] || fail "$bad: exit $rc, expected 1 (usage)"
  name=$(echo "$bad" | sed 's/^--//; s/ .*//; s/-/_/g')
  echo "$msg" | grep -q "option '$name'" || fail "$bad: message does not name the option: $msg"
  [ ! -e "$T/bad" ] || fail "$bad: wrote $T/bad"
done

# FGS mask + ground truth.
"$BIN" --scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --method fgs --solver bk \
  --labels "$T/s/labels.npy" --out "$T/fgs" --quiet >/dev/null || fail "fgs run"
for f in refined.npy refined.txt added.txt remaining.ply report.json; do
  [ -s "$T/fgs/$f" ] || fail "missing $f"
done
[ "$(jget "$T/fgs/report.json" "['status']")" = ok ] || fail "status"
[ "$(jget "$T/fgs/report.json" "['params']['preset']['features']")" = semantic_ ] || fail "fgs preset"
in_n=$(npy_true "$T/s/removed_fgs.npy" count)
out_n=$(npy_true "$T/fgs/refined.npy" count)
added=$(jget "$T/fgs/report.json" "['counts']['added']")
restored=$(jget "$T/fgs/report.json" "['counts']['restored']")
[ "$out_n" = $((in_n + added - restored)) ] || fail "refined $out_n != removed $in_n + added $added - restored $restored"
[ "$(jget "$T/fgs/report.json" "['counts']['refined']")" = "$out_n" ] || fail "refined count"
[ "$(jget "$T/fgs/report.json" "['params']['restore']")" = auto ] || fail "restore is auto by default"
[ "$(jget "$T/fgs/report.json" "['decision']['restore']")" = True ] || fail "fgs restores by default"
[ "$(jget "$T/fgs/report.json" "['gt']['change']['added']")" = "$added" ] || fail "gt.change.added"
# The simulated FGS also took part of a look-alike: the report names the second object, and the
# prior credits no kept Gaussian unless --no-second-object-guard.
[ "$(jget "$T/fgs/report.json" "['graph']['second_object']['share'] >= 0.2")" = True ] || fail "second object not reported"
[ "$(jget "$T/fgs/report.json" "['graph']['prior']['kept_credit']")" = False ] || fail "kept credit with a second object"
jget "$T/fgs/report.json" "['warnings']" | grep -q "holds a second object" || fail "no second-object warning"
"$BIN" --scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --method fgs --solver bk --no-second-object-guard \
  --taken-whole-guard off --out "$T/fgs_unguarded" --quiet >/dev/null || fail "fgs --no-second-object-guard run"
[ "$(jget "$T/fgs_unguarded/report.json" "['params']['taken_whole_guard']")" = off ] || fail "taken-whole param"
[ "$(jget "$T/fgs/report.json" "['params']['taken_whole_guard']")" = auto ] || fail "taken-whole default"
[ "$(jget "$T/fgs_unguarded/report.json" "['graph']['prior']['kept_credit']")" = True ] || fail "guard not turned off"
[ "$(jget "$T/fgs_unguarded/report.json" "['params']['second_object_guard']")" = off ] || fail "guard param"
# With a second object the additions are read both ways (--second-object-tolerance): what was
# taken back plus what stays is what the parts were given.
[ "$(jget "$T/fgs/report.json" "['params']['second_object_tolerance']")" = 0.005 ] || fail "tolerance default"
python3 - "$T/fgs/report.json" <<'PY' || fail "either_object counts"
import json, sys
d = json.load(open(sys.argv[1]))["decision"]
e = d.get("either_object")
sys.exit(0 if e is None or sum(e["added"]) == d["added"] + e["trimmed"] else 1)
PY
# The feature-group bound (docs/refine.md items 13, 14) takes back by default only where the
# additions are a layer of a body that goes on (auto), with item 11's tolerance (out-of-range
# values: the loop at the top).
[ "$(jget "$T/fgs/report.json" "['params']['feature_group_tolerance']")" = 0.005 ] || fail "group tolerance default"
[ "$(jget "$T/fgs/report.json" "['params']['feature_group_bound']")" = auto ] || fail "feature-group bound default"
# --no-restore: refinement only adds.
"$BIN" --scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --method fgs --solver bk --no-restore \
  --labels "$T/s/labels.npy" --out "$T/fgs_add" --quiet >/dev/null || fail "fgs --no-restore run"
[ "$(jget "$T/fgs_add/report.json" "['counts']['restored']")" = 0 ] || fail "--no-restore restored"
python3 - "$T/s/removed_fgs.npy" "$T/fgs_add/refined.npy" <<'PY' || fail "refined is not a superset of removed"
import sys
def m(p):
    b = open(p, 'rb').read(); n = int.from_bytes(b[8:10], 'little'); return b[10 + n:]
a, r = m(sys.argv[1]), m(sys.argv[2])
sys.exit(0 if all((not x) or y for x, y in zip(a, r)) and len(a) == len(r) else 1)
PY
for key in precision recall f1 iou precision_w recall_w f1_w iou_w; do
  jget "$T/fgs/report.json" "['gt']['after']['$key']" >/dev/null || fail "gt.after.$key"
done
[ "$(jget "$T/fgs/report.json" "['solver']['name']")" = bk ] || fail "solver name"

# GG: the remaining-scene PLY of the run above; the preset implies --removed-is remaining.
"$BIN" --scene "$T/s/scene.ply" --removed "$T/fgs/remaining.ply" --method gg --features semantic_ \
  --solver bk --out "$T/gg" --quiet >/dev/null || fail "gg run"
[ "$(jget "$T/gg/report.json" "['params']['removed_is']")" = remaining ] || fail "gg removed_is"
[ "$(jget "$T/gg/report.json" "['counts']['removed_input']")" = "$out_n" ] || fail "gg matched count"
# A mask is the removed set for every preset (never complemented by the gg preset).
"$BIN" --scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --method gg --solver bk --out "$T/ggm" \
  --quiet >/dev/null 2>"$T/ggm.err" || fail "gg mask run"
[ "$(jget "$T/ggm/report.json" "['params']['removed_is']")" = removed ] || fail "gg mask removed_is"
[ "$(jget "$T/ggm/report.json" "['counts']['removed_input']")" = "$in_n" ] || fail "gg mask count"
grep -q "features semantic_" "$T/ggm.err" || fail "gg without obj_dc_ does not name its features"
# --lambda auto: gg with bk weighs the edges 1.5 (the preset's), with cp 1; a number wins.
[ "$(jget "$T/ggm/report.json" "['params']['lambda']")" = auto ] || fail "gg lambda param"
[ "$(jget "$T/ggm/report.json" "['graph']['lambda']")" = 1.5 ] || fail "gg bk lambda auto"
# The restore window (docs/refine.md item 15) is opt-in: off by default, and on, what it keeps
# removed plus what is still restored is what the cut restored.
"$BIN" --scene "$T/s/scene.ply" --removed "$T/s/removed_gg.npy" --method gg --solver bk --out "$T/rw_off" \
  --quiet >/dev/null 2>&1 || fail "gg run for the window"
"$BIN" --scene "$T/s/scene.ply" --removed "$T/s/removed_gg.npy" --method gg --solver bk --out "$T/rw_on" \
  --restore-window on --restore-window-mads 3 --quiet >/dev/null 2>&1 || fail "gg run with the window"
[ "$(jget "$T/rw_off/report.json" "['params']['restore_window']")" = auto ] || fail "restore-window default"
python3 - "$T/rw_off/report.json" "$T/rw_on/report.json" <<'PY' || fail "restore-window counts"
import json, sys
off, on = (json.load(open(p))["decision"] for p in sys.argv[1:])
w = on["restore_window"]
ok = "restore_window" not in off and w["prototype_rows"] > 0 and w["floor"] <= w["median"]
sys.exit(0 if ok and on["restored"] + w["kept"] == off["restored"] else 1)
PY
[ "$(jget "$T/ggm/report.json" "['params']['preset']['bk_lambda']")" = 1.5 ] || fail "gg preset bk_lambda"
"$BIN" --scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --method gg --solver cp --out "$T/ggcp" \
  --quiet >/dev/null 2>&1 || fail "gg cp run"
[ "$(jget "$T/ggcp/report.json" "['graph']['lambda']")" = 1.0 ] || fail "gg cp lambda auto"
"$BIN" --scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --method gg --solver bk --lambda 0.75 \
  --out "$T/ggl" --quiet >/dev/null 2>&1 || fail "gg --lambda run"
[ "$(jget "$T/ggl/report.json" "['graph']['lambda']")" = 0.75 ] || fail "explicit lambda not applied"
# More than half the scene removed: a warning on stderr and in the report.
"$BIN" --scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --removed-is remaining --solver bk --k 1 \
  --delta 0 --out "$T/most" --quiet >/dev/null 2>"$T/most.err" || true
grep -q "more than half the scene" "$T/most.err" || fail "no warning above half the scene"
jget "$T/most/report.json" "['warnings']" | grep -q "more than half" || fail "report lacks the half-scene warning"

# SAGS: a removed-subset PLY. Build it as the remaining.ply of an empty-graph run on the complement.
python3 - "$T/s/removed_fgs.npy" "$T/compl.npy" <<'PY'
import sys
b = open(sys.argv[1], 'rb').read(); n = int.from_bytes(b[8:10], 'little')
open(sys.argv[2], 'wb').write(b[:10 + n] + bytes(0 if v else 1 for v in b[10 + n:]))
PY
set +e
"$BIN" --scene "$T/s/scene.ply" --removed "$T/compl.npy" --solver bk --k 1 --delta 0 --out "$T/empty" --quiet >/dev/null 2>"$T/empty.err"
rc=$?
set -e
[ "$rc" = 3 ] || fail "empty graph exit code $rc"
[ "$(jget "$T/empty/report.json" "['status']")" = empty_graph ] || fail "empty status"
grep -q "delta" "$T/empty.err" || fail "empty-graph message"
cmp -s <(npy_true "$T/compl.npy") <(npy_true "$T/empty/refined.npy") || fail "empty graph changed the mask"
"$BIN" --scene "$T/s/scene.ply" --removed "$T/empty/remaining.ply" --method sags --solver bk \
  --out "$T/sags" --quiet >/dev/null || fail "sags run"
[ "$(jget "$T/sags/report.json" "['counts']['removed_input']")" = "$in_n" ] || fail "sags matched count"
# SAGS has no features of its own: the scene's semantic_* here (colour only without them).
[ "$(jget "$T/sags/report.json" "['params']['colour_fallback']")" = False ] || fail "sags took colour"
[ "$(jget "$T/sags/report.json" "['params']['feature_source']")" = "semantic_*" ] || fail "sags feature source"
# --feature-width auto: the sags preset's kernel is twice the gate bound; fgs keeps the gate's.
[ "$(jget "$T/sags/report.json" "['params']['feature_width']")" = auto ] || fail "feature width param"
[ "$(jget "$T/sags/report.json" "['graph']['sigma_f'] == 2 * r['graph']['gate_distance']")" = True ] || fail "sags sigma_f"
[ "$(jget "$T/fgs/report.json" "['graph']['sigma_f'] == r['graph']['gate_distance']")" = True ] || fail "fgs sigma_f"

# GC: float polarity (0 = removed), 5 Gaussians of a 20k scene.
python3 - "$T/gc.npy" <<'PY'
import struct, sys
hdr = "{'descr': '<f8', 'fortran_order': False, 'shape': (20000,), }"
hdr += ' ' * (63 - (10 + len(hdr)) % 64) + '\n'
vals = [0.0 if i in (10, 20, 30, 40, 50) else 1.0 for i in range(20000)]
open(sys.argv[1], 'wb').write(b'\x93NUMPY\x01\x00' + struct.pack('<H', len(hdr)) + hdr.encode() + struct.pack('<20000d', *vals))
PY
set +e
"$BIN" --scene "$T/s/scene.ply" --removed "$T/gc.npy" --method gc --solver bk --out "$T/gc" --quiet >/dev/null 2>&1
rc=$?
set -e
[ "$rc" = 0 ] || [ "$rc" = 3 ] || fail "gc run exit $rc"
[ "$(jget "$T/gc/report.json" "['counts']['removed_input']")" = 5 ] || fail "gc polarity"
[ "$(jget "$T/gc/report.json" "['params']['preset']['restore']")" = False ] || fail "gc preset restores"
# The same float array without --method gc is rejected (polarity is never guessed).
set +e
"$BIN" --scene "$T/s/scene.ply" --removed "$T/gc.npy" --solver bk --out "$T/gc2" --quiet >/dev/null 2>&1
rc=$?
set -e
[ "$rc" = 2 ] || fail "float mask without gc accepted (exit $rc)"

# FGS derived mask, hand-made: 4 Gaussians, 3 prompts (0 positive).
cat > "$T/tiny.ply" <<'PLY'
ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property float scale_0
property float scale_1
property float scale_2
property float semantic_0
property float semantic_1
property float semantic_2
end_header
0 0 0 -1 -1 -1 1 0 0
0.1 0 0 -1 -1 -1 0 1 0
0.2 0 0 -1 -1 -1 0.9 0.9 0
5 5 5 -1 -1 -1 0 0 1
PLY
npyw "$T/prompts.npy" f4 1 0 0 0 1 0 0 0 1 --shape 3,3
# Gaussian 0: argmax positive. 1 and 3: P_pos = 1/(2+e) = 0.21194 < 0.3. 2: tie 0/1 -> argmax = 0 (first).
"$BIN" --scene "$T/tiny.ply" --method fgs --prompt-embeddings "$T/prompts.npy" --positive 0 \
  --fgs-threshold 0.3 --solver bk --k 2 --delta 2 --out "$T/tiny" --quiet >/dev/null 2>&1 || true
[ "$(jget "$T/tiny/report.json" "['fgs_mask']['removed']")" = 2 ] || fail "fgs derived mask count"
[ "$(jget "$T/tiny/report.json" "['fgs_mask']['by_threshold_only']")" = 0 ] || fail "fgs by threshold"
# Threshold 0.2115: Gaussians 1 and 3 join by the share alone, both within 1e-3 of the threshold.
"$BIN" --scene "$T/tiny.ply" --method fgs --prompt-embeddings "$T/prompts.npy" --positive 0 \
  --fgs-threshold 0.2115 --solver bk --k 2 --delta 2 --out "$T/tiny2" --quiet >/dev/null 2>&1 || true
[ "$(jget "$T/tiny2/report.json" "['fgs_mask']['removed']")" = 4 ] || fail "fgs threshold-only"
[ "$(jget "$T/tiny2/report.json" "['fgs_mask']['by_threshold_only']")" = 2 ] || fail "fgs threshold-only count"
[ "$(jget "$T/tiny2/report.json" "['fgs_mask']['near_threshold']")" = 2 ] || fail "fgs near-threshold count"
echo "refine_presets: ok"
