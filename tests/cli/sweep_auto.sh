#!/usr/bin/env bash
# refine --auto (issue #7 part 3): the chosen point is the best-scoring grid point, the refinement
# ran with it, the runner-up is the second best; the criterion is decision stability without
# cameras and acc_delta_depth_float - collateral_depth with them, acc only over the views no
# candidate's trust flags mark (issue 16; every view flagged: stability decides); ground truth is
# only reported.
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
"$BIN" synth --preset counter --gaussians 8000 --seed 1 --views 2 --resolution 40x30 --quiet --out "$T/s" >/dev/null
COMMON=(--scene "$T/s/scene.ply" --removed "$T/s/removed_gc.npy" --labels "$T/s/labels.npy" --solver bk --quiet
        --auto --auto-k 4,8 --auto-delta 0.8,1.2 --auto-lambda 1,2)
"$BIN" refine "${COMMON[@]}" --out "$T/stab" > "$T/stab.txt"
# 40x30 views: the object covers < 256 px in both, so every view is flagged small_object.
"$BIN" refine "${COMMON[@]}" --cameras "$T/s/cameras.json" --object-masks "$T/s/masks" --out "$T/flagged" >/dev/null
# A room at 120x90 with 4 views: some views trusted, some flagged.
"$BIN" synth --preset room --gaussians 8000 --seed 1 --views 4 --resolution 120x90 --quiet --out "$T/r" >/dev/null
"$BIN" refine --scene "$T/r/scene.ply" --removed "$T/r/removed_gc.npy" --labels "$T/r/labels.npy" --solver bk --quiet \
  --auto --auto-k 4,8 --auto-delta 0.8,1.2 --auto-lambda 1,2 --cameras "$T/r/cameras.json" --object-masks "$T/r/masks" \
  --out "$T/eval" >/dev/null
grep -q "chosen" "$T/stab.txt" && grep -q "runner-up" "$T/stab.txt" || { echo "FAIL: no chosen/runner-up lines"; cat "$T/stab.txt"; exit 1; }
python3 - "$T" <<'PY'
import json, sys, os
T = sys.argv[1]
def fail(msg): print('FAIL:', msg); sys.exit(1)
for run, criterion in (('stab', 'stability'), ('eval', 'eval'),
                       ('flagged', 'stability (eval: acc_delta_depth flagged in every view)')):
    rep = json.load(open(os.path.join(T, run, 'report.json')))
    a = rep['auto']
    c = a['candidates']
    if a['criterion'] != criterion: fail('%s: criterion %s' % (run, a['criterion']))
    if len(c) != 8: fail('%s: %d candidates, expected 8' % (run, len(c)))
    grid = [(x['k'], x['delta'], x['lambda']) for x in c]
    if grid != [(k, d, l) for k in (4, 8) for d in (0.8, 1.2) for l in (1.0, 2.0)]: fail('%s: grid order %s' % (run, grid))
    scores = [x['score'] for x in c]
    ch, ru = a['chosen'], a['runner_up']
    first_best = scores.index(max(scores))
    if (ch['k'], ch['delta'], ch['lambda']) != grid[first_best]: fail('%s: chosen is not the first best score' % run)
    second = sorted(range(8), key=lambda i: (-scores[i], i))[1]
    if (ru['k'], ru['delta'], ru['lambda']) != grid[second]: fail('%s: runner-up is not the second best' % run)
    p = rep['params']
    if (p['k'], p['delta'], p['lambda']) != (ch['k'], ch['delta'], ch['lambda']): fail('%s: refine did not run the chosen point' % run)
    if abs(rep['gt']['after']['f1'] - ch['gt_f1']) > 1e-12: fail('%s: refined F1 differs from the chosen candidate' % run)
    if a['best_by_gt']['gt_f1'] != max(x['gt_f1'] for x in c): fail('%s: best_by_gt' % run)
    if criterion.startswith('stability'):
        if any(not (0 <= s <= 1) for s in scores): fail('stability scores outside [0, 1]: %s' % scores)
        # A point that changes nothing has no boundary to be stable on: its Jaccard with any
        # neighbour is 0 (two empty sets included), so its score is 0.
        if any(x['added'] + x['restored'] == 0 and x['score'] != 0 for x in c): fail('do-nothing point scored > 0')
        # The score is the mean Jaccard over the one-step grid neighbours the report lists, and
        # the similarity of a pair is the same seen from either end.
        for i, x in enumerate(c):
            nb = dict(x['neighbours'])
            steps = {j for j in range(8) if sum(a != b for a, b in zip(grid[i], grid[j])) == 1}
            if set(nb) != steps: fail('%s: neighbours of %d are %s, expected %s' % (run, i, sorted(nb), sorted(steps)))
            if abs(x['score'] - sum(nb.values()) / len(nb)) > 1e-12: fail('%s: score is not the neighbours\' mean' % run)
            if any(abs(v - dict(c[j]['neighbours'])[i]) > 1e-15 for j, v in nb.items()): fail('%s: asymmetric Jaccard' % run)
    if run == 'flagged' and not all(v['flags_float'] for v in c[0]['eval']['views']): fail('flagged: a view is trusted')
    if criterion == 'eval':
        flagged = {v['view'] for x in c for v in x['eval']['views'] if v['flags_float']}
        every = {v['view'] for v in c[0]['eval']['views']}
        trusted = sorted(every - flagged)
        if not flagged or not trusted: fail('eval: want both trusted and flagged views, flagged %s' % flagged)
        for x in c:
            e, views = x['eval'], x['eval']['views']
            if e['score_views'] != trusted: fail('eval: score views %s, trusted %s' % (e['score_views'], trusted))
            acc = sum(v['acc_delta_depth_float'] for v in views if v['view'] in trusted) / len(trusted)
            coll = sum(v['collateral_depth'] for v in views) / len(views)
            if abs(x['score'] - (acc - coll)) > 1e-12: fail('eval score %s' % x)
            if abs(coll - e['collateral_depth']) > 1e-12: fail('eval collateral %s' % x)
            if e['views_evaluated'] != len(views) or e['views_evaluated'] < 1: fail('views evaluated')
    if os.path.exists(os.path.join(T, run, '.auto_eval')): fail('scratch folder left behind')
print('auto ok: stability and eval criteria (flagged views excluded), chosen/runner-up consistent')
PY
# Gates so tight that half the grid has no edge: those points change nothing, and agreeing on
# nothing is no plateau (before, their stability 1 chose one of them and refinement did nothing).
"$BIN" refine "${COMMON[@]::${#COMMON[@]}-7}" --auto --auto-k 4,8 --auto-delta 0,0.01,0.8 --auto-lambda 1,2 \
  --out "$T/tight" >/dev/null
python3 - "$T/tight/report.json" <<'PY'
import json, sys
a = json.load(open(sys.argv[1]))['auto']
empty = [x for x in a['candidates'] if x['added'] + x['restored'] == 0]
if len(empty) < 6: print('FAIL: expected the delta 0 / 0.01 points to change nothing'); sys.exit(1)
if any(x['score'] != 0 for x in empty): print('FAIL: a do-nothing point scored > 0'); sys.exit(1)
if a['chosen']['added'] + a['chosen']['restored'] == 0: print('FAIL: --auto chose to do nothing'); sys.exit(1)
print('auto ok: do-nothing points score 0')
PY
set +e
"$BIN" refine --scene "$T/s/scene.ply" --removed "$T/s/removed_gc.npy" --auto --auto-k 4.5 --out "$T/bad" >/dev/null 2>&1
[ $? -eq 1 ] || { echo "FAIL: --auto-k 4.5 accepted"; exit 1; }
"$BIN" refine --scene "$T/s/scene.ply" --removed "$T/s/removed_gc.npy" --cameras "$T/s/cameras.json" --out "$T/bad" >/dev/null 2>&1
[ $? -eq 1 ] || { echo "FAIL: --cameras without --auto accepted"; exit 1; }
"$BIN" refine --scene "$T/s/scene.ply" --removed "$T/s/removed_gc.npy" --auto --cameras "$T/s/cameras.json" --out "$T/bad" >/dev/null 2>&1
[ $? -eq 1 ] || { echo "FAIL: --auto --cameras without an object accepted"; exit 1; }
[ ! -e "$T/bad/report.json" ] || { echo "FAIL: output written on bad input"; exit 1; }
echo "bad input ok"
