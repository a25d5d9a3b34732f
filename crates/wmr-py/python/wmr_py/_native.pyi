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

#: A controller reference: {"pose": .., "twist": .., "accel": ..} or rows of
#: (x, y, theta, v, omega, v', omega').
_ReferenceLike = Union[Mapping[str, Any], _ArrayLike]

@final
class Reference:
    """A moving reference: the scenario's ``[reference]`` keys (kind circle, figure_eight,
    line, waypoints or file), read and checked by the scenario code."""

    def __new__(cls, kind: str, **keys: Any) -> Self: ...
    @property
    def kind(self) -> str: ...
    @property
    def start_pose(self) -> Tuple[float, float, float]:
        """Pose of C_ref at t = 0, (x_m, y_m, theta_rad)."""
    def to_dict(self) -> dict[str, Any]:
        """The keys as given, with ``kind``."""
    def state_at(self, t_s: Union[float, _FloatArray]) -> Any:
        """At a time (s): {"pose": (x, y, theta), "twist": (v, omega), "accel": (v', omega')};
        at a 1-D array of N times: an (N, 7) array of those rows."""

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
        # keys from wmr_scenario::schema(), generated: WMR_BLESS=1 cargo test -p wmr-cli --test keys_documented
        mass: float = 5.0,  # [kg] m, total mass.
        wheel_radius: float = 0.1,  # [m] r, wheel radius.
        half_track: float = 0.2,  # [m] R, half the distance between the wheels (axle midpoint C to each wheel).
        com_offset: float = 0.25,  # [m] d, distance from C forward to the centre of mass G (negative: G behind C).
        wheel_inertia: float = 0.002,  # [kg m^2] I_m, inertia of one wheel plus its motor rotor about the wheel axis.
        platform_inertia: float = 0.005,  # [kg m^2] I_p, platform inertia about G.
        gear_ratio: float = 0.1,  # k_t, gear reduction: wheel speed = k_t * motor speed.
        viscous_friction: float = 0.0,  # [N m s] b_v, viscous friction at each wheel: tau_f = b_v * omega_wheel.
        coulomb_friction: float = 0.0,  # [N m] tau_c, Coulomb friction at each wheel, smoothed by coulomb_speed.
        coulomb_speed: float = 0.001,  # [rad/s] omega_eps: Coulomb friction is tau_c * tanh(omega_wheel / omega_eps).
        # end of generated keys
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
        # keys from wmr_scenario::schema(), generated: WMR_BLESS=1 cargo test -p wmr-cli --test keys_documented
        mode: str = "pose",  # Pose mode (reach x, y, theta: theta_R = 2 alpha - theta_d) or position mode (heading free: theta_R = alpha).
        kp_theta: float = 2.0,  # [rad/rad] Kp_theta, rad of heading command per rad of error (paper: 2).
        ki_theta: float = 0.1,  # [1/s] Ki_theta (paper: 0.1).
        kp_s: float = 1.0,  # [m/m] Kp_s, m of path command per m of error (paper: 1).
        ki_s: float = 0.25,  # [1/s] Ki_s (paper: 0.25).
        goal_radius: float = 0.001,  # [m] Within this distance of the goal alpha keeps its last value.
        hold_radius: float = 0.005,  # [m] Within this distance of the goal the outer errors are zero and the outer integrators stop (0: off).
        hold: str = "auto",  # The hold: auto (zero_errors in pose mode, freeze in position mode), zero_errors (references step on entry) or freeze (bumpless).
        anti_windup: str = "off",  # Anti-windup of the integrators (outer loops and wheel servos): off (as printed in the paper) or conditional (they hold while the wheels saturate).
        servo_kp: float = 14.0,  # [N m/rad or V/rad] Wheel servo Kp (the unit follows the drive: torque or dc_motor).
        servo_kd: float = 1.4,  # [N m s/rad or V s/rad] Wheel servo Kd.
        servo_ki: float = 0.0,  # [N m/(rad s) or V/(rad s)] Wheel servo Ki.
        wheel_speed_max: float = math.inf,  # [rad/s] Per-wheel speed limit (inf: off), on the references with the curvature kept.
        control_dt: float = 0.001,  # [s] Control period: the law, the servos and the sensor tick at this rate.
        # end of generated keys
    ) -> Self: ...
    def update(
        self,
        pose: _ArrayLike,
        wheel_angles: _ArrayLike,
        wheel_speeds: _ArrayLike,
        reference: Optional[_ReferenceLike] = None,
    ) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch of (N, 3) poses, (N, 2) wheel angles and (N, 2) wheel speeds.
        reference: the reference tracked at this tick (default: the goal at rest, or a
        tracking law's Reference at the tick's time), a dict
        {"pose": (x, y, theta rad), "twist": (v m/s, omega rad/s), "accel": (v' m/s^2,
        omega' rad/s^2)}, a row of those 7 numbers or an (N, 7) array (or one row for all)."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Optional[Tuple[float, float, float]]:
        """The goal (x_m, y_m, theta_rad) of C; None for a tracking law."""
    @property
    def reference(self) -> Optional[Reference]:
        """The Reference a tracking law follows; None for a stabilization law."""
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
        # keys from wmr_scenario::schema(), generated: WMR_BLESS=1 cargo test -p wmr-cli --test keys_documented
        kp_theta: float = 0.0,  # [rad/rad] Kp_theta, rad of heading command per rad of error (0: no step when e_theta jumps).
        ki_theta: float = 1.0,  # [1/s] Ki_theta; below the bound the approach to the goal is unstable.
        kp_s: float = 0.0,  # [m/m] Kp_s, m of path command per m of error (0: no lunge when e_s swings as the robot turns).
        ki_s: float = 0.25,  # [1/s] Ki_s.
        goal_radius: float = 0.001,  # [m] Within this distance of the goal alpha keeps its last value.
        hold_radius: float = 0.005,  # [m] Within this distance of the goal the outer loops hold (0: off).
        hold: str = "freeze",  # The hold: freeze (bumpless; auto is the same) or zero_errors.
        servo_kp: float = 14.0,  # [N m/rad or V/rad] Wheel servo Kp (the unit follows the drive: torque or dc_motor).
        servo_kd: float = 1.4,  # [N m s/rad or V s/rad] Wheel servo Kd.
        servo_ki: float = 0.0,  # [N m/(rad s) or V/(rad s)] Wheel servo Ki.
        wheel_speed_max: float = math.inf,  # [rad/s] Per-wheel speed limit (inf: off), on the references with the curvature kept.
        control_dt: float = 0.001,  # [s] Control period: the law, the servos and the sensor tick at this rate.
        # end of generated keys
    ) -> Self: ...
    def update(
        self,
        pose: _ArrayLike,
        wheel_angles: _ArrayLike,
        wheel_speeds: _ArrayLike,
        reference: Optional[_ReferenceLike] = None,
    ) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch of (N, 3) poses, (N, 2) wheel angles and (N, 2) wheel speeds.
        reference: the reference tracked at this tick (default: the goal at rest, or a
        tracking law's Reference at the tick's time), a dict
        {"pose": (x, y, theta rad), "twist": (v m/s, omega rad/s), "accel": (v' m/s^2,
        omega' rad/s^2)}, a row of those 7 numbers or an (N, 7) array (or one row for all)."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Optional[Tuple[float, float, float]]:
        """The goal (x_m, y_m, theta_rad) of C; None for a tracking law."""
    @property
    def reference(self) -> Optional[Reference]:
        """The Reference a tracking law follows; None for a stabilization law."""
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
        # keys from wmr_scenario::schema(), generated: WMR_BLESS=1 cargo test -p wmr-cli --test keys_documented
        k_rho: float = 0.5,  # [1/s] k_rho: forward speed per metre of distance.
        k_alpha: float = 3.0,  # [1/s] k_alpha: yaw rate per rad of alpha.
        k_beta: float = -1.2,  # [1/s] k_beta: yaw rate per rad of beta.
        reverse: bool = True,  # Drive backwards when the goal is behind (false: always forward).
        reverse_hysteresis: float = 0.5235987755982989,  # [rad] Overshoot of |alpha| past pi/2 before a later direction switch.
        goal_radius: float = 0.001,  # [m] Within this distance of the goal the law stops; it resumes beyond twice that.
        servo_kp: float = 14.0,  # [N m/rad or V/rad] Wheel servo Kp (the unit follows the drive: torque or dc_motor).
        servo_kd: float = 1.4,  # [N m s/rad or V s/rad] Wheel servo Kd.
        servo_ki: float = 0.0,  # [N m/(rad s) or V/(rad s)] Wheel servo Ki.
        wheel_speed_max: float = math.inf,  # [rad/s] Per-wheel speed limit (inf: off), on the references with the curvature kept.
        control_dt: float = 0.001,  # [s] Control period: the law, the servos and the sensor tick at this rate.
        # end of generated keys
    ) -> Self: ...
    def update(
        self,
        pose: _ArrayLike,
        wheel_angles: _ArrayLike,
        wheel_speeds: _ArrayLike,
        reference: Optional[_ReferenceLike] = None,
    ) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch of (N, 3) poses, (N, 2) wheel angles and (N, 2) wheel speeds.
        reference: the reference tracked at this tick (default: the goal at rest, or a
        tracking law's Reference at the tick's time), a dict
        {"pose": (x, y, theta rad), "twist": (v m/s, omega rad/s), "accel": (v' m/s^2,
        omega' rad/s^2)}, a row of those 7 numbers or an (N, 7) array (or one row for all)."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Optional[Tuple[float, float, float]]:
        """The goal (x_m, y_m, theta_rad) of C; None for a tracking law."""
    @property
    def reference(self) -> Optional[Reference]:
        """The Reference a tracking law follows; None for a stabilization law."""
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
        # keys from wmr_scenario::schema(), generated: WMR_BLESS=1 cargo test -p wmr-cli --test keys_documented
        gamma: float = 0.5,  # [1/s] gamma: forward speed per metre of distance, times cos(alpha).
        k: float = 3.0,  # [1/s] k: yaw rate per rad of alpha.
        h: float = 9.0,  # h: weight of theta_A against alpha in V.
        reverse: bool = True,  # Drive backwards when the goal is behind (false: always start forward).
        reverse_hysteresis: float = 0.5235987755982989,  # [rad] Overshoot of |alpha| past pi/2 before a later direction switch.
        goal_radius: float = 0.001,  # [m] Within this distance of the goal the law stops.
        servo_kp: float = 14.0,  # [N m/rad or V/rad] Wheel servo Kp (the unit follows the drive: torque or dc_motor).
        servo_kd: float = 1.4,  # [N m s/rad or V s/rad] Wheel servo Kd.
        servo_ki: float = 0.0,  # [N m/(rad s) or V/(rad s)] Wheel servo Ki.
        wheel_speed_max: float = math.inf,  # [rad/s] Per-wheel speed limit (inf: off), on the references with the curvature kept.
        control_dt: float = 0.001,  # [s] Control period: the law, the servos and the sensor tick at this rate.
        # end of generated keys
    ) -> Self: ...
    def update(
        self,
        pose: _ArrayLike,
        wheel_angles: _ArrayLike,
        wheel_speeds: _ArrayLike,
        reference: Optional[_ReferenceLike] = None,
    ) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch of (N, 3) poses, (N, 2) wheel angles and (N, 2) wheel speeds.
        reference: the reference tracked at this tick (default: the goal at rest, or a
        tracking law's Reference at the tick's time), a dict
        {"pose": (x, y, theta rad), "twist": (v m/s, omega rad/s), "accel": (v' m/s^2,
        omega' rad/s^2)}, a row of those 7 numbers or an (N, 7) array (or one row for all)."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Optional[Tuple[float, float, float]]:
        """The goal (x_m, y_m, theta_rad) of C; None for a tracking law."""
    @property
    def reference(self) -> Optional[Reference]:
        """The Reference a tracking law follows; None for a stabilization law."""
    @property
    def kind(self) -> str: ...
    @property
    def n(self) -> int:
        """Robots in the batch (1 for single calls)."""
    @property
    def scenario_toml(self) -> str: ...


@final
class KanayamaController:
    """Kanayama et al.'s trajectory tracking law (kind "kanayama"), following a Reference."""

    def __new__(
        cls,
        reference: Union[Reference, Mapping[str, Any]],
        robot: Union[None, Robot, Mapping[str, float]] = None,
        drive: Optional[Mapping[str, Any]] = None,
        *,
        # keys from wmr_scenario::schema(), generated: WMR_BLESS=1 cargo test -p wmr-cli --test keys_documented
        kx: float = 10.0,  # [1/s] kx: forward speed per metre of along-track error.
        ky: float = 64.0,  # [1/m^2] ky: yaw rate per metre of lateral error, per m/s of v_ref.
        ktheta: float = 16.0,  # [1/m] ktheta: yaw rate per unit of sin(heading error), per m/s of v_ref.
        servo_kp: float = 14.0,  # [N m/rad or V/rad] Wheel servo Kp (the unit follows the drive: torque or dc_motor).
        servo_kd: float = 1.4,  # [N m s/rad or V s/rad] Wheel servo Kd.
        servo_ki: float = 0.0,  # [N m/(rad s) or V/(rad s)] Wheel servo Ki.
        wheel_speed_max: float = math.inf,  # [rad/s] Per-wheel speed limit (inf: off), on the references with the curvature kept.
        control_dt: float = 0.001,  # [s] Control period: the law, the servos and the sensor tick at this rate.
        # end of generated keys
    ) -> Self: ...
    def update(
        self,
        pose: _ArrayLike,
        wheel_angles: _ArrayLike,
        wheel_speeds: _ArrayLike,
        reference: Optional[_ReferenceLike] = None,
    ) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch. reference: the reference state at this tick (default: the
        class's Reference at the tick's time, tick k at k control_dt), as for PaperController."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Optional[Tuple[float, float, float]]:
        """None: a tracking law follows ``reference``."""
    @property
    def reference(self) -> Optional[Reference]:
        """The Reference the law follows."""
    @property
    def kind(self) -> str: ...
    @property
    def n(self) -> int:
        """Robots in the batch (1 for single calls)."""
    @property
    def scenario_toml(self) -> str: ...


@final
class BacksteppingController:
    """Kanayama's twist back-stepped into the dynamics (kind "backstepping"), following a Reference."""

    def __new__(
        cls,
        reference: Union[Reference, Mapping[str, Any]],
        robot: Union[None, Robot, Mapping[str, float]] = None,
        drive: Optional[Mapping[str, Any]] = None,
        *,
        # keys from wmr_scenario::schema(), generated: WMR_BLESS=1 cargo test -p wmr-cli --test keys_documented
        kx: float = 10.0,  # [1/s] kx: Kanayama's forward speed per metre of along-track error.
        ky: float = 64.0,  # [1/m^2] ky: Kanayama's yaw rate per metre of lateral error, per m/s of v_ref.
        ktheta: float = 16.0,  # [1/m] ktheta: Kanayama's yaw rate per unit of sin(heading error), per m/s of v_ref.
        k4: float = 20.0,  # [1/s] k4: rate at which the body twist is driven to Kanayama's.
        servo_kp: float = 14.0,  # [N m/rad or V/rad] Wheel servo Kp (the unit follows the drive: torque or dc_motor).
        servo_kd: float = 1.4,  # [N m s/rad or V s/rad] Wheel servo Kd.
        servo_ki: float = 0.0,  # [N m/(rad s) or V/(rad s)] Wheel servo Ki.
        wheel_speed_max: float = math.inf,  # [rad/s] Per-wheel speed limit (inf: off), on the references with the curvature kept.
        control_dt: float = 0.001,  # [s] Control period: the law, the servos and the sensor tick at this rate.
        # end of generated keys
    ) -> Self: ...
    def update(
        self,
        pose: _ArrayLike,
        wheel_angles: _ArrayLike,
        wheel_speeds: _ArrayLike,
        reference: Optional[_ReferenceLike] = None,
    ) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch. reference: the reference state at this tick (default: the
        class's Reference at the tick's time, tick k at k control_dt), as for PaperController."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Optional[Tuple[float, float, float]]:
        """None: a tracking law follows ``reference``."""
    @property
    def reference(self) -> Optional[Reference]:
        """The Reference the law follows."""
    @property
    def kind(self) -> str: ...
    @property
    def n(self) -> int:
        """Robots in the batch (1 for single calls)."""
    @property
    def scenario_toml(self) -> str: ...


@final
class PurePursuitController:
    """Regulated pure pursuit (kind "pure_pursuit"), following a Reference's path."""

    def __new__(
        cls,
        reference: Union[Reference, Mapping[str, Any]],
        robot: Union[None, Robot, Mapping[str, float]] = None,
        drive: Optional[Mapping[str, Any]] = None,
        *,
        # keys from wmr_scenario::schema(), generated: WMR_BLESS=1 cargo test -p wmr-cli --test keys_documented
        speed: float = 0.3,  # [m/s] speed: the forward speed on a straight path (nav2's desired_linear_vel).
        lookahead_time: float = 1.5,  # [s] The lookahead distance per m/s of speed.
        min_lookahead_dist: float = 0.3,  # [m] The shortest lookahead distance.
        max_lookahead_dist: float = 0.9,  # [m] The longest lookahead distance.
        regulated_linear_scaling_min_radius: float = 0.9,  # [m] Below this turning radius the speed is scaled down in proportion.
        regulated_linear_scaling_min_speed: float = 0.25,  # [m/s] The curvature scaling never brings the speed below this.
        approach_velocity_scaling_dist: float = 0.6,  # [m] Within this path length of the end the speed is scaled down in proportion.
        min_approach_linear_velocity: float = 0.05,  # [m/s] The approach scaling never brings the speed below this.
        xy_goal_tolerance: float = 0.01,  # [m] Within this distance of the path's end the law stops.
        servo_kp: float = 14.0,  # [N m/rad or V/rad] Wheel servo Kp (the unit follows the drive: torque or dc_motor).
        servo_kd: float = 1.4,  # [N m s/rad or V s/rad] Wheel servo Kd.
        servo_ki: float = 0.0,  # [N m/(rad s) or V/(rad s)] Wheel servo Ki.
        wheel_speed_max: float = math.inf,  # [rad/s] Per-wheel speed limit (inf: off), on the references with the curvature kept.
        control_dt: float = 0.001,  # [s] Control period: the law, the servos and the sensor tick at this rate.
        # end of generated keys
    ) -> Self: ...
    def update(
        self,
        pose: _ArrayLike,
        wheel_angles: _ArrayLike,
        wheel_speeds: _ArrayLike,
        reference: Optional[_ReferenceLike] = None,
    ) -> Any:
        """One tick: (tau_r, tau_l) in N m (before the drive's clamp) for one robot, or an
        (N, 2) array for a batch. reference: the reference state at this tick (default: the
        class's Reference at the tick's time, tick k at k control_dt), as for PaperController."""
    def reset(self) -> None: ...
    @property
    def errors(self) -> Any:
        """(e_s in m, e_theta in rad, dl in m) of the last update, (N, 3) after a batched one."""
    @property
    def control_dt(self) -> float: ...
    @property
    def goal(self) -> Optional[Tuple[float, float, float]]:
        """None: a tracking law follows ``reference``."""
    @property
    def reference(self) -> Optional[Reference]:
        """The Reference the law follows."""
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
    def tracking(self) -> bool:
        """True for a tracking run (a scenario with a [reference])."""
    @property
    def rms_error(self) -> Optional[float]:
        """Tracking run: RMS tracking error over the last half of t_end, m."""
    @property
    def max_error(self) -> Optional[float]:
        """Tracking run: largest tracking error over the last half of t_end, m."""
    @property
    def time_to_tolerance(self) -> Optional[float]:
        """Tracking run: time after which the error stays below the tolerance, s."""
    @property
    def final_error(self) -> Optional[float]:
        """Tracking run: the error at the last step, m."""
    @property
    def tracking_tolerance(self) -> Optional[float]:
        """Tracking run: sim.tracking_tolerance, m."""
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
    @property
    def x_odom(self) -> _FloatArray:
        """Run on odometry only (AttributeError otherwise), m."""
    @property
    def y_odom(self) -> _FloatArray:
        """Run on odometry only, m."""
    @property
    def theta_odom(self) -> _FloatArray:
        """Run on odometry only, rad."""
    @property
    def slip_r(self) -> _FloatArray:
        """Run whose wheels slip only (AttributeError otherwise), m/s."""
    @property
    def slip_l(self) -> _FloatArray:
        """Run whose wheels slip only, m/s."""
    @property
    def v_lat(self) -> _FloatArray:
        """Run whose wheels slip only, m/s."""
    @property
    def fx_r(self) -> _FloatArray:
        """Run whose wheels slip only, N."""
    @property
    def fx_l(self) -> _FloatArray:
        """Run whose wheels slip only, N."""
    @property
    def fy_r(self) -> _FloatArray:
        """Run whose wheels slip only, N."""
    @property
    def fy_l(self) -> _FloatArray:
        """Run whose wheels slip only, N."""
    @property
    def n_r(self) -> _FloatArray:
        """Run whose wheels slip only, N."""
    @property
    def n_l(self) -> _FloatArray:
        """Run whose wheels slip only, N."""
    @property
    def x_ref(self) -> _FloatArray:
        """Tracking run only (AttributeError otherwise), m."""
    @property
    def y_ref(self) -> _FloatArray:
        """Tracking run only, m."""
    @property
    def theta_ref(self) -> _FloatArray:
        """Tracking run only, rad."""
    @property
    def v_ref(self) -> _FloatArray:
        """Tracking run only, m/s."""
    @property
    def omega_ref(self) -> _FloatArray:
        """Tracking run only, rad/s."""
    @property
    def column_names(self) -> list[str]:
        """The run's columns in CSV order (the measured pose always)."""
    def __getitem__(self, name: str, /) -> _FloatArray: ...
    def __len__(self) -> int: ...
    def columns(self) -> dict[str, _FloatArray]:
        """Every CSV column (``run`` first), in CSV order."""
    def to_pandas(self) -> Any:
        """Every column with ``run`` and ``label``, one row per sample (needs pandas); a
        tracking run's summary in ``df.attrs``."""
    def to_xarray(self) -> Any:
        """Every column along ``t`` with its units, the summary as attributes (needs xarray)."""
    def __getstate__(self) -> dict[str, Any]: ...

__version__: str
COLUMNS: Tuple[str, ...]
COLUMN_UNITS: Tuple[str, ...]
CSV_COLUMNS: Tuple[str, ...]
MEASURED_COLUMNS: Tuple[str, ...]
ODOMETRY_COLUMNS: Tuple[str, ...]
ODOMETRY_UNITS: Tuple[str, ...]
CONTACT_COLUMNS: Tuple[str, ...]
CONTACT_UNITS: Tuple[str, ...]
OUTCOME_FIELDS: Tuple[str, ...]
_SWEEP_ROW_LEN: int
ARRIVAL_RADIUS_M: float
REFERENCE_COLUMNS: Tuple[str, ...]
REFERENCE_UNITS: Tuple[str, ...]
TRACKING_FIELDS: Tuple[str, ...]

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
    "BacksteppingController",
    "KanayamaController",
    "PurePursuitController",
    "Reference",
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
    "_SWEEP_ROW_LEN",
    "COLUMN_UNITS",
    "CSV_COLUMNS",
    "MEASURED_COLUMNS",
    "ODOMETRY_COLUMNS",
    "ODOMETRY_UNITS",
    "CONTACT_COLUMNS",
    "CONTACT_UNITS",
    "OUTCOME_FIELDS",
    "ARRIVAL_RADIUS_M",
    "REFERENCE_COLUMNS",
    "REFERENCE_UNITS",
    "TRACKING_FIELDS",
]
