"""rsf.design equals `rsf design`, and its ranking comes out as a DataFrame."""

import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import rsf

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLI = os.path.join(ROOT, "target", "release", "rsf")


def small_steps_record(path):
    """An Aging-law record of one 0.5-decade step with white noise 1e-3: the laws are not told
    apart yet (the record is made by rsf itself: this test compares two front ends, not physics)."""
    m = rsf.Model(mu0=0.6, v0=1.0, a=0.010, stiffness=0.01, states=[rsf.State("aging", b=0.013, dc=10.0)])
    p = rsf.Protocol(v_init=1.0, segments=[(1.0, {"duration": 60.0}), (10 ** 0.5, {"duration": 20.0})])
    s = rsf.simulate(m, p, dt=0.1, method="implicit", rtol=1e-11, atol=1e-14)
    mu = np.asarray(s.mu) + 1e-3 * np.random.default_rng(3).standard_normal(len(s.mu))
    with open(path, "w") as f:
        f.write("time_s,load_point_um,mu\n")
        for row in zip(s.time_s, s.load_point_um, mu):
            f.write("%.17g,%.17g,%.17g\n" % row)


def test_design_equals_the_cli_and_gives_a_dataframe():
    if not os.path.exists(CLI):
        pytest.skip("target/release/rsf not built (cargo build --release -p rsf-cli)")
    with tempfile.TemporaryDirectory() as d:
        rec = os.path.join(d, "r.csv")
        small_steps_record(rec)
        j = os.path.join(d, "g.json")
        subprocess.run([CLI, "design", rec, "--stiffness", "0.01", "--max-time", "3600", "--max-hold", "3000",
                        "--json", j], check=True, capture_output=True, text=True)
        ref = json.load(open(j))
        # a law registered earlier in this process (test_laws, test_batch) is a candidate of the
        # diagnosis and a rival of the design; the CLI knows none, so the comparison runs in a
        # fresh interpreter
        fj = os.path.join(d, "fresh.json")
        script = ("import json, sys, rsf; g = rsf.design(rsf.read_record(sys.argv[1]), stiffness=0.01, "
                  "max_time=3600, max_hold=3000, threads=1); json.dump(dict(g), open(sys.argv[2], 'w'))")
        subprocess.run([sys.executable, "-c", script, rec, fj], check=True, capture_output=True, text=True)
        fresh = json.load(open(fj))
        assert len(fresh["models"]) >= 2 and fresh["proposals"]
        assert [r["description"] for r in fresh["proposals"][:5]] == [r["description"] for r in ref["proposals"][:5]]
        assert fresh["proposals"][0]["score"] == pytest.approx(ref["proposals"][0]["score"], rel=1e-9)
        # the three standard segments of the same machine time, the best of them as `standard`
        kinds = [s["standard"] for s in fresh["standards"]]
        assert kinds == [s["standard"] for s in ref["standards"]] and "hold_reslide" in kinds
        assert fresh["standard"] in fresh["standards"]
        py = rsf.design(rsf.read_record(rec), stiffness=0.01, max_time=3600, max_hold=3000, threads=1)
        assert py["proposals"] and py["standards"]
        assert py.protocol.startswith("# rsf design: proposal 1")
        out = os.path.join(d, "next.toml")
        py.write_protocol(out)
        assert rsf.simulate(out).time_s[-1] == pytest.approx(py["proposals"][0]["machine_time_s"], rel=1e-2)
    pd = pytest.importorskip("pandas")
    df = py.to_pandas()
    assert isinstance(df, pd.DataFrame) and list(df["rank"][:3]) == [1, 2, 3]
    assert any(c.startswith("dchi2:") for c in df.columns)
    assert (df["effect_score"] >= 0).all()
    # the stick-slip screen: a peak slip rate per proposal, and those that run away rank last
    assert (df["peak_slip_rate"] > 0).all()
    flags = list(df["stick_slip"])
    assert flags == sorted(flags)


def test_design_from_a_diagnosis_and_with_normal_stress_changes():
    """rsf.design(diagnosis=...) designs from a diagnosis without diagnosing again, and ranks as
    the design that diagnoses; with max_sigma_change the α model is credible and σ changes come
    out in the ranking's normal_stress_ratio."""
    with tempfile.TemporaryDirectory() as d:
        rec = os.path.join(d, "r.csv")
        small_steps_record(rec)
        r = rsf.read_record(rec)
        opts = dict(stiffness=0.01, max_time=3600, max_hold=3000, threads=1)
        live = rsf.design(r, **opts)
        diag = rsf.diagnose(r, stiffness=0.01, threads=1)
        back = rsf.design(r, diagnosis=diag, **opts)
        assert [m["name"] for m in back["models"]] == [m["name"] for m in live["models"]]
        assert [p["description"] for p in back["proposals"][:3]] == [p["description"] for p in live["proposals"][:3]]
        assert back["proposals"][0]["score"] == pytest.approx(live["proposals"][0]["score"], rel=1e-2)
        path = os.path.join(d, "diag.json")
        with open(path, "w") as f:
            f.write(diag.to_json())
        again = rsf.design(r, diagnosis=path, **opts)
        assert again["proposals"][0]["description"] == back["proposals"][0]["description"]
        sig = rsf.design(r, diagnosis=diag, max_sigma_change=0.2, **opts)
        assert any(m["name"] == "normal_stress_coupling" for m in sig["models"])
        assert any(x != 1.0 for p in sig["proposals"] for x in p["normal_stress_ratio"])
        with pytest.raises(ValueError, match="baseline"):
            rsf.design(r, diagnosis=diag, baseline="aging", **opts)
