"""Issue 12: every Python entry point called with seeded random arguments, right and
wrong. Each call returns, or raises one of the documented exceptions: ParameterError (or
ScenarioError) whose ``key`` names the argument or scenario key and starts the message;
FileNotFoundError and its kin for files (``key == "scenario"``); FloatingPointError for a
result too large to be finite; MemoryError. Never TypeError, OverflowError,
UnicodeError, a plain ValueError, nor a PanicException (which ``except Exception`` would
not even catch). ``WMR_FUZZ_CASES`` (default 5,000) and ``WMR_FUZZ_SEED`` (default 12)
choose how many calls and which."""

from __future__ import annotations

import math
import os
import random
import time
import warnings

import numpy as np

import wmr_py
from conftest import REPO

NUMBERS = [0, -1, 1, 2.5, 1e308, -1e308, 1e-320, math.nan, math.inf, -math.inf, 10**400, 2**63, True, -0.0, 1e-3]
JUNK = [None, "", "123", "1e-3", "\udcff", "\x1b[31m\u202e", b"abc", 1j, object(), [], {}, (1, 2), {"x": "y"}]
# Run lengths: the valid ones are short; the rest are refused (so no call runs for long).
T_END = [0.01, 0.05, 0.1, 0, -1, math.nan, math.inf, 1e308, 2e6, "1", None, 1j]
DT = [None, 1e-3, 5e-4, 0, -1e-3, math.nan, "x", 3e-4, 1j]
KEYS = {
    "robot": ["mass", "wheel_radius", "half_track", "com_offset", "wheel_inertia", "gear_ratio", "coulomb_friction", "mas"],
    "drive": ["kind", "motor_torque_max", "voltage_max", "torque_constant", "bogus"],
    "controller": ["kind", "mode", "kp_theta", "ki_s", "servo_kp", "wheel_speed_max", "control_dt", "hold", "k_rho"],
}
KINDS = ["paper", "polar", "lyapunov", "torque", "dc_motor", "pose", "position", "jet"]


def value(rng: random.Random, depth: int = 0):
    r = rng.random()
    if r < 0.45:
        return rng.choice(NUMBERS)
    if r < 0.6:
        return rng.choice(KINDS)
    if r < 0.8 or depth > 2:
        return rng.choice(JUNK)
    if r < 0.9:
        return [value(rng, depth + 1) for _ in range(rng.randrange(5))]
    return array(rng)


def array(rng: random.Random):
    shape = rng.choice([(3,), (7,), (2,), (0,), (1, 3), (4, 3), (3, 2), ()])
    dtype = rng.choice([np.float64, np.float32, np.int64, np.complex128, np.bool_, object, "U3"])
    a = np.zeros(shape, dtype=dtype)
    if dtype in (np.float64, np.float32) and a.size:
        a.flat[rng.randrange(a.size)] = rng.choice([math.nan, 1e30, -2.0, 0.5])
    return a


def pose(rng: random.Random):
    r = rng.random()
    if r < 0.4:
        return (rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-3, 3))
    if r < 0.6:
        keys = rng.sample(["x", "y", "theta", "theta_deg", "z"], rng.randrange(4))
        return {k: value(rng) if rng.random() < 0.3 else rng.uniform(-2, 2) for k in keys}
    return value(rng)


# Valid values of some keys, so that most scenarios get past the first check.
GOOD = {
    "mass": [5.0, 2, 8.5], "wheel_radius": [0.1, 0.05], "half_track": [0.2], "com_offset": [0.25, -0.1, 0],
    "wheel_inertia": [0.002, 0], "gear_ratio": [0.1, 1], "coulomb_friction": [0.0, 0.01],
    "kind": ["paper", "polar", "lyapunov"], "motor_torque_max": [0.2, math.inf], "mode": ["pose", "position"],
    "kp_theta": [2.0, 0], "ki_s": [0.25], "servo_kp": [14.0, 1e6], "wheel_speed_max": [math.inf, 5.0],
    "control_dt": [1e-3, 2e-3], "hold": ["zero_errors", "freeze"], "k_rho": [0.5],
}


def good_or_not(rng: random.Random, key: str):
    """Mostly a valid value of `key`; one time in six anything."""
    if key in GOOD and rng.random() < 5 / 6:
        return rng.choice(GOOD[key])
    return value(rng)


def table(rng: random.Random, name: str):
    if rng.random() < 0.5:
        return None
    if rng.random() < 0.05:
        return value(rng)
    keys = [k for k in rng.sample(KEYS[name], rng.randrange(4)) if name != "controller" or k != "kind"]
    t = {k: good_or_not(rng, k) for k in keys}
    if name == "drive" and "kind" in t and rng.random() < 0.8:
        t["kind"] = rng.choice(["torque", "dc_motor"])
    return t


def small_pose(rng: random.Random):
    return (rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-3, 3)) if rng.random() < 0.85 else pose(rng)


def table_pose(rng: random.Random):
    """A pose as a scenario table (mostly valid)."""
    if rng.random() < 0.85:
        return {"x": rng.uniform(-2, 2), "y": rng.uniform(-2, 2), "theta_deg": rng.uniform(-180, 180)}
    return pose(rng)


def scenario(rng: random.Random):
    ok = rng.random() < 0.7
    sim = {"t_end": rng.choice([0.01, 0.05, 0.1]) if ok else rng.choice(T_END)}
    if not ok or rng.random() < 0.3:
        sim["dt"] = rng.choice(DT)
        sim["log_dt"] = rng.choice(DT + [0.01])
    sc: dict = {"sim": sim}
    for name in KEYS:
        t = table(rng, name)
        if t is not None:
            sc[name] = t
    if rng.random() < 0.8:
        sc["run"] = [{"start": table_pose(rng), "goal": table_pose(rng)} for _ in range(rng.randrange(1, 4))]
    if rng.random() < 0.3:
        sc["sweep"] = {
            "controllers": [{"kind": rng.choice(["paper", "polar", "lyapunov"] if ok else KINDS)}],
            "random": {
                "n": rng.choice([1, 3]) if ok else rng.choice([0, -1, 2**40, "x"]),
                "radius": rng.choice([0.5, 1.0]) if ok else rng.choice([1e308, -1, math.nan]),
            },
        }
    if rng.random() < 0.1:
        sc[rng.choice(["robto", "", "\udcff", "name"])] = value(rng)
    return sc


def call(rng: random.Random):
    """One random call: (what it was, a thunk)."""
    k = rng.randrange(11)
    kw = lambda: {n: table(rng, n) for n in KEYS if rng.random() < 0.4}  # noqa: E731
    if k == 0:
        t_end = rng.choice([0.05, 0.1]) if rng.random() < 0.6 else rng.choice(T_END)
        dt = None if rng.random() < 0.6 else rng.choice(DT)
        return "simulate", lambda: wmr_py.simulate(small_pose(rng), small_pose(rng), t_end=t_end, dt=dt, **kw())
    if k == 1:
        rows = [[rng.uniform(-1, 1) for _ in range(3)] for _ in range(rng.randrange(1, 5))]
        starts = rows if rng.random() < 0.6 else rng.choice([array(rng), value(rng)])
        t_end = rng.choice([0.05, 0.1]) if rng.random() < 0.6 else rng.choice(T_END)
        return "run_batch", lambda: wmr_py.run_batch(starts, small_pose(rng), t_end=t_end, **kw())
    if k in (2, 3):
        return "run_scenario", lambda: wmr_py.run_scenario(scenario(rng))
    if k == 4:
        src = rng.choice([value(rng), str(REPO / "examples" / "missing.toml"), "[sim]\nt_end = 0.05\n[[run]]\ngoal = {x=1}\n", "[[run]\n"])
        return "run_scenario(text)", lambda: wmr_py.run_scenario(src)
    if k == 5:
        return "sweep", lambda: wmr_py.sweep(scenario(rng))
    if k == 6:
        return "Robot", lambda: wmr_py.Robot(**{key: good_or_not(rng, key) for key in rng.sample(KEYS["robot"], rng.randrange(3))})
    if k == 7:
        args = (rng.choice([array(rng), value(rng), [0.0] * 7]), rng.choice([array(rng), value(rng), (0.0, 0.0)]), rng.choice(NUMBERS + JUNK))
        return "Robot.step", lambda: wmr_py.Robot().step(*args)
    if k == 8:
        m = rng.choice(["derivative", "kinetic_energy", "wheel_speeds"])
        state = rng.choice([array(rng), value(rng), [0.0] * 7])
        extra = (rng.choice([array(rng), value(rng), (0.0, 0.0)]),) if m == "derivative" else ()
        return f"Robot.{m}", lambda: getattr(wmr_py.Robot(), m)(state, *extra)
    if k == 9:
        gains = {key: good_or_not(rng, key) for key in rng.sample(KEYS["controller"][1:], rng.randrange(3))}
        return "PaperController", lambda: wmr_py.PaperController(pose(rng), **gains)
    args = tuple(rng.choice([array(rng), value(rng), (0.1, 0.2, 0.3), (0.0, 0.0)]) for _ in range(3))
    return "PaperController.update", lambda: wmr_py.PaperController((1, 1, 0)).update(*args)


def check(what: str, thunk) -> str | None:
    """None when the call ended as documented, else what went wrong."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            thunk()
    except wmr_py.ParameterError as e:
        key = getattr(e, "key", None)
        if not isinstance(key, str) or not key:
            return f"{what}: ParameterError without a key: {e!r}"
        if not str(e).startswith(f"{key}: "):
            return f"{what}: message does not start with the key {key!r}: {e}"
    except (FileNotFoundError, PermissionError, IsADirectoryError) as e:
        if getattr(e, "key", None) != "scenario":
            return f"{what}: {type(e).__name__} without key 'scenario': {e!r}"
    except (FloatingPointError, MemoryError):
        pass
    except BaseException as e:  # noqa: BLE001 - anything else is the finding
        return f"{what}: {type(e).__name__}: {e!r}"[:400]
    return None


def test_random_calls_raise_only_documented_exceptions() -> None:
    cases = int(os.environ.get("WMR_FUZZ_CASES", "5000"))
    seed = int(os.environ.get("WMR_FUZZ_SEED", "12"))
    started = time.monotonic()
    failures = []
    for i in range(cases):
        rng = random.Random(seed * 1_000_003 + i)
        what, thunk = call(rng)
        found = check(what, thunk)
        if found:
            failures.append(f"case {i} (seed {seed}): {found}")
    print(f"{cases} calls in {time.monotonic() - started:.1f} s")
    assert not failures, f"{len(failures)} failures:\n" + "\n".join(failures[:30])
