"""The cost of a law by the form it is written in, from Python: the Aging law built in, as a law
file (`aging_text.toml`) and as a Python function; simulate (the steps-and-hold protocol of
this folder) and fit (the first 420 s of tests/data/outside/power_aging.csv, velocity steps).
Prints the median of REPEATS runs of each, and the ratio to the built-in law.

    target/pyvenv/bin/python benches/laws/python_laws.py
"""

import os
import statistics
import time

import rsf

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..", "..")
REPEATS = 7


def aging_py(v, theta, dc, b, stress_rate):
    return 1.0 - v * theta / dc


def median_time(f):
    times = []
    for _ in range(REPEATS):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main():
    rsf.load_law(os.path.join(HERE, "aging_text.toml"))
    protocol = rsf.Protocol(v_init=1.0, segments=[(1.0, {"displacement": 50.0}), (10.0, {"displacement": 100.0}),
                                                  (1.0, {"displacement": 50.0}), (0.0, {"duration": 100.0}),
                                                  (1.0, {"displacement": 50.0})])
    rec = rsf.read_record(os.path.join(ROOT, "tests", "data", "outside", "power_aging.csv"))
    keep = rec["time_s"] <= 420.0
    cols = dict(time=rec["time_s"][keep], load_point=rec["load_point_um"][keep], mu=rec["mu"][keep])
    rows = []
    for label, law in (("built in", "aging"), ("law file", "aging-text"), ("Python function", aging_py)):
        for method in ("auto", "implicit"):
            model = rsf.Model(0.6, 1.0, 0.008, 0.02, [rsf.State(law, b=0.011, dc=5.0)])
            t = median_time(lambda: rsf.simulate(model, protocol, dt=0.05, method=method))
            rows.append((f"simulate ({method})", label, t))
        t = median_time(lambda: rsf.fit(stiffness=0.02, law=law, starts=1, threads=1, **cols))
        rows.append(("fit (1 start, 1 thread)", label, t))
    base = {what: t for what, label, t in rows if label == "built in"}
    print(f"{'what':<26} {'law':<16} {'median s':>10} {'× built in':>11}")
    for what, label, t in rows:
        print(f"{what:<26} {label:<16} {t:>10.4f} {t / base[what]:>11.2f}")


if __name__ == "__main__":
    main()
