"""run_batch and sweep on outside executors and with progress bars (issue 14): parts run
in workers give the local call's result bit for bit, in order."""

from __future__ import annotations

import multiprocessing
import os
import time
from concurrent.futures import Future, ProcessPoolExecutor

import numpy as np
import pytest

import wmr_py
from test_data import VARY_SWEEP, same

NOISY = {"position_noise": 0.01, "heading_noise_deg": 0.5, "seed": 3}


def starts(n: int) -> np.ndarray:
    rng = np.random.default_rng(7)
    return np.column_stack([rng.uniform(-1.5, 1.5, (n, 2)), rng.uniform(-np.pi, np.pi, n)])


class ReverseExecutor:
    """Runs each task when its result is asked for, and hands out futures that finish in
    reverse order of submission (the last submitted runs first): the order of the parts
    must come from the caller, not from when they finish."""

    def __init__(self) -> None:
        self.submitted: list = []

    def submit(self, fn, *args):  # noqa: ANN001, ANN201
        f: Future = Future()
        self.submitted.append((f, fn, args))
        return _Lazy(self, f)

    def run_all(self) -> None:
        for f, fn, args in reversed(self.submitted):
            if not f.done():
                f.set_result(fn(*args))


class _Lazy:
    def __init__(self, ex: ReverseExecutor, f: Future) -> None:
        self.ex, self.f = ex, f

    def result(self):  # noqa: ANN201
        self.ex.run_all()
        return self.f.result()


def test_batch_parts_are_the_local_batch() -> None:
    s = starts(23)
    local = wmr_py.run_batch(s, (0, 0, 0), t_end=3.0, sensor=NOISY)
    ex = ReverseExecutor()
    parted = wmr_py.run_batch(s, (0, 0, 0), t_end=3.0, sensor=NOISY, executor=ex, chunk_size=5)
    assert len(ex.submitted) == 5
    assert list(parted) == list(local)
    for k in local:
        assert same(parted[k], local[k]), k


def test_sweep_parts_are_the_local_sweep() -> None:
    local = wmr_py.sweep(VARY_SWEEP)
    ex = ReverseExecutor()
    parted = wmr_py.sweep(VARY_SWEEP, executor=ex, chunk_size=7)
    assert len(ex.submitted) == -(-len(local) // 7)
    assert list(parted) == list(local)
    for k in local:
        assert same(parted[k], local[k]), k
    assert parted.scenario_toml == local.scenario_toml


def test_process_pool() -> None:
    s = starts(16)
    local = wmr_py.run_batch(s, (0.2, 0, 1.0), t_end=3.0, sensor=NOISY)
    # Spawned, not forked: a worker forked from a parent whose thread pool has run would
    # wait on that pool's copied locks forever (the test hung in CI with fork).
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as ex:
        parted = wmr_py.run_batch(s, (0.2, 0, 1.0), t_end=3.0, sensor=NOISY, executor=ex)
        swept = wmr_py.sweep(VARY_SWEEP, executor=ex)
    assert all(same(parted[k], local[k]) for k in local)
    ref = wmr_py.sweep(VARY_SWEEP)
    assert all(same(swept[k], ref[k]) for k in ref)


def test_dask_local_cluster(tmp_path) -> None:  # noqa: ANN001
    distributed = pytest.importorskip("distributed")
    ref = wmr_py.sweep(VARY_SWEEP)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0", local_directory=str(tmp_path)
    ) as cluster, distributed.Client(cluster) as client:
        swept = wmr_py.sweep(VARY_SWEEP, executor=client)
        s = starts(10)
        batch = wmr_py.run_batch(s, (0, 0, 0), t_end=2.0, executor=client, chunk_size=3)
    assert all(same(swept[k], ref[k]) for k in ref)
    local = wmr_py.run_batch(s, (0, 0, 0), t_end=2.0)
    assert all(same(batch[k], local[k]) for k in local)


def test_bad_executor_and_chunk_size_are_named() -> None:
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.sweep(VARY_SWEEP, executor=object())
    assert e.value.key == "executor"
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.run_batch(starts(3), (0, 0, 0), t_end=1.0, executor=ReverseExecutor(), chunk_size=0)
    assert e.value.key == "chunk_size"
    bad = starts(8)
    bad[6, 1] = np.nan
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.run_batch(bad, (0, 0, 0), t_end=1.0, executor=ReverseExecutor(), chunk_size=2)
    assert e.value.key == "starts[6, 1]"


def test_progress_bar(capsys: pytest.CaptureFixture) -> None:
    pytest.importorskip("tqdm")
    res = wmr_py.run_batch(starts(12), (0, 0, 0), t_end=2.0, progress=True)
    err = capsys.readouterr().err
    assert "run_batch" in err and "12/12" in err
    wmr_py.sweep(VARY_SWEEP, progress=True, executor=ReverseExecutor(), chunk_size=16)
    assert "64/64" in capsys.readouterr().err
    wmr_py.run_scenario("[sim]\nt_end = 2.0\n[[run]]\ngoal = { x = 1.0 }\n", progress=True)
    assert "201/201" in capsys.readouterr().err
    assert len(res) == 12


def test_progress_is_reported_from_the_waiting_thread(monkeypatch: pytest.MonkeyPatch) -> None:
    """The runs only count; the bar is moved about every 50 ms, not once per run."""
    calls = []

    class Recorder:
        def __init__(self, desc: str, unit: str) -> None:
            pass

        def __call__(self, n: int) -> None:
            calls.append(n)

        def close(self) -> None:
            pass

    monkeypatch.setattr(wmr_py._results, "Bar", Recorder)
    t0 = time.perf_counter()
    wmr_py.run_batch(starts(400), (0, 0, 0), t_end=1.0, progress=True)
    elapsed = time.perf_counter() - t0
    assert calls[0] == -400 and calls[-1] == 400
    assert calls[1:] == sorted(calls[1:])
    assert len(calls) <= 2 + elapsed / 0.05 + 1, (len(calls), elapsed)


def test_progress_without_tqdm_warns_and_runs(monkeypatch: pytest.MonkeyPatch) -> None:
    import sys

    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    monkeypatch.setitem(sys.modules, "tqdm.std", None)
    with pytest.warns(UserWarning, match="tqdm"):
        res = wmr_py.run_batch(starts(3), (0, 0, 0), t_end=1.0, progress=True)
    assert len(res) == 3


WATCH_THREADS = """
import os, sys, threading, time
import numpy as np
import wmr_py
seen = []
stop = threading.Event()
def watch():
    while not stop.is_set():
        seen.append(len(os.listdir("/proc/self/task")))
        time.sleep(0.002)
before = len(os.listdir("/proc/self/task"))
t = threading.Thread(target=watch)
t.start()
base = {"sim": {"t_end": 3.0, "log_dt": 3.0}, "run": [{"goal": {"x": 0.0}}]}
starts = np.column_stack([np.linspace(-1, 1, 8), np.linspace(1, -1, 8), np.zeros(8)])
wmr_py._results.batch_task(base, starts, None, 0)
stop.set()
t.join()
print(before, max(seen))
"""


def test_worker_part_runs_on_one_thread() -> None:
    """A part runs its starts one after the other (threads=1) on the one worker thread of
    the Ctrl-C watch: no rayon pool per worker process (it would oversubscribe the cores
    that the executor's other workers use)."""
    import subprocess
    import sys

    if not os.path.isdir("/proc/self/task"):
        pytest.skip("needs /proc")
    out = subprocess.run([sys.executable, "-c", WATCH_THREADS], capture_output=True, text=True, check=True).stdout
    before, most = map(int, out.split())
    # The main thread (and numpy's, counted in `before`), the watcher, the run's worker.
    assert most <= before + 2, (before, most)


class JoblibExecutor:
    """The README's executor over joblib (there on joblib's Ray backend; here on its
    default, loky): submit() collects, the first result() runs every call."""

    def __init__(self, n_jobs: int = 2) -> None:
        self.calls: list = []
        self.results = None
        self.n_jobs = n_jobs

    def submit(self, fn, *args):  # noqa: ANN001, ANN201
        self.calls.append((fn, args))
        return _JoblibFuture(self, len(self.calls) - 1)


class _JoblibFuture:
    def __init__(self, ex: JoblibExecutor, i: int) -> None:
        self.ex, self.i = ex, i

    def result(self):  # noqa: ANN201
        import joblib

        if self.ex.results is None:
            self.ex.results = joblib.Parallel(n_jobs=self.ex.n_jobs)(joblib.delayed(fn)(*a) for fn, a in self.ex.calls)
        return self.ex.results[self.i]


def test_joblib_executor_of_the_readme() -> None:
    pytest.importorskip("joblib")
    ref = wmr_py.sweep(VARY_SWEEP)
    got = wmr_py.sweep(VARY_SWEEP, executor=JoblibExecutor())
    assert all(same(got[k], ref[k]) for k in ref)


def test_settled_sweep_parts_are_the_local_sweep() -> None:
    """[sim] stop_when_settled (runs end early) holds in the parts too."""
    text = (
        "[sim]\nt_end = 30.0\nstop_when_settled = true\n[sweep]\n"
        'controllers = [{ kind = "polar" }, { kind = "lyapunov" }]\nrandom = { n = 10, seed = 3, radius = 1.5 }\n'
    )
    local = wmr_py.sweep(text)
    assert np.min(local["t_final_s"]) < 30.0
    parted = wmr_py.sweep(text, executor=ReverseExecutor(), chunk_size=3)
    assert all(same(parted[k], local[k]) for k in local)


def test_regression_39_11_a_foreign_row_names_its_run() -> None:
    """A part whose rows are not the runs asked for is refused naming the row and the run
    (the message printed a literal ``{k}``)."""
    text, n = wmr_py._native._sweep_plan(VARY_SWEEP)
    rows = wmr_py._results.sweep_task(text, 0, n)
    rows[2] = rows[3]  # row 2 now holds run 3's outcome
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py._native._sweep_gather(text, rows)
    assert e.value.key == "rows[2]"
    assert "is not the outcome of run 2" in str(e.value), str(e.value)
    assert "{k}" not in str(e.value)
