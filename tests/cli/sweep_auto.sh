#!/usr/bin/env bash
# refine --auto (issue #7 part 3): the chosen point is the best-scoring grid point, the refinement
# ran with it, the runner-up is the second best; the criterion is decision stability without
# cameras and acc_delta_depth_float - collateral_depth with them; ground truth is only reported.
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
"$BIN" synth --preset counter --gaussians 8000 --seed 1 --views 2 --resolution 40x30 --quiet --out "$T/s" >/dev/null
COMMON=(--scene "$T/s/scene.ply" --removed "$T/s/removed_gc.npy" --labels "$T/s/labels.npy" --solver bk --quiet
        --auto --auto-k 4,8 --auto-delta 0.8,1.2 --auto-lambda 1,2)
"$BIN" refine "${COMMON[@]}" --out "$T/stab" > "$T/stab.txt"
"$BIN" refine "${COMMON[@]}" --cameras "$T/s/cameras.json" --object-masks "$T/s/masks" --out "$T/eval" >/dev/null
grep -q "chosen" "$T/stab.txt" && grep -q "runner-up" "$T/stab.txt" || { echo "FAIL: no chosen/runner-up lines"; cat "$T/stab.txt"; exit 1; }
python3 - "$T" <<'PY'
import json, sys, os
T = sys.argv[1]
def fail(msg): print('FAIL:', msg); sys.exit(1)
for run, criterion in (('stab', 'stability'), ('eval', 'eval')):
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
    if criterion == 'stability':
        if any(not (0 <= s <= 1) for s in scores): fail('stability scores outside [0, 1]: %s' % scores)
    else:
        for x in c:
            e = x['eval']
            if abs(x['score'] - (e['acc_delta_depth_float'] - e['collateral_depth'])) > 1e-12: fail('eval score %s' % x)
            if e['views_evaluated'] < 1: fail('no view evaluated')
    if os.path.exists(os.path.join(T, run, '.auto_eval')): fail('scratch folder left behind')
print('auto ok: stability and eval criteria, chosen/runner-up consistent')
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
