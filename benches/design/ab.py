#!/usr/bin/env python3
"""Two builds of `rsf design --from` (the design's own part: the diagnosis is read, not re-run)
on records of a design-study folder, alternated (old, new, old, new, …) so that machine load
affects both alike; prints a Markdown table of median wall s, their ratio and peak RSS (MB).

    python3 benches/design/ab.py STUDY_DIR NAME [NAME …] --old OLD_RSF --new NEW_RSF
        [--repeats 3] [--threads 2] [--design-arg=…]

STUDY_DIR is a folder written by benches/design/study.py (its study.json gives each case's
stiffness; records/NAME.csv and records/NAME.diag.json are the record and its diagnosis).
"""
import argparse
import json
import statistics
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from timing import run  # noqa: E402  (wall s and peak RSS of one child process)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("study")
    ap.add_argument("names", nargs="+")
    ap.add_argument("--old", required=True)
    ap.add_argument("--new", required=True)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--design-arg", action="append", default=[])
    a = ap.parse_args()
    study = Path(a.study)
    cases = {c["name"]: c for c in json.loads((study / "study.json").read_text())["cases"]}
    print("| record | rows | credible models (new) | old s | new s | ratio | peak MB (old / new) |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as tmp:
        for name in a.names:
            rec, diag = study / "records" / f"{name}.csv", study / "records" / f"{name}.diag.json"
            k = repr(float(cases[name]["truth"]["k"]))
            out = Path(tmp) / "g.json"
            cmd = lambda b: [b, "design", str(rec), "--time-col", "time_s", "--lp-col", "load_point_um",
                             "--mu-col", "mu", "--stiffness", k, "--threads", str(a.threads), "--seed", "1",
                             "--from", str(diag), "--json", str(out), *a.design_arg]
            t = {"old": [], "new": []}
            mem = {"old": 0.0, "new": 0.0}
            for _ in range(a.repeats):
                for which in ("old", "new"):
                    w, m = run(cmd(getattr(a, which)))
                    t[which].append(w)
                    mem[which] = max(mem[which], m)
            models = len(json.loads(out.read_text())["models"])
            rows = sum(1 for _ in rec.open()) - 1
            mo, mn = statistics.median(t["old"]), statistics.median(t["new"])
            print(f"| {name} | {rows:,} | {models} | {mo:.2f} | {mn:.2f} | {mn / mo:.2f} | "
                  f"{mem['old']:.0f} / {mem['new']:.0f} |", flush=True)


if __name__ == "__main__":
    main()
