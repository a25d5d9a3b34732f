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
