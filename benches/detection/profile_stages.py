"""Where a diagnosis's time goes, stage by stage (issue 22): runs `rsf diagnose` with
`rsf diagnose --stage-times` on the records of a generated set whose row count lies in a range, and
prints a Markdown table of the stages (wall seconds; candidate fits with their held-out tests,
and per-event refits, as CPU seconds of their own jobs).

    python3 benches/detection/generate.py --out DIR --drift --seed 22 --rows-scale 5 --limit 30
    python3 benches/detection/profile_stages.py DIR [--rows 55000 80000] [--rsf target/release/rsf]
"""

import argparse
import json
import re
import statistics
import subprocess
import time
from pathlib import Path


def stages(text):
    at = {m.group(1): float(m.group(2)) for m in re.finditer(r"diagnose: (.*?) done at ([0-9.]+) s", text)}
    jobs = {}
    for m in re.finditer(r"diagnose: (\S+(?: \d+| held out)?) in ([0-9.]+) s", text):
        jobs[m.group(1)] = jobs.get(m.group(1), 0.0) + float(m.group(2))
    null = sum(float(m.group(1)) for m in re.finditer(r"null calibration of \S+ in ([0-9.]+) s", text))
    base, mask = at["baseline and reconstruction check"], at["break-timing mask"]
    held, cands, comb = at["held-out baseline"], at["candidates, events and null calibration"], at["combinations"]
    return {
        "total": comb, "baseline": base, "mask": mask - base, "held-out baseline": held - mask,
        "candidates+events (wall)": cands - held - null, "null": null, "combinations": comb - cands,
        "events (cpu)": sum(v for k, v in jobs.items() if k.startswith("segment")),
        # a candidate's fit and its held-out test (a job of its own beside the fit)
        **{f"{c} (cpu)": jobs.get(c, 0.0) + jobs.get(f"{c} held out", 0.0) for c in
           ["second_state_variable", "cutoff_velocity", "evolution_law", "stiffness", "slip_trend"]},
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir", type=Path)
    ap.add_argument("--rows", type=int, nargs=2, default=[55000, 80000])
    ap.add_argument("--rsf", default="target/release/rsf")
    a = ap.parse_args()
    recs = [r for r in json.loads((a.dir / "manifest.json").read_text()) if a.rows[0] <= r["n_samples"] <= a.rows[1]]
    rows = []
    for r in recs:
        t0 = time.perf_counter()
        p = subprocess.run([a.rsf, "diagnose", str(a.dir / r["file"]), "--stiffness", str(r["nominal_stiffness"]),
                            "--stage-times"], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        cause = p.stdout.split("\n", 1)[0].removeprefix("cause: ")
        rows.append((r["file"], r["n_samples"], r["cause"], cause, wall, stages(p.stderr)))
    keys = list(rows[0][5])
    print("| record | rows | truth | named | " + " | ".join(keys) + " |")
    print("|" + "---|" * (4 + len(keys)))
    for f, n, truth, named, wall, s in rows:
        print(f"| {f} | {n} | {truth} | {named} | " + " | ".join(f"{s[k]:.1f}" for k in keys) + " |")
    print("| **median** | | | | " + " | ".join(f"{statistics.median(r[5][k] for r in rows):.1f}" for k in keys) + " |")


if __name__ == "__main__":
    main()
