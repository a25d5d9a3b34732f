"""Type stubs of the native module wmr_py._native (Rust, pyo3). SI units, radians."""

from __future__ import annotations

import math
import os
from typing import Any, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
ArrayLike = Union[Sequence[float], FloatArray]
PoseLike = Union[Sequence[float], Mapping[str, float]]
ScenarioLike = Union[str, os.PathLike[str], Mapping[str, Any]]

class ParameterError(ValueError):
    """A bad argument or parameter value; ``key`` names it (``robot.mass``, ``state[3]``)."""

    key: str
    line: Optional[int]

class ScenarioError(ParameterError):
    """A bad scenario (file, TOML text or dict): ``key`` is the dotted key
    (``run[0].start.x``), ``line`` the 1-based TOML line when known."""

class Robot:
    """A differential-drive robot; keywords are the scenario's ``[robot]`` keys."""

    def __init__(
        self,
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
    ) -> None: ...
    def derivative(self, state: ArrayLike, tau: ArrayLike) -> FloatArray:
        """d/dt of [x, y, theta, v, omega, phi_r, phi_l] under wheel torques (tau_r, tau_l), N m."""
    def step(self, state: ArrayLike, tau: ArrayLike, dt: float) -> FloatArray:
        """The state after one RK4 step of dt seconds with constant wheel torques."""
    def kinetic_energy(self, state: ArrayLike) -> float:
        """1/2 M11 v^2 + 1/2 M22 omega^2, J."""
    def wheel_speeds(self, state: ArrayLike) -> Tuple[float, float]:
        """(omega_r, omega_l), rad/s."""
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

class PaperController:
    """The paper's controller; gains are the scenario's ``[controller]`` keys."""

    def __init__(
        self,
        goal: PoseLike,
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
    ) -> None: ...
    def update(self, pose: ArrayLike, wheel_angles: ArrayLike, wheel_speeds: ArrayLike) -> Tuple[float, float]:
        """(tau_r, tau_l): wheel torque demands, N m, before the drive's clamp."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Tuple[float, float, float]:
        """(e_s in m, e_theta in rad, dl in m) of the last update."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Tuple[float, float, float]: ...

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
    t: FloatArray
    x: FloatArray
    y: FloatArray
    theta: FloatArray
    v: FloatArray
    omega: FloatArray
    phi_r: FloatArray
    phi_l: FloatArray
    omega_r: FloatArray
    omega_l: FloatArray
    tau_r: FloatArray
    tau_l: FloatArray
    e_s: FloatArray
    e_theta: FloatArray
    dl: FloatArray
    x_meas: FloatArray
    """x of the pose the controller used at its last tick, m (equal to x without [sensor])."""
    y_meas: FloatArray
    theta_meas: FloatArray
    def __getitem__(self, name: str) -> FloatArray: ...
    def __len__(self) -> int: ...
    def columns(self) -> dict[str, FloatArray]:
        """Every CSV column (``run`` first), in CSV order."""

def run_scenario(scenario: ScenarioLike) -> list[RunResult]:
    """Every run of a scenario (path, TOML text or dict), in run order."""

def sweep(scenario: ScenarioLike) -> dict[str, Any]:
    """Every law from every start of the scenario's [sweep], in parallel (GIL released):
    ``law`` (list[str]), ``start`` (int64), ``x0``, ``y0`` (m), ``theta0`` (rad), the
    outcome arrays of ``run_batch`` (``final_x`` ... ``energy``, ``converged``,
    ``diverged``), and ``table`` (the CLI's comparison table)."""

def _run_batch(base: Mapping[str, Any], starts: FloatArray, goals: Optional[FloatArray] = None) -> dict[str, Any]: ...
def _time_run_rust(scenario: ScenarioLike, n: int) -> float:
    """Best of n wall times (s) of parse + run 0 + columns inside Rust, GIL released."""
