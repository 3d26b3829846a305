#!/usr/bin/env python3
"""Coverage of `rsf fit`'s 95 % intervals on records with known truths (generate.py here).

    python3 benches/coverage/study.py DIR [--rsf target/release/rsf] [--jobs 2] [--out OUT]

Fits every record of DIR/truth.csv with its true law and the true stiffness (fixed; alpha
fitted, shared, on the normal-stress records), once: the result carries both the intervals
under the residuals' noise model (the default) and the white-noise form
(`noise.ci95_white`). Writes OUT/coverage.csv (a row per record and parameter) and
OUT/coverage.md (coverage per noise family and parameter, both forms, with the binomial 95 %
range of a coverage of 95 % for that many records). Standard library only.
"""
import argparse
import csv
import json
import math
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

PARAMS = ["a", "b1", "dc1", "alpha1"]
TRUTH_KEY = {"a": "a", "b1": "b", "dc1": "dc", "alpha1": "alpha"}


def fit(rsf, d, row, out):
    rec = d / row["file"]
    js = out / (Path(row["file"]).stem + ".fit.json")
    cmd = [rsf, "fit", str(rec), "--law", row["law"], "--stiffness", row["k"], "--threads", "1", "--json", str(js)]
    if row.get("alpha", "") not in ("", None):
        cmd += ["--normal-col", "normal_stress_mpa", "--fit-alpha", "shared"]
    t0 = time.time()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - t0
    if not js.exists():
        return row, None, p.stderr.strip().splitlines()[-1:] or ["no output"], wall
    return row, json.loads(js.read_text()), p.returncode, wall


def binomial_range(n, p=0.95):
    """The central 95 % range of the count of successes out of n at probability p, as shares."""
    pmf = [math.comb(n, k) * p**k * (1 - p) ** (n - k) for k in range(n + 1)]
    c, lo, hi = 0.0, 0, n
    for k in range(n + 1):
        c += pmf[k]
        if c >= 0.025:
            lo = k
            break
    c = 0.0
    for k in range(n, -1, -1):
        c += pmf[k]
        if c >= 0.025:
            hi = k
            break
    return lo / n, hi / n


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir", type=Path)
    ap.add_argument("--rsf", default=str(Path(__file__).resolve().parents[2] / "target/release/rsf"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", type=Path)
    a = ap.parse_args()
    out = a.out or a.dir / "coverage"
    out.mkdir(parents=True, exist_ok=True)
    rows = list(csv.DictReader(open(a.dir / "truth.csv", newline="")))
    results, failed, walls = [], [], []
    with ThreadPoolExecutor(a.jobs) as ex:
        for i, (row, res, rc, wall) in enumerate(ex.map(lambda r: fit(a.rsf, a.dir, r, out), rows)):
            walls.append(wall)
            if res is None:
                failed.append((row["file"], rc))
                continue
            results.append((row, res, rc))
            if (i + 1) % 20 == 0:
                print(f"{i + 1}/{len(rows)} fitted", file=sys.stderr)
    lines = []
    for row, res, rc in results:
        for p in PARAMS:
            key = TRUTH_KEY[p]
            if row.get(key, "") in ("", None) or p not in res["ci95"]:
                continue
            truth = float(row[key])
            lo, hi = res["ci95"][p]
            wlo, whi = res.get("noise", {}).get("ci95_white", {}).get(p, res["ci95"][p])
            value = res["params"]["a"] if p == "a" else (
                res["params"]["b"][0] if p == "b1" else res["params"]["dc"][0] if p == "dc1" else res["params"]["alpha"][0])
            family = row["noise"] if row.get("alpha", "") in ("", None) else "σ steps, " + row["noise"]
            lines.append({
                "file": row["file"], "noise": family, "law": row["law"], "param": p, "truth": truth,
                "value": value, "lo": lo, "hi": hi, "lo_white": wlo, "hi_white": whi,
                "covered": int(lo <= truth <= hi), "covered_white": int(wlo <= truth <= whi),
                "converged": int(bool(res.get("converged"))), "exit": rc,
                "widen": (hi - lo) / (whi - wlo) if whi > wlo else float("nan"),
            })
    with open(out / "coverage.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(lines[0].keys()))
        w.writeheader()
        w.writerows(lines)
    fams = sorted({l["noise"] for l in lines}, key=lambda f: (f.startswith("σ"), f))
    md = ["| noise | parameter | records | noise-model form | white form | median widening | 95 % range at 95 % |",
          "|---|---|---|---|---|---|---|"]
    for fam in fams + ["all", "all σ steps"]:
        for p in PARAMS:
            sel = [l for l in lines if (fam == "all" or l["noise"] == fam
                                        or (fam == "all σ steps" and l["noise"].startswith("σ"))) and l["param"] == p]
            if not sel:
                continue
            n = len(sel)
            c = sum(l["covered"] for l in sel) / n
            cw = sum(l["covered_white"] for l in sel) / n
            wid = sorted(l["widen"] for l in sel)[n // 2]
            lo, hi = binomial_range(n)
            md.append(f"| {fam} | {p} | {n} | {100 * c:.0f} % | {100 * cw:.0f} % | {wid:.2f}× | {100 * lo:.0f}–{100 * hi:.0f} % |")
    walls.sort()
    md.append("")
    md.append(f"{len(results)} of {len(rows)} records fitted ({len(failed)} without a result"
              f"{': ' + ', '.join(f for f, _ in failed[:5]) if failed else ''}); "
              f"{sum(1 for r, res, rc in results if not res.get('converged'))} not converged; "
              f"fit wall median {walls[len(walls) // 2]:.2f} s, max {walls[-1]:.2f} s.")
    (out / "coverage.md").write_text("\n".join(md) + "\n")
    print("\n".join(md))


if __name__ == "__main__":
    main()
