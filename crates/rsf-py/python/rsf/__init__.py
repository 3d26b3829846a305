"""rsf: rate-and-state friction from Python, with the Rust crates inside.

numpy arrays in and out. Units as everywhere in rsf: µm, s, µm/s, 1/µm, MPa.

>>> import rsf
>>> model = rsf.Model(mu0=0.6, v0=1.0, a=0.01, stiffness=1e-3, states=[rsf.State("slip", b=0.015, dc=10.0)])
>>> step = rsf.Protocol(v_init=1.0, segments=[(10.0, {"displacement": 200.0})])
>>> out = rsf.simulate(model, step, dt=0.1)                     # out.mu, out.time_s, …
>>> same = rsf.simulate(rsf.load_protocol("examples/step_down.toml"))   # = rsf simulate FILE
>>> rec = rsf.read_record("examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt",
...                       time_col="Time(s)", lp_col="Displ(microns)", mu_col="Friction")
>>> fit = rsf.fit(rec, law="slip", stiffness=0.0151, fit_stiffness=True)
>>> fit.params["a"], fit.ci95["a"]
>>> d = rsf.diagnose(rec, stiffness=0.0151); d.cause; d.write_report("basalt.html")

Results are dicts of the CLI's JSON (``rsf fit --json``, ``rsf diagnose --json``) with
attribute access; solves, fits and diagnoses release the GIL; Ctrl-C stops a fit or a
diagnosis within one model evaluation. Errors: ``ValueError`` with the CLI's message, and
``rsf.SolveError`` (a ValueError) when a forward solve fails, with ``time``, ``slip_rate`` and
``mu`` attributes.
"""

from __future__ import annotations

import dataclasses
import json
import math
import os
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np

from . import _rsf

SolveError = _rsf.SolveError

from .batch import diagnose_many, fit_many  # noqa: E402  (many records; Dask)

__all__ = [
    "State", "Model", "Protocol", "Setup", "load_protocol", "simulate", "read_record", "fit",
    "diagnose", "SimulationResult", "FitResult", "Diagnosis", "SolveError", "LAWS", "fit_many",
    "diagnose_many", "design", "Design", "load_law", "register_law", "laws", "check_law",
]

#: Built-in state laws by name.
LAWS = tuple(_rsf.LAW_NAMES)  # the built-in laws, from Rust's registry

ThetaRate = Callable[..., float]


def load_law(path: Union[str, os.PathLike]) -> str:
    """Registers the law of a law file (TOML: its rate as an expression of ``v``, ``theta``,
    ``dc``, ``b``, ``tau_rate``, ``sigma``, ``sigma_rate``, ``omega`` and its own parameters;
    docs/laws.md) and returns its name, usable at once by :func:`simulate` (``State(law=name,
    params={...})``), :func:`fit` (its parameters fitted), :func:`diagnose` (a candidate law) and
    :func:`design`. Loading an edited file again replaces the law."""
    return _rsf.register_law_file(os.fspath(path))


def register_law(name: str, theta_rate: ThetaRate, parameters: Optional[Mapping[str, Mapping[str, Any]]] = None,
                 words: Optional[str] = None, candidate: bool = True) -> str:
    """Registers a Python function ``theta_rate(v, theta, dc, b, stress_rate, *params) -> dθ/dt``
    as law ``name`` (lower case, digits and ``-``); a function whose signature names ``sigma``
    is also given ``sigma`` (MPa) and ``sigma_rate`` (MPa/s) by keyword. ``parameters`` maps each own parameter, in
    the order the function takes them, to ``{"range": (lo, hi), "start": x}`` and optionally
    ``"unit"`` and ``"log"``. The law is then used by name everywhere, like a law file's.

    With ``candidate`` (default) every later :func:`diagnose` of the session tries it as the
    evolution law. The slow path: about 1 µs per call and derivatives by central differences (a
    law file is evaluated in Rust with exact derivatives; docs/BENCHMARKS.md has both costs)."""
    specs = []
    for pname, spec in (parameters or {}).items():
        lo, hi = spec["range"]
        specs.append((pname, spec.get("unit", ""), float(lo), float(hi), bool(spec.get("log", False)),
                      float(spec["start"])))
    name = _rsf.register_py_law(name, theta_rate, words or name, specs, candidate=candidate)
    _FUNCTION_LAWS[theta_rate] = name
    return name


def check_law(law: Union[str, os.PathLike, ThetaRate], cases: Optional[int] = None,
              steady_state_dc_over_v: bool = False) -> str:
    """Runs rsf's conformance kit on a law — a registered law's name, a law file (``.toml``)
    or a Python function (registered as :func:`fit` does, when it is not yet) — as ``rsf
    check-law`` does, and returns the report (each property: passed on how many inputs, or
    skipped and why). A property that fails raises ``ValueError`` naming it, why, and the
    smallest input found. ``steady_state_dc_over_v`` claims θ_ss = Dc/V; ``cases`` is the
    number of inputs per property (default 256). A Python function's derivatives are central
    differences: its ``jacobian`` is checked against the kit's own central differences; its
    parameters are taken at their starts, and a parameter whose ``unit`` is ``"µm/s"`` or
    ``"µm"`` is rescaled with time and length."""
    if isinstance(law, os.PathLike):
        law = os.fspath(law)
    return _rsf.check_law(_law_name(law), cases, steady_state_dc_over_v)


def laws() -> list:
    """The names of every registered law: the built-in ones (:data:`LAWS`), then those loaded
    by :func:`load_law` or :func:`register_law`."""
    return list(_rsf.law_names())


_FUNCTION_LAWS: dict = {}  # function → the name it was registered under


def _law_name(law: Union[str, ThetaRate]) -> str:
    """A law given by name, or a Python function: the name it was registered under, or else
    registered (without parameters of its own, and not as a candidate of later diagnoses) under
    its ``__name__`` made a law name (``my_law`` → ``my-law``, a lambda → ``lambda``), with
    ``-2``, ``-3``… when another law has that name."""
    if isinstance(law, str):
        return law
    if callable(law):
        if law in _FUNCTION_LAWS:
            return _FUNCTION_LAWS[law]
        raw = getattr(law, "__name__", "")
        base = "".join(c if c.isascii() and c.isalnum() else "-" for c in raw.lower()).strip("-")
        base = "-".join(x for x in base.split("-") if x)
        if not base or not base[0].isalpha():
            base = "python-law"
        taken = set(laws())
        name, i = base, 1
        while name in taken:
            i += 1
            name = f"{base}-{i}"
        name = _rsf.register_py_law(name, law, name, [], candidate=False)
        _FUNCTION_LAWS[law] = name
        return name
    raise TypeError(f"law must be a name or a function theta_rate(v, theta, dc, b, stress_rate), not {law!r}")


# ---------------------------------------------------------------------------- model objects

@dataclass
class State:
    """One state variable: its evolution ``law`` (a registered name — see :func:`laws` — or a
    Python callable ``theta_rate(v, theta, dc, b, stress_rate) -> dθ/dt``), ``b``, ``dc`` (µm),
    the law's own parameters (``vc`` µm/s for Kato–Tullis, ``c`` for Nagata, or any by name in
    ``params``, e.g. ``{"n": 1.5}`` for a law file's) and the Linker–Dieterich ``alpha``.

    A Python law is the slow path: about 1 µs per call, one call per state per right-hand side,
    derivatives for implicit methods by central differences.
    """
    law: Union[str, ThetaRate]
    b: float
    dc: float
    vc: Optional[float] = None
    c: Optional[float] = None
    alpha: float = 0.0
    params: Optional[dict] = None


@dataclass
class Model:
    """A rate-and-state model on a spring: ``mu0``, ``v0`` (µm/s), ``a``, ``stiffness`` k
    (1/µm; ``math.inf`` imposes V = V_lp), the ``states``, radiation damping ``eta`` (friction
    per µm/s), ``form`` (``"classic"`` or ``"regularized"``), ``normal_stress`` σ_ref (MPa) and
    ``a_slope`` a₁, a direct effect that varies with the slip rate: ∂f/∂ln V = a + a₁ ln(V/V0)
    (classic form, no radiation damping; ``rsf.fit(..., fit_a_slope=True)`` fits it).
    """
    mu0: float
    v0: float
    a: float
    stiffness: float
    states: list = field(default_factory=list)
    eta: float = 0.0
    form: str = "classic"
    normal_stress: Optional[float] = None
    a_slope: float = 0.0


@dataclass
class Protocol:
    """The loading: steady state at ``v_init`` (µm/s), then ``segments`` — each ``(v, spec)``
    with ``spec`` a dict holding ``duration`` (s) or ``displacement`` (µm), and optionally
    ``normal_stress`` (MPa, a step at the segment's start) and ``normal_stress_rate`` (MPa/s) —
    or a measured ``record`` (a file path; ``time_column``, ``load_point_column``,
    ``friction_column``, ``normal_stress_column``).
    """
    v_init: float
    segments: list = field(default_factory=list)
    record: Optional[str] = None
    time_column: Optional[str] = None
    load_point_column: Optional[str] = None
    friction_column: Optional[str] = None
    normal_stress_column: Optional[str] = None


@dataclass
class Setup:
    """Everything a protocol file holds: ``model``, ``protocol``, ``output`` (``dt``,
    ``peak_slip_rate``, ``event_slip_rate``), ``solver`` (``method``, ``rtol``, ``atol``,
    ``max_slip_rate``) and ``initial`` (``v``, ``theta``). ``rsf.simulate(setup)`` gives exactly
    what ``rsf simulate FILE`` writes.
    """
    model: Model
    protocol: Protocol
    output: dict = field(default_factory=dict)
    solver: dict = field(default_factory=dict)
    initial: Optional[dict] = None
    source: str = ""


def _fields(**kw: Any) -> dict:
    """The fields given (``None``: not given)."""
    return {k: v for k, v in kw.items() if v is not None}


def _to_spec(setup: Setup) -> dict:
    """The setup as the protocol file's tables (dicts and lists of plain values), which Rust
    checks by the file's rules (``rsf_solvers::protocol::from_table``) — no text between."""
    m, p = setup.model, setup.protocol
    states = []
    for s in m.states:
        law = s.law if isinstance(s.law, str) else "aging"  # placeholder for a Python law
        fields = _fields(law=law, b=s.b, dc=s.dc, vc=s.vc, c=s.c, alpha=s.alpha or None)
        for k, v in (s.params or {}).items():
            if k in fields:
                raise ValueError(f"state parameter `{k}` given twice (as a field and in params)")
            fields[k] = v
        states.append(fields)
    segments = []
    for seg in p.segments:
        v, spec = (seg["v"], {k: x for k, x in seg.items() if k != "v"}) if isinstance(seg, Mapping) else seg
        segments.append(_fields(v=v, **spec))
    spec = dict(
        model=_fields(mu0=m.mu0, v0=m.v0, a=m.a, stiffness=m.stiffness, eta=m.eta,
                      a_slope=m.a_slope or None, form=m.form, normal_stress=m.normal_stress, state=states),
        loading=_fields(v_init=p.v_init, segment=segments or None, record=p.record, time_column=p.time_column,
                        load_point_column=p.load_point_column, friction_column=p.friction_column,
                        normal_stress_column=p.normal_stress_column))
    for key, table in (("output", setup.output), ("solver", setup.solver), ("initial", setup.initial)):
        if table:
            spec[key] = _fields(**table)
    return spec


def load_protocol(path: Union[str, os.PathLike]) -> Setup:
    """Reads a protocol file (checked exactly as ``rsf simulate`` checks it) into a
    :class:`Setup` of Python objects; a measured record's path becomes absolute."""
    path = os.fspath(path)
    with open(path, encoding="utf-8") as f:
        text = f.read()
    base = os.path.dirname(os.path.abspath(path))
    raw = json.loads(_rsf.protocol_json(text, base, path))
    rm = raw["model"]
    own = lambda s: {k: v for k, v in s.items() if k not in ("law", "b", "dc", "vc", "c", "alpha")} or None
    states = [State(law=s["law"], b=s["b"], dc=s["dc"], vc=s.get("vc"), c=s.get("c"), alpha=s.get("alpha", 0.0),
                    params=own(s))
              for s in rm.get("state", [])]
    model = Model(mu0=rm["mu0"], v0=rm["v0"], a=rm["a"], stiffness=rm["stiffness"], states=states,
                  eta=rm.get("eta", 0.0), form=rm.get("form", "classic"), normal_stress=rm.get("normal_stress"),
                  a_slope=rm.get("a_slope", 0.0))
    rl = raw["loading"]
    record = rl.get("record")
    if record is not None and not os.path.isabs(record):
        record = os.path.join(base, record)
    segments = [(s["v"], {k: x for k, x in s.items() if k != "v"}) for s in rl.get("segment", [])]
    protocol = Protocol(v_init=rl["v_init"], segments=segments, record=record, time_column=rl.get("time_column"),
                        load_point_column=rl.get("load_point_column"), friction_column=rl.get("friction_column"),
                        normal_stress_column=rl.get("normal_stress_column"))
    return Setup(model=model, protocol=protocol, output=raw.get("output", {}), solver=raw.get("solver", {}),
                 initial=raw.get("initial"), source=path)


# ---------------------------------------------------------------------------- results

class _AttrDict(dict):
    """A dict whose keys read as attributes too."""

    def __getattr__(self, name: str) -> Any:
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None


class SimulationResult(_AttrDict):
    """Columns of a solution as numpy arrays: ``time_s``, ``load_point_um``, ``mu``,
    ``slip_rate_um_s``, ``slip_um``, ``theta_s`` (rows × state variables), and
    ``peak_slip_rate_um_s`` / ``normal_stress_mpa`` when present; ``method``, ``steps``."""

    def to_pandas(self):
        """The columns as a pandas DataFrame (``theta_1_s``, ``theta_2_s``, … for θ)."""
        import pandas as pd  # optional dependency
        cols = {k: v for k, v in self.items() if isinstance(v, np.ndarray) and v.ndim == 1}
        theta = self["theta_s"]
        for i in range(theta.shape[1]):
            cols[f"theta_{i + 1}_s"] = theta[:, i]
        return pd.DataFrame(cols)


class FitResult(_AttrDict):
    """A fit: the dict of ``rsf fit --json`` (``params``, ``ci95``, ``stderr``, ``rms``, ``aic``,
    ``bic``, ``segments``, …) plus ``curve`` (numpy arrays ``time``, ``load_point``, ``data``,
    ``model``, ``slip_rate`` at the used samples) and ``samples`` (MCMC draws, rows ×
    ``sample_names``)."""

    def __init__(self, raw: Mapping[str, Any], samples: Sequence, names: Sequence[str],
                 curve: Sequence = ()):
        super().__init__(raw)
        self["curve"] = _AttrDict({k: np.asarray(v, dtype=np.float64) for k, v in curve})
        self["samples"] = np.asarray(samples, dtype=np.float64).reshape(len(samples), len(names))
        self["sample_names"] = list(names)

    def to_json(self, indent: Optional[int] = 2) -> str:
        """The fit as the JSON ``rsf fit --json`` writes (numpy arrays as lists, no samples)."""
        out = {k: v for k, v in self.items() if k not in ("samples", "sample_names", "curve")}
        return json.dumps(out, indent=indent, default=lambda a: a.tolist())


class Diagnosis(_AttrDict):
    """A diagnosis: the dict of ``rsf diagnose --json`` (``cause``, ``gain``, ``candidates``,
    ``evidence``, …)."""

    def __init__(self, raw: Mapping[str, Any], html: str):
        super().__init__(raw)
        self._html = html

    def write_report(self, path: Union[str, os.PathLike]) -> None:
        """Writes the self-contained HTML report (``rsf diagnose --report``), as the CLI writes
        its outputs: into a temporary file beside ``path``, renamed over it when complete."""
        _write_atomic(os.fspath(path), self._html)

    def to_json(self, indent: Optional[int] = 2) -> str:
        return json.dumps(dict(self), indent=indent)


class Design(_AttrDict):
    """A design: the dict of ``rsf design --json`` (``summary``, ``models``, ``proposals`` best
    first, each with its ``effect`` — the named effect's parameters with their standard errors
    now and expected after it — when the cause has parameters of its own; ``standards``, the
    lab's standard segments of the best proposal's machine time within the same limits (a hold
    and reslide, a decade down and back, a decade up and back), and ``standard``, the best of
    them; ``curves``, ``noise``, ``notes``); ``to_pandas()`` gives the ranking as a DataFrame,
    ``protocol`` the best proposal as ``rsf simulate`` TOML."""

    def __init__(self, raw: Mapping[str, Any], html: str, protocol: str):
        super().__init__(raw)
        self._html = html
        self.protocol = protocol

    def to_pandas(self):
        """The ranking as a pandas DataFrame, one row per proposal, best first: ``rank``,
        ``kind``, ``description``, ``machine_time_s``, ``slip_um``, ``samples``, ``score``,
        ``score_per_hour``, ``lead_pair_dchi2``, ``peak_slip_rate`` (µm/s, the fastest a credible
        model slips in it), ``stick_slip`` (a model runs away in it: ranked last),
        ``effect_score`` (the part of the score for measuring the named effect; 0 without one)
        and one ``dchi2:A|B`` column per model pair."""
        import pandas as pd  # optional dependency
        rows = []
        for r in self["proposals"]:
            row = {k: r[k] for k in ("rank", "kind", "description", "machine_time_s", "slip_um", "samples",
                                     "score", "score_per_hour", "lead_pair_dchi2", "peak_slip_rate",
                                     "stick_slip")}
            row["effect_score"] = (r.get("effect") or {}).get("score", 0.0)
            row.update({f"dchi2:{p['a']}|{p['b']}": p["dchi2"] for p in r["pairs"]})
            rows.append(row)
        return pd.DataFrame(rows)

    def write_report(self, path: Union[str, os.PathLike]) -> None:
        """Writes the HTML page (``rsf design --report``) atomically."""
        _write_atomic(os.fspath(path), self._html)

    def write_protocol(self, path: Union[str, os.PathLike]) -> None:
        """Writes the best proposal as a TOML protocol (``rsf design --protocol``) atomically."""
        if not self.protocol:
            raise ValueError("there is no proposal to write: " + self["summary"])
        _write_atomic(os.fspath(path), self.protocol)

    def to_json(self, indent: Optional[int] = 2) -> str:
        return json.dumps(dict(self), indent=indent)


# ---------------------------------------------------------------------------- functions

def simulate(model: Union[Model, Setup, str, os.PathLike], protocol: Optional[Protocol] = None, *,
             dt: Optional[float] = None, method: Optional[str] = None, rtol: Optional[float] = None,
             atol: Optional[float] = None, time=None, load_point=None) -> SimulationResult:
    """Solves a forward problem: ``simulate(model, protocol, dt=…)``, ``simulate(setup)`` (from
    :func:`load_protocol`), or ``simulate(path_or_toml_text)`` — exactly as ``rsf simulate``.

    ``method``: ``"auto"`` (default), ``"vern6"``, ``"tsit5"``, ``"dopri5"``, ``"rodas5p"``, ``"rodas4"``,
    ``"explicit"``, ``"implicit"``. With ``time`` (s) and ``load_point`` (µm) arrays a measured
    load point drives the model (piecewise linear) with output at ``time``.
    Raises ValueError (bad input, the CLI's message) or :class:`SolveError` (a failed solve).
    """
    arrays = {}
    if time is not None or load_point is not None:
        arrays = dict(time=None if time is None else np.ascontiguousarray(time, dtype=np.float64),
                      load_point=None if load_point is None else np.ascontiguousarray(load_point, dtype=np.float64))
    if isinstance(model, (str, os.PathLike)):
        text = os.fspath(model)
        if "\n" not in text and os.path.exists(text):
            if protocol is None and dt is None and method is None and rtol is None and atol is None:
                with open(text, encoding="utf-8") as f:
                    body = f.read()
                base = os.path.dirname(os.path.abspath(text))
                return SimulationResult(_rsf.simulate_toml(body, base, text, **arrays))
            model = load_protocol(text)
        else:
            return SimulationResult(_rsf.simulate_toml(text, None, "protocol.toml", **arrays))
    if isinstance(model, Setup):
        setup = Setup(model.model, protocol or model.protocol, dict(model.output), dict(model.solver),
                      model.initial, model.source)
    elif isinstance(model, Model):
        if protocol is None:
            raise ValueError("simulate(model, protocol): give the protocol")
        setup = Setup(model, protocol, {}, {}, None)
    else:
        raise TypeError(f"simulate: expected a Model, a Setup or a protocol path, got {type(model).__name__}")
    if dt is not None:
        setup.output["dt"] = dt
    elif "dt" not in setup.output and setup.protocol.record is None and "time" not in arrays:
        raise ValueError("simulate: give dt (s), the output sampling interval")
    for k, v in (("method", method), ("rtol", rtol), ("atol", atol)):
        if v is not None:
            setup.solver[k] = v
    for s in setup.model.states:
        if not isinstance(s.law, str) and not callable(s.law):
            raise ValueError(f"state law {s.law!r}: give a name ({', '.join(laws())}) or a callable")
        if callable(s.law) and s.params:
            if s.law not in _FUNCTION_LAWS:
                raise ValueError("a Python law with parameters of its own: register it with rsf.register_law(name, "
                                 "function, parameters={...}), then give the function or its name")
    # registered functions go by name (with their parameters); others as the solve's own callables
    named = [s.law if isinstance(s.law, str) else _FUNCTION_LAWS.get(s.law) for s in setup.model.states]
    laws_ = [None if n is not None else s.law for n, s in zip(named, setup.model.states)]
    states = [State(n, s.b, s.dc, s.vc, s.c, s.alpha, s.params) if n is not None else s
              for n, s in zip(named, setup.model.states)]
    setup = Setup(dataclasses.replace(setup.model, states=states),
                  setup.protocol, setup.output, setup.solver, setup.initial, setup.source)
    base = os.path.dirname(os.path.abspath(setup.source)) if setup.source else None
    return SimulationResult(_rsf.simulate_spec(_to_spec(setup), base, setup.source or "Python objects", laws=laws_,
                                               **arrays))


def _write_atomic(path: str, text: str) -> None:
    """Writes ``text`` to ``path`` through a temporary file in the same folder, renamed over
    ``path`` only when complete: an interrupted write leaves the old file, never a mix."""
    import tempfile
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".rsf-partial", dir=folder)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def read_record(path: Union[str, os.PathLike], time_col: str = "time_s", lp_col: str = "load_point_um",
                mu_col: str = "mu", normal_col: Optional[str] = None, drop_invalid: bool = False,
                accept_implausible: bool = False) -> dict:
    """Reads a lab record with rsf's one record reader (the CLI's formats and checks: comma,
    tab, semicolon with decimal comma or whitespace separated; UTF-8, UTF-16 or Windows-1252).

    Returns ``{"time_s", "load_point_um", "mu"}`` as numpy arrays, plus ``normal_stress_mpa``
    when ``normal_col`` names a normal-stress column (MPa; it can drive the model's σ(t)).
    A cut, ragged or over-range record raises ``ValueError`` naming file, line and column;
    ``drop_invalid=True`` drops rows with over-range, sentinel or non-finite values instead.
    A record that does not look like a friction experiment (friction outside 0.05–2 or negative,
    the friction and load-point columns swapped, the load point backwards or at an implausible
    speed) raises ``ValueError`` naming what looks wrong, unless ``accept_implausible=True``.
    What the reader warns of (a dropped cut last line, dropped rows) is issued as a
    ``UserWarning``.
    """
    import warnings
    rec = _rsf.read_record_columns(os.fspath(path), time_col, lp_col, mu_col, normal_col, drop_invalid,
                                   accept_implausible)
    for w in rec.pop("warnings"):
        warnings.warn(f"{os.fspath(path)}: {w}", UserWarning, stacklevel=2)
    return rec


def _columns(record: Optional[Mapping[str, Any]], time, load_point, mu, normal_stress=None):
    if record is not None:
        time, load_point, mu = record["time_s"], record["load_point_um"], record["mu"]
        normal_stress = record.get("normal_stress_mpa", normal_stress)
    if time is None or load_point is None or mu is None:
        raise ValueError("give a record (from rsf.read_record) or the arrays time, load_point and mu")

    def f64(a):
        return np.ascontiguousarray(a, dtype=np.float64)
    return f64(time), f64(load_point), f64(mu), (None if normal_stress is None else f64(normal_stress))


def _warn_accepted(accepted: bool, t, x, m, who: str) -> None:
    """What an accepted implausible record was found to be, as ``UserWarning``s."""
    if accepted:
        for w in _rsf.implausible(t, x, m):
            warnings.warn(f"{who}: accepted as plausible: {w}", UserWarning, stacklevel=3)


def fit(record: Optional[Mapping[str, Any]] = None, *, stiffness: float, law: Union[str, ThetaRate] = "slip",
        laws: Optional[Sequence[Union[str, ThetaRate]]] = None, loading: str = "protocol", fit_stiffness: bool = False,
        fit_slip_trend: bool = False, fit_alpha: Optional[str] = None, normal_stress_mode: str = "auto",
        fix: Sequence[str] = (), initial: Optional[Mapping[str, float]] = None, rtol: float = 1e-7,
        starts: int = 4, mcmc: Optional[int] = None, chains: int = 4, seed: int = 1, progress: bool = False,
        window_um: Optional[float] = None, mu0_per_segment: bool = False, weights: str = "equal",
        per_segment: bool = False, threads: int = 0, time=None, load_point=None, mu=None,
        normal_stress=None, max_iter: int = 100, accept_implausible: bool = False,
        uncertainty: str = "noise-model", fit_a_slope: bool = False) -> FitResult:
    """Fits a rate-and-state model to a record — the dict of :func:`read_record`, or the arrays
    ``time`` (s), ``load_point`` (µm), ``mu`` and optionally ``normal_stress`` (MPa) — as
    ``rsf fit`` does with the same options: ``stiffness`` (1/µm), ``law`` or ``laws`` (one per
    state; a registered name or a Python function, which is registered under its ``__name__``), ``loading`` (``"protocol"`` or ``"record"``), ``fit_stiffness``, ``fit_slip_trend``,
    ``fit_a_slope`` (a rate-dependent direct effect, ∂f/∂ln V = a + a_slope·ln(V/V0)),
    ``fit_alpha`` (None, ``"shared"``, ``"per-state"``), ``fix`` (e.g. ``["a-b=-0.003"]``),
    ``initial`` (name → value), ``window_um``, ``mu0_per_segment``, ``weights`` (``"equal"`` or
    ``"uniform"``), ``per_segment`` (refit each step and hold alone: ``per_segment`` in the
    result), ``mcmc`` (total samples; ``chains``, ``seed``), ``progress`` (MCMC progress bar on
    stderr), ``threads`` (for the starts after the first; 0: all cores; the result does not
    depend on it), ``max_iter`` (LM iterations per start), ``accept_implausible`` (fit a record
    that does not look like a friction experiment instead of raising ``ValueError``; the
    findings are issued as ``UserWarning``), ``uncertainty`` (``"noise-model"``: standard errors
    and intervals under the white, AR(1) and drift noise fitted to the residuals, summarised in
    ``noise`` with the white-noise ``stderr_white`` beside them; ``"white"``: independent
    residuals).

    Returns a :class:`FitResult`: ``params`` (``a``, ``b`` and ``dc`` lists per state, ``mu0``,
    ``k``, ``g``, ``alpha``…), ``converged`` (False, with a ``RuntimeWarning``, when no start
    reached an optimum: a budget stopped it or LM's iteration limit), ``starts_failed``,
    ``ci95``, ``stderr``, ``rms``, ``aic``, ``bic``, ``segments``,
    ``curve`` (numpy arrays ``time``, ``data``, ``model``…), ``mcmc`` summaries and ``samples``.
    """
    t, x, m, sn = _columns(record, time, load_point, mu, normal_stress)
    raw, samples, names, curve = _rsf.fit_json(
        t, x, m, stiffness, law=_law_name(law), loading=loading, fit_stiffness=fit_stiffness, normal_stress=sn,
        normal_stress_mode=normal_stress_mode, fit_alpha=fit_alpha,
        laws=None if laws is None else [_law_name(x) for x in laws],
        fit_slip_trend=fit_slip_trend, fix=list(fix), initial=list((initial or {}).items()), rtol=rtol,
        starts=starts, mcmc=mcmc, chains=chains, seed=seed, progress=progress, window_um=window_um,
        mu0_per_segment=mu0_per_segment, weights=weights, per_segment=per_segment, threads=threads,
        max_iter=max_iter, accept_implausible=accept_implausible, uncertainty=uncertainty,
        fit_a_slope=fit_a_slope)
    _warn_accepted(accept_implausible, t, x, m, "rsf.fit")
    result = FitResult(json.loads(raw), samples, names, curve)
    if not result.get("converged", True):
        # the best point found is returned, marked: ``result.converged`` is False
        why = result.get("budget_hit") or f"stopped at the {result.get('stop_reason')}"
        warnings.warn(f"rsf.fit did not converge ({why}; {result.get('starts_failed')} of {result.get('starts')} starts "
                      "failed): its numbers are the best point found, not an optimum", RuntimeWarning, stacklevel=2)
    return result


def diagnose(record: Optional[Mapping[str, Any]] = None, *, stiffness: float, baseline: str = "slip",
             loading: str = "protocol", seed: int = 1, threads: int = 0, normal_stress_mode: str = "auto",
             report: Optional[Union[str, os.PathLike]] = None, name: str = "record", progress: bool = False,
             time=None, load_point=None, mu=None, normal_stress=None,
             stiffness_uncertainty: float = 0.02, accept_implausible: bool = False) -> Diagnosis:
    """Diagnoses a record as ``rsf diagnose`` does: a :class:`Diagnosis` (``cause``, ``gain``,
    ``candidates``, ``evidence``, ``reconstruction``, ``per_segment``, ``adequacy``, ``partial``,
    …; ``write_report``). ``cause`` is ``"unexplained"`` when no model on the menu explains the
    record's events to its noise level, and ``"undecided"`` when two extensions explain it within
    ΔBIC 10 of each other, or, the better one's model untestable, with a lead the noise could
    reverse (``lead``: the lead in ln L, its chance spread ``sd``, ``z``, ``p``) (``undecided``
    lists both, ``partial`` is the better one).
    ``stiffness_uncertainty`` is the nominal stiffness's relative uncertainty (one standard
    deviation), as ``--stiffness-uncertainty``.
    The result depends on the record, the options and ``seed`` only (not on ``threads``).
    ``progress=True`` prints each finished fit on stderr. ``accept_implausible`` as in :func:`fit`.
    """
    t, x, m, sn = _columns(record, time, load_point, mu, normal_stress)
    raw, html = _rsf.diagnose_json(t, x, m, stiffness, baseline, loading, seed, threads, sn, normal_stress_mode,
                                   None if report is None else os.fspath(report), name, progress,
                                   float(stiffness_uncertainty), accept_implausible)
    _warn_accepted(accept_implausible, t, x, m, "rsf.diagnose")
    return Diagnosis(json.loads(raw), html)

def design(record: Optional[Mapping[str, Any]] = None, *, stiffness: float, baseline: str = "slip",
           loading: str = "protocol", v_range=(0.001, 300.0), max_hold: float = 1e4, max_time: float = 14400.0,
           max_slip: float = 1000.0, max_sigma_change: float = 0.0, credible: float = 10.0, draws: int = 12, sequences: bool = True,
           seed: int = 1, threads: int = 0, name: str = "record", time=None, load_point=None, mu=None,
           diagnosis: Union[Mapping[str, Any], str, os.PathLike, None] = None,
           accept_implausible: bool = False) -> Design:
    """Designs the next experiment as ``rsf design`` does: diagnoses the record, then ranks
    velocity steps, holds, normal-stress changes (``max_sigma_change`` > 0: the largest change
    the machine can make, as a fraction of the record's σ) and sequences of two appended at its
    end by how well they would tell the credible models apart. A :class:`Design`;
    ``.to_pandas()`` is the ranking. ``diagnosis`` (a :class:`Diagnosis` of the same record with
    the same options, its dict, or the path of its JSON) is designed from instead of diagnosing
    again, as ``rsf design --from``. The result
    depends on the record, the options and ``seed`` only (not on ``threads``).
    """
    t, x, m, _ = _columns(record, time, load_point, mu, None)
    lo, hi = (float(v) for v in v_range)
    if diagnosis is None or isinstance(diagnosis, Mapping):
        diag = None if diagnosis is None else json.dumps(dict(diagnosis))
    else:
        with open(os.fspath(diagnosis), encoding="utf-8") as f:
            diag = f.read()
    raw, html, toml = _rsf.design_json(t, x, m, stiffness, baseline, loading, (lo, hi), max_hold, max_time, max_slip,
                                       max_sigma_change, credible, draws, sequences, seed, threads, name, diag,
                                       accept_implausible)
    _warn_accepted(accept_implausible, t, x, m, "rsf.design")
    return Design(json.loads(raw), html, toml)

