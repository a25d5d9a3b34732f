"""Issue 39 (a fourth attack on wmr): the Python items. Item 7: a call whose allocation
the caller sizes (N times, N robots, N starts) and that this process cannot hold raises
MemoryError naming the argument, as numpy does, instead of aborting the interpreter.
Item 11: one controller updated from many threads; an executor part that returns
nothing. Item 8: an executor sweep with a preset or a file reference runs on workers in
another folder, from the shipped text alone."""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys
import textwrap
import threading

import numpy as np
import pytest

import wmr_py
from conftest import REPO

# --- item 7: MemoryError, not an abort, under the process's own memory limit ----------

# Each call under a 2.5 GB cap (set in the child after the imports, by RLIMIT_AS or
# RLIMIT_DATA), with the figures of the reproducers. The inputs are zero-stride
# views of one row (np.broadcast_to), except the states of step and derivative, so that
# only the memory the call would take is large.
CAPPED = textwrap.dedent(
    """
    import resource, sys
    import numpy as np
    import wmr_py
    which, limit = sys.argv[1], sys.argv[2]
    def rows(n, row):
        return np.broadcast_to(np.asarray(row, dtype=float), (n, len(row)))
    reference = wmr_py.Reference("circle")
    robot = wmr_py.Robot()
    kanayama = wmr_py.KanayamaController(reference)
    calls = {
        "state_at": (lambda: reference.state_at(np.broadcast_to(0.0, (60_000_000,))), "t_s"),
        "step": (lambda: robot.step(states, torques, 1e-3), "state"),
        "derivative": (lambda: robot.derivative(states, torques), "state"),
        "update": (lambda: kanayama.update(rows(30_000_000, [0, 0, 0]), rows(30_000_000, [0, 0]),
                                           rows(30_000_000, [0, 0])), "pose"),
        "run_batch": (lambda: wmr_py.run_batch(rows(12_000_000, [0.5, 0.5, 0.0]), (0, 0, 0), t_end=1.0), "starts"),
    }
    if which in ("step", "derivative"):
        # Real arrays (1.4 GB): the (N, 7) result of the same size no longer fits.
        states, torques = np.zeros((20_000_000, 7)), np.zeros((20_000_000, 2))
    call, key = calls[which]
    cap = 2_500_000_000
    resource.setrlimit(resource.RLIMIT_AS if limit == "as" else resource.RLIMIT_DATA, (cap, cap))
    # A small call still runs under the cap (no refusal for what fits).
    assert reference.state_at(np.linspace(0, 1, 1000)).shape == (1000, 7)
    try:
        call()
    except MemoryError as e:
        assert e.key == key and str(e).startswith(key + ": "), (e.key, str(e))
        print("MemoryError:", e)
        sys.exit(0)
    print("no MemoryError")
    sys.exit(3)
    """
)


@pytest.mark.parametrize("which", ["state_at", "step", "derivative", "update", "run_batch"])
@pytest.mark.parametrize("limit", ["as", "data"])
def test_regression_39_7_memory_error_not_an_abort(which: str, limit: str) -> None:
    """Issue 39 item 7: on the old code the child aborted (SIGABRT: Rust's failed
    allocation) or, for run_batch, passed a check against MemAvailable only."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    p = subprocess.run(
        [sys.executable, "-c", CAPPED, which, limit], capture_output=True, text=True, timeout=600, env=env
    )
    assert p.returncode == 0, f"exit {p.returncode}\n{p.stdout}\n{p.stderr[-2000:]}"
    limit_name = "RLIMIT_AS" if limit == "as" else "RLIMIT_DATA"
    assert "GB of memory but this process may take only" in p.stdout and limit_name in p.stdout, p.stdout


# --- item 11: threads, and an executor part that returns nothing ----------------------


def test_regression_39_11_one_controller_from_8_threads() -> None:
    """Issue 39 item 11: 8 threads updating one controller raised ``RuntimeError: Already
    borrowed`` on most calls. Now every call is one tick, whatever thread makes it."""
    c = wmr_py.PaperController((1.0, 1.0, 0.5))
    barrier = threading.Barrier(8)
    failures: list = []
    old = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)

    def work() -> None:
        barrier.wait()
        for k in range(2000):
            try:
                c.update((0.01 * (k % 7), 0.0, 0.1), (0.0, 0.0), (0.0, 0.0))
                c.errors  # noqa: B018 - a read while others write
            except Exception as e:  # noqa: BLE001 - any exception is the finding
                failures.append(repr(e))

    try:
        threads = [threading.Thread(target=work) for _ in range(8)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    finally:
        sys.setswitchinterval(old)
    assert not failures, f"{len(failures)} of 16000 calls failed, e.g. {failures[:3]}"
    assert "ticks=16000" in repr(c), repr(c)


class _Returns:
    """An executor whose every future returns `value` (a broken or foreign worker)."""

    def __init__(self, value: object) -> None:
        self.value = value

    def submit(self, fn, *args):  # noqa: ANN001, ANN201
        value = self.value

        class _F:
            def result(self):  # noqa: ANN202
                return value

        return _F()


SMALL_SWEEP = "[sim]\nt_end = 0.5\n[sweep]\nrandom = { n = 4, radius = 1.0 }\n"


@pytest.mark.parametrize("value", [None, "rows", np.zeros((3, 2)), np.zeros((1, wmr_py._native._SWEEP_ROW_LEN))])
def test_regression_39_11_a_sweep_part_that_is_no_rows_names_the_part(value: object) -> None:
    """Issue 39 item 11: a part returning None raised numpy's ValueError without `.key`."""
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.sweep(SMALL_SWEEP, executor=_Returns(value), chunk_size=2)
    assert e.value.key == "executor", e.value
    assert str(e.value).startswith("executor: part 0 (runs 0:2) returned"), str(e.value)


# --- item 8: an executor sweep with a preset and a file reference, in another folder ----

SWEEP_WITH_FILES = """\
[robot]
from = "robots/mine.toml"
[sim]
t_end = 1.0
[sweep]
controllers = [{ kind = "kanayama" }, { kind = "pure_pursuit" }]
references = [{ kind = "file", path = "ref.csv" }, { kind = "circle" }]
random = { n = 3, seed = 2, radius = 0.1, max_heading_deg = 10.0 }
"""


def _scenario_folder(root: pathlib.Path) -> pathlib.Path:
    d = root / "scenario"
    (d / "robots").mkdir(parents=True)
    (d / "robots" / "mine.toml").write_text("[robot]\nmass = 7.5\nwheel_radius = 0.08\n")
    (d / "ref.csv").write_text("t,x,y\n0,0.0,0.0\n1,0.5,0.0\n2,1.0,0.25\n3,1.5,0.75\n")
    (d / "s.toml").write_text(SWEEP_WITH_FILES)
    return d


def _chdir(path: str) -> None:
    os.chdir(path)


def test_regression_39_8_executor_sweep_with_a_preset_and_a_file_runs_in_another_folder(
    tmp_path: pathlib.Path,
) -> None:
    """Issue 39 item 8: the workers (in a folder without the scenario's files) parsed the
    scenario's raw text: `robot.from` and `reference.path` were not found there."""
    from concurrent.futures import ProcessPoolExecutor
    import multiprocessing

    d = _scenario_folder(tmp_path)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    local = wmr_py.sweep(d / "s.toml")
    ctx = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(1, mp_context=ctx, initializer=_chdir, initargs=(str(elsewhere),)) as ex:
        parted = wmr_py.sweep(d / "s.toml", executor=ex, chunk_size=5)
    for k in ("final_dl_m", "rms_error_m", "x0", "converged"):
        np.testing.assert_array_equal(parted[k], local[k])
    assert list(parted["reference"]) == list(local["reference"])


def test_regression_39_8_resolved_scenario_runs_again_without_its_files(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Issue 39 item 8: `scenario_toml` (and to_xarray().attrs["scenario"]) kept the
    preset's `from` and the file's relative path; copied elsewhere, it did not run."""
    d = _scenario_folder(tmp_path)
    local = wmr_py.sweep(d / "s.toml")
    text = local.scenario_toml
    assert "from =" not in text and "points = [[0.0, 0.0], [0.5, 0.0]" in text, text
    # Only the text, in another folder, the scenario's files gone.
    import shutil

    shutil.rmtree(d)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    again = wmr_py.sweep(text)
    for k in ("final_dl_m", "rms_error_m", "x0"):
        np.testing.assert_array_equal(again[k], local[k])
    assert list(again["reference"]) == list(local["reference"])
    assert sorted(local["reference"]) == ["circle"] * 6 + ["file"] * 6


# --- item 14: the files a scenario names stay in its folder ------------------------------


def test_regression_39_14_file_references_stay_in_the_scenario_folder(
    tmp_path: pathlib.Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Issue 39 item 14: `[robot] from` and `[reference] path` could name any file on the
    machine (`..`, absolute paths, links). Now they are read from the scenario's folder
    (for text and dicts: the current folder) and below, unless ``allow_files_under``
    allows another; the error is a ScenarioError naming the key, the file and the keyword."""
    d = _scenario_folder(tmp_path)
    shared = tmp_path / "shared"
    shared.mkdir()
    (d / "robots" / "mine.toml").rename(shared / "mine.toml")
    (d / "s.toml").write_text(SWEEP_WITH_FILES.replace("robots/mine.toml", "../shared/mine.toml"))
    with pytest.raises(wmr_py.ScenarioError) as e:
        wmr_py.sweep(d / "s.toml")
    assert e.value.key == "robot.from", str(e.value)
    for word in ("../shared/mine.toml", "outside the scenario's folder", "allow_files_under"):
        assert word in str(e.value), str(e.value)
    # Allowed: the folder the error names, as a list or a single path.
    allowed = wmr_py.sweep(d / "s.toml", allow_files_under=[shared])
    again = wmr_py.sweep(d / "s.toml", allow_files_under=str(shared))
    np.testing.assert_array_equal(allowed["final_dl_m"], again["final_dl_m"])
    # A link inside the folder that leads outside is outside; text is judged from the
    # current folder, and every function that reads a scenario takes the keyword.
    outside_csv = tmp_path / "secret.csv"
    outside_csv.write_text((d / "ref.csv").read_text())
    (d / "ref.csv").unlink()
    (d / "ref.csv").symlink_to(outside_csv)
    monkeypatch.chdir(d)
    track = '[reference]\nkind = "file"\npath = "ref.csv"\n[controller]\nkind = "kanayama"\n[sim]\nt_end = 0.2\n[[run]]\n'
    calls = [
        lambda **k: wmr_py.run_scenario(track, **k),
        lambda **k: wmr_py.simulate((0, 0, 0), reference={"kind": "file", "path": "ref.csv"},
                                    controller={"kind": "kanayama"}, t_end=0.2, **k),
        lambda **k: wmr_py.run_batch(np.zeros((2, 3)), reference={"kind": "file", "path": str(outside_csv)},
                                     controller={"kind": "kanayama"}, t_end=0.2, **k),
    ]
    for call in calls:
        with pytest.raises(wmr_py.ScenarioError) as e:
            call()
        assert e.value.key == "reference.path" and "allow_files_under" in str(e.value), str(e.value)
        call(allow_files_under=[tmp_path])
    # A folder to allow that does not exist is named.
    with pytest.raises(wmr_py.ScenarioError) as e:
        wmr_py.run_scenario(track, allow_files_under=[tmp_path / "missing"])
    assert e.value.key == "allow_files_under", str(e.value)
    # A Reference reads the path its caller gives, as open() does.
    ref = wmr_py.Reference("file", path=str(outside_csv))
    wmr_py.simulate((0, 0, 0), reference=ref, controller={"kind": "kanayama"}, t_end=0.2)
