"""run_batch: right answers, in order, in parallel, with the GIL released."""

from __future__ import annotations

import math
import threading
import time

import numpy as np
import pytest

import wmr_py

GOAL = (0.0, 0.0, 0.0)


def starts(n: int, seed: int = 7) -> np.ndarray:
    rng = np.random.default_rng(seed)
    radius = rng.uniform(0.3, 2.0, n)
    angle = rng.uniform(-math.pi, math.pi, n)
    return np.column_stack([radius * np.cos(angle), radius * np.sin(angle), rng.uniform(-math.pi, math.pi, n)])


def test_batch_equals_simulate_per_start() -> None:
    s = starts(6)
    out = wmr_py.run_batch(s, GOAL, t_end=5.0)
    assert set(out) >= {"converged", "diverged", "time_to_1cm_s", "final_dl_m", "final_heading_error_deg", "peak_wheel_speed_rad_s"}
    assert out["converged"].dtype == np.bool_ and out["final_dl_m"].dtype == np.float64
    for i, start in enumerate(s):
        one = wmr_py.simulate(start, GOAL, t_end=5.0)
        assert out["final_dl_m"][i] == one.final_dl_m
        assert out["final_heading_error_deg"][i] == one.final_heading_error_deg
        assert out["peak_wheel_speed_rad_s"][i] == one.peak_wheel_speed_rad_s
        assert out["final_x_m"][i] == one.x[-1] and out["final_y_m"][i] == one.y[-1]
        assert bool(out["converged"][i]) == one.converged and bool(out["diverged"][i]) == one.diverged
        t1 = out["time_to_1cm_s"][i]
        assert (math.isnan(t1) and one.time_to_1cm_s is None) or t1 == one.time_to_1cm_s
        # Every outcome field in one spelling: each array of the batch is the run's
        # attribute of the same name (NaN where the attribute is None).
        for name in wmr_py.OUTCOME_FIELDS:
            v = getattr(one, name)
            assert (v is None and math.isnan(out[name][i])) or out[name][i] == v, name


def test_outcome_fields_carry_their_unit() -> None:
    """One spelling, with the unit as suffix: the names the CSV, help and docs use."""
    units = ("_m", "_s", "_deg", "_rad_s", "_j")
    # The flags (1/0 or bool) have no unit.
    floats = [n for n in wmr_py.OUTCOME_FIELDS if n not in ("docked", "converged", "diverged", "collided")]
    assert floats and all(n.endswith(units) for n in (*floats, *wmr_py.TRACKING_FIELDS))
    assert "abs_work_j" in floats and "energy" not in wmr_py.OUTCOME_FIELDS
    r = wmr_py.simulate((1.0, 0.5, 0.0), GOAL, t_end=1.0)
    assert r.final_theta_deg == pytest.approx(math.degrees(r.theta[-1]))
    assert r.t_final_s == r.t[-1] and r.final_x_m == r.x[-1]


def test_batch_releases_the_gil() -> None:
    """While run_batch runs, another Python thread keeps counting."""
    s = starts(48)
    count = 0
    stop = threading.Event()

    def spin() -> None:
        nonlocal count
        while not stop.is_set():
            count += 1

    t = threading.Thread(target=spin)
    t.start()
    try:
        time.sleep(0.05)
        before = count
        t0 = time.perf_counter()
        wmr_py.run_batch(s, GOAL, t_end=60.0)
        elapsed = time.perf_counter() - t0
        during = count - before
    finally:
        stop.set()
        t.join()
    assert elapsed > 0.05, "batch too short to tell"
    # Holding the GIL for the whole call would leave the counter (nearly) still.
    assert during > 10_000, f"counter advanced only {during} in {elapsed:.3f} s"


def test_two_threads_at_once_get_the_right_answers() -> None:
    a, b = starts(8, seed=1), starts(8, seed=2)
    want_a = wmr_py.run_batch(a, GOAL, t_end=4.0)
    want_b = wmr_py.run_batch(b, (0.5, 0.5, 1.0), t_end=4.0)
    got: dict = {}

    def work(name, s, goal) -> None:
        got[name] = wmr_py.run_batch(s, goal, t_end=4.0)

    threads = [threading.Thread(target=work, args=("a", a, GOAL)), threading.Thread(target=work, args=("b", b, (0.5, 0.5, 1.0)))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for want, have in ((want_a, got["a"]), (want_b, got["b"])):
        for key in ("final_dl_m", "final_heading_error_deg", "final_x_m", "converged"):
            np.testing.assert_array_equal(want[key], have[key], err_msg=key)


def test_batch_goal_forms_and_settings() -> None:
    s = starts(3)
    a = wmr_py.run_batch(s, {"x": 1.0, "y": 1.0, "theta_deg": 90.0}, t_end=2.0)
    b = wmr_py.run_batch(s.tolist(), (1.0, 1.0, math.pi / 2), t_end=2.0)
    np.testing.assert_array_equal(a["final_dl_m"], b["final_dl_m"])
    c = wmr_py.run_batch(s, (1.0, 1.0, math.pi / 2), t_end=2.0, robot={"mass": 8.0})
    assert not np.array_equal(a["final_dl_m"], c["final_dl_m"])
    assert a["t_final_s"] == pytest.approx([2.0, 2.0, 2.0])
