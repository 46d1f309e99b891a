#!/usr/bin/env bash
# refine --export-problem writes the exact problem the solver saw (issue #5 part 8): the CSR arrays
# agree with each other and with report.json, p has one value per node in [0, 1], and the nodes the
# decision added are nodes of the exported graph with p >= 0.5.
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
"$BIN" synth --preset room --gaussians 20000 --seed 3 --views 2 --resolution 32x24 --no-masks --quiet --out "$T/s" >/dev/null
"$BIN" refine --scene "$T/s/scene.ply" --removed "$T/s/removed_fgs.npy" --method fgs --solver cp --quiet \
  --out "$T/o" --export-problem "$T/o/problem" >/dev/null
python3 - "$T/o" <<'PY'
import json, struct, sys, os
out = sys.argv[1]; d = os.path.join(out, 'problem')
def npy(name):
    b = open(os.path.join(d, name + '.npy'), 'rb').read()
    n = int.from_bytes(b[8:10], 'little'); h = b[10:10 + n].decode()
    descr = h.split("'descr': '")[1][:3]
    shape = eval(h.split("'shape': ")[1].split(')')[0] + ')')
    fmt = {'<i8': 'q', '<f8': 'd'}[descr]
    count = 1
    for s in shape: count *= s
    return shape, struct.unpack('<%d%s' % (count, fmt), b[10 + n:])
def fail(msg): print('FAIL:', msg); sys.exit(1)
rep = json.load(open(os.path.join(out, 'report.json')))
(_, first), (_, adj), (_, w) = npy('first_edge'), npy('adj_vertices'), npy('edge_weights')
(yshape, y), (_, nw), (_, ids), (_, p) = npy('y'), npy('node_weights'), npy('node_ids'), npy('p')
V = len(ids)
if V != rep['counts']['candidates']: fail('V %d != candidates %d' % (V, rep['counts']['candidates']))
if len(first) != V + 1 or first[0] != 0 or first[-1] != len(adj): fail('first_edge is not a CSR index')
if len(adj) != rep['counts']['edges'] or len(w) != len(adj): fail('edge count mismatch')
if any(a < 0 or a >= V for a in adj) or any(not (x >= 0) for x in w): fail('bad edge targets or weights')  # exp() may underflow to 0
if yshape != (V, 2) or any(abs(y[2*i] + y[2*i+1] - 1) > 1e-12 for i in range(V)): fail('y rows are not on the simplex')
if len(nw) != V or len(p) != V or any(not (0 <= x <= 1) for x in p): fail('p outside [0, 1]')
params = json.load(open(os.path.join(d, 'params.json')))
if params.get('metric') != 'd1' or 's' not in params: fail('params.json: %s' % params)
added = [int(l) for l in open(os.path.join(out, 'added.txt')) if l.strip() and not l.startswith('#')]
pos = {g: i for i, g in enumerate(ids)}
for g in added:
    if g not in pos or p[pos[g]] < 0.5: fail('added Gaussian %d is not a graph node with p >= 0.5' % g)
print('export ok: V=%d E=%d added=%d' % (V, len(adj), len(added)))
PY
