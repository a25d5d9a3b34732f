"""MPPI from Python (wmr issue 41): each run draws its own noise, as in the CLI (the CLI's
CSV bit for bit, a sweep's trials differ, a rerun is the same), and ``MppiController``
stepped by hand knows the obstacles and the run: fed a scenario run's states it gives that
run's commands (to 1e-9 N m: the wheel speeds it is fed are the CSV's, which the scenario
computes in another order, 1 ulp apart; the bits of the whole loop are the CLI's CSV)."""

from __future__ import annotations

import pathlib
import shutil
import subprocess

import numpy as np
import pytest

import wmr_py

# A post and a box beside the way to the goal; two runs from the same start, so that only
# their noise differs. A small batch keeps the test quick.
SCENARIO = """
name = "mppi-two-runs"
[robot]
footprint_radius = 0.22
[controller]
kind = "mppi"
batch_size = 32
time_steps = 16
seed = 11
[sim]
t_end = 1.5
log_dt = 0.001
[[world.obstacle]]
kind = "circle"
center = { x = 0.55, y = 0.3 }
radius = 0.1
[[world.obstacle]]
kind = "polygon"
points = [[0.3, -0.55], [0.7, -0.55], [0.7, -0.3], [0.3, -0.3]]
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 1.0, y = 0.0, theta_deg = 0.0 }
[[run]]
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 1.0, y = 0.0, theta_deg = 0.0 }
"""

OBSTACLES = [
    {"kind": "circle", "center": {"x": 0.55, "y": 0.3}, "radius": 0.1},
    {"kind": "polygon", "points": [[0.3, -0.55], [0.7, -0.55], [0.7, -0.3], [0.3, -0.3]]},
]
KEYS = {"batch_size": 32, "time_steps": 16, "seed": 11}
GOAL = (1.0, 0.0, 0.0)


def test_each_run_draws_its_own_noise_and_a_rerun_the_same() -> None:
    r0, r1 = wmr_py.run_scenario(SCENARIO)
    assert not np.array_equal(r0.x, r1.x)
    again = wmr_py.run_scenario(SCENARIO)
    np.testing.assert_array_equal(again[0].x, r0.x)
    np.testing.assert_array_equal(again[1].x, r1.x)


@pytest.mark.skipif(shutil.which("cargo") is None, reason="cargo is not on PATH: cannot build wmr-cli to compare with")
def test_both_runs_equal_the_cli_csv(tmp_path: pathlib.Path) -> None:
    from test_scenario import CSV_COLUMNS, build_cli, read_csv

    path = tmp_path / "mppi.toml"
    path.write_text(SCENARIO)
    out = tmp_path / "mppi.csv"
    subprocess.run([str(build_cli()), "run", str(path), "-o", str(out)], check=True, capture_output=True, timeout=600)
    cli = read_csv(out)
    for r in wmr_py.run_scenario(path):
        mine = cli["run"] == r.run
        py = r.columns()
        for name in CSV_COLUMNS:
            np.testing.assert_array_equal(py[name], cli[name][mine], err_msg=f"run {r.run} {name}")


def test_a_sweeps_trials_differ_and_a_rerun_is_the_same() -> None:
    sc = {
        "sim": {"t_end": 1.0},
        "sweep": {
            "goal": {"x": 0.0, "y": 0.0, "theta_deg": 0.0},
            "controllers": [{"kind": "mppi", "motion_model": "kinematic", "batch_size": 24, "time_steps": 12}],
            "random": {"n": 2, "seed": 9, "radius": 0.8, "min_radius": 0.5},
            "trials": 2,
        },
    }
    a = wmr_py.sweep(sc)
    b = wmr_py.sweep(sc)
    trial, start = np.asarray(a.trial), np.asarray(a["start"])
    x = np.asarray(a["final_x_m"])
    for s in (0, 1):
        assert x[(start == s) & (trial == 0)][0] != x[(start == s) & (trial == 1)][0]
    np.testing.assert_array_equal(np.asarray(b["final_x_m"]), x)
    np.testing.assert_array_equal(np.asarray(wmr_py.sweep(sc, fast=True)["final_x_m"]), x)


def replay(ctrl: "wmr_py.MppiController", r: "wmr_py.RunResult", ticks: int) -> np.ndarray:
    """The controller's commands fed the run's states (logged every control tick), clamped
    as the torque drive clamps them (|tau| <= motor_torque_max / gear_ratio = 2 N m)."""
    tau_max = 0.2 / wmr_py.Robot().gear_ratio
    out = []
    for k in range(ticks):
        pose = [float(r.x[k]), float(r.y[k]), float(r.theta[k])]
        cmd = ctrl.update(pose, [float(r.phi_r[k]), float(r.phi_l[k])], [float(r.omega_r[k]), float(r.omega_l[k])])
        out.append(np.clip(cmd, -tau_max, tau_max))
    return np.array(out)


def test_mppi_controller_with_obstacles_and_run_is_the_scenarios_run() -> None:
    runs = wmr_py.run_scenario(SCENARIO)
    ticks = 600
    for r in runs:
        ctrl = wmr_py.MppiController(GOAL, obstacles=OBSTACLES, footprint_radius=0.22, run=r.run, **KEYS)
        assert ctrl.run == r.run
        mine = replay(ctrl, r, ticks)
        np.testing.assert_allclose(mine[:, 0], r.tau_r[:ticks], rtol=0, atol=1e-9, err_msg=f"run {r.run}")
        np.testing.assert_allclose(mine[:, 1], r.tau_l[:ticks], rtol=0, atol=1e-9, err_msg=f"run {r.run}")
    # Without the obstacles, or with run 0's noise, the commands are others.
    blind = replay(wmr_py.MppiController(GOAL, footprint_radius=0.22, run=1, **KEYS), runs[1], ticks)
    assert np.max(np.abs(blind[:, 0] - runs[1].tau_r[:ticks])) > 1e-3
    other = replay(wmr_py.MppiController(GOAL, obstacles=OBSTACLES, footprint_radius=0.22, **KEYS), runs[1], ticks)
    assert np.max(np.abs(other[:, 0] - runs[1].tau_r[:ticks])) > 1e-3


def test_a_batchs_lane_i_draws_run_plus_i() -> None:
    r0, r1 = wmr_py.run_scenario(SCENARIO)
    ctrl = wmr_py.MppiController(GOAL, obstacles=OBSTACLES, footprint_radius=0.22, **KEYS)
    for k in range(300):
        rs = (r0, r1)
        pose = np.array([[r.x[k], r.y[k], r.theta[k]] for r in rs])
        ang = np.array([[r.phi_r[k], r.phi_l[k]] for r in rs])
        spd = np.array([[r.omega_r[k], r.omega_l[k]] for r in rs])
        cmd = np.clip(ctrl.update(pose, ang, spd), -2.0, 2.0)
        for i, r in enumerate(rs):
            assert abs(cmd[i, 0] - r.tau_r[k]) < 1e-9 and abs(cmd[i, 1] - r.tau_l[k]) < 1e-9, (k, i)


def test_pickling_keeps_the_obstacles_and_the_run() -> None:
    import pickle

    ctrl = wmr_py.MppiController(GOAL, obstacles=OBSTACLES, footprint_radius=0.22, run=1, **KEYS)
    back = pickle.loads(pickle.dumps(ctrl))
    assert back.run == 1 and "world.obstacle" in back.scenario_toml
    r1 = wmr_py.run_scenario(SCENARIO)[1]
    np.testing.assert_array_equal(replay(back, r1, 200), replay(ctrl, r1, 200))


def test_bad_obstacles_are_refused_by_their_key() -> None:
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.MppiController(GOAL, obstacles=[{"kind": "circle", "center": {"x": 0.0, "y": 0.0}, "radius": -1.0}])
    assert e.value.key == "world.obstacle[0].radius"
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.MppiController(GOAL, obstacles=[{"kind": "polygon", "points": [[0, 0], [1, 0]]}])
    assert e.value.key == "world.obstacle[0].points"
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.MppiController(GOAL, footprint_radius=float("nan"), obstacles=OBSTACLES)
    assert e.value.key.endswith("footprint_radius")
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.PaperController(GOAL, obstacles=OBSTACLES)
    assert e.value.key == "obstacles"
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.PaperController(GOAL, run=3)
    assert e.value.key == "run"
