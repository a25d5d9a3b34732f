"""`wmr-cli urdf` and the MCAP's `/robot_description` (issue 43 item 2): the URDF parsed
with `yourdfpy`, its masses, inertias and joints checked against the scenario's robot as
`wmr-cli check` resolves it (TOML read with tomllib)."""

from __future__ import annotations

import pathlib
import subprocess
import tomllib

import numpy as np
import pytest

from test_scenario import build_cli

REPO = pathlib.Path(__file__).resolve().parents[3]

yourdfpy = pytest.importorskip("yourdfpy", reason="yourdfpy is not installed (scripts/python-test-requirements.txt)")
pytest.importorskip("mcap_ros2", reason="mcap-ros2-support is not installed")
from mcap.reader import make_reader  # noqa: E402
from mcap_ros2.decoder import DecoderFactory  # noqa: E402

SCENARIOS = ["examples/paper/fig7.toml", "examples/turtlebot3.toml"]


@pytest.fixture(scope="module")
def cli() -> pathlib.Path:
    return build_cli()


def robot_of(cli: pathlib.Path, scenario: pathlib.Path) -> dict:
    text = subprocess.run([str(cli), "check", str(scenario)], check=True, capture_output=True, text=True).stdout
    return tomllib.loads("\n".join(line for line in text.splitlines() if not line.startswith("# ")))["robot"]


@pytest.mark.parametrize("scenario", SCENARIOS)
def test_the_urdf_has_the_scenarios_masses_inertias_and_joints(cli, tmp_path, scenario):
    path = tmp_path / "robot.urdf"
    subprocess.run([str(cli), "urdf", str(REPO / scenario), "-o", str(path)], check=True, capture_output=True)
    robot = robot_of(cli, REPO / scenario)
    urdf = yourdfpy.URDF.load(str(path), load_meshes=False, build_scene_graph=True)
    links = urdf.link_map
    assert set(links) == {"base_link", "wheel_left_link", "wheel_right_link", "caster_link"}
    total = sum(l.inertial.mass for l in links.values() if l.inertial is not None)
    assert total == robot["mass"]
    base = links["base_link"].inertial
    assert base.mass == robot["mass"]
    # G is com_offset ahead of C (base_link's origin).
    assert base.origin[0, 3] == robot["com_offset"] and base.origin[1, 3] == 0.0
    assert base.inertia[2, 2] == robot["platform_inertia"]
    for name in ("wheel_left_link", "wheel_right_link"):
        wheel = links[name].inertial
        assert wheel.inertia[1, 1] == robot["wheel_inertia"]
        assert np.all(np.linalg.eigvalsh(wheel.inertia) >= 0)
    joints = urdf.joint_map
    for name, side in (("wheel_left_joint", 1.0), ("wheel_right_joint", -1.0)):
        j = joints[name]
        assert j.type == "continuous" and j.parent == "base_link"
        assert list(j.axis) == [0.0, 1.0, 0.0]
        assert j.origin[1, 3] == side * robot["half_track"] and j.origin[2, 3] == robot["wheel_radius"]
    assert joints["caster_joint"].type == "fixed"
    # The caster lies beyond G, on its side of the axle: G is inside the support.
    caster_x = joints["caster_joint"].origin[0, 3]
    assert caster_x * robot["com_offset"] >= 0 and abs(caster_x) >= abs(robot["com_offset"])


def test_stdout_when_no_output_is_given_and_a_bad_file_is_one_line(cli, tmp_path):
    out = subprocess.run([str(cli), "urdf", str(REPO / SCENARIOS[0])], check=True, capture_output=True, text=True)
    assert out.stdout.startswith("<?xml") and "<robot name=\"fig7\">" in out.stdout
    bad = tmp_path / "bad.toml"
    bad.write_text("[robot]\nmass = -1.0\n")
    r = subprocess.run([str(cli), "urdf", str(bad)], capture_output=True, text=True)
    assert r.returncode == 2 and "mass" in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_every_ros2_mcap_carries_the_urdf_as_topic_and_attachment(cli, tmp_path):
    scenario = REPO / "crates" / "wmr-cli" / "tests" / "fixtures" / "two-runs-every-topic.toml"
    urdf = subprocess.run([str(cli), "urdf", str(scenario)], check=True, capture_output=True, text=True).stdout
    for profile in ("ros2", "both"):
        path = tmp_path / f"{profile}.mcap"
        subprocess.run([str(cli), "run", str(scenario), "-o", str(path), "--profile", profile], check=True,
                       capture_output=True)
        with open(path, "rb") as f:
            reader = make_reader(f, decoder_factories=[DecoderFactory()])
            attachments = list(reader.iter_attachments())
            assert [(a.name, a.media_type) for a in attachments] == [("robot.urdf", "application/xml")]
            assert attachments[0].data.decode() == urdf
            descriptions = {
                ch.topic: msg.data
                for _, ch, _, msg in reader.iter_decoded_messages(topics=["/run0/robot_description", "/run1/robot_description"])
            }
            summary = reader.get_summary()
        assert set(descriptions) == {"/run0/robot_description", "/run1/robot_description"}
        # Each run's URDF names its links as its tf frames are named: run1/base_link, ...
        assert descriptions["/run1/robot_description"] == urdf.replace('"base_link', '"run1/base_link').replace(
            '"wheel_', '"run1/wheel_').replace('"caster_', '"run1/caster_')
        ch = next(c for c in summary.channels.values() if c.topic == "/run0/robot_description")
        assert "durability: 1" in ch.metadata["offered_qos_profiles"]
    # The Foxglove profile is unchanged: no attachment.
    path = tmp_path / "fox.mcap"
    subprocess.run([str(cli), "run", str(scenario), "-o", str(path)], check=True, capture_output=True)
    with open(path, "rb") as f:
        assert list(make_reader(f).iter_attachments()) == []


@pytest.mark.parametrize("scenario", SCENARIOS)
def test_python_gives_the_urdf_the_cli_writes(cli, scenario):
    """`wmr_py.Robot.urdf()`: the very text of `wmr-cli urdf` for the same robot and name."""
    import wmr_py

    robot = robot_of(cli, REPO / scenario)
    keys = wmr_py.Robot().to_dict().keys()
    text = subprocess.run([str(cli), "urdf", str(REPO / scenario)], check=True, capture_output=True, text=True).stdout
    # The scenario's name, which the CLI names the robot after.
    name = tomllib.loads((REPO / scenario).read_text())["name"]
    assert f'<robot name="{name}">' in text
    assert wmr_py.Robot(**{k: robot[k] for k in keys}).urdf(name=name) == text
    # Escaped where XML needs it, and named "wmr" by default.
    assert '<robot name="a&lt;b&amp;&quot;c">' in wmr_py.Robot().urdf(name='a<b&"c')
    assert '<robot name="wmr">' in wmr_py.Robot().urdf()
