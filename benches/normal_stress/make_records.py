#!/usr/bin/env python3
"""Synthetic lab-like records with normal-stress changes, for fit-recovery tests.

    python make_records.py OUTDIR [--seed 20240601] [--instant] [--out-small OUTDIR2]
    python make_records.py --out-small OUTDIR2 [--seed 20240601]      (small set only)

Full set: OUTDIR/ns_a{alpha}_s{step}.csv (header time_s,lp_um,mu,normal_stress_mpa), the generating
protocol OUTDIR/ns_a{alpha}_s{step}.toml beside each, and OUTDIR/truth.json.
Model: 1 Slip-law state, mu0 0.6, v0 1, a 0.008, b 0.011, dc 8 um, k 0.01 1/um, sigma_ref 10 MPa,
alpha in {0, 0.1, 0.3, 0.5}; sigma change in {+10 %, +30 %, -20 %}.
Protocol: 200 s at 1 um/s | sigma ramp over 2 s (200-202 s), then 298 s | 10 um/s 40 s |
1 um/s 200 s | sigma ramp back to 10 MPa over 2 s (740-742 s), then 298 s | hold 100 s |
reslide 1 um/s 150 s.   (total 1290 s; velocity changes at 500, 540, 1040, 1140 s as before)
Every sigma change is a linear ramp (reference.py normal_stress_rate segment) of RAMP_S = 2 s whose
start and end are sample times, so the piecewise-linear interpolation of the recorded sigma column
is exactly sigma(t).  --instant restores the old instantaneous steps at 200 and 740 s (a sample at
a step time then holds the value just before the step, as in reference.py).
Sampling 10 Hz, plus 50 Hz for 5 s after every change of load-point velocity (t = 500, 540, 1040,
1140 s: step up, step down, hold start, reslide; no burst touches a ramp).  mu gets N(0, 2e-4)
white noise from numpy default_rng(seed + record index); lp and sigma are exact.  Values written
with repr (round-trip).

Small set (--out-small, test fixtures): alpha 0.3 / +30 %, alpha 0 / +30 %, alpha 0.3 / -20 %,
named ns_small_a{alpha}_s{step}.csv (+ .toml, truth.json).  Protocol: 100 s at 1 um/s | sigma ramp
2 s | 150 s | 10 um/s 30 s | 1 um/s 120 s | sigma ramp back 2 s | 150 s | hold 60 s |
reslide 1 um/s 100 s (total 714 s); 10 Hz only (7141 rows); noise seed = seed + 100 + index;
values written with 10 significant digits.
"""
import json
import os
import sys
import time

import numpy as np

import reference as R

MODEL = dict(mu0=0.6, v0=1.0, a=0.008, stiffness=0.01, normal_stress=10.0)
STATE = dict(law="slip", b=0.011, dc=8.0)
ALPHAS, STEPS, NOISE_SD = (0.0, 0.1, 0.3, 0.5), (10, 30, -20), 2e-4
RAMP_S = 2.0
SMALL = ((0.3, 30), (0.0, 30), (0.3, -20))  # (alpha, step %) of the small fixture set, in file order
SMALL_SEED_OFFSET = 100
HEADER = "time_s,lp_um,mu,normal_stress_mpa"


def ramp(sig_from, sig_to, v=1.0):
    """A RAMP_S-long segment taking sigma linearly from sig_from to sig_to (exact end value checked)."""
    rate = (sig_to - sig_from) / RAMP_S
    assert sig_from + rate * RAMP_S == sig_to, (sig_from, sig_to, rate)
    return dict(v=v, duration=RAMP_S, normal_stress_rate=rate)


def segments(sig1, instant=False):
    if instant:
        return [dict(v=1.0, duration=200.0), dict(v=1.0, duration=300.0, normal_stress=sig1),
                dict(v=10.0, duration=40.0), dict(v=1.0, duration=200.0),
                dict(v=1.0, duration=300.0, normal_stress=10.0), dict(v=0.0, duration=100.0),
                dict(v=1.0, duration=150.0)]
    return [dict(v=1.0, duration=200.0), ramp(10.0, sig1), dict(v=1.0, duration=300.0 - RAMP_S),
            dict(v=10.0, duration=40.0), dict(v=1.0, duration=200.0),
            ramp(sig1, 10.0), dict(v=1.0, duration=300.0 - RAMP_S), dict(v=0.0, duration=100.0),
            dict(v=1.0, duration=150.0)]


def segments_small(sig1):
    return [dict(v=1.0, duration=100.0), ramp(10.0, sig1), dict(v=1.0, duration=150.0),
            dict(v=10.0, duration=30.0), dict(v=1.0, duration=120.0), ramp(sig1, 10.0),
            dict(v=1.0, duration=150.0), dict(v=0.0, duration=60.0), dict(v=1.0, duration=100.0)]


def bounds(segs):
    return np.cumsum([0.0] + [s["duration"] for s in segs])


def sample_times(segs, bursts=True):
    """Ticks of 1/50 s: every 5th tick (10 Hz) plus 250 ticks (5 s) after each velocity change."""
    b = bounds(segs)
    ticks = set(range(0, int(round(b[-1] * 50)) + 1, 5))
    for i in range(1, len(segs)) if bursts else ():
        if segs[i]["v"] != segs[i - 1]["v"]:
            t0 = int(round(b[i] * 50))
            ticks.update(range(t0, min(t0 + 251, int(round(b[-1] * 50)) + 1)))
    return np.array(sorted(ticks)) / 50.0


def check_grid(segs, times):
    """Every segment boundary (so every ramp start and end) must be a sample time, exactly."""
    ts = set(times.tolist())
    off = [t for t in bounds(segs) if float(t) not in ts]
    if off:
        raise AssertionError(f"segment boundaries not on the sample grid: {off}")


def seg_comment(s, t0, sig):
    t1 = t0 + s["duration"]
    span = f"{t0:g}-{t1:g} s"
    if "normal_stress_rate" in s:
        return f"sigma ramp {sig:g} -> {sig + s['normal_stress_rate'] * s['duration']:g} MPa at v = {s['v']:g} um/s, {span}"
    if "normal_stress" in s:
        return f"sigma step {sig:g} -> {s['normal_stress']:g} MPa, v = {s['v']:g} um/s, {span}"
    what = "hold" if s["v"] == 0 else f"v = {s['v']:g} um/s"
    return f"{what}, {span}"


def toml_text(alpha, segs, note):
    lines = [f"# Generated by make_records.py (noise-free protocol of the record beside it). {note}", "[model]"]
    lines += [f"{k} = {v!r}" for k, v in MODEL.items()]
    lines += ["", "[[model.state]]", f'law = "{STATE["law"]}"', f"b = {STATE['b']!r}", f"dc = {STATE['dc']!r}",
              f"alpha = {alpha!r}", "", "[loading]", "v_init = 1.0"]
    t, sig = 0.0, MODEL["normal_stress"]
    for s in segs:
        lines += ["", f"[[loading.segment]]   # {seg_comment(s, t, sig)}"] + [f"{k} = {v!r}" for k, v in s.items()]
        sig = s.get("normal_stress", sig) + s.get("normal_stress_rate", 0.0) * s["duration"]
        t += s["duration"]
    lines += ["", "[output]", "dt = 0.1", ""]
    return "\n".join(lines)


def write_rows(path, rows, fmt):
    with open(path, "w") as fh:
        fh.write(HEADER + "\n")
        for r in rows:
            fh.write(",".join(fmt(float(x)) for x in r) + "\n")


def make_one(outdir, name, alpha, pct, segs, times, seed, fmt, note, extra):
    t_start = time.perf_counter()
    check_grid(segs, times)
    model = R.Model(MODEL["mu0"], MODEL["v0"], MODEL["a"], MODEL["stiffness"], MODEL["normal_stress"],
                    [dict(STATE, alpha=alpha)])
    rows = R.simulate(model, R.build_pieces({"segment": segs}, model.sref), times, 1.0)
    if not np.all(np.isfinite(rows)):
        raise RuntimeError(f"{name}: non-finite values")
    rng = np.random.default_rng(seed)
    mu = rows[:, 2] + rng.normal(0.0, NOISE_SD, len(times))
    write_rows(os.path.join(outdir, name + ".csv"), np.column_stack([times, rows[:, 1], mu, rows[:, -1]]), fmt)
    with open(os.path.join(outdir, name + ".toml"), "w") as fh:
        fh.write(toml_text(alpha, segs, note))
    vmax = float(np.max(rows[:, 3]))
    dt = time.perf_counter() - t_start
    print(f"{name}.csv  {len(times)} samples  max V {vmax:.4g} um/s  ({dt:.1f} s)", flush=True)
    return dict(file=name + ".csv", protocol=name + ".toml", seed=seed, noise_sd_mu=NOISE_SD,
                sigma_step_pct=pct, sigma_step_to_mpa=10.0 * (1 + pct / 100), n_samples=len(times),
                max_slip_rate_at_samples_um_s=vmax, min_slip_rate_at_samples_um_s=float(np.min(rows[:, 3])),
                params=dict(mu0=MODEL["mu0"], v0=MODEL["v0"], a=MODEL["a"], b=STATE["b"],
                            dc=STATE["dc"], k=MODEL["stiffness"], alpha=alpha, law=STATE["law"],
                            sigma_ref=MODEL["normal_stress"]),
                v_init=1.0, segments=segs, **extra)


def main(outdir, seed, instant=False):
    os.makedirs(outdir, exist_ok=True)
    truth, idx = [], 0
    sampling = "10 Hz plus 50 Hz for 5 s after each change of load-point velocity"
    for alpha in ALPHAS:
        for pct in STEPS:
            sig1 = 10.0 * (1 + pct / 100)
            segs = segments(sig1, instant)
            note = "sigma steps instantaneous (--instant)." if instant else f"sigma changes are {RAMP_S:g} s ramps."
            truth.append(make_one(outdir, f"ns_a{alpha:g}_s{pct:+d}", alpha, pct, segs, sample_times(segs), seed + idx,
                                  repr, note, dict(sigma_change="instant" if instant else "ramp",
                                                   ramp_s=None if instant else RAMP_S, sampling=sampling)))
            idx += 1
    with open(os.path.join(outdir, "truth.json"), "w") as fh:
        json.dump(truth, fh, indent=1)


def main_small(outdir, seed):
    os.makedirs(outdir, exist_ok=True)
    truth = []
    for i, (alpha, pct) in enumerate(SMALL):
        sig1 = 10.0 * (1 + pct / 100)
        segs = segments_small(sig1)
        n = int(round(bounds(segs)[-1] * 10))
        times = np.arange(n + 1) / 10.0
        truth.append(make_one(outdir, f"ns_small_a{alpha:g}_s{pct:+d}", alpha, pct, segs, times,
                              seed + SMALL_SEED_OFFSET + i, lambda x: f"{x:.10g}",
                              f"sigma changes are {RAMP_S:g} s ramps.",
                              dict(sigma_change="ramp", ramp_s=RAMP_S, sampling="10 Hz (t = k/10 s)",
                                   value_format="%.10g")))
    with open(os.path.join(outdir, "truth.json"), "w") as fh:
        json.dump(truth, fh, indent=1)


if __name__ == "__main__":
    a = sys.argv[1:]
    opts, pos, i = {}, [], 0
    while i < len(a):
        if a[i] in ("--seed", "--out-small"):
            opts[a[i]] = a[i + 1]
            i += 2
        elif a[i] == "--instant":
            opts[a[i]] = True
            i += 1
        elif a[i].startswith("--"):
            sys.exit(f"unknown option {a[i]}\n{__doc__}")
        else:
            pos.append(a[i])
            i += 1
    if len(pos) > 1 or (not pos and "--out-small" not in opts):
        sys.exit(__doc__)
    seed = int(opts.get("--seed", 20240601))
    if pos:
        main(pos[0], seed, instant=bool(opts.get("--instant")))
    if "--out-small" in opts:
        main_small(opts["--out-small"], seed)
