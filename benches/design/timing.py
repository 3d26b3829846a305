#!/usr/bin/env python3
"""Wall time and peak memory of `rsf design` against `rsf diagnose` (its first stage, the
reference run in the same go) on a folder of records written by benches/detection/generate.py
(its manifest.json gives each record's nominal stiffness).

    python3 benches/design/timing.py DIR [--rsf target/release/rsf] [--repeats 3] [--threads 2]
        [--min-rows 0]

Each record is run `repeats` times each way, alternating (diagnose, design, diagnose, …), so
that machine load affects both alike. Prints a Markdown table: rows, median wall s of each,
their ratio, the design's own part (design − diagnose), and the peak resident memory (MB) of
each, from the kernel's rusage of the child process.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


def run(cmd):
    """Wall s and peak RSS (MB) of one child process; raises on failure."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    err = p.stderr.read().decode(errors="replace")
    p.stderr.close()
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}: {err.strip()[-300:]}")
    return wall, ru.ru_maxrss / 1024.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("dir", type=Path)
    ap.add_argument("--rsf", default=str(Path(__file__).resolve().parents[2] / "target" / "release" / "rsf"))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--min-rows", type=int, default=0)
    a = ap.parse_args()
    manifest = json.loads((a.dir / "manifest.json").read_text())
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for rec in manifest:
            if rec["n_samples"] < a.min_rows:
                continue
            path = str(a.dir / rec["file"])
            common = ["--stiffness", repr(rec["nominal_stiffness"]), "--threads", str(a.threads)]
            diag = [a.rsf, "diagnose", path, *common]
            des = [a.rsf, "design", path, *common, "--json", os.path.join(tmp, "d.json")]
            t_diag, t_des, m_diag, m_des = [], [], [], []
            for _ in range(a.repeats):
                w, m = run(diag)
                t_diag.append(w)
                m_diag.append(m)
                w, m = run(des)
                t_des.append(w)
                m_des.append(m)
            d = json.loads(Path(tmp, "d.json").read_text())
            r = dict(file=rec["file"], rows=rec["n_samples"], cause=d["cause"], models=len(d["models"]),
                     proposals=len(d["proposals"]), diagnose_s=statistics.median(t_diag),
                     design_s=statistics.median(t_des), diagnose_mb=max(m_diag), design_mb=max(m_des))
            rows.append(r)
            print(f"{rec['file']}: {r['rows']} rows, diagnose {r['diagnose_s']:.1f} s, design {r['design_s']:.1f} s",
                  file=sys.stderr)
    print("| record | rows | cause | models | diagnose s | design s | ratio | design's own s | peak MB (diagnose / design) |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['file']} | {r['rows']:,} | {r['cause']} | {r['models']} | {r['diagnose_s']:.1f} | {r['design_s']:.1f} | "
              f"{r['design_s'] / r['diagnose_s']:.2f} | {r['design_s'] - r['diagnose_s']:.1f} | "
              f"{r['diagnose_mb']:.0f} / {r['design_mb']:.0f} |")
    if rows:
        med = statistics.median(r["design_s"] for r in rows)
        print(f"\nmedian design {med:.1f} s, max {max(r['design_s'] for r in rows):.1f} s over {len(rows)} records")


if __name__ == "__main__":
    main()
