"""run_scenario: the CLI's CSV of the same file, the three input forms, the summary."""

from __future__ import annotations

import csv
import json
import math
import os
import pathlib
import shutil
import subprocess

import numpy as np
import pytest

import wmr_py
from conftest import REPO

CSV_COLUMNS = ["run", "t", "x", "y", "theta", "v", "omega", "phi_r", "phi_l", "omega_r", "omega_l", "tau_r", "tau_l", "e_s", "e_theta", "dl"]
# The golden header (outputs unchanged); the package gives the same list from its one source.
assert list(wmr_py.CSV_COLUMNS) == CSV_COLUMNS, wmr_py.CSV_COLUMNS


def read_csv(path: pathlib.Path) -> dict[str, np.ndarray]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header = rows[0]
    assert header[: len(CSV_COLUMNS)] == CSV_COLUMNS, header
    data = np.array([[float(v) for v in row[: len(CSV_COLUMNS)]] for row in rows[1:]])
    return {name: data[:, j] for j, name in enumerate(CSV_COLUMNS)}


def build_cli() -> pathlib.Path:
    """The wmr-cli to compare with: `WMR_TEST_CLI` when set (the test command passes the
    binary its Rust tests just built, with the workspace's features), else wmr-cli built
    on its own (debug profile: Rust does not reorder floating point, so the numbers are
    those of a release build) and returned.

    Built alone, its dependency features differ from the wheel's (numpy turns on
    num-traits' `std`), and the results must not. wmr-core calls the `libm` crate itself
    for that reason; before it did, the two differed by up to ~2e-10 in Fig. 7. That
    second build of wmr-core and wmr-scenario takes minutes, so the test command runs it
    only under WMR_LONG_TESTS=1 (the firmware check compares a third build, no_std, too).
    """
    given = os.environ.get("WMR_TEST_CLI")
    if given:
        path = pathlib.Path(given)
        if not path.is_file():
            raise FileNotFoundError(f"WMR_TEST_CLI={given}: no such file")
        return path
    subprocess.run(["cargo", "build", "--quiet", "-p", "wmr-cli"], cwd=REPO, check=True, timeout=1800)
    meta = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--no-deps", "--offline"],
        cwd=REPO, check=True, capture_output=True, text=True,
    )
    exe = "wmr-cli.exe" if os.name == "nt" else "wmr-cli"
    return pathlib.Path(json.loads(meta.stdout)["target_directory"]) / "debug" / exe


@pytest.mark.skipif(shutil.which("cargo") is None, reason="cargo is not on PATH: cannot build wmr-cli to compare with")
def test_fig7_equals_cli_csv(fig7_path: pathlib.Path, tmp_path: pathlib.Path) -> None:
    out = tmp_path / "fig7.csv"
    subprocess.run([str(build_cli()), "run", str(fig7_path), "-o", str(out)], check=True, capture_output=True, timeout=300)
    cli = read_csv(out)
    (res,) = wmr_py.run_scenario(fig7_path)
    py = res.columns()
    assert list(py) == CSV_COLUMNS
    for name in CSV_COLUMNS:
        assert py[name].shape == cli[name].shape, name
        # Bit for bit: the CSV carries the shortest round-trip repr of every f64.
        np.testing.assert_array_equal(py[name], cli[name], err_msg=name)


def test_fig7_shape_and_summary(fig7_path: pathlib.Path) -> None:
    (res,) = wmr_py.run_scenario(str(fig7_path))
    assert len(res) == 6001 and res.t[0] == 0.0 and res.t[-1] == pytest.approx(60.0)
    for name in CSV_COLUMNS[1:]:
        col = res[name]
        assert isinstance(col, np.ndarray) and col.dtype == np.float64 and col.shape == (6001,)
        assert np.isfinite(col).all()
        # Built once in Rust and handed over: numpy does not own the buffer, the Rust
        # Vec behind it (the array's base, not another ndarray) does.
        assert col.flags["C_CONTIGUOUS"] and not col.flags["OWNDATA"]
        assert col.base is not None and not isinstance(col.base, np.ndarray)
    assert res.x is res.x  # the same array object every time: no copy per access
    # The paper's law: the position converges within ~40-50 s; a heading error remains.
    assert res.converged and not res.diverged and res.status == "converged"
    assert res.time_to_1cm_s is not None and 20.0 < res.time_to_1cm_s < 60.0
    assert res.final_dl_m == pytest.approx(math.hypot(1 - res.x[-1], 1 - res.y[-1]))
    # The goal heading of Fig. 7 is 120 deg: the error is wrap(theta_d - theta), in degrees.
    wrapped = math.remainder(math.radians(120.0) - res.theta[-1], math.tau)
    assert res.final_heading_error_deg == pytest.approx(math.degrees(wrapped))
    assert 1.0 < abs(res.final_heading_error_deg) < 20.0
    assert res.dl[-1] == pytest.approx(res.final_dl_m, abs=1e-3)


def test_path_text_dict_and_simulate_agree(fig7_path: pathlib.Path) -> None:
    text = fig7_path.read_text()
    a = wmr_py.run_scenario(fig7_path)[0]
    b = wmr_py.run_scenario(text)[0]
    c = wmr_py.run_scenario(
        {
            "sim": {"t_end": 60.0, "dt": 1e-3, "log_dt": 0.01},
            "run": [{"start": {"x": 0, "y": 0, "theta_deg": 0}, "goal": {"x": 1, "y": 1, "theta_deg": 120}}],
        }
    )[0]
    d = wmr_py.simulate((0, 0, 0), (1, 1, math.radians(120)))
    for other in (b, c, d):
        for name in CSV_COLUMNS[1:]:
            np.testing.assert_array_equal(a[name], other[name], err_msg=name)


def test_several_runs_keep_order() -> None:
    goals = [(1.0, 1.0, 0.5), (-1.0, 0.5, 2.0), (0.5, -1.0, -1.0)]
    sc = {"sim": {"t_end": 2.0}, "run": [{"label": f"g{i}", "goal": {"x": g[0], "y": g[1], "theta": g[2]}} for i, g in enumerate(goals)]}
    results = wmr_py.run_scenario(sc)
    assert [r.run for r in results] == [0, 1, 2] and [r.label for r in results] == ["g0", "g1", "g2"]
    for r, g in zip(results, goals):
        single = wmr_py.simulate((0, 0, 0), g, t_end=2.0)
        np.testing.assert_array_equal(r.x, single.x)
        assert (r.columns()["run"] == r.run).all()


def test_overrides_reach_the_model() -> None:
    base = wmr_py.simulate((0, 0, 0), (1, 1, 0), t_end=1.0)
    heavy = wmr_py.simulate((0, 0, 0), (1, 1, 0), t_end=1.0, robot={"mass": 10.0})
    assert not np.array_equal(heavy.x, base.x)
    robot = wmr_py.Robot(mass=10.0)
    again = wmr_py.simulate((0, 0, 0), (1, 1, 0), t_end=1.0, robot=robot)
    np.testing.assert_array_equal(heavy.x, again.x)
    dc = wmr_py.simulate((0, 0, 0), (1, 1, 0), t_end=1.0, drive={"kind": "dc_motor"})
    assert np.isfinite(dc.x).all() and not np.array_equal(dc.x, base.x)
    pos = wmr_py.simulate((0, 0, 0), (1, 1, 0), t_end=1.0, controller={"mode": "position"})
    assert not np.array_equal(pos.theta, base.theta)
