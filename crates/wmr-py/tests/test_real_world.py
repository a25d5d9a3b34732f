"""The real-world keys from Python: the same scenario code as files, through dicts."""

import numpy as np
import pytest

import wmr_py

GOAL = {"x": 1.0, "y": 1.0, "theta_deg": 120.0}


def test_sensor_delays_and_noises_the_pose_the_controller_uses():
    r = wmr_py.simulate((0, 0, 0), GOAL, t_end=3.0, sensor={"rate_hz": 20.0, "latency": 0.1, "position_noise": 0.01, "seed": 4})
    assert len(r.x_meas) == len(r.x)
    # Before the first sample arrives (0.1 s) the controller sees the start pose.
    early = r.t < 0.1
    assert np.all(r.x_meas[early] == 0.0)
    # Later the seen pose differs from the true one by noise and lag.
    late = r.t > 1.0
    assert np.any(np.abs(r.x_meas[late] - r.x[late]) > 1e-3)
    again = wmr_py.simulate((0, 0, 0), GOAL, t_end=3.0, sensor={"rate_hz": 20.0, "latency": 0.1, "position_noise": 0.01, "seed": 4})
    assert np.array_equal(again.x_meas, r.x_meas) and np.array_equal(again.x, r.x)
    other = wmr_py.simulate((0, 0, 0), GOAL, t_end=3.0, sensor={"rate_hz": 20.0, "latency": 0.1, "position_noise": 0.01, "seed": 5})
    assert not np.array_equal(other.x_meas, r.x_meas)


def test_without_sensor_the_measured_pose_is_the_true_pose():
    r = wmr_py.simulate((0, 0, 0), GOAL, t_end=2.0)
    assert np.array_equal(r.x_meas, r.x) and np.array_equal(r.theta_meas, r.theta)


def test_model_world_and_current_limit_keys():
    nominal = wmr_py.simulate((0, 0, 0), GOAL, t_end=5.0)
    wrong = wmr_py.simulate((0, 0, 0), GOAL, t_end=5.0, controller={"model": {"wheel_radius": 0.105}})
    assert not np.array_equal(wrong.x, nominal.x)
    sloped = wmr_py.simulate((0, 0, 0), GOAL, t_end=5.0, world={"slope_deg": 5.0, "slope_direction_deg": 90.0})
    assert not np.array_equal(sloped.y, nominal.y)
    limited = wmr_py.simulate(
        (0, 0, 0), GOAL, t_end=5.0, drive={"kind": "dc_motor", "current_max": 2.0}, controller={"servo_kd": 1.1}
    )
    # k_tau i_max / k_t: the default motor's torque constant (wmr_core DcMotorParams), 2 A, k_t = 0.1.
    assert np.max(np.abs(limited.tau_r)) <= 0.03744 * 2.0 / 0.1 * (1 + 1e-12)


@pytest.mark.parametrize(
    "kwargs, key",
    [
        ({"sensor": {"position_noise": -1.0}}, "sensor.position_noise"),
        ({"sensor": {"latency": 0.0005}}, "sensor.latency"),
        ({"world": {"slope_deg": 95.0}}, "world.slope_deg"),
        ({"controller": {"model": {"wheel_radius": 0.0}}}, "controller.model.wheel_radius"),
        ({"drive": {"kind": "dc_motor", "current_max": -1.0}}, "drive.current_max"),
    ],
)
def test_bad_real_world_keys_name_the_key(kwargs, key):
    with pytest.raises(wmr_py.ScenarioError) as e:
        wmr_py.simulate((0, 0, 0), GOAL, t_end=1.0, **kwargs)
    assert e.value.key == key


def test_run_batch_takes_a_sensor_and_a_sweep_reports_varied_keys():
    starts = np.array([[0.5, 0.0, 0.0], [-0.5, 0.3, 1.0]])
    out = wmr_py.run_batch(starts, (0, 0, 0), t_end=2.0, sensor={"position_noise": 0.005, "seed": 1})
    assert out["final_dl_m"].shape == (2,)
    sw = wmr_py.sweep(
        {
            "sim": {"t_end": 1.0},
            "sweep": {
                "controllers": [{"kind": "polar"}],
                "random": {"n": 2, "seed": 1, "radius": 1.0},
                "vary": [{"key": "sensor.latency", "values": [0.0, 0.05]}],
            },
        }
    )
    assert list(sw["sensor.latency"]) == [0.0, 0.0, 0.05, 0.05]
