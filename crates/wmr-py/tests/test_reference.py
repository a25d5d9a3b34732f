"""update(reference=...): the goal at rest given as a reference changes nothing, a moving
reference reaches the law, bad values raise ParameterError naming the field."""

from __future__ import annotations

import math

import numpy as np
import pytest

import wmr_py

GOAL = (1.0, 0.5, 0.7)
CLASSES = [
    wmr_py.PaperController,
    wmr_py.PaperBidirectionalController,
    wmr_py.PolarController,
    wmr_py.LyapunovController,
]
AT_REST = [
    {"pose": GOAL, "twist": (0.0, 0.0), "accel": (0.0, 0.0)},
    {"pose": {"x": GOAL[0], "y": GOAL[1], "theta": GOAL[2]}},
    (*GOAL, 0.0, 0.0, 0.0, 0.0),
    np.array([[*GOAL, 0.0, 0.0, 0.0, 0.0]]),
]


def loop(ctrl, starts: np.ndarray, ticks: int, reference=None) -> np.ndarray:
    """A batch closed in Python for `ticks` ticks; every command and error, stacked."""
    robot = wmr_py.Robot()
    state = np.hstack([starts, np.zeros((len(starts), 4))])
    out = []
    for _ in range(ticks):
        kw = {} if reference is None else {"reference": reference}
        tau = np.clip(ctrl.update(state[:, :3], state[:, 5:7], robot.wheel_speeds(state), **kw), -2.0, 2.0)
        out.append(np.hstack([tau, ctrl.errors]))
        state = robot.step(state, tau, ctrl.control_dt)
    return np.array(out)


@pytest.mark.parametrize("cls", CLASSES)
@pytest.mark.parametrize("ref", range(len(AT_REST)))
def test_goal_at_rest_as_reference_changes_nothing(cls, ref) -> None:
    starts = np.array([[0.0, 0.0, 0.0], [-0.5, 0.3, 2.0], [0.2, -1.0, -1.0]])
    want = loop(cls(GOAL), starts, 300)
    got = loop(cls(GOAL), starts, 300, AT_REST[ref])
    np.testing.assert_array_equal(got, want)
    # One robot, 1-D arguments.
    a = cls(GOAL).update(starts[1], (0.1, 0.2), (0.3, -0.4), reference=AT_REST[ref])
    b = cls(GOAL).update(starts[1], (0.1, 0.2), (0.3, -0.4))
    assert a == b

def test_per_robot_references_reach_the_law() -> None:
    starts = np.zeros((2, 3))
    other = (-1.0, 2.0, 0.0)
    refs = np.array([[*GOAL, 0, 0, 0, 0], [*other, 0, 0, 0, 0]], dtype=float)
    got = loop(wmr_py.PolarController(GOAL), starts, 50, refs)
    np.testing.assert_array_equal(got[:, 0], loop(wmr_py.PolarController(GOAL), starts[:1], 50)[:, 0])
    np.testing.assert_array_equal(got[:, 1], loop(wmr_py.PolarController(other), starts[:1], 50)[:, 0])


@pytest.mark.parametrize(
    "ref, field",
    [
        ({"twist": (math.nan, 0.0)}, "reference.twist.v"),
        ({"twist": {"v": 0.0, "omega": math.inf}}, "reference.twist.omega"),
        ({"accel": {"v": math.nan, "omega": 0.0}}, "reference.accel.v"),
        ({"pose": (0.0, math.nan, 0.0)}, "reference.pose.y"),
        ({"twist": {"v": "fast", "omega": 0.0}}, "reference.twist.v"),
        ({"twist": {"v": 0.0}}, "reference.twist.omega"),
        ({"twist": {"v": 0.0, "omega": 0.0, "w": 1.0}}, "reference.twist.w"),
        ({"jerk": (0.0, 0.0)}, "reference.jerk"),
        ((*GOAL, math.nan, 0.0, 0.0, 0.0), "reference.twist.v"),
        ((*GOAL, 0.0, 0.0, 0.0, math.nan), "reference.accel.omega"),
    ],
)
def test_bad_reference_names_the_field(ref, field) -> None:
    ctrl = wmr_py.PaperController(GOAL)
    with pytest.raises(ValueError, match=field.replace(".", r"\.")) as e:
        ctrl.update((0.0, 0.0, 0.0), (0.0, 0.0), (0.0, 0.0), reference=ref)
    assert isinstance(e.value, wmr_py.ParameterError)


def test_bad_batch_reference_names_the_field() -> None:
    ctrl = wmr_py.PolarController(GOAL)
    refs = np.zeros((2, 7))
    refs[1, 5] = math.nan
    with pytest.raises(wmr_py.ParameterError, match=r"reference\.accel\.v"):
        ctrl.update(np.zeros((2, 3)), np.zeros((2, 2)), np.zeros((2, 2)), reference=refs)
    with pytest.raises(wmr_py.ParameterError, match="1 .* or 2"):
        ctrl.update(np.zeros((2, 3)), np.zeros((2, 2)), np.zeros((2, 2)), reference=np.zeros((3, 7)))
    assert ctrl.n == 1  # a refused call changes nothing
