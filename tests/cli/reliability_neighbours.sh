#!/usr/bin/env bash
# Reliability against neighbours (issue #31, docs/reliability.md "Threat model"): another local user
# (or a careless script) plants look-alike bookkeeping beside or inside an output folder — forged
# commit and staging folders, symlinks sprayed for the next process ids, a FIFO where a report
# should be — or two writers share one --out, or the disk fills up, or a run is signalled. Each case
# is one check that failed before the output set took its locks and claims; the table printed at
# the end names every case. The full-disk case mounts a tmpfs (root only; skipped otherwise).
set -euo pipefail
BIN="$1"
T=$(mktemp -d)
cleanup() {
  if mountpoint -q "$T/disk" 2>/dev/null; then umount -l "$T/disk" || true; fi
  rm -rf "$T"
}
trap cleanup EXIT
python3 - "$BIN" "$T" <<'PY'
import json, os, shutil, signal, subprocess, sys, time
BIN, T = os.path.abspath(sys.argv[1]), sys.argv[2]
results = []  # (case, ok, detail)

def run(args, timeout=120, cwd=None):
    t0 = time.monotonic()
    try:
        p = subprocess.run([BIN] + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                           timeout=timeout, cwd=cwd)
        return p.returncode, p.stdout, p.stderr, time.monotonic() - t0
    except subprocess.TimeoutExpired:
        return None, "", "timed out", time.monotonic() - t0

def check(case, ok, detail=""):
    results.append((case, bool(ok), detail))

def read(path):
    with open(path) as f:
        return f.read()

def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)

def verify(d):
    rc, out, err, _ = run(["info", "--verify", d], timeout=30)
    return rc, (out + err).strip()

def ids_of(path):
    """The ids of results.jsonl; a line that is not a record (interleaved writers) counts as None."""
    if not os.path.exists(path):
        return []
    out = []
    for line in open(path):
        try:
            out.append(json.loads(line)["id"])
        except ValueError:
            out.append(None)
    return out

def next_pids(n):
    with open("/proc/sys/kernel/ns_last_pid") as f:
        last = int(f.read())
    return range(last + 1, last + 1 + n)

os.chdir(T)
S = os.path.join(T, "t")
rc, _, err, _ = run(["synth", "--preset", "counter", "--gaussians", "3000", "--views", "3", "--resolution",
                     "64x48", "--seed", "3", "--quiet", "--out", S])
if rc != 0:
    print("FAIL: synth:", err)
    sys.exit(1)
scene, removed, labels = S + "/scene.ply", S + "/removed_fgs.npy", S + "/labels.npy"
refine = ["refine", "--scene", scene, "--removed", removed, "--method", "fgs", "--quiet"]
grid12 = "k=4,6,8;delta=0.8,1.0;lambda=0.5,2;solver=bk"
sweep = ["sweep", "--scene", scene, "--removed", removed, "--method", "fgs", "--labels", labels, "--quiet"]

# A. A forged commit folder must neither delete files of --out nor plant its own.
V = os.path.join(T, "V")
write(V + "/precious.txt", "precious\n")
write(V + "/notes.md", "notes\n")
forged = os.path.join(T, ".V.al-commit-99999999")
write(forged + "/.al-remove", "precious.txt\nnotes.md\n")
write(forged + "/planted.html", "planted\n")
rc, _, err, _ = run(refine + ["--out", V])
check("A forged commit folder", rc == 0 and os.path.exists(V + "/precious.txt") and os.path.exists(V + "/notes.md")
      and not os.path.exists(V + "/planted.html") and os.path.exists(forged + "/planted.html")
      and ".V.al-commit-99999999" in err,
      "exit %s; V holds %s; warning named it: %s" % (rc, sorted(os.listdir(V)), ".V.al-commit-99999999" in err))

# B. The same name as a symlink to another folder must not empty that folder into --out.
vic = os.path.join(T, "vic")
write(vic + "/id_rsa", "key\n")
os.symlink(vic, os.path.join(T, ".X.al-commit-99999999"))
rc, _, err, _ = run(refine + ["--out", os.path.join(T, "X")])
check("B symlinked commit folder", rc == 0 and os.path.exists(vic + "/id_rsa")
      and not os.path.exists(T + "/X/id_rsa") and os.path.islink(T + "/.X.al-commit-99999999"),
      "exit %s; vic holds %s" % (rc, os.listdir(vic)))

# B'. Symlinks sprayed for the next process ids must not touch another folder or an earlier set.
Y, vic2 = os.path.join(T, "Y"), os.path.join(T, "vic2")
write(vic2 + "/k", "key\n")
rc1, *_ = run(refine + ["--out", Y])
for pid in next_pids(300):
    for kind in ("al-staging-", "al-commit-"):
        os.symlink(vic2, os.path.join(T, ".Y.%s%d" % (kind, pid)))
rc2, _, err, _ = run(["refine", "--scene", scene, "--removed", S + "/removed_gc.npy", "--method", "gc",
                      "--quiet", "--out", Y])
vrc, vout = verify(Y)
check("B' sprayed symlinks", rc1 == 0 and rc2 == 0 and vrc == 0 and os.listdir(vic2) == ["k"],
      "exits %s/%s; verify %s: %s; vic2 holds %s" % (rc1, rc2, vrc, vout[:120], os.listdir(vic2)))

# C. A forged staging claim must not make sweep append to the user's own results.jsonl.
Q = os.path.join(T, "Q")
mine = '{"id": "the user\'s own record"}\n'  # parses like a sweep record: only the claim protects it
write(Q + "/results.jsonl", mine)
write(T + "/.Q.al-staging-99999999/.al-journals", "results.jsonl\n")
rc, _, err, _ = run(sweep + ["--grid", "k=4,6", "--out", Q])
check("C forged staging claim", rc == 2 and read(Q + "/results.jsonl") == mine and "results.jsonl" in err,
      "exit %s; results.jsonl %r" % (rc, read(Q + "/results.jsonl")[:40]))

# D. A FIFO where report.json (or results.jsonl) would be: exit 2 in under 1 s, never a hang.
D = os.path.join(T, "D")
os.makedirs(D)
os.mkfifo(D + "/report.json")
vrc, _, verr, vdt = run(["info", "--verify", D], timeout=10)
rrc, _, rerr, rdt = run(refine + ["--out", D], timeout=10)
D2 = os.path.join(T, "D2")
os.makedirs(D2)
os.mkfifo(D2 + "/results.jsonl")
src, _, serr, sdt = run(sweep + ["--grid", "k=4", "--out", D2], timeout=10)
check("D FIFO in --out", vrc == 2 and rrc == 2 and src == 2 and max(vdt, rdt, sdt) < 1.0,
      "verify %s in %.2f s, refine %s in %.2f s, sweep %s in %.2f s" % (vrc, vdt, rrc, rdt, src, sdt))

# F. Killing a sweep that grows the grid must leave the earlier complete set verifying.
Fref = os.path.join(T, "Fref")
rc, *_ = run(sweep + ["--grid", "k=4,6;solver=bk", "--out", Fref])
bad = []
for delay in (0.05, 0.15, 0.3, 0.5, 0.8):
    F = os.path.join(T, "F")
    shutil.rmtree(F, ignore_errors=True)
    shutil.copytree(Fref, F, symlinks=True)
    p = subprocess.Popen([BIN] + sweep + ["--grid", "k=4,6,8,10,12,14;solver=bk,cp", "--out", F],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(delay)
    p.send_signal(signal.SIGKILL)
    p.wait()
    vrc, vout = verify(F)
    if vrc != 0:
        bad.append("%.2f s: %s" % (delay, vout[:100]))
check("F killed grid growth", rc == 0 and not bad, "; ".join(bad))

# G. Two sweeps into one --out at once: one writer at a time, every point once.
G = os.path.join(T, "G")
procs = [subprocess.Popen([BIN] + sweep + ["--grid", grid12, "--out", G], stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True) for _ in range(2)]
codes = [p.wait(timeout=300) for p in procs]
waited = any("waiting" in p.stderr.read() for p in procs)
ids = ids_of(G + "/results.jsonl")
vrc, vout = verify(G)
check("G concurrent sweeps", codes == [0, 0] and len(ids) == 12 and len(set(ids)) == 12 and vrc == 0 and waited,
      "exits %s; %d records for 12 points; verify %s; a writer waited: %s" % (codes, len(ids), vrc, waited))

# E. A sweep on a full disk fails (exit 2); once there is space the identical command resumes.
if os.geteuid() == 0 and shutil.which("mount"):
    disk = os.path.join(T, "disk")
    os.makedirs(disk)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=24k", "tmpfs", disk]).returncode == 0:
        E = os.path.join(disk, "sw")
        big = sweep + ["--grid", "k=3,4,5,6,7,8,9,10,11,12;delta=0.8,1.0;solver=bk", "--out", E]
        rc1, _, err1, _ = run(big)
        subprocess.run(["mount", "-o", "remount,size=16m", disk], check=True)
        rc2, _, err2, _ = run(big)
        ids = ids_of(E + "/results.jsonl")
        vrc, vout = verify(E)
        check("E full disk, then resume", rc1 == 2 and rc2 == 0 and len(ids) == 20 and len(set(ids)) == 20 and vrc == 0,
              "first exit %s, rerun exit %s (%s); %d records; verify %s" % (rc1, rc2, err2.strip()[:160], len(ids), vrc))
    else:
        check("E full disk, then resume", True, "SKIPPED: tmpfs mount failed")
else:
    check("E full disk, then resume", True, "SKIPPED: needs root to mount a tmpfs")

# Also seen: SIGTERM and SIGINT remove the run's staging and exit 128+n.
for sig, code in ((signal.SIGTERM, 143), (signal.SIGINT, 130)):
    out = os.path.join(T, "sig%d" % sig)
    p = subprocess.Popen([BIN, "synth", "--gaussians", "400000", "--views", "24", "--quiet", "--out", out],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    prefix = ".sig%d.al-staging-" % sig
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not any(e.startswith(prefix) for e in os.listdir(T)) and p.poll() is None:
        time.sleep(0.02)
    time.sleep(0.3)
    p.send_signal(sig)
    rc = p.wait(timeout=60)
    left = [e for e in os.listdir(T) if e.startswith(".sig%d.al-" % sig)]
    check("signal %s" % signal.Signals(sig).name, rc == code and not left and not os.path.exists(out),
          "exit %s (want %d); left %s" % (rc, code, left))

# Also seen: the sweep's "truncated line dropped" warning reaches stderr.
W = os.path.join(T, "W")
shutil.copytree(Fref, W, symlinks=True)
with open(W + "/results.jsonl", "a") as f:
    f.write('{"id": "half')
rc, _, err, _ = run(["sweep", "--scene", scene, "--removed", removed, "--method", "fgs", "--labels", labels,
                     "--grid", "k=4,6;solver=bk", "--out", W])
check("sweep truncated-line warning on stderr", rc == 0 and "truncated" in err, "exit %s; stderr %r" % (rc, err[-200:]))

width = max(len(c) for c, _, _ in results)
failed = [c for c, ok, _ in results if not ok]
for c, ok, d in results:
    print("%-*s  %s  %s" % (width, c, "ok  " if ok else "FAIL", d))
if failed:
    print("FAIL: %d of %d cases: %s" % (len(failed), len(results), ", ".join(failed)))
    sys.exit(1)
PY
echo "reliability neighbours OK"
