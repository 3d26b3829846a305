"""SEAS BP1-QD run by a QDYN build (its own friction or rsf's), with the event catalogue.

Usage: python bp1.py QDYN_SRC_DIR --cells 512 --years 3000 --out DIR

QDYN_SRC_DIR is the `src` folder of a built QDYN (it holds `qdyn` and `pyqdyn.py`). The
problem is the benchmark's (Erickson et al. 2020), set through pyqdyn's documented settings:
MESHDIM = 1 with FINITE = 3 (a fault of length L mirrored about the free surface, steady creep
at V_p outside), the SEAS regularized law (RNS_LAW = 2), the aging law, RKF45 (SOLVER = 2) at
ACC = 1e-7, a(z) from 0.010 to 0.025 between 15 and 18 km, the benchmark's initial stress and
depth-dependent initial state. Writes DIR/events.csv in rsf-cycle's columns
(onset_yr,peak_slip_rate_m_s,surface_slip_m,nucleation_depth_km: onset when the fault-wide
maximum V first reaches 1e-3 m/s, interpolated in ln V between output steps) and
DIR/run.json (wall time of the QDYN executable, steps, settings).
"""

import argparse
import json
import math
import os
import sys
import time

import numpy as np

YEAR = 365.0 * 86400.0  # the SEAS convention, as rsf-cycle's YEAR
V_EVENT = 1e-3  # m/s: the benchmark's event threshold


def bp1_settings(p, cells, years):
    rho, cs, sigma = 2670.0, 3464.0, 50e6
    a0, amax, b, dc = 0.010, 0.025, 0.015, 0.008
    v0, f0, vp, vinit = 1e-6, 0.6, 1e-9, 1e-9
    big_h, h, length = 15e3, 3e3, 40e3
    s = p.set_dict
    s.update({
        "MESHDIM": 1, "FINITE": 3, "SOLVER": 2, "ACC": 1e-7, "N": cells, "L": length, "W": 50e3,
        "VS": cs, "MU": rho * cs**2, "SIGMA": sigma, "V_PL": vp, "TMAX": years * YEAR,
        "NTOUT_OT": 1, "NTOUT": 10**8, "NXOUT": cells, "DTTRY": 1e-3,
        "FEAT_STRESS_COUPL": 0, "FEAT_TP": 0, "FEAT_LOCALISATION": 0,
    })
    s["SET_DICT_RSF"].update({"RNS_LAW": 2, "THETA_LAW": 1, "A": a0, "B": b, "DC": dc, "V_SS": v0,
                              "MU_SS": f0, "V_0": vinit, "TH_0": dc / v0, "V1": 0.01, "V2": 1e-7, "CO": 0})
    p.settings(s)
    p.render_mesh()
    # element i (from 0) spans depths [i, i + 1] L/N from the free surface (FINITE = 3; pyqdyn
    # leaves X at 0 for this geometry, so the depths are computed here)
    depth = (np.arange(cells) + 0.5) * length / cells
    a = np.where(depth < big_h, a0, np.where(depth < big_h + h, a0 + (amax - a0) * (depth - big_h) / h, amax))
    eta = rho * cs / 2.0
    tau0 = sigma * amax * math.asinh(vinit / (2 * v0) * math.exp((f0 + b * math.log(v0 / vinit)) / amax)) + eta * vinit
    theta0 = dc / v0 * np.exp(a / b * np.log(2 * v0 / vinit * np.sinh((tau0 - eta * vinit) / (a * sigma))) - f0 / b)
    p.mesh_dict["A"] = a
    p.mesh_dict["TH_0"] = theta0
    iot = np.zeros(cells, dtype=int)
    iot[int(np.argmin(depth))] = 1  # the surface element's time series
    p.mesh_dict["IOT"] = iot
    return depth


def catalogue(t, vmax, ivmax, t_surf, slip_surf, depth):
    """Events from the fault-wide maximum slip rate: onset at the first crossing of V_EVENT
    (interpolated in ln V), end at the next crossing down; peak and surface slip inside."""
    events = []
    above = vmax >= V_EVENT
    i = 1
    n = len(t)
    while i < n:
        if above[i] and not above[i - 1]:
            w = (math.log(V_EVENT) - math.log(vmax[i - 1])) / (math.log(vmax[i]) - math.log(vmax[i - 1]))
            onset = t[i - 1] + w * (t[i] - t[i - 1])
            j = i
            while j < n and above[j]:
                j += 1
            end = t[min(j, n - 1)]
            s0 = np.interp(onset, t_surf, slip_surf)
            s1 = np.interp(end, t_surf, slip_surf)
            events.append((onset / YEAR, float(vmax[i:j].max()), float(s1 - s0), float(depth[int(ivmax[i]) - 1]) / 1e3))
            i = j
        i += 1
    return events


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("src")
    ap.add_argument("--cells", type=int, default=512)
    ap.add_argument("--years", type=float, default=3000.0)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    src = os.path.abspath(args.src)
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    sys.path.insert(0, src)
    from pyqdyn import qdyn  # QDYN's own wrapper, from the checkout under test

    os.chdir(out)
    p = qdyn()
    depth = bp1_settings(p, args.cells, args.years)
    p.write_input()
    t0 = time.perf_counter()
    failed = p.run()
    wall = time.perf_counter() - t0
    if failed:
        sys.exit(f"bp1.py: QDYN failed in {out}")
    p.read_output(read_ox=False)
    vm = p.ot_vmax
    t = vm["t"].to_numpy(float)
    surf = p.ot[0]
    events = catalogue(t, vm["v"].to_numpy(float), vm["ivmax"].to_numpy(int), surf["t"].to_numpy(float),
                       surf["slip"].to_numpy(float), depth)
    tmp = os.path.join(out, "events.csv.tmp")
    with open(tmp, "w") as f:
        f.write("onset_yr,peak_slip_rate_m_s,surface_slip_m,nucleation_depth_km\n")
        for e in events:
            f.write("%.6f,%.6g,%.6g,%.4f\n" % e)
    os.replace(tmp, os.path.join(out, "events.csv"))
    info = {"cells": args.cells, "years": args.years, "wall_s": wall, "steps": int(len(t)), "events": len(events),
            "qdyn_src": src}
    with open(os.path.join(out, "run.json.tmp"), "w") as f:
        json.dump(info, f, indent=1)
    os.replace(os.path.join(out, "run.json.tmp"), os.path.join(out, "run.json"))
    for f in os.listdir(out):  # QDYN's raw outputs are large; the catalogue is what is kept
        if f.startswith("output_") or f == "qdyn.in":
            os.remove(os.path.join(out, f))
    print(json.dumps(info))


if __name__ == "__main__":
    main()
