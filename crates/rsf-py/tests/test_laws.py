"""A researcher's law from Python: a law file and a Python function, registered once and then
used by simulate, fit (its own parameter fitted) and diagnose; the CLI agrees on the file."""

import json
import math
import os
import subprocess

import numpy as np
import pytest

import rsf

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLI = os.path.join(ROOT, "target", "release", "rsf")
POWER_FILE = os.path.join(ROOT, "examples", "laws", "power_aging.toml")
# power-law aging, n = 1.5, from the independent generator (tests/data/outside/SOURCE.md)
POWER_RECORD = os.path.join(ROOT, "tests", "data", "outside", "power_aging.csv")


def steps(law, params=None):
    m = rsf.Model(mu0=0.6, v0=1.0, a=0.008, stiffness=0.02,
                  states=[rsf.State(law=law, b=0.011, dc=5.0, params=params)])
    p = rsf.Protocol(v_init=1.0, segments=[(10.0, {"displacement": 100.0}), (1.0, {"displacement": 50.0}),
                                           (0.0, {"duration": 100.0}), (1.0, {"displacement": 50.0})])
    return rsf.simulate(m, p, dt=0.1, method="implicit")


def test_a_law_file_is_used_by_name_and_fits_its_own_parameter(tmp_path):
    assert rsf.load_law(POWER_FILE) == "power-aging"
    assert "power-aging" in rsf.laws() and "power-aging" not in rsf.LAWS
    # n = 1 is the Aging law
    a, p1 = steps("aging"), steps("power-aging", {"n": 1.0})
    assert np.max(np.abs(a.mu - p1.mu)) < 1e-8
    assert np.max(np.abs(steps("power-aging", {"n": 1.5}).mu - a.mu)) > 1e-4
    rec = rsf.read_record(POWER_RECORD)
    f = rsf.fit(rec, stiffness=0.02, law="power-aging")
    n = f.params["law_params"]["n1"]
    assert abs(n - 1.5) < 0.005, n
    # the CLI, with the same file, fits the same n
    if os.path.exists(CLI):
        out = tmp_path / "fit.json"
        subprocess.run([CLI, "--law-file", POWER_FILE, "fit", POWER_RECORD, "--law", "power-aging",
                        "--stiffness", "0.02", "--loading", "protocol", "--json", str(out)], check=True, capture_output=True, text=True)
        cli_n = json.loads(out.read_text())["params"]["law_params"]["n1"]
        assert abs(cli_n - n) <= 1e-9 * n


def test_the_diagnosis_names_a_registered_law():
    rsf.load_law(POWER_FILE)
    d = rsf.diagnose(rsf.read_record(POWER_RECORD), stiffness=0.02)
    assert d.cause == "evolution_law", d.cause
    assert d.effect["law"] == "power-aging" and abs(d.effect["n"] - 1.5) < 0.01, d.effect


def power_aging(v, theta, dc, b, stress_rate, n):
    # float ** raises OverflowError far out; an explicit trial stage may go there and be rejected
    return 1.0 - (v * theta / dc) ** n


def test_a_python_function_with_a_parameter_fits_it():
    name = rsf.register_law("power-aging-py", power_aging, parameters={"n": {"range": (0.2, 5.0), "start": 1.0}},
                            candidate=False)
    assert name in rsf.laws()
    # the same law as the file, to the solver's tolerance
    rsf.load_law(POWER_FILE)
    py, txt = steps(power_aging, {"n": 1.5}), steps("power-aging", {"n": 1.5})
    assert np.max(np.abs(py.mu - txt.mu)) < 1e-7
    rec = rsf.read_record(POWER_RECORD)
    keep = rec["time_s"] <= 420.0  # the velocity steps: the slow path costs ~1 µs a call
    f = rsf.fit(time=rec["time_s"][keep], load_point=rec["load_point_um"][keep], mu=rec["mu"][keep], stiffness=0.02,
                law=power_aging, starts=1)
    n = f.params["law_params"]["n1"]
    assert abs(n - 1.5) < 0.02, n


def aging_by_hand(v, theta, dc, b, stress_rate):
    return 1.0 - v * theta / dc


def test_fit_takes_a_function_without_parameters():
    rec = rsf.read_record(POWER_RECORD)
    keep = rec["time_s"] <= 420.0
    cols = dict(time=rec["time_s"][keep], load_point=rec["load_point_um"][keep], mu=rec["mu"][keep])
    f = rsf.fit(stiffness=0.02, law=aging_by_hand, starts=1, **cols)
    g = rsf.fit(stiffness=0.02, law="aging", starts=1, **cols)
    assert f.params["laws"] == ["aging-by-hand"]
    assert abs(f.params["b"][0] - g.params["b"][0]) < 1e-5 * abs(g.params["b"][0])


def test_an_exception_in_a_rejected_trial_stage_is_not_raised():
    # a law that raises once, as a float power overflows in an explicit method's trial stage
    # far out (V ~ 1e237): the solver rejects that step and goes on; the answer is the Aging
    # law's, and the exception is not raised after a solve that succeeded
    calls = [0]

    def aging_raising_once(v, th, dc, b, sr):
        calls[0] += 1
        if calls[0] == 200:
            raise OverflowError("(34, 'Numerical result out of range')")
        return 1.0 - v * th / dc

    p = rsf.Protocol(v_init=1.0, segments=[(10.0, {"displacement": 100.0}), (1.0, {"displacement": 50.0})])
    state = dict(b=0.011, dc=5.0)
    model = lambda law: rsf.Model(mu0=0.6, v0=1.0, a=0.008, stiffness=0.02, states=[rsf.State(law=law, **state)])
    out, ref = rsf.simulate(model(aging_raising_once), p, dt=1.0), rsf.simulate(model("aging"), p, dt=1.0)
    assert calls[0] > 200 and np.max(np.abs(out.mu - ref.mu)) < 1e-8
    # an exception on every call fails the solve, and that exception is what is raised
    def broken(v, th, dc, b, sr):
        raise ZeroDivisionError("the law's own bug")
    with pytest.raises(ZeroDivisionError, match="own bug"):
        rsf.simulate(model(broken), p, dt=1.0)


def test_bad_laws_say_what_is_wrong(tmp_path):
    with pytest.raises(ValueError, match="unknown law `nope`"):
        rsf.fit(rsf.read_record(POWER_RECORD), stiffness=0.02, law="nope")
    with pytest.raises(ValueError, match="built-in"):
        rsf.register_law("slip", aging_by_hand)
    bad = tmp_path / "bad_law.toml"
    bad.write_text('name = "bad"\ntheta_rate = "1 - omega^m"\n')
    with pytest.raises(ValueError, match=r"bad_law.toml:2:25: unknown name `m`"):
        rsf.load_law(bad)


def test_a_python_law_that_names_sigma_gets_the_normal_stress():
    seen = set()

    def sigma_aging(v, theta, dc, b, stress_rate, sigma=None, sigma_rate=None):
        seen.add(round(sigma, 9))
        return 1.0 - v * theta / dc

    m = rsf.Model(mu0=0.6, v0=1.0, a=0.008, stiffness=0.02, normal_stress=10.0,
                  states=[rsf.State(law=sigma_aging, b=0.011, dc=5.0)])
    p = rsf.Protocol(v_init=1.0, segments=[(1.0, {"displacement": 20.0}),
                                           (1.0, {"displacement": 20.0, "normal_stress": 12.0})])
    out = rsf.simulate(m, p, dt=0.5)
    # 10 and 12 MPa along the protocol (and 1, where the steady state is solved: docs/laws.md)
    assert np.all(np.isfinite(out.mu)) and {10.0, 12.0} <= seen <= {1.0, 10.0, 12.0}, seen


def test_function_names_and_parameter_names_are_made_safe():
    # a lambda, a name rsf has built in, two closures of one name: each its own law
    lam = lambda v, th, dc, b, sr: 1.0 - v * th / dc  # noqa: E731

    def aging(v, th, dc, b, sr):
        return 1.0 - v * th / dc

    def make(k):
        def scaled(v, th, dc, b, sr):
            return k * (1.0 - v * th / dc)
        return scaled

    rec = rsf.read_record(POWER_RECORD)
    keep = rec["time_s"] <= 100.0
    cols = dict(time=rec["time_s"][keep], load_point=rec["load_point_um"][keep], mu=rec["mu"][keep])
    names = [rsf.fit(stiffness=0.02, law=f, starts=1, **cols).params["laws"][0]
             for f in (lam, aging, make(1.0), make(2.0))]
    assert names[0] == "lambda" and names[1] == "aging-2" and names[2] != names[3], names
    # a parameter named like a model parameter cannot be fitted by name: refused when registered
    with pytest.raises(ValueError, match="parameter name `alpha`"):
        rsf.register_law("bad-param", power_aging, parameters={"alpha": {"range": (0.2, 5.0), "start": 1.0}})
    # a law's own parameter given twice is an error, not a TypeError
    m = rsf.Model(mu0=0.6, v0=1.0, a=0.008, stiffness=0.02,
                  states=[rsf.State(law="nagata", b=0.011, dc=5.0, c=1.0, params={"c": 2.0})])
    with pytest.raises(ValueError, match="given twice"):
        rsf.simulate(m, rsf.Protocol(v_init=1.0, segments=[(1.0, {"displacement": 10.0})]), dt=1.0)


def test_load_protocol_keeps_a_laws_own_parameters():
    setup = rsf.load_protocol(os.path.join(ROOT, "examples", "power_aging_steps.toml"))
    assert setup.model.states[0].params == {"n": 1.5}
    out = rsf.simulate(setup)
    ref = rsf.simulate(os.path.join(ROOT, "examples", "power_aging_steps.toml"))
    assert np.array_equal(out.mu, ref.mu)


BLEND = """name = "blend-py"
words = "power-law aging blended with the Slip law"
theta_rate = "w*(1 - omega^n) - (1 - w)*omega*ln(omega)"

[[parameter]]
name = "n"
range = [0.2, 5.0]
start = 1.0

[[parameter]]
name = "w"
range = [0.0, 1.0]
start = 0.5
"""


def test_a_law_with_two_parameters_has_both_fitted_and_is_a_baseline(tmp_path):
    # issue 39: every own parameter is fitted (on the main before it, only the first: w stayed
    # at its start) and a diagnosis takes any registered law as its baseline
    path = tmp_path / "blend.toml"
    path.write_text(BLEND)
    assert rsf.load_law(str(path)) == "blend-py"
    m = rsf.Model(mu0=0.6, v0=1.0, a=0.010, stiffness=0.01,
                  states=[rsf.State(law="blend-py", b=0.014, dc=10.0, params={"n": 1.6, "w": 0.7})])
    p = rsf.Protocol(v_init=1.0, segments=[(1.0, {"duration": 80.0}), (10.0, {"duration": 20.0}),
                                           (1.0, {"duration": 120.0}), (0.0, {"duration": 30.0}),
                                           (1.0, {"duration": 100.0}), (0.0, {"duration": 300.0}),
                                           (1.0, {"duration": 120.0})])
    s = rsf.simulate(m, p, dt=0.1, method="implicit")
    mu = s.mu + np.random.default_rng(3).normal(0.0, 2e-4, s.mu.size)
    f = rsf.fit(time=s.time_s, load_point=s.load_point_um, mu=mu, stiffness=0.01, law="blend-py")
    lp = f.params["law_params"]
    for name, truth in (("n1", 1.6), ("w1", 0.7)):
        assert name in f.stderr, f.stderr
        assert abs(lp[name] - truth) < 4 * max(f.stderr[name], 1e-3), (name, lp[name], f.stderr[name])
    d = rsf.diagnose(time=s.time_s, load_point=s.load_point_um, mu=mu, stiffness=0.01, baseline="blend-py")
    assert d.cause == "none", d.cause


def test_check_law_runs_the_kit_on_files_names_and_functions():
    # issue 39: the conformance kit for text and Python laws, from Python as from `rsf check-law`
    rep = rsf.check_law(POWER_FILE, cases=32, steady_state_dc_over_v=True)
    assert "parameter_derivative: passed" in rep, rep
    name = rsf.register_law("power-aging-kit", power_aging, parameters={"n": {"range": (0.2, 5.0), "start": 1.0}},
                            candidate=False)
    rep = rsf.check_law(name, cases=16, steady_state_dc_over_v=True)
    for prop in ("jacobian: passed", "parameter_round_trip: passed", "integrators_agree: passed"):
        assert prop in rep, rep

    def off_by_a_tenth(v, theta, dc, b, stress_rate):
        return 1.1 - v * theta / dc

    with pytest.raises(ValueError, match="steady_state"):
        rsf.check_law(off_by_a_tenth, cases=16, steady_state_dc_over_v=True)


def test_a_fit_says_whether_it_converged():
    # issue 40: `converged` and `starts_failed` in the result; a fit that did not converge
    # warns and is marked, its numbers still the best point found
    rsf.load_law(POWER_FILE)
    rec = rsf.read_record(POWER_RECORD)
    f = rsf.fit(rec, stiffness=0.02, law="power-aging")
    assert f.converged is True and f.starts_failed >= 0, (f.converged, f.starts_failed)
    assert abs(f.params["law_params"]["n1"] - 1.5) < 0.005
    with pytest.warns(RuntimeWarning, match="did not converge"):
        g = rsf.fit(rec, stiffness=0.02, law="power-aging", max_iter=2, starts=1)
    assert g.converged is False and g.stop_reason == "iteration limit"
