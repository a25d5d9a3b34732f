"""Python rough edges of issue 27 and issue 25's item 13, each kept gone by a test."""

from __future__ import annotations

import io
import pickle
import warnings
from concurrent.futures import Future
from pathlib import Path

import numpy as np
import pytest

import wmr_py

ROOT = Path(__file__).resolve().parents[3]
SWEEP = """
[sim]
t_end = 2.0
[sweep]
controllers = [{ kind = "paper" }, { kind = "polar" }]
random = { n = 4, seed = 3, radius = 1.0 }
"""


class Swapping:
    """An executor whose parts come back in the wrong order (or short)."""

    def __init__(self, mode: str) -> None:
        self.mode, self.done = mode, []

    def submit(self, fn, *args):
        f: Future = Future()
        f.set_result(fn(*args))
        self.done.append(f)
        if self.mode == "swap" and len(self.done) == 2:
            a, b = self.done
            ra, rb = a.result(), b.result()
            a._result, b._result = rb, ra
        if self.mode == "short":
            r = dict(f.result())
            r["converged"] = r["converged"][:-1]
            f._result = r
        return f


@pytest.mark.parametrize("mode", ["swap", "short"])
def test_regression_25_13_run_batch_checks_what_the_executors_parts_return(mode: str) -> None:
    starts = np.array([[1.0, 0.5, 0.0], [-1.0, 1.0, 1.0], [0.5, -0.5, 2.0], [0.2, 0.1, 0.0]])
    ex = Swapping(mode)
    with pytest.raises(wmr_py.ParameterError, match="executor: part") as e:
        wmr_py.run_batch(starts, (0, 0, 0), t_end=1.0, executor=ex, chunk_size=2)
    assert e.value.key == "executor"


def test_run_batch_with_an_honest_executor_is_the_local_call() -> None:
    starts = np.array([[1.0, 0.5, 0.0], [-1.0, 1.0, 1.0], [0.5, -0.5, 2.0]])
    local = wmr_py.run_batch(starts, (0, 0, 0), t_end=1.0)
    parts = wmr_py.run_batch(starts, (0, 0, 0), t_end=1.0, executor=Swapping("none"), chunk_size=2)
    assert set(local) == set(parts)
    for k in local:
        np.testing.assert_array_equal(local[k], parts[k])


def test_regression_25_13_wheel_speeds_and_kinetic_energy_raise_where_step_raises() -> None:
    robot = wmr_py.Robot()
    huge = np.array([0.0, 0.0, 0.0, 1e308, 1e308, 0.0, 0.0])
    with pytest.raises(FloatingPointError):
        robot.step(huge, (0.0, 0.0), 1e-3)
    with pytest.raises(FloatingPointError, match="wheel speeds"):
        robot.wheel_speeds(huge)
    with pytest.raises(FloatingPointError, match="kinetic energy"):
        robot.kinetic_energy(huge)
    batch = np.zeros((3, 7))
    batch[1] = huge
    with pytest.raises(FloatingPointError, match="robot 1"):
        robot.wheel_speeds(batch)
    with pytest.raises(FloatingPointError, match="robot 1"):
        robot.kinetic_energy(batch)
    # Finite states are unchanged.
    assert np.all(np.isfinite(robot.wheel_speeds(np.zeros((3, 7)))))


def test_regression_25_13_repr_of_an_empty_result() -> None:
    assert "0 starts" in repr(wmr_py.BatchResult())
    assert "0 runs" in repr(wmr_py.SweepResult())


def test_regression_25_13_a_run_result_state_with_columns_of_different_lengths_is_refused() -> None:
    r = wmr_py.simulate((0, 0, 0), (1, 1, 0), t_end=0.5)
    state = r.__getstate__()
    state["x"] = state["x"][:-1].copy()
    with pytest.raises(wmr_py.ParameterError, match="state.x"):
        wmr_py._restore_run_result(state)
    # An intact state still round-trips.
    back = pickle.loads(pickle.dumps(r))
    np.testing.assert_array_equal(back.x, r.x)


def test_regression_27_results_behave_one_way_attributes_and_items() -> None:
    res = wmr_py.sweep(SWEEP)
    assert res.table is res["table"]
    assert res.converged is res["converged"]
    assert res.laws == ["paper", "polar"]
    batch = wmr_py.run_batch(np.array([[1.0, 0.5, 0.0]]), (0, 0, 0), t_end=1.0)
    assert batch.final_dl_m is batch["final_dl_m"]
    assert batch.law == "paper"
    r = wmr_py.simulate((0, 0, 0), (1, 1, 0), t_end=0.5)
    np.testing.assert_array_equal(r.x, r["x"])
    with pytest.raises(AttributeError, match="no attribute or entry 'tabel'"):
        res.tabel


def test_regression_27_a_tuples_heading_gets_a_radians_hint() -> None:
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        wmr_py.simulate((0, 0, 0), (1, 1, 120), t_end=0.2)
    messages = [str(x.message) for x in w]
    assert any("math.radians(120)" in m and "theta_deg" in m for m in messages), messages
    assert not any("write theta_deg = " in m for m in messages), messages


def test_regression_27_progress_to_a_log_is_one_line() -> None:
    pytest.importorskip("tqdm")
    import contextlib

    buf = io.StringIO()
    with contextlib.redirect_stderr(buf):
        wmr_py.sweep(SWEEP.replace("n = 4", "n = 40").replace("t_end = 2.0", "t_end = 20.0"), progress=True)
    text = buf.getvalue()
    # Drawn at the start and at the end: two states of the bar, one line.
    assert text.count("\n") <= 1, text
    assert text.count("\r") <= 2, text
    assert "100%" in text


def test_regression_27_a_robot_from_a_file_runs_from_python(tmp_path: Path) -> None:
    import shutil

    shutil.copytree(ROOT / "robots", tmp_path / "robots")
    scenario = tmp_path / "tb.toml"
    scenario.write_text(
        '[robot]\nfrom = "robots/turtlebot3_burger.toml"\nmass = 1.2\n[controller]\nkind = "lyapunov"\n'
        "[sim]\nt_end = 30.0\n[[run]]\ngoal = { x = 1.0, y = 1.0, theta_deg = 120.0 }\n"
    )
    # The path is relative to the scenario's folder, not the current one.
    (r,) = wmr_py.run_scenario(str(scenario))
    assert r.status == "converged", r.summary
    (same,) = wmr_py.run_scenario(ROOT / "examples" / "turtlebot3.toml")
    assert same.status == "converged"
    # A built-in name from a dict, and the preset's mass overridden beside it.
    r2 = wmr_py.simulate((0, 0, 0), (1, 1, 0), robot={"from": "turtlebot3_burger", "mass": 1.2}, t_end=0.5)
    r3 = wmr_py.run_scenario(scenario.read_text().replace("t_end = 30.0", "t_end = 0.5").replace(
        "theta_deg = 120.0", "theta_deg = 0.0").replace("[controller]\nkind = \"lyapunov\"\n", "").replace(
        "robots/turtlebot3_burger.toml", str(tmp_path / "robots" / "turtlebot3_burger.toml")),
        allow_files_under=[tmp_path])[0]  # text is judged from the current folder: tmp_path is outside
    np.testing.assert_array_equal(r2.x, r3.x)
    with pytest.raises(wmr_py.ScenarioError, match="robot.from") as e:
        wmr_py.simulate((0, 0, 0), (1, 1, 0), robot={"from": "turtlebot4"}, t_end=0.5)
    assert e.value.key == "robot.from"
