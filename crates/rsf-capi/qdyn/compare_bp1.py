"""The BP1-QD comparison table of run.sh --bp1: QDYN on rsf's friction, QDYN on its own, and
rsf-cycle, from WORK/bp1_{rsf,own,cycle}/events.csv and run.json (Markdown on stdout)."""

import csv
import json
import os
import sys


def load(work, name):
    d = os.path.join(work, "bp1_" + name)
    if not os.path.exists(os.path.join(d, "events.csv")):
        return None
    with open(os.path.join(d, "events.csv")) as f:
        ev = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    # large events only: the benchmark's events all exceed 1 m/s; a flicker of the fault-wide
    # maximum around the threshold as a rupture arrests is not an event of its own
    ev = [e for e in ev if e["peak_slip_rate_m_s"] > 0.1]
    run = {}
    if os.path.exists(os.path.join(d, "run.json")):
        with open(os.path.join(d, "run.json")) as f:
            run = json.load(f)
    return ev, run


def row(ev, run):
    on = [e["onset_yr"] for e in ev]
    iv = [b - a for a, b in zip(on, on[1:])]
    return {
        "events": f"{len(ev)}",
        "first onset (yr)": f"{on[0]:.2f}" if on else "-",
        "intervals 1-3 (yr)": ", ".join(f"{x:.2f}" for x in iv[:3]) or "-",
        "last interval (yr)": f"{iv[-1]:.2f}" if iv else "-",
        "peak V first / last (m/s)": f"{ev[0]['peak_slip_rate_m_s']:.3f} / {ev[-1]['peak_slip_rate_m_s']:.3f}" if ev else "-",
        "surface slip first / last (m)": f"{ev[0]['surface_slip_m']:.3f} / {ev[-1]['surface_slip_m']:.3f}" if ev else "-",
        "nucleation depth (km)": f"{min(e['nucleation_depth_km'] for e in ev):.2f}-{max(e['nucleation_depth_km'] for e in ev):.2f}" if ev else "-",
        "wall time (s)": f"{run['wall_s']:.1f}" if "wall_s" in run else "-",
    }


def main():
    work = sys.argv[1]
    cols = [("rsf", "QDYN on rsf's friction"), ("own", "QDYN on its own friction"), ("cycle", "rsf-cycle")]
    rows = {name: row(*got) for name, _ in cols if (got := load(work, name)) is not None}
    names = [(n, t) for n, t in cols if n in rows]
    print("| quantity | " + " | ".join(t for _, t in names) + " |")
    print("|---|" + "---|" * len(names))
    for q in next(iter(rows.values())).keys():
        print(f"| {q} | " + " | ".join(rows[n][q] for n, _ in names) + " |")


if __name__ == "__main__":
    main()
