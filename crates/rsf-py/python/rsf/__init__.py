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
                mu_col: str = "mu") -> dict[str, np.ndarray]:
    """Reads a lab record (CSV, tab- or semicolon-separated) with the CLI's column options.

    Returns ``{"time_s", "load_point_um", "mu"}`` as numpy arrays.
    """
    return _rsf.read_record_columns(os.fspath(path), time_col, lp_col, mu_col)


def _columns(record: Mapping[str, Any] | None, time, load_point, mu):
    if record is not None:
        time, load_point, mu = record["time_s"], record["load_point_um"], record["mu"]
    return (np.ascontiguousarray(time, dtype=np.float64),
            np.ascontiguousarray(load_point, dtype=np.float64),
            np.ascontiguousarray(mu, dtype=np.float64))


def fit(record: Mapping[str, Any] | None = None, *, stiffness: float, law: str = "slip",
        loading: str = "protocol", fit_stiffness: bool = False, time=None, load_point=None,
        mu=None) -> dict[str, Any]:
    """Fits a one-state law to a record (the dict of :func:`read_record`, or the arrays
    ``time`` s, ``load_point`` µm, ``mu``), as ``rsf fit`` does with the same options.

    Returns the fit as the dict of ``rsf fit --json`` (``params`` with ``a``, ``b`` and ``dc``
    lists, ``mu0``, ``k``; ``ci95``, ``stderr``, ``rms``, ``aic``, ``bic``, ``segments``, …).
    """
    t, x, m = _columns(record, time, load_point, mu)
    return json.loads(_rsf.fit_json(t, x, m, stiffness, law, loading, fit_stiffness))


def diagnose(record: Mapping[str, Any] | None = None, *, stiffness: float, baseline: str = "slip",
             loading: str = "protocol", seed: int = 1, threads: int = 0, time=None,
             load_point=None, mu=None) -> dict[str, Any]:
    """Diagnoses a record as ``rsf diagnose`` does: the dict of its JSON (``cause``,
    ``gain``, ``candidates``, ``evidence``, ``reconstruction``, ``per_segment``, …). The
    result depends on the record, the options and ``seed`` only (not on ``threads``).
    """
    t, x, m = _columns(record, time, load_point, mu)
    return json.loads(_rsf.diagnose_json(t, x, m, stiffness, baseline, loading, seed, threads))
