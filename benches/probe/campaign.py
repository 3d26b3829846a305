#!/usr/bin/env python3
"""The archive probe campaign (docs/fuzzing.md): kills during every write of `rsf batch`,
concurrent runs on one output folder, and special files as records and outputs.

    python3 benches/probe/campaign.py [--rsf target/release/rsf] [--kills 100] [--diagnose-kills 24]
                                      [--concurrent 20] [--work DIR]

Standard library only. Prints one table of counts; exits 1 if any check failed.

Kills: a clean run of a small lab folder gives the reference outputs and its wall time T. Then,
for each kill, a fresh copy of the folder is run and SIGKILLed after a delay spread evenly over
[0, 1.1 T]; the folder is inspected as the kill left it (which files existed, which were
partial: the phase the kill landed in; a summary set that claims to be complete must be one
run's), then a resumed run must exit 0, leave no partial file, and give the reference summary
set byte for byte.

Concurrent: 2–4 runs started at once on one folder: every run either finishes or says the folder
is in use (naming the holder); the folder ends with one run's complete set, equal to the
reference.

Every write: a clean run's renames, links and unlinks are counted under strace, and the run is
repeated once per call, SIGKILLed by strace's fault injection just before that call (the one
after the last is the clean end); each is inspected and resumed as above. This reaches the
instants a timed kill almost never hits (between the summary set's renames).

Special files: a FIFO, a directory, /dev/null and a symlink out of the folder as records; `-`
and /dev/stdout as outputs. Each must end within 60 s with the documented outcome.
"""
import argparse
import hashlib
import json
import os
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
RECORDS = [REPO / "tests/data/outside" / f for f in ("prz_holds.csv", "nagata.csv", "mix1_holds.csv", "power_aging.csv")]
SET_FILES = ["summary.csv", "summary.parquet", "summary.svg"]


def lab(root: Path, diagnose: bool) -> Path:
    d = root / "lab"
    d.mkdir(parents=True)
    rows = ["file,stiffness"]
    for r in RECORDS[: 2 if diagnose else 4]:
        shutil.copy(r, d / r.name)
        rows.append(f"{r.name},0.02")
    (d / "manifest.csv").write_text("\n".join(rows) + "\n")
    return d


def cmd(rsf, d: Path, diagnose: bool, jobs: int = 2):
    c = [rsf, "batch", str(d / "manifest.csv"), "--out", str(d / "out"), "--fit", "--jobs", str(jobs)]
    return c + (["--diagnose"] if diagnose else [])


def set_state(out: Path):
    """'absent', 'complete' or 'incomplete' (no set file beside summary files, or a mismatch)."""
    setf = out / "summary.set.json"
    present = [f for f in SET_FILES if (out / f).exists()]
    if not setf.exists():
        return "absent" if not present else "incomplete"
    try:
        s = json.loads(setf.read_text())
    except ValueError:
        return "mismatch"
    for f in SET_FILES:
        p = out / f
        if not p.exists() or hashlib.sha256(p.read_bytes()).hexdigest() != s["files"][f]["sha256"]:
            return "mismatch"
    return "complete"


def phase(out: Path):
    """Where the kill landed, from what it left."""
    if not out.exists():
        return "before any output"
    partial = sorted(p.name for p in out.rglob("*.rsf-partial"))
    if partial:
        name = partial[0].lstrip(".").split(".rsf-partial")[0]
        kind = name.split(".")[-2] if name.count(".") >= 2 else name
        return "writing " + (".".join(name.split(".")[-2:-1]) or kind)
    recs = out / "records"
    stamps = len(list(recs.glob("*.stamp"))) if recs.exists() else 0
    st = set_state(out)
    if st == "complete":
        return "after the set file"
    if any((out / f).exists() for f in SET_FILES):
        return "between summary renames"
    return f"records ({stamps} stamped)"


def sha_set(out: Path):
    return {f: hashlib.sha256((out / f).read_bytes()).hexdigest() for f in SET_FILES}


def kills(rsf, n, diagnose, work: Path, counts, failures):
    ref_root = work / f"ref_{int(diagnose)}"
    d = lab(ref_root, diagnose)
    t0 = time.time()
    subprocess.run(cmd(rsf, d, diagnose), check=True, capture_output=True)
    T = time.time() - t0
    ref = sha_set(d / "out")
    label = "fit + diagnose" if diagnose else "fit"
    phases = {}
    for i in range(n):
        root = work / f"k{int(diagnose)}_{i}"
        d = lab(root, diagnose)
        delay = 1.1 * T * (i + 0.5) / n
        p = subprocess.Popen(cmd(rsf, d, diagnose), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(delay)
        p.send_signal(signal.SIGKILL)
        p.wait()
        out = d / "out"
        ph = phase(out)
        phases[ph] = phases.get(ph, 0) + 1
        if out.exists() and set_state(out) == "mismatch":
            failures.append(f"kill {label} {i}: a set file naming other bytes")
        r = subprocess.run(cmd(rsf, d, diagnose), capture_output=True, text=True, timeout=600)
        if r.returncode != 0:
            failures.append(f"kill {label} {i}: resume exit {r.returncode}: {r.stderr[-300:]}")
        elif sha_set(out) != ref or set_state(out) != "complete":
            failures.append(f"kill {label} {i}: resumed set differs from the clean run's")
        if list(out.rglob("*.rsf-partial")):
            failures.append(f"kill {label} {i}: partial files left after the resume")
        shutil.rmtree(root)
    counts.append((f"SIGKILL during `rsf batch --{label.replace(' + ', ' --')}` (clean run {T:.1f} s), then resume", n,
                   ", ".join(f"{k}: {v}" for k, v in sorted(phases.items()))))
    shutil.rmtree(ref_root)
    return ref


WRITES = ["rename", "renameat", "renameat2", "link", "linkat", "unlink", "unlinkat"]


def every_write(rsf, diagnose, work: Path, counts, failures):
    """A SIGKILL at each file-system change of a clean run, one run per change: strace's fault
    injection counts each syscall separately (per thread: the runs here take one record at a
    time, `--jobs 1`, so every call is the main thread's), so syscall s is hit at its k-th call
    for every k up to its count in the clean run."""
    label = "fit + diagnose" if diagnose else "fit"
    if shutil.which("strace") is None:
        counts.append((f"SIGKILL at every write of `rsf batch --{label}`", 0, "SKIP: no strace"))
        return
    ref_root = work / f"wref_{int(diagnose)}"
    d = lab(ref_root, diagnose)
    trace = work / "trace"
    subprocess.run(["strace", "-f", "-qq", "-o", str(trace), "-e", "trace=" + ",".join(WRITES), *cmd(rsf, d, diagnose, 1)],
                   check=True, capture_output=True)
    per = {}
    for line in trace.read_text().splitlines():
        parts = line.split(None, 1)
        if len(parts) == 2 and "(" in parts[1] and not parts[1].startswith(("<", "+++", "---")):
            name = parts[1].split("(", 1)[0]
            if name in WRITES:
                per[name] = per.get(name, 0) + 1
    ref = sha_set(d / "out")
    shutil.rmtree(ref_root)
    where, trials, died = {}, 0, 0
    for sc, n_calls in sorted(per.items()):
        for k in range(1, n_calls + 1):
            root = work / f"w{int(diagnose)}_{sc}_{k}"
            d = lab(root, diagnose)
            p = subprocess.run(["strace", "-f", "-qq", "-o", str(trace), "-e", f"trace={sc}", "-e",
                                f"inject={sc}:signal=SIGKILL:when={k}", *cmd(rsf, d, diagnose, 1)],
                               capture_output=True, timeout=600)
            trials += 1
            out = d / "out"
            lines = trace.read_text().splitlines()
            if any("killed by SIGKILL" in l for l in lines):
                died += 1
                calls = [l for l in lines if f" {sc}(" in l]
                path = calls[-1].split('"')[-2] if calls and calls[-1].count('"') >= 2 else "?"
                name = Path(path).name
                kind = ("summary set" if name.startswith(("summary", ".summary")) else
                        "lock" if "rsf-batch.lock" in name else "record output")
                key = f"{kind} ({sc})"
                where[key] = where.get(key, 0) + 1
            if out.exists() and set_state(out) == "mismatch":
                failures.append(f"write {label} {sc} #{k}: a set file naming other bytes")
            r = subprocess.run(cmd(rsf, d, diagnose, 1), capture_output=True, text=True, timeout=600)
            if r.returncode != 0:
                failures.append(f"write {label} {sc} #{k}: resume exit {r.returncode}: {r.stderr[-300:]}")
            elif sha_set(out) != ref or set_state(out) != "complete":
                failures.append(f"write {label} {sc} #{k}: resumed set differs from the clean run's")
            if list(out.rglob("*.rsf-partial")) or (out / ".rsf-batch.lock").exists():
                failures.append(f"write {label} {sc} #{k}: partial files or a lock left after the resume")
            shutil.rmtree(root)
    total = sum(per.values())
    counts.append((f"SIGKILL at every write of `rsf batch --{label.replace(' + ', ' --')} --jobs 1` (each of its {total} "
                   "renames, links and unlinks, just before it), then resume", trials,
                   f"{died} killed there: " + ", ".join(f"{k}: {v}" for k, v in sorted(where.items()))))


def concurrent(rsf, n, work: Path, counts, failures):
    ref_root = work / "cref"
    d = lab(ref_root, False)
    subprocess.run(cmd(rsf, d, False), check=True, capture_output=True)
    ref = sha_set(d / "out")
    finished = refused = 0
    for i in range(n):
        root = work / f"c{i}"
        d = lab(root, False)
        k = 2 + i % 3
        ps = [subprocess.Popen(cmd(rsf, d, False), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
              for _ in range(k)]
        outs = [p.communicate(timeout=600) for p in ps]
        for p, (_, err) in zip(ps, outs):
            if p.returncode == 0:
                finished += 1
            elif "in use by another rsf batch" in err and "pid " in err:
                refused += 1
            else:
                failures.append(f"concurrent {i}: exit {p.returncode} without the lock's message: {err[-300:]}")
        if set_state(d / "out") != "complete" or sha_set(d / "out") != ref:
            failures.append(f"concurrent {i}: the folder does not hold one run's set")
        shutil.rmtree(root)
    counts.append((f"2–4 `rsf batch` at once on one folder", n, f"{finished} runs finished, {refused} refused naming the holder"))
    shutil.rmtree(ref_root)


def special(rsf, work: Path, counts, failures):
    d = work / "special"
    d.mkdir()
    shutil.copy(RECORDS[0], d / "a.csv")
    fifo = d / "fifo.csv"
    os.mkfifo(fifo)
    (d / "sub").mkdir()
    os.symlink("/etc/hostname", d / "out_link.csv")
    os.symlink("/dev/null", d / "null.csv")
    cases = []

    def run(name, args, want_exit_zero, want_text, cwd=d, stdout_file=None):
        try:
            so = open(stdout_file, "w") if stdout_file else subprocess.PIPE
            r = subprocess.run([rsf, *args], cwd=cwd, stdout=so, stderr=subprocess.PIPE, text=True, timeout=60)
            text = (r.stdout or "") + r.stderr
            ok = (r.returncode == 0) == want_exit_zero and all(w in text for w in want_text)
            cases.append((name, ok, "" if ok else f"exit {r.returncode}: {text[-300:]}"))
        except subprocess.TimeoutExpired:
            cases.append((name, False, "hang (60 s)"))

    man = lambda rows: (d / "manifest.csv").write_text("file,stiffness\n" + "".join(f"{r},0.02\n" for r in rows))
    man(["a.csv", "fifo.csv"])
    run("FIFO as a record", ["batch", "manifest.csv", "--out", "o1", "--fit"], False, ["fifo.csv", "read_failed"])
    man(["a.csv", "sub"])
    run("folder as a record", ["batch", "manifest.csv", "--out", "o2", "--fit"], False, ["sub", "read_failed"])
    man(["a.csv", "null.csv"])
    run("/dev/null (symlink) as a record", ["batch", "manifest.csv", "--out", "o3", "--fit"], False, ["null.csv"])
    man(["a.csv", "out_link.csv"])
    run("symlink out of the folder", ["batch", "manifest.csv", "--out", "o4", "--fit"], False, ["outside"])
    man(["a.csv", "../../../etc/passwd"])
    run("path out of the folder", ["batch", "manifest.csv", "--out", "o5", "--fit"], False, ["outside"])
    # a FIFO read as a stream: the record written into it by another process (`rsf fit <(…)`)
    writer = subprocess.Popen(["sh", "-c", f"cat '{d / 'a.csv'}' > '{fifo}'"])
    run("FIFO with a writer to rsf fit", ["fit", "fifo.csv", "--stiffness", "0.02"], True, ["rms"])
    writer.wait(timeout=60)
    run("--json - to standard output", ["fit", "a.csv", "--stiffness", "0.02", "--json", "-"], True, ['"params"'])
    out = d / "stdout.txt"
    run("--json /dev/stdout > file", ["fit", "a.csv", "--stiffness", "0.02", "--json", "/dev/stdout"], True, [],
        stdout_file=out)
    ok = out.exists() and '"params"' in out.read_text() and not (d / "-").exists()
    cases.append(("  … the redirected file holds the JSON, no file `-`", ok, ""))
    for name, ok, why in cases:
        if not ok:
            failures.append(f"special: {name}: {why}")
    counts.append(("special files (FIFO, folder, /dev/null, symlink and path out, `-`, /dev/stdout)", len(cases),
                   f"{sum(ok for _, ok, _ in cases)} as documented"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rsf", default=str(REPO / "target/release/rsf"))
    ap.add_argument("--kills", type=int, default=100)
    ap.add_argument("--diagnose-kills", type=int, default=24)
    ap.add_argument("--concurrent", type=int, default=20)
    ap.add_argument("--work", type=Path)
    a = ap.parse_args()
    work = Path(tempfile.mkdtemp(prefix="rsf-probe-", dir=a.work))
    counts, failures = [], []
    t0 = time.time()
    special(a.rsf, work, counts, failures)
    concurrent(a.rsf, a.concurrent, work, counts, failures)
    every_write(a.rsf, False, work, counts, failures)
    every_write(a.rsf, True, work, counts, failures)
    kills(a.rsf, a.kills, False, work, counts, failures)
    if a.diagnose_kills:
        kills(a.rsf, a.diagnose_kills, True, work, counts, failures)
    print("| probe | trials | outcome |\n|---|---|---|")
    for what, n, outcome in counts:
        print(f"| {what} | {n} | {outcome} |")
    print(f"\n{len(failures)} failures; {time.time() - t0:.0f} s")
    for f in failures:
        print("FAIL", f)
    shutil.rmtree(work, ignore_errors=True)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
