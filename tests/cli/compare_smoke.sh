#!/usr/bin/env bash
# al-refine compare (issue #5 parts 7-8) on a small generated scene: one row per solver run (cp once
# per grid point, exact added as the reference), gaps measured against exact, F1 with --labels,
# CSV = JSON rows, the exported problem with one p per run; bad solver lists / grids / inputs give
# the documented exit codes and write nothing. Also refine --solver exact --threshold percentile:95
# reports the rule it ran (part 6).
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
"$BIN" synth --preset room --gaussians 20000 --seed 2 --views 2 --resolution 32x24 --no-masks --quiet --out "$T/s" >/dev/null
S=(--scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --method fgs)

"$BIN" compare "${S[@]}" --labels "$T/s/labels.npy" --solvers cp,bk --grid "cp_dif_tol=1e-2,1e-4" \
  --k 8 --delta 0.9 --out "$T/o" --export-problem "$T/o/problem" >"$T/stdout" 2>"$T/stderr"
grep -q "\[4/4\] exact" "$T/stderr" || fail "no progress line for the reference run: $(cat "$T/stderr")"
for f in report.json compare.csv compare.json tradeoff.gp tradeoff.dat; do
  [ -s "$T/o/$f" ] || fail "missing $f"
done
if command -v gnuplot >/dev/null; then [ -s "$T/o/tradeoff.png" ] || fail "gnuplot present but no tradeoff.png"; fi
python3 - "$T/o" <<'PY'
import csv, json, os, struct, sys
out = sys.argv[1]
def fail(m): print('FAIL:', m); sys.exit(1)
rep = json.load(open(os.path.join(out, 'report.json')))
rows = json.load(open(os.path.join(out, 'compare.json')))['rows']
ids = [r['id'] for r in rows]
if ids != ['cp_1', 'cp_2', 'bk', 'exact']: fail('runs %s' % ids)
if rep['command'] != 'compare' or rep['status'] != 'ok': fail('status %s' % rep['status'])
if rep['params']['k'] != 8 or rep['params']['delta'] != 0.9: fail('graph flags not applied: %s' % rep['params'])
if rep['grid'] != {'cp_dif_tol': [0.01, 0.0001]}: fail('grid %s' % rep['grid'])
if not rows[3]['reference_only'] or any(r['reference_only'] for r in rows[:3]): fail('reference flag')
fstar = rep['reference_objective']
for r in rows:
    if abs(r['gap'] - (r['objective'] - fstar) / abs(fstar)) > 1e-12: fail('gap of %s' % r['id'])
    if r['gap'] < -1e-9: fail('%s below the exact optimum: %g' % (r['id'], r['gap']))
    if not 0 <= r['gt']['f1'] <= 1: fail('F1 of %s' % r['id'])
if rows[1]['gap'] > 1e-3: fail('cp at tol 1e-4 is %g above exact' % rows[1]['gap'])
if rows[2]['gap'] <= 0: fail('bk (integral) should not reach the relaxed optimum')
table = list(csv.DictReader(open(os.path.join(out, 'compare.csv'))))
if [t['id'] for t in table] != ids: fail('CSV rows differ from JSON rows')
if table[0]['held_back'] == '' or int(table[0]['held_back']) != rows[0]['decision']['held_back']: fail('held_back column')
if json.loads(table[0]['options']) != {'cp_dif_tol': 0.01}: fail('CSV options %s' % table[0]['options'])
if any(abs(float(t['objective']) - r['objective']) > 1e-9 * abs(r['objective']) for t, r in zip(table, rows)):
    fail('CSV objectives differ from JSON')
d = os.path.join(out, 'problem')
sols = json.load(open(os.path.join(d, 'solutions.json')))
if [s['id'] for s in sols] != ids: fail('solutions.json %s' % sols)
V = rep['counts']['candidates']
for s in sols:
    b = open(os.path.join(d, s['file']), 'rb').read()
    n = int.from_bytes(b[8:10], 'little')
    p = struct.unpack('<%dd' % V, b[10 + n:])
    if any(not (0 <= x <= 1) for x in p): fail('%s outside [0, 1]' % s['file'])
for f in ['first_edge', 'adj_vertices', 'edge_weights', 'y', 'node_weights', 'node_ids']:
    if not os.path.exists(os.path.join(d, f + '.npy')): fail('missing %s.npy' % f)
print('compare ok:', ', '.join('%s gap %.3g F1 %.4f' % (r['id'], r['gap'], r['gt']['f1']) for r in rows))
PY

# --reference none without exact: gaps are null, with the reason.
"$BIN" compare "${S[@]}" --solvers bk --reference none --quiet --out "$T/n" >/dev/null
python3 - "$T/n/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert [x['id'] for x in r['rows']] == ['bk'] and r['rows'][0]['gap'] is None and r['gap_reason'], r['rows']
PY

# Empty graph: exit 3, report with status empty_graph and refine's advice, a header-only CSV.
set +e; "$BIN" compare "${S[@]}" --k 1 --delta 0 --quiet --out "$T/e" >/dev/null 2>"$T/e.err"; rc=$?; set -e
[ "$rc" = 3 ] || fail "empty graph: exit $rc ($(cat "$T/e.err"))"
grep -q "delta" "$T/e.err" || fail "empty graph message does not name delta"
python3 - "$T/e/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r['status'] == 'empty_graph' and r['rows'] == [] and r['counts']['edges'] == 0, r['status']
PY
[ "$(wc -l < "$T/e/compare.csv")" = 1 ] || fail "empty graph CSV has rows"

# Part 6: the decision rule is wired and reported for the relaxed solvers.
"$BIN" refine "${S[@]}" --solver exact --threshold percentile:95 --quiet --out "$T/r" >/dev/null
python3 - "$T/r/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert r['solver']['name'] == 'exact' and r['decision']['rule'] == 'percentile:95', (r['solver'], r['decision'])
assert r['counts']['added'] == r['decision']['added'], (r['counts'], r['decision'])
PY

# Errors: usage (1) for bad solver lists / grids / options, bad input (2) for files; nothing written.
expect() {
  local want="$1"; shift
  set +e; "$BIN" compare "$@" --out "$T/bad" >/dev/null 2>"$T/err"; local rc=$?; set -e
  [ "$rc" = "$want" ] || fail "compare $* -> exit $rc, want $want ($(cat "$T/err"))"
  [ -s "$T/err" ] || fail "no error message for: $*"
  [ ! -e "$T/bad" ] || fail "output written for a bad invocation: $*"
}
expect 1 "${S[@]}" --solvers bk,nope
expect 1 "${S[@]}" --solvers bk,bk
expect 1 "${S[@]}" --solvers cp --grid "cp_dif_tol=1e-2,abc"
expect 1 "${S[@]}" --solvers cp --grid "cp_dif_tol"
expect 1 "${S[@]}" --solvers cp --grid "no_such_option=1"
expect 1 "${S[@]}" --solvers bk --grid "cp_dif_tol=1e-3"
expect 1 "${S[@]}" --solvers cp --solver-options '{"cp":'
expect 1 "${S[@]}" --solvers bk --min-segment-share 1.5
expect 2 --scene "$T/missing.ply" --removed "$T/s/removed_fgs.npy" --method fgs
echo "compare cli ok"
