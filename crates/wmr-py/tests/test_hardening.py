"""Issue 12: what an attack on the Python module broke, one test per defect
(``test_regression_12_N_...``). The seeded fuzz test is in test_fuzz.py."""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pytest

import wmr_py
from conftest import REPO

GOAL = {"x": 1.0, "y": 1.0, "theta_deg": 120.0}


def _raises_parameter_error(call, key: str) -> wmr_py.ParameterError:
    with pytest.raises(wmr_py.ParameterError) as info:
        call()
    err = info.value
    assert err.key == key, f"key {err.key!r}: {err}"
    assert str(err).startswith(f"{key}: "), str(err)
    return err


# --- defect 2: a sweep grid count that wraps -------------------------------------------


def test_regression_12_2_grid_count_does_not_wrap() -> None:
    grid = {"x_min": 0, "x_max": 1, "nx": 2147483648, "y_min": 0, "y_max": 1, "ny": 2147483648, "theta_deg": [0, 1, 2, 3]}
    err = _raises_parameter_error(lambda: wmr_py.sweep({"sim": {"t_end": 1.0}, "sweep": {"grid": grid}}), "sweep.grid")
    assert "18446744073709551616 starts" in str(err)


# --- defect 3: memory bombs -------------------------------------------------------------


def test_regression_12_3_columns_larger_than_memory_are_refused_before_allocating() -> None:
    # 1e9 samples x 18 columns x 8 bytes = 144 GB: refused, naming the key to change.
    err = _raises_parameter_error(
        lambda: wmr_py.simulate((0, 0, 0), (1, 1, 2), t_end=1e6, log_dt=1e-3), "sim.log_dt"
    )
    assert "GB of memory" in str(err) and "raise sim.log_dt to at least" in str(err)
    _raises_parameter_error(
        lambda: wmr_py.run_scenario("[sim]\nt_end = 1e6\nlog_dt = 1e-3\n[[run]]\ngoal = { x = 1.0 }\n"), "sim.log_dt"
    )


# --- defect 5: Ctrl-C -------------------------------------------------------------------

SIGINT_SCRIPT = textwrap.dedent(
    """
    import os, signal, sys, threading, time
    import numpy as np
    import wmr_py
    which, warm = sys.argv[1], sys.argv[2] == "warm"
    # Python's own handler, also when the parent ignores SIGINT (a background job of a
    # shell without job control does): the ignore is inherited, and Python then installs
    # no handler, so the signal would never reach the call under test.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    calls = {
        "simulate": lambda: wmr_py.simulate((0, 0, 0), (1, 1, 2), t_end=50000.0, log_dt=10.0),
        "run_batch": lambda: wmr_py.run_batch(np.zeros((4, 3)) + [0.5, 0.5, 0.0], (0, 0, 0), t_end=50000.0),
        "run_scenario": lambda: wmr_py.run_scenario(
            "[sim]\\nt_end = 50000.0\\nlog_dt = 10.0\\n[[run]]\\ngoal = { x = 1.0 }\\n[[run]]\\ngoal = { x = 2.0 }\\n"
        ),
        "sweep": lambda: wmr_py.sweep(
            "[sim]\\nt_end = 20000.0\\n[sweep]\\ncontrollers = [{ kind = \\"paper\\" }, { kind = \\"polar\\" }]\\n"
            "random = { n = 8, radius = 1.0 }\\n"
        ),
    }
    if warm:
        wmr_py.simulate((0, 0, 0), (1, 1, 2), t_end=0.1)
    sent = []
    def fire():
        time.sleep(1.0)
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)
    threading.Thread(target=fire, daemon=True).start()
    try:
        calls[which]()
        print("FINISHED")
    except KeyboardInterrupt:
        print("INTERRUPTED", time.monotonic() - sent[0])
    """
)


@pytest.mark.parametrize("warm", ["fresh", "warm"])
@pytest.mark.parametrize("which", ["simulate", "run_batch", "run_scenario", "sweep"])
def test_regression_12_5_ctrl_c_raises_keyboard_interrupt_within_half_a_second(which: str, warm: str) -> None:
    """SIGINT 1 s into a long call (in a fresh process, and after a warm-up call):
    KeyboardInterrupt within 0.5 s, never the end of the run, never a PanicException."""
    o = subprocess.run(
        [sys.executable, "-c", SIGINT_SCRIPT, which, warm], capture_output=True, text=True, timeout=120
    )
    assert o.returncode == 0, o.stderr
    assert "PanicException" not in o.stderr and "capsule" not in o.stderr, o.stderr
    words = o.stdout.split()
    assert words[:1] == ["INTERRUPTED"], o.stdout + o.stderr
    assert float(words[1]) < 0.5, f"KeyboardInterrupt {words[1]} s after SIGINT"


# --- defect 14: arguments of the wrong kind ---------------------------------------------

WRONG_ARGUMENTS = [
    ("a str start", lambda: wmr_py.simulate("123", GOAL, t_end=0.1), "start"),
    ("a bytes start", lambda: wmr_py.simulate(b"abc", GOAL, t_end=0.1), "start"),
    ("a numpy str start", lambda: wmr_py.simulate(np.array(["1", "2", "3"]), GOAL, t_end=0.1), "start"),
    ("a complex start", lambda: wmr_py.simulate(np.array([0, 0, 1j]), GOAL, t_end=0.1), "start"),
    ("complex starts", lambda: wmr_py.run_batch(np.array([[0.5, 0.5, 1j]]), GOAL, t_end=0.1), "starts"),
    ("str starts", lambda: wmr_py.run_batch([["a", "b", "c"]], GOAL, t_end=0.1), "starts"),
    ("ragged starts", lambda: wmr_py.run_batch([[0, 0, 0], [1, 2]], GOAL, t_end=0.1), "starts"),
    ("object starts", lambda: wmr_py.run_batch(np.array([[object()] * 3], dtype=object), GOAL, t_end=0.1), "starts"),
    ("dt None", lambda: wmr_py.Robot().step(np.zeros(7), (0, 0), None), "dt"),
    ("dt a str", lambda: wmr_py.Robot().step(np.zeros(7), (0, 0), "1e-3"), "dt"),
    ("dt complex", lambda: wmr_py.Robot().step(np.zeros(7), (0, 0), 1e-3 + 0j), "dt"),
    ("a bytes state", lambda: wmr_py.Robot().derivative(b"abcdefg", (0, 0)), "state"),
    ("a complex state", lambda: wmr_py.Robot().derivative(np.zeros(7, dtype=complex), (0, 0)), "state"),
    ("a dict state", lambda: wmr_py.Robot().kinetic_energy({"x": 1.0}), "state"),
    ("a numpy complex in a list", lambda: wmr_py.Robot().wheel_speeds([0, 0, 0, np.complex128(1), 0, 0, 0]), "state[3]"),
    ("mass 10**400", lambda: wmr_py.simulate((0, 0, 0), GOAL, robot={"mass": 10**400}, t_end=0.1), "robot.mass"),
    ("a lone surrogate label", lambda: wmr_py.simulate((0, 0, 0), GOAL, label="\udcff", t_end=0.1), "run[0].label"),
    ("a lone surrogate key", lambda: wmr_py.run_scenario({"robot": {"\udcff": 1.0}, "run": [{"goal": {}}]}), "robot"),
    ("a sweep-only file", lambda: wmr_py.run_scenario(REPO / "examples" / "compare.toml"), "run"),
    ("not a scenario", lambda: wmr_py.run_scenario(42), "scenario"),
    ("TOML that is no TOML", lambda: wmr_py.run_scenario("[robot\nmass = 1\n"), "scenario"),
    ("a start outside the box", lambda: wmr_py.simulate((5000, 0, 0), GOAL, t_end=0.1), "run[0].start.x"),
    ("a batch start outside the box", lambda: wmr_py.run_batch([[5000.0, 0, 0]], GOAL, t_end=0.1), "starts[0, 0]"),
    ("a goal of 1e300", lambda: wmr_py.simulate((0, 0, 0), (1e300, 0, 0), t_end=0.1), "run[0].goal.x"),
]


@pytest.mark.parametrize("name, call, key", WRONG_ARGUMENTS, ids=[c[0] for c in WRONG_ARGUMENTS])
def test_regression_12_14_wrong_arguments_raise_parameter_error_naming_them(name: str, call, key: str) -> None:
    _raises_parameter_error(call, key)


def test_regression_12_14_infinite_controller_output_raises_and_keeps_the_state() -> None:
    ctrl = wmr_py.PaperController((1, 1, 0), servo_kp=1e6)
    first = ctrl.update((0, 0, 0), (0, 0), (0, 0))
    ctrl.reset()
    with pytest.raises(FloatingPointError):
        ctrl.update((0, 0, 0), (1e308, -1e308), (0, 0))
    # The refused tick changed nothing: the next one is the first one again.
    assert ctrl.update((0, 0, 0), (0, 0), (0, 0)) == first


def test_regression_12_14_missing_file_is_file_not_found(tmp_path: pathlib.Path) -> None:
    with pytest.raises(FileNotFoundError) as info:
        wmr_py.run_scenario(str(tmp_path / "missing.toml"))
    assert info.value.filename == str(tmp_path / "missing.toml") and info.value.key == "scenario"
    with pytest.raises(IsADirectoryError):
        wmr_py.run_scenario(tmp_path)


def test_regression_12_14_toml_text_errors_start_with_the_key() -> None:
    with pytest.raises(wmr_py.ScenarioError) as info:
        wmr_py.run_scenario("[sim]\nt_end = 1.0\n\n[robot]\nmass = -1.0\n[[run]]\ngoal = {}\n")
    err = info.value
    assert str(err) == "robot.mass: must be > 0 (got -1) (line 5)" and err.key == "robot.mass" and err.line == 5


# --- defect 15 --------------------------------------------------------------------------


def test_regression_12_15_theta_beyond_a_turn_warns() -> None:
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        wmr_py.simulate((0, 0, 0), (1, 1, 90), t_end=0.01)
    messages = [str(w.message) for w in seen if issubclass(w.category, UserWarning)]
    # In Python's words (issue 27): a tuple cannot hold degrees, a dict can.
    assert any(
        "run[0].goal.theta: 90 rad is 14.3 turns" in m and "math.radians(90)" in m and '"theta_deg": 90' in m
        for m in messages
    ), messages


def test_regression_12_15_times_are_exact_decimals() -> None:
    r = wmr_py.simulate((0, 0, 0), GOAL, t_end=2.0)
    assert [repr(float(t)) for t in r.t[:9]] == ["0.0", "0.01", "0.02", "0.03", "0.04", "0.05", "0.06", "0.07", "0.08"]
    assert all(float(f"{k / 100:.2f}") == t for k, t in enumerate(r.t))


# --- unaligned arrays (found when Dask shipped a batch's starts to its workers) --------


def _unaligned(a: np.ndarray) -> np.ndarray:
    """A float64 copy of `a` whose data starts one byte past an 8-byte boundary, as
    np.frombuffer at an odd offset (or a pickle-5 buffer) gives."""
    a = np.ascontiguousarray(a, dtype=np.float64)
    buf = bytearray(a.nbytes + 1)
    out = np.frombuffer(buf, dtype=np.float64, count=a.size, offset=1).reshape(a.shape)
    out[...] = a
    assert not out.flags.aligned
    return out


def test_unaligned_arrays_are_read_as_their_aligned_copies() -> None:
    starts = np.array([[0.5, 0.2, 0.1], [-0.4, 0.3, 2.0], [0.1, -0.6, -1.0]])
    ref = wmr_py.run_batch(starts, (0, 0, 0), t_end=2.0)
    # Through the worker part an executor runs (what Dask called with unaligned starts).
    base = wmr_py._scenario([{"start": {"x": 0.5, "y": 0.2, "theta": 0.1}, "goal": wmr_py._pose((0, 0, 0), "goal")}], None, None, None, 2.0, None, 2.0, None, None, None)
    part = wmr_py._results.batch_task(base, _unaligned(starts), None, 0)
    # Float arrays compare with their NaNs (a time never reached); `status` is words.
    for k in ref:
        if k in part:
            a, b = np.asarray(part[k]), np.asarray(ref[k])
            assert np.array_equal(a, b, equal_nan=b.dtype.kind == "f"), k
    robot = wmr_py.Robot()
    states = np.array([[0.0, 0.0, 0.3, 0.4, 0.1, 0.0, 0.0], [1.0, 2.0, -0.3, 0.2, -0.5, 1.0, 2.0]])
    tau = np.array([[0.1, -0.2], [0.3, 0.05]])
    assert np.array_equal(robot.step(_unaligned(states), _unaligned(tau), 0.01), robot.step(states, tau, 0.01))
    assert np.array_equal(robot.derivative(_unaligned(states[0]), _unaligned(tau[0])), robot.derivative(states[0], tau[0]))
    circle = wmr_py.Reference("circle", radius=1.0, speed=0.3)
    t = np.linspace(0.0, 2.0, 5)
    assert np.array_equal(circle.state_at(_unaligned(t)), circle.state_at(t))


class _FakePanic(BaseException):
    """Stands for pyo3's PanicException, a BaseException."""


def test_a_panic_in_a_worker_part_is_an_exception_an_executor_reports(monkeypatch: pytest.MonkeyPatch) -> None:
    # A Dask worker does not catch a BaseException: the future never completed and the
    # caller hung (how the unaligned-array panic showed in CI). Raised as RuntimeError, it
    # reaches the caller as every other error of a part does.
    def panics(*_args: object) -> None:
        raise _FakePanic("The pointer must be aligned.")

    monkeypatch.setattr(wmr_py._results._native, "_run_batch", panics)
    monkeypatch.setattr(wmr_py._results._native, "_sweep_part", panics)
    with pytest.raises(RuntimeError, match="_FakePanic: The pointer must be aligned"):
        wmr_py._results.batch_task({}, np.zeros((1, 3)), None, 0)
    with pytest.raises(RuntimeError, match="_FakePanic"):
        wmr_py._results.sweep_task("", 0, 1)
    with pytest.raises(KeyboardInterrupt):  # what stops a run stays what it is
        monkeypatch.setattr(wmr_py._results._native, "_sweep_part", lambda *_a: (_ for _ in ()).throw(KeyboardInterrupt()))
        wmr_py._results.sweep_task("", 0, 1)
