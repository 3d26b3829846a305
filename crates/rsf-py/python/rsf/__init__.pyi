# Type stubs of the rsf package (units: µm, s, µm/s, 1/µm, MPa).
import os
from dataclasses import dataclass
from typing import Any, Callable, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

ThetaRate = Callable[..., float]
LAWS: tuple[str, ...]

def load_law(path: Union[str, os.PathLike[str]]) -> str: ...
def register_law(
    name: str,
    theta_rate: ThetaRate,
    parameters: Optional[Mapping[str, Mapping[str, Any]]] = ...,
    words: Optional[str] = ...,
    candidate: bool = ...,
) -> str: ...
def check_law(law: Union[str, os.PathLike[str], Callable[..., float]], cases: Optional[int] = ...,
              steady_state_dc_over_v: bool = ...) -> str: ...
def laws() -> list[str]: ...

class SolveError(ValueError):
    time: float
    slip_rate: float
    mu: float
    piece: int
    v_lp: float

@dataclass
class State:
    law: Union[str, ThetaRate]
    b: float
    dc: float
    vc: Optional[float] = ...
    c: Optional[float] = ...
    alpha: float = ...
    params: Optional[dict[str, float]] = ...

@dataclass
class Model:
    mu0: float
    v0: float
    a: float
    stiffness: float
    states: list[State] = ...
    eta: float = ...
    form: str = ...
    normal_stress: Optional[float] = ...
    a_slope: float = ...

@dataclass
class Protocol:
    v_init: float
    segments: list[Any] = ...
    record: Optional[str] = ...
    time_column: Optional[str] = ...
    load_point_column: Optional[str] = ...
    friction_column: Optional[str] = ...
    normal_stress_column: Optional[str] = ...

@dataclass
class Setup:
    model: Model
    protocol: Protocol
    output: dict[str, Any] = ...
    solver: dict[str, Any] = ...
    initial: Optional[dict[str, Any]] = ...
    source: str = ...

class SimulationResult(dict[str, Any]):
    time_s: npt.NDArray[np.float64]
    load_point_um: npt.NDArray[np.float64]
    mu: npt.NDArray[np.float64]
    slip_rate_um_s: npt.NDArray[np.float64]
    slip_um: npt.NDArray[np.float64]
    theta_s: npt.NDArray[np.float64]
    method: str
    steps: int
    def to_pandas(self) -> Any: ...

class FitResult(dict[str, Any]):
    params: dict[str, Any]
    ci95: dict[str, list[float]]
    stderr: dict[str, float]
    converged: bool
    starts_failed: int
    rms: float
    aic: float
    bic: float
    segments: list[dict[str, Any]]
    curve: dict[str, npt.NDArray[np.float64]]
    samples: npt.NDArray[np.float64]
    sample_names: list[str]
    def to_json(self, indent: Optional[int] = ...) -> str: ...

class Design(dict[str, Any]):
    protocol: str
    def to_pandas(self) -> Any: ...  # pandas.DataFrame: the ranking
    def write_report(self, path: Union[str, os.PathLike[str]]) -> None: ...
    def write_protocol(self, path: Union[str, os.PathLike[str]]) -> None: ...
    def to_json(self, indent: Optional[int] = ...) -> str: ...

class Diagnosis(dict[str, Any]):
    cause: str
    candidates: list[dict[str, Any]]
    def write_report(self, path: Union[str, os.PathLike[str]]) -> None: ...
    def to_json(self, indent: Optional[int] = ...) -> str: ...

def load_protocol(path: Union[str, os.PathLike[str]]) -> Setup: ...
def simulate(
    model: Union[Model, Setup, str, os.PathLike[str]],
    protocol: Optional[Protocol] = ...,
    *,
    dt: Optional[float] = ...,
    method: Optional[str] = ...,
    rtol: Optional[float] = ...,
    atol: Optional[float] = ...,
    time: Optional[npt.ArrayLike] = ...,
    load_point: Optional[npt.ArrayLike] = ...,
) -> SimulationResult: ...
def read_record(
    path: Union[str, os.PathLike[str]],
    time_col: str = ...,
    lp_col: str = ...,
    mu_col: str = ...,
    normal_col: Optional[str] = ...,
) -> dict[str, npt.NDArray[np.float64]]: ...
def fit(
    record: Optional[Mapping[str, Any]] = ...,
    *,
    stiffness: float,
    law: Union[str, ThetaRate] = ...,
    laws: Optional[Sequence[Union[str, ThetaRate]]] = ...,
    loading: str = ...,
    fit_stiffness: bool = ...,
    fit_slip_trend: bool = ...,
    fit_alpha: Optional[str] = ...,
    normal_stress_mode: str = ...,
    fix: Sequence[str] = ...,
    initial: Optional[Mapping[str, float]] = ...,
    rtol: float = ...,
    starts: int = ...,
    mcmc: Optional[int] = ...,
    chains: int = ...,
    seed: int = ...,
    progress: bool = ...,
    window_um: Optional[float] = ...,
    mu0_per_segment: bool = ...,
    weights: str = ...,
    per_segment: bool = ...,
    threads: int = ...,
    time: Optional[npt.ArrayLike] = ...,
    load_point: Optional[npt.ArrayLike] = ...,
    mu: Optional[npt.ArrayLike] = ...,
    normal_stress: Optional[npt.ArrayLike] = ...,
    max_iter: int = ...,
    accept_implausible: bool = ...,
    uncertainty: str = ...,
    fit_a_slope: bool = ...,
) -> FitResult: ...
def diagnose(
    record: Optional[Mapping[str, Any]] = ...,
    *,
    stiffness: float,
    baseline: str = ...,
    loading: str = ...,
    seed: int = ...,
    threads: int = ...,
    normal_stress_mode: str = ...,
    report: Optional[Union[str, os.PathLike[str]]] = ...,
    name: str = ...,
    progress: bool = ...,
    time: Optional[npt.ArrayLike] = ...,
    load_point: Optional[npt.ArrayLike] = ...,
    mu: Optional[npt.ArrayLike] = ...,
    normal_stress: Optional[npt.ArrayLike] = ...,
) -> Diagnosis: ...
def design(
    record: Optional[Mapping[str, Any]] = ...,
    *,
    stiffness: float,
    baseline: str = ...,
    loading: str = ...,
    v_range: Tuple[float, float] = ...,
    max_hold: float = ...,
    max_time: float = ...,
    max_slip: float = ...,
    max_sigma_change: float = ...,
    credible: float = ...,
    draws: int = ...,
    sequences: bool = ...,
    seed: int = ...,
    threads: int = ...,
    name: str = ...,
    time: Optional[npt.ArrayLike] = ...,
    load_point: Optional[npt.ArrayLike] = ...,
    mu: Optional[npt.ArrayLike] = ...,
    diagnosis: Union[Mapping[str, Any], str, os.PathLike, None] = ...,
) -> Design: ...
def fit_many(
    manifest_or_paths: Union[str, os.PathLike[str], Sequence[Union[str, os.PathLike[str]]]],
    stiffness: Optional[float] = ...,
    client: Any = ...,
    *,
    diagnose: bool = ...,
    progress: bool = ...,
    allow_outside: bool = ...,
    **options: Any,
) -> Any: ...  # pandas.DataFrame: the columns of `rsf batch`'s summary.csv
def diagnose_many(
    manifest_or_paths: Union[str, os.PathLike[str], Sequence[Union[str, os.PathLike[str]]]],
    stiffness: Optional[float] = ...,
    client: Any = ...,
    *,
    fit: bool = ...,
    progress: bool = ...,
    allow_outside: bool = ...,
    **options: Any,
) -> Any: ...  # pandas.DataFrame
