"""Shared fixtures: the repository root and the Fig. 7 scenario file; skips counted.

Every skipped test is appended to ``WMR_SKIP_LOG`` (scripts/test counts them with the
Rust tests' skips), and a test skipped for a package it could not import fails the run
when ``WMR_REQUIRE`` lists ``python-packages`` (scripts/test installs them all): a skip
never passes silently where the test command provides what the test needs.
"""

from __future__ import annotations

import os
import pathlib

import pytest

#: (test id, reason) of every skipped test of the session.
_SKIPS: list = []


def _skip_reason(report: pytest.TestReport) -> str:
    longrepr = report.longrepr
    # (path, line, reason); a list when the report came from a pytest-xdist worker.
    return str(longrepr[2]) if isinstance(longrepr, (tuple, list)) and len(longrepr) == 3 else str(longrepr)


def pytest_runtest_logreport(report: pytest.TestReport) -> None:
    if report.skipped:
        _SKIPS.append((report.nodeid, _skip_reason(report)))


def _missing_package(reason: str) -> bool:
    """True for pytest.importorskip's reason: "could not import 'pandas': ..."."""
    return "could not import" in reason


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    # Under pytest-xdist (`pytest -n 2`) the controller sees every worker's reports: it
    # alone counts the skips, once.
    if os.environ.get("PYTEST_XDIST_WORKER"):
        return
    log = os.environ.get("WMR_SKIP_LOG")
    if log and _SKIPS:
        with open(log, "a", encoding="utf-8") as f:
            for nodeid, reason in _SKIPS:
                f.write(f"SKIP python {nodeid}: {reason}\n")
    required = "python-packages" in os.environ.get("WMR_REQUIRE", "").split(",")
    missing = [(n, r) for n, r in _SKIPS if _missing_package(r)]
    if required and missing:
        for nodeid, reason in missing:
            print(f"\nFAILED (WMR_REQUIRE=python-packages) {nodeid}: skipped: {reason}")
        session.exitstatus = pytest.ExitCode.TESTS_FAILED

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
