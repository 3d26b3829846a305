#!/usr/bin/env python3
"""The simulation study of `rsf design` (issue 24): does the designed next segment resolve
ambiguous diagnoses, compared with a standard segment of the same machine time?

    python benches/design/study.py --out DIR --rsf target/release/rsf [--seed 1] [--cases 32]
        [--threads 2] [--jobs 1] [--keep-going] [--resume] [--families a,b] [--max-tries 150]
    python benches/design/study.py --check [--out DIR]   # generator tests, no rsf needed

The truths are simulated by benches/detection/generate.py (numpy + scipy Radau, written from
the equations); see README.md here for the families, the noise and its continuation.
"""
import argparse
import importlib.util
import io
import json
import math
import subprocess
import sys
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("generate", HERE.parent / "detection" / "generate.py")
gen = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(gen)

FAMILIES = ["evolution_law", "cutoff_velocity", "second_state_variable", "normal_stress_coupling"]
# Truths outside the one-step menu (issue 41), with what the diagnosis should say of them: the
# cause and the law it should name (a law in rsf's library), or `unexplained` (no library has it).
OUTSIDE_FAMILIES = {"mix1_steps": ("evolution_law", "aging-slip"), "prz_steps": ("evolution_law", "prz"),
                    "rate_a_steps": ("unexplained", None)}
ALL_FAMILIES = FAMILIES + list(OUTSIDE_FAMILIES)
STANDARDS = ["hold_reslide", "step_down_back", "step_up_back"]   # rsf design's standard segments
DECISIVE = 10.0            # |ΔBIC| that decides between two models
LONG_HOLD = 1e4            # rsf design's longest hold (its default --max-hold), s
HOLD_DT = 1.0              # holds are sampled at 1 Hz (old and new)
PINK_HORIZON = 6 * 3600.0  # the 1/f field runs this far past the record's end (a proposal is <= 4 h)
K_FLOOR = 3e-4             # softest machine, 1/um
# Radau at rtol 1e-8 instead of the detection sets' 1e-10: 3x faster, friction within 5e-11
# (measured), far below the noise (1e-4); generate.py's own defaults are untouched.
gen.RTOL, gen.ATOL_LOG, gen.ATOL_SLIP = 1e-8, 1e-10, 1e-8
STANDARD_FALLBACK_S = 600.0
HEADER = "time_s,load_point_um,mu"
SIGMA_MPA = 10.0           # the records' normal stress, MPa (written only once a proposal changes it)
SIGMA_COL = "normal_stress_mpa"
SIGMA_VMAX_FACTOR = 1e4    # run-away threshold of simulate_sigma, times the fastest load point


def log_uniform(rng, lo, hi):
    return math.exp(rng.uniform(math.log(lo), math.log(hi)))


# ---------------------------------------------------------------- protocols and sampling
def sample_times(t_start, segs, dt_slide, dt_hold):
    """Sample times after t_start through segments [(v, dur)]: n = max(1, floor(dur/dt)) samples
    at t0 + dur k/n, k = 1..n (rsf design's sampling plan); each segment's last sample is its end."""
    out, t0 = [], t_start
    for v, dur in segs:
        dt = dt_slide if v > 0 else dt_hold
        n = max(1, int(math.floor(dur / dt + 1e-9)))
        t1 = t0 + dur
        out.append(np.r_[t0 + dur * np.arange(1, n) / n, t1])
        t0 = t1
    return np.concatenate(out) if out else np.empty(0)


def breaks(segs, t_start=0.0):
    return np.r_[t_start, t_start + np.cumsum([d for _, d in segs])]


STEP_DECADES = {"evolution_law": [0.15, 0.2, 0.3, 0.5], "cutoff_velocity": [0.5, 1.0],
                "second_state_variable": [0.15, 0.2, 0.3, 0.5], "normal_stress_coupling": [0.5, 1.0],
                "mix1_steps": [0.5, 1.0], "prz_steps": [0.5, 1.0], "rate_a_steps": [0.5, 1.0]}
MIN_STEP_S = 20.0          # shorter steps may be missed by rsf's segment detection
STEP_DC = {"evolution_law": (2, 5), "cutoff_velocity": (3, 6), "second_state_variable": (1.5, 4),
           "normal_stress_coupling": (3, 6), "mix1_steps": (3, 6), "prz_steps": (3, 6), "rate_a_steps": (3, 6)}


def draw_protocol(rng, family, dc, vb):
    """2-6 small velocity steps from vb and back (STEP_DECADES up or down), each sliding a few
    Dc (STEP_DC, at least MIN_STEP_S); cut-off records also have none or 1-3 holds of 10-100 s.
    Each step and hold is followed by steady sliding at vb for 1-4x its duration (at least 3 Dc);
    a run-in before the first. Sliding is sampled at 10 Hz (5 Hz beyond 800 s), holds at 1 Hz."""
    steps, size = [], float(rng.choice(STEP_DECADES[family]))        # one step size per record...
    for _ in range(int(rng.integers(2, 7))):
        if family == "cutoff_velocity":                                 # ...except for cut-offs
            size = float(rng.choice(STEP_DECADES[family]))
        v = vb * 10 ** (size * float(rng.choice([-1, 1])))
        steps.append((v, max(MIN_STEP_S, rng.uniform(*STEP_DC[family]) * dc / v)))
    if family == "cutoff_velocity" and rng.random() < 0.6:
        for h in rng.choice([10.0, 30.0, 100.0], size=int(rng.integers(1, 4))):
            steps.insert(int(rng.integers(0, len(steps) + 1)), (0.0, float(h)))
    after = lambda d: max(3 * dc / vb, d * rng.uniform(1, 4))
    segs = [(vb, after(steps[0][1]))]
    for s in steps:
        segs += [s, (vb, after(s[1]))]
    dt = 0.1 if sum(d for v, d in segs if v > 0) <= 800 else 0.2
    segs = [(v, max(1, round(d / dt)) * dt if v > 0 else d) for v, d in segs]   # breaks on samples
    return segs, dt


# ---------------------------------------------------------------- truth
def draw_truth(rng, family):
    """a 0.005-0.012, total b/a 1.1-1.5, Dc1 5-30 um, and the family's hidden effect."""
    a = rng.uniform(0.005, 0.012)
    b = a * rng.uniform(1.1, 1.5)
    dc = log_uniform(rng, 5, 30)
    p = dict(mu0=rng.uniform(0.55, 0.7), a=a, b=[b], dc=[dc], laws=["slip"], vc=None, g=0.0, k=None, v0=None)
    if family == "evolution_law":            # Aging, or an Aging/Slip mixture sharing Dc
        f = float(rng.choice([0.5, 0.75, 1.0]))
        if f == 1.0:
            p["laws"] = ["aging"]
        else:
            p.update(b=[(1 - f) * b, f * b], dc=[dc, dc], laws=["slip", "aging"])
        effect = {"aging_share": f}
    elif family == "second_state_variable":  # a second Slip state with a long Dc, b2 ~ b1
        r, dc2 = log_uniform(rng, 0.2, 1.0), dc * log_uniform(rng, 5, 30)
        p.update(b=[b / (1 + r), b * r / (1 + r)], dc=[dc, dc2], laws=["slip", "slip"])
        effect = {"b2": p["b"][1], "dc2": dc2}
    elif family == "normal_stress_coupling":  # Linker-Dieterich alpha; the record never changes sigma
        p["alpha"] = [rng.uniform(0.1, 0.5)]
        effect = {"alpha": p["alpha"][0]}
    elif family == "mix1_steps":             # one state healing by w Aging + (1 - w) Slip, steps only
        p.update(laws=["mix1"], w=float(rng.uniform(0.15, 0.3)))
        effect = {"w": p["w"]}
    elif family == "prz_steps":              # Perrin-Rice-Zheng, steps only
        p["laws"], effect = ["prz"], {}
    elif family == "rate_a_steps":           # Slip law with a direct effect whose slope spans a (1 -+ 0.35)
        p["a1"] = float(rng.choice([-1.0, 1.0])) * 0.35 * a / (math.log(10.0) + 1.0)
        effect = {"a1": p["a1"]}
    else:                                    # Kato-Tullis; vc is chosen once the protocol is known
        p["laws"], effect = ["kato-tullis"], {}
    kc = max(0.0, sum(p["b"]) - a) / min(p["dc"])    # >= (b_i - a)/Dc_i of every state
    # the --outside laws collapse their state far faster than Aging/Slip after steps up and
    # holds (generate.py's OUTSIDE_VMAX_FACTOR): their machines are stiffer, as generate.py's
    p["k"] = max(K_FLOOR, kc * log_uniform(rng, *((8.0, 16.0) if family in OUTSIDE_FAMILIES else (1.5, 4.0))))
    return p, effect, kc


def outside(p):
    """Whether the truth is one of the --outside laws (or a rate-dependent a): simulated by
    generate.py's --outside equations."""
    return p["laws"][0] in ("mix1", "prz", "power_aging", "nagata") or "a1" in p


def simulate(p, seg_t, seg_v, ts):
    if outside(p):
        return gen.simulate(p, seg_t, seg_v, ts, model=gen.rhs_and_jac_outside)
    return gen.simulate(p, seg_t, seg_v, ts)


def friction(p, Y):
    return gen.friction_outside(p, Y) if outside(p) else gen.friction(p, Y, p["v0"])


def survive(p, seg_t, seg_v, ts):
    """Simulate; on stick-slip raise k by 1.5x, up to 3 times (p["k"] is updated). None if it fails."""
    for _ in range(4):
        try:
            return simulate(p, seg_t, seg_v, ts)[0]
        except gen.Unstable:
            p["k"] *= 1.5
    return None


def build_case(family, seed, i):
    """One case: truth, protocol, clean and noisy record. Deterministic in (family, seed, i).
    The truth must survive (no stick-slip) a 10^4 s hold + reslide and a 2-decade step up after
    the record (k is raised 1.5x up to 3 times, else the draw is redrawn); a cut-off's Vc is
    drawn between 3x the slip rate such a hold would reach and 1/10 of the record's slowest."""
    rng = np.random.default_rng([seed, ALL_FAMILIES.index(family), i])
    for attempt in range(60):
        p, effect, kc = draw_truth(rng, family)
        vb = log_uniform(rng, 1.0, 10 ** 0.5)
        segs, dt = draw_protocol(rng, family, p["dc"][0], vb)
        if not 2500 <= sum(d / (dt if v > 0 else HOLD_DT) for v, d in segs) <= 9000:
            continue
        p["v0"] = vb
        ts = np.r_[0.0, sample_times(0.0, segs, dt, HOLD_DT)]
        test = [(0.0, LONG_HOLD), (vb, 10 * p["dc"][0]), (100 * vb, 10 * p["dc"][0])]
        seg_t, seg_v = breaks(segs + test), [v for v, _ in segs + test]
        ts_all = np.r_[ts, seg_t[len(segs) + 1:]]          # the record, then the test's breaks
        i_hold_end = len(ts)                               # the first of those: the hold's end
        if family == "cutoff_velocity":
            twin = dict(p, laws=["slip"])                  # Vc -> 0: where the slip rates go
            Yt = survive(twin, seg_t, seg_v, ts_all)
            if Yt is None:
                continue
            p["k"] = twin["k"]
            v_rec, v_hold = np.exp(Yt[: len(ts), 0]).min(), math.exp(Yt[i_hold_end, 0])
            if 3 * v_hold >= v_rec / 10:
                continue
            p["vc"] = log_uniform(rng, 3 * v_hold, v_rec / 10)
            effect = {"vc": p["vc"], "v_min_record": float(v_rec), "v_after_1e4s_hold_slip_law": v_hold}
        Y = survive(p, seg_t, seg_v, ts_all)
        if Y is None:
            continue
        Y = Y[: len(ts)]
        if family == "cutoff_velocity" and np.exp(Y[:, 0]).min() < 10 * p["vc"]:
            continue
        mu = friction(p, Y)
        noise = draw_noise(rng, ts, dt)
        lp = gen.load_point(breaks(segs), [v for v, _ in segs], ts)
        text = table_text(ts, lp, mu + noise["total"], header=True)
        truth = {k: v for k, v in p.items() if v is not None}
        return dict(family=family, seed=seed, index=i, attempts=attempt + 1, truth=truth, effect=effect,
                    k_over_kc=p["k"] / kc if kc > 0 else None, segs=segs, dt=dt, ts=ts, mu_clean=mu,
                    noise=noise, text=text, n_rows=len(ts), v_end=vb, p=p,
                    v_min=float(np.exp(Y[:, 0]).min()), v_max=float(np.exp(Y[:, 0]).max()))
    raise RuntimeError(f"{family} #{i}: no stable draw")


# ---------------------------------------------------------------- noise
def ar1(rng, ts, sigma, tau, prev=None):
    """AR(1) of stationary sd sigma, correlation time tau, at times ts; continues from prev=(t, e)."""
    xi, e = sigma * rng.standard_normal(len(ts)), np.empty(len(ts))
    t_last, e_last = prev if prev is not None else (None, None)
    for j, t in enumerate(ts):
        if t_last is None:
            e[j] = xi[j]
        else:
            phi = math.exp(-(t - t_last) / tau)
            e[j] = phi * e_last + math.sqrt(1 - phi * phi) * xi[j]
        t_last, e_last = t, e[j]
    return e


def pink_field(seed, t_end, dt):
    """1/f noise on a uniform grid from 0 to t_end (random-phase Fourier synthesis as
    generate.pink_noise, power ∝ 1/f from 1/T up); deterministic in seed."""
    rng = np.random.default_rng(seed)
    n = int(2 ** math.ceil(math.log2(t_end / dt + 2)))
    f = np.fft.rfftfreq(n, dt)
    amp = np.zeros_like(f)
    amp[1:] = f[1:] ** -0.5
    x = np.fft.irfft(amp * (rng.standard_normal(len(f)) + 1j * rng.standard_normal(len(f))), n)
    return dt * np.arange(n), x


def draw_noise(rng, ts, dt):
    """White sigma 1e-4-3e-4; half the cases add AR(1) (sd 0.5-1.5 sigma, tau 1-5 s), a third
    add mild 1/f drift (rms 0.3-1 sigma over the record) from a field that runs PINK_HORIZON on."""
    sigma = log_uniform(rng, 1e-4, 3e-4)
    spec = dict(white_sigma=sigma)
    total = sigma * rng.standard_normal(len(ts))
    ar = None
    if rng.random() < 0.5:
        spec.update(ar1_sigma=sigma * rng.uniform(0.5, 1.5), ar1_tau_s=rng.uniform(1, 5))
        ar = ar1(rng, ts, spec["ar1_sigma"], spec["ar1_tau_s"])
        total = total + ar
    if rng.random() < 1 / 3:
        spec.update(pink_rms=sigma * rng.uniform(0.3, 1.0), pink_seed=int(rng.integers(2 ** 62)))
        grid, x = pink_field(spec["pink_seed"], ts[-1] + PINK_HORIZON, dt)
        y = np.interp(ts, grid, x)
        spec["pink_offset"], spec["pink_scale"] = float(y.mean()), spec["pink_rms"] / float(y.std())
        total = total + (y - spec["pink_offset"]) * spec["pink_scale"]
    return dict(spec=spec, total=total, ar_last=None if ar is None else (float(ts[-1]), float(ar[-1])))


def continue_noise(case, t_new, rng):
    """The same noise process at the new times: fresh white draws, the AR(1) recursion from the
    record's last AR value, the same 1/f realization (same seed, offset and scale)."""
    spec, n = case["noise"]["spec"], len(t_new)
    out = spec["white_sigma"] * rng.standard_normal(n)
    if "ar1_tau_s" in spec:
        out += ar1(rng, t_new, spec["ar1_sigma"], spec["ar1_tau_s"], case["noise"]["ar_last"])
    if "pink_seed" in spec:
        grid, x = pink_field(spec["pink_seed"], case["ts"][-1] + PINK_HORIZON, case["dt"])
        out += (np.interp(t_new, grid, x) - spec["pink_offset"]) * spec["pink_scale"]
    return out


# ---------------------------------------------------------------- records
def table_text(ts, lp, mu, header=False):
    buf = io.StringIO()
    np.savetxt(buf, np.column_stack([ts, lp, mu]), fmt="%.17g", delimiter=",",
               header=HEADER if header else "", comments="")
    return buf.getvalue() if header else buf.getvalue().lstrip("\n")


def ramp_rhs(p, vlp, s0, rate, t0):
    """Right-hand side of y = (x = ln V, s_i = ln theta_i, delta) while the normal stress ramps,
    S(t) = s0 + rate (t - t0) in units of the record's (from the equations, not rsf's code):
    tau = S mu and dtau/dt = k (vlp - V) give dmu/dt = (k (vlp - V) - mu dS/dt) / S; each state
    gets -alpha_i/b_i dS/dt / S (Linker & Dieterich 1992); a dx/dt = dmu/dt - sum b_i ds_i/dt - g V."""
    f0, _ = gen.rhs_and_jac(dict(p, k=0.0, g=0.0), vlp)      # its state rates G_i at this (x, s)
    alpha = p.get("alpha") or [0.0] * len(p["b"])
    n, v0 = len(p["b"]), p["v0"]

    def f(t, y):
        S, dy = s0 + rate * (t - t0), f0(t, y)
        v, r = math.exp(y[0]), rate / (s0 + rate * (t - t0))
        mu = gen.friction(p, y[None, :], v0)[0]
        sb = 0.0
        for i in range(n):
            dy[1 + i] -= alpha[i] / p["b"][i] * r
            sb += p["b"][i] * dy[1 + i]
        dy[0] = ((p["k"] * (vlp - v) - mu * rate) / S - sb - p["g"] * v) / p["a"]
        return dy
    return f


def simulate_sigma(p, segs, ts):
    """As generate.simulate through segments (v, duration, S_end): S is the normal stress over the
    record's at each segment's end, ramped linearly through a segment that changes it. At constant
    S the spring-slider is generate.py's own with stiffness k/S (tau = S mu), analytic Jacobian;
    through a ramp, ramp_rhs with a finite-difference Jacobian."""
    v_first, n = segs[0][0], len(p["b"])
    y = np.array([math.log(v_first)] + [gen.steady_ln_theta(l, v_first, dc, p.get("vc"))
                                        for l, dc in zip(p["laws"], p["dc"])] + [0.0])
    seg_t = breaks([(v, d) for v, d, _ in segs])
    atol = np.r_[np.full(n + 1, gen.ATOL_LOG), gen.ATOL_SLIP]
    # a drop of sigma forces fast slip (tau must follow), not an instability: stick-slip is a
    # run-away, caught far above generate.py's 10x the fastest load point
    xmax = math.log(SIGMA_VMAX_FACTOR * max(v for v, _, _ in segs))
    blowup = lambda t, y: y[0] - xmax
    blowup.terminal = True
    Y, level = np.empty((len(ts), n + 2)), 1.0
    for j, (vlp, _, s_end) in enumerate(segs):
        t0, t1 = seg_t[j], seg_t[j + 1]
        lo = np.searchsorted(ts, t0, "left")
        hi = len(ts) if j == len(segs) - 1 else np.searchsorted(ts, t1, "left")
        te = np.r_[ts[lo:hi], t1] if hi == lo or ts[hi - 1] < t1 else ts[lo:hi]
        if s_end == level:
            f, jac = gen.rhs_and_jac(dict(p, k=p["k"] / level), vlp)
        else:
            f, jac = ramp_rhs(p, vlp, level, (s_end - level) / (t1 - t0), t0), None
        sol = solve_ivp(f, (t0, t1), y, method="Radau", jac=jac, rtol=gen.RTOL, atol=atol, t_eval=te,
                        events=blowup)
        if sol.status != 0:
            raise gen.Unstable(f"segment {j} at t={t0:.4g}: {sol.message}")
        Y[lo:hi] = sol.y.T[: hi - lo]
        y, level = sol.y[:, -1], s_end
    return Y


def sigma_at(segs, ts):
    """S (normal stress over the record's) at times ts: piecewise linear through the segments."""
    t_b = breaks([(v, d) for v, d, _ in segs])
    return np.interp(ts, t_b, np.r_[1.0, [s for _, _, s in segs]])


def append(case, new_segs, dt_slide, dt_hold, noise_seed, sigma=None):
    """The same truth through the old protocol + new segments in one run; the old rows are the
    record's text unchanged, new rows at the given intervals with the noise continued. `sigma`:
    the normal stress over the record's at each new segment's end (rsf design's
    normal_stress_ratio); when it changes, the record gets a fourth column, SIGMA_COL (MPa)."""
    segs = case["segs"] + [(float(v), float(d)) for v, d in new_segs]
    seg_t, seg_v = breaks(segs), [v for v, _ in segs]
    t_new = sample_times(case["ts"][-1], new_segs, dt_slide, dt_hold)
    ts = np.r_[case["ts"], t_new]
    changes = sigma is not None and any(s != 1.0 for s in sigma)
    if changes and outside(case["p"]):
        raise gen.Unstable("a change of normal stress is not simulated for the --outside laws")
    if changes:
        levels = [1.0] * len(case["segs"]) + [float(s) for s in sigma]
        full = [(v, d, s) for (v, d), s in zip(segs, levels)]
        Y = simulate_sigma(case["p"], full, ts)
    else:
        Y, _ = simulate(case["p"], seg_t, seg_v, ts)
    mu = friction(case["p"], Y)
    n_old = len(case["ts"])
    old_dev = float(np.abs(mu[:n_old] - case["mu_clean"]).max())
    new = mu[n_old:] + continue_noise(case, t_new, np.random.default_rng(noise_seed))
    if changes:
        s_all = SIGMA_MPA * sigma_at(full, ts)
        rows = np.column_stack([ts, gen.load_point(seg_t, seg_v, ts), np.r_[np.full(n_old, np.nan), new], s_all])
        head, old_lines = case["text"].split("\n", 1)
        text = head + "," + SIGMA_COL + "\n" + "".join(
            f"{line},{SIGMA_MPA!r}\n" for line in old_lines.splitlines())
        buf = io.StringIO()
        np.savetxt(buf, rows[n_old:], fmt="%.17g", delimiter=",")
        text += buf.getvalue()
    else:
        text = case["text"] + table_text(t_new, gen.load_point(seg_t, seg_v, t_new), new)
    v = np.exp(Y[n_old:, 0])
    return text, dict(rows_added=len(t_new), old_clean_max_dev=old_dev, v_min_new=float(v.min()),
                      v_max_new=float(v.max()), mu_clean_join=[float(mu[n_old - 1]), float(mu[n_old])],
                      normal_stress=changes)


# ---------------------------------------------------------------- rsf
def run_rsf(opts, sub, csv, k, out_json, extra=()):
    """Run `rsf SUB`; returns (json or None, error or None, seconds). Never raises."""
    t = time.time()
    if opts["resume"] and out_json.exists():
        try:
            return json.loads(out_json.read_text()), None, 0.0
        except ValueError:
            pass
    out_json.unlink(missing_ok=True)
    cmd = [opts["rsf"], sub, str(csv), "--time-col", "time_s", "--lp-col", "load_point_um", "--mu-col", "mu",
           "--stiffness", repr(float(k)), "--threads", str(opts["threads"]), "--seed", "1",
           "--json", str(out_json), *extra]
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=opts["timeout"])
        if r.returncode != 0:
            return None, f"exit {r.returncode}: {r.stderr.strip()[-400:]}", time.time() - t
        return json.loads(out_json.read_text()), None, time.time() - t
    except (OSError, ValueError, subprocess.SubprocessError) as e:
        return None, f"{type(e).__name__}: {e}", time.time() - t


def count_segments(opts, csv):
    """Segments `rsf segments` detects (None if it cannot run)."""
    try:
        r = subprocess.run([opts["rsf"], "segments", str(csv)], capture_output=True, text=True, timeout=120)
        return sum(1 for line in r.stdout.splitlines()[1:] if line.strip()) if r.returncode == 0 else None
    except (OSError, subprocess.SubprocessError):
        return None


def ranking(diag):
    """(cause, ΔBIC) of the baseline (0) and every candidate with a finite ΔBIC, best first."""
    pts = [("none", 0.0)] + [(c.get("cause"), c["delta_bic"]) for c in diag.get("candidates", [])
                             if isinstance(c.get("delta_bic"), (int, float)) and math.isfinite(c["delta_bic"])]
    return sorted(pts, key=lambda x: x[1])


def target(family):
    """(cause, law) the diagnosis should name for a family's truth (law None: any)."""
    return OUTSIDE_FAMILIES.get(family, (family, None))


def summary(diag, family):
    """The diagnosis against the truth: `decided` (the true cause, and law, with a lead of 10 in
    ΔBIC; for an outside truth no library has, `unexplained`), `named_close`, `close` (another
    cause within 10), `missed` (`none`), `wrong` (another cause, decisively)."""
    r = ranking(diag)
    gap = r[1][1] - r[0][1] if len(r) > 1 else math.inf
    named = diag.get("cause")
    cause, law = target(family)
    named_law = (diag.get("effect") or {}).get("law")
    adequacy = (diag.get("adequacy") or {}).get("verdict")
    if named == cause and (law is None or named_law == law):
        kind = "decided" if gap >= DECISIVE or cause == "unexplained" else "named_close"
    elif named == "unexplained":
        kind = "unexplained"
    else:
        kind = "close" if gap < DECISIVE else "missed" if named == "none" else "wrong"
    return dict(cause=named, law=named_law, adequacy=adequacy, best=r[0], runner=r[1] if len(r) > 1 else None,
                gap=gap, kind=kind,
                runner_up=diag.get("runner_up"), undecided=diag.get("undecided"),
                ranking=[[c, round(d, 2)] for c, d in r])


def case_name(family, i):
    return f"{family}_{i:03d}"


def screen(family, i, opts):
    """Generate case i of a family and diagnose it: is it ambiguous?"""
    out = Path(opts["out"]) / "records"
    name = case_name(family, i)
    try:
        c = build_case(family, opts["seed"], i)
    except Exception as e:                     # noqa: BLE001 - recorded, never fatal
        return dict(name=name, family=family, index=i, error=f"generator: {e}")
    csv = out / f"{name}.csv"
    csv.write_text(c["text"])
    found = count_segments(opts, csv)
    if found is not None and found != len(c["segs"]):     # rsf would fit another protocol
        return dict(name=name, family=family, index=i, rows=c["n_rows"],
                    error=f"segments: rsf found {found} of the {len(c['segs'])} protocol segments")
    d, err, sec = run_rsf(opts, "diagnose", csv, c["p"]["k"], out / f"{name}.diag.json")
    r = dict(name=name, family=family, index=i, rows=c["n_rows"], truth=c["truth"], effect=c["effect"],
             k_over_kc=c["k_over_kc"], noise=c["noise"]["spec"], dt=c["dt"], v_end=c["v_end"],
             protocol=[[v, d] for v, d in c["segs"]], v_min=c["v_min"], diagnose_s=round(sec, 2))
    if err:
        r["error"] = f"diagnose: {err}"
    else:
        r["first"] = summary(d, family)
        # an outside truth is also kept when named decisively but with its adequacy not shown:
        # the design must help where the diagnosis is sure but not checked
        r["ambiguous"] = r["first"]["kind"] != "decided" or (
            family in OUTSIDE_FAMILIES and r["first"]["adequacy"] != "adequate")
    return r


def fallback_standards(v_end, machine_time, dc, max_slip=1000.0, max_hold=1e4, v_hi=300.0):
    """rsf design's three standard segments (crates/rsf-design/src/standard.rs) when the design
    proposed nothing: a hold then a reslide of 10 Dc, a decade down and back, a decade up and
    back, of `machine_time` s within its default limits."""
    out = {}
    slip = min(max(10 * dc, 10.0 * v_end), max_slip, v_end * machine_time / 2)   # >= MIN_SEGMENT_S (10 s)
    out["hold_reslide"] = [[0.0, min(machine_time - slip / v_end, max_hold)], [v_end, slip / v_end]]
    for k, v1 in (("step_down_back", v_end / 10), ("step_up_back", min(10 * v_end, v_hi))):
        half = min(machine_time / 2, max_slip / (v1 + v_end))
        out[k] = [[v1, half], [v_end, half]]
    return out


#: The true value of each effect parameter (rsf's name) of a family's truth.
EFFECT_TRUTH = {"second_state_variable": {"dc2": "dc2", "b2": "b2"}, "cutoff_velocity": {"vc1": "vc"},
                "normal_stress_coupling": {"alpha1": "alpha"}, "mix1_steps": {"w1": "w"}}


def effect_fit(diag, effect, family):
    """The named model's effect parameters after the appended segment, each with the truth and
    its standard error as the design states it (the fit's, inflated by sqrt(n/n_eff) for
    correlated noise); whether the truth lies within 2 of them."""
    ext = diag.get("extended") or {}
    names = EFFECT_TRUTH.get(family, {})
    if diag.get("cause") != target(family)[0] or not names or not ext:
        return None
    n, n_eff = ext.get("n") or 1, max((diag.get("evidence") or {}).get("n_effective") or 1.0, 1.0)
    pars, sds, out = ext.get("params") or {}, ext.get("stderr") or {}, {}
    flat = dict(pars.get("law_params") or {})
    for key in ("b", "dc", "alpha"):
        for j, x in enumerate(pars.get(key) or []):
            flat[f"{key}{j + 1}"] = x
    for name, tkey in names.items():
        if name in flat and name in sds and tkey in effect:
            sd = sds[name] * math.sqrt(max(n / n_eff, 1.0))
            out[name] = dict(value=flat[name], stderr=sd, truth=effect[tkey],
                             within=abs(flat[name] - effect[tkey]) <= 2 * sd)
    return out or None


def resolve(family, i, opts):
    """rsf design on an ambiguous case; the design-appended and standard-appended records,
    each re-diagnosed. Never raises: errors are recorded in the result."""
    out = Path(opts["out"]) / "records"
    name = case_name(family, i)
    r = dict(name=name)
    try:
        c = build_case(family, opts["seed"], i)
        csv = out / f"{name}.csv"
        if csv.read_text() != c["text"]:
            raise RuntimeError("the regenerated record differs from the screened one")
        des, err, sec = run_rsf(opts, "design", csv, c["p"]["k"], out / f"{name}.design.json", opts["design_args"])
        r["design_s"] = round(sec, 2)
        if err:
            r["error"] = f"design: {err}"
            return r
        props = des.get("proposals") or []
        dt_slide, dt_hold = c["dt"], HOLD_DT        # the record's own intervals (holds: 1 Hz)
        r["design_dt"] = [des.get("dt_slide_s"), des.get("dt_hold_s")]
        r["design_models"] = [[m.get("name"), m.get("delta_bic")] for m in des.get("models", [])]
        r["design_summary"] = des.get("summary")
        r["design_notes"] = des.get("notes")
        v_end = float(des.get("v_end") or c["v_end"])
        if props:
            top = props[0]
            r["proposal"] = {k: top.get(k) for k in ("segments", "normal_stress_ratio", "machine_time_s", "slip_um",
                                                     "description", "kind", "score", "lead_pair_dchi2", "samples",
                                                     "effect")}
            # rsf design's standard segments of the same machine time within the same limits; a
            # kind the design could not score (a credible model's fit does not run through it)
            # is built here by the same rule, so the truth still runs through every standard
            dc = next((m["params"]["dc"][0] for m in des.get("models", []) if m.get("name") == "baseline"),
                      c["p"]["dc"][0])
            stds = fallback_standards(v_end, top["machine_time_s"], dc)
            stds.update({st["standard"]: st["segments"] for st in des.get("standards") or []})
        else:
            r["proposal"] = None                  # design had nothing to propose: not resolved
            dc = next((m["params"]["dc"][0] for m in des.get("models", []) if m.get("name") == "baseline"),
                      c["p"]["dc"][0])
            stds = fallback_standards(v_end, STANDARD_FALLBACK_S, dc)
        r["standards"] = stds
        runs = [("design", r["proposal"] and r["proposal"]["segments"])] + [("std_" + k, v) for k, v in stds.items()]
        for which, segs in runs:
            if not segs:
                continue
            res = r[which + "_run"] = {}
            sigma = r["proposal"].get("normal_stress_ratio") if which == "design" else None
            try:
                text, info = append(c, segs, dt_slide, dt_hold, [opts["seed"], ALL_FAMILIES.index(family), i, 99], sigma)
            except gen.Unstable as e:
                res.update(cause=None, error=f"the truth stick-slips through this segment: {e}")
                continue
            res.update(info)
            app = out / f"{name}.{which}.csv"
            app.write_text(text)
            res["segments"] = [count_segments(opts, app), len(c["segs"]) + len(segs)]   # found, true
            d, err, sec = run_rsf(opts, "diagnose", app, c["p"]["k"], out / f"{name}.{which}.diag.json",
                                  ("--normal-col", SIGMA_COL) if info["normal_stress"] else ())
            res["diagnose_s"] = round(sec, 2)
            if err:
                res.update(cause=None, error=f"diagnose: {err}")
            else:
                res.update(summary(d, family))
                res["effect_fit"] = effect_fit(d, c["effect"], family)
            if not opts["keep_records"]:
                app.unlink()
    except Exception as e:                     # noqa: BLE001 - recorded, never fatal
        r["error"] = f"{type(e).__name__}: {e}"
    return r


def resolved(case, which, decisive=False):
    """The truth's cause (and law) named after the appended segment (decisive: also >= 10 in
    ΔBIC ahead; an outside truth no library has: `unexplained`)."""
    run = case.get(which + "_run") or {}
    return run.get("kind") == "decided" or (not decisive and run.get("kind") == "named_close")


def wrong(case, which):
    """Another cause than the truth's named decisively after the appended segment."""
    return (case.get(which + "_run") or {}).get("kind") == "wrong"


def pct(k, n):
    return f"{k} ({100 * k / n:.0f} %)" if n else "–"


# ---------------------------------------------------------------- report
def tables(cases):
    """Per family (the menu's, then the truths outside it) and overall: the truth named after the
    design's segment and after each standard segment of the same machine time and limits, the
    best standard of the family, the ratio, decisive wrong causes, nothing proposed, errors;
    then the effect's parameters after the design against their stated uncertainty."""
    head = ("| family | cases | design | decisive | " + " | ".join(STANDARDS)
            + " | best standard | design / best | decisive wrong: design | standards | nothing proposed | errors |")
    rows = [head, "|---|" + "---|" * (head.count("|") - 2)]
    groups = [f for f in ALL_FAMILIES if any(c["family"] == f for c in cases)]
    menu = [c for c in cases if c["family"] in FAMILIES]
    out_ = [c for c in cases if c["family"] in OUTSIDE_FAMILIES]
    for fam, cs in [(f, [c for c in cases if c["family"] == f]) for f in groups] + \
            [("all on the menu", menu), ("all outside it", out_), ("all", cases)]:
        if not cs:
            continue
        n = len(cs)
        nd, dd = sum(resolved(c, "design") for c in cs), sum(resolved(c, "design", True) for c in cs)
        per = {k: sum(resolved(c, "std_" + k) for c in cs) for k in STANDARDS}
        best_k = max(STANDARDS, key=lambda k: per[k])
        nb = per[best_k]
        ratio = f"{nd / nb:.2f}" if nb else ("∞" if nd else "–")
        wd = sum(wrong(c, "design") for c in cs)
        ws = sum(wrong(c, "std_" + k) for c in cs for k in STANDARDS)
        none = sum(1 for c in cs if "proposal" in c and c["proposal"] is None)
        errs = sum(1 for c in cs if c.get("error") or any((c.get(w + "_run") or {}).get("error")
                                                          for w in ["design"] + ["std_" + k for k in STANDARDS]))
        rows.append(f"| {fam} | {n} | {pct(nd, n)} | {dd} | " + " | ".join(pct(per[k], n) for k in STANDARDS)
                    + f" | {best_k} | {ratio} | {wd} | {ws} | {none} | {errs} |")
    # the effect's parameters after the design: expected and achieved standard errors, truth within 2
    eff = ["\n| case | parameter | truth | after design | stated sd (design expected) | within 2 sd |",
           "|---|---|---|---|---|---|"]
    inside = total = 0
    for c in cases:
        fit = (c.get("design_run") or {}).get("effect_fit") or {}
        expected = {p["name"]: p for p in (((c.get("proposal") or {}).get("effect") or {}).get("parameters") or [])}
        for name, e in fit.items():
            total += 1
            inside += bool(e["within"])
            x = expected.get(name)
            exp = f" ({x['stderr_now']:.3g} → {x['stderr_expected']:.3g})" if x else ""
            eff.append(f"| {c['name']} | {name} | {e['truth']:.4g} | {e['value']:.4g} | {e['stderr']:.3g}{exp} | "
                       f"{'yes' if e['within'] else '**no**'} |")
    eff.append(f"\nEffect parameters within 2 stated sd of the truth after the design: {inside} of {total}.")
    det = ["\n| case | first diagnosis (kind, gap) | design's proposal | machine s | after design | "
           + " | ".join("after " + k for k in STANDARDS) + " |", "|---|---|---|---|---|" + "---|" * len(STANDARDS)]

    def cell(c, w):
        run = c.get(w + "_run") or {}
        if not run.get("cause"):
            return run.get("error", "–")[:50]
        law = f" {run['law']}" if run.get("law") else ""
        return f"{run['cause']}{law} ({run.get('kind')}, {run.get('gap', math.nan):.1f})"
    for c in cases:
        f, p = c.get("first", {}), c.get("proposal") or {}
        what = p.get("description") or ("nothing proposed" if "proposal" in c else c.get("error", "–")[:60])
        first = f"{f.get('cause')}{' ' + f['law'] if f.get('law') else ''} ({f.get('kind')}, {f.get('gap', math.nan):.1f}, {f.get('adequacy')})"
        det.append(f"| {c['name']} | {first} | {what} | {p.get('machine_time_s') or 0:.0f} | {cell(c, 'design')} | "
                   + " | ".join(cell(c, "std_" + k) for k in STANDARDS) + " |")
    return "\n".join(rows) + "\n" + "\n".join(eff) + "\n" + "\n".join(det) + "\n"


# ---------------------------------------------------------------- driver
def log(msg):
    print(msg, file=sys.stderr, flush=True)


def study(args):
    out = Path(args.out)
    (out / "records").mkdir(parents=True, exist_ok=True)
    opts = dict(out=str(out), rsf=str(args.rsf), seed=args.seed, threads=args.threads, timeout=args.timeout,
                resume=args.resume, keep_records=args.keep_records, design_args=args.design_arg or [])
    fams = [f for f in ALL_FAMILIES if f in args.families.split(",")]
    quota = {f: args.cases // len(fams) + (j < args.cases % len(fams)) for j, f in enumerate(fams)}
    screened, kept, tries = {f: {} for f in fams}, {f: [] for f in fams}, {f: 0 for f in fams}
    fails = [0, 0]                                    # rsf errors, rsf successes
    t0 = time.time()

    def need(f):
        return len(kept[f]) < quota[f] and tries[f] < args.max_tries

    def check_broken(err):
        fails[0 if err else 1] += 1
        if not args.keep_going and fails[1] == 0 and fails[0] >= 3:
            sys.exit(f"the first {fails[0]} rsf runs all failed (last: {err}); check --rsf, or use --keep-going")

    with ProcessPoolExecutor(max_workers=args.jobs) as ex:
        # 1. screening: cases in order per family until each family has its quota of ambiguous ones
        pending = {}
        while True:
            while len(pending) < args.jobs and any(need(f) for f in fams):
                f = min((f for f in fams if need(f)), key=lambda f: tries[f])    # round robin
                pending[ex.submit(screen, f, tries[f], opts)] = (f, tries[f])
                tries[f] += 1
            if not pending:
                break
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                f, i = pending.pop(fut)
                r = fut.result()
                screened[f][i] = r
                if not r.get("error", "").startswith(("generator", "segments")):
                    check_broken(r.get("error"))
                if r.get("ambiguous"):
                    kept[f].append(i)
                fr = r.get("first", {})
                log(f"[{time.time() - t0:6.0f}s] screen {r['name']}: {r.get('error') or fr['cause']} "
                    f"({fr.get('kind')}, gap {fr.get('gap', math.nan):.1f}) rows={r.get('rows')} "
                    f"{r.get('diagnose_s', 0):.0f}s  kept {len(kept[f])}/{quota[f]}")
        chosen = [(f, i) for f in fams for i in sorted(kept[f])[: quota[f]]]
        if args.screen_only:
            write_results(out, args, screened, [])
            return
        for f in fams:
            if len(kept[f]) < quota[f]:
                log(f"warning: {f}: only {len(kept[f])} ambiguous cases in {tries[f]} tries")
        # 2. design + the two appended records, re-diagnosed
        cases, futs = [], {ex.submit(resolve, f, i, opts): (f, i) for f, i in chosen}
        for fut in futs:                               # results in the chosen (deterministic) order
            f, i = futs[fut]
            r = {**screened[f][i], **fut.result()}
            cases.append(r)
            check_broken(r.get("error") if str(r.get("error", "")).startswith("design") else None)
            log(f"[{time.time() - t0:6.0f}s] case {r['name']}: proposal "
                f"{(r.get('proposal') or {}).get('description', r.get('error', 'nothing proposed'))}; "
                f"design → {(r.get('design_run') or {}).get('cause')}, standards → "
                f"{[(r.get('std_' + k + '_run') or {}).get('cause') for k in STANDARDS]} (truth {f})")
            write_results(out, args, screened, cases)
    md = tables(cases)
    write_results(out, args, screened, cases, md)
    print(md)


def write_results(out, args, screened, cases, md=None):
    doc = dict(settings={k: (str(v) if isinstance(v, Path) else v) for k, v in vars(args).items()},
               screened=[r for f in screened.values() for _, r in sorted(f.items())], cases=cases)
    (out / "study.json").write_text(json.dumps(doc, indent=1, default=float))
    if md:
        (out / "study.md").write_text(f"# rsf design study (seed {args.seed})\n\n" + md)


def self_check(out):
    """Generator tests without rsf: one case per family, appended with a long hold + step and with
    the standard segment; the old rows byte-identical, the clean old friction identical, the join
    continuous within noise, the run deterministic."""
    ok = True
    for j, fam in enumerate(FAMILIES):
        t = time.time()
        c = build_case(fam, 1, j)
        again = build_case(fam, 1, j)
        sd = math.sqrt(sum(c["noise"]["spec"].get(k, 0) ** 2 for k in ("white_sigma", "ar1_sigma", "pink_rms")))
        log(f"{fam}: rows={c['n_rows']} dt={c['dt']} k={c['p']['k']:.3g} (k/kc {c['k_over_kc']:.2f}) "
            f"effect={c['effect']} noise={ {k: round(v, 6) for k, v in c['noise']['spec'].items() if k != 'pink_seed'} } "
            f"V=[{c['v_min']:.3g},{c['v_max']:.3g}] tries={c['attempts']} {time.time() - t:.1f}s")
        ok &= again["text"] == c["text"]
        for label, segs, sig in (
                ("hold+step", [[0.0, 3000.0], [c["v_end"], 60.0], [10 * c["v_end"], 30.0]], None),
                ("standard", [[c["v_end"] / 10, 300.0], [c["v_end"], 300.0]], None),
                ("sigma", [[c["v_end"], 1.0], [c["v_end"], 200.0], [c["v_end"], 1.0], [c["v_end"], 200.0]],
                 [1.2, 1.2, 0.9, 0.9])):
            text, info = append(c, segs, c["dt"], HOLD_DT, [1, j, 99], sig)
            old_same = text.startswith(c["text"]) if sig is None else \
                [line.rsplit(",", 1)[0] for line in text.splitlines()[:c["n_rows"] + 1]] == c["text"].splitlines()
            rows = np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1)
            n = c["n_rows"]
            jump, clean_jump = rows[n, 2] - rows[n - 1, 2], info["mu_clean_join"][1] - info["mu_clean_join"][0]
            cont = abs(jump - clean_jump) < 6 * sd
            mono = bool(np.all(np.diff(rows[:, 0]) > 0)) and abs(rows[n, 1] - rows[n - 1, 1]) < 1.01 * segs[0][0] * (rows[n, 0] - rows[n - 1, 0]) + 1e-9
            log(f"   {label:9s}: +{info['rows_added']} rows, old text identical={old_same}, old clean max dev="
                f"{info['old_clean_max_dev']:.1e}, join Δμ={jump:.2e} (clean {clean_jump:.2e}, noise sd {sd:.1e}) "
                f"continuous={cont}, times/load point ok={mono}, V new=[{info['v_min_new']:.3g},{info['v_max_new']:.3g}]")
            ok &= old_same and info["old_clean_max_dev"] == 0.0 and cont and mono
            if sig is not None and fam == "normal_stress_coupling":
                ok &= sigma_against_reference(c, segs, sig, rows)
            if out:
                Path(out).mkdir(parents=True, exist_ok=True)
                (Path(out) / f"check_{fam}.csv").write_text(c["text"])
                (Path(out) / f"check_{fam}_{label.replace('+', '_')}.csv").write_text(text)
    log("check: " + ("all passed" if ok else "FAILED"))
    return ok


def sigma_against_reference(c, segs, sig, rows):
    """simulate_sigma against benches/normal_stress/reference.py (its own formulation: tau as the
    variable, V from the friction law) on the rows of the appended normal-stress changes."""
    spec = importlib.util.spec_from_file_location("reference", HERE.parent / "normal_stress" / "reference.py")
    ref = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ref)
    p = c["p"]
    states = [dict(law=l, b=b, dc=dc, alpha=al) for l, b, dc, al in zip(p["laws"], p["b"], p["dc"], p["alpha"])]
    model = ref.Model(p["mu0"], p["v0"], p["a"], p["k"], SIGMA_MPA, states)
    full, level = [dict(v=v, duration=d) for v, d in c["segs"]], 1.0
    for (v, d), s in zip(segs, sig):
        full.append(dict(v=v, duration=d, normal_stress_rate=SIGMA_MPA * (s - level) / d))
        level = s
    n = c["n_rows"]
    ts = rows[n:, 0][:: max(1, (len(rows) - n) // 200)]
    r = ref.simulate(model, ref.build_pieces({"segment": full}, SIGMA_MPA), ts, c["segs"][0][0], rtol=1e-10, atol=1e-10)
    Y = simulate_sigma(p, [(v, d, 1.0) for v, d in c["segs"]] + [(v, d, s) for (v, d), s in zip(segs, sig)], ts)
    dev = float(np.abs(gen.friction(p, Y, p["v0"]) - r[:, 2]).max())
    sdev = float(np.abs(sigma_at([(v, d, 1.0) for v, d in c["segs"]] + [(v, d, s) for (v, d), s in zip(segs, sig)],
                                 ts) * SIGMA_MPA - r[:, -1]).max())
    log(f"   sigma vs reference.py: {len(ts)} rows, friction max |dev| {dev:.1e}, sigma max |dev| {sdev:.1e}")
    return dev < 1e-6 and sdev < 1e-9


def main():
    ap = argparse.ArgumentParser(description=" ".join(__doc__.split("\n")[:3]))
    ap.add_argument("--out", type=Path)
    ap.add_argument("--rsf", type=Path, default=HERE.parent.parent / "target" / "release" / "rsf")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cases", type=int, default=32, help="ambiguous cases in all (split over the families)")
    ap.add_argument("--threads", type=int, default=2, help="threads of each rsf run")
    ap.add_argument("--jobs", type=int, default=1, help="cases run concurrently")
    ap.add_argument("--families", default=",".join(FAMILIES),
                    help="among " + ",".join(ALL_FAMILIES) + " (the last three: truths outside the menu)")
    ap.add_argument("--max-tries", type=int, default=150, help="cases generated per family at most")
    ap.add_argument("--timeout", type=float, default=3600, help="s per rsf run")
    ap.add_argument("--keep-going", action="store_true", help="do not stop when the first rsf runs all fail")
    ap.add_argument("--resume", action="store_true", help="reuse rsf JSON outputs already in --out")
    ap.add_argument("--keep-records", action="store_true", help="keep the appended CSVs (else deleted)")
    ap.add_argument("--design-arg", action="append", help="extra argument for rsf design (repeatable)")
    ap.add_argument("--screen-only", action="store_true", help="generate and diagnose only (the yield)")
    ap.add_argument("--check", action="store_true", help="test the generator part only (no rsf)")
    args = ap.parse_args()
    if args.check:
        sys.exit(0 if self_check(args.out) else 1)
    if not args.out:
        ap.error("give --out DIR (or --check)")
    study(args)


if __name__ == "__main__":
    main()
