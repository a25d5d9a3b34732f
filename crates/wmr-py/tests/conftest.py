"""Shared fixtures: the repository root and the Fig. 7 scenario file."""

from __future__ import annotations

import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]

# The paper's Figs. 7-9: start (0, 0, 0), goal (1, 1, 120 deg), defaults elsewhere.
FIG7_FALLBACK = """\
name = "fig7"
[sim]
t_end = 60.0
dt = 1e-3
log_dt = 0.01
[[run]]
label = "to (1, 1, 120 deg)"
start = { x = 0.0, y = 0.0, theta_deg = 0.0 }
goal = { x = 1.0, y = 1.0, theta_deg = 120.0 }
"""


@pytest.fixture(scope="session")
def fig7_path(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    """examples/paper/fig7.toml, or the same scenario written to a temp file."""
    path = REPO / "examples" / "paper" / "fig7.toml"
    if path.is_file():
        return path
    tmp = tmp_path_factory.mktemp("fig7") / "fig7.toml"
    tmp.write_text(FIG7_FALLBACK)
    return tmp
