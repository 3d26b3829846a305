"""One case of QDYN's regression suite on one build, with the ODE solver of one's choice: the
case's own settings (its test/CASE.py, unchanged) but SOLVER, so that a case written for
Bulirsch-Stoer (SOLVER = 1) also runs under Runge-Kutta-Fehlberg (SOLVER = 2), and the reverse.

Usage: python solvers.py BUILD_DIR CASE SOLVER OUT.json [THETA_LAW]   (run one build)
       python solvers.py --compare OWN.json RSF.json               (rsf's against QDYN's own)

THETA_LAW, when given, replaces the case's state law too (0: aging without healing, 1: aging,
2: slip), so that a law no case of the suite uses is run by both builds.
BUILD_DIR is a QDYN copy (run.sh's WORK/own or WORK/rsf); CASE one of tserice, vstep,
stickslip, singleasperity (its RSF mode). OUT.json gets the case's (t, var1, var2) as QDYN's
test records them, the wall time, the run's end time and whether it reached TMAX. --compare
prints one Markdown row: both runs' ends and times and rsf's largest relative deviation from
QDYN's own on QDYN's own times, at QDYN's criterion (rtol 1e-4); exit 1 when rsf's run did not
reach the end QDYN's own reached, or deviates by more.
"""

import json
import os
import sys
import time

CLASSES = {"tserice": "TestTseRice", "vstep": "TestVstep", "stickslip": "TestStickSlip",
           "singleasperity": "TestSingleAsperity"}
RTOL = 1e-4  # QDYN's own criterion (test/aux.py)


def run(build, case, solver, out, theta_law=None):
    import numpy as np

    test_dir = os.path.join(os.path.abspath(build), "test")
    sys.path.insert(0, os.path.join(os.path.abspath(build), "src"))
    sys.path.insert(0, test_dir)
    os.chdir(test_dir)
    from pyqdyn import qdyn

    module = __import__(case)
    p = qdyn()
    settings = p.settings

    def with_solver(set_dict):  # the case's settings, but the solver (and the state law)
        set_dict["SOLVER"] = solver
        if theta_law is not None:
            set_dict["SET_DICT_RSF"]["THETA_LAW"] = theta_law
        return settings(set_dict)

    p.settings = with_solver
    t = getattr(module, CLASSES[case])(p)
    t.compare_results = lambda mode: None  # the frozen comparison is the suite's business
    t0 = time.perf_counter()
    failed = None
    try:
        if case in ("vstep", "stickslip", "singleasperity"):
            t.run_test("RSF")
        else:
            t.run_test()
    except Exception as e:  # a run that stopped: its reason is the result
        failed = f"{type(e).__name__}: {e}"
    wall = time.perf_counter() - t0
    r = t.test_results.get("RSF")
    rec = {"case": case, "solver": solver, "theta_law": theta_law, "wall_s": wall, "failed": failed}
    if r is not None:
        rec.update({k: np.asarray(r[k], float).tolist() for k in ("t", "var1", "var2")})
        rec["t_end"] = float(np.asarray(r["t"], float)[-1])
        rec["t_max"] = float(p.set_dict["TMAX"])
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(rec, f)
    os.replace(tmp, out)
    print(json.dumps({k: v for k, v in rec.items() if k not in ("t", "var1", "var2")}))


def compare(own_path, rsf_path):
    import numpy as np
    from scipy.interpolate import interp1d

    own, rsf = (json.load(open(x)) for x in (own_path, rsf_path))

    def end(r):
        if "t" not in r:
            return f"stopped ({r['failed']})"
        return f"{r['t_end']:.4g} s of {r['t_max']:.4g} s in {r['wall_s']:.1f} s"

    dev = "-"
    ok = "t" in rsf and "t" in own and rsf["t_end"] >= own["t_end"] * (1 - 1e-9)
    if ok:
        t = np.asarray(own["t"], float)
        t = t[(t >= min(rsf["t"])) & (t <= max(rsf["t"]))]
        devs = []
        for v in ("var1", "var2"):
            ref = interp1d(own["t"], own[v])(t)
            got = interp1d(rsf["t"], rsf[v])(t)
            devs.append(float(np.max(np.abs(got - ref) / np.maximum(np.abs(ref), 1e-300))))
        dev = f"{devs[0]:.1e}, {devs[1]:.1e}"
        ok = max(devs) <= RTOL
    law = "" if own.get("theta_law") is None else f" (THETA_LAW {own['theta_law']})"
    print(f"| {own['case']}{law} | {own['solver']} | {end(own)} | {end(rsf)} | {dev} | {'same within rtol 1e-4' if ok else 'DIFFERENT'} |")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    if len(sys.argv) == 4 and sys.argv[1] == "--compare":
        compare(sys.argv[2], sys.argv[3])
    elif len(sys.argv) in (5, 6):
        run(sys.argv[1], sys.argv[2], int(sys.argv[3]), os.path.abspath(sys.argv[4]),
            int(sys.argv[5]) if len(sys.argv) == 6 else None)
    else:
        sys.exit(__doc__)
