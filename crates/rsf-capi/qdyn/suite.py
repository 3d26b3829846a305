"""QDYN's regression suite (its own test/test_suite.py, run unchanged) with a record of how far
each case is from QDYN's frozen results, and the results themselves for comparing two builds.

Usage: python suite.py QDYN_TEST_DIR OUT.json [--against OTHER.json]

QDYN's criterion (test/aux.py) is numpy's assert_allclose at rtol 1e-4 on the two variables of
each case, interpolated at the frozen times. This wrapper replaces nothing: it wraps the
suite's compare step to also keep, per case, the largest relative deviation from the frozen
run and the verdict, and saves each case's (t, var1, var2). With --against, each case is also
compared with the same case of another build (e.g. QDYN on its own friction) at the same
rtol, on the frozen times. Exit status: the suite's own.
"""

import json
import os
import runpy
import sys

import numpy as np


def rel_dev(ref, got):
    ref, got = np.asarray(ref, float), np.asarray(got, float)
    scale = np.maximum(np.abs(ref), 1e-300)
    return float(np.max(np.abs(got - ref) / scale))


def main():
    test_dir = os.path.abspath(sys.argv[1])
    out = os.path.abspath(sys.argv[2])
    against = None
    if len(sys.argv) > 4 and sys.argv[3] == "--against":
        with open(sys.argv[4]) as f:
            against = json.load(f)
    sys.path.insert(0, test_dir)
    os.chdir(test_dir)
    import aux  # QDYN's test helpers, from the checkout under test
    from scipy.interpolate import interp1d

    record = {}
    compare = aux.AuxiliaryFunctions.compare_results

    def recording(self, mode):
        compare(self, mode)
        if not self.frozen_loaded:
            return
        b, r = self.frozen_results[mode], self.test_results[mode]
        tb = np.asarray(b["t"], float)
        case = {"passed": bool(r["success"]), "t": np.asarray(r["t"], float).tolist()}
        for v in ("var1", "var2"):
            got = interp1d(r["t"], r[v])(tb)
            case["dev_" + v] = rel_dev(b[v], got)
            case[v] = np.asarray(r[v], float).tolist()
        record[f"{self.dirname}/{mode}"] = case

    aux.AuxiliaryFunctions.compare_results = recording
    code = 0
    crashed = None
    try:
        runpy.run_path(os.path.join(test_dir, "test_suite.py"), run_name="__main__")
    except SystemExit as e:
        code = int(e.code or 0)
    except Exception as e:  # a case that crashed: the cases before it are still reported
        code, crashed = 1, f"{type(e).__name__}: {e}"
        print(f"the suite stopped: {crashed}")
    summary = {}
    for name, case in record.items():
        s = {"passed": case["passed"], "dev_var1": case["dev_var1"], "dev_var2": case["dev_var2"]}
        if against is not None and name in against.get("cases", {}):
            o = against["cases"][name]
            t = np.asarray(o["t"], float)
            t = t[(t >= min(case["t"])) & (t <= max(case["t"]))]
            for v in ("var1", "var2"):
                s["vs_other_" + v] = rel_dev(interp1d(o["t"], o[v])(t), interp1d(case["t"], case[v])(t))
        summary[name] = s
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        json.dump({"exit": code, "crashed": crashed, "summary": summary, "cases": record}, f)
    os.replace(tmp, out)
    print("per case: QDYN's verdict, largest relative deviation from the frozen run (var1, var2)"
          + (", and from the other build" if against is not None else ""))
    for name, s in summary.items():
        line = f"  {name:22s} {'ok    ' if s['passed'] else 'FAILED'} frozen {s['dev_var1']:.2e} {s['dev_var2']:.2e}"
        if "vs_other_var1" in s:
            line += f"   other build {s['vs_other_var1']:.2e} {s['vs_other_var2']:.2e}"
        print(line)
    passed = sum(1 for s in summary.values() if s["passed"])
    print(f"cases: {passed} of {len(summary)} pass QDYN's criterion against its frozen results"
          + (f"; the suite stopped: {crashed}" if crashed else ""))
    sys.exit(code)


if __name__ == "__main__":
    main()
