"""Bad input raises a ValueError subclass whose message (and `key`) names the key; no
panic, no NaN returned silently."""

from __future__ import annotations

import math

import numpy as np
import pytest

import wmr_py

NAN, INF = float("nan"), float("inf")
GOAL = {"x": 1.0, "y": 1.0, "theta_deg": 120.0}


def scenario(**tables) -> dict:
    sc = {"sim": {"t_end": 0.1}, "run": [{"goal": GOAL}]}
    sc.update(tables)
    return sc


# (name, callable, expected key). Same kinds as the CLI's bad-input corpus.
CASES = [
    ("unknown top-level key", lambda: wmr_py.run_scenario(scenario(robto={"mass": 1.0})), "robto"),
    ("unknown robot key", lambda: wmr_py.run_scenario(scenario(robot={"mas": 1.0})), "robot.mas"),
    ("unknown controller key", lambda: wmr_py.simulate((0, 0, 0), GOAL, controller={"kp_thta": 1.0}), "controller.kp_thta"),
    ("NaN mass", lambda: wmr_py.run_scenario(scenario(robot={"mass": NAN})), "robot.mass"),
    ("inf wheel radius", lambda: wmr_py.run_scenario(scenario(robot={"wheel_radius": INF})), "robot.wheel_radius"),
    ("negative mass", lambda: wmr_py.Robot(mass=-1.0), "robot.mass"),
    ("negative wheel inertia", lambda: wmr_py.simulate((0, 0, 0), GOAL, robot={"wheel_inertia": -0.1}), "robot.wheel_inertia"),
    ("zero dt", lambda: wmr_py.simulate((0, 0, 0), GOAL, dt=0.0), "sim.dt"),
    ("dt not dividing control_dt", lambda: wmr_py.simulate((0, 0, 0), GOAL, dt=3e-4, log_dt=3e-3, t_end=0.3), "controller.control_dt"),
    ("log_dt not a multiple of dt", lambda: wmr_py.simulate((0, 0, 0), GOAL, log_dt=0.0105), "sim.log_dt"),
    ("negative t_end", lambda: wmr_py.simulate((0, 0, 0), GOAL, t_end=-1.0), "sim.t_end"),
    ("both theta and theta_deg", lambda: wmr_py.simulate({"x": 0, "y": 0, "theta": 0.1, "theta_deg": 5}, GOAL), "run[0].start.theta_deg"),
    ("NaN start", lambda: wmr_py.simulate((0.0, NAN, 0.0), GOAL), "run[0].start.y"),
    ("inf goal", lambda: wmr_py.simulate((0, 0, 0), (INF, 0.0, 0.0)), "run[0].goal.x"),
    ("missing runs", lambda: wmr_py.run_scenario({"robot": {"mass": 5.0}}), "run"),
    ("run without goal", lambda: wmr_py.run_scenario({"run": [{"start": {"x": 1.0}}]}), "run[0].goal"),
    ("wrong type", lambda: wmr_py.run_scenario(scenario(robot={"mass": "heavy"})), "robot.mass"),
    ("unknown drive kind", lambda: wmr_py.simulate((0, 0, 0), GOAL, drive={"kind": "jet"}), "drive.kind"),
    ("NaN motor torque limit", lambda: wmr_py.simulate((0, 0, 0), GOAL, drive={"motor_torque_max": NAN}), "drive.motor_torque_max"),
    ("bad controller mode", lambda: wmr_py.PaperController((1, 1, 0), mode="fast"), "controller.mode"),
    ("negative gain", lambda: wmr_py.PaperController((1, 1, 0), kp_s=-1.0), "controller.kp_s"),
    ("NaN state", lambda: wmr_py.Robot().step([0, 0, NAN, 0, 0, 0, 0], (0, 0), 1e-3), "state[2]"),
    ("short state", lambda: wmr_py.Robot().derivative([0, 0, 0], (0, 0)), "state"),
    ("inf torque", lambda: wmr_py.Robot().step(np.zeros(7), (INF, 0.0), 1e-3), "tau[0]"),
    ("NaN dt", lambda: wmr_py.Robot().step(np.zeros(7), (0.0, 0.0), NAN), "dt"),
    ("NaN measured pose", lambda: wmr_py.PaperController((1, 1, 0)).update((0, NAN, 0), (0, 0), (0, 0)), "pose[1]"),
    ("NaN batch start", lambda: wmr_py.run_batch(np.array([[0, 0, 0], [0, NAN, 0]]), GOAL, t_end=0.1), "starts[1, 1]"),
    ("batch starts of wrong shape", lambda: wmr_py.run_batch(np.zeros((3, 2)), GOAL), "starts"),
]


@pytest.mark.parametrize("name, call, key", CASES, ids=[c[0] for c in CASES])
def test_bad_input_names_the_key(name: str, call, key: str) -> None:
    with pytest.raises(ValueError) as info:
        call()
    err = info.value
    assert isinstance(err, wmr_py.ParameterError), type(err)
    assert err.key == key, f"{name}: key {err.key!r}, message {err}"
    assert key in str(err)


def test_enough_cases() -> None:
    assert len(CASES) >= 15


def test_bad_toml_text_gives_line() -> None:
    with pytest.raises(wmr_py.ScenarioError) as info:
        wmr_py.run_scenario("[robot]\nmass = -1.0\n[[run]]\ngoal = { x = 1.0 }\n")
    assert info.value.key == "robot.mass" and info.value.line == 2
    with pytest.raises(wmr_py.ScenarioError) as info:
        wmr_py.run_scenario("[robot\nmass = 1\n")
    assert info.value.line == 1  # a TOML syntax error: no key, but the line


def test_missing_file_is_a_file_not_found_error(tmp_path) -> None:
    """As open() would: FileNotFoundError with errno and filename (issue 12, defect 14)."""
    missing = tmp_path / "nope.toml"
    with pytest.raises(FileNotFoundError) as info:
        wmr_py.run_scenario(missing)
    assert info.value.errno == 2 and info.value.filename == str(missing)
    assert info.value.key == "scenario"


def test_scenario_error_is_a_parameter_error_is_a_value_error() -> None:
    assert issubclass(wmr_py.ScenarioError, wmr_py.ParameterError)
    assert issubclass(wmr_py.ParameterError, ValueError)


def test_overflowing_step_raises_instead_of_returning_inf() -> None:
    """Finite but huge inputs: the result is not finite, so it is an error, not an array of inf."""
    with pytest.raises(FloatingPointError):
        wmr_py.Robot().step([0, 0, 0, 1e300, 1e300, 0, 0], (0, 0), 1.0)


def test_inf_motor_torque_limit_is_allowed() -> None:
    r = wmr_py.simulate((0, 0, 0), GOAL, drive={"motor_torque_max": math.inf}, t_end=0.1)
    assert np.isfinite(r.x).all() and np.max(np.abs(r.tau_r)) > 2.0
