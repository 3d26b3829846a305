#!/usr/bin/env python3
"""How far an Aging or a Slip law fit stays from the noise-free truth of the small test records
of tests/data/outside (generate.py --outside-tests): the effect's size against the noise.

    /tmp/genvenv/bin/python benches/detection/outside_misfit.py [NAME ...]   # ~2-5 min per fit

For each record it rebuilds the truth without noise (generate.py's own integrator) and fits the
one-state Aging and Slip laws to it: mu0, a, b, Dc free, k fixed at the truth's, V0 = 1 um/s;
scipy least_squares (trf, finite differences) from the truth's values, rtol 1e-8, residuals
on every second sample. The fits are local optima, not proven global minima. Like generate.py,
this uses no rsf code.
"""
import importlib.util
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

spec = importlib.util.spec_from_file_location("generate", Path(__file__).with_name("generate.py"))
g = importlib.util.module_from_spec(spec)
spec.loader.exec_module(g)


def fit(law, mu, p, seg_t, seg_v, ts):
    sel = np.arange(0, len(ts), 2)

    def res(q):
        pp = dict(mu0=q[0], a=math.exp(q[1]), b=[math.exp(q[2])], dc=[math.exp(q[3])], laws=[law],
                  g=0.0, k=p["k"], v0=p["v0"], vc=None)
        try:
            Y, _ = g.simulate(pp, seg_t, seg_v, ts)
        except g.Unstable:
            return np.ones(len(sel))
        return (g.friction(pp, Y, pp["v0"]) - mu)[sel]

    q0 = [p["mu0"], math.log(p["a"]), math.log(p["b"][0]), math.log(p["dc"][0])]
    g.RTOL = 1e-8
    r = least_squares(res, q0, diff_step=1e-6, x_scale=[1e-3, 0.1, 0.1, 0.1], max_nfev=60)
    g.RTOL = 1e-10
    return math.sqrt(np.mean(r.fun ** 2)), np.abs(r.fun).max(), [r.x[0]] + [math.exp(x) for x in r.x[1:]]


def main(names):
    for name in names or g.OUTSIDE_TESTS:
        law, k, segs, _ = g.OUTSIDE_TESTS[name]
        p = dict(mu0=0.6, a=0.008, b=[0.011], dc=[5.0], g=0.0, k=k, v0=1.0, vc=None, **law)
        seg_t, ts = g.piecewise_grid(segs)
        seg_v = [s[1] for s in segs]
        Y, _ = g.simulate(p, seg_t, seg_v, ts, model=g.rhs_and_jac_outside)
        mu = g.friction_outside(p, Y)
        for fl in ("aging", "slip"):
            t = time.time()
            rms, mx, q = fit(fl, mu, p, seg_t, seg_v, ts)
            print(f"{name:12s} {fl:5s} fit: rms {rms:.2e} (x{rms / 1.5e-4:.0f} the white noise), max {mx:.2e}; "
                  f"mu0 {q[0]:.4f} a {q[1]:.4g} b {q[2]:.4g} Dc {q[3]:.3g}  {time.time() - t:.0f}s", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
