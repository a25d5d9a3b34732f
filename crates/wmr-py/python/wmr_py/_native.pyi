"""Type stubs of the native module wmr_py._native (Rust, pyo3). SI units, radians."""

from __future__ import annotations

import math
import os
from typing import Any, Callable, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt
from typing_extensions import Self, final

_FloatArray = npt.NDArray[np.float64]
_ArrayLike = Union[Sequence[float], _FloatArray]
_PoseLike = Union[Sequence[float], Mapping[str, float]]
_ScenarioLike = Union[str, os.PathLike[str], Mapping[str, Any]]

class ParameterError(ValueError):
    """A bad argument or parameter value; ``key`` names it (``robot.mass``, ``state[3]``)."""

    key: str
    line: Optional[int]

class ScenarioError(ParameterError):
    """A bad scenario (file, TOML text or dict): ``key`` is the dotted key
    (``run[0].start.x``), ``line`` the 1-based TOML line when known."""

@final
class Robot:
    """A differential-drive robot; keywords are the scenario's ``[robot]`` keys."""

    def __new__(
        cls,
        *,
        mass: float = 5.0,
        wheel_radius: float = 0.1,
        half_track: float = 0.2,
        com_offset: float = 0.25,
        wheel_inertia: float = 0.002,
        platform_inertia: float = 0.005,
        gear_ratio: float = 0.1,
        viscous_friction: float = 0.0,
        coulomb_friction: float = 0.0,
        coulomb_speed: float = 0.001,
    ) -> Self: ...
    def derivative(self, state: _ArrayLike, tau: _ArrayLike) -> _FloatArray:
        """d/dt of [x, y, theta, v, omega, phi_r, phi_l] under wheel torques (tau_r, tau_l), N m;
        (N, 7) for a batch of (N, 7) states and (N, 2) torques."""
    def step(self, state: _ArrayLike, tau: _ArrayLike, dt: float) -> _FloatArray:
        """The state after one RK4 step of dt seconds with constant wheel torques; (N, 7) for a batch."""
    def kinetic_energy(self, state: _ArrayLike) -> Any:
        """1/2 M11 v^2 + 1/2 M22 omega^2, J (float; (N,) array for (N, 7) states)."""
    def wheel_speeds(self, state: _ArrayLike) -> Any:
        """(omega_r, omega_l), rad/s ((N, 2) array for (N, 7) states)."""
    def to_dict(self) -> dict[str, float]: ...
    @property
    def reduced_inertia(self) -> Tuple[float, float]:
        """(M11 in kg, M22 in kg m^2)."""
    @property
    def mass(self) -> float: ...
    @property
    def wheel_radius(self) -> float: ...
    @property
    def half_track(self) -> float: ...
    @property
    def com_offset(self) -> float: ...
    @property
    def wheel_inertia(self) -> float: ...
    @property
    def platform_inertia(self) -> float: ...
    @property
    def gear_ratio(self) -> float: ...
    @property
    def viscous_friction(self) -> float: ...
    @property
    def coulomb_friction(self) -> float: ...
    @property
    def coulomb_speed(self) -> float: ...

@final
class PaperController:
    """The paper's controller; gains are the scenario's ``[controller]`` keys of kind "paper"."""

    def __new__(
        cls,
        goal: _PoseLike,
        robot: Union[None, Robot, Mapping[str, float]] = None,
        drive: Optional[Mapping[str, Any]] = None,
        *,
        mode: str = "pose",
        kp_theta: float = 2.0,
        ki_theta: float = 0.1,
        kp_s: float = 1.0,
        ki_s: float = 0.25,
        goal_radius: float = 0.001,
        hold_radius: float = 0.005,
        hold: str = "auto",
        servo_kp: float = 14.0,
        servo_kd: float = 1.4,
        servo_ki: float = 0.0,
        wheel_speed_max: float = math.inf,
        control_dt: float = 0.001,
    ) -> Self: ...
    def update(self, pose: _ArrayLike, wheel_angles: _ArrayLike, wheel_speeds: _ArrayLike) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch of (N, 3) poses, (N, 2) wheel angles and (N, 2) wheel speeds."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Tuple[float, float, float]: ...
    @property
    def kind(self) -> str: ...
    @property
    def n(self) -> int:
        """Robots in the batch (1 for single calls)."""
    @property
    def scenario_toml(self) -> str: ...


@final
class PaperBidirectionalController:
    """The paper's law repaired (kind "paper_bidirectional")."""

    def __new__(
        cls,
        goal: _PoseLike,
        robot: Union[None, Robot, Mapping[str, float]] = None,
        drive: Optional[Mapping[str, Any]] = None,
        *,
        kp_theta: float = 0.0,
        ki_theta: float = 1.0,
        kp_s: float = 0.0,
        ki_s: float = 0.25,
        goal_radius: float = 0.001,
        hold_radius: float = 0.005,
        hold: str = "freeze",
        servo_kp: float = 14.0,
        servo_kd: float = 1.4,
        servo_ki: float = 0.0,
        wheel_speed_max: float = math.inf,
        control_dt: float = 0.001,
    ) -> Self: ...
    def update(self, pose: _ArrayLike, wheel_angles: _ArrayLike, wheel_speeds: _ArrayLike) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch of (N, 3) poses, (N, 2) wheel angles and (N, 2) wheel speeds."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Tuple[float, float, float]: ...
    @property
    def kind(self) -> str: ...
    @property
    def n(self) -> int:
        """Robots in the batch (1 for single calls)."""
    @property
    def scenario_toml(self) -> str: ...


@final
class PolarController:
    """Astolfi's polar law (kind "polar")."""

    def __new__(
        cls,
        goal: _PoseLike,
        robot: Union[None, Robot, Mapping[str, float]] = None,
        drive: Optional[Mapping[str, Any]] = None,
        *,
        k_rho: float = 0.5,
        k_alpha: float = 3.0,
        k_beta: float = -1.2,
        reverse: bool = True,
        reverse_hysteresis: float = 0.5235987755982989,
        goal_radius: float = 0.001,
        servo_kp: float = 14.0,
        servo_kd: float = 1.4,
        servo_ki: float = 0.0,
        wheel_speed_max: float = math.inf,
        control_dt: float = 0.001,
    ) -> Self: ...
    def update(self, pose: _ArrayLike, wheel_angles: _ArrayLike, wheel_speeds: _ArrayLike) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch of (N, 3) poses, (N, 2) wheel angles and (N, 2) wheel speeds."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Tuple[float, float, float]: ...
    @property
    def kind(self) -> str: ...
    @property
    def n(self) -> int:
        """Robots in the batch (1 for single calls)."""
    @property
    def scenario_toml(self) -> str: ...


@final
class LyapunovController:
    """Aicardi et al.'s Lyapunov law (kind "lyapunov")."""

    def __new__(
        cls,
        goal: _PoseLike,
        robot: Union[None, Robot, Mapping[str, float]] = None,
        drive: Optional[Mapping[str, Any]] = None,
        *,
        gamma: float = 0.5,
        k: float = 3.0,
        h: float = 9.0,
        reverse: bool = True,
        reverse_hysteresis: float = 0.5235987755982989,
        goal_radius: float = 0.001,
        servo_kp: float = 14.0,
        servo_kd: float = 1.4,
        servo_ki: float = 0.0,
        wheel_speed_max: float = math.inf,
        control_dt: float = 0.001,
    ) -> Self: ...
    def update(self, pose: _ArrayLike, wheel_angles: _ArrayLike, wheel_speeds: _ArrayLike) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch of (N, 3) poses, (N, 2) wheel angles and (N, 2) wheel speeds."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Tuple[float, float, float]: ...
    @property
    def kind(self) -> str: ...
    @property
    def n(self) -> int:
        """Robots in the batch (1 for single calls)."""
    @property
    def scenario_toml(self) -> str: ...


@final
class RunResult:
    """One run: the CSV columns of docs/scenario.md as float64 arrays, plus the summary."""

    run: int
    label: str
    status: str
    converged: bool
    diverged: bool
    time_to_1cm: Optional[float]
    final_dl: float
    final_heading_error: float
    final_heading_error_deg: float
    t_final: float
    peak_wheel_speed: float
    path_length: float
    energy: float
    summary: str
    @property
    def t(self) -> _FloatArray: ...
    @property
    def x(self) -> _FloatArray: ...
    @property
    def y(self) -> _FloatArray: ...
    @property
    def theta(self) -> _FloatArray: ...
    @property
    def v(self) -> _FloatArray: ...
    @property
    def omega(self) -> _FloatArray: ...
    @property
    def phi_r(self) -> _FloatArray: ...
    @property
    def phi_l(self) -> _FloatArray: ...
    @property
    def omega_r(self) -> _FloatArray: ...
    @property
    def omega_l(self) -> _FloatArray: ...
    @property
    def tau_r(self) -> _FloatArray: ...
    @property
    def tau_l(self) -> _FloatArray: ...
    @property
    def e_s(self) -> _FloatArray: ...
    @property
    def e_theta(self) -> _FloatArray: ...
    @property
    def dl(self) -> _FloatArray: ...
    @property
    def x_meas(self) -> _FloatArray: ...
    @property
    def y_meas(self) -> _FloatArray: ...
    @property
    def theta_meas(self) -> _FloatArray: ...
    def __getitem__(self, name: str, /) -> _FloatArray: ...
    def __len__(self) -> int: ...
    def columns(self) -> dict[str, _FloatArray]:
        """Every CSV column (``run`` first), in CSV order."""
    def to_pandas(self) -> Any:
        """Every column with ``run`` and ``label``, one row per sample (needs pandas)."""
    def __getstate__(self) -> dict[str, Any]: ...

__version__: str
COLUMNS: Tuple[str, ...]
COLUMN_UNITS: Tuple[str, ...]
CSV_COLUMNS: Tuple[str, ...]
MEASURED_COLUMNS: Tuple[str, ...]
OUTCOME_FIELDS: Tuple[str, ...]
ARRIVAL_RADIUS_M: float

_Progress = Optional[Callable[[int], Any]]

def run_scenario(scenario: _ScenarioLike, progress: _Progress = None) -> list[RunResult]:
    """Every run of a scenario (path, TOML text or dict), in run order."""

def _sweep(scenario: _ScenarioLike, progress: _Progress = None, fast: bool = False) -> dict[str, Any]: ...
def _sweep_plan(scenario: _ScenarioLike) -> Tuple[str, int]: ...
def _sweep_part(text: str, first: int, last: int, fast: bool = False) -> _FloatArray: ...
def _sweep_gather(text: str, rows: _FloatArray) -> dict[str, Any]: ...
def _run_batch(
    base: Mapping[str, Any],
    starts: _FloatArray,
    goals: Optional[_FloatArray] = None,
    first: int = 0,
    threads: int = 0,
    progress: _Progress = None,
    fast: bool = False,
) -> dict[str, Any]: ...
def _run_result_from_state(state: Mapping[str, Any]) -> RunResult: ...
def _controller_from_toml(class_name: str, text: str) -> Any: ...
def _time_run_rust(scenario: _ScenarioLike, n: int) -> float:
    """Best of n wall times (s) of parse + run 0 + columns inside Rust, GIL released."""

__all__ = [
    "LyapunovController",
    "PaperBidirectionalController",
    "PaperController",
    "PolarController",
    "_controller_from_toml",
    "ParameterError",
    "ScenarioError",
    "Robot",
    "RunResult",
    "_run_batch",
    "_run_result_from_state",
    "run_scenario",
    "_sweep",
    "_sweep_gather",
    "_sweep_part",
    "_sweep_plan",
    "_time_run_rust",
    "__version__",
    "COLUMNS",
    "COLUMN_UNITS",
    "CSV_COLUMNS",
    "MEASURED_COLUMNS",
    "OUTCOME_FIELDS",
    "ARRIVAL_RADIUS_M",
]
