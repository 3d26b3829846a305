#!/usr/bin/env python3
"""Independent generator of synthetic lab friction records for the coverage study of fitted-parameter
uncertainties (do the confidence intervals of `rsf fit` contain the truth as often as they claim?).

    python benches/coverage/generate.py --out DIR [--seed 1] [--per-noise 70] [--normal-stress 30]
    python benches/coverage/generate.py --check          # integrator cross-checks (no records)

Writes DIR/rec_NNN.csv (header time_s,load_point_um,mu; normal-stress records add
normal_stress_mpa) and DIR/truth.csv (one row per record: the true parameters and the noise).
Written from the equations only with numpy + scipy; shares no code with rsf. It reuses the
integrator of benches/detection/generate.py (scipy Radau on y = (ln V, ln theta, delta), rtol 1e-10,
analytic Jacobian) for the constant-normal-stress records, and integrates the Linker-Dieterich
normal-stress records with the same variables and tolerances (cross-checked against
benches/normal_stress/reference.py, a different formulation, by --check).

Units: time s, displacement um, velocity um/s, theta s, k 1/um (friction per um at sigma_ref),
normal stress MPa, friction dimensionless.
    mu      = mu0 + a ln(V/V0) + b ln(V0 theta/Dc)                 (V0 = first load-point velocity)
    tau     = sigma(t) mu,    dtau/dt = K (V_lp - V),   K = k sigma_ref  (sigma_ref = initial sigma)
    aging:  dtheta/dt = 1 - V theta/Dc,   slip: dtheta/dt = -(V theta/Dc) ln(V theta/Dc)
    normal stress (Linker-Dieterich): d ln theta/dt gets  - (alpha/b) sigma'/sigma
    so  d lnV/dt = [ (K (V_lp - V) - mu sigma')/sigma - b d ln theta/dt ] / a
"""
import argparse
import csv
import importlib.util
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

HERE = Path(__file__).resolve().parent


def _load(name, path):
    spec = importlib.util.spec_from_file_location(name, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


# benches/detection/generate.py: its simulate() (Radau, rtol 1e-10), friction(), load_point(), Unstable
G = _load("detection_generate", HERE.parent / "detection" / "generate.py")
RTOL, ATOL_LOG, ATOL_SLIP = G.RTOL, G.ATOL_LOG, G.ATOL_SLIP


def _fast_radau():
    """Speed only: scipy's Radau solves its small real and complex Newton systems through
    scipy.linalg.lu_solve, whose argument checks and batching wrapper cost far more than the 3x3 solve
    itself (~35 % of the run). Call the same LAPACK routine (getrs) directly: the records are bit for
    bit the same, 1.6x faster."""
    from scipy.integrate._ivp import radau
    from scipy.linalg import lapack

    def lu_solve(lu_and_piv, b, overwrite_b=False):
        lu, piv = lu_and_piv
        getrs = lapack.zgetrs if np.iscomplexobj(lu) or np.iscomplexobj(b) else lapack.dgetrs
        x, info = getrs(lu, piv, b, overwrite_b=overwrite_b)
        if info != 0:
            raise ValueError(f"getrs: illegal value in argument {-info}")
        return x

    radau.lu_solve = lu_solve


_fast_radau()
VMAX_FACTOR = G.VMAX_FACTOR          # slip rate above 10x the fastest load point: stick-slip, redraw
SETTLE = math.log(1.5)               # |ln(V/V_lp)| at the end of every slide must be below this

V_LO, V_HI = 0.1, 100.0              # load-point velocities of the protocols, um/s
DT_MIN, DT_MAX = 1e-3, 10.0          # sampling interval limits (1 kHz .. 0.1 Hz)
MIN_PER_DC = 20                      # samples per Dc of slip (before the 1 kHz cap)
ROWS_LO, ROWS_HI = 3000, 8000
NOISES = ("white", "ar1", "pink")
ALPHAS = (0.0, 0.1, 0.2, 0.3)
QUANT = 1e-5                         # encoder quantisation of friction (half of the records)


def logu(rng, lo, hi):
    return math.exp(rng.uniform(math.log(lo), math.log(hi)))


def nice_floor(x):
    """Largest 1, 2 or 5 x 10^n not above x (lab sampling intervals)."""
    e = math.floor(math.log10(x) + 1e-12)
    for c in (5, 2, 1):
        if c * 10.0 ** e <= x * (1 + 1e-12):
            return float(f"{c}e{e}")
    return float(f"1e{e}")


def sig2(v):
    return float(f"{v:.2g}")


# ---------------------------------------------------------------- truths
def draw_truth(rng, law):
    """a log-U 0.003-0.015; b = a + U(-0.003, 0.006) > 0.001; Dc log-U 3-100 um;
    k log-U [max(1.5 (b-a)/Dc, 3e-3), 5e-2]; mu0 U(0.55, 0.7)."""
    a = logu(rng, 0.003, 0.015)
    while True:
        b = a + rng.uniform(-0.003, 0.006)
        if b > 0.001:
            break
    dc = logu(rng, 3.0, 100.0)
    k = logu(rng, max(1.5 * (b - a) / dc, 3e-3), 5e-2)
    return dict(mu0=rng.uniform(0.55, 0.7), a=a, b=b, dc=dc, k=k, law=law)


# ---------------------------------------------------------------- protocols
def velocities(rng, nsteps, canonical=False):
    """1->10->1->100->10 um/s, or a start log-U 0.3-10 um/s and nsteps random steps of 0.5-2 decades
    (direction random where both stay in 0.1-100 um/s), velocities to 2 significant digits."""
    if canonical:
        return [1.0, 10.0, 1.0, 100.0, 10.0]
    vs = [sig2(logu(rng, 0.3, 10.0))]
    for _ in range(nsteps):
        m = rng.uniform(0.5, 2.0)
        up, down = math.log10(V_HI / vs[-1]), math.log10(vs[-1] / V_LO)
        dirs = [d for d, room in ((1, up), (-1, down)) if room >= m]
        if dirs:
            d = int(rng.choice(dirs))
        else:
            d, m = (1, min(m, up)) if up >= down else (-1, min(m, down))
        vs.append(min(V_HI, max(V_LO, sig2(vs[-1] * 10 ** (d * m)))))
    return vs


def slide(v, L):
    return dict(kind="slide", v=v, L=L, rate=0.0)


def protocol_steps(rng, canonical):
    vs = velocities(rng, int(rng.integers(4, 7)), canonical)
    segs = [slide(v, rng.uniform(15, 25)) for v in vs]
    return segs, "steps " + "->".join(f"{v:g}" for v in vs) + " um/s"


def protocol_hold(rng):
    """3-4 velocity steps, then a hold of 10-300 s (log-U) and a reslide of 20-30 Dc at the last velocity."""
    vs = velocities(rng, int(rng.integers(3, 5)))
    segs = [slide(v, rng.uniform(15, 25)) for v in vs]
    hold = round(logu(rng, 10.0, 300.0), 1)
    segs += [dict(kind="hold", v=0.0, d=hold, rate=0.0), dict(slide(vs[-1], rng.uniform(20, 30)), burst=True)]
    return segs, "steps " + "->".join(f"{v:g}" for v in vs) + f" um/s; hold {hold:g} s; reslide"


def protocol_ns(rng, p):
    """Velocity steps with two normal-stress changes at constant load-point velocity: run-in V1,
    step to V2, sigma -> sigma_ref (1 +- 10-30 %) as a ramp, slide, step to V3, sigma back to sigma_ref,
    slide, [step to V4]. Each ramp lasts max(1 s, c mu0 |dsigma/sigma_ref| / (k V)) with c in
    0.3-0.6, which keeps the slip-rate excursion near (1 + 1/c) V."""
    vs = velocities(rng, int(rng.integers(2, 4)))
    sref = float(rng.choice([5.0, 10.0, 20.0, 30.0, 50.0]))
    frac = round(float(rng.choice([-1, 1])) * rng.uniform(0.10, 0.30), 2)
    s1 = round(sref * (1 + frac), 2)

    def ramp(v, s_from, s_to):
        t = max(1.0, rng.uniform(0.3, 0.6) * p["mu0"] * abs(s_to - s_from) / sref / (p["k"] * v))
        return dict(kind="ramp", v=v, d=t, s_from=s_from, s_to=s_to)

    segs = [slide(vs[0], rng.uniform(15, 25)), slide(vs[1], rng.uniform(15, 25)), ramp(vs[1], sref, s1),
            slide(vs[1], rng.uniform(15, 25)), slide(vs[2], rng.uniform(15, 25)), ramp(vs[2], s1, sref),
            slide(vs[2], rng.uniform(15, 25))]
    segs += [slide(v, rng.uniform(15, 25)) for v in vs[3:]]
    label = (f"steps {vs[0]:g}->{vs[1]:g} (sigma {sref:g}->{s1:g} MPa) ->{vs[2]:g} (sigma ->{sref:g}) "
             + "".join(f"->{v:g}" for v in vs[3:]) + " um/s")
    return segs, label, sref


# ---------------------------------------------------------------- sampling
def sample(segs, dc, per_dc, hold_pts):
    """Give each segment a duration and sample times: every slide is sampled uniformly at the lab
    interval nice_floor(Dc / (per_dc V)) in 1 ms .. 10 s, its duration a whole number of intervals;
    a ramp at min(that, T/10); a hold at nice_floor(T/hold_pts) (at most 10 s); a reslide (burst)
    at 1/5 of its interval (at least 1 ms) for its first 3 Dc. Segment breaks are samples.
    Sets each segment's "dt" (and a ramp's final "d"); returns the segment start times (+ end) and
    the sample times, both rounded to 1e-9 s."""
    t, seg_t, pieces = 0.0, [0.0], []
    for s in segs:
        if s["kind"] == "hold":
            dt = min(DT_MAX, nice_floor(s["d"] / hold_pts))
            n = max(1, round(s["d"] / dt))
            pieces.append(t + dt * np.arange(n))
            t += n * dt
        else:
            v = s["v"]
            dt = min(DT_MAX, max(DT_MIN, nice_floor(dc / (per_dc * v))))
            if s["kind"] == "ramp":
                dt = max(DT_MIN, nice_floor(min(dt, s["d"] / 10)))
                n = math.ceil(s["d"] / dt - 1e-9)
                pieces.append(t + dt * np.arange(n))
                s["d"] = n * dt
                t += n * dt
            else:
                dur = s["L"] * dc / v
                if s.get("burst"):
                    dtb = max(DT_MIN, nice_floor(dt / 5))
                    nb = math.ceil(3 * dc / v / dtb)
                    pieces.append(t + dtb * np.arange(nb))
                    t, dur = t + nb * dtb, dur - nb * dtb
                n = max(2, math.ceil(dur / dt))
                pieces.append(t + dt * np.arange(n))
                t += n * dt
            s["dt"] = dt
        t = round(t, 9)
        seg_t.append(t)
    ts = np.round(np.concatenate(pieces + [[t]]), 9)
    seg_t = np.array(seg_t)
    seg_t = np.round(seg_t, 9)
    assert np.all(np.diff(ts) > 0) and np.all(np.isin(seg_t, ts))
    return seg_t, ts


def plan_sampling(rng, segs, dc):
    """Samples per Dc of slip so that the record has a drawn target of 3,000-8,000 rows (never fewer
    than MIN_PER_DC per Dc; the 1 kHz cap can give fewer on fast slides of small Dc)."""
    target = rng.uniform(ROWS_LO, ROWS_HI)
    hold_pts = int(rng.integers(100, 300))
    per_dc = max(MIN_PER_DC, target / sum(s.get("L", 0.0) for s in segs))
    for _ in range(30):
        trial = [dict(s) for s in segs]
        seg_t, ts = sample(trial, dc, per_dc, hold_pts)
        if len(ts) <= ROWS_HI or per_dc <= MIN_PER_DC:
            break
        per_dc = max(MIN_PER_DC, per_dc * 0.9)
    return trial, seg_t, ts, per_dc


# ---------------------------------------------------------------- normal-stress integrator
def simulate_ns(p, segs, seg_t, ts, sref):
    """y = (x = ln V, s = ln theta, delta) through segments with sigma(t) piecewise linear (ramps);
    returns Y at ts and sigma at ts. Same tolerances and blow-up event as detection/generate.py."""
    a, b, dc, k, alpha = p["a"], p["b"], p["dc"], p["k"], p["alpha"]
    K, ldc, aging = k * sref, math.log(dc), p["law"] == "aging"
    v0 = segs[0]["v"]
    y = np.array([math.log(v0), math.log(dc / v0), 0.0])
    mu_of = lambda x, s: p["mu0"] + a * (x - math.log(v0)) + b * (math.log(v0) + s - ldc)
    xmax = math.log(VMAX_FACTOR * max(s["v"] for s in segs))
    blowup = lambda t, y: y[0] - xmax
    blowup.terminal = True
    atol = np.array([ATOL_LOG, ATOL_LOG, ATOL_SLIP])
    Y, SIG, nfev, sig = np.empty((len(ts), 3)), np.empty(len(ts)), 0, sref
    for j, s in enumerate(segs):
        t0, t1, vlp = seg_t[j], seg_t[j + 1], s["v"]
        rate = (s["s_to"] - s["s_from"]) / (t1 - t0) if s["kind"] == "ramp" else 0.0
        s_start = sig

        def rates(x, z):
            v = math.exp(x)
            if aging:
                e = math.exp(-z)
                return e - v / dc, -v / dc, -e
            u = x + z - ldc
            return -(v / dc) * u, -(v / dc) * (u + 1.0), -v / dc

        def f(t, y, t0=t0, s_start=s_start, rate=rate, vlp=vlp):
            sg = s_start + rate * (t - t0)
            v = math.exp(y[0])
            g = rates(y[0], y[1])[0]
            zd = g - (alpha / b) * rate / sg
            xd = ((K * (vlp - v) - mu_of(y[0], y[1]) * rate) / sg - b * zd) / a
            return np.array([xd, zd, v])

        def jac(t, y, t0=t0, s_start=s_start, rate=rate):
            sg = s_start + rate * (t - t0)
            v = math.exp(y[0])
            _, gx, gz = rates(y[0], y[1])
            return np.array([[((-K * v - a * rate) / sg - b * gx) / a, (-b * rate / sg - b * gz) / a, 0.0],
                             [gx, gz, 0.0], [v, 0.0, 0.0]])

        lo = np.searchsorted(ts, t0, "left")
        hi = len(ts) if j == len(segs) - 1 else np.searchsorted(ts, t1, "left")
        te = ts[lo:hi] if ts[hi - 1] >= t1 else np.r_[ts[lo:hi], t1]
        sol = solve_ivp(f, (t0, t1), y, method="Radau", jac=jac, rtol=RTOL, atol=atol, t_eval=te, events=blowup)
        if sol.status != 0:
            raise G.Unstable(f"segment {j} at t={t0:.4g}: {sol.message}")
        Y[lo:hi] = sol.y.T[: hi - lo]
        SIG[lo:hi] = s_start + rate * (ts[lo:hi] - t0)
        y, nfev = sol.y[:, -1], nfev + sol.nfev
        sig = s["s_to"] if s["kind"] == "ramp" else sig
    return Y, SIG, nfev


# ---------------------------------------------------------------- noise
def ou(rng, ts, sd, tau):
    """Stationary Ornstein-Uhlenbeck process (AR(1) at the sample times, phi = exp(-dt/tau))."""
    phi = np.exp(-np.diff(ts) / tau)
    xi, e = rng.standard_normal(len(ts)), np.empty(len(ts))
    e[0] = sd * xi[0]
    c = sd * np.sqrt(1 - phi ** 2)
    for i in range(1, len(ts)):
        e[i] = phi[i - 1] * e[i - 1] + c[i - 1] * xi[i]
    return e


def power_law(rng, ts, rms, beta):
    """Gaussian noise with power spectrum ~ f^-beta (random complex amplitudes, Fourier synthesis) on a
    uniform grid over twice the record (at most 2^21 points, spacing >= the shortest sample interval),
    zero mean and the given rms over the record's time span, linearly interpolated to ts."""
    T = ts[-1] - ts[0]
    dtmin = float(np.min(np.diff(ts)))
    n = int(2 ** min(21, math.ceil(math.log2(2 * T / dtmin + 2))))
    dg = 2 * T / (n - 1)
    f = np.fft.rfftfreq(n, dg)
    amp = np.zeros_like(f)
    amp[1:] = f[1:] ** (-beta / 2)
    x = np.fft.irfft(amp * (rng.standard_normal(len(f)) + 1j * rng.standard_normal(len(f))), n)
    grid = ts[0] + dg * np.arange(n)
    m = np.searchsorted(grid, ts[-1]) + 1
    x = x[:m] - x[:m].mean()
    x *= rms / math.sqrt(np.mean(x ** 2))
    return np.interp(ts, grid[:m], x)


def add_noise(rng, family, ts):
    info = dict(white_sd="", ar1_sd="", ar1_tau_s="", pink_rms="", pink_beta="")
    if family == "white":
        info["white_sd"] = logu(rng, 1e-4, 4e-4)
        e = info["white_sd"] * rng.standard_normal(len(ts))
    elif family == "ar1":
        info["ar1_tau_s"], info["ar1_sd"] = logu(rng, 0.3, 10.0), logu(rng, 1e-4, 4e-4)
        info["white_sd"] = logu(rng, 2e-5, 6e-5)
        e = ou(rng, ts, info["ar1_sd"], info["ar1_tau_s"]) + info["white_sd"] * rng.standard_normal(len(ts))
    else:
        info["pink_beta"], info["pink_rms"] = rng.uniform(0.8, 1.5), logu(rng, 2e-4, 1e-3)
        info["white_sd"] = logu(rng, 5e-5, 1.5e-4)
        e = power_law(rng, ts, info["pink_rms"], info["pink_beta"]) + info["white_sd"] * rng.standard_normal(len(ts))
    return e, info


# ---------------------------------------------------------------- records
def plan(per_noise, n_ns):
    """Record specs: per noise family, law alternating (half each), every 5th a hold record, every 3rd
    of the rest the canonical 1->10->1->100->10 protocol; then the normal-stress records with noise in
    rotation, alpha cycling through 0, 0.1, 0.2, 0.3 and the law alternating every 4."""
    specs = []
    for fam in NOISES:
        for j in range(per_noise):
            kind = "hold" if j % 5 == 4 else ("canonical" if j % 3 == 0 else "steps")
            specs.append(dict(noise=fam, law=("aging", "slip")[j % 2], kind=kind, alpha=None))
    for j in range(n_ns):
        specs.append(dict(noise=NOISES[j % 3], law=("aging", "slip")[(j // 4) % 2], kind="normal_stress",
                          alpha=ALPHAS[j % 4]))
    return specs


def make_record(spec, rng):
    for attempt in range(100):
        p = draw_truth(rng, spec["law"])
        sref = None
        if spec["kind"] == "normal_stress":
            p["alpha"] = spec["alpha"]
            segs, label, sref = protocol_ns(rng, p)
        elif spec["kind"] == "hold":
            segs, label = protocol_hold(rng)
        else:
            segs, label = protocol_steps(rng, spec["kind"] == "canonical")
        segs, seg_t, ts, per_dc = plan_sampling(rng, segs, p["dc"])
        seg_v = [s["v"] for s in segs]
        v0 = seg_v[0]
        try:
            if sref is None:
                q = dict(mu0=p["mu0"], a=p["a"], b=[p["b"]], dc=[p["dc"]], laws=[p["law"]], k=p["k"], g=0.0,
                         vc=None, v0=v0)
                Y, nfev = G.simulate(q, seg_t, seg_v, ts)
                mu = G.friction(q, Y, v0)
                sig = None
            else:
                Y, sig, nfev = simulate_ns(p, segs, seg_t, ts, sref)
                mu = p["mu0"] + p["a"] * (Y[:, 0] - math.log(v0)) + p["b"] * (math.log(v0) + Y[:, 1] - math.log(p["dc"]))
        except G.Unstable:
            continue
        lp = G.load_point(seg_t, seg_v, ts)
        v = np.exp(Y[:, 0])
        ends = np.searchsorted(ts, seg_t[1:])
        if any(s["kind"] == "slide" and abs(math.log(v[i] / s["v"])) > SETTLE for s, i in zip(segs, ends)):
            continue                                    # a slide that has not settled: redraw
        # spring relation: tau(t) - tau(0) = K (lp - delta), tau = sigma mu (sigma = 1 without normal stress)
        s_arr = np.ones(len(ts)) if sig is None else sig / sref
        spring = float(np.abs(s_arr * mu - mu[0] - p["k"] * (lp - Y[:, 2])).max())
        e, info = add_noise(rng, spec["noise"], ts)
        quant = QUANT if rng.random() < 0.5 else 0.0
        mu_n = mu + e
        if quant:
            mu_n = np.round(mu_n / quant) * quant
        p.update(v0=v0, sigma_ref=sref)
        return dict(ts=ts, lp=lp, mu=mu_n, sig=sig, p=p, info=info, quant=quant, label=label, per_dc=per_dc,
                    vmin=float(v.min()), vmax=float(v.max()), nfev=nfev, attempts=attempt + 1, spring=spring,
                    segs=segs)
    raise RuntimeError(f"no stable record for {spec}")


def write_csv(path, r):
    cols = [r["ts"], r["lp"], r["mu"]] + ([] if r["sig"] is None else [r["sig"]])
    head = "time_s,load_point_um,mu" + ("" if r["sig"] is None else ",normal_stress_mpa")
    mu_fmt = (lambda x: f"{x:.5f}") if r["quant"] else repr
    rows = zip(*[c.tolist() for c in cols])
    with open(path, "w") as fh:
        fh.write(head + "\n")
        for row in rows:
            fh.write(",".join([repr(row[0]), repr(row[1]), mu_fmt(row[2])] + [repr(x) for x in row[3:]]) + "\n")


TRUTH_COLS = ["file", "noise", "law", "mu0", "v0", "a", "b", "dc", "k", "alpha", "rows",
              "white_sd", "ar1_sd", "ar1_tau_s", "pink_rms", "pink_beta", "quant", "kind", "sigma_ref",
              "hold_s", "duration_s", "samples_per_dc", "v_min", "v_max", "attempts", "spring_check", "protocol"]


def generate(out, seed, per_noise, n_ns):
    out.mkdir(parents=True, exist_ok=True)
    specs = plan(per_noise, n_ns)
    t_all, rows = time.time(), []
    for i, spec in enumerate(specs):
        t1 = time.time()
        r = make_record(spec, np.random.default_rng([seed, i]))
        name = f"rec_{i:03d}.csv"
        write_csv(out / name, r)
        p = r["p"]
        hold = next((s["d"] for s in r["segs"] if s["kind"] == "hold"), "")
        rows.append(dict(file=name, noise=spec["noise"], law=p["law"], mu0=p["mu0"], v0=p["v0"], a=p["a"], b=p["b"],
                         dc=p["dc"], k=p["k"], alpha="" if spec["alpha"] is None else p["alpha"], rows=len(r["ts"]),
                         **r["info"], quant=r["quant"], kind=spec["kind"],
                         sigma_ref="" if p["sigma_ref"] is None else p["sigma_ref"], hold_s=hold,
                         duration_s=float(r["ts"][-1]), samples_per_dc=round(r["per_dc"], 2), v_min=r["vmin"],
                         v_max=r["vmax"], attempts=r["attempts"], spring_check=r["spring"], protocol=r["label"]))
        print(f"{name} {spec['noise']:5s} {p['law']:5s} {spec['kind']:13s} n={len(r['ts']):5d} "
              f"T={r['ts'][-1]:8.0f}s a={p['a']:.4f} b-a={p['b'] - p['a']:+.4f} dc={p['dc']:6.2f} "
              f"k/kc={p['k'] * p['dc'] / max(p['b'] - p['a'], 1e-12):8.3g} V=[{r['vmin']:.2e},{r['vmax']:.3g}] "
              f"nfev={r['nfev']} try={r['attempts']} spring={r['spring']:.1e} {time.time() - t1:.1f}s", flush=True)
    with open(out / "truth.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=TRUTH_COLS)
        w.writeheader()
        for row in rows:
            w.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in row.items()})
    print(f"{len(specs)} records in {time.time() - t_all:.0f} s -> {out}")


# ---------------------------------------------------------------- checks
def check():
    """simulate_ns at constant sigma vs detection/generate.py's simulate (same formulation), and on
    normal-stress protocols vs benches/normal_stress/reference.py ((tau, ln theta, delta), V from the
    inverted friction law, rtol = atol = 1e-12, restarted at every output time)."""
    R = _load("ns_reference", HERE.parent / "normal_stress" / "reference.py")
    for i in range(4):
        rng = np.random.default_rng([99, i])
        law = ("aging", "slip")[i % 2]
        p = draw_truth(rng, law)
        p["alpha"] = ALPHAS[1 + i % 3]
        segs, label, sref = protocol_ns(rng, p)
        segs, seg_t, ts, _ = plan_sampling(rng, segs, p["dc"])
        v0 = segs[0]["v"]
        t1 = time.time()
        try:
            Y, sig, _ = simulate_ns(p, segs, seg_t, ts, sref)
        except G.Unstable as e:
            print(f"case {i}: unstable ({e}), skipped")
            continue
        t_mine = time.time() - t1
        mu = p["mu0"] + p["a"] * (Y[:, 0] - math.log(v0)) + p["b"] * (math.log(v0) + Y[:, 1] - math.log(p["dc"]))
        model = R.Model(p["mu0"], v0, p["a"], p["k"], sref, [dict(law=law, b=p["b"], dc=p["dc"], alpha=p["alpha"])])
        rsegs, s = [], sref
        for sg, d in zip(segs, np.diff(seg_t)):
            seg = dict(v=sg["v"], duration=float(d))
            if sg["kind"] == "ramp":
                seg["normal_stress_rate"] = (sg["s_to"] - sg["s_from"]) / float(d)
            rsegs.append(seg)
        keep = ts[:: max(1, len(ts) // 400)]                # the reference restarts at every output time
        idx = np.searchsorted(ts, keep)
        t1 = time.time()
        ref = R.simulate(model, R.build_pieces({"segment": rsegs}, sref), keep, v0, rtol=1e-12, atol=1e-12)
        print(f"ns case {i} {law} alpha={p['alpha']} {label}: {len(keep)} rows, max|dmu|="
              f"{np.abs(mu[idx] - ref[:, 2]).max():.2e} max|dlnV|={np.abs(Y[idx, 0] - np.log(ref[:, 3])).max():.2e} "
              f"max|dsigma|={np.abs(sig[idx] - ref[:, -1]).max():.1e}  ({t_mine:.1f} s vs {time.time() - t1:.1f} s)")
        # the same protocol at constant sigma (alpha irrelevant) vs detection/generate.py
        flat = [dict(s, kind="slide") if s["kind"] == "ramp" else s for s in segs]
        Y2, _, _ = simulate_ns(dict(p, alpha=0.0), flat, seg_t, ts, sref)
        q = dict(mu0=p["mu0"], a=p["a"], b=[p["b"]], dc=[p["dc"]], laws=[law], k=p["k"], g=0.0, vc=None, v0=v0)
        Yg, _ = G.simulate(q, seg_t, [s["v"] for s in segs], ts)
        print(f"   constant sigma vs detection/generate.py: max|dlnV|={np.abs(Y2[:, 0] - Yg[:, 0]).max():.2e} "
              f"max|dlntheta|={np.abs(Y2[:, 1] - Yg[:, 1]).max():.2e}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", type=Path)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--per-noise", type=int, default=70, help="records per noise family (white, ar1, pink)")
    ap.add_argument("--normal-stress", type=int, default=30, help="normal-stress records (noise in rotation)")
    ap.add_argument("--check", action="store_true", help="integrator cross-checks")
    args = ap.parse_args()
    if args.check:
        check()
    if args.out:
        generate(args.out, args.seed, args.per_noise, args.normal_stress)
    elif not args.check:
        ap.error("give --out DIR (or --check)")
