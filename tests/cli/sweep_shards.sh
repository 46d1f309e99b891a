#!/usr/bin/env bash
# sweep (issue #7 parts 1-2): the same grid run whole and as 3 shards + merge gives the same records
# (everything but timings), in the same order; a rerun skips every point; a results.jsonl cut in the
# middle of a line (a killed run) is repaired on resume and the lost point is recomputed identically.
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
trap '[ -n "${KEEP:-}" ] || rm -rf "$T"' EXIT
"$BIN" synth --preset room --gaussians 12000 --seed 3 --views 2 --resolution 32x24 --no-masks --quiet --out "$T/s" >/dev/null
ARGS=(--scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --method fgs --labels "$T/s/labels.npy"
      --grid "k=4,6;delta=0.8,1.0;lambda=0.5,2;solver=bk,cp" --solver-options '{"cp": {"cp_it_max": 3}}')
"$BIN" sweep "${ARGS[@]}" --quiet --out "$T/full" >/dev/null
for i in 0 1 2; do "$BIN" sweep "${ARGS[@]}" --quiet --shard "$i/3" --out "$T/shard$i" >/dev/null; done
"$BIN" merge "$T/shard2" "$T/shard0" "$T/shard1" "$T/shard0" --out "$T/merged" >/dev/null   # order and a repeat must not matter

# Resume: cut the whole run's file in the middle of its last line, rerun, expect one point rerun.
cp -r "$T/full" "$T/killed"
python3 - "$T/killed/results.jsonl" <<'PY'
import sys
p = sys.argv[1]; b = open(p, 'rb').read()
last = b.rstrip(b'\n').rfind(b'\n') + 1
open(p, 'wb').write(b[:last + (len(b) - last) // 2])   # half of the last line, no newline
PY
"$BIN" sweep "${ARGS[@]}" --out "$T/killed" >/dev/null 2>"$T/killed.err"
"$BIN" sweep "${ARGS[@]}" --quiet --out "$T/full" >/dev/null   # nothing left to do
# A complete last record without its newline is kept, and the next append starts a new line.
cp -r "$T/full" "$T/nonl"
python3 - "$T/nonl/results.jsonl" <<'PY'
import sys
p = sys.argv[1]; lines = open(p, 'rb').read().rstrip(b'\n').split(b'\n')
open(p, 'wb').write(b'\n'.join(lines[:-2] + [lines[-1]]))   # drop one record, no final newline
PY
"$BIN" sweep "${ARGS[@]}" --quiet --out "$T/nonl" >/dev/null

python3 - "$T" <<'PY'
import json, sys, os
T = sys.argv[1]
def fail(msg): print('FAIL:', msg); sys.exit(1)
def records(d):
    return [json.loads(l) for l in open(os.path.join(T, d, 'results.jsonl'))]
def strip(r): return {k: v for k, v in r.items() if k not in ('seconds', 'run')}
full, merged = records('full'), records('merged')
if len(full) != 16: fail('whole run has %d records, expected 16' % len(full))
if len({r['id'] for r in full}) != 16: fail('duplicate ids in the whole run')
shards = [records('shard%d' % i) for i in range(3)]
sizes = sorted(len(s) for s in shards)
if sizes != [5, 5, 6] or len({r['id'] for s in shards for r in s}) != 16: fail('shards are not a partition: %s' % sizes)
by_id = {r['id']: strip(r) for r in full}
if [strip(r) for r in merged] != [by_id[r['id']] for r in merged] or len(merged) != 16:
    fail('merged records differ from the whole run')
# merged order is the canonical order; the whole run's results.csv uses the same order
csv_ids = [l.split(',')[0] for l in open(os.path.join(T, 'full', 'results.csv')).read().splitlines()[1:]]
if csv_ids != [r['id'] for r in merged]: fail('results.csv order differs from the merged order')
rep = json.load(open(os.path.join(T, 'merged', 'report.json')))
if rep['counts']['duplicates'] != len(shards[0]) or rep['counts']['conflicts'] != 0: fail('merge counts %s' % rep['counts'])
if rep['status'] != 'ok' or rep['command'] != 'merge': fail('merge report')
import shutil
if shutil.which('gnuplot'):
    for chart in ('pareto.png', 'heatmap_f1_bk.png', 'heatmap_f1_cp.png'):
        if chart not in rep['outputs']['charts'] or not os.path.getsize(os.path.join(T, 'merged', chart)):
            fail('merge did not draw %s' % chart)
# graphs reused: 4 graph settings (k x delta) for 16 points
rep = json.load(open(os.path.join(T, 'full', 'report.json')))
c = rep['counts']
if c['ran'] != 0 or c['already_done'] != 16 or c['records'] != 16: fail('rerun did not skip every point: %s' % c)
killed = records('killed')
rk = json.load(open(os.path.join(T, 'killed', 'report.json')))
if rk['counts']['ran'] != 1 or len(killed) != 16: fail('resume after a truncated line: %s, %d records' % (rk['counts'], len(killed)))
if sorted(json.dumps(strip(r), sort_keys=True) for r in killed) != sorted(json.dumps(v, sort_keys=True) for v in by_id.values()):
    fail('resumed records differ from the whole run')
if not any('truncated' in w for w in rk['warnings']): fail('no warning about the truncated line')
nonl = records('nonl')
rn = json.load(open(os.path.join(T, 'nonl', 'report.json')))
if rn['counts']['ran'] != 1 or len(nonl) != 16 or sorted(r['id'] for r in nonl) != sorted(by_id):
    fail('resume after a last line without newline: %s' % rn['counts'])
# what each record carries
r = full[0]
for key in ('params', 'graph', 'solver', 'decision', 'counts', 'gt', 'seconds', 'status'):
    if key not in r: fail('record lacks %s' % key)
if set(r['params']) < {'k', 'delta', 'lambda', 'solver', 'hops', 'threshold'}: fail('params %s' % r['params'])
# lambda only rescales: same graph statistics for the two lambdas of a (k, delta), but the
# applied scale, which the graph record names
g = {}
for r in full:
    key = (r['params']['k'], r['params']['delta'])
    if r['graph']['lambda'] != r['params']['lambda']: fail('graph lambda %s' % r['graph']['lambda'])
    g.setdefault(key, set()).add(json.dumps({k: v for k, v in r['graph'].items() if k != 'lambda'}, sort_keys=True))
if any(len(v) != 1 for v in g.values()): fail('graph statistics differ within a (k, delta) setting')
print('sweep shards ok: 16 points, shards %s, merged == whole run, resume ok' % sizes)
PY
# The progress lines name the point and its F1 (one per point).
grep -q "point 16/16 .*F1" "$T/killed.err" || { echo "FAIL: no progress line for the resumed point"; cat "$T/killed.err"; exit 1; }
# Bad input: bad shard, unknown grid key, manifest and --scene together.
set +e
"$BIN" sweep "${ARGS[@]}" --shard 3/3 --out "$T/bad" >/dev/null 2>&1; [ $? -eq 1 ] || { echo "FAIL: --shard 3/3 accepted"; exit 1; }
"$BIN" sweep --scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --grid "kk=1" --out "$T/bad" >/dev/null 2>&1
[ $? -eq 1 ] || { echo "FAIL: unknown grid key accepted"; exit 1; }
"$BIN" merge "$T/s" --out "$T/bad" >/dev/null 2>&1; [ $? -eq 2 ] || { echo "FAIL: merge of a non-sweep dir"; exit 1; }
[ ! -e "$T/bad/results.jsonl" ] || { echo "FAIL: output written on bad input"; exit 1; }
echo "bad input ok"

# merge checks its inputs (issue #18): every folder must be a shard of one sweep (shard.json), and
# a set with a shard or a point missing is refused unless --allow-partial.
expect_refusal() {  # expect_refusal NAME PATTERN COMMAND...: exit 2, PATTERN on stdout+stderr, no output folder
  local name="$1" pattern="$2" rc
  shift 2
  set +e
  "$@" >"$T/$name.out" 2>&1
  rc=$?
  set -e
  [ $rc -eq 2 ] && grep -q -- "$pattern" "$T/$name.out" || { cat "$T/$name.out"; echo "FAIL: $name (rc $rc, expected 2 and '$pattern')"; exit 1; }
  [ ! -e "$T/m_$name" ] || { echo "FAIL: $name: a refused merge wrote an output"; exit 1; }
}
expect_refusal missing "^incomplete shards: 1$" "$BIN" merge "$T/shard0" "$T/shard2" --out "$T/m_missing"
grep -q "no folder for shard 1 (of 3)" "$T/missing.out" || { echo "FAIL: the missing shard is not named"; exit 1; }
"$BIN" merge "$T/shard0" "$T/shard2" --allow-partial --out "$T/partial" >"$T/partial.out" 2>&1
"$BIN" merge "$T/shard0" "$T/shard1" "$T/shard2" --check >"$T/check.out"
grep -q "16 of 16 points .*: complete" "$T/check.out" || { cat "$T/check.out"; echo "FAIL: --check"; exit 1; }
cp -r "$T/shard1" "$T/cut1"   # a killed shard: 2 of its 5 points written
head -n 2 "$T/shard1/results.jsonl" >"$T/cut1/results.jsonl"
expect_refusal cut "cut1: 2 of 5 points" "$BIN" merge "$T/shard0" "$T/cut1" "$T/shard2" --out "$T/m_cut"
grep -q "^incomplete shards: 1$" "$T/cut.out" || { echo "FAIL: the partial shard is not listed"; exit 1; }
# Shards of other sweeps: another grid, another shard count (a stale folder), other fixed flags, another binary.
"$BIN" sweep "${ARGS[@]/k=4,6/k=4,8}" --quiet --shard 1/3 --out "$T/grid1" >/dev/null
expect_refusal grid "grid (k: \[4,6\] vs \[4,8\])" "$BIN" merge "$T/shard0" "$T/grid1" "$T/shard2" --out "$T/m_grid"
"$BIN" sweep "${ARGS[@]}" --quiet --shard 3/4 --out "$T/n4" >/dev/null
expect_refusal count "shard count (3 vs 4)" "$BIN" merge "$T/shard0" "$T/shard1" "$T/shard2" "$T/n4" --out "$T/m_count"
"$BIN" sweep "${ARGS[@]/cp_it_max\": 3/cp_it_max\": 4}" --quiet --shard 1/3 --out "$T/flags1" >/dev/null
expect_refusal flags "fixed flags (solver_options.cp.cp_it_max: 3 vs 4)" "$BIN" merge "$T/shard0" "$T/flags1" "$T/shard2" --out "$T/m_flags"
cp -r "$T/shard1" "$T/bin1"
python3 -c "import json,sys; p=sys.argv[1]; j=json.load(open(p)); j['binary']['sha256']='0'*64; json.dump(j, open(p,'w'))" "$T/bin1/shard.json"
expect_refusal binary "binary (sha256: " "$BIN" merge "$T/shard0" "$T/bin1" "$T/shard2" --out "$T/m_binary"
# sweep will not resume a folder of another sweep or shard; an unsharded run may grow its grid.
expect_refusal resume_grid "already holds another shard or sweep (there vs here: grid" "$BIN" sweep "${ARGS[@]/k=4,6/k=4,8}" --quiet --shard 0/3 --out "$T/shard0"
expect_refusal resume_shard "shard (0/3 vs 1/3)" "$BIN" sweep "${ARGS[@]}" --quiet --shard 1/3 --out "$T/shard0"
"$BIN" sweep "${ARGS[@]/k=4,6/k=4,6,8}" --quiet --out "$T/full" >"$T/grow.out"
grep -q "^sweep: 8 points run, 16 already done" "$T/grow.out" || { cat "$T/grow.out"; echo "FAIL: a grown grid did not resume"; exit 1; }
"$BIN" sweep "${ARGS[@]}" --dry-run --shard 2/3 --out "$T/dry" >"$T/dry.out"
grep -q "dry run: 16 points, 6 in shard 2/3" "$T/dry.out" && [ ! -e "$T/dry" ] || { cat "$T/dry.out"; echo "FAIL: --dry-run"; exit 1; }
python3 - "$T" <<'PY'
import json, sys, os
T = sys.argv[1]
def fail(msg): print('FAIL:', msg); sys.exit(1)
rep = json.load(open(os.path.join(T, 'partial', 'report.json')))
if rep['complete'] is not False or rep['missing_shards'] != [1] or rep['counts']['points_found'] != 11:
    fail('partial merge report: complete %s, missing %s, counts %s' % (rep['complete'], rep['missing_shards'], rep['counts']))
if sum(1 for _ in open(os.path.join(T, 'partial', 'results.jsonl'))) != 11: fail('partial merge records')
rep = json.load(open(os.path.join(T, 'merged', 'report.json')))
if rep['complete'] is not True or rep['counts']['points_total'] != 16 or rep['sweep']['shard_count'] != 3:
    fail('complete merge report %s' % rep['counts'])
info = json.load(open(os.path.join(T, 'shard2', 'shard.json')))
if (info['shard'], info['points_total'], info['first_point'], info['points_in_shard']) != ('2/3', 16, 10, 6): fail('shard.json %s' % info)
if len(info['binary']['sha256']) != 64 or not info['scenes'][0]['inputs']['scene']['sha256']: fail('shard.json identity')
print('merge checks ok: missing, partial, grid, shard count, flags, binary refused; --allow-partial, --check, --dry-run')
PY
