"""Rerun reads `wmr-cli run --profile ros2` (issue 43 item 4): `rerun mcap convert` maps the
file by meaning, with no blueprint: /tf to transforms, /goal_pose to poses, /joint_states to
scalars, /robot_description to the robot's drawn links. Counted per entity here."""

from __future__ import annotations

import os
import pathlib
import shutil
import subprocess
import sys
from collections import defaultdict

import pytest

from test_scenario import build_cli

REPO = pathlib.Path(__file__).resolve().parents[3]
FIXTURES = REPO / "crates" / "wmr-cli" / "tests" / "fixtures"

pytest.importorskip("rerun", reason="rerun-sdk is not installed (scripts/python-test-requirements.txt)")
from rerun.chunk import RrdReader  # noqa: E402


def rerun_cli() -> str:
    here = pathlib.Path(sys.executable).parent / "rerun"
    found = str(here) if here.exists() else shutil.which("rerun")
    if found is None:
        pytest.skip("the rerun command of rerun-sdk is not on PATH")
    return found


def test_rerun_maps_transforms_poses_scalars_and_the_robot(tmp_path):
    cli = build_cli()
    scenario = FIXTURES / "two-runs-every-topic.toml"
    mcap, rrd = tmp_path / "r.mcap", tmp_path / "r.rrd"
    subprocess.run([str(cli), "run", str(scenario), "-o", str(mcap), "--profile", "ros2"], check=True,
                   capture_output=True)
    env = {**os.environ, "TELEMETRY_ENABLED": "false"}
    subprocess.run([rerun_cli(), "mcap", "convert", str(mcap), "-o", str(rrd)], check=True, capture_output=True,
                   env=env, timeout=300)
    rows: dict[str, int] = defaultdict(int)
    components: dict[str, set] = defaultdict(set)
    for chunk in RrdReader(rrd).stream():
        for field in chunk.to_record_batch().schema:
            name = (field.metadata or {}).get(b"rerun:component", b"").decode()
            if name:
                components[chunk.entity_path].add(name.split(":")[0])
                if name in ("Transform3D:translation", "InstancePoses3D:translations", "Scalars:scalars"):
                    rows[chunk.entity_path] += chunk.num_rows
    samples = 201  # 2 s logged every 10 ms
    for run in ("run0", "run1"):
        # Four transforms a sample (map -> odom -> base_link, two wheels).
        assert "Transform3D" in components[f"/{run}/tf"] and rows[f"/{run}/tf"] == 4 * samples
        assert "Transform3D" in components[f"/{run}/tf_static"]
        assert "InstancePoses3D" in components[f"/{run}/goal_pose"] and rows[f"/{run}/goal_pose"] == 1
        for series in ("position", "velocity", "effort"):
            path = f"/{run}/joint_states/{series}"
            assert "Scalars" in components[path] and rows[path] == samples, path
        links = [e for e in components if e.startswith("/two-runs-every-topic/visual_geometries/" + run)]
        assert len(links) == 4, links  # base_link, two wheels, caster


def _read_rrd(path: pathlib.Path) -> tuple[dict, dict]:
    """Per entity: its components, and per component its values flattened (row order)."""
    components: dict[str, set] = defaultdict(set)
    values: dict[tuple[str, str], list] = defaultdict(list)
    for chunk in RrdReader(path).stream():
        batch = chunk.to_record_batch()
        for i, field in enumerate(batch.schema):
            name = (field.metadata or {}).get(b"rerun:component", b"").decode()
            if name:
                components[chunk.entity_path].add(name)
                for row in batch.column(i).to_pylist():
                    values[(chunk.entity_path, name)].extend(row or [])
    return components, values


def test_log_rerun_gives_the_path_the_pose_and_every_column_as_a_plot(tmp_path):
    """RunResult.log_rerun(): what `rerun mcap convert` does not show, read back from the
    recording: the path and the reference as line strips (their points the columns'), the
    pose at every sample, every other column as Scalars equal to the column to the bit."""
    import rerun as rr

    import wmr_py

    r = wmr_py.run_scenario(FIXTURES / "two-runs-every-topic.toml")[1]
    assert r.tracking
    rec = rr.RecordingStream("wmr-test")
    rrd = tmp_path / "run.rrd"
    rec.save(str(rrd))
    r.log_rerun(rec)
    rec.flush()
    rec.disconnect()
    components, values = _read_rrd(rrd)
    n = len(r)

    def f32(*columns):  # Rerun keeps positions as float32
        return [[float(np.float32(v)) for v in p] for p in zip(*columns)]

    import numpy as np

    strip = values[("/wmr/run1/path", "LineStrips3D:strips")]
    assert len(strip) == 1 and [p[:2] for p in strip[0]] == f32(r.x, r.y)
    ref = values[("/wmr/run1/reference", "LineStrips3D:strips")]
    assert [p[:2] for p in ref[0]] == f32(r["x_ref"], r["y_ref"])
    translations = values[("/wmr/run1/base_link", "Transform3D:translation")]
    assert [p[:2] for p in translations] == f32(r.x, r.y) and len(translations) == n
    for name in ("dl", "e_theta", "omega_r", "tau_l", "x_ref", "v_cmd"):
        got = values[(f"/wmr/run1/columns/{name}", "Scalars:scalars")]
        assert got == list(r[name]), name
    assert not any(e.startswith("/wmr/run1/columns/") and e.endswith(("/x", "/y", "/theta", "/t")) for e in components)


def test_log_rerun_without_rerun_names_the_package(monkeypatch):
    import sys

    import wmr_py

    r = wmr_py.simulate(start=(0, 0, 0), goal={"x": 0.2, "y": 0.0, "theta_deg": 0}, t_end=0.1)
    monkeypatch.setitem(sys.modules, "rerun", None)
    with pytest.raises(ImportError, match="rerun"):
        r.log_rerun()
