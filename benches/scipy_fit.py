#!/usr/bin/env python3
"""Peer comparison for the rsf fitting benchmark.

This is the peer approach: finite-difference least squares over scipy's ODE solvers, for
docs/BENCHMARKS.md. It fits (mu0, a, b, dc) of a one-state rate-and-state spring-slider to a
lab friction record with scipy.optimize.least_squares (default '2-point' Jacobian, i.e. one
extra forward run per parameter per Jacobian), each forward run being solve_ivp segment by
segment through the load-point protocol, and prints timing and work as JSON.

    python3 benches/scipy_fit.py RECORD.csv SETUP.json [--repeats 3]
        [--method RK45|DOP853|LSODA|Radau] [--ls-method trf|lm]

State y = (x = ln V, z = ln theta); units um, s, um/s, k in 1/um.
    mu     = mu0 + a (x - ln v0) + b (ln v0 + z - ln dc)
    dz/dt  = aging: 1/theta - V/dc          slip: -(V/dc) ln(V theta/dc)
    dx/dt  = (k (v_lp - V) - b dz/dt) / a
Fitted vector p = (mu0, ln a, b, ln dc), so a and dc stay positive (as in rsf).
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
from scipy.optimize import least_squares

IMPLICIT = {"Radau", "BDF", "LSODA"}  # methods that accept jac=
FAIL = 1e3                            # residual returned when a trial point cannot be integrated


def read_record(path):
    d = np.genfromtxt(path, delimiter=",", names=True)
    t, lp, mu = d["time_s"], d["load_point_um"], d["mu"]
    if t[0] != 0.0 or np.any(np.diff(t) <= 0):
        raise ValueError("record times must start at 0 and strictly increase")
    return t, lp, mu


def split_segments(t, segments):
    """Per segment (t0, t1, v_lp, sample indices); a boundary sample goes to the later segment."""
    ends = np.cumsum([float(s["duration"]) for s in segments])
    starts = np.concatenate([[0.0], ends[:-1]])
    tol = 1e-9 * max(1.0, ends[-1])
    if t[-1] > ends[-1] + tol:
        raise ValueError(f"record runs to t={t[-1]} past the protocol end {ends[-1]}")
    t = t.copy()
    for e in ends:  # snap samples that sit on a boundary onto it exactly
        t[np.abs(t - e) <= tol] = e
    out = []
    for i, (t0, t1, s) in enumerate(zip(starts, ends, segments)):
        last = i == len(segments) - 1
        idx = np.nonzero((t >= t0) & ((t <= t1) if last else (t < t1)))[0]
        if t1 > t0:
            out.append((t0, t1, float(s["v"]), idx))
    return t, out


def check_load_point(t, lp, plan):
    """Warn if the record's load point does not follow the protocol in SETUP.json."""
    pred = np.empty_like(t)
    x0 = 0.0
    for t0, t1, v, idx in plan:
        pred[idx] = x0 + v * (t[idx] - t0)
        x0 += v * (t1 - t0)
    err = np.abs((lp - lp[0]) - pred).max()
    if err > 1e-6 * max(1.0, np.abs(pred).max()):
        print(f"warning: load point differs from the protocol by up to {err:.3g} um", file=sys.stderr)


class Forward:
    """Forward model mu(t; p) at the record times, counting the solves."""

    def __init__(self, setup, t, plan, method):
        self.aging = {"aging": True, "slip": False}[setup["law"]]
        self.k, self.lnv0 = float(setup["k"]), np.log(float(setup["v0"]))
        self.lnvi = np.log(float(setup["v_init"]))
        self.rtol = float(setup["rtol"])
        self.t, self.plan, self.method = t, plan, method
        self.n_solves = 0

    def zdot(self, x, z, lndc):
        if self.aging:
            return np.exp(-z) - np.exp(x - lndc)
        return -np.exp(x - lndc) * (x + z - lndc)

    def rhs(self, t, y, vlp, a, b, lndc):
        zd = self.zdot(y[0], y[1], lndc)
        return [(self.k * (vlp - np.exp(y[0])) - b * zd) / a, zd]

    def jac(self, t, y, vlp, a, b, lndc):
        x, z = y
        v_dc = np.exp(x - lndc)
        if self.aging:
            dx, dz = -v_dc, -np.exp(-z)
        else:
            dx, dz = -v_dc * (x + z - lndc + 1.0), -v_dc
        return [[(-self.k * np.exp(x) - b * dx) / a, -b * dz / a], [dx, dz]]

    def mu(self, p):
        """Model friction at every record time; None if the integration fails."""
        self.n_solves += 1
        mu0, a, b, lndc = p[0], np.exp(p[1]), p[2], p[3]
        y = np.array([self.lnvi, lndc - self.lnvi])  # steady state at v_init
        out = np.empty((2, len(self.t)))
        kw = {"jac": self.jac} if self.method in IMPLICIT else {}
        for t0, t1, vlp, idx in self.plan:
            t_eval = self.t[idx]
            if not len(idx) or t_eval[-1] < t1:  # t1 too, to restart exactly on the boundary
                t_eval = np.append(t_eval, t1)
            sol = solve_ivp(self.rhs, (t0, t1), y, method=self.method, t_eval=t_eval,
                            rtol=self.rtol, atol=[self.rtol, self.rtol],
                            args=(vlp, a, b, lndc), **kw)
            if not sol.success or not np.all(np.isfinite(sol.y)):
                return None
            out[:, idx] = sol.y[:, :len(idx)]
            y = sol.y[:, -1].copy()
        return mu0 + a * (out[0] - self.lnv0) + b * (self.lnv0 + out[1] - lndc)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("record")
    ap.add_argument("setup")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--method", default="DOP853", choices=["RK45", "DOP853", "LSODA", "Radau"])
    ap.add_argument("--ls-method", default="trf", choices=["trf", "lm"])
    args = ap.parse_args()

    with open(args.setup) as f:
        setup = json.load(f)
    t, lp, data = read_record(args.record)
    t, plan = split_segments(t, setup["segments"])
    check_load_point(t, lp, plan)
    fwd = Forward(setup, t, plan, args.method)

    def residual(p):
        with np.errstate(all="ignore"):
            try:
                m = fwd.mu(p)
            except (ArithmeticError, ValueError):
                m = None
        return np.full(len(data), FAIL) if m is None else m - data

    ini = setup["initial"]
    p0 = np.array([ini["mu0"], np.log(ini["a"]), ini["b"], np.log(ini["dc"])], float)
    walls = []
    for _ in range(args.repeats):
        fwd.n_solves = 0
        t0 = time.perf_counter()
        res = least_squares(residual, p0, jac="2-point", x_scale="jac", method=args.ls_method)
        walls.append(time.perf_counter() - t0)

    p = res.x
    out = {
        "method": args.method, "ls_method": args.ls_method, "repeats": args.repeats,
        "wall_s_all": walls, "wall_s_median": statistics.median(walls),
        "nfev": int(res.nfev), "njev": None if res.njev is None else int(res.njev),
        "n_ode_solves": fwd.n_solves,
        "params": {"mu0": float(p[0]), "a": float(np.exp(p[1])), "b": float(p[2]),
                   "dc": float(np.exp(p[3]))},
        "rms": float(np.sqrt(np.mean(res.fun ** 2))), "n": len(data),
        "success": bool(res.success), "message": res.message,
        "scipy": scipy.__version__, "numpy": np.__version__, "python": platform.python_version(),
    }
    json.dump(out, sys.stdout)
    print()


if __name__ == "__main__":
    main()
