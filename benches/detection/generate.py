#!/usr/bin/env python3
"""Independent generator of lab-realistic synthetic friction records with hidden effects.

For the detection study of `rsf diagnose` (see README.md here). Written from the equations
only (numpy + scipy solve_ivp Radau, rtol 1e-10); shares no code with rsf.

    python3 benches/detection/generate.py --out DIR [--seed 1] [--quick]
    python3 benches/detection/generate.py --check ../shared/reference   # integrator check

Units: time s, displacement um, velocity um/s, theta s, k 1/um, friction dimensionless.
    mu     = mu0 + a ln(V/V0) + sum_i b_i ln(V0 theta_i/Dc_i) + g delta
    dmu/dt = k (V_lp(t) - V)
    aging: dtheta/dt = 1 - O   slip: -O ln O   kato-tullis: exp(-V/Vc) - O ln O   (O = V theta/Dc)
Integrated as y = (ln V, ln theta_i, delta), restarted exactly at every load-point break.
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
    """ln theta at steady state: O = 1, except Kato-Tullis: O ln O = exp(-V/Vc), O > 1."""
    omega = 1.0
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


def simulate(p, seg_t, seg_v, ts):
    """Integrate through segments [seg_t[j], seg_t[j+1]) at V_lp = seg_v[j]; states at times ts."""
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
        f, jac = rhs_and_jac(p, vlp)
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
def protocol_rock(rng, max_hold):
    """Velocity steps of 0.5-3.5 decades around 1 um/s, then slide-hold-slides at the end."""
    vb, segs = 1.0, [(rng.uniform(20, 40), 1.0, "slide")]
    downs = sorted(rng.choice(np.arange(0.5, 3.51, 0.5), size=rng.integers(2, 4), replace=False))
    partners = [vb * 10 ** 0.5] + [vb * 10 ** -d for d in downs]
    order = rng.permutation(len(partners))
    for v in (partners[i] for i in order):
        segs.append((min(rng.uniform(20, 40) / v, rng.uniform(800, 2000)), v, "slide"))
        segs.append((rng.uniform(30, 60) / vb, vb, "slide"))
    ladder = [10, 30, 100, 300, 1000, 3000, 10000]
    short = [h for h in ladder if h <= min(max_hold, 1000) and h < max_hold]
    holds = sorted(rng.choice(short, size=min(len(short), rng.integers(2, 5)), replace=False).tolist()
                   + [max_hold])
    for h in holds:
        segs += [(float(h), 0.0, "hold"), (rng.uniform(40, 60) / vb, vb, "slide")]
    label = ("rock steps 1<->" + ",".join(f"{partners[i]:.3g}" for i in order)
             + " um/s; holds " + ",".join(f"{h:g}" for h in holds) + " s")
    return segs, label


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
        if "variable_sampling" in feats:
            seg_t = np.r_[0.0, np.cumsum([s[0] for s in segs])]
            ts, dt_fast = variable_grid(rng, segs, seg_t), 0.1
        else:
            seg_t, ts = uniform_grid(rng, segs)
            dt_fast = ts[1] - ts[0]
        if "time_jitter" in feats:
            ts = jitter(rng, ts)
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


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", type=Path)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--quick", action="store_true", help="about 1/5 of the set")
    ap.add_argument("--check", type=Path, metavar="REFDIR", help="compare with shared/reference")
    ap.add_argument("--drift", action="store_true", help="the 1/f-noise set (32 none, 16 mixture, 16 cut-off)")
    ap.add_argument("--issue21", type=Path, metavar="CSV", help="write issue 21's false-alarm record")
    ap.add_argument("--rows-scale", type=float, default=1.0,
                    help="records this many times longer in rows (the speed set of issue 22: 3.5)")
    ap.add_argument("--limit", type=int, help="only the first N records of the (shuffled) set")
    args = ap.parse_args()
    ROWS_SCALE = args.rows_scale
    if args.issue21:
        issue21_case(args.issue21)
        sys.exit(0)
    if args.check:
        check(args.check)
    if args.out:
        generate(args.out, args.seed, args.quick, args.drift, args.limit)
    elif not args.check:
        ap.error("give --out DIR (and/or --check REFDIR)")
