#!/usr/bin/env bash
# Reliability (issue #14, docs/reliability.md): memory bounds. A render and a PNG decode over the
# memory limit are refused from their estimates (exit 2, message with the estimate and the limit)
# in < 2 s with a peak RSS < 200 MB; an allocation failure ends with exit 2 and a message, never 4.
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
"$BIN" synth --gaussians 12000 --seed 4 --views 2 --resolution 32x24 --quiet --out "$T/s" >/dev/null
python3 "$HERE/make_degenerate.py" png "$T/big.png" 20000 20000    # ~100 KB file, 400 MB of pixels
mkdir -p "$T/masks"
for v in $(python3 -c "import json; print(' '.join(c['img_name'] for c in json.load(open('$T/s/cameras.json'))))"); do
  cp "$T/big.png" "$T/masks/$v.png"
done
python3 - "$BIN" "$T" <<'PY'
import os, subprocess, sys, time
BIN, T = sys.argv[1], sys.argv[2]
S = os.path.join(T, "s")
def fail(msg):
    print("FAIL:", msg); sys.exit(1)
def measure(args, env=None, preexec=None):
    t0 = time.monotonic()
    p = subprocess.Popen([BIN] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=env,
                         preexec_fn=preexec)
    err = p.stderr.read()
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    return p.returncode, time.monotonic() - t0, usage.ru_maxrss / 1024.0, err
def refused(what, args, **kw):
    code, secs, rss, err = measure(args, **kw)
    if code != 2: fail("%s: exit %d, expected 2: %s" % (what, code, err))
    if "memory limit" not in err or "needs about" not in err: fail("%s: message lacks estimate/limit: %s" % (what, err))
    if secs >= 2.0: fail("%s: took %.2f s" % (what, secs))
    if rss >= 200: fail("%s: peak RSS %.0f MB" % (what, rss))
    print("%s: refused in %.2f s, RSS %.0f MB: %s" % (what, secs, rss, err.strip().splitlines()[-1][:150]))
# 20000x20000 render: ~15 GB estimated; refused under the default limit (half of physical memory)
# when the machine has < 30 GB, and under --max-memory 4G always.
refused("render 20000x20000", ["render", "--scene", S + "/scene.ply", "--cameras", S + "/cameras.json",
        "--width", "20000", "--height", "20000", "--max-memory", "4G", "--out", T + "/r"])
refused("render 65536x65536 (default limit)", ["render", "--scene", S + "/scene.ply", "--cameras", S + "/cameras.json",
        "--width", "65536", "--height", "65536", "--out", T + "/r"])
refused("PNG 20000x20000 object mask", ["eval", "--scene", S + "/scene.ply", "--removed", S + "/removed_fgs.npy",
        "--cameras", S + "/cameras.json", "--object-masks", T + "/masks", "--max-memory", "256M", "--quiet",
        "--out", T + "/e"])
if os.path.exists(T + "/r") or os.path.exists(T + "/e"): fail("a refused run left an output folder")
# Allocation failure (address space capped at 300 MB, a 3M-Gaussian synth needs more): exit 2, not 4.
import resource
def cap():
    resource.setrlimit(resource.RLIMIT_AS, (300 << 20, 300 << 20))
code, secs, rss, err = measure(["synth", "--gaussians", "3000000", "--views", "1", "--no-masks", "--quiet",
                                "--threads", "1", "--out", T + "/big"], preexec=cap)
if code != 2 or "out of memory" not in err: fail("allocation failure: exit %d (expected 2): %s" % (code, err))
print("allocation failure: exit 2: " + err.strip().splitlines()[-1][:120])
PY
echo "reliability bounds OK"
