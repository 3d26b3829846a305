#!/usr/bin/env python3
"""Normal-stress records with the noise labs really have (issue 21): 1/f drift in time on top of
white and, in half, AR(1) noise in time, for the diagnosis's false-alarm study.

    python make_drift_records.py OUTDIR [--seed 21] [--count 16] [--jobs 2]

Each record: the protocol of make_records.py (200 s at 1 um/s | sigma ramp over 2 s | 298 s |
10 um/s 40 s | 1 um/s 200 s | sigma ramp back | 298 s | hold 100 s | reslide 150 s), sampled at
10 Hz plus 50 Hz for 5 s after each change of load-point velocity, simulated by reference.py
(scipy Radau, its own formulation, not rsf). Per record, drawn from numpy default_rng(seed + i):
one Slip-law state with a in [0.006, 0.012], b = a + U(-0.003, 0.004) (velocity weakening and
strengthening), Dc log-uniform in [4, 30] um, k = 0.01 /um; a sigma change of +10, +30 or -20 %;
alpha = 0 (nothing hidden: the true cause is `none`) for the first three quarters, alpha = 0.3
(`normal_stress_coupling`) for the rest. Noise in mu: white of sd log-uniform in [1e-4, 3e-4];
1/f noise in time (random-phase Fourier synthesis on a uniform grid, interpolated) of rms
0.5-2x the white sd; in every other record AR(1) noise in time (tau 1-5 s, by its recursion at
the sample times) of sd 0.5x the white. Writes OUTDIR/ns_drift_NN.csv (time_s,lp_um,mu,
normal_stress_mpa; 10 significant digits) and OUTDIR/truth.json in the format of
make_records.py, with `cause` and `noise` added (read by the example `normal_stress_study`).
"""
import json
import math
import multiprocessing
import os
import sys
import time

import numpy as np

import make_records as M
import reference as R

PCTS = (10, 30, -20)


def pink_noise(rng, ts, rms):
    """1/f noise in time: power proportional to 1/f from 1/T up, on a uniform grid at the median
    interval, linearly interpolated to ts, scaled to the rms given."""
    dt = float(np.median(np.diff(ts)))
    n = int(2 ** math.ceil(math.log2((ts[-1] - ts[0]) / dt + 2)))
    f = np.fft.rfftfreq(n, dt)
    amp = np.zeros_like(f)
    amp[1:] = f[1:] ** -0.5
    x = np.fft.irfft(amp * (rng.standard_normal(len(f)) + 1j * rng.standard_normal(len(f))), n)
    y = np.interp(ts, ts[0] + dt * np.arange(n), x)
    y -= y.mean()
    return y * rms / y.std()


def ar1_in_time(rng, ts, sd, tau):
    e = np.empty(len(ts))
    z = rng.standard_normal(len(ts))
    e[0] = sd * z[0]
    for i in range(1, len(ts)):
        phi = math.exp(-(ts[i] - ts[i - 1]) / tau)
        e[i] = phi * e[i - 1] + sd * math.sqrt(1 - phi * phi) * z[i]
    return e


def make(outdir, seed, count, i):
    """Record i (its own generator, seeded seed + i: the set does not depend on --jobs)."""
    rng = np.random.default_rng(seed + i)
    a = rng.uniform(0.006, 0.012)
    b = a + rng.uniform(-0.003, 0.004)
    dc = math.exp(rng.uniform(math.log(4.0), math.log(30.0)))
    pct = PCTS[i % len(PCTS)]
    alpha = 0.0 if i < (3 * count) // 4 else 0.3
    segs = M.segments(10.0 * (1 + pct / 100), False)
    times = M.sample_times(segs)
    M.check_grid(segs, times)
    clock = time.perf_counter()
    model = R.Model(0.6, 1.0, a, 0.01, 10.0, [dict(law="slip", b=b, dc=dc, alpha=alpha)])
    rows = R.simulate(model, R.build_pieces({"segment": segs}, model.sref), times, 1.0)
    if not np.all(np.isfinite(rows)):
        raise RuntimeError(f"record {i}: non-finite values")
    white = math.exp(rng.uniform(math.log(1e-4), math.log(3e-4)))
    ratio = rng.uniform(0.5, 2.0)
    noise = dict(white_sd=white, pink_rms_over_white=ratio)
    mu = rows[:, 2] + white * rng.standard_normal(len(times)) + pink_noise(rng, times, ratio * white)
    if i % 2 == 1:
        tau = rng.uniform(1.0, 5.0)
        mu = mu + ar1_in_time(rng, times, 0.5 * white, tau)
        noise.update(ar1_sd=0.5 * white, ar1_tau_s=tau)
    name = f"ns_drift_{i:02d}"
    M.write_rows(os.path.join(outdir, name + ".csv"), np.column_stack([times, rows[:, 1], mu, rows[:, -1]]),
                 lambda x: f"{x:.10g}")
    print(f"{name}.csv  {len(times)} samples  alpha {alpha:g}  sigma {pct:+d} %  a-b {a - b:+.4f}  "
          f"({time.perf_counter() - clock:.1f} s)", flush=True)
    return dict(file=name + ".csv", cause="none" if alpha == 0 else "normal_stress_coupling",
                seed=seed + i, sigma_step_pct=pct, n_samples=len(times), noise=noise,
                params=dict(mu0=0.6, v0=1.0, a=a, b=b, dc=dc, k=0.01, alpha=alpha, law="slip",
                            sigma_ref=10.0),
                sampling="10 Hz plus 50 Hz for 5 s after each change of load-point velocity")


def main(outdir, seed, count, jobs):
    os.makedirs(outdir, exist_ok=True)
    args = [(outdir, seed, count, i) for i in range(count)]
    if jobs > 1:
        with multiprocessing.Pool(jobs) as pool:
            truth = pool.starmap(make, args)
    else:
        truth = [make(*a) for a in args]
    with open(os.path.join(outdir, "truth.json"), "w") as fh:
        json.dump(truth, fh, indent=1)


if __name__ == "__main__":
    args = sys.argv[1:]
    if not args or args[0].startswith("--"):
        sys.exit(__doc__)
    opt = lambda k, d: int(args[args.index(k) + 1]) if k in args else d
    main(args[0], opt("--seed", 21), opt("--count", 16), opt("--jobs", 1))
