#!/usr/bin/env python3
"""Peer comparison for the rsf protocol benchmark.

This is the peer approach: scipy solve_ivp over the same log-variable equations,
for docs/BENCHMARKS.md. It integrates a rate-and-state spring-slider through a
piecewise-constant load-point velocity protocol and prints timing and work as JSON.

    python3 benches/scipy_protocol.py PROTOCOL.json [--repeats 5] [--method Radau]

State y = (x = ln V, z_1..z_N = ln theta_i, delta = slip); units um, s, um/s, k in 1/um.
    mu       = mu0 + a (x - ln v0) + sum_i b_i (ln v0 + z_i - ln dc_i)
    dz_i/dt  = G_i(V, theta_i) / theta_i
               aging: G = 1 - V theta/dc        slip: G = -(V theta/dc) ln(V theta/dc)
    dx/dt    = (k (v_lp - V) - sum_i b_i dz_i/dt) / a
    ddelta/dt = V
"""
import argparse
import json
import platform
import statistics
import sys
import time

import numpy as np
import scipy
from scipy.integrate import solve_ivp

IMPLICIT = {"Radau", "BDF", "LSODA"}  # methods that accept jac=


class Model:
    def __init__(self, m):
        self.mu0, self.a, self.k = m["mu0"], m["a"], m["k"]
        self.lnv0 = np.log(m["v0"])
        st = m["states"]
        for s in st:
            if s["law"] not in ("aging", "slip"):
                raise ValueError(f"unknown law {s['law']!r}")
        self.n = len(st)
        self.b = np.array([s["b"] for s in st], float)
        self.lndc = np.log([s["dc"] for s in st])
        self.aging = np.array([s["law"] == "aging" for s in st])

    def zdot_and_partials(self, x, z):
        """dz/dt and its partials d/dx, d/dz (diagonal), per state."""
        v_dc = np.exp(x - self.lndc)   # V/dc
        lnw = x + z - self.lndc        # ln(V theta/dc)
        inv_th = np.exp(-z)            # 1/theta
        # aging: zdot = 1/theta - V/dc ;             d/dx = -V/dc,              d/dz = -1/theta
        # slip:  zdot = -(V/dc) ln w ;               d/dx = -(V/dc)(ln w + 1), d/dz = -V/dc
        zd = np.where(self.aging, inv_th - v_dc, -v_dc * lnw)
        dx = np.where(self.aging, -v_dc, -v_dc * (lnw + 1.0))
        dz = np.where(self.aging, -inv_th, -v_dc)
        return zd, dx, dz

    def rhs(self, t, y, vlp):
        x, z = y[0], y[1:-1]
        v = np.exp(x)
        zd, _, _ = self.zdot_and_partials(x, z)
        out = np.empty_like(y)
        out[0] = (self.k * (vlp - v) - self.b @ zd) / self.a
        out[1:-1] = zd
        out[-1] = v
        return out

    def jac(self, t, y, vlp):
        x, z = y[0], y[1:-1]
        v = np.exp(x)
        _, dx, dz = self.zdot_and_partials(x, z)
        n = self.n
        J = np.zeros((n + 2, n + 2))
        J[0, 0] = (-self.k * v - self.b @ dx) / self.a
        J[0, 1:n + 1] = -self.b * dz / self.a
        J[1:n + 1, 0] = dx
        J[np.arange(1, n + 1), np.arange(1, n + 1)] = dz
        J[n + 1, 0] = v                   # ddelta/dt = V; no column depends on delta
        return J

    def mu(self, y):
        return self.mu0 + self.a * (y[0] - self.lnv0) + self.b @ (self.lnv0 + y[1:-1] - self.lndc)


def check_jacobian(model, y, vlp, tol=1e-5):
    """Central-difference check of the analytic Jacobian; raises if it is wrong."""
    J = model.jac(0.0, y, vlp)
    Jfd = np.zeros_like(J)
    for j in range(len(y)):
        h = 1e-6 * max(1.0, abs(y[j]))
        yp, ym = y.copy(), y.copy()
        yp[j] += h
        ym[j] -= h
        Jfd[:, j] = (model.rhs(0.0, yp, vlp) - model.rhs(0.0, ym, vlp)) / (2 * h)
    scale = np.maximum(np.abs(Jfd), 1e-9 * np.abs(Jfd).max())
    err = (np.abs(J - Jfd) / scale).max()
    assert err < tol, f"analytic Jacobian disagrees with finite differences: max rel err {err:.3e}"
    return err


def run_protocol(model, y0, segments, method, rtol, atol):
    y = y0.copy()
    work = {"nfev": 0, "njev": 0, "nlu": 0}
    for seg in segments:
        vlp = float(seg["v"])
        kw = {"jac": model.jac} if method in IMPLICIT else {}
        sol = solve_ivp(model.rhs, (0.0, float(seg["duration"])), y, method=method,
                        rtol=rtol, atol=atol, args=(vlp,), first_step=None, **kw)
        if not sol.success:
            raise RuntimeError(f"solve_ivp failed on segment {seg}: {sol.message}")
        y = sol.y[:, -1].copy()  # restart exactly at the segment boundary
        for key in work:
            work[key] += int(sol[key])
    return y, work


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("protocol")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--method", default="Radau")
    args = ap.parse_args()

    with open(args.protocol) as f:
        p = json.load(f)
    model = Model(p["model"])
    n = model.n
    v_init = float(p["v_init"])
    # Steady state at v_init: theta_i = dc_i / v_init, delta = 0.
    y0 = np.concatenate([[np.log(v_init)], model.lndc - np.log(v_init), [0.0]])
    rtol = float(p["rtol"])
    # atol per component: x and z_i are logs, so an absolute error of rtol on them is a
    # relative error of ~rtol on V and theta_i; slip delta gets the protocol's absolute atol.
    atol = np.array([rtol] * (n + 1) + [float(p["atol"])])
    segments = p["segments"]

    # Verify the hand-derived Jacobian once, at a perturbed (non-steady) state.
    y_chk = y0 + np.concatenate([[0.3], -0.2 - 0.1 * np.arange(n), [1.0]])
    check_jacobian(model, y_chk, float(segments[0]["v"]) if segments else v_init)

    walls = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        y, work = run_protocol(model, y0, segments, args.method, rtol, atol)
        walls.append(time.perf_counter() - t0)

    out = {
        "method": args.method, "rtol": rtol, "repeats": args.repeats,
        "wall_s_all": walls, "wall_s_median": statistics.median(walls),
        **work, "n_segments": len(segments),
        "end": {"mu": float(model.mu(y)), "v": float(np.exp(y[0])),
                "theta": np.exp(y[1:-1]).tolist(), "slip": float(y[-1])},
        "scipy": scipy.__version__, "numpy": np.__version__, "python": platform.python_version(),
    }
    json.dump(out, sys.stdout)
    print()


if __name__ == "__main__":
    main()
