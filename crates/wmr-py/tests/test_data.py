"""Results as data, pickling, version and tab completion (issue 14: wmr_py for notebooks
and clusters)."""

from __future__ import annotations

import math
import pickle
import re
import sys

import numpy as np
import pytest

import wmr_py
from conftest import REPO

VARY_SWEEP = """
[sim]
t_end = 6.0
[sensor]
position_noise = 0.002
seed = 4
[sweep]
goal = { x = 0.0, y = 0.0, theta_deg = 0.0 }
controllers = [{ kind = "paper" }, { kind = "polar" }]
random = { n = 4, seed = 9, radius = 1.5, min_radius = 0.2 }
trials = 2
vary = [
  { key = "sensor.latency", values = [0.0, 0.02] },
  { key = "world.slope_deg", values = [0.0, 3.0] },
  { key = "controller.model.wheel_radius", uniform = [0.095, 0.105] },
]
"""


def same(a: object, b: object) -> bool:
    """Equal bit for bit (NaN where NaN), for arrays and plain values."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        return a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
    return a == b


def test_version_is_the_workspace_version() -> None:
    # [workspace.package] version, which wmr-cli --version prints.
    workspace = (REPO / "Cargo.toml").read_text().split("[workspace.package]", 1)[1]
    assert wmr_py.__version__ == re.search(r'^version = "([^"]+)"', workspace, re.M).group(1)
    from importlib.metadata import version

    assert version("wmr-py") == wmr_py.__version__


def test_tab_completion_shows_the_api_only() -> None:
    names = dir(wmr_py)
    assert names == sorted([*wmr_py.__all__, "__version__"])
    assert "np" not in names and "math" not in names
    for name in wmr_py.__all__:
        assert getattr(wmr_py, name) is not None
    for cls in ("PaperController", "PaperBidirectionalController", "PolarController", "LyapunovController"):
        assert cls in wmr_py.__all__


def test_run_result_to_pandas_and_pickle() -> None:
    pd = pytest.importorskip("pandas")
    r = wmr_py.simulate((0, 0, 0), (1, 1, 2.0), t_end=3.0, label="a")
    df = r.to_pandas()
    assert isinstance(df, pd.DataFrame) and len(df) == len(r) == 301
    assert list(df.columns[:2]) == ["run", "label"] and set(df["label"]) == {"a"}
    for name, col in r.columns().items():
        assert np.array_equal(df[name].to_numpy(), col), name
    assert np.array_equal(df["theta_meas"].to_numpy(), r.theta_meas)
    back = pickle.loads(pickle.dumps(r))
    assert type(back) is wmr_py.RunResult
    for name in ("run", "label", "status", "converged", "diverged", "time_to_1cm_s", "final_dl_m", "abs_work_j", "summary"):
        assert getattr(back, name) == getattr(r, name), name
    for name, col in back.columns().items():
        assert same(col, r.columns()[name]), name
    assert same(back.theta_meas, r.theta_meas)
    assert "samples=301" in repr(r) and "label=" in repr(r)


def test_robot_and_controllers_pickle() -> None:
    robot = wmr_py.Robot(mass=4.0, viscous_friction=0.01)
    assert pickle.loads(pickle.dumps(robot)) == robot
    classes = {
        "paper": wmr_py.PaperController,
        "paper_bidirectional": wmr_py.PaperBidirectionalController,
        "polar": wmr_py.PolarController,
        "lyapunov": wmr_py.LyapunovController,
    }
    gains = {"paper": {"kp_s": 2.0}, "paper_bidirectional": {"ki_theta": 2.0}, "polar": {"k_rho": 0.7}, "lyapunov": {"h": 5.0}}
    for kind, cls in classes.items():
        c = cls((1.0, 0.5, 0.3), robot, **gains[kind])
        back = pickle.loads(pickle.dumps(c))
        assert type(back) is cls and back.kind == kind and back.goal == c.goal
        # The same gains, robot and goal: the same commands, tick after tick.
        for k in range(5):
            m = ((0.1 * k, 0.0, 0.0), (0.0, 0.0), (1.0, 0.5))
            assert back.update(*m) == c.update(*m), kind
        with pytest.raises(TypeError, match="reset"):
            pickle.dumps(c)
        c.reset()
        assert pickle.loads(pickle.dumps(c)).kind == kind


def test_run_batch_gives_its_starts_and_a_data_frame() -> None:
    starts = np.array([[0.5, 0.0, 0.0], [-0.4, 0.3, 1.0], [0.2, -0.6, -2.0]])
    res = wmr_py.run_batch(starts, (0, 0, 0), t_end=4.0, controller={"kind": "polar"})
    assert isinstance(res, wmr_py.BatchResult) and len(res) == 3
    # Issue 14: a scalar beside the arrays broke DataFrame(res); it is an attribute now.
    assert "arrival_radius" not in res and res.arrival_radius == 0.01
    assert all(np.shape(v) == (3,) for v in res.values())
    assert list(res["start"]) == [0, 1, 2]
    assert np.array_equal(np.column_stack([res["x0"], res["y0"], res["theta0"]]), starts)
    assert res.law == "polar" and "3 starts" in repr(res)
    pd = pytest.importorskip("pandas")
    df = res.to_pandas()
    assert len(df) == 3 and set(df["law"]) == {"polar"}
    assert list(df.columns[:6]) == ["law", "start", "x0", "y0", "theta0", "status"]
    assert np.array_equal(df["final_dl_m"].to_numpy(), res["final_dl_m"])
    assert pd.DataFrame(dict(res)).shape == (3, len(res.keys()))
    back = pickle.loads(pickle.dumps(res))
    assert type(back) is wmr_py.BatchResult and back.law == "polar"
    assert all(same(back[k], res[k]) for k in res)


def test_sweep_to_pandas_and_xarray() -> None:
    xr = pytest.importorskip("xarray")
    res = wmr_py.sweep(VARY_SWEEP)
    # laws x variants (latency 0.0, 0.02, slope 0.0, 3.0: one key at a time) x trials x starts.
    n = 2 * 4 * 2 * 4
    assert len(res) == n and res.laws == ["paper", "polar"] and res.trials == 2
    df = res.to_pandas()
    assert len(df) == n
    assert {"law", "start", "x0", "sensor.latency", "world.slope_deg", "controller.model.wheel_radius", "trial"} <= set(df.columns)
    ds = res.to_xarray()
    assert isinstance(ds, xr.Dataset)
    assert ds["final_dl_m"].dims == ("law", "sensor.latency", "world.slope_deg", "trial", "start")
    assert list(ds["sensor.latency"].values) == [0.0, 0.02] and list(ds["world.slope_deg"].values) == [0.0, 3.0]
    assert ds.attrs["seed"] == 0 and ds.attrs["starts_seed"] == 9 and ds.attrs["wmr_version"] == wmr_py.__version__
    # Each run sits in its cell: latency, slope, trial and start of the row.
    law, lat, slope, trial, start = (np.asarray(df[c]) for c in ("law", "sensor.latency", "world.slope_deg", "trial", "start"))
    for i in range(n):
        # Two variants reach (latency 0, slope 0); the cell keeps the first run.
        if lat[i] == 0.0 and slope[i] == 0.0 and i % 32 >= 16:
            continue
        cell = ds.sel({"law": law[i], "sensor.latency": lat[i], "world.slope_deg": slope[i], "trial": trial[i], "start": start[i]})
        assert cell["final_dl_m"].item() == res["final_dl_m"][i], i
        assert cell["controller.model.wheel_radius"].item() == res["controller.model.wheel_radius"][i]
    # Cells no run reaches (latency and slope both off nominal) are NaN.
    assert math.isnan(ds["final_dl_m"].sel({"law": "paper", "sensor.latency": 0.02, "world.slope_deg": 3.0}).values[0, 0])
    # The resolved scenario in the attributes runs the same sweep.
    again = wmr_py.sweep(ds.attrs["scenario"])
    assert all(same(np.asarray(again[k]), np.asarray(res[k])) for k in res if k != "law")
    back = pickle.loads(pickle.dumps(res))
    assert back.scenario_toml == res.scenario_toml and all(same(back[k], res[k]) for k in res if k != "law")
    assert "SweepResult" in repr(res) and "sensor.latency" in repr(res)


def test_plain_sweep_has_law_by_start() -> None:
    pytest.importorskip("xarray")
    res = wmr_py.sweep("[sim]\nt_end = 3.0\n[sweep]\ncontrollers = [{ kind = \"paper\" }, { kind = \"lyapunov\" }]\n"
                       "grid = { x_min = -1.0, x_max = 1.0, nx = 3, y_min = -1.0, y_max = 1.0, ny = 2 }\n")
    ds = res.to_xarray()
    assert ds["converged"].dims == ("law", "start") and ds["converged"].dtype == bool
    assert ds.sizes == {"law": 2, "start": 6}
    assert np.array_equal(ds["final_x_m"].values.ravel(), res["final_x_m"])
    assert np.array_equal(ds["x0"].values, res["x0"][:6])


@pytest.mark.parametrize("package", ["pandas", "xarray"])
def test_missing_optional_package_is_named(monkeypatch: pytest.MonkeyPatch, package: str) -> None:
    res = wmr_py.sweep("[sim]\nt_end = 1.0\n[sweep]\nrandom = { n = 2, radius = 1.0 }\n")
    monkeypatch.setitem(sys.modules, package, None)
    with pytest.raises(ImportError, match=re.escape(f"needs {package}")):
        res.to_xarray() if package == "xarray" else res.to_pandas()
