#!/usr/bin/env python3
"""rsf.simulate against scipy in the same process, on the seed-like protocol.

    python crates/rsf-py/bench/bench_simulate.py [--repeats 31]

Needs the rsf package and scipy in the same environment (e.g. `bash crates/rsf-py/test.sh`, then
`target/pyvenv/bin/pip install scipy`). The protocol (seed_protocol.json, written by
`cargo run --release -p rsf-solvers --example bench_protocol`) is 71 segments of constant
load-point velocity, one Slip-law state, rtol 1e-8. Three solvers of the same equations:

* rsf.simulate (method auto, output every 50 s) — the whole call: TOML, solve, numpy arrays;
* scipy solve_ivp(Radau) with the exact Jacobian, restarted at every segment (benches/scipy_protocol.py);
* rsfmodel-style: scipy odeint (LSODA) over (mu, theta) with V from the inverted friction law,
  one call per segment, as the rsfmodel package integrates (written here from its equations).
"""
import argparse
import json
import os
import statistics
import sys
import time

import numpy as np
from scipy.integrate import odeint

import rsf

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "..", "benches"))
import scipy_protocol  # noqa: E402


def toml_text(p):
    m, s = p["model"], p["model"]["states"][0]
    lines = ["[model]", f"mu0 = {m['mu0']!r}", f"v0 = {m['v0']!r}", f"a = {m['a']!r}", f"stiffness = {m['k']!r}",
             "[[model.state]]", f"law = \"{s['law']}\"", f"b = {s['b']!r}", f"dc = {s['dc']!r}",
             "[loading]", f"v_init = {p['v_init']!r}"]
    for seg in p["segments"]:
        lines += ["[[loading.segment]]", f"v = {seg['v']!r}", f"duration = {seg['duration']!r}"]
    lines += ["[output]", "dt = 50.0", "[solver]", "method = \"auto\"", f"rtol = {p['rtol']!r}", f"atol = {p['atol']!r}"]
    return "\n".join(lines) + "\n"


def rsfmodel_style(p, rtol):
    """(mu, theta) with V = v0 exp((mu - mu0 - b ln(v0 theta/dc))/a), dmu/dt = k (v_lp - V),
    Slip law; odeint per segment (LSODA), as rsfmodel does."""
    m, s = p["model"], p["model"]["states"][0]
    mu0, a, k, v0, b, dc = m["mu0"], m["a"], m["k"], m["v0"], s["b"], s["dc"]

    def rhs(y, t, vlp):
        mu, th = y
        v = v0 * np.exp((mu - mu0 - b * np.log(v0 * th / dc)) / a)
        om = v * th / dc
        return [k * (vlp - v), -om * np.log(om)]

    vi = p["v_init"]
    y = [mu0 + (a - b) * np.log(vi / v0), dc / vi]
    for seg in p["segments"]:
        out = odeint(rhs, y, [0.0, seg["duration"]], args=(seg["v"],), rtol=rtol, atol=1e-12, mxstep=10 ** 6)
        y = out[-1]
    return y[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=31)
    args = ap.parse_args()
    with open(os.path.join(HERE, "seed_protocol.json")) as f:
        p = json.load(f)
    text = toml_text(p)
    rsf.simulate(text)  # warm
    t_rsf = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        out = rsf.simulate(text)
        t_rsf.append(time.perf_counter() - t0)
    model = scipy_protocol.Model(p["model"])
    vi = p["v_init"]
    y0 = np.concatenate([[np.log(vi)], model.lndc - np.log(vi), [0.0]])
    atol = np.array([p["rtol"]] * (model.n + 1) + [p["atol"]])
    t_radau = []
    for _ in range(3):
        t0 = time.perf_counter()
        y, _ = scipy_protocol.run_protocol(model, y0, p["segments"], "Radau", p["rtol"], atol)
        t_radau.append(time.perf_counter() - t0)
    t_ode = []
    for _ in range(3):
        t0 = time.perf_counter()
        mu_odeint = rsfmodel_style(p, p["rtol"])
        t_ode.append(time.perf_counter() - t0)
    mu_rsf, mu_radau = out["mu"][-1], float(model.mu(y))
    r, rad, ode = statistics.median(t_rsf), statistics.median(t_radau), statistics.median(t_ode)
    print(json.dumps({
        "rows": len(out["mu"]),
        "rsf_simulate_ms": r * 1e3, "rsf_min_ms": min(t_rsf) * 1e3,
        "scipy_radau_ms": rad * 1e3, "rsfmodel_style_odeint_ms": ode * 1e3,
        "speedup_vs_radau": rad / r, "speedup_vs_odeint": ode / r,
        "end_mu": {"rsf": mu_rsf, "radau": mu_radau, "odeint": float(mu_odeint)},
    }, indent=1))


if __name__ == "__main__":
    main()
