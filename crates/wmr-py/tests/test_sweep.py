"""wmr_py.sweep: the laws compared from a notebook, same numbers as single runs."""

from __future__ import annotations

import numpy as np
import pytest

import wmr_py

SWEEP = """
[sim]
t_end = 15.0
[sweep]
controllers = [{ kind = "paper" }, { kind = "lyapunov" }]
random = { n = 6, seed = 11, radius = 1.5, min_radius = 0.2 }
"""


def test_sweep_rows_match_single_runs() -> None:
    out = wmr_py.sweep(SWEEP)
    assert out["law"] == ["paper"] * 6 + ["lyapunov"] * 6
    assert list(out["start"]) == list(range(6)) * 2
    assert "lyapunov" in out["table"] and "paper" in out["table"]
    # Each row equals a direct simulate() of the same start with the same law.
    for i in (0, 7):
        kind = out["law"][i]
        r = wmr_py.simulate(
            (out["x0"][i], out["y0"][i], out["theta0"][i]), (0, 0, 0), controller={"kind": kind}, t_end=15.0
        )
        assert r.final_dl_m == out["final_dl_m"][i]
        assert r.final_heading_error_deg == out["final_heading_error_deg"][i]
        assert r.converged == bool(out["converged"][i])
    # The exact-heading law ends with no heading error wherever it converged.
    lyap = np.array(out["law"]) == "lyapunov"
    ok = lyap & out["converged"]
    assert ok.any()
    assert np.all(np.abs(out["final_heading_error_deg"][ok]) < 1.0)


def test_sweep_without_sweep_table_names_the_key() -> None:
    with pytest.raises(wmr_py.ScenarioError) as e:
        wmr_py.sweep("[[run]]\ngoal = { x = 1.0 }\n")
    assert e.value.key == "sweep"
