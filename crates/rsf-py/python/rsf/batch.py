"""Many records at once: ``rsf batch``'s per-record work from Python, on a Dask cluster when a
``client`` is given (``dask.distributed``; dask-jobqueue for SLURM/PBS — see docs/scale.md).

The work of each record and the summary table are the same Rust code as ``rsf batch``, so
``diagnose_many(manifest, client=...)`` equals ``rsf batch manifest --diagnose``'s
``summary.csv`` read with pandas, whatever the cluster. Rows travel as JSON text.
"""

from __future__ import annotations

import json
import math
import os
import sys
from typing import Any, Optional, Sequence, Union

from . import _rsf

#: The per-record options: the manifest's option columns, also accepted as keyword arguments
#: (the batch-wide defaults a manifest's cells override).
OPTIONS = ("stiffness", "time_col", "lp_col", "mu_col", "shear_col", "normal_col", "normal_stress",
           "disp_unit", "time_unit", "t_min", "t_max", "law_file", "law", "baseline", "loading", "fit_stiffness",
           "fit_slip_trend", "fit_a_slope", "drop_invalid", "accept_implausible", "seed")

PathLike = Union[str, os.PathLike]


def _entries(manifest_or_paths: Union[PathLike, Sequence[PathLike]], allow_outside: bool = False) -> list:
    if isinstance(manifest_or_paths, (str, os.PathLike)):
        return json.loads(_rsf.batch_entries(os.fspath(manifest_or_paths), allow_outside))
    return [{"name": os.fspath(p), "path": os.path.abspath(os.fspath(p)), "line": 0, "options": {}, "meta": []}
            for p in manifest_or_paths]


def _row(entry_json: str, defaults_json: str, fit: bool, diagnose: bool, threads: int) -> str:
    """One record's summary row (JSON); what a Dask task runs."""
    return _rsf.batch_row(entry_json, defaults_json, fit, diagnose, threads)


def _many(manifest_or_paths, stiffness, client, fit: bool, diagnose: bool, progress: bool, options: dict,
          allow_outside: bool = False):
    unknown = sorted(set(options) - set(OPTIONS))
    if unknown:
        raise TypeError(f"unknown option(s) {', '.join(unknown)}: use {', '.join(OPTIONS)}")
    defaults = {k: v for k, v in options.items() if v is not None}
    if stiffness is not None:
        defaults["stiffness"] = float(stiffness)
    for k, v in defaults.items():
        # said in the user's terms, not as the JSON the options travel in
        if isinstance(v, float) and not math.isfinite(v):
            raise ValueError(f"{k} = {v} must be a finite number")
    if "law_file" in defaults:
        # absolute, so that a worker in another folder or process finds it
        defaults["law_file"] = os.path.abspath(os.fspath(defaults["law_file"]))
    dj = json.dumps(defaults)
    _rsf.batch_check_options(dj)
    entries = [json.dumps(e) for e in _entries(manifest_or_paths, allow_outside)]
    if client is None:
        rows = []
        for k, e in enumerate(entries):
            rows.append(_row(e, dj, fit, diagnose, 0))
            if progress:
                r = json.loads(rows[-1])
                print(f"rsf: {k + 1}/{len(entries)} {r['file']}: {r['status']}", file=sys.stderr)
    else:
        # one task per record, one thread each: the workers are the parallelism
        futures = client.map(_row, entries, defaults_json=dj, fit=fit, diagnose=diagnose, threads=1, pure=False)
        if progress:
            from distributed import progress as show
            show(futures)
        rows = [_result(f, e) for f, e in zip(futures, entries)]
    return _table(rows)


def _result(future, entry_json: str) -> str:
    """A task's row; a task that raised, or whose record killed its workers (Dask's
    ``KilledWorker``), becomes a ``crashed`` row saying so, and the other rows are kept."""
    try:
        return future.result()
    except Exception as e:  # noqa: BLE001 — any failure of one record is that record's row
        return _rsf.batch_crashed_row(entry_json, f"the task failed: {type(e).__name__}: {e}")


def _table(rows: Sequence[str]):
    """The summary as a DataFrame built from the typed rows, as ``rsf batch`` types them: text
    columns as text exactly as the manifest and the work gave them (a meta ``NA`` or ``007``
    stays text; no spreadsheet quoting), numbers as float (NaN for none), counts as ``Int64``."""
    import pandas as pd
    header, kinds, columns = _rsf.batch_table(list(rows))
    dtype = {"text": object, "number": "float64", "count": "Int64"}
    return pd.DataFrame({h: pd.Series(c, dtype=dtype[k]) for h, k, c in zip(header, kinds, columns)})


def fit_many(manifest_or_paths: Union[PathLike, Sequence[PathLike]], stiffness: Optional[float] = None,
             client: Any = None, *, diagnose: bool = False, progress: bool = False, allow_outside: bool = False,
             **options):
    """Fits every record of a manifest (CSV), a folder, or a list of paths, as
    ``rsf batch --fit`` does; a pandas DataFrame with its ``summary.csv`` columns (``file``,
    ``status``, ``error``, conditions, parameters and ``*_se``, …). ``stiffness`` and
    ``options`` (see :data:`OPTIONS`) are the defaults a manifest's cells override. With a
    ``dask.distributed`` ``client`` each record is a task on the cluster. A failing record is a
    row whose ``status`` says what failed; the others go on. A manifest's record outside its
    folder is refused unless ``allow_outside``."""
    return _many(manifest_or_paths, stiffness, client, True, diagnose, progress, options, allow_outside)


def diagnose_many(manifest_or_paths: Union[PathLike, Sequence[PathLike]], stiffness: Optional[float] = None,
                  client: Any = None, *, fit: bool = False, progress: bool = False, allow_outside: bool = False,
                  **options):
    """Diagnoses every record, as ``rsf batch --diagnose`` does (``fit=True``: ``--fit
    --diagnose``); see :func:`fit_many`. The table adds ``cause``, ``delta_bic``,
    ``rms_ratio``, ``effect``, ``runner_up``, ``partial``, ``adequacy``, ``adequacy_excess``,
    ``events_tested`` (of ``events``, the record's steps and reslides), ``drift_rms`` and
    ``quiet_wander`` (the named model's residuals' wander in the quiet stretches of sliding over
    what their noise model says, in variance: far below 1 when its drift is misfit) and
    ``form_delta_bic`` (the form test: ΔBIC of the best model reshaped in state or with a
    rate-dependent direct effect against the one named, or the baseline for ``none``; below −10
    and beyond chance its form is not the record's) and ``lead_z`` (the lead of the cause chosen
    over its best credible rival in spreads of their log-likelihood ratio under the noise)."""
    return _many(manifest_or_paths, stiffness, client, fit, True, progress, options, allow_outside)
