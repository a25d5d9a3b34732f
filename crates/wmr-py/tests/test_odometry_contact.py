"""A run on odometry and a run whose wheels slip: RunResult carries the CSV's odometry
(x_odom, y_odom, theta_odom) and contact (slip_r ... n_l) columns, by item and attribute,
bit for bit the CLI's CSV, and in the CSV's order in to_pandas and to_xarray."""

from __future__ import annotations

import csv
import pathlib
import pickle
import shutil
import subprocess

import numpy as np
import pytest

import wmr_py
from conftest import REPO

ODOMETRY = REPO / "crates" / "wmr-cli" / "tests" / "fixtures" / "odometry-3s.toml"

# 3 s of Fig. 7 on examples/slip.toml's robot (wheels that slip on asphalt).
SLIP = (REPO / "crates" / "wmr-cli" / "tests" / "fixtures" / "slip-3s.toml").read_text()


def read_csv(path: pathlib.Path) -> tuple[list[str], np.ndarray]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in row] for row in rows[1:]])


def test_the_native_lists_are_exported() -> None:
    assert wmr_py.ODOMETRY_COLUMNS == ("x_odom", "y_odom", "theta_odom")
    assert wmr_py.CONTACT_COLUMNS == ("slip_r", "slip_l", "v_lat", "fx_r", "fx_l", "fy_r", "fy_l", "n_r", "n_l")
    assert len(wmr_py.ODOMETRY_UNITS) == 3 and len(wmr_py.CONTACT_UNITS) == 9


@pytest.mark.skipif(shutil.which("cargo") is None, reason="cargo is not on PATH: cannot build wmr-cli to compare with")
@pytest.mark.parametrize("name", ["odometry", "slip"])
def test_odometry_and_contact_columns_equal_the_cli_csv(name: str, tmp_path: pathlib.Path) -> None:
    from test_scenario import build_cli

    if name == "odometry":
        scenario, group, other = ODOMETRY, wmr_py.ODOMETRY_COLUMNS, wmr_py.CONTACT_COLUMNS
    else:
        scenario = tmp_path / "slip.toml"
        scenario.write_text(SLIP)
        group, other = wmr_py.CONTACT_COLUMNS, wmr_py.ODOMETRY_COLUMNS
    out = tmp_path / f"{name}.csv"
    subprocess.run([str(build_cli()), "run", str(scenario), "-o", str(out)], check=True, capture_output=True, timeout=300)
    header, rows = read_csv(out)
    assert [c for c in header if c in group] == list(group), header
    (res,) = wmr_py.run_scenario(scenario)
    # Every CSV column, bit for bit (the CSV writes -0 as 0, which compares equal).
    for j, col in enumerate(header[1:], start=1):
        np.testing.assert_array_equal(res[col], rows[:, j], err_msg=f"{name}: {col}")
    for col in group:
        assert getattr(res, col) is res[col], col
        assert getattr(wmr_py.RunResult, col).__doc__, col
    # The other group is not there: KeyError and AttributeError that say which runs have it.
    with pytest.raises(KeyError, match="only a run"):
        res[other[0]]
    with pytest.raises(AttributeError, match="only a run"):
        getattr(res, other[0])
    # CSV order in the tables (which always have the measured pose; the CSV only with a [sensor]).
    pytest.importorskip("pandas")  # optional: what follows needs it
    pytest.importorskip("xarray")  # optional: what follows needs it
    df = res.to_pandas()
    assert [c for c in df.columns if c in header] == header
    assert list(df.columns)[-len(group):] == list(group)
    for col in group:
        np.testing.assert_array_equal(df[col].to_numpy(), res[col])
    ds = res.to_xarray()
    assert [v for v in ds.data_vars if v in header] == [c for c in header[2:]]
    units = dict(zip(group, wmr_py.ODOMETRY_UNITS if group == wmr_py.ODOMETRY_COLUMNS else wmr_py.CONTACT_UNITS))
    for col in group:
        assert ds[col].attrs["units"] == units[col]
    assert res.column_names == [c for c in df.columns if c not in ("run", "label")]
    # A pickled result keeps the group.
    back = pickle.loads(pickle.dumps(res))
    for col in group:
        np.testing.assert_array_equal(back[col], res[col], err_msg=col)
