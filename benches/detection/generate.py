#!/usr/bin/env python3
"""Independent generator of lab-realistic synthetic friction records with hidden effects.

For the detection study of `rsf diagnose` (see README.md here). Written from the equations
only (numpy + scipy solve_ivp Radau, rtol 1e-10); shares no code with rsf.

    python3 benches/detection/generate.py --out DIR [--seed 1] [--quick]
    python3 benches/detection/generate.py --check ../shared/reference   # integrator check
    python3 benches/detection/generate.py --out DIR --outside [--seed 38] [--outside-families A,B]
    python3 benches/detection/generate.py --outside-tests tests/data/outside

Units: time s, displacement um, velocity um/s, theta s, k 1/um, friction dimensionless.
    mu     = mu0 + a ln(V/V0) + sum_i b_i ln(V0 theta_i/Dc_i) + g delta
    dmu/dt = k (V_lp(t) - V)
    aging: dtheta/dt = 1 - O   slip: -O ln O   kato-tullis: exp(-V/Vc) - O ln O   (O = V theta/Dc)
Integrated as y = (ln V, ln theta_i, delta), restarted exactly at every load-point break.
--outside: one state under PRZ, Nagata, a one-state Aging/Slip mixture, power-law aging, or the
Slip law with a rate-dependent direct effect (see the section "outside the menu" below).
"""
import argparse
import sys
import json
import math
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.special import lambertw

RTOL, ATOL_LOG, ATOL_SLIP = 1e-10, 1e-12, 1e-10
VMAX_FACTOR = 10.0   # slip rate above 10x the fastest load point = stick-slip: redraw the record
#: Row counts are scaled by this (--rows-scale): 1 for the detection sets.
ROWS_SCALE = 1.0

FEATURES = ["variable_sampling", "time_jitter", "nonzero_t0", "encoder_noise", "ar1_noise", "spikes"]
# effect-size ladders, subtle -> obvious
LADDERS = {
    "evolution_law": [0.1, 0.25, 0.5, 0.75, 1.0],            # aging share of total b
    "second_state_variable": [3e-4, 6e-4, 1.2e-3, 2.5e-3, 5e-3],  # |b2|
    "cutoff_velocity": [1e-6, 3e-6, 1e-5, 1e-4, 1e-3],     # Vc, um/s
    "slip_trend": [1e-7, 3e-7, 1e-6, 3e-6, 1e-5],           # |g|, 1/um
    "stiffness": [0.8, 0.7, 0.6, 0.5, 0.4],                  # true k / nominal k
}


class Unstable(Exception):
    pass


# ---------------------------------------------------------------- physics
def steady_ln_theta(law, v, dc, vc):
    """ln theta at steady state: O = 1, except Kato-Tullis: O ln O = exp(-V/Vc), O > 1, and
    PRZ: theta = 2 Dc/V."""
    omega = 1.0
    if law == "prz":
        omega = 2.0
    if law == "kato-tullis":
        c = math.exp(-v / vc)
        omega = math.exp(lambertw(c).real) if c > 0 else 1.0   # O ln O = c  <=>  ln O = W(c)
    return math.log(omega * dc / v)


def rhs_and_jac(p, vlp):
    """Right-hand side and analytic Jacobian of y = (x = ln V, s_i = ln theta_i, delta)."""
    a, k, g = p["a"], p["k"], p["g"]
    st = [(law, b, dc, math.log(dc), p.get("vc")) for law, b, dc in zip(p["laws"], p["b"], p["dc"])]
    n = len(st)

    def rates(x, s, law, dc, ldc, vc):        # ds/dt and its partials in x and s
        v = math.exp(x)
        if law == "aging":
            e = math.exp(-s)
            return e - v / dc, -v / dc, -e
        u = x + s - ldc                          # ln O
        r, rx, rs = -(v / dc) * u, -(v / dc) * (u + 1.0), -v / dc
        if law == "kato-tullis":
            e = math.exp(-v / vc - s)
            r, rx, rs = r + e, rx - (v / vc) * e, rs - e
        return r, rx, rs

    def f(t, y):
        v, dy, sb = math.exp(y[0]), np.empty(n + 2), 0.0
        for i, (law, b, dc, ldc, vc) in enumerate(st):
            dy[1 + i] = rates(y[0], y[1 + i], law, dc, ldc, vc)[0]
            sb += b * dy[1 + i]
        dy[0] = (k * (vlp - v) - sb - g * v) / a
        dy[n + 1] = v
        return dy

    def jac(t, y):
        v, J = math.exp(y[0]), np.zeros((n + 2, n + 2))
        dx = -(k + g) * v
        for i, (law, b, dc, ldc, vc) in enumerate(st):
            _, rx, rs = rates(y[0], y[1 + i], law, dc, ldc, vc)
            J[1 + i, 0], J[1 + i, 1 + i], J[0, 1 + i] = rx, rs, -b * rs / a
            dx -= b * rx
        J[0, 0], J[n + 1, 0] = dx / a, v
        return J

    return f, jac


def simulate(p, seg_t, seg_v, ts, model=rhs_and_jac):
    """Integrate through segments [seg_t[j], seg_t[j+1]) at V_lp = seg_v[j]; states at times ts.
    `model(p, vlp)` gives the right-hand side and Jacobian (rhs_and_jac_outside for --outside)."""
    v0, n = seg_v[0], len(p["b"])
    y = np.array([math.log(v0)] + [steady_ln_theta(l, v0, dc, p.get("vc"))
                                   for l, dc in zip(p["laws"], p["dc"])] + [0.0])
    atol = np.r_[np.full(n + 1, ATOL_LOG), ATOL_SLIP]
    xmax = math.log(VMAX_FACTOR * max(seg_v))
    blowup = lambda t, y: y[0] - xmax
    blowup.terminal = True
    Y, nfev = np.empty((len(ts), n + 2)), 0
    for j, vlp in enumerate(seg_v):
        t0, t1 = seg_t[j], seg_t[j + 1]
        lo = np.searchsorted(ts, t0, "left")
        hi = len(ts) if j == len(seg_v) - 1 else np.searchsorted(ts, t1, "left")
        te = np.r_[ts[lo:hi], t1] if hi == lo or ts[hi - 1] < t1 else ts[lo:hi]
        f, jac = model(p, vlp)
        sol = solve_ivp(f, (t0, t1), y, method="Radau", jac=jac, rtol=RTOL, atol=atol,
                        t_eval=te, events=blowup)
        if sol.status != 0:
            raise Unstable(f"segment {j} at t={t0:.4g}: {sol.message}")
        Y[lo:hi] = sol.y.T[: hi - lo]
        y, nfev = sol.y[:, -1], nfev + sol.nfev
    return Y, nfev


def friction(p, Y, v0):
    mu = p["mu0"] + p["a"] * (Y[:, 0] - math.log(v0)) + p["g"] * Y[:, -1]
    for i, (b, dc) in enumerate(zip(p["b"], p["dc"])):
        mu += b * (math.log(v0) + Y[:, 1 + i] - math.log(dc))
    return mu


def load_point(seg_t, seg_v, t):
    cum = np.r_[0.0, np.cumsum(np.diff(seg_t) * seg_v)]
    j = np.clip(np.searchsorted(seg_t, t, "right") - 1, 0, len(seg_v) - 1)
    return cum[j] + np.asarray(seg_v)[j] * (t - seg_t[j])


# ---------------------------------------------------------------- protocols
def rock_steps(rng):
    """A run-in at 1 um/s, then steps 1 <-> 3.16 um/s and 1 <-> 2-3 velocities 0.5-3.5 decades
    lower, in random order, each followed by a return to 1 um/s."""
    vb, segs = 1.0, [(rng.uniform(20, 40), 1.0, "slide")]
    downs = sorted(rng.choice(np.arange(0.5, 3.51, 0.5), size=rng.integers(2, 4), replace=False))
    partners = [vb * 10 ** 0.5] + [vb * 10 ** -d for d in downs]
    order = rng.permutation(len(partners))
    for v in (partners[i] for i in order):
        segs.append((min(rng.uniform(20, 40) / v, rng.uniform(800, 2000)), v, "slide"))
        segs.append((rng.uniform(30, 60) / vb, vb, "slide"))
    return segs, "rock steps 1<->" + ",".join(f"{partners[i]:.3g}" for i in order) + " um/s"


def rock_holds(rng, max_hold):
    """2-4 holds from the ladder 10-1000 s below max_hold, then max_hold itself."""
    ladder = [10, 30, 100, 300, 1000, 3000, 10000]
    short = [h for h in ladder if h <= min(max_hold, 1000) and h < max_hold]
    return sorted(rng.choice(short, size=min(len(short), rng.integers(2, 5)), replace=False).tolist()
                  + [max_hold])


def protocol_rock(rng, max_hold):
    """Velocity steps of 0.5-3.5 decades around 1 um/s, then slide-hold-slides at the end."""
    segs, label = rock_steps(rng)
    holds = rock_holds(rng, max_hold)
    for h in holds:
        segs += [(float(h), 0.0, "hold"), (rng.uniform(40, 60), 1.0, "slide")]
    return segs, label + "; holds " + ",".join(f"{h:g}" for h in holds) + " s"


def protocol_gouge(rng, dc, force_300):
    """Staircase 1->300 um/s (each step >= 5 Dc), then holds of 3-300 s at 10 um/s."""
    segs = [(rng.uniform(5, 7) * dc / v, v, "slide") for v in (1.0, 3.0, 10.0, 30.0, 100.0, 300.0)]
    segs.append((rng.uniform(5, 7) * dc / 10.0, 10.0, "slide"))
    pool = [3, 10, 30, 100, 300]
    holds = sorted(rng.choice(pool[:-1], size=rng.integers(2, 5), replace=False).tolist()
                   + ([300] if force_300 or rng.random() < 0.6 else []))
    for h in holds:
        segs += [(float(h), 0.0, "hold"), (rng.uniform(4, 6) * dc / 10.0, 10.0, "slide")]
    return segs, "gouge staircase 1-300 um/s; holds " + ",".join(f"{h:g}" for h in holds) + " s at 10 um/s"


# ---------------------------------------------------------------- sampling
NICE_DT = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0]


def uniform_grid(rng, segs):
    """One fixed interval; segment ends are snapped onto the grid so breaks are samples."""
    raw = sum(s[0] for s in segs) / (ROWS_SCALE * rng.uniform(13000, 23000))
    dt = next((d for d in NICE_DT if d >= raw), NICE_DT[-1])
    ends = np.cumsum([max(1, round(s[0] / dt)) for s in segs])
    return np.r_[0, ends] * dt, np.arange(ends[-1] + 1) * dt


def variable_grid(rng, segs, seg_t):
    """10 Hz base (slower below 0.1 um/s), 100 Hz bursts after each change, holds at <= 1 Hz."""
    burst = rng.uniform(5, 10)
    base = [min(10.0, max(0.5, 100 * v)) if kind == "slide" else
            (1.0 if d <= 1000 else max(0.2, 1000 / d)) for d, v, kind in segs]
    for _ in range(40):
        pieces = [seg_t]
        for j, (d, v, kind) in enumerate(segs):
            t0, t1 = seg_t[j], seg_t[j + 1]
            tb = min(t1, t0 + burst) if j > 0 else t0
            dtb = 1.0 / base[j]                               # no sample within half a step of a break
            pieces += [np.arange(t0, tb - 0.005, 0.01), np.arange(tb, t1 - 0.5 * dtb, dtb)]
        ts = np.unique(np.concatenate(pieces))
        if len(ts) <= ROWS_SCALE * 24000:
            return ts
        base, burst = [r * 0.85 for r in base], max(3.0, burst * 0.9)
    return ts


def jitter(rng, ts):
    gap = np.minimum(np.diff(ts)[:-1], np.diff(ts)[1:])
    out = ts.copy()
    out[1:-1] += rng.uniform(-0.01, 0.01, len(gap)) * gap
    return out


def sample_times(rng, segs, feats):
    """Segment start times, sample times and the fastest sampling interval of a protocol, with
    the sampling features of `feats` (variable sampling, time jitter)."""
    if "variable_sampling" in feats:
        seg_t = np.r_[0.0, np.cumsum([s[0] for s in segs])]
        ts, dt_fast = variable_grid(rng, segs, seg_t), 0.1
    else:
        seg_t, ts = uniform_grid(rng, segs)
        dt_fast = ts[1] - ts[0]
    if "time_jitter" in feats:
        ts = jitter(rng, ts)
    return seg_t, ts, dt_fast


# ---------------------------------------------------------------- parameters
def sample_truth(rng, material, cause, size, sign, dc_lo, dc_hi, k_lo):
    """Material parameters, the hidden effect, and a stable machine (true k >= 8 kc)."""
    for _ in range(500):
        dc = math.exp(rng.uniform(math.log(dc_lo), math.log(dc_hi)))
        if material == "bare_rock":
            a = rng.uniform(0.006, 0.012); b = a + rng.uniform(0.001, 0.004)
            k_nom = math.exp(rng.uniform(math.log(max(0.01, k_lo)), math.log(0.07)))
            mu0 = rng.uniform(0.55, 0.72)
        else:
            a = rng.uniform(0.008, 0.014); b = a - rng.uniform(0.001, 0.004)
            k_nom = rng.uniform(max(0.002, k_lo), 0.006); mu0 = rng.uniform(0.45, 0.65)
        p = dict(mu0=mu0, a=a, b=[b], dc=[dc], laws=["slip"], vc=None, g=0.0, k=k_nom, v0=None)
        effect = {}
        if cause == "evolution_law":
            p["b"], p["dc"], p["laws"] = ([b], [dc], ["aging"]) if size >= 1.0 else \
                ([(1 - size) * b, size * b], [dc, dc], ["slip", "aging"])
            effect = {"b_other_fraction": size}
        elif cause == "second_state_variable":
            dc2 = dc * rng.uniform(5, 20)
            p["b"], p["dc"], p["laws"] = [b, sign * size], [dc, dc2], ["slip", "slip"]
            effect = {"b2": sign * size, "dc2": dc2}
        elif cause == "cutoff_velocity":
            p["laws"], p["vc"], effect = ["kato-tullis"], size, {"vc": size}
        elif cause == "slip_trend":
            p["g"] = sign * size; effect = {"g": p["g"]}
        elif cause == "stiffness":
            p["k"] = k_nom * size; effect = {"k": p["k"]}
        kc = max(0.0, sum(max(x, 0.0) for x in p["b"]) - a) / min(p["dc"])
        if p["k"] >= 8 * kc:
            return p, effect, k_nom
    raise RuntimeError("no stable parameter draw")


# ---------------------------------------------------------------- records
def balanced(rng, groups, quick=False, extra=()):
    """Specs for (cause, sizes) groups: material, holds and feature flags balanced within each
    cause, in a blind (shuffled) order."""
    specs = []
    for cause, sizes in groups:
        n = len(sizes)
        flags = {f: rng.permutation(np.arange(n) < (n + 1) // 2) for f in FEATURES}
        for i, size in enumerate(sizes):
            material = "bare_rock" if i % 2 == 0 else "gouge_vs"
            if cause == "cutoff_velocity":
                material = "gouge_vs" if size >= 1e-3 and (quick or i % 3 < 2) else "bare_rock"
            long_hold = (i // 2) % 2 == 0 if cause != "cutoff_velocity" else size < 1e-3
            specs.append(dict(cause=cause, size=size, material=material, long_hold=long_hold,
                              features=[material, *extra] + [f for f in FEATURES if flags[f][i]]))
    order = rng.permutation(len(specs))                       # blind file names
    return [specs[i] for i in order]


def plan(rng, quick):
    """Cause, size, material and feature flags of every record, balanced within each cause."""
    groups = [("none", [None] * (6 if quick else 36))]
    for cause, ladder in LADDERS.items():
        idx = [0, 1, 3, 4] if quick else [i for i in range(5) for _ in range(3)]
        groups.append((cause, [ladder[i] for i in idx]))
    return balanced(rng, groups, quick)


def plan_drift(rng):
    """The 1/f set (issue 21): every record carries 1/f noise of 0.5-2x the white noise's rms on
    top of white (and, for half, AR(1)) noise: 32 with nothing hidden, half bare rock
    (velocity weakening, holds up to 1e4 s) and half velocity-strengthening gouge; 16 with an
    Aging/Slip mixture (aging share 0.1-0.75) and 16 with a cut-off velocity."""
    mixture = [0.1, 0.25, 0.5, 0.75]
    cutoff = [1e-6, 3e-6, 1e-5, 1e-4]
    groups = [("none", [None] * 32), ("evolution_law", mixture * 4), ("cutoff_velocity", cutoff * 4)]
    return balanced(rng, groups, extra=("pink_noise",))


def size_label(cause, size):
    return {"none": lambda s: "none", "evolution_law": lambda s: f"aging share {s:g}",
            "second_state_variable": lambda s: f"b2 {s:g}", "cutoff_velocity": lambda s: f"Vc {s:g}",
            "slip_trend": lambda s: f"g {s:g}", "stiffness": lambda s: f"k {s:g}x"}[cause](size)


def pink_noise(rng, ts, rms):
    """1/f noise in time (power ∝ 1/f from 1/T up): drawn on a uniform grid at the median
    sampling interval by random-phase Fourier synthesis, linearly interpolated to ts, scaled to
    the given rms."""
    dt = float(np.median(np.diff(ts)))
    n = int(min(2 ** 22, 2 ** math.ceil(math.log2((ts[-1] - ts[0]) / dt + 2))))
    f = np.fft.rfftfreq(n, dt)
    amp = np.zeros_like(f)
    amp[1:] = f[1:] ** -0.5
    spec = amp * (rng.standard_normal(len(f)) + 1j * rng.standard_normal(len(f)))
    x = np.fft.irfft(spec, n)
    grid = ts[0] + dt * np.arange(n)
    y = np.interp(ts, grid, x)
    y -= y.mean()
    return y * rms / y.std()


def add_noise(rng, feats, ts, mu, lp):
    sigma = math.exp(rng.uniform(math.log(1e-4), math.log(5e-4)))
    info = {"friction_sigma": sigma}
    if "pink_noise" in feats:
        ratio = rng.uniform(0.5, 2.0)                 # 1/f rms over the white sigma
        mu = mu + pink_noise(rng, ts, ratio * sigma)
        info["pink_rms_over_white"] = ratio
    if "ar1_noise" in feats:
        tau = rng.uniform(1, 5)
        phi = np.exp(-np.diff(ts) / tau)
        xi, e = rng.standard_normal(len(ts)), np.empty(len(ts))
        e[0] = sigma * xi[0]
        for i in range(1, len(ts)):
            e[i] = phi[i - 1] * e[i - 1] + math.sqrt(1 - phi[i - 1] ** 2) * sigma * xi[i]
        info["ar1_tau_s"] = tau
    else:
        e = sigma * rng.standard_normal(len(ts))
    mu = mu + e
    if "spikes" in feats:
        nsp = int(rng.integers(3, 9))
        cand = rng.choice(np.arange(20, len(ts) - 20, 20), size=nsp, replace=False)
        idx = cand + rng.integers(0, 10, nsp)
        mu[idx] += rng.choice([-1, 1], nsp) * rng.uniform(10, 20, nsp) * sigma
        info["spike_indices"] = sorted(int(i) for i in idx)
    if "encoder_noise" in feats:
        info["encoder_sigma_um"] = rng.uniform(0.05, 0.2)
        lp = lp + info["encoder_sigma_um"] * rng.standard_normal(len(ts))
    return mu, lp, sigma, info


def make_record(spec, rng):
    feats, cause, size, rock = spec["features"], spec["cause"], spec["size"], spec["material"] == "bare_rock"
    sign = float(rng.choice([-1.0, 1.0]))
    max_hold = float(rng.choice([3000, 10000])) if spec["long_hold"] else float(rng.choice([300, 1000]))
    k_lo = 0.0
    if cause == "cutoff_velocity":            # the record must creep down to within ~10 Vc
        if rock and size <= 1e-4:
            max_hold, k_lo = 10000.0, min(0.065, 1e-3 / (size * 10000.0))  # V_min ~ a/(k t_hold)
        elif not rock:
            k_lo = 0.004
    for attempt in range(40):
        dc_g = math.exp(rng.uniform(math.log(10.0), math.log(60.0)))
        segs, label = protocol_rock(rng, max_hold) if rock else \
            protocol_gouge(rng, dc_g, cause == "cutoff_velocity")
        vmax = max(s[1] for s in segs)
        seg_t, ts, dt_fast = sample_times(rng, segs, feats)
        dc_lo, dc_hi = (max(1.0, 1.5 * vmax * dt_fast), 20.0) if rock else (dc_g, dc_g)
        p, effect, k_nom = sample_truth(rng, spec["material"], cause, size, sign, dc_lo, dc_hi, k_lo)
        seg_v = [s[1] for s in segs]
        p["v0"] = seg_v[0]
        try:
            Y, nfev = simulate(p, seg_t, seg_v, ts)
        except Unstable:
            continue
        if cause == "cutoff_velocity" and np.exp(Y[:, 0]).min() > 10 * size:
            continue                                           # Vc never reached: redraw
        mu = friction(p, Y, p["v0"])
        mu_n, lp_n, sigma, info = add_noise(rng, feats, ts, mu, load_point(seg_t, seg_v, ts))
        info["t0_s"] = math.exp(rng.uniform(math.log(100), math.log(1e5))) if "nonzero_t0" in feats else 0.0
        v = np.exp(Y[:, 0])
        spring = np.abs(mu - mu[0] - p["k"] * (load_point(seg_t, seg_v, ts) - Y[:, -1])).max()
        info["spring_check"] = float(spring)            # |mu - mu(0) - k (x_lp - delta)|: ~1e-13 seen
        return dict(table=np.column_stack([ts + info["t0_s"], lp_n, mu_n]), effect=effect, truth=p,
                    k_nom=k_nom, sigma=sigma, label=label, info=info, vmin=float(v.min()),
                    vmax=float(v.max()), nfev=nfev, attempts=attempt + 1)
    raise RuntimeError(f"no stable record for {spec}")


def generate(out, seed, quick, drift=False, limit=None):
    out.mkdir(parents=True, exist_ok=True)
    specs = plan_drift(np.random.default_rng(seed)) if drift else plan(np.random.default_rng(seed), quick)
    specs = specs[:limit]
    manifest, t_start = [], time.time()
    for i, spec in enumerate(specs):
        t1 = time.time()
        r = make_record(spec, np.random.default_rng([seed, i]))
        name = f"rec_{i:03d}.csv"
        np.savetxt(out / name, r["table"], fmt="%.17g", delimiter=",",
                   header="time_s,load_point_um,mu", comments="")
        truth = {k: v for k, v in r["truth"].items() if v is not None}
        manifest.append({"file": name, "cause": spec["cause"], "size": size_label(spec["cause"], spec["size"]),
                         "effect": r["effect"], "nominal_stiffness": r["k_nom"], "truth": truth,
                         "features": spec["features"], "noise_sigma": r["sigma"], "protocol": r["label"],
                         "n_samples": len(r["table"]), "v_min_reached": r["vmin"], "noise": r["info"]})
        vc = r["truth"].get("vc")
        flag = "" if vc is None else f" Vmin/Vc={r['vmin'] / vc:.3g}" + (" WARN" if r["vmin"] > 10 * vc else "")
        print(f"{name} {spec['cause']:22s} {manifest[-1]['size']:16s} {spec['material']:9s} "
              f"n={len(r['table']):6d} T={r['table'][-1, 0] - r['table'][0, 0]:8.0f}s "
              f"V=[{r['vmin']:.2e},{r['vmax']:.3g}] nfev={r['nfev']} try={r['attempts']} "
              f"spring={r['info'].pop('spring_check'):.1e} {time.time() - t1:.1f}s{flag}", flush=True)
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1))
    print(f"{len(specs)} records in {time.time() - t_start:.0f} s -> {out}")


def issue21_case(path, seed=21):
    """Issue 21's false alarm as one record: a plain one-state Slip-law gouge (a > b), the
    staircase 1 -> 300 um/s and holds of 3-300 s at 10 um/s, 28,401 rows on one interval; noise
    white 1.5e-4, AR(1) 5e-5 with tau = 1 s, and 1/f of rms 1.5e-4. Nothing is hidden."""
    rng = np.random.default_rng([seed, 21])
    dc = 30.0
    segs, label = protocol_gouge(rng, dc, True)
    dt = sum(s[0] for s in segs) / 28400
    ends = np.cumsum([max(1, round(s[0] / dt)) for s in segs])
    seg_t, ts = np.r_[0, ends] * dt, np.arange(ends[-1] + 1) * dt
    seg_v = [s[1] for s in segs]
    p = dict(mu0=0.6, a=0.011, b=[0.008], dc=[dc], laws=["slip"], vc=None, g=0.0, k=0.004, v0=seg_v[0])
    Y, _ = simulate(p, seg_t, seg_v, ts)
    mu = friction(p, Y, p["v0"])
    phi = math.exp(-dt / 1.0)
    xi, e = rng.standard_normal(len(ts)), np.empty(len(ts))
    e[0] = 5e-5 * xi[0]
    for i in range(1, len(ts)):
        e[i] = phi * e[i - 1] + math.sqrt(1 - phi ** 2) * 5e-5 * xi[i]
    mu = mu + 1.5e-4 * rng.standard_normal(len(ts)) + e + pink_noise(rng, ts, 1.5e-4)
    table = np.column_stack([ts, load_point(seg_t, seg_v, ts), mu])
    np.savetxt(path, table, fmt="%.10g", delimiter=",", header="time_s,load_point_um,mu", comments="")
    print(f"{path}: {len(ts)} rows, {label}, k {p['k']}")


# ---------------------------------------------------------------- outside the menu (--outside)
# Records whose truth is none of the diagnosis's one-step alternatives: other state laws, a
# rate-dependent direct effect. One state variable each, y = (ln V, ln theta, delta).
#   prz:          dtheta/dt = 1 - (V theta/(2 Dc))^2, friction term b ln(V0 theta/(2 Dc))
#   nagata:       dtheta/dt = 1 - V theta/Dc - (c/b) theta dmu/dt, dmu/dt = k (V_lp - V)
#   mix1:         dtheta/dt = w (1 - O) + (1 - w)(-O ln O)        (one state, O = V theta/Dc)
#   power_aging:  dtheta/dt = 1 - O^n
#   rate_a:       Slip law; the direct effect's local slope dmu/dlnV = a + a1 ln(V/V0), i.e.
#                 mu = mu0 + a ln(V/V0) + (a1/2) ln(V/V0)^2 + b ln(V0 theta/Dc)
LN2 = math.log(2.0)
#: --outside: a draw whose slip rate exceeds 2x the fastest load point (incipient stick-slip: these
#: laws collapse their state far faster than Aging/Slip after steps up and holds) is drawn again
OUTSIDE_VMAX_FACTOR = 2.0
#: family: (truth law, law parameter, its ladder: 12 records each)
OUTSIDE = {
    "prz_steps": ("prz", None, [None] * 12),
    "prz_holds": ("prz", None, [None] * 12),
    "nagata": ("nagata", "c", [0.5, 1.0, 1.5, 2.0, 2.5, 3.0] * 2),
    "mix1": ("mix1", "w", [0.15, 0.3, 0.5, 0.7] * 3),
    "power_aging": ("power_aging", "n", [1.3, 1.4, 1.5, 1.6, 1.7, 1.8] * 2),
    "rate_a": ("rate_a", "a_span", [0.15, 0.25, 0.35, 0.5] * 3),
}


def outside_rates(p, vlp):
    """d ln(theta)/dt of the one state and its partials in x = ln V and s = ln theta."""
    law, b, dc, k = p["laws"][0], p["b"][0], p["dc"][0], p["k"]
    ldc = math.log(dc)

    def rates(x, s):
        v, e = math.exp(x), math.exp(-s)
        vd = v / dc
        if law == "aging":
            return e - vd, -vd, -e
        if law == "slip":
            u = x + s - ldc
            return -vd * u, -vd * (u + 1.0), -vd
        if law == "prz":                                   # (V theta/(2 Dc))^2 = exp(2 (x + s - ln 2Dc))
            w2 = math.exp(2.0 * (x + s - ldc - LN2))
            return e * (1.0 - w2), -2.0 * e * w2, -e * (1.0 + w2)
        if law == "power_aging":
            n = p["n"]
            on = math.exp(n * (x + s - ldc))
            return e * (1.0 - on), -n * e * on, -e * (1.0 + (n - 1.0) * on)
        if law == "mix1":
            w, u = p["w"], x + s - ldc
            return (w * (e - vd) + (1.0 - w) * (-vd * u),
                    -w * vd - (1.0 - w) * vd * (u + 1.0), -w * e - (1.0 - w) * vd)
        if law == "nagata":                                # dmu/dt = k (V_lp - V) is explicit
            cb = p["c"] / b
            return e - vd - cb * k * (vlp - v), -vd + cb * k * v, -e
        raise ValueError(law)

    return rates


def rhs_and_jac_outside(p, vlp):
    """Right-hand side and analytic Jacobian of y = (x = ln V, s = ln theta, delta) for one state
    under an --outside law. From dmu/dt = k (V_lp - V) = a_loc(x) dx/dt + b ds/dt with
    a_loc = a + a1 (x - ln V0): dx/dt = (k (V_lp - V) - b ds/dt)/a_loc. Under Nagata ds/dt itself
    holds -(c/b) dmu/dt; since dmu/dt is the spring's rate the relation is explicit:
    a dx/dt = (1 + c) k (V_lp - V) - b (1/theta - V/Dc)."""
    a, a1, k, b = p["a"], p.get("a1", 0.0), p["k"], p["b"][0]
    lv0 = math.log(p["v0"])
    rates = outside_rates(p, vlp)

    def f(t, y):
        v = math.exp(y[0])
        r = rates(y[0], y[1])[0]
        return np.array([(k * (vlp - v) - b * r) / (a + a1 * (y[0] - lv0)), r, v])

    def jac(t, y):
        v = math.exp(y[0])
        r, rx, rs = rates(y[0], y[1])
        ap = a + a1 * (y[0] - lv0)
        xd = (k * (vlp - v) - b * r) / ap
        return np.array([[(-k * v - b * rx - a1 * xd) / ap, -b * rs / ap, 0.0],
                         [rx, rs, 0.0], [v, 0.0, 0.0]])

    return f, jac


def friction_outside(p, Y):
    X = Y[:, 0] - math.log(p["v0"])
    ldc = math.log(p["dc"][0]) + (LN2 if p["laws"][0] == "prz" else 0.0)
    return (p["mu0"] + p["a"] * X + 0.5 * p.get("a1", 0.0) * X ** 2
            + p["b"][0] * (math.log(p["v0"]) + Y[:, 1] - ldc))


def protocol_outside(rng, holds):
    """The bare-rock steps, then slide-hold-slides: holds None (steps only), "short" (2-3 of 10,
    30, 100 s) or a longest hold in s (with 2-4 shorter ones, as protocol_rock)."""
    segs, label = rock_steps(rng)
    if holds is None:
        return segs, label + "; no holds"
    hs = (sorted(rng.choice([10, 30, 100], size=rng.integers(2, 4), replace=False).tolist())
          if holds == "short" else rock_holds(rng, holds))
    for h in hs:
        segs += [(float(h), 0.0, "hold"), (rng.uniform(40, 60), 1.0, "slide")]
    return segs, label + "; holds " + ",".join(f"{h:g}" for h in hs) + " s"


def outside_size(family, value):
    """The label of the law parameter (magnitude only: rate_a's sign is in `effect`)."""
    law, name, _ = OUTSIDE[family]
    return law if name is None else f"{name.replace('_', ' ')} {value:g}"


def plan_outside(rng, families):
    """Family, law parameter, material and feature flags of every record (flags balanced within
    each family, 1/f noise in half), in a blind (shuffled) order."""
    specs = []
    for fam in families:
        _, _, ladder = OUTSIDE[fam]
        n, period = len(ladder), len(set(ladder))
        flags = {f: rng.permutation(np.arange(n) < (n + 1) // 2) for f in FEATURES + ["pink_noise"]}
        for i, value in enumerate(ladder):
            vw = (i + (i // period if period > 1 else 0)) % 2 == 0   # each value meets both materials
            material = "bare_rock" if vw else "rock_vs"
            specs.append(dict(family=fam, value=value, material=material,
                              features=[material] + [f for f in FEATURES + ["pink_noise"] if flags[f][i]]))
    order = rng.permutation(len(specs))
    return [specs[i] for i in order]


def sample_outside_truth(rng, spec, sign, dc_lo, dc_hi, x_span):
    """Material (velocity weakening or strengthening, rock ranges), the law's parameter and a
    stable machine: k >= 8 kc, kc the law's linear critical stiffness."""
    law, _, _ = OUTSIDE[spec["family"]]
    val = spec["value"]
    for _ in range(500):
        dc = math.exp(rng.uniform(math.log(dc_lo), math.log(dc_hi)))
        a = rng.uniform(0.006, 0.012) if spec["material"] == "bare_rock" else rng.uniform(0.008, 0.014)
        b = a + rng.uniform(0.001, 0.004) if spec["material"] == "bare_rock" else a - rng.uniform(0.001, 0.004)
        k = math.exp(rng.uniform(math.log(0.01), math.log(0.07)))
        mu0 = rng.uniform(0.55, 0.72)
        p = dict(mu0=mu0, a=a, b=[b], dc=[dc], laws=[law], vc=None, g=0.0, k=k, v0=None)
        a_min, factor, effect = a, 1.0, {}
        if law == "nagata":
            p["c"], factor, effect = val, 1.0 / (1.0 + val), {"c": val}
        elif law == "mix1":
            p["w"], effect = val, {"w": val}
        elif law == "power_aging":
            p["n"], factor, effect = val, val, {"n": val}
        elif law == "rate_a":              # a_loc spans a (1 -+ a_span) over the slip rates reached
            p["laws"], p["a1"], a_min = ["slip"], sign * val * a / x_span, a * (1.0 - val)
            effect = {"a1": p["a1"], "a_span": val}
        kc = factor * max(0.0, b - a_min) / dc
        if k >= 8 * kc:
            return p, effect, kc
    raise RuntimeError("no stable parameter draw")


def make_outside_record(spec, rng):
    feats, fam = spec["features"], spec["family"]
    law = OUTSIDE[fam][0]
    sign = float(rng.choice([-1.0, 1.0]))
    holds = None                                          # prz_steps, rate_a: steps only
    if fam == "prz_holds":
        holds = "short"
    elif fam == "mix1":
        holds = float(rng.choice([3000, 10000]))
    elif fam in ("nagata", "power_aging"):
        holds = float(rng.choice([300, 1000, 3000]))
    for attempt in range(40):
        segs, label = protocol_outside(rng, holds)
        vmax = max(s[1] for s in segs)
        seg_t, ts, dt_fast = sample_times(rng, segs, feats)
        seg_v = [s[1] for s in segs]
        vpos = [v for v in seg_v if v > 0]
        x_span = max(-math.log(min(vpos) / seg_v[0]), math.log(max(vpos) / seg_v[0])) + 1.0
        p, effect, kc = sample_outside_truth(rng, spec, sign, max(1.0, 1.5 * vmax * dt_fast), 20.0, x_span)
        p["v0"] = seg_v[0]
        try:
            Y, nfev = simulate(p, seg_t, seg_v, ts, model=rhs_and_jac_outside)
        except Unstable:
            continue
        a_loc = p["a"] + p.get("a1", 0.0) * (Y[:, 0] - math.log(p["v0"]))
        if a_loc.min() < 0.2 * p["a"] or Y[:, 0].max() > math.log(OUTSIDE_VMAX_FACTOR * vmax):
            continue                                           # a_loc near zero, or a slip burst: redraw
        mu = friction_outside(p, Y)
        lp = load_point(seg_t, seg_v, ts)
        mu_n, lp_n, sigma, info = add_noise(rng, feats, ts, mu, lp)
        info["t0_s"] = math.exp(rng.uniform(math.log(100), math.log(1e5))) if "nonzero_t0" in feats else 0.0
        v = np.exp(Y[:, 0])
        info["spring_check"] = float(np.abs(mu - mu[0] - p["k"] * (lp - Y[:, -1])).max())
        return dict(table=np.column_stack([ts + info["t0_s"], lp_n, mu_n]), effect=effect, truth=p,
                    k_nom=p["k"], kc=kc, sigma=sigma, label=label, info=info, vmin=float(v.min()),
                    vmax=float(v.max()), nfev=nfev, attempts=attempt + 1)
    raise RuntimeError(f"no stable record for {spec}")


def generate_outside(out, seed, families, limit=None):
    out.mkdir(parents=True, exist_ok=True)
    specs = plan_outside(np.random.default_rng(seed), families)[:limit]
    manifest, t_start = [], time.time()
    for i, spec in enumerate(specs):
        t1 = time.time()
        r = make_outside_record(spec, np.random.default_rng([seed, i]))
        name = f"rec_{i:03d}.csv"
        np.savetxt(out / name, r["table"], fmt="%.17g", delimiter=",",
                   header="time_s,load_point_um,mu", comments="")
        truth = {k: v for k, v in r["truth"].items() if v is not None}
        law = OUTSIDE[spec["family"]][0]
        size = outside_size(spec["family"], spec["value"])
        manifest.append({"file": name, "cause": "outside", "size": size, "effect": r["effect"],
                         "nominal_stiffness": r["k_nom"], "truth": truth, "features": spec["features"],
                         "noise_sigma": r["sigma"], "protocol": r["label"], "n_samples": len(r["table"]),
                         "v_min_reached": r["vmin"], "noise": r["info"], "family": spec["family"],
                         "truth_law": law, "critical_stiffness": r["kc"]})
        print(f"{name} {spec['family']:12s} {size:15s} {spec['material']:9s} "
              f"n={len(r['table']):6d} T={r['table'][-1, 0] - r['table'][0, 0]:8.0f}s "
              f"V=[{r['vmin']:.2e},{r['vmax']:.3g}] k/kc={r['k_nom'] / r['kc'] if r['kc'] > 0 else math.inf:.3g} "
              f"nfev={r['nfev']} try={r['attempts']} spring={r['info'].pop('spring_check'):.1e} "
              f"{time.time() - t1:.1f}s", flush=True)
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1))
    print(f"{len(specs)} records in {time.time() - t_start:.0f} s -> {out}")


def piecewise_grid(segs, dt_slide=0.3, dt_burst=0.02, burst=4.0, hold_pts=400, dt_hold=0.5):
    """Breaks are samples; dt_burst for `burst` s after each change, then dt_slide on slides
    (max(dt_slide, 0.01/V) when slow) and max(dt_hold, T/hold_pts) in holds."""
    seg_t = np.r_[0.0, np.cumsum([s[0] for s in segs])]
    pieces = [seg_t[-1:]]
    for j, (d, v, kind) in enumerate(segs):
        t0, t1 = seg_t[j], seg_t[j + 1]
        tb = min(t1, t0 + burst) if j > 0 else t0
        pieces.append(t0 + dt_burst * np.arange(int(round((tb - t0) / dt_burst))))
        dt = max(dt_slide, 0.01 / v) if kind == "slide" else max(dt_hold, d / hold_pts)
        pieces.append(tb + dt * np.arange(max(0, int(math.floor((t1 - tb) / dt - 0.5)) + 1)))
    return seg_t, np.unique(np.concatenate(pieces))


#: The four small records of tests/data/outside: name: (law parameters, k, protocol, AR(1) sigma)
S316 = (30 / 10 ** 0.5, 10 ** 0.5, "slide")
STEPS = [(30.0, 1.0, "slide"), S316, (40.0, 1.0, "slide"), (300.0, 0.1, "slide"), (40.0, 1.0, "slide")]
OUTSIDE_TESTS = {
    "prz_holds": (dict(laws=["prz"]), 0.02, STEPS + [(600.0, 0.03, "slide"), (40.0, 1.0, "slide")]
                  + [s for h in (10, 30, 100) for s in ((float(h), 0.0, "hold"), (50.0, 1.0, "slide"))], 1e-4),
    "mix1_holds": (dict(laws=["mix1"], w=0.3), 0.02,
                   STEPS + [s for h in (10, 100, 1000, 10000) for s in ((float(h), 0.0, "hold"), (50.0, 1.0, "slide"))], 0.0),
    "power_aging": (dict(laws=["power_aging"], n=1.5), 0.02, STEPS + [(1000.0, 0.01, "slide"), (40.0, 1.0, "slide")]
                    + [s for h in (10, 100, 1000) for s in ((float(h), 0.0, "hold"), (50.0, 1.0, "slide"))], 0.0),
    "nagata": (dict(laws=["nagata"], c=2.0), 0.01, STEPS + [(1000.0, 0.01, "slide"), (40.0, 1.0, "slide")]
               + [s for h in (10, 100, 1000) for s in ((float(h), 0.0, "hold"), (50.0, 1.0, "slide"))], 0.0),
}


#: The records of tests/data/design (issue 41), made like OUTSIDE_TESTS: name: (law
#: parameters, k, protocol, AR(1) sigma, noise stream). A record and its continuation share a
#: noise stream, so the continuation's rows up to the first record's end are the first record's.
STEPS_ONLY = STEPS + [(30.0, 10.0, "slide"), (40.0, 1.0, "slide"), (300.0, 0.1, "slide"), (40.0, 1.0, "slide")]
DESIGN_TESTS = {
    # a one-state Aging/Slip mixture with a small aging share, seen through steps only; then the
    # same record continued through a 10^4 s hold and a reslide (issue 41: long holds turned it
    # into a decisive wrong cut-off)
    "mix1_steps": (dict(laws=["mix1"], w=0.15), 0.02, STEPS_ONLY, 0.0, 2000),
    "mix1_steps_hold": (dict(laws=["mix1"], w=0.15), 0.02,
                        STEPS_ONLY + [(10000.0, 0.0, "hold"), (50.0, 1.0, "slide")], 0.0, 2000),
    # a rate-dependent direct effect (a law no library has): the local slope dmu/dlnV spans
    # a (1 -+ 0.35) over the record's slip rates, Slip-law state; steps only
    "rate_a_steps": (dict(laws=["slip"], a1=-0.35 * 0.008 / (math.log(10.0) + 1.0)), 0.02, STEPS_ONLY, 0.0, 2001),
}


def outside_tests(out, names=None, table=None):
    """The small test records of tests/data/outside (<= 8,000 rows each, %.10g): one state,
    a = 0.008, b = 0.011, Dc = 5 um, mu0 = 0.6, V0 = 1 um/s; white noise 1.5e-4 (prz_holds:
    plus AR(1) of 1e-4 with tau = 2 s). With `table` (DESIGN_TESTS), its records instead, each
    with its own noise stream."""
    out.mkdir(parents=True, exist_ok=True)
    rows = OUTSIDE_TESTS.items() if table is None else table.items()
    for idx, (name, spec) in enumerate(rows):
        law, k, segs, ar1 = spec[:4]
        if names and name not in names:
            continue
        t1 = time.time()
        rng = np.random.default_rng([38, spec[4] if len(spec) > 4 else 1000 + idx])
        p = dict(mu0=0.6, a=0.008, b=[0.011], dc=[5.0], g=0.0, k=k, v0=1.0, vc=None, **law)
        seg_t, ts = piecewise_grid(segs)
        seg_v = [s[1] for s in segs]
        Y, _ = simulate(p, seg_t, seg_v, ts, model=rhs_and_jac_outside)
        mu = friction_outside(p, Y) + 1.5e-4 * rng.standard_normal(len(ts))
        if ar1 > 0:
            phi = np.exp(-np.diff(ts) / 2.0)
            xi, e = rng.standard_normal(len(ts)), np.empty(len(ts))
            e[0] = ar1 * xi[0]
            for i in range(1, len(ts)):
                e[i] = phi[i - 1] * e[i - 1] + math.sqrt(1 - phi[i - 1] ** 2) * ar1 * xi[i]
            mu = mu + e
        path = out / f"{name}.csv"
        np.savetxt(path, np.column_stack([ts, load_point(seg_t, seg_v, ts), mu]), fmt="%.10g",
                   delimiter=",", header="time_s,load_point_um,mu", comments="")
        v = np.exp(Y[:, 0])
        print(f"{path}: {len(ts)} rows, {path.stat().st_size // 1024} KB, T {ts[-1]:.0f} s, "
              f"V [{v.min():.3g}, {v.max():.3g}], k {k}, {time.time() - t1:.1f}s", flush=True)


# ---------------------------------------------------------------- integrator check
def check(refdir):
    """Compare with the tight Radau reference solutions (Aging and Slip cases that are well posed)."""
    cases = json.loads((refdir / "rsfmodel" / "cases.json").read_text())["cases"]
    for c in cases:
        laws = [c[f"law{i + 1}"] for i in range(c["n_states"])]
        if any(l not in ("aging", "slip") for l in laws) or c["name"] == "b_slip_vstep_1_10":
            continue
        ref = np.genfromtxt(refdir / "tight_radau" / c["csv"], delimiter=",", names=True)
        p = dict(mu0=c["mu0"], a=c["a"], k=c["k"], g=0.0, laws=laws,
                 b=[c[f"b{i + 1}"] for i in range(len(laws))], dc=[c[f"Dc{i + 1}"] for i in range(len(laws))])
        seg_t = [s[0] for s in c["schedule"]] + [ref["time_s"][-1]]
        seg_v = [s[1] for s in c["schedule"]]
        t1 = time.time()
        Y, nfev = simulate(p, np.array(seg_t), seg_v, ref["time_s"])
        mu = friction(p, Y, c["V0"])
        dv = np.abs(np.exp(Y[:, 0]) / ref["velocity_um_s"] - 1).max()
        print(f"{c['name']:26s} rows={len(mu):6d} max|dmu|={np.abs(mu - ref['mu']).max():.2e} "
              f"max|dV/V|={dv:.2e} nfev={nfev} {time.time() - t1:.2f}s")


def check_outside(refdir):
    """The --outside integrator: against the tight Radau references (PRZ, Nagata, and the Aging
    and Slip cases through each new law's reducing parameter), against this file's own
    Aging/Slip integrator on bare-rock records with holds up to 1e4 s, and against the same laws
    written in (mu, theta) and integrated explicitly (DOP853)."""
    cases = json.loads((refdir / "rsfmodel" / "cases.json").read_text())["cases"]
    # the reducing parameter of each new law: (law, parameters) that equals Aging or Slip
    reduce = {"aging": [("mix1", {"w": 1.0}), ("power_aging", {"n": 1.0}), ("nagata", {"c": 0.0})],
              "slip": [("mix1", {"w": 0.0}), ("slip", {"a1": 0.0})]}
    print("-- outside laws vs tight_radau")
    for c in cases:
        if c["n_states"] != 1 or c["name"] == "b_slip_vstep_1_10":
            continue
        ref = np.genfromtxt(refdir / "tight_radau" / c["csv"], delimiter=",", names=True)
        base = dict(mu0=c["mu0"], a=c["a"], k=c["k"], g=0.0, b=[c["b1"]], dc=[c["Dc1"]], v0=c["V0"])
        runs = reduce.get(c["law1"], [(c["law1"], {"c": c.get("c1")} if c["law1"] == "nagata" else {})])
        for law, extra in runs:
            keep = np.isfinite(ref["mu"]) & (ref["time_s"] <= (11.0 if c["name"] == "g_prz_vstep_1_10" else np.inf))
            ts = ref["time_s"][keep]
            seg_t = [s[0] for s in c["schedule"]] + [ts[-1]]
            p = dict(base, laws=[law], **extra)
            Y, nfev = simulate(p, np.array(seg_t), [s[1] for s in c["schedule"]], ts, model=rhs_and_jac_outside)
            mu = friction_outside(p, Y)
            dv = np.abs(np.exp(Y[:, 0]) / ref["velocity_um_s"][keep] - 1).max()
            tag = law + "".join(f" {k}={v:g}" for k, v in extra.items())
            print(f"{c['name']:26s} as {tag:18s} rows={len(mu):6d} max|dmu|={np.abs(mu - ref['mu'][keep]).max():.2e} "
                  f"max|dV/V|={dv:.2e} nfev={nfev}")
    print("-- outside laws at their reducing parameter vs this file's Aging/Slip integrator")
    for seed in range(3):
        rng = np.random.default_rng([seed, 38])
        segs, label = protocol_rock(rng, 10000.0)
        seg_t, ts = uniform_grid(rng, segs)
        seg_v = [s[1] for s in segs]
        a = rng.uniform(0.006, 0.012)
        base = dict(mu0=0.6, a=a, b=[a + rng.uniform(0.001, 0.004)], dc=[rng.uniform(5, 20)], g=0.0,
                    k=0.05, v0=1.0, vc=None)
        for pure, runs in reduce.items():
            q = dict(base, laws=[pure])
            Yq, _ = simulate(q, seg_t, seg_v, ts)
            muq = friction(q, Yq, 1.0)
            for law, extra in runs:
                p = dict(base, laws=[law], **extra)
                Y, _ = simulate(p, seg_t, seg_v, ts, model=rhs_and_jac_outside)
                dv = np.abs(np.exp(Y[:, 0] - Yq[:, 0]) - 1).max()
                tag = law + "".join(f" {k}={v:g}" for k, v in extra.items())
                print(f"record {seed} ({len(ts)} rows, V_min {np.exp(Yq[:, 0]).min():.1e}) {tag:18s} vs {pure:5s} "
                      f"max|dmu|={np.abs(friction_outside(p, Y) - muq).max():.2e} max|dV/V|={dv:.2e}")

    print("-- outside laws in (mu, theta) form (DOP853, rtol 1e-12) vs the (ln V, ln theta) Radau path")
    segs = [(30.0, 1.0), (10.0, 10 ** 0.5), (40.0, 1.0), (300.0, 0.1), (40.0, 1.0), (100.0, 0.0), (60.0, 1.0)]
    seg_t, seg_v = np.r_[0.0, np.cumsum([s[0] for s in segs])], [s[1] for s in segs]
    ts = np.round(np.arange(0.0, seg_t[-1] + 1e-9, 0.05), 10)
    base = dict(mu0=0.6, a=0.01, b=[0.013], dc=[5.0], g=0.0, k=0.02, v0=1.0)
    for law, extra in [("prz", {}), ("nagata", {"c": 2.0}), ("mix1", {"w": 0.3}), ("power_aging", {"n": 1.5}),
                       ("slip", {"a1": 5e-4}), ("slip", {"a1": -5e-4})]:
        p = dict(base, laws=[law], **extra)
        Y, _ = simulate(p, seg_t, seg_v, ts, model=rhs_and_jac_outside)
        mu0, a, a1, b, dc, k = p["mu0"], p["a"], p.get("a1", 0.0), p["b"][0], p["dc"][0], p["k"]
        dce = 2 * dc if law == "prz" else dc

        def vel(mu, th):                      # invert mu = mu0 + a X + (a1/2) X^2 + b ln(V0 th/Dc')
            r = mu - mu0 - b * math.log(th / dce)
            return math.exp(2 * r / (a + math.sqrt(a * a + 2 * a1 * r)))

        def f(t, y, vlp):
            mu, th = y
            v = vel(mu, th)
            om, mud = v * th / dc, k * (vlp - v)
            thd = {"prz": lambda: 1 - (v * th / (2 * dc)) ** 2,
                   "nagata": lambda: 1 - om - p.get("c", 0) / b * th * mud,
                   "mix1": lambda: p.get("w", 0) * (1 - om) + (1 - p.get("w", 0)) * (-om * math.log(om)),
                   "power_aging": lambda: 1 - om ** p.get("n", 1),
                   "slip": lambda: -om * math.log(om)}[law]()
            return [mud, thd]

        y, mus, vs = [mu0, dce / p["v0"]], [], []
        for j, vlp in enumerate(seg_v):           # restarted at each break, as simulate()
            last = j == len(seg_v) - 1
            te = ts[(ts >= seg_t[j]) & ((ts < seg_t[j + 1]) | last)]
            sol = solve_ivp(f, (seg_t[j], seg_t[j + 1]), y, method="DOP853", rtol=1e-12,
                            atol=[1e-15, 1e-12], t_eval=te if last else np.r_[te, seg_t[j + 1]], args=(vlp,))
            mus += list(sol.y[0, :len(te)])
            vs += [vel(m, th) for m, th in sol.y[:, :len(te)].T]
            y = sol.y[:, -1]
        tag = law + "".join(f" {k}={v:g}" for k, v in extra.items())
        print(f"steps 1<->3.16,0.1 + hold 100 s ({len(ts)} rows) {tag:18s} "
              f"max|dmu|={np.abs(friction_outside(p, Y) - np.array(mus)).max():.2e} "
              f"max|dV/V|={np.abs(np.exp(Y[:, 0]) / np.array(vs) - 1).max():.2e}")

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", type=Path)
    ap.add_argument("--seed", type=int, help="default 1 (--outside: 38)")
    ap.add_argument("--quick", action="store_true", help="about 1/5 of the set")
    ap.add_argument("--check", type=Path, metavar="REFDIR", help="compare with shared/reference")
    ap.add_argument("--drift", action="store_true", help="the 1/f-noise set (32 none, 16 mixture, 16 cut-off)")
    ap.add_argument("--issue21", type=Path, metavar="CSV", help="write issue 21's false-alarm record")
    ap.add_argument("--rows-scale", type=float, default=1.0,
                    help="records this many times longer in rows (the speed set of issue 22: 3.5)")
    ap.add_argument("--limit", type=int, help="only the first N records of the (shuffled) set")
    ap.add_argument("--outside", action="store_true",
                    help="truths outside the diagnosis's menu: PRZ, Nagata, one-state Aging/Slip mixture, "
                         "power-law aging, rate-dependent a (12 records per family)")
    ap.add_argument("--outside-families", metavar="A,B", help="only these families of --outside: "
                    + ",".join(OUTSIDE))
    ap.add_argument("--outside-tests", type=Path, metavar="DIR",
                    help="write the four small test records of tests/data/outside")
    ap.add_argument("--design-tests", type=Path, metavar="DIR",
                    help="write the small test records of tests/data/design (issue 41)")
    args = ap.parse_args()
    ROWS_SCALE = args.rows_scale
    if args.outside_tests:
        outside_tests(args.outside_tests)
        sys.exit(0)
    if args.design_tests:
        outside_tests(args.design_tests, table=DESIGN_TESTS)
        sys.exit(0)
    if args.issue21:
        issue21_case(args.issue21)
        sys.exit(0)
    if args.check:
        check(args.check)
        check_outside(args.check)
    if args.out and args.outside:
        fams = args.outside_families.split(",") if args.outside_families else list(OUTSIDE)
        if any(f not in OUTSIDE for f in fams):
            ap.error(f"--outside-families: choose among {','.join(OUTSIDE)}")
        generate_outside(args.out, 38 if args.seed is None else args.seed, fams, args.limit)
    elif args.out:
        generate(args.out, 1 if args.seed is None else args.seed, args.quick, args.drift, args.limit)
    elif not args.check:
        ap.error("give --out DIR (and/or --check REFDIR)")
