"""Results as data (pandas, xarray), progress bars and outside executors for wmr_py.

pandas, xarray and tqdm are optional: they are imported when a method needs them, and a
missing one raises ImportError naming the package (tqdm: a warning, the run goes on).
"""

from __future__ import annotations

import importlib
import importlib.util
import math
import sys
import warnings
from collections.abc import Mapping
from typing import Any, Callable, Optional, Sequence

import numpy as np

from . import _native

#: Outcome arrays of run_batch and sweep, in order (float64 except converged/diverged):
#: the native module's list, named once next to the values in Rust.
OUTCOME_FIELDS: tuple = _native.OUTCOME_FIELDS

#: A run has converged when its final distance to the goal is below this, m (wmr-core's).
ARRIVAL_RADIUS_M: float = _native.ARRIVAL_RADIUS_M

#: The tracking summary arrays of a batch (or sweep) of a tracking scenario, after
#: OUTCOME_FIELDS (float64, m, m, s, m): the native module's list.
TRACKING_FIELDS: tuple = _native.TRACKING_FIELDS

#: A tracking run's summary as RunResult attributes: TRACKING_FIELDS and the tolerance.
RUN_TRACKING_FIELDS: tuple = (*_native.TRACKING_FIELDS, "tracking_tolerance_m")


def require(package: str, what: str) -> Any:
    """Imports an optional package, or raises ImportError naming it and what needs it."""
    try:
        return importlib.import_module(package)
    except ImportError as e:
        raise ImportError(f"{what} needs {package}, which is not installed: pip install {package}") from e


#: Every run's status word, as the CLI's CSV writes it, in report order (wmr-core's
#: ``Status``): a tracking run whose reference asks more than the robot can give is
#: ``cannot_follow``, neither converged nor diverged.
STATUSES: tuple = ("converged", "diverged", "unsettled", "cannot_follow")


def _status(res: Any) -> np.ndarray:
    """Each run's status word: the native ``status`` entry; a result without one (built
    by hand from ``converged`` and ``diverged``) cannot tell cannot_follow from unsettled."""
    if "status" in res:
        return np.asarray(res["status"], dtype=str)
    return np.where(res["converged"], "converged", np.where(res["diverged"], "diverged", "unsettled"))


def _shares(res: Any) -> str:
    if "converged" not in res or "diverged" not in res:
        return "no runs"
    status = _status(res)
    n = max(len(status), 1)
    shares = [f"{100 * int(np.sum(status == s)) / n:.1f}% {s}" for s in STATUSES]
    # cannot_follow only where a run is (a goal's batch never is).
    return ", ".join(shares if "cannot_follow" in status else shares[:3])


def _run_columns(r: Any) -> dict:
    """A RunResult's columns in CSV order (``r.column_names``): COLUMNS, the measured pose,
    then a run on odometry's ODOMETRY_COLUMNS, a slipping run's CONTACT_COLUMNS and a
    tracking run's reference columns (x_ref ... omega_ref) last."""
    return {name: r[name] for name in r.column_names}


def _run_attrs(r: Any) -> dict:
    """A RunResult's summary: run, label, status and, for a tracking run, its tracking
    summary (RUN_TRACKING_FIELDS: time_to_tolerance_s, or None, rms_error_m, max_error_m,
    final_error_m and tracking_tolerance_m)."""
    attrs: dict = {"run": r.run, "label": r.label, "status": r.status, "summary": r.summary}
    if r.tracking:
        for name in RUN_TRACKING_FIELDS:
            attrs[name] = getattr(r, name)
    return attrs


def run_result_to_pandas(r: Any) -> Any:
    """RunResult.to_pandas(): every CSV column with `run` and `label`, one row per sample;
    a tracking run's reference columns, and its tracking summary in ``df.attrs``."""
    pd = require("pandas", "RunResult.to_pandas()")
    n = len(r)
    data = {"run": np.full(n, r.run, dtype=np.int64), "label": np.full(n, r.label, dtype=object)}
    data.update(_run_columns(r))
    df = pd.DataFrame(data)
    df.attrs.update(_run_attrs(r))
    return df


def run_result_to_xarray(r: Any) -> Any:
    """RunResult.to_xarray(): every column as a variable along ``t`` (s), its unit in the
    variable's ``units``; the summary (with a tracking run's) as the Dataset's attributes."""
    xr = require("xarray", "RunResult.to_xarray()")
    units = dict(zip(_native.COLUMNS, _native.COLUMN_UNITS))
    units.update(zip(_native.MEASURED_COLUMNS, ("m", "m", "rad")))
    units.update(zip(_native.ODOMETRY_COLUMNS, _native.ODOMETRY_UNITS))
    units.update(zip(_native.CONTACT_COLUMNS, _native.CONTACT_UNITS))
    units.update(zip(_native.REFERENCE_COLUMNS, _native.REFERENCE_UNITS))
    cols = _run_columns(r)
    t = cols.pop("t")
    data_vars = {k: ("t", v, {"units": units[k]}) for k, v in cols.items()}
    attrs = {k: ("none" if v is None else v) for k, v in _run_attrs(r).items()}
    return xr.Dataset(data_vars, coords={"t": ("t", t, {"units": "s"})}, attrs=attrs)


class _Entries(dict):
    """A dict whose entries read as attributes too: ``res.converged is res["converged"]``,
    as a RunResult's columns are ``r.x`` and ``r["x"]``. Attributes of the class (``law``,
    ``to_pandas``) come first; an unknown name raises AttributeError naming the entries."""

    def __getattr__(self, name: str) -> Any:
        # Called only when normal lookup fails: the instance's and class's attributes win.
        if name.startswith("__"):
            raise AttributeError(name)
        try:
            return self[name]
        except KeyError:
            raise AttributeError(
                f"{type(self).__name__} has no attribute or entry {name!r}; its entries: {', '.join(self)}"
            ) from None

    def __dir__(self) -> list:
        return sorted(set(super().__dir__()) | {k for k in self if isinstance(k, str) and k.isidentifier()})


class BatchResult(_Entries):
    """The outcome of ``run_batch``: a dict of 1-D arrays, one entry per start, in order.

    ``start`` (int64), ``x0``, ``y0`` (m), ``theta0`` (rad): the starts; the outcome
    fields of ``OUTCOME_FIELDS`` as float64, each name ending in its unit (``final_x_m``,
    ``final_theta_deg``, ``final_dl_m``, ``time_to_1cm_s``: NaN if dl never stays below
    1 cm, ..., ``abs_work_j``; ``wmr-cli help keys outputs`` says what each is);
    ``converged`` and ``diverged`` as bool; ``status`` (list of str, each run's word as
    the CLI's CSV writes it: ``cannot_follow`` for a tracking run whose reference asks
    more than the robot can give). Attributes: ``law`` (the controller's
    kind), ``arrival_radius`` (m, the 1 cm threshold of ``converged``); every entry reads
    as an attribute too (``res.converged``, ``res["converged"]``).
    """

    law: str
    arrival_radius: float

    def __init__(self, data: Any = (), law: str = "paper") -> None:
        super().__init__(data)
        self.law = law
        self.arrival_radius = ARRIVAL_RADIUS_M

    def __len__(self) -> int:  # the number of starts, not of keys
        return len(self["start"]) if "start" in self else 0

    def to_pandas(self) -> Any:
        """One row per start: law, start, x0, y0, theta0, status and the outcome columns."""
        pd = require("pandas", "BatchResult.to_pandas()")
        n = len(self)
        data: dict = {"law": np.full(n, self.law, dtype=object)}
        for k in ("start", "x0", "y0", "theta0"):
            data[k] = self[k]
        data["status"] = _status(self)
        for k in (*OUTCOME_FIELDS, *TRACKING_FIELDS):
            if k in self:
                data[k] = self[k]
        return pd.DataFrame(data)

    def __repr__(self) -> str:
        return f"<BatchResult: {len(self)} starts, law {self.law}: {_shares(self)}>"


class SweepResult(_Entries):
    """The outcome of ``sweep``: a dict of 1-D arrays, one entry per run, in law then
    variant, trial and start order: ``law`` (list of names), ``start`` (int64), ``x0``,
    ``y0`` (m), ``theta0`` (rad), the outcome arrays of ``run_batch``, one array per
    varied key of ``[sweep] vary`` (the value each run used), and ``table`` (the CLI's
    comparison table). A sweep over references (``[sweep] references``) adds ``reference``
    (the reference's name per run) and the tracking arrays (``TRACKING_FIELDS``:
    ``time_to_tolerance_s`` ... ``final_error_m``); its ``converged``/``diverged`` are the tracking rule's.

    Attributes: ``laws`` (names, in order), ``references`` (names, in order; empty for a
    sweep towards a goal), ``tracking_tolerance_m`` (or None), ``varied`` ({key: "values", "uniform" or
    "normal"}), ``trials``, ``scenario_toml`` (the resolved scenario), ``seed`` (of the
    draws), ``starts_seed`` (of random starts, or None), ``goal``, ``version`` (wmr's);
    every entry reads as an attribute too (``res.table``, ``res["table"]``; ``res.law`` is
    the entry, one name per run, ``res.laws`` the names in order).
    """

    laws: list
    references: list
    tracking_tolerance_m: Optional[float]
    varied: dict
    trials: int
    scenario_toml: str
    seed: int
    starts_seed: Optional[int]
    goal: tuple
    version: str

    def __init__(self, data: Any = ()) -> None:
        data = dict(data)
        meta = data.pop("_meta", {})
        self.trial = meta.get("trial")
        super().__init__(data)
        self.laws = list(meta.get("laws", []))
        self.references = list(meta.get("references", []))
        self.tracking_tolerance_m = meta.get("tracking_tolerance_m")
        self.varied = dict(meta.get("varied", {}))
        self.trials = int(meta.get("trials", 1))
        self.scenario_toml = meta.get("scenario_toml", "")
        self.seed = int(meta.get("seed", 0))
        self.starts_seed = meta.get("starts_seed")
        self.goal = tuple(meta.get("goal", (0.0, 0.0, 0.0)))
        self.version = _native.__version__

    def __len__(self) -> int:  # the number of runs
        return len(self["start"]) if "start" in self else 0

    def to_pandas(self) -> Any:
        """One row per run (law, reference, start, variant, trial): law, reference (a sweep
        over references), start, x0, y0, theta0, the varied keys, trial (when trials > 1),
        status and the outcome columns (and the tracking ones)."""
        pd = require("pandas", "SweepResult.to_pandas()")
        data: dict = {"law": np.asarray(self["law"], dtype=object)}
        if self.references:
            data["reference"] = np.asarray(self["reference"], dtype=object)
        for k in ("start", "x0", "y0", "theta0"):
            data[k] = self[k]
        for k in self.varied:
            data[k] = self[k]
        if self.trials > 1:
            data["trial"] = self.trial
        data["status"] = _status(self)
        for k in (*OUTCOME_FIELDS, *TRACKING_FIELDS):
            if k in self:
                data[k] = self[k]
        return pd.DataFrame(data)

    def to_xarray(self) -> Any:
        """The sweep as an ``xarray.Dataset`` with dimensions ``law`` x (``reference`` for a
        sweep over references, whose start poses are then data variables: each reference
        has its own) x (one per varied key
        with ``values``) x (``trial`` when trials > 1) x ``start``; the start poses ``x0``,
        ``y0``, ``theta0`` as coordinates along ``start``. Keys varied one at a time fill
        the cells where the other keys are nominal (NaN elsewhere, and ``converged`` /
        ``diverged`` are then float 1/0/NaN); drawn keys (``uniform``/``normal``) are data
        variables. Attributes: ``scenario`` (resolved TOML), ``seed``, ``starts_seed``,
        ``wmr_version``, ``table``.
        """
        xr = require("xarray", "SweepResult.to_xarray()")
        axis_keys = [k for k, kind in self.varied.items() if kind == "values"]
        drawn_keys = [k for k, kind in self.varied.items() if kind != "values"]
        starts = np.asarray(self["start"])
        n_starts = int(starts.max()) + 1 if len(starts) else 0
        coords: dict = {"law": self.laws}
        idx = [np.array([self.laws.index(name) for name in self["law"]], dtype=np.int64)]
        if self.references:
            coords["reference"] = self.references
            idx.append(np.array([self.references.index(name) for name in self["reference"]], dtype=np.int64))
        for k in axis_keys:
            values = np.unique(self[k])
            coords[k] = values
            idx.append(np.searchsorted(values, self[k]))
        if self.trials > 1:
            coords["trial"] = np.arange(self.trials)
            idx.append(np.asarray(self.trial, dtype=np.int64))
        coords["start"] = np.arange(n_starts)
        idx.append(starts)
        dims = list(coords)
        shape = tuple(len(coords[d]) for d in dims)
        flat = np.ravel_multi_index(tuple(idx), shape)
        # A cell that two variants reach (every key nominal in both) keeps the first run.
        cells, first = np.unique(flat, return_index=True)
        dense = len(cells) == math.prod(shape)
        data_vars = {}
        poses = ["x0", "y0", "theta0"] if self.references else []
        for k in [*OUTCOME_FIELDS, *(f for f in TRACKING_FIELDS if f in self), *drawn_keys, *poses]:
            col = np.asarray(self[k])
            if col.dtype == bool and dense:
                arr = np.zeros(shape, dtype=bool)
            else:
                arr = np.full(shape, np.nan)
            arr.reshape(-1)[cells] = col[first]
            data_vars[k] = (dims, arr)
        if not self.references:
            x0 = np.zeros(n_starts)
            y0 = np.zeros(n_starts)
            t0 = np.zeros(n_starts)
            x0[starts], y0[starts], t0[starts] = self["x0"], self["y0"], self["theta0"]
            coords["x0"] = ("start", x0)
            coords["y0"] = ("start", y0)
            coords["theta0"] = ("start", t0)
        attrs = {
            "scenario": self.scenario_toml,
            "seed": self.seed,
            "wmr_version": self.version,
            "goal": list(self.goal),
            "table": self.get("table", ""),
        }
        if self.starts_seed is not None:
            attrs["starts_seed"] = self.starts_seed
        return xr.Dataset(data_vars, coords=coords, attrs=attrs)

    def __repr__(self) -> str:
        parts = [f"<SweepResult: {len(self)} runs of {len(self.laws)} laws ({', '.join(self.laws)})"]
        if self.varied:
            parts.append(f", varied: {', '.join(self.varied)}")
        return "".join(parts) + ">\n" + str(self.get("table", ""))


def _tqdm_class() -> Any:
    """tqdm.auto's bar where it can draw it: in a Jupyter kernel without ipywidgets,
    importing tqdm.auto warns "IProgress not found" (and falls back to the text bar), so
    the text bar is taken directly there."""
    if importlib.util.find_spec("ipywidgets") is None:
        from tqdm.std import tqdm  # type: ignore

        return tqdm
    from tqdm.auto import tqdm  # type: ignore

    return tqdm


class Bar:
    """A progress callback for the native runs: ``bar(-total)`` opens a tqdm bar (tqdm.auto:
    a widget in a notebook), ``bar(done)`` moves it. Without tqdm: one warning, no bar."""

    def __init__(self, desc: str, unit: str) -> None:
        self.desc, self.unit = desc, unit
        self.bar: Any = None
        try:
            tqdm = _tqdm_class()
        except ImportError:
            warnings.warn("progress=True needs tqdm (pip install tqdm); running without a bar", stacklevel=3)
            self.tqdm = None
        else:
            self.tqdm = tqdm

    def __call__(self, n: int) -> None:
        if self.tqdm is None:
            return
        if n < 0:
            kwargs: dict = {}
            # tqdm.auto gives a widget in a notebook (with ipywidgets). Writing text to a
            # stream that is not a terminal (a log, a notebook run headless by nbclient),
            # where every refresh would become a line of its own, the bar is drawn once
            # at the start and once at the end.
            if not _is_widget(self.tqdm) and not _isatty(sys.stderr):
                kwargs["mininterval"] = float("inf")
            self.bar = self.tqdm(total=-n, desc=self.desc, unit=self.unit, **kwargs)
        elif self.bar is not None:
            self.bar.update(n - self.bar.n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _is_widget(tqdm_class: Any) -> bool:
    """Whether tqdm.auto picked the notebook widget (in a kernel with ipywidgets)."""
    try:
        from tqdm.notebook import tqdm as notebook_tqdm  # type: ignore
    except ImportError:
        return False
    return isinstance(tqdm_class, type) and issubclass(tqdm_class, notebook_tqdm)


def _isatty(stream: Any) -> bool:
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def progress_bar(progress: bool, desc: str, unit: str) -> Optional[Bar]:
    return Bar(desc, unit) if progress else None


def check_executor(executor: Any) -> None:
    if not callable(getattr(executor, "submit", None)):
        err = _native.ParameterError(
            f"executor: expected an object with submit(fn, *args) returning futures "
            f"(concurrent.futures.ProcessPoolExecutor, dask.distributed.Client), got {type(executor).__name__}"
        )
        err.key = "executor"
        err.line = None
        raise err


def chunks(n: int, chunk_size: Optional[int]) -> list:
    """[first, last) ranges covering range(n): `chunk_size` each, or about 32 parts."""
    if chunk_size is None:
        chunk_size = max(1, math.ceil(n / 32))
    if not isinstance(chunk_size, int) or isinstance(chunk_size, bool) or chunk_size < 1:
        err = _native.ParameterError(f"chunk_size: expected an int >= 1, got {chunk_size!r}")
        err.key = "chunk_size"
        err.line = None
        raise err
    return [(a, min(a + chunk_size, n)) for a in range(0, n, chunk_size)]


def run_tasks(executor: Any, fn: Callable, tasks: Sequence[tuple], bar: Optional[Bar], sizes: Sequence[int]) -> list:
    """Submits fn(*task) for every task and returns the results in task order. Waits on
    each future's .result() in order (concurrent.futures.wait does not take Dask's)."""
    futures = [executor.submit(fn, *t) for t in tasks]
    out = []
    done = 0
    if bar is not None:
        bar(-sum(sizes))
    try:
        for f, size in zip(futures, sizes):
            out.append(f.result())
            done += size
            if bar is not None:
                bar(done)
    except BaseException:
        for f in futures:
            cancel = getattr(f, "cancel", None)
            if cancel is not None:
                cancel()
        raise
    return out


# The tasks an outside executor runs: module-level functions, pickled by reference, each
# running its part on one thread in the worker.


def _in_worker(call: Callable[[], Any]) -> Any:
    """call(), with a Rust panic re-raised as a RuntimeError: pyo3's PanicException is a
    BaseException, which a Dask worker does not catch, so the task's future would never
    complete and the caller would wait forever instead of seeing the error."""
    try:
        return call()
    except (KeyboardInterrupt, SystemExit, GeneratorExit):
        raise
    except Exception:
        raise
    except BaseException as e:
        raise RuntimeError(f"wmr_py worker part failed: {type(e).__name__}: {e}") from e


def sweep_task(text: str, first: int, last: int, fast: bool = False) -> np.ndarray:
    """Runs first..last of a sweep on one thread: an (n, _SWEEP_ROW_LEN) array of outcome rows."""
    return _in_worker(lambda: _native._sweep_part(text, first, last, fast))


def batch_task(
    base: dict,
    starts: np.ndarray,
    goals: Optional[np.ndarray],
    first: int,
    fast: bool = False,
    allow_files_under: Optional[list] = None,
) -> dict:
    """Runs a part of a batch (starts[first:...] of the whole) on one thread; the result
    says which part it is (``_first``, ``_starts``), for ``gather_batch`` to check."""
    out = dict(_in_worker(lambda: _native._run_batch(base, starts, goals, first, 1, None, fast, allow_files_under)))
    out["_first"] = first
    out["_starts"] = np.asarray(starts)
    return out


def check_sweep_parts(rows: Sequence[Any], parts: Sequence[tuple]) -> None:
    """Each part an executor returned must be the (n, _SWEEP_ROW_LEN) float array of its
    runs: anything else (None, a foreign object, rows of another shape) raises
    ParameterError naming the part (``key == "executor"``), as ``gather_batch`` does;
    which rows they are is checked by ``_sweep_gather``."""
    for k, (r, (a, b)) in enumerate(zip(rows, parts)):
        shape = np.shape(r) if isinstance(r, np.ndarray) else None
        if shape != (b - a, _native._SWEEP_ROW_LEN) or r.dtype.kind != "f":
            got = type(r).__name__ if shape is None else f"an array of shape {shape} ({r.dtype})"
            err = _native.ParameterError(
                f"executor: part {k} (runs {a}:{b}) returned {got}, "
                f"expected the ({b - a}, {_native._SWEEP_ROW_LEN}) float rows of its runs"
            )
            err.key = "executor"
            err.line = None
            raise err


def gather_batch(outs: Sequence[Any], parts: Sequence[tuple], starts: np.ndarray) -> dict:
    """The whole batch from the parts an executor returned, each checked to be the part
    asked for (its first index and its starts, bit for bit) with every outcome array of
    its length: a swapped, short or foreign result raises ParameterError naming the
    part, as the sweep does, instead of being accepted."""

    def bad(k: int, why: str) -> Exception:
        err = _native.ParameterError(f"executor: part {k} (starts[{parts[k][0]}:{parts[k][1]}]) {why}")
        err.key = "executor"
        err.line = None
        return err

    if len(outs) != len(parts):
        raise bad(len(outs) - 1 if len(outs) > len(parts) else len(outs), f"missing: {len(outs)} results for {len(parts)} parts")
    for k, (o, (a, b)) in enumerate(zip(outs, parts)):
        if not isinstance(o, Mapping):
            raise bad(k, f"returned {type(o).__name__}, not the dict of a batch part")
        if o.get("_first") != a or not np.array_equal(np.asarray(o.get("_starts")), starts[a:b]):
            raise bad(k, "returned the result of another part (swapped or foreign)")
    # A tracking scenario's parts carry the tracking arrays too (each part, as the first).
    fields = [*OUTCOME_FIELDS, *(f for f in TRACKING_FIELDS if outs and isinstance(outs[0], Mapping) and f in outs[0])]
    fields.append("status")
    for k, (o, (a, b)) in enumerate(zip(outs, parts)):
        for f in fields:
            col = o.get(f)
            if col is None or np.ndim(col) != 1 or len(col) != b - a:
                got = "missing" if col is None else f"of shape {np.shape(col)}"
                raise bad(k, f"returned {f} {got}, expected {b - a} values")
    return {f: np.concatenate([o[f] for o in outs]) for f in fields}
