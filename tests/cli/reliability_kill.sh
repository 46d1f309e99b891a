#!/usr/bin/env bash
# Reliability (issue #14, docs/reliability.md): SIGKILL at several points of synth, refine, render,
# eval and sweep while they replace an earlier output set. After every kill the folder must hold
# the previous complete set or the new complete set (file hashes against reference runs, checked by
# the manifest and by `info --verify`); the next run must finish the set and leave no staging.
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
python3 - "$BIN" "$T" <<'PY'
import hashlib, json, os, shutil, signal, subprocess, sys, time
BIN, T = sys.argv[1], sys.argv[2]

def fail(msg):
    print("FAIL:", msg)
    sys.exit(1)

def run(args, check=True):
    p = subprocess.run([BIN] + args, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if check and p.returncode != 0:
        fail("%s exited %d: %s" % (" ".join(args[:2]), p.returncode, p.stderr.strip()))
    return p

def sha(path):
    return hashlib.sha256(open(path, "rb").read()).hexdigest()

def content(d, ignore=("report.json",)):
    """{relative path: sha256} of every file under d (what a reader sees)."""
    out = {}
    for root, _, files in os.walk(d):
        for f in files:
            rel = os.path.relpath(os.path.join(root, f), d)
            if rel not in ignore:
                out[rel] = sha(os.path.join(root, f))
    return out

def leftovers(parent, name):
    return [e for e in os.listdir(parent) if e.startswith("." + name + ".al-")]

S = os.path.join(T, "s")
run(["synth", "--gaussians", "12000", "--seed", "5", "--views", "3", "--resolution", "48x36", "--quiet", "--out", S])
scene, removed = os.path.join(S, "scene.ply"), os.path.join(S, "removed_fgs.npy")
cams, masks = os.path.join(S, "cameras.json"), os.path.join(S, "masks")
# Each command twice: an "old" and a "new" parameter set whose outputs differ.
commands = {
    "synth": lambda seed: ["synth", "--gaussians", "15000", "--seed", str(seed), "--views", "3",
                           "--resolution", "48x36", "--quiet"],
    "refine": lambda seed: ["refine", "--scene", scene, "--removed", os.path.join(S, ("removed_fgs.npy", "removed_gc.npy")[seed % 2]),
                            "--method", "fgs", "--quiet"],
    "render": lambda seed: ["render", "--scene", scene, "--cameras", cams, "--npy", "--width", str(40 + seed)],
    "eval": lambda seed: ["eval", "--scene", scene, "--removed", removed, "--cameras", cams,
                          "--object-masks", masks, "--quiet", "--bg", str(seed % 2)],
}
for name, make in commands.items():
    refs = {}
    for tag, seed in (("old", 1), ("new", 2)):
        d = os.path.join(T, name + "_ref_" + tag)
        t0 = time.monotonic()
        run(make(seed) + ["--out", d])
        refs[tag] = (content(d), time.monotonic() - t0)
        if run(["info", "--verify", d], check=False).returncode != 0:
            fail(name + ": reference set does not verify")
    if refs["old"][0] == refs["new"][0]:
        fail(name + ": old and new sets are identical, the test could not tell them apart")
    duration = refs["new"][1]
    seen = set()
    for frac in (0.1, 0.3, 0.5, 0.7, 0.85, 0.95, 1.05, 1.2, 1.5):
        out = os.path.join(T, name + "_out")
        shutil.rmtree(out, ignore_errors=True)
        shutil.copytree(os.path.join(T, name + "_ref_old"), out)
        p = subprocess.Popen([BIN] + make(2) + ["--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(frac * duration)
        p.send_signal(signal.SIGKILL)
        p.wait()
        now = content(out)
        which = "old" if now == refs["old"][0] else "new" if now == refs["new"][0] else None
        if which is None:
            fail("%s killed at %.2f s: the folder holds neither the previous nor the new set (%d files)"
                 % (name, frac * duration, len(now)))
        if run(["info", "--verify", out], check=False).returncode != 0:
            fail("%s killed at %.2f s: report.json does not describe the folder" % (name, frac * duration))
        seen.add(which)
        # The next run completes the set and removes what the killed one left beside it.
        run(make(2) + ["--out", out])
        if content(out) != refs["new"][0]:
            fail(name + ": the run after a kill did not produce the new set")
        if leftovers(T, name + "_out"):
            fail(name + ": staging left behind after the next run: %s" % leftovers(T, name + "_out"))
    print("%s: 9 kills, folder held %s" % (name, " or ".join(sorted(seen))))

# sweep: results.jsonl is a journal (appended point by point, kept across kills); the rest of the
# set is a transaction. After a kill the committed prefix must be intact; the resumed run equals
# an uninterrupted one (records without timings).
grid = "k=4,6,8;delta=0.8,1.0;lambda=0.5,2;solver=bk"
args = ["sweep", "--scene", scene, "--removed", removed, "--method", "fgs", "--labels", os.path.join(S, "labels.npy"),
        "--grid", grid, "--quiet"]
ref = os.path.join(T, "sweep_ref")
t0 = time.monotonic()
run(args + ["--out", ref])
duration = time.monotonic() - t0
def records(d):
    recs = [json.loads(l) for l in open(os.path.join(d, "results.jsonl")) if l.strip()]
    for r in recs:
        r.pop("seconds", None)
        r.pop("run", None)
    return sorted(recs, key=lambda r: r["id"])
for frac in (0.2, 0.5, 0.8, 1.0):
    out = os.path.join(T, "sweep_out")
    shutil.rmtree(out, ignore_errors=True)
    p = subprocess.Popen([BIN] + args + ["--out", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(frac * duration)
    p.send_signal(signal.SIGKILL)
    p.wait()
    if os.path.exists(os.path.join(out, "report.json")) and run(["info", "--verify", out], check=False).returncode != 0:
        fail("sweep killed at %.2f s: report.json does not describe the folder" % (frac * duration))
    run(args + ["--out", out])
    if records(out) != records(ref):
        fail("sweep: the resumed run differs from an uninterrupted one")
    if run(["info", "--verify", out], check=False).returncode != 0 or leftovers(T, "sweep_out"):
        fail("sweep: the resumed set is incomplete or staging was left behind")
print("sweep: 4 kills, every resume equal to the uninterrupted run")
PY
echo "reliability kill OK"
