"""rsf: rate-and-state friction from Python, with the Rust crates inside.

numpy arrays in and out; results of fits and diagnoses are the dicts of the CLI's JSON
(``rsf fit --json``, ``rsf diagnose --json``). Units as everywhere in rsf: µm, s, µm/s, 1/µm.

>>> import rsf
>>> out = rsf.simulate("examples/step_down.toml")          # a protocol file, as `rsf simulate`
>>> rec = rsf.read_record("examples/data/giacomel-basalt/velstep4_BRAVA_expb819_basalt.txt",
...                       time_col="Time(s)", lp_col="Displ(microns)", mu_col="Friction")
>>> fit = rsf.fit(rec, law="slip", stiffness=0.0151, fit_stiffness=True)
>>> fit["params"]["a"], fit["params"]["dc"]
"""

from __future__ import annotations

import json
import os
from typing import Any, Mapping

import numpy as np

from . import _rsf

__all__ = ["simulate", "read_record", "fit", "diagnose"]


def simulate(protocol: str | os.PathLike, time=None, load_point=None) -> dict[str, Any]:
    """Solves a protocol (a TOML file path, or TOML text) exactly as ``rsf simulate`` does.

    With ``time`` (s) and ``load_point`` (µm) arrays, a measured load point drives the model
    instead of the protocol's loading (piecewise linear between samples), with output at
    ``time``; the protocol then supplies the model, ``v_init`` and the solver.

    Returns a dict of numpy arrays: ``time_s``, ``load_point_um``, ``mu``,
    ``slip_rate_um_s``, ``slip_um``, ``theta_s`` (rows × state variables), plus
    ``peak_slip_rate_um_s`` when the protocol asks for it, ``method`` and ``steps``.
    Raises ValueError with the CLI's message (file, line and field) on a bad protocol or a
    failed solve.
    """
    text = os.fspath(protocol)
    arrays = {}
    if time is not None or load_point is not None:
        arrays = dict(time=None if time is None else np.ascontiguousarray(time, dtype=np.float64),
                      load_point=None if load_point is None else np.ascontiguousarray(load_point, dtype=np.float64))
    if "\n" not in text and os.path.exists(text):
        with open(text, encoding="utf-8") as f:
            body = f.read()
        base = os.path.dirname(os.path.abspath(text))
        return _rsf.simulate_toml(body, base, text, **arrays)
    return _rsf.simulate_toml(text, None, "protocol.toml", **arrays)


def read_record(path: str | os.PathLike, time_col: str = "time_s", lp_col: str = "load_point_um",
                mu_col: str = "mu", normal_col: str | None = None) -> dict[str, np.ndarray]:
    """Reads a lab record (CSV, tab- or semicolon-separated) with the CLI's column options.

    Returns ``{"time_s", "load_point_um", "mu"}`` as numpy arrays, plus ``normal_stress_mpa``
    when ``normal_col`` names a normal-stress column (MPa; it can drive the model's σ(t)).
    """
    return _rsf.read_record_columns(os.fspath(path), time_col, lp_col, mu_col, normal_col)


def _columns(record: Mapping[str, Any] | None, time, load_point, mu, normal_stress=None):
    if record is not None:
        time, load_point, mu = record["time_s"], record["load_point_um"], record["mu"]
        normal_stress = record.get("normal_stress_mpa", normal_stress)
    f64 = lambda a: np.ascontiguousarray(a, dtype=np.float64)  # noqa: E731
    return f64(time), f64(load_point), f64(mu), (None if normal_stress is None else f64(normal_stress))


def fit(record: Mapping[str, Any] | None = None, *, stiffness: float, law: str = "slip",
        loading: str = "protocol", fit_stiffness: bool = False, fit_alpha: str | None = None,
        normal_stress_mode: str = "auto", time=None, load_point=None, mu=None,
        normal_stress=None) -> dict[str, Any]:
    """Fits a one-state law to a record (the dict of :func:`read_record`, or the arrays
    ``time`` s, ``load_point`` µm, ``mu`` and optionally ``normal_stress`` MPa), as ``rsf fit``
    does with the same options (``fit_alpha``: None, ``"shared"`` or ``"per-state"``, as
    ``--fit-alpha``; ``normal_stress_mode``: ``"auto"``, ``"record"`` or ``"constant"``).

    Returns the fit as the dict of ``rsf fit --json`` (``params`` with ``a``, ``b`` and ``dc``
    lists, ``mu0``, ``k``, ``alpha`` when σ drives the model; ``ci95``, ``stderr``, ``rms``,
    ``aic``, ``bic``, ``segments``, …).
    """
    t, x, m, sn = _columns(record, time, load_point, mu, normal_stress)
    return json.loads(_rsf.fit_json(t, x, m, stiffness, law, loading, fit_stiffness, sn, normal_stress_mode,
                                    fit_alpha))


def diagnose(record: Mapping[str, Any] | None = None, *, stiffness: float, baseline: str = "slip",
             loading: str = "protocol", seed: int = 1, threads: int = 0, normal_stress_mode: str = "auto",
             time=None, load_point=None, mu=None, normal_stress=None) -> dict[str, Any]:
    """Diagnoses a record as ``rsf diagnose`` does: the dict of its JSON (``cause``,
    ``gain``, ``candidates``, ``evidence``, ``reconstruction``, ``per_segment``, …). The
    result depends on the record, the options and ``seed`` only (not on ``threads``).
    """
    t, x, m, sn = _columns(record, time, load_point, mu, normal_stress)
    return json.loads(_rsf.diagnose_json(t, x, m, stiffness, baseline, loading, seed, threads, sn,
                                         normal_stress_mode))
