"""fast=True (issue 15): the lanes' results next to the exact ones, locally and through an
executor (which must give the local fast call's result, bit for bit)."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np

import wmr_py

SWEEP = """
[sim]
t_end = 30.0
stop_when_settled = true
[sweep]
goal = { x = 0.0, y = 0.0, theta_deg = 0.0 }
controllers = [{ kind = "paper_bidirectional" }, { kind = "polar" }]
random = { n = 24, seed = 5, radius = 1.5 }
"""


def test_fast_sweep_is_close_to_the_exact_one_and_the_same_through_an_executor():
    exact = wmr_py.sweep(SWEEP)
    fast = wmr_py.sweep(SWEEP, fast=True)
    assert list(fast["converged"]) == list(exact["converged"])
    for key in ("final_x_m", "final_y_m", "final_theta_deg"):
        np.testing.assert_allclose(fast[key], exact[key], rtol=1e-9, atol=1e-9)
    with ThreadPoolExecutor(2) as ex:
        parted = wmr_py.sweep(SWEEP, fast=True, executor=ex, chunk_size=7)
    for key in ("final_x_m", "final_y_m", "final_theta_deg", "time_to_1cm_s"):
        np.testing.assert_array_equal(parted[key], fast[key])


def test_fast_batch_is_close_to_the_exact_one():
    rng = np.random.default_rng(3)
    starts = np.column_stack([rng.uniform(-1, 1, 16), rng.uniform(-1, 1, 16), rng.uniform(-3, 3, 16)])
    goal = (0.5, 0.5, 0.0)
    ctl = {"kind": "polar"}
    exact = wmr_py.run_batch(starts, goal, controller=ctl, t_end=20.0)
    fast = wmr_py.run_batch(starts, goal, controller=ctl, t_end=20.0, fast=True)
    assert list(fast["converged"]) == list(exact["converged"])
    np.testing.assert_allclose(fast["final_x_m"], exact["final_x_m"], rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(fast["start"], exact["start"])
    with ThreadPoolExecutor(2) as ex:
        parted = wmr_py.run_batch(starts, goal, controller=ctl, t_end=20.0, fast=True, executor=ex, chunk_size=5)
    np.testing.assert_array_equal(parted["final_x_m"], fast["final_x_m"])
