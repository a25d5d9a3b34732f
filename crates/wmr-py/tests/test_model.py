"""Robot and PaperController against independent numpy computations."""

from __future__ import annotations

import math

import numpy as np
import pytest

import wmr_py


def reduced_inertia(p: dict) -> tuple[float, float]:
    """M_r11 = m + 2 I_m / r^2, M_r22 = I_p + 2 R^2 I_m / r^2 + m d^2 (docs/model.md)."""
    m, r, big_r, d = p["mass"], p["wheel_radius"], p["half_track"], p["com_offset"]
    i_m, i_p = p["wheel_inertia"], p["platform_inertia"]
    return m + 2 * i_m / r**2, i_p + 2 * big_r**2 * i_m / r**2 + m * d**2


def test_robot_defaults_and_properties() -> None:
    robot = wmr_py.Robot()
    assert robot.mass == 5.0 and robot.wheel_radius == 0.1 and robot.half_track == 0.2
    assert robot.com_offset == 0.25 and robot.gear_ratio == 0.1
    p = robot.to_dict()
    assert robot.reduced_inertia == pytest.approx(reduced_inertia(p), rel=1e-15)
    assert wmr_py.Robot(mass=7.0).mass == 7.0
    assert wmr_py.Robot(**p) == robot


def test_static_friction_is_a_robot_key() -> None:
    """Issue 42: stiction's breakaway torque, 0 (off) by default, >= coulomb_friction."""
    assert wmr_py.Robot().static_friction == 0.0
    robot = wmr_py.Robot(coulomb_friction=0.1, coulomb_speed=0.01, static_friction=0.2)
    assert robot.static_friction == 0.2 and robot.to_dict()["static_friction"] == 0.2
    assert wmr_py.Robot(**robot.to_dict()) == robot
    with pytest.raises(wmr_py.ScenarioError) as e:
        wmr_py.Robot(coulomb_friction=0.1, coulomb_speed=0.01, static_friction=0.05)
    assert e.value.key == "robot.static_friction"


def test_derivative_matches_equations_of_motion() -> None:
    """The dynamics (15) of docs/model.md, written out in numpy, at a generic state with friction."""
    robot = wmr_py.Robot(viscous_friction=0.05, coulomb_friction=0.02, coulomb_speed=0.5)
    p = robot.to_dict()
    m11, m22 = reduced_inertia(p)
    r, big_r, md = p["wheel_radius"], p["half_track"], p["mass"] * p["com_offset"]
    s = np.array([0.3, -0.2, 0.7, 0.4, -0.9, 1.0, 2.0])
    tau = (0.8, -0.3)
    x, y, th, v, om = s[:5]
    w_r, w_l = (v + big_r * om) / r, (v - big_r * om) / r
    fric = lambda w: p["viscous_friction"] * w + p["coulomb_friction"] * math.tanh(w / p["coulomb_speed"])  # noqa: E731
    n_r, n_l = tau[0] - fric(w_r), tau[1] - fric(w_l)
    expected = [
        v * math.cos(th),
        v * math.sin(th),
        om,
        ((n_r + n_l) / r + md * om**2) / m11,
        ((big_r / r) * (n_r - n_l) - md * v * om) / m22,
        w_r,
        w_l,
    ]
    got = robot.derivative(s, tau)
    assert got.dtype == np.float64 and got.shape == (7,)
    np.testing.assert_allclose(got, expected, rtol=1e-13, atol=1e-15)


def test_kinetic_energy_conserved_without_torque_or_friction() -> None:
    """Zero torque, zero friction: T = 1/2 M11 v^2 + 1/2 M22 omega^2 is constant (the
    Coriolis terms do no work); RK4's drift over 5 s at dt = 1 ms stays below 1e-9."""
    robot = wmr_py.Robot()
    m11, m22 = reduced_inertia(robot.to_dict())
    state = np.array([0.0, 0.0, 0.3, 0.5, 2.0, 0.0, 0.0])
    energy = lambda s: 0.5 * m11 * s[3] ** 2 + 0.5 * m22 * s[4] ** 2  # noqa: E731
    e0 = energy(state)
    assert robot.kinetic_energy(state) == pytest.approx(e0, rel=1e-15)
    worst = 0.0
    for _ in range(5000):
        state = robot.step(state, (0.0, 0.0), 1e-3)
        worst = max(worst, abs(energy(state) - e0) / e0)
    assert worst < 1e-9
    # The motion is not trivial: speed went into turning and back (d != 0 couples them).
    assert abs(state[3] - 0.5) > 1e-3


def test_step_is_rk4_of_derivative() -> None:
    """One step equals classic RK4 written in numpy over Robot.derivative."""
    robot = wmr_py.Robot()
    s = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7])
    tau, h = (1.0, -0.5), 1e-2
    f = lambda y: robot.derivative(y, tau)  # noqa: E731
    k1 = f(s)
    k2 = f(s + h / 2 * k1)
    k3 = f(s + h / 2 * k2)
    k4 = f(s + h * k3)
    expected = s + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    np.testing.assert_allclose(robot.step(s, tau, h), expected, rtol=1e-14, atol=1e-16)


def closed_loop_in_python(start, goal, t_end: float, dt: float = 1e-3, log_dt: float = 0.01):
    """The paper's loop (docs/model.md) closed in Python: controller every control_dt (zero-order
    hold), torque drive clamp |tau| <= motor_torque_max / k_t = 2 N m, RK4 plant."""
    robot = wmr_py.Robot()
    ctrl = wmr_py.PaperController(goal, robot)
    tau_max = 0.2 / robot.gear_ratio
    every = round(ctrl.control_dt / dt)
    log_every = round(log_dt / dt)
    state = np.array([*start, 0.0, 0.0, 0.0, 0.0])
    rows = []
    tau = (0.0, 0.0)
    for k in range(round(t_end / dt) + 1):
        if k % every == 0:
            w = robot.wheel_speeds(state)
            cmd = ctrl.update(state[:3], state[5:7], w)
            tau = tuple(float(np.clip(c, -tau_max, tau_max)) for c in cmd)
        if k % log_every == 0:
            rows.append([k * dt, *state, *robot.wheel_speeds(state), *tau, *ctrl.errors])
        if k * dt < t_end - dt / 2:
            state = robot.step(state, tau, dt)
    return np.array(rows)


def test_python_loop_reproduces_simulate() -> None:
    start, goal = (0.0, 0.0, 0.0), (1.0, 1.0, math.radians(120))
    t_end = 15.0
    mine = closed_loop_in_python(start, goal, t_end)
    ref = wmr_py.simulate(start, goal, t_end=t_end)
    names = ["t", "x", "y", "theta", "v", "omega", "phi_r", "phi_l", "omega_r", "omega_l", "tau_r", "tau_l", "e_s", "e_theta", "dl"]
    assert mine.shape == (len(ref), len(names))
    for j, name in enumerate(names):
        np.testing.assert_allclose(mine[:, j], ref[name], rtol=0, atol=1e-9, err_msg=name)
    # Torques hit the clamp early on: the test exercises the drive limit.
    assert np.max(np.abs(ref.tau_r)) == pytest.approx(2.0)


def test_controller_errors_reset_and_goal() -> None:
    ctrl = wmr_py.PaperController({"x": 1.0, "y": 1.0, "theta_deg": 90.0}, kp_s=2.0)
    assert ctrl.goal == pytest.approx((1.0, 1.0, math.pi / 2))
    assert ctrl.control_dt == 1e-3
    first = ctrl.update((0, 0, 0), (0, 0), (0, 0))
    e_s, e_theta, dl = ctrl.errors
    assert dl == pytest.approx(math.sqrt(2))
    # theta_R = 2 alpha - theta_d = 0: the heading error is zero, e_s = dl.
    assert e_theta == pytest.approx(0.0, abs=1e-15) and e_s == pytest.approx(dl)
    second = ctrl.update((0, 0, 0), (0, 0), (0, 0))
    assert second != first  # the integrators moved
    ctrl.reset()
    assert ctrl.update((0, 0, 0), (0, 0), (0, 0)) == first
