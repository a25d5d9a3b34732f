"""wmr_py: simulate and control two-wheeled differential-drive robots, with numpy.

The models, the paper's controller and the scenario runner are the Rust crates of wmr
(wmr-core, wmr-scenario); this package is a thin layer over them (``wmr_py._native``).
SI units and radians everywhere; keys ending in ``_deg`` take degrees.

- ``run_scenario(path_or_toml_or_dict)``: every run of a scenario (docs/scenario.md) as
  numpy columns plus its summary.
- ``simulate(start, goal, ...)``: one run with keyword overrides; ``simulate(start,
  reference=...)`` tracks a moving reference (a ``Reference`` or a dict of the
  scenario's ``[reference]`` keys) with a tracking law.
- ``run_batch(starts, goal, ...)``: many starts in parallel, the GIL released (also
  with ``reference=``).
- ``sweep(scenario)``: every law from every start of a ``[sweep]``.
- ``Robot`` and one controller class per law (``LAW_CLASSES``: ``PaperController``,
  ``PaperBidirectionalController``, ``PolarController``, ``LyapunovController`` towards a
  goal; ``KanayamaController``, ``BacksteppingController``, ``PurePursuitController``
  along a ``Reference``): building blocks for loops closed in Python, one robot or a
  batch of N as (N, k) arrays.
- ``ParameterError`` / ``ScenarioError`` (both ``ValueError``): bad input, ``err.key`` names it.

Results pickle (processes, joblib, Dask, caches) and become data: ``RunResult.to_pandas()``,
``run_batch(...).to_pandas()``, ``sweep(...).to_pandas()`` and ``.to_xarray()`` (pandas and
xarray are optional). ``progress=True`` shows a tqdm bar; ``executor=`` runs a batch or a
sweep in parts on any executor with ``submit`` (a process pool, a Dask client).

Example::

    import wmr_py
    r = wmr_py.simulate(start=(0, 0, 0), goal={"x": 1, "y": 1, "theta_deg": 120})
    print(r.summary)
    r.x, r.y, r.omega_r          # float64 ndarrays, one value per 10 ms sample
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any, Optional, Sequence, Union

import numpy as np

from ._native import (
    ParameterError,
    Reference,
    Robot,
    RunResult,
    ScenarioError,
)
from ._laws import *  # noqa: F401,F403 (one class per law of the registry: LAW_CLASSES)
from . import _laws, _native, _results
from ._results import BatchResult, SweepResult

__version__: str = _native.__version__

#: The sample columns of a RunResult and of the CSV after ``run``, in order (wmr-scenario's list).
COLUMNS: tuple = _native.COLUMNS
#: The unit of each of COLUMNS.
COLUMN_UNITS: tuple = _native.COLUMN_UNITS
#: The CSV header: ``run``, then COLUMNS.
CSV_COLUMNS: tuple = _native.CSV_COLUMNS
#: The measured-pose columns a RunResult has after COLUMNS (and the CSV with a [sensor]).
MEASURED_COLUMNS: tuple = _native.MEASURED_COLUMNS
#: The dead-reckoned pose columns a run on odometry's RunResult (and CSV) has after the
#: measured (then fused) pose (wmr-scenario's list).
ODOMETRY_COLUMNS: tuple = _native.ODOMETRY_COLUMNS
#: The unit of each of ODOMETRY_COLUMNS.
ODOMETRY_UNITS: tuple = _native.ODOMETRY_UNITS
#: The wheel-ground contact columns a run whose wheels slip has (RunResult and CSV), after
#: the odometry's place (wmr-scenario's list).
CONTACT_COLUMNS: tuple = _native.CONTACT_COLUMNS
#: The unit of each of CONTACT_COLUMNS.
CONTACT_UNITS: tuple = _native.CONTACT_UNITS
#: The outcome arrays of run_batch and sweep, in order.
OUTCOME_FIELDS: tuple = _native.OUTCOME_FIELDS
#: A run has converged when its final distance to the goal is below this, m.
ARRIVAL_RADIUS_M: float = _native.ARRIVAL_RADIUS_M
#: The reference columns a tracking run's RunResult (and CSV) has: the reference at each
#: sample's t (wmr-scenario's list).
REFERENCE_COLUMNS: tuple = _native.REFERENCE_COLUMNS
#: The unit of each of REFERENCE_COLUMNS.
REFERENCE_UNITS: tuple = _native.REFERENCE_UNITS
#: The tracking summary arrays run_batch adds for a tracking scenario (RunResult has them
#: as attributes, with ``tracking_tolerance``).
TRACKING_FIELDS: tuple = _native.TRACKING_FIELDS

__all__ = [
    "ARRIVAL_RADIUS_M",
    "BatchResult",
    "COLUMNS",
    "COLUMN_UNITS",
    "CONTACT_COLUMNS",
    "CONTACT_UNITS",
    "CSV_COLUMNS",
    "MEASURED_COLUMNS",
    "ODOMETRY_COLUMNS",
    "ODOMETRY_UNITS",
    "OUTCOME_FIELDS",
    "ParameterError",
    "REFERENCE_COLUMNS",
    "REFERENCE_UNITS",
    "Reference",
    "Robot",
    "RunResult",
    "ScenarioError",
    "SweepResult",
    "TRACKING_FIELDS",
    "run_batch",
    "run_scenario",
    "simulate",
    "sweep",
    *_laws.__all__,
]


def __dir__() -> list[str]:
    """Tab completion shows the API, not the modules this one imports."""
    return sorted([*__all__, "__version__"])

Pose = Union[Sequence[float], Mapping[str, float]]


def _error(arg: str, message: str) -> ParameterError:
    """A ParameterError about the argument ``arg``: ``.key`` names it."""
    err = ParameterError(f"{arg}: {message}")
    err.key = arg
    err.line = None
    return err


def _real_array(value: Any, arg: str, what: str) -> np.ndarray:
    """``value`` as a float64 array of real numbers: text, complex numbers (whose imaginary
    part would be lost), objects and ragged nestings raise ParameterError naming ``arg``."""
    if isinstance(value, (str, bytes, bytearray, memoryview)):
        raise _error(arg, f"expected {what}, got {type(value).__name__} {value!r:.40}")
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as e:
        # A ragged nesting ([[1, 2, 3], [4, 5]]) or an object numpy cannot read.
        raise _error(arg, f"expected {what}: {e}") from None
    if arr.dtype.kind not in "iuf":
        kinds = {"c": "complex numbers", "b": "booleans", "U": "strings", "S": "bytes", "O": "Python objects"}
        got = kinds.get(arr.dtype.kind, f"values of dtype {arr.dtype}")
        raise _error(arg, f"expected {what}, got {got}")
    return arr.astype(np.float64)


def _pose(value: Any, arg: str) -> Any:
    """A pose as the scenario's pose table: a mapping is passed on as is (the scenario
    parser checks its keys), a sequence must be (x_m, y_m, theta_rad)."""
    if isinstance(value, Mapping):
        return dict(value)
    what = "(x, y, theta_rad) or a dict with x, y, theta or theta_deg"
    arr = _real_array(value, arg, what)
    if arr.shape != (3,):
        raise _error(arg, f"expected 3 numbers (x, y, theta_rad), got shape {arr.shape}")
    return {"x": float(arr[0]), "y": float(arr[1]), "theta": float(arr[2])}


def _table(value: Any, arg: str) -> Optional[dict]:
    if value is None:
        return None
    if isinstance(value, Robot):
        return value.to_dict()
    if isinstance(value, Mapping):
        return dict(value)
    raise _error(arg, f"expected a dict of scenario keys, got {type(value).__name__}")


def _reference(value: Any) -> Optional[dict]:
    """The ``reference=`` argument as the scenario's ``[reference]`` table: a Reference's
    keys, or a dict passed on as is (the scenario parser checks its keys)."""
    if value is None:
        return None
    if isinstance(value, Reference):
        return value.to_dict()
    if isinstance(value, Mapping):
        return dict(value)
    raise _error(
        "reference", f"expected a wmr_py.Reference or a dict of [reference] keys, got {type(value).__name__}"
    )


def _scenario(
    runs: list,
    robot: Any,
    drive: Any,
    controller: Any,
    t_end: float,
    dt: Optional[float],
    log_dt: Optional[float],
    sensor: Any = None,
    world: Any = None,
    reference: Any = None,
) -> dict:
    sc: dict = {"name": "simulate", "run": runs, "sim": {"t_end": t_end, "dt": dt, "log_dt": log_dt}}
    ref = _reference(reference)
    if ref is not None:
        sc["reference"] = ref
    tables = (("robot", robot), ("drive", drive), ("controller", controller), ("sensor", sensor), ("world", world))
    for key, value in tables:
        table = _table(value, key)
        if table is not None:
            sc[key] = table
    return sc


def simulate(
    start: Pose,
    goal: Optional[Pose] = None,
    robot: Union[None, Robot, Mapping[str, float]] = None,
    drive: Optional[Mapping[str, Any]] = None,
    controller: Optional[Mapping[str, Any]] = None,
    t_end: float = 60.0,
    dt: Optional[float] = None,
    log_dt: float = 0.01,
    label: Optional[str] = None,
    sensor: Optional[Mapping[str, Any]] = None,
    world: Optional[Mapping[str, Any]] = None,
    reference: Union[None, Reference, Mapping[str, Any]] = None,
) -> RunResult:
    """Simulate one run of the closed loop and return its RunResult.

    start, goal: poses of point C, as ``(x_m, y_m, theta_rad)`` or a dict with ``x``,
    ``y`` and ``theta`` (rad) or ``theta_deg`` (degrees).
    reference: instead of a goal, a moving reference to track (a ``Reference`` or a dict
    of the scenario's ``[reference]`` keys, ``{"kind": "circle", "radius": 1.0}``), with
    a tracking law (``controller={"kind": "kanayama"}``, ``"backstepping"`` or
    ``"pure_pursuit"``). The result then has the reference columns (``x_ref``, ``y_ref``,
    ``theta_ref``, ``v_ref``, ``omega_ref``, as the CSV) and the tracking summary
    (``rms_error``, ``max_error``, ``time_to_tolerance``, ``final_error``); it
    converged when the tracking error stayed below ``sim.tracking_tolerance`` (1 cm)
    over the last 10 % of t_end.
    robot, drive, controller: overrides with the scenario's ``[robot]``, ``[drive]`` and
    ``[controller]`` keys (docs/scenario.md); ``robot`` may also be a ``Robot``.
    t_end: simulated time, s. dt: RK4 step, s (default: the controller's control_dt,
    1 ms). log_dt: output sample period, s (a whole multiple of dt). The result keeps
    t_end / log_dt + 1 samples of 18 float64 columns (144 bytes each: 0.9 MB for 60 s at
    the default 0.01 s); a run whose columns would not fit in the memory available is
    refused before it starts, with a ParameterError naming ``sim.log_dt`` and the value
    that would fit.
    sensor, world: the scenario's ``[sensor]`` (pose rate, latency, noise, encoders, seed)
    and ``[world]`` (slope) keys; a ``controller`` dict may hold a ``model`` dict (the
    controller's idea of the robot). With ``sensor``, ``x_meas``, ``y_meas`` and
    ``theta_meas`` are the pose the controller used.

    The same as ``run_scenario`` on a one-run scenario: same parser, checks and loop.
    Raises ScenarioError naming the key (e.g. ``robot.mass``, ``run[0].start.x``).
    """
    # A tracking run gives its start only (the reference is its goal): a goal given
    # with a reference is left to the scenario parser, which names run[0].goal.
    run: dict = {"start": _pose(start, "start")}
    if goal is not None or reference is None:
        run["goal"] = _pose(goal, "goal") if goal is not None else None
    if label is not None:
        run["label"] = label
    sc = _scenario([run], robot, drive, controller, t_end, dt, log_dt, sensor, world, reference)
    return run_scenario(sc)[0]


def run_batch(
    starts: Any,
    goal: Optional[Pose] = None,
    robot: Union[None, Robot, Mapping[str, float]] = None,
    drive: Optional[Mapping[str, Any]] = None,
    controller: Optional[Mapping[str, Any]] = None,
    t_end: float = 60.0,
    dt: Optional[float] = None,
    sensor: Optional[Mapping[str, Any]] = None,
    world: Optional[Mapping[str, Any]] = None,
    *,
    progress: bool = False,
    executor: Any = None,
    chunk_size: Optional[int] = None,
    fast: bool = False,
    reference: Union[None, Reference, Mapping[str, Any]] = None,
) -> BatchResult:
    """Run the closed loop from many starts to one goal in parallel (rayon, the GIL
    released) and return a BatchResult: a dict of 1-D arrays, one entry per start, in order:

    ``start`` (int64), ``x0``, ``y0`` (m), ``theta0`` (rad): the starts; ``final_x``,
    ``final_y`` (m), ``final_theta`` (rad), ``final_dl`` (m), ``final_heading_error``
    (rad, wrap(theta_d - theta)), ``time_to_1cm`` (s; NaN if dl never stays below 1 cm),
    ``t_final`` (s), ``peak_wheel_speed`` (rad/s), ``path_length`` (m), ``energy`` (J)
    as float64; ``converged`` and ``diverged`` as bool. ``.arrival_radius`` (m, the 1 cm
    threshold) and ``.law`` are attributes; ``.to_pandas()`` gives one row per start.

    starts: array-like of shape (N, 3): rows (x_m, y_m, theta_rad).
    goal, robot, drive, controller, t_end, dt, sensor, world: as for ``simulate``; run i
    draws its sensor noise from stream i.
    progress: show a tqdm bar (needs tqdm); it costs the runs nothing measurable.
    executor: any object with ``submit(fn, *args)`` returning futures with ``.result()``
    (``concurrent.futures.ProcessPoolExecutor``, ``dask.distributed.Client``): the starts
    go in parts of ``chunk_size`` (default: about 32 parts), each run on one thread in a
    worker; the result is the local call's, bit for bit, in order.
    fast: step the runs in SIMD lanes, several at once (as ``wmr-cli sweep --fast``):
    several times faster, not bit-identical to the exact path (final poses within about
    1e-9 relative; docs/scenario.md, "The fast path"). Runs with a real sensor or a
    reference take the exact path.
    reference: instead of a goal, a moving reference every start tracks (as for
    ``simulate``); the result then also has ``rms_error``, ``max_error`` (m, over the
    last half), ``time_to_tolerance`` (s; NaN if the error is above the tolerance at the
    end) and ``final_error`` (m), and ``converged`` is the tracking rule's.
    """
    arr = np.ascontiguousarray(_real_array(starts, "starts", "an array of shape (N, 3) of (x, y, theta_rad)"))
    if arr.ndim != 2 or arr.shape[1] != 3 or arr.shape[0] == 0:
        raise _error("starts", f"expected an array of shape (N, 3), N >= 1, got shape {arr.shape}")
    # The base scenario carries the goal and every setting; the scenario parser checks it
    # with the first start, then each start becomes a run. Logging is not needed, so
    # log_dt = t_end (a whole multiple of dt whenever t_end is).
    first = arr[0]
    base_start: Optional[dict] = {"x": float(first[0]), "y": float(first[1]), "theta": float(first[2])}
    # A first start the scenario would refuse is left to the native check, which names it
    # as starts[i, j].
    if not all(math.isfinite(v) for v in first) or max(abs(first[0]), abs(first[1])) > 1000.0:
        base_start = None
    run: dict = {"start": base_start}
    if goal is not None or reference is None:
        run["goal"] = _pose(goal, "goal") if goal is not None else None
    base = _scenario([run], robot, drive, controller, t_end, dt, t_end, sensor, world, reference)
    law = str(controller.get("kind", "paper")) if isinstance(controller, Mapping) else "paper"
    bar = _results.progress_bar(progress, "run_batch", "run")
    try:
        if executor is None:
            out = _native._run_batch(base, arr, None, 0, 0, bar, fast)
        else:
            _results.check_executor(executor)
            # Checked here as the local call checks them, so an error names starts[i, j]
            # of the whole batch, not of a part.
            for (i, j) in zip(*np.nonzero(~np.isfinite(arr))):
                raise _error(f"starts[{i}, {j}]", f"{('x', 'y', 'theta')[j]} must be a finite number (got {arr[i, j]})")
            for (i, j) in zip(*np.nonzero(np.abs(arr[:, :2]) > 1000.0)):
                raise _error(f"starts[{i}, {j}]", f"{('x', 'y')[j]} must be within 1000 m of the origin (got {arr[i, j]:e})")
            parts = _results.chunks(len(arr), chunk_size)
            tasks = [(base, arr[a:b], None, a, fast) for a, b in parts]
            outs = _results.run_tasks(executor, _results.batch_task, tasks, bar, [b - a for a, b in parts])
            out = _results.gather_batch(outs, parts, arr)
    finally:
        if bar is not None:
            bar.close()
    res = BatchResult(law=law)
    res["start"] = np.arange(len(arr), dtype=np.int64)
    res["x0"], res["y0"], res["theta0"] = arr[:, 0].copy(), arr[:, 1].copy(), arr[:, 2].copy()
    res.update(out)
    return res


def run_scenario(scenario: Any, *, progress: bool = False) -> list[RunResult]:
    """Run every ``[[run]]`` of a scenario and return one RunResult per run, in run order.

    scenario: a path (str or os.PathLike) to a TOML file, TOML text, or a dict with the
    same keys (docs/scenario.md; None values take the default). Runs go in parallel with
    the GIL released. Raises ScenarioError (a ValueError) naming the bad key.
    progress: show a tqdm bar of the samples logged (needs tqdm).

    Memory: every run keeps its columns, 18 float64 arrays of t_end / log_dt + 1 values
    (144 bytes per sample; a 60 s run at the default log_dt = 0.01 s takes 0.9 MB). A
    scenario whose columns would not fit in the memory available is refused before it
    runs, with a ParameterError naming ``sim.log_dt`` and the value that would fit.
    """
    bar = _results.progress_bar(progress, "run_scenario", "sample")
    try:
        return _native.run_scenario(scenario, bar)
    finally:
        if bar is not None:
            bar.close()


def sweep(
    scenario: Any,
    *,
    progress: bool = False,
    executor: Any = None,
    chunk_size: Optional[int] = None,
    fast: bool = False,
) -> SweepResult:
    """Run a scenario's ``[sweep]``: every law from every start (and every variant and
    trial of ``vary``), in parallel with the GIL released, and return a SweepResult (a
    dict of 1-D arrays, one entry per run, with ``.to_pandas()`` and ``.to_xarray()``).

    scenario: a path, TOML text or a dict, as for ``run_scenario``.
    progress: show a tqdm bar of the runs (needs tqdm).
    executor: any object with ``submit(fn, *args)`` returning futures with ``.result()``
    (a process pool, a Dask client): the runs go in parts of ``chunk_size`` (default:
    about 32 parts), each run on one thread in a worker, which parses the scenario's
    text again (a file need not exist on the workers); the result is the local call's,
    bit for bit, in order.
    fast: step the runs in SIMD lanes (``wmr-cli sweep --fast``): several times faster,
    not bit-identical to the exact path; with an executor, the local fast call's result.
    """
    bar = _results.progress_bar(progress, "sweep", "run")
    try:
        if executor is None:
            return SweepResult(_native._sweep(scenario, bar, fast))
        _results.check_executor(executor)
        text, n = _native._sweep_plan(scenario)
        parts = _results.chunks(n, chunk_size)
        tasks = [(text, a, b, fast) for a, b in parts]
        rows = _results.run_tasks(executor, _results.sweep_task, tasks, bar, [b - a for a, b in parts])
        stacked = np.concatenate(rows) if rows else np.zeros((0, _native._SWEEP_ROW_LEN))
        return SweepResult(_native._sweep_gather(text, stacked))
    finally:
        if bar is not None:
            bar.close()


# Pickling: the native classes reduce to these (module-level, found by name on unpickling).


def _make_robot(params: dict) -> Robot:
    return Robot(**params)


def _make_reference(keys: dict) -> Reference:
    keys = dict(keys)
    return Reference(keys.pop("kind"), **keys)


def _restore_run_result(state: dict) -> RunResult:
    return _native._run_result_from_state(state)


def _restore_controller(class_name: str, scenario_toml: str) -> Any:
    return _native._controller_from_toml(class_name, scenario_toml)
