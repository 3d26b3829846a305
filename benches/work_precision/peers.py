#!/usr/bin/env python3
"""Work-precision peers: scipy solve_ivp on an rsf spring-slider protocol, error in mu vs wall time.

    python3 benches/work_precision/peers.py CASE.json OUT.json \
        [--rtols 1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10] [--methods Radau,LSODA,DOP853] [--repeats 3]

Needs numpy and scipy (no system copy here; one way:
    python3 -m venv /tmp/wpvenv && /tmp/wpvenv/bin/pip install numpy scipy matplotlib
and run it with /tmp/wpvenv/bin/python).

Units: slip and Dc in um, time in s, velocities in um/s, k in 1/um (friction per um),
eta in friction per (um/s). State y = (x = ln V, z_1..z_N = ln theta_i, delta = slip), the
same log variables rsf integrates:
    dz_i/dt    = G_i / theta_i       aging: G = 1 - V theta/Dc    slip: G = -(V theta/Dc) ln(V theta/Dc)
    dx/dt      = (k (v_lp - V) - sum_i b_i dz_i/dt) / (a + eta V)   (radiation damping eta)
    ddelta/dt  = V
    mu         = mu0 + a (x - ln v0) + sum_i b_i (ln v0 + z_i - ln Dc_i) + eta V
Start at steady state at v_init: theta_i = Dc_i / v_init, delta = 0. Each segment (v_lp =
seg.v, for seg.duration s; v_lp = 0 is a hold) is a separate solve_ivp call from the state at
the end of the previous one, so every velocity discontinuity is an exact restart. mu is
reported at the end of every segment. Tolerances: rtol on all components; atol = rtol on x and
z_i (logs, so a relative error on V, theta), atol = 1e-12 um on delta. Radau and LSODA get the
analytic Jacobian (checked against central differences before any run). Overflow warnings are
silenced during solves: an explicit method's over-long trial step can overflow exp(x) before the
step is rejected (NaN error norm), which is how scipy's RK step control works, not a failure.

The reference is DOP853 at rtol 1e-13 (Radau at rtol 1e-12 is solved too and their max
|delta mu| over segment ends is reported); if a tight solve fails or passes the time limit,
the next candidate is used and OUT.json says so. Each method x rtol run records the median wall
time over --repeats whole-protocol solves (time.perf_counter), nfev/njev/nlu summed over
segments, mu at segment ends and err = max |mu - mu_ref|; a failing solve is recorded with
"error" instead.
"""
import argparse
import gc
import json
import os
import platform
import statistics
import sys
import time

import numpy as np
import scipy
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from scipy_protocol import Model  # noqa: E402  (constructor and dz/dt partials, eta = 0)

IMPLICIT = {"Radau", "BDF", "LSODA"}  # methods that accept jac=
DELTA_ATOL = 1e-12                    # um
REF_LIMIT_S = 600.0                   # per tight reference solve
SLOW_FIRST_S = 20.0                   # a first repeat slower than this is not repeated


class TimeLimit(Exception):
    pass


class DampedModel(Model):
    """scipy_protocol.Model plus radiation damping eta (eta = 0 gives the same equations)."""

    def __init__(self, m):
        super().__init__(m)
        self.eta = float(m.get("eta", 0.0))
        if self.eta < 0:
            raise ValueError("eta must be >= 0")

    def rhs(self, t, y, vlp):
        x, z = y[0], y[1:-1]
        v = np.exp(x)
        zd, _, _ = self.zdot_and_partials(x, z)
        out = np.empty_like(y)
        out[0] = (self.k * (vlp - v) - self.b @ zd) / (self.a + self.eta * v)
        out[1:-1] = zd
        out[-1] = v
        return out

    def jac(self, t, y, vlp):
        # xdot = N / D with N = k (vlp - V) - sum b zd, D = a + eta V, dV/dx = V:
        # dxdot/dx = (dN/dx - xdot eta V) / D,   dxdot/dz_i = -b_i dzd_i/dz_i / D.
        x, z = y[0], y[1:-1]
        v = np.exp(x)
        zd, dx, dz = self.zdot_and_partials(x, z)
        n = self.n
        d = self.a + self.eta * v
        xdot = (self.k * (vlp - v) - self.b @ zd) / d
        J = np.zeros((n + 2, n + 2))
        J[0, 0] = (-self.k * v - self.b @ dx - xdot * self.eta * v) / d
        J[0, 1:n + 1] = -self.b * dz / d
        J[1:n + 1, 0] = dx
        J[np.arange(1, n + 1), np.arange(1, n + 1)] = dz
        J[n + 1, 0] = v                    # ddelta/dt = V; no column depends on delta
        return J

    def mu(self, y):
        return super().mu(y) + self.eta * np.exp(y[0])


def check_jacobian(model, y, vlp, tol=1e-5):
    """Central differences vs the analytic Jacobian; raises ValueError if they disagree."""
    J = model.jac(0.0, y, vlp)
    Jfd = np.zeros_like(J)
    for j in range(len(y)):
        h = 1e-6 * max(1.0, abs(y[j]))
        yp, ym = y.copy(), y.copy()
        yp[j] += h
        ym[j] -= h
        Jfd[:, j] = (model.rhs(0.0, yp, vlp) - model.rhs(0.0, ym, vlp)) / (2 * h)
    scale = np.maximum(np.abs(Jfd), 1e-9 * np.abs(Jfd).max())
    err = float((np.abs(J - Jfd) / scale).max())
    if not err < tol:
        raise ValueError(f"analytic Jacobian disagrees with finite differences at vlp={vlp}: "
                         f"max rel err {err:.3e}\nanalytic\n{J}\nfinite differences\n{Jfd}")
    return err


def run_protocol(model, y0, segments, method, rtol, limit_s):
    """Whole protocol; returns (mu at segment ends, work). Raises on failure or time limit."""
    n = model.n
    atol = np.array([rtol] * (n + 1) + [DELTA_ATOL])
    deadline = time.perf_counter() + limit_s

    def fun(t, y, vlp):
        if time.perf_counter() > deadline:
            raise TimeLimit(f"time limit {limit_s:g} s exceeded")
        return model.rhs(t, y, vlp)

    kw = {"jac": model.jac} if method in IMPLICIT else {}
    y = y0.copy()
    mus = []
    work = {"nfev": 0, "njev": 0, "nlu": 0}
    for i, seg in enumerate(segments):
        vlp, dur = float(seg["v"]), float(seg["duration"])
        with np.errstate(over="ignore", invalid="ignore"):  # rejected explicit trial steps
            sol = solve_ivp(fun, (0.0, dur), y, method=method, rtol=rtol, atol=atol,
                            args=(vlp,), **kw)
        if not sol.success:
            raise RuntimeError(f"segment {i} (v={vlp:g}, duration={dur:g}): {sol.message}")
        y = sol.y[:, -1].copy()            # restart exactly at the segment boundary
        if not np.all(np.isfinite(y)):
            raise RuntimeError(f"segment {i}: non-finite state {y}")
        mus.append(float(model.mu(y)))
        for key in work:
            work[key] += int(sol[key])
    return mus, work


def try_solve(model, y0, segments, method, rtol, limit_s):
    t0 = time.perf_counter()
    try:
        mus, work = run_protocol(model, y0, segments, method, rtol, limit_s)
        return mus, work, time.perf_counter() - t0, None
    except Exception as e:  # a failed solve is a result, not a crash
        return None, None, time.perf_counter() - t0, f"{type(e).__name__}: {e}"


def reference(model, y0, segments, log):
    """DOP853 1e-13 and Radau 1e-12; falls back to looser solves if those fail."""
    sols, notes = {}, []
    for method, rtol in [("DOP853", 1e-13), ("Radau", 1e-12)]:
        mus, work, wall, err = try_solve(model, y0, segments, method, rtol, REF_LIMIT_S)
        log(f"reference {method} rtol {rtol:g}: {wall:.1f} s" + (f"  FAILED {err}" if err else ""))
        if err:
            notes.append(f"{method} rtol {rtol:g} failed after {wall:.1f} s: {err}")
        else:
            sols[method] = (rtol, mus, wall, work["nfev"])
    for method, rtol in [("DOP853", 1e-12), ("Radau", 1e-11)]:
        if sols:
            break
        mus, work, wall, err = try_solve(model, y0, segments, method, rtol, REF_LIMIT_S)
        log(f"fallback reference {method} rtol {rtol:g}: {wall:.1f} s" + (f"  FAILED {err}" if err else ""))
        if err:
            notes.append(f"{method} rtol {rtol:g} failed after {wall:.1f} s: {err}")
        else:
            sols[method] = (rtol, mus, wall, work["nfev"])
    if not sols:
        raise SystemExit("no reference solve succeeded:\n" + "\n".join(notes))
    method = "DOP853" if "DOP853" in sols else "Radau"
    rtol, mus, wall, nfev = sols[method]
    ref = {"mu": mus, "method": method, "rtol": rtol, "wall_s": wall, "nfev": nfev,
           "radau_vs_dop853": None}
    if "DOP853" in sols and "Radau" in sols:
        ref["radau_vs_dop853"] = float(np.max(np.abs(np.subtract(sols["Radau"][1], sols["DOP853"][1]))))
        ref["radau"] = {"rtol": sols["Radau"][0], "wall_s": sols["Radau"][2], "nfev": sols["Radau"][3]}
    else:
        notes.append("only one tight solve succeeded: radau_vs_dop853 is null")
    if notes:
        ref["notes"] = notes
    return ref


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("case")
    ap.add_argument("out")
    ap.add_argument("--rtols", default="1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10")
    ap.add_argument("--methods", default="Radau,LSODA,DOP853")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--time-limit", type=float, default=120.0,
                    help="abort one timed solve after this many seconds (recorded as an error)")
    args = ap.parse_args()
    rtols = [float(r) for r in args.rtols.split(",") if r.strip()]
    methods = [m.strip() for m in args.methods.split(",") if m.strip()]

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    with open(args.case) as f:
        case = json.load(f)
    model = DampedModel(case["model"])
    n = model.n
    v_init = float(case["v_init"])
    segments = case["segments"]
    y0 = np.concatenate([[np.log(v_init)], model.lndc - np.log(v_init), [0.0]])

    # Verify the Jacobian at a perturbed (non-steady) state, under load and in a hold.
    y_chk = y0 + np.concatenate([[0.3], -0.2 - 0.1 * np.arange(n), [1.0]])
    for vlp in {float(segments[0]["v"]) if segments else v_init, 0.0}:
        check_jacobian(model, y_chk, vlp)

    t_start = time.perf_counter()
    ref = reference(model, y0, segments, log)
    log(f"reference: {ref['method']} rtol {ref['rtol']:g}; radau_vs_dop853 = {ref['radau_vs_dop853']}")
    mu_ref = np.array(ref["mu"])

    runs = []
    for method in methods:
        for rtol in rtols:
            run = {"solver": f"scipy {method}", "method": method, "rtol": rtol}
            walls, res, err = [], None, None
            for rep in range(max(1, args.repeats)):
                gc.collect()
                mus, work, wall, err = try_solve(model, y0, segments, method, rtol, args.time_limit)
                if err:
                    break
                walls.append(wall)
                res = (mus, work)
                if rep == 0 and wall > SLOW_FIRST_S:
                    run["note"] = f"first solve took {wall:.1f} s > {SLOW_FIRST_S:g} s: not repeated"
                    break
            if err:
                run["error"] = err
                log(f"{method:7s} rtol {rtol:7.0e}: FAILED {err}")
            else:
                mus, work = res
                run.update({"wall_s": statistics.median(walls), "wall_s_all": walls, **work,
                            "mu": mus, "err": float(np.max(np.abs(np.array(mus) - mu_ref)))})
                log(f"{method:7s} rtol {rtol:7.0e}: {1e3 * run['wall_s']:9.1f} ms  "
                    f"err {run['err']:.2e}  nfev {work['nfev']}")
            runs.append(run)

    out = {"case": case.get("name", os.path.splitext(os.path.basename(args.case))[0]),
           "n_segments": len(segments), "reference": ref, "runs": runs,
           "total_s": time.perf_counter() - t_start,
           "versions": {"python": platform.python_version(), "numpy": np.__version__,
                        "scipy": scipy.__version__}}
    with open(args.out, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
