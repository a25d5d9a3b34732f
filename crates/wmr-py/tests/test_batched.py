"""Loops closed in Python over N robots at once (issue 14): the batched Robot methods and
law classes are the single-robot calls row by row, and every law's loop closed in Python
ends where run_batch's Rust loop does."""

from __future__ import annotations

import numpy as np
import pytest

import wmr_py

CLASSES = {
    "paper": wmr_py.PaperController,
    "paper_bidirectional": wmr_py.PaperBidirectionalController,
    "polar": wmr_py.PolarController,
    "lyapunov": wmr_py.LyapunovController,
}


def states(n: int, seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    s = rng.uniform(-1.0, 1.0, (n, 7))
    s[:, 3:5] *= 0.5
    return s


def test_robot_batch_is_row_by_row() -> None:
    robot = wmr_py.Robot(viscous_friction=0.02, coulomb_friction=0.01)
    s = states(9)
    tau = np.random.default_rng(2).uniform(-2, 2, (9, 2))
    step = robot.step(s, tau, 1e-3)
    deriv = robot.derivative(s, tau)
    ws = robot.wheel_speeds(s)
    ke = robot.kinetic_energy(s)
    assert step.shape == deriv.shape == (9, 7) and ws.shape == (9, 2) and ke.shape == (9,)
    for i in range(9):
        assert np.array_equal(step[i], robot.step(s[i], tau[i], 1e-3))
        assert np.array_equal(deriv[i], robot.derivative(s[i], tau[i]))
        assert tuple(ws[i]) == robot.wheel_speeds(s[i])
        assert ke[i] == robot.kinetic_energy(s[i])
    # Lists of rows and non-contiguous views are batches too.
    assert np.array_equal(robot.step(s.tolist(), tau.tolist(), 1e-3), step)
    wide = np.zeros((9, 10))
    wide[:, :7] = s
    assert np.array_equal(robot.step(wide[:, :7], tau, 1e-3), step)


def test_batch_errors_name_the_argument() -> None:
    robot = wmr_py.Robot()
    s = states(4)
    s[2, 3] = np.nan
    with pytest.raises(wmr_py.ParameterError) as e:
        robot.step(s, np.zeros((4, 2)), 1e-3)
    assert e.value.key == "state[2, 3]"
    with pytest.raises(wmr_py.ParameterError) as e:
        robot.step(states(4), np.zeros((3, 2)), 1e-3)
    assert e.value.key == "tau"
    with pytest.raises(wmr_py.ParameterError) as e:
        robot.step(states(4), np.zeros(2), 1e-3)
    assert e.value.key == "tau"
    with pytest.raises(wmr_py.ParameterError) as e:
        robot.step(np.zeros((4, 6)), np.zeros((4, 2)), 1e-3)
    assert e.value.key == "state"
    with pytest.raises(FloatingPointError, match="robot 1"):
        big = states(3)
        big[1, 3] = 1e300
        robot.step(big, np.zeros((3, 2)), 1e-3)


@pytest.mark.parametrize("kind", list(CLASSES))
def test_law_batch_is_n_controllers(kind: str) -> None:
    n = 6
    batch = CLASSES[kind]((0.3, -0.2, 0.5))
    singles = [CLASSES[kind]((0.3, -0.2, 0.5)) for _ in range(n)]
    rng = np.random.default_rng(3)
    for _ in range(4):
        pose = rng.uniform(-1, 1, (n, 3))
        angles = rng.uniform(-3, 3, (n, 2))
        speeds = rng.uniform(-5, 5, (n, 2))
        out = batch.update(pose, angles, speeds)
        assert out.shape == (n, 2) and batch.errors.shape == (n, 3) and batch.n == n
        for i, c in enumerate(singles):
            assert tuple(out[i]) == c.update(pose[i], angles[i], speeds[i]), (kind, i)
            assert tuple(batch.errors[i]) == c.errors
    # The batch is fixed once running; reset() frees it.
    with pytest.raises(wmr_py.ParameterError) as e:
        batch.update(np.zeros((n + 1, 3)), np.zeros((n + 1, 2)), np.zeros((n + 1, 2)))
    assert e.value.key == "pose"
    with pytest.raises(wmr_py.ParameterError) as e:
        batch.update(np.zeros((n, 3)), np.zeros((n - 1, 2)), np.zeros((n, 2)))
    assert e.value.key == "wheel_angles"
    batch.reset()
    assert batch.update(np.zeros((2, 3)), np.zeros((2, 2)), np.zeros((2, 2))).shape == (2, 2)


def test_a_failed_batch_tick_changes_nothing() -> None:
    c = wmr_py.PaperController((1.0, 1.0, 0.0))
    pose = np.zeros((3, 3))
    first = c.update(pose, np.zeros((3, 2)), np.zeros((3, 2)))
    huge = np.zeros((3, 2))
    huge[2] = 1e308
    with pytest.raises(FloatingPointError, match="robot 2"):
        c.update(pose, huge, huge)
    ref = wmr_py.PaperController((1.0, 1.0, 0.0))
    ref.update(pose, np.zeros((3, 2)), np.zeros((3, 2)))
    assert np.array_equal(c.update(pose, np.zeros((3, 2)), np.zeros((3, 2))), ref.update(pose, np.zeros((3, 2)), np.zeros((3, 2))))
    assert first.shape == (3, 2)


def test_law_class_refuses_another_kind() -> None:
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.PolarController((0, 0, 0), kind="paper")
    assert e.value.key == "controller.kind"
    with pytest.raises(wmr_py.ScenarioError) as e:
        wmr_py.LyapunovController((0, 0, 0), kp_s=1.0)
    assert "kp_s" in e.value.key


@pytest.mark.parametrize("kind", list(CLASSES))
def test_batched_loop_in_python_is_run_batch(kind: str) -> None:
    """Every law closed in Python over a batch (control every step, torque clamp, RK4)
    ends where run_batch's Rust loop ends, start by start."""
    rng = np.random.default_rng(5)
    n, steps, dt = 8, 3000, 1e-3
    starts = np.column_stack([rng.uniform(-1.5, 1.5, (n, 2)), rng.uniform(-np.pi, np.pi, n)])
    goal = (0.2, -0.1, 0.4)
    robot = wmr_py.Robot()
    ctrl = CLASSES[kind](goal, robot)
    tau_max = 0.2 / robot.gear_ratio
    state = np.zeros((n, 7))
    state[:, :3] = starts
    for _ in range(steps):
        tau = ctrl.update(state[:, :3], state[:, 5:7], robot.wheel_speeds(state))
        np.clip(tau, -tau_max, tau_max, out=tau)
        state = robot.step(state, tau, dt)
    ref = wmr_py.run_batch(starts, goal, t_end=steps * dt, controller={"kind": kind})
    final = np.column_stack([ref["final_x_m"], ref["final_y_m"], np.radians(ref["final_theta_deg"])])
    np.testing.assert_allclose(state[:, :3], final, rtol=0, atol=1e-9)
    # The loop did something: the robots moved.
    assert np.min(np.linalg.norm(state[:, :2] - starts[:, :2], axis=1)) > 1e-3
