"""QDYN on rsf's friction against QDYN on its own, timed side by side: the same input files run
by the two executables alternately (own, rsf, own, rsf, ...), wall time and peak memory of
each run, medians.

Usage: python bench.py WORK [--repeats 3] [--cases bp1,singleasperity] [--bp1-years 1000]

WORK is run.sh's work folder, with the two builds in WORK/own/src and WORK/rsf/src. The inputs
are written once by QDYN's own Python (pyqdyn, from WORK/own/src):
- bp1: SEAS BP1-QD as bp1.py sets it (512 cells, RKF45 at 1e-7, dense kernel), --bp1-years;
- singleasperity: the RSF case of QDYN's regression suite (test/singleasperity.py, 4096
  elements, FFT kernel, Bulirsch-Stoer at 1e-10), its first 7.884e7 s (a quarter of its
  10 years): the case where friction is the largest share of the work.
Writes WORK/bench.json and WORK/bench.md (a Markdown table); prints the table.
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SINGLE_TMAX = 7.884e7  # s: a quarter of the suite case's 10 years


def write_bp1(own_src, folder, years):
    sys.path.insert(0, HERE)
    from bp1 import bp1_settings
    from pyqdyn import qdyn

    os.makedirs(folder, exist_ok=True)
    os.chdir(folder)
    p = qdyn()
    bp1_settings(p, 512, years)
    p.write_input()


class _Stop(Exception):
    pass


def write_singleasperity(test_dir, folder):
    """QDYN's own test writes the input; its run is stopped before the executable starts."""
    from pyqdyn import qdyn

    sys.path.insert(0, test_dir)
    cwd = os.getcwd()
    os.chdir(test_dir)
    from singleasperity import TestSingleAsperity

    p = qdyn()

    def stop(*_a, **_k):
        raise _Stop

    p.run = stop
    case = TestSingleAsperity(p)
    try:
        case.run_test("RSF")
    except _Stop:
        pass
    os.chdir(cwd)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(test_dir, "qdyn.in")) as f:
        lines = f.read().split("\n")
    # the line after the one naming TMAX holds its value (pyqdyn's layout: "... tmax ..." in a
    # comment line is not used; the value line is the one pyqdyn wrote from set_dict)
    text = "\n".join(lines)
    old = "%.15g" % (10 * 3600 * 24 * 365.0)
    if old not in text:
        # pyqdyn writes floats with repr: find the token equal to 10 yr in seconds
        tokens = [t for line in lines for t in line.split() if _is(t, 10 * 3600 * 24 * 365.0)]
        if not tokens:
            sys.exit("bench.py: could not find TMAX (10 yr) in the single-asperity qdyn.in")
        old = tokens[0]
    text = text.replace(old, "%.6e" % SINGLE_TMAX, 1)
    with open(os.path.join(folder, "qdyn.in"), "w") as f:
        f.write(text)


def _is(token, value):
    try:
        return abs(float(token) - value) <= 1e-9 * value
    except ValueError:
        return False


def run_once(exe, folder):
    """Wall time (s) and peak resident memory (MB) of one run of `exe` in `folder`."""
    for f in os.listdir(folder):
        if f.startswith("output_") or f.startswith("fort."):
            os.remove(os.path.join(folder, f))
    out = subprocess.run(["/usr/bin/time", "-f", "%e %M", exe], cwd=folder, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"bench.py: {exe} failed in {folder}:\n{out.stdout[-2000:]}{out.stderr[-2000:]}")
    wall, kb = out.stderr.strip().split("\n")[-1].split()
    return float(wall), float(kb) / 1024.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("work")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--cases", default="bp1,singleasperity")
    ap.add_argument("--bp1-years", type=float, default=1000.0)
    a = ap.parse_args()
    work = os.path.abspath(a.work)
    own_src, rsf_src = os.path.join(work, "own", "src"), os.path.join(work, "rsf", "src")
    for src in (own_src, rsf_src):
        if not os.path.exists(os.path.join(src, "qdyn")):
            sys.exit(f"bench.py: no QDYN executable in {src} (run run.sh --compare first)")
    sys.path.insert(0, own_src)
    cases = a.cases.split(",")
    inputs = {}
    for case in cases:
        folder = os.path.join(work, "bench", case)
        if case == "bp1":
            write_bp1(own_src, folder, a.bp1_years)
            inputs[case] = f"SEAS BP1-QD, 512 cells, {a.bp1_years:g} yr (RKF45, dense kernel)"
        elif case == "singleasperity":
            write_singleasperity(os.path.join(work, "own", "test"), folder)
            inputs[case] = "single asperity RSF, first 7.884e7 s (4096 elements, FFT, Bulirsch-Stoer)"
        else:
            sys.exit(f"bench.py: unknown case {case} (bp1, singleasperity)")
    results = {}
    for case in cases:
        folder = os.path.join(work, "bench", case)
        runs = {"own": [], "rsf": []}
        for i in range(a.repeats):
            for name, src in (("own", own_src), ("rsf", rsf_src)):
                wall, mb = run_once(os.path.join(src, "qdyn"), folder)
                runs[name].append({"wall_s": wall, "peak_mb": mb})
                print(f"{case} run {i + 1}/{a.repeats} {name}: {wall:.2f} s, {mb:.1f} MB", flush=True)
        med = {n: statistics.median(r["wall_s"] for r in runs[n]) for n in runs}
        results[case] = {"input": inputs[case], "runs": runs, "median_own_s": med["own"], "median_rsf_s": med["rsf"],
                         "ratio": med["rsf"] / med["own"]}
        shutil.rmtree(folder, ignore_errors=True)
    rows = ["| case | QDYN's own friction | rsf's friction | ratio | runs (own; rsf), s | peak memory (own; rsf) |",
            "|---|---|---|---|---|---|"]
    for case, r in results.items():
        w = lambda n: "/".join(f"{x['wall_s']:.2f}" for x in r["runs"][n])  # noqa: E731
        m = lambda n: max(x["peak_mb"] for x in r["runs"][n])  # noqa: E731
        rows.append(f"| {r['input']} | {r['median_own_s']:.2f} s | {r['median_rsf_s']:.2f} s | {r['ratio']:.3f} | "
                    f"{w('own')}; {w('rsf')} | {m('own'):.1f}; {m('rsf'):.1f} MB |")
    table = "\n".join(rows)
    for name, text in (("bench.json", json.dumps(results, indent=1)), ("bench.md", table + "\n")):
        tmp = os.path.join(work, name + ".tmp")
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, os.path.join(work, name))
    print(table)


if __name__ == "__main__":
    main()
