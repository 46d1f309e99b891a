#!/usr/bin/env bash
# sweep --manifest (issue #7 part 1): two scenes from one manifest with relative paths, one of them
# with cameras and object masks (evaluator metrics per point), the other with labels only; records
# are named by scene, each scene's inputs are in the report, and the evaluated scene's records
# carry eval metrics equal to `al-refine eval` on `al-refine refine`'s output for that point.
set -euo pipefail
BIN="$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"   # the sweep runs from another folder
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
"$BIN" synth --preset room --gaussians 6000 --seed 4 --views 2 --resolution 40x30 --quiet --out "$T/a" >/dev/null
"$BIN" synth --preset garden --gaussians 6000 --seed 5 --views 2 --resolution 40x30 --no-masks --quiet --out "$T/b" >/dev/null
cat > "$T/scenes.json" <<'JSON'
[{"name": "roomA", "scene": "a/scene.ply", "removed": "a/removed_gc.npy", "labels": "a/labels.npy",
  "cameras": "a/cameras.json", "object_masks": "a/masks"},
 {"name": "gardenB", "scene": "b/scene.ply", "removed": "b/removed_fgs.npy", "method": "fgs", "labels": "b/labels.npy"}]
JSON
(cd / && "$BIN" sweep --manifest "$T/scenes.json" --grid "k=4,8;solver=bk" --out "$T/out" 2>"$T/err" >/dev/null)
"$BIN" refine --scene "$T/a/scene.ply" --removed "$T/a/removed_gc.npy" --k 4 --solver bk --quiet --out "$T/r" >/dev/null
"$BIN" eval --scene "$T/a/scene.ply" --removed "$T/a/removed_gc.npy" --refined "$T/r/refined.npy" \
  --cameras "$T/a/cameras.json" --object-masks "$T/a/masks" --no-images --quiet --out "$T/ev" >/dev/null
python3 - "$T" <<'PY'
import json, sys, os
T = sys.argv[1]
def fail(msg): print('FAIL:', msg); sys.exit(1)
recs = [json.loads(l) for l in open(os.path.join(T, 'out', 'results.jsonl'))]
if [r['scene'] for r in recs] != ['roomA', 'roomA', 'gardenB', 'gardenB']: fail('scene order %s' % [r['scene'] for r in recs])
if [r['params']['k'] for r in recs] != [4, 8, 4, 8]: fail('k order')
if recs[2]['params']['method'] != 'fgs' or recs[0]['params']['method'] != 'generic': fail('per-scene method')
for r in recs[:2]:
    e = r.get('eval')
    if not e or e['views_evaluated'] < 1 or not (0 <= e['collateral_depth'] <= 1): fail('roomA eval %s' % e)
if any('eval' in r for r in recs[2:]): fail('gardenB has no cameras but got eval metrics')
rep = json.load(open(os.path.join(T, 'out', 'report.json')))
if set(rep['inputs']) != {'roomA', 'gardenB'}: fail('inputs %s' % list(rep['inputs']))
if rep['counts']['graphs_built'] != 4 or rep['counts']['records'] != 4: fail('counts %s' % rep['counts'])
csv = [l.split(',') for l in open(os.path.join(T, 'out', 'results.csv')).read().splitlines()]
col, scol = csv[0].index('eval_collateral_depth'), csv[0].index('scene')
if any((row[col] != '') != (row[scol] == 'roomA') for row in csv[1:]): fail('CSV eval column')
# The same point through refine + eval gives the same evaluator numbers.
ev = json.load(open(os.path.join(T, 'ev', 'report.json')))['metrics']['columns'][1]
e = recs[0]['eval']
for got, want in ((e['acc_delta_depth'], ev['depth']['mean_acc_delta_depth']),
                  (e['acc_delta_depth_float'], ev['depth_float']['mean_acc_delta_depth']),
                  (e['collateral_depth'], ev['depth']['collateral_depth']['mean'])):
    if abs(got - want) > 1e-12: fail('sweep eval %s != eval %s' % (got, want))
print('manifest ok')
PY
[ "$(grep -c '^sweep  point' "$T/err")" -eq 4 ] || { echo "FAIL: expected 4 progress lines"; cat "$T/err"; exit 1; }
# A missing file in the manifest is bad input, reported before any point runs.
sed 's#b/labels.npy#b/nope.npy#' "$T/scenes.json" > "$T/bad.json"
set +e
"$BIN" sweep --manifest "$T/bad.json" --grid "k=4" --out "$T/bad" >/dev/null 2>"$T/bad.err"
[ $? -eq 2 ] || { echo "FAIL: missing labels in the manifest not exit 2"; exit 1; }
grep -q "nope.npy" "$T/bad.err" || { echo "FAIL: error does not name the file"; exit 1; }
[ ! -s "$T/bad/results.jsonl" ] || { echo "FAIL: points ran despite bad input"; exit 1; }
echo "bad manifest ok"
set -e
# λ auto in a sweep resolves per scene and solver as refine would (gg with bk: 1.5, cp: 1; the
# generic preset: 1); a λ the grid names is used as given.
cat > "$T/gg.json" <<'JSON'
[{"name": "gg", "scene": "b/scene.ply", "removed": "b/removed_gg.npy", "method": "gg"},
 {"name": "plain", "scene": "b/scene.ply", "removed": "b/removed_gg.npy"}]
JSON
"$BIN" sweep --manifest "$T/gg.json" --grid "solver=bk,cp;lambda=auto,0.5" --out "$T/gg" >/dev/null 2>&1
python3 - "$T/gg/results.jsonl" <<'PY'
import json, sys
recs = {(r['scene'], r['params']['solver'], r['params']['lambda_auto']): r for r in map(json.loads, open(sys.argv[1]))}
want = {('gg', 'bk', True): 1.5, ('gg', 'cp', True): 1.0, ('plain', 'bk', True): 1.0, ('plain', 'cp', True): 1.0,
        ('gg', 'bk', False): 0.5, ('gg', 'cp', False): 0.5, ('plain', 'bk', False): 0.5, ('plain', 'cp', False): 0.5}
if set(recs) != set(want): print('FAIL: records', sorted(recs)); sys.exit(1)
for k, lam in want.items():
    r = recs[k]
    if r["params"]["lambda"] != lam or r["graph"]["lambda"] != lam:
        print('FAIL: lambda of', k, r['params']['lambda'], 'want', lam); sys.exit(1)
    if ('lambda=auto' in r['id']) != k[2]: print('FAIL: id', r['id']); sys.exit(1)
print('sweep lambda auto ok')
PY
# A sweep point is the refine run with the same flags, candidate growth included (--grow-rounds;
# on this scene the second round changes the gg result: 278 refined with growth, 356 without).
"$BIN" synth --preset counter --gaussians 8000 --seed 3 --views 2 --resolution 40x30 --no-masks --quiet \
  --out "$T/c" >/dev/null
cat > "$T/grow.json" <<'JSON'
[{"name": "c", "scene": "c/scene.ply", "removed": "c/removed_gg.npy", "method": "gg", "labels": "c/labels.npy"}]
JSON
for rounds in 8 0; do
  "$BIN" sweep --manifest "$T/grow.json" --grid "solver=bk,cp" --grow-rounds $rounds --out "$T/grow$rounds" >/dev/null 2>&1
  for solver in bk cp; do
    "$BIN" refine --scene "$T/c/scene.ply" --removed "$T/c/removed_gg.npy" --method gg --labels "$T/c/labels.npy" \
      --solver $solver --grow-rounds $rounds --out "$T/grow_refine_$solver$rounds" --quiet >/dev/null 2>&1
    python3 - "$T/grow$rounds/results.jsonl" "$T/grow_refine_$solver$rounds" $solver <<'PY'
import json, sys
rec = [r for r in map(json.loads, open(sys.argv[1])) if r['params']['solver'] == sys.argv[3]][0]
rep = json.load(open(sys.argv[2] + '/report.json'))
refined = sum(open(sys.argv[2] + '/refined.npy', 'rb').read()[128:])
if rec['counts']['refined'] != rep['counts']['refined'] or rec['counts']['refined'] != refined:
    print('FAIL: sweep refined %d, refine %d' % (rec['counts']['refined'], rep['counts']['refined'])); sys.exit(1)
if rec['gt']['after']['f1'] != rep['gt']['after']['f1']: print('FAIL: F1 differs'); sys.exit(1)
if rec['growth']['rounds'] != rep['graph']['rounds']: print('FAIL: rounds', rec['growth'], rep['graph']['rounds']); sys.exit(1)
print('sweep = refine', sys.argv[3], rec['params']['grow_rounds'], rec['counts']['refined'], rec['growth']['rounds'])
PY
  done
done
