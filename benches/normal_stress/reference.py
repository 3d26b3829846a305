#!/usr/bin/env python3
"""Independent reference solver: rate-and-state friction with a time-varying normal stress.

    python reference.py PROTOCOL.toml OUT.csv [--method Radau|LSODA|DOP853]

Units: um, s, um/s, MPa; friction dimensionless.  Written from the equations only (numpy + scipy).

Model
    mu      = mu0 + a ln(V/v0) + sum_i b_i ln(v0 theta_i / dc_i)
    tau     = sigma(t) mu                              (shear stress, MPa)
    dtau/dt = K (V_lp - V),   K = k sigma_ref          (k in 1/um, K in MPa/um)
    dtheta_i/dt = G_i(V, theta_i) - alpha_i theta_i / (b_i sigma) dsigma/dt
        aging: G = 1 - V theta/dc        slip: G = -(V theta/dc) ln(V theta/dc)
    sigma(t): piecewise linear, with instantaneous steps at segment starts.

Formulation (differs from the Rust one, which integrates ln V, ln theta and dV/dt from the
time derivative of the friction balance): the integrated state is
    finite k:   y = (tau [MPa], z_i = ln theta_i, delta [um])
    infinite k: y = (z_i)          (V = V_lp, delta = load point)
and V is obtained at every RHS call by inverting the friction law with the current sigma(t):
    ln V = ln v0 + (tau/sigma - mu0 - sum_i b_i (ln v0 + z_i - ln dc_i)) / a
    dz_i/dt = G_i/theta_i - alpha_i/(b_i sigma) dsigma/dt
The load point is exact: LP(t) = LP(t0) + V_lp (t - t0) on each piece.

Instantaneous sigma step sigma- -> sigma+ (load point fixed): tau continuous, and
    z_i+ = z_i- + (alpha_i/b_i) ln(sigma-/sigma+)        (theta_i+ = theta_i- (sigma-/sigma+)^(alpha_i/b_i))
V+ then follows from the friction law with mu+ = tau/sigma+ (implicit in this formulation).
At infinite stiffness V = V_lp and mu jumps by -sum_i alpha_i ln(sigma+/sigma-).

Each protocol piece (segment) is integrated separately, and inside a piece the solver is
restarted at every output time (first_step = last accepted step), so output values are
step-end values, never dense-output interpolants.  Output row at a segment-start time belongs to
the piece ending there (value just before the step); row t = 0 is the initial steady state.
"""
import math
import sys
import tomllib

import numpy as np
from scipy.integrate import solve_ivp

RTOL, ATOL = 1e-12, 1e-12


class Model:
    def __init__(self, mu0, v0, a, k, sigma_ref, states):
        self.mu0, self.v0, self.a, self.sref = float(mu0), float(v0), float(a), float(sigma_ref)
        if isinstance(k, str):
            k = math.inf if k.strip().lower() in ("inf", "infinity") else float(k)
        self.k = float(k)
        self.inf = not math.isfinite(self.k)
        self.K = self.k * self.sref  # MPa/um
        for s in states:
            if s["law"] not in ("aging", "slip"):
                raise ValueError(f"unknown law {s['law']!r}")
        self.n = len(states)
        self.aging = np.array([s["law"] == "aging" for s in states])
        self.b = np.array([float(s["b"]) for s in states])
        self.dc = np.array([float(s["dc"]) for s in states])
        self.alpha = np.array([float(s.get("alpha", 0.0)) for s in states])
        if np.any((self.alpha != 0) & (self.b == 0)):
            raise ValueError("alpha != 0 needs b != 0")
        self.lndc, self.lnv0 = np.log(self.dc), math.log(self.v0)
        # exponent of the step map: alpha_i / b_i (0 where alpha_i = 0)
        self.ab = np.divide(self.alpha, self.b, out=np.zeros(self.n), where=self.alpha != 0)

    @classmethod
    def from_dict(cls, m):
        return cls(m["mu0"], m["v0"], m["a"], m["stiffness"], m["normal_stress"], m["state"])

    def mu(self, lnv, z):  # friction law
        return self.mu0 + self.a * (lnv - self.lnv0) + np.sum(self.b * (self.lnv0 + z - self.lndc))

    def lnv(self, mu, z):  # inverse friction law
        return self.lnv0 + (mu - self.mu0 - np.sum(self.b * (self.lnv0 + z - self.lndc))) / self.a

    def zdot(self, lnv, z, sig, dsig):
        # d ln(theta)/dt = G/theta - alpha/(b sigma) dsigma/dt
        with np.errstate(over="ignore", invalid="ignore"):  # only in rejected explicit trial stages
            v_dc = np.exp(lnv - self.lndc)
            g_th = np.where(self.aging, np.exp(-z) - v_dc, -v_dc * (lnv + z - self.lndc))
        return g_th - self.ab * dsig / sig

    def jac(self, y, sig, vlp):
        """Analytic Jacobian of the finite-k RHS in y = (tau, z, delta); lnV_tau = 1/(a sig), lnV_z = -b/a."""
        z, n = y[1:-1], self.n
        lnv = self.lnv(y[0] / sig, z)
        v = math.exp(min(lnv, 700.0))
        v_dc = np.exp(lnv - self.lndc)
        # dg_i/dlnV and direct dg_i/dz_i   (aging: g = e^-z - V/dc;  slip: g = -(V/dc) ln(V e^z/dc))
        g_x = np.where(self.aging, -v_dc, -v_dc * (lnv + z - self.lndc + 1.0))
        g_z = np.where(self.aging, -np.exp(-z), -v_dc)
        x_y = np.concatenate([[1.0 / (self.a * sig)], -self.b / self.a, [0.0]])  # dlnV/dy
        J = np.zeros((n + 2, n + 2))
        J[0] = -self.K * v * x_y
        J[1:-1] = np.outer(g_x, x_y)
        J[1:-1, 1:-1] += np.diag(g_z)
        J[-1] = v * x_y
        return J

    def step_z(self, z, s_minus, s_plus):
        # theta+ = theta- (sigma-/sigma+)^(alpha/b)
        return z + self.ab * math.log(s_minus / s_plus)


def build_pieces(loading, sigma_ref):
    """One piece per segment: (t0, t1, v_lp, sigma before the start step, sigma at start, rate)."""
    t, sig, out = 0.0, float(sigma_ref), []
    for seg in loading["segment"]:
        v = float(seg["v"])
        if "duration" in seg:
            dur = float(seg["duration"])
        else:
            if v == 0:
                raise ValueError("displacement segment needs v != 0")
            dur = float(seg["displacement"]) / abs(v)
        s_minus = sig
        sig = float(seg.get("normal_stress", sig))
        rate = float(seg.get("normal_stress_rate", 0.0))
        out.append(dict(t0=t, t1=t + dur, v=v, s_minus=s_minus, s0=sig, rate=rate))
        t, sig = t + dur, sig + rate * dur
        if min(out[-1]["s0"], sig) <= 0:
            raise ValueError("normal stress must stay positive")
    return out


def simulate(model, pieces, times, v_init, method="Radau", rtol=RTOL, atol=ATOL, tol=None):
    """Rows (t, LP, mu, V, delta, theta_1..N, sigma) at the sorted `times`.

    An output time within `tol` of a segment end is taken as that segment's end."""
    times = np.asarray(times, float)
    t_end = pieces[-1]["t1"]
    tol = 1e-13 * max(1.0, t_end) if tol is None else tol
    n = model.n
    rows = np.full((len(times), 6 + n), np.nan)
    z = model.lndc - math.log(v_init)  # steady state theta = dc / v_init
    mu_init = model.mu(math.log(v_init), z)
    y = z.copy() if model.inf else np.concatenate([[model.sref * mu_init], z, [0.0]])
    lp = 0.0

    def row(t, y, lp, sig, vlp):
        if model.inf:
            z, lnv, delta = y, math.log(vlp), lp
            mu = model.mu(lnv, z)
        else:
            z, delta = y[1:-1], y[-1]
            mu = y[0] / sig
            lnv = model.lnv(mu, z)
        return [t, lp, mu, math.exp(lnv), delta, *np.exp(z), sig]

    for i in np.nonzero(times <= tol)[0]:  # t = 0: initial steady state, before any step
        rows[i] = row(times[i], y, 0.0, model.sref, v_init)

    for p in pieces:
        t0, t1, vlp, s0, rate = p["t0"], p["t1"], p["v"], p["s0"], p["rate"]
        if model.inf and vlp <= 0:
            raise ValueError("infinite stiffness needs v_lp > 0")
        # the solver runs in piece-local time s = t - t0 (full float resolution right after a step)
        sig = lambda s: s0 + rate * s
        if s0 != p["s_minus"]:  # instantaneous step: tau, LP continuous; theta mapped
            zs = model.step_z(y if model.inf else y[1:-1], p["s_minus"], s0)
            y = zs if model.inf else np.concatenate([[y[0]], zs, [y[-1]]])

        if model.inf:
            lnvlp = math.log(vlp)
            f = lambda s, y: model.zdot(lnvlp, y, sig(s), rate)
        else:
            def f(s, y):
                sg = sig(s)
                lnv = model.lnv(y[0] / sg, y[1:-1])
                v = math.exp(min(lnv, 700.0))  # guard: explicit methods' rejected trial stages
                return np.concatenate([[model.K * (vlp - v)], model.zdot(lnv, y[1:-1], sg, rate), [v]])

        idx = np.nonzero((times > t0 + tol) & (times <= t1 + tol))[0]
        knots = [(min(times[i], t1) - t0, i) for i in idx]
        if not knots or knots[-1][0] < t1 - t0:
            knots.append((t1 - t0, None))
        ta, h = 0.0, None
        for tb, i in knots:
            if tb > ta:
                first = None if h is None else min(h, tb - ta)
                kw = {} if model.inf or method == "DOP853" else dict(jac=lambda s, y: model.jac(y, sig(s), vlp))
                sol = solve_ivp(f, (ta, tb), y, method=method, rtol=rtol, atol=atol, first_step=first, **kw)
                if not sol.success and method != "LSODA":
                    # Radau/BDF cannot resolve extreme events (V > 1e19 um/s after a large sigma drop at
                    # alpha = 0: time steps below the float spacing of t); LSODA gets through them.
                    print(f"note: {method} failed on [{t0 + ta}, {t0 + tb}] ({sol.message}); retrying with LSODA",
                          file=sys.stderr)
                    sol = solve_ivp(f, (ta, tb), y, method="LSODA", rtol=rtol, atol=atol, **kw)
                if not sol.success:
                    raise RuntimeError(f"solve_ivp failed on [{t0 + ta}, {t0 + tb}]: {sol.message}")
                y = sol.y[:, -1]
                if len(sol.t) > 2:
                    h = sol.t[-2] - sol.t[-3]  # last untruncated step
                ta = tb
            if i is not None:
                rows[i] = row(times[i], y, lp + vlp * tb, sig(tb), vlp)
        lp += vlp * (t1 - t0)
    return rows


def load_protocol(path):
    with open(path, "rb") as fh:
        doc = tomllib.load(fh)
    model = Model.from_dict(doc["model"])
    pieces = build_pieces(doc["loading"], model.sref)
    return doc, model, pieces


def output_times(dt, t_end):
    tol = 1e-13 * max(1.0, t_end)
    t = dt * np.arange(int(math.floor(t_end / dt + 1e-9)) + 1)
    return t if t_end - t[-1] <= tol else np.append(t, t_end)


def header(n):
    return ",".join(["time_s", "load_point_um", "mu", "slip_rate_um_s", "slip_um"]
                    + [f"theta_{i + 1}_s" for i in range(n)] + ["normal_stress_mpa"])


def write_csv(path, head, rows):
    with open(path, "w") as fh:
        fh.write(head + "\n")
        for r in rows:
            fh.write(",".join(repr(float(x)) for x in r) + "\n")


def run(protocol, out=None, method="Radau"):
    doc, model, pieces = load_protocol(protocol)
    times = output_times(float(doc["output"]["dt"]), pieces[-1]["t1"])
    rows = simulate(model, pieces, times, float(doc["loading"]["v_init"]), method=method)
    if out:
        write_csv(out, header(model.n), rows)
    return rows


if __name__ == "__main__":
    args = sys.argv[1:]
    meth = "Radau"
    if "--method" in args:
        j = args.index("--method")
        meth = args[j + 1]
        del args[j:j + 2]
    if len(args) != 2:
        sys.exit(__doc__.split("\n\n")[1])
    run(args[0], args[1], meth)
