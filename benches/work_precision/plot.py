#!/usr/bin/env python3
"""Work-precision diagrams: rsf's integrators beside scipy's, error in friction vs wall time.

    python3 benches/work_precision/plot.py OUTDIR CASE1_rsf.json CASE1_peers.json \
        [CASE2_rsf.json CASE2_peers.json ...]

Writes OUTDIR/work_precision_<case>.svg for every pair and OUTDIR/work_precision.md (one
markdown table per case: solver, rtol, wall ms, err).

Inputs: a *_rsf.json from rsf's example ({"case", "runs": [{"solver", "method", "rtol",
"wall_s", "steps", "mu": [...]}]}) and a *_peers.json from peers.py beside this file (same
"runs" format plus "reference": {"mu": [...]}). Every run's error, rsf's and scipy's alike, is
recomputed here as err = max over segment ends of |mu - mu_ref|, with mu_ref the peers file's
tight DOP853 reference, so all solvers are judged against one independent solution. mu is the
friction coefficient (dimensionless); wall time is per whole protocol, in ms. A run with
"error" (a failed solve) is listed in the table and left out of the plot; an error of exactly 0
is drawn at 1e-16.

Needs matplotlib (and numpy). No system copy here; one way:
    python3 -m venv /tmp/wpvenv && /tmp/wpvenv/bin/pip install numpy scipy matplotlib
and run it with /tmp/wpvenv/bin/python.
"""
import json
import os
import re
import sys

import matplotlib

matplotlib.use("svg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ERR_FLOOR = 1e-16
MARKERS = "osD^vP*Xh<>p"


def load(path):
    with open(path) as f:
        return json.load(f)


def judged(runs, mu_ref, source):
    """Copies of runs with err recomputed against mu_ref (or "error" if unusable)."""
    out = []
    for r in runs:
        r = dict(r)
        if "error" not in r:
            mu = r.get("mu")
            if mu is None or len(mu) != len(mu_ref):
                r["error"] = (f"{source}: {len(mu) if mu is not None else 'no'} mu values, "
                              f"reference has {len(mu_ref)}")
            elif not np.all(np.isfinite(mu)):
                r["error"] = f"{source}: non-finite mu"
            else:
                r["err"] = float(np.max(np.abs(np.asarray(mu, float) - mu_ref)))
        out.append(r)
    return out


def series(runs):
    """{solver: [runs sorted by descending rtol]} in first-seen order."""
    by = {}
    for r in runs:
        by.setdefault(r["solver"], []).append(r)
    return {s: sorted(rs, key=lambda r: -r["rtol"]) for s, rs in by.items()}


def plot_case(case, ref, groups, path):
    plt.rcParams.update({"svg.hashsalt": "rsf-work-precision", "font.size": 9})
    fig, ax = plt.subplots(figsize=(640 / 96, 440 / 96))  # 640 x 440 px in SVG units
    cmap = plt.get_cmap("tab10")
    for i, (solver, rs) in enumerate(groups.items()):
        ok = [r for r in rs if "error" not in r]
        if not ok:
            continue
        x = [max(r["err"], ERR_FLOOR) for r in ok]
        y = [1e3 * r["wall_s"] for r in ok]
        style = "-" if solver.startswith("rsf") else "--"
        ax.loglog(x, y, style, marker=MARKERS[i % len(MARKERS)], color=cmap(i % 10),
                  ms=5, lw=1.4, label=solver)
        for (xe, ye, r) in ((x[0], y[0], ok[0]), (x[-1], y[-1], ok[-1])):
            ax.annotate(f"{r['rtol']:.0e}", (xe, ye), textcoords="offset points",
                        xytext=(4, 3), fontsize=6.5, color=cmap(i % 10))
    xs = [max(r["err"], ERR_FLOOR) for rs in groups.values() for r in rs if "error" not in r]
    rvd = ref.get("radau_vs_dop853")
    if rvd is not None:  # errors left of this line are below the reference's own uncertainty
        xs.append(max(rvd, ERR_FLOOR))
        ax.axvline(xs[-1], color="0.6", ls=":", lw=1, zorder=0,
                   label="reference: Radau vs DOP853")
    if xs:
        ax.set_xlim(min(xs) / 3, max(xs) * 3)
    ax.set_xlabel("error in μ: max |μ − μ_ref| over segment ends")
    ax.set_ylabel("wall time per protocol (ms)")
    ax.set_title(f"Work–precision: {case}")
    ax.grid(True, which="major", color="0.85", lw=0.6)
    ax.grid(True, which="minor", color="0.94", lw=0.4)
    ax.legend(fontsize=7.5, frameon=False, loc="best")
    for side in ("top", "right"):
        ax.spines[side].set_visible(False)
    fig.tight_layout()
    fig.savefig(path, format="svg", metadata={"Date": None})
    plt.close(fig)


def table(case, peers, groups):
    ref = peers["reference"]
    rvd = ref.get("radau_vs_dop853")
    lines = [f"## {case}", "",
             f"Reference: scipy {ref.get('method', 'DOP853')} at rtol {ref.get('rtol', 1e-13):g}; "
             f"Radau rtol 1e-12 differs from it by "
             f"{'n/a' if rvd is None else f'{rvd:.1e}'} in μ. "
             f"{len(ref['mu'])} segment ends."
             + "".join(f" {n}" for n in ref.get("notes", [])), "",
             "| solver | rtol | wall ms | err |", "| --- | ---: | ---: | ---: |"]
    for solver, rs in groups.items():
        for r in rs:
            if "error" in r:
                msg = r["error"].replace("|", "\\|").replace("<", "&lt;").replace("\n", " ")[:120]
                lines.append(f"| {solver} | {r['rtol']:.0e} | — | failed: {msg} |")
            else:
                lines.append(f"| {solver} | {r['rtol']:.0e} | {1e3 * r['wall_s']:.2f} "
                             f"| {r['err']:.1e} |")
    v = peers.get("versions", {})
    if v:
        lines += ["", "scipy runs: " + ", ".join(f"{k} {v[k]}" for k in sorted(v)) + "."]
    return "\n".join(lines) + "\n"


def main():
    argv = sys.argv[1:]
    if len(argv) < 3 or len(argv) % 2 != 1:
        sys.exit(__doc__)
    outdir, pairs = argv[0], list(zip(argv[1::2], argv[2::2]))
    os.makedirs(outdir, exist_ok=True)
    md = ["# Work–precision: rsf and scipy", "",
          "Error: max |μ − μ_ref| over segment ends, μ_ref = scipy DOP853 at rtol 1e-13 "
          "(independent of rsf). Wall: median per whole protocol.", ""]
    for rsf_path, peers_path in pairs:
        rsf, peers = load(rsf_path), load(peers_path)
        case = peers["case"]
        if rsf.get("case", case) != case:
            sys.exit(f"case mismatch: {rsf_path} is {rsf.get('case')!r}, {peers_path} is {case!r}")
        mu_ref = np.asarray(peers["reference"]["mu"], float)
        runs = judged(rsf["runs"], mu_ref, rsf_path) + judged(peers["runs"], mu_ref, peers_path)
        groups = series(runs)
        name = re.sub(r"[^A-Za-z0-9_.-]+", "_", case)
        svg = os.path.join(outdir, f"work_precision_{name}.svg")
        plot_case(case, peers["reference"], groups, svg)
        md += [table(case, peers, groups), f"![{case}](work_precision_{name}.svg)", ""]
        print(svg)
    path = os.path.join(outdir, "work_precision.md")
    with open(path, "w") as f:
        f.write("\n".join(md))
    print(path)


if __name__ == "__main__":
    main()
