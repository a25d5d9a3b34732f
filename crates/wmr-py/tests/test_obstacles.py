"""Obstacles from Python (wmr issue 41): a run whose footprint touches a
`[[world.obstacle]]` ends collided, with the CLI's words, and its contact is where an
independent distance computed here says."""

import math

import wmr_py

POST = (1.0, 0.0, 0.15)  # x, y, radius, m
FOOTPRINT = 0.1  # m

SCENARIO = f"""
name = "post"
[robot]
footprint_radius = {FOOTPRINT}
[controller]
kind = "graceful"
[[world.obstacle]]
kind = "circle"
center = {{ x = {POST[0]}, y = {POST[1]} }}
radius = {POST[2]}
[sim]
t_end = 10.0
log_dt = 0.001
[[run]]
start = {{ x = 0.0, y = 0.0, theta_deg = 0.0 }}
goal = {{ x = 2.0, y = 0.0, theta_deg = 0.0 }}
"""


def clearance(x: float, y: float) -> float:
    return math.hypot(x - POST[0], y - POST[1]) - POST[2] - FOOTPRINT


def test_a_run_into_a_post_ends_collided_at_the_contact() -> None:
    (r,) = wmr_py.run_scenario(SCENARIO)
    assert r.status == "collided" and r.collided and not r.diverged and not r.converged
    assert "collided at t = " in r.summary and "with obstacle 0" in r.summary
    # Logged every step: the last sample is the first in contact, the one before is not.
    assert clearance(r.x[-1], r.y[-1]) <= 0.0 < clearance(r.x[-2], r.y[-2])
    assert r.t_final_s == r.t[-1]


def test_without_the_post_the_same_run_does_not_collide() -> None:
    free = SCENARIO.split("[[world.obstacle]]")[0] + SCENARIO.split(f"radius = {POST[2]}\n")[1]
    (r,) = wmr_py.run_scenario(free)
    assert r.status != "collided" and not r.collided
