"""`wmr-cli excite --speed-max` (issue 44, last item): the profile as a ROS 2 MCAP of
/cmd_vel (geometry_msgs/msg/Twist, CDR) in a rosbag2 bag, read with `rosbags` (the bag's
metadata.yaml and the MCAP, its Jazzy and Humble typestores) and with `mcap` +
`mcap_ros2`'s decoder: every message equals the CSV's row to the bit, at the profile's time
(run k's row at start + base_k + t, each test `--pause` after the last message of the one
before), published every profile step."""

from __future__ import annotations

import csv
import pathlib
import subprocess

import pytest

from test_scenario import build_cli

REPO = pathlib.Path(__file__).resolve().parents[3]

pytest.importorskip("rosbags", reason="rosbags is not installed (scripts/python-test-requirements.txt)")
pytest.importorskip("mcap_ros2", reason="mcap-ros2-support is not installed")
from mcap.reader import make_reader  # noqa: E402
from mcap_ros2.decoder import DecoderFactory  # noqa: E402
from rosbags.rosbag2 import Reader  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402

START_NS = 1_765_000_000_123_456_789
PAUSE_S = 3
STEP_NS = 10_000_000


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    cli = build_cli()
    d = tmp_path_factory.mktemp("excite")
    (d / "bag").mkdir()
    robot = str(REPO / "examples" / "identify" / "robot.toml")
    common = [str(cli), "excite", "--robot", robot, "--speed-max", "0.3"]
    subprocess.run([*common, "-o", str(d / "twist.csv")], check=True, capture_output=True)
    subprocess.run(
        [*common, "-o", str(d / "bag" / "twist.mcap"), "--start-ns", str(START_NS), "--pause", str(PAUSE_S), "--rosbag2"],
        check=True,
        capture_output=True,
    )
    with open(d / "twist.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    # The expected log time of each row: run k starts PAUSE_S after the last row of run k - 1.
    expected = []
    base = START_NS
    for k in sorted({int(r["run"]) for r in rows}):
        run_rows = [r for r in rows if int(r["run"]) == k]
        for r in run_rows:
            expected.append((base + round(float(r["t"]) * 1e9), float(r["v_cmd"]), float(r["omega_cmd"])))
        base += round(float(run_rows[-1]["t"]) * 1e9) + PAUSE_S * 1_000_000_000
    return d / "bag", expected


def test_mcap_ros2_decodes_every_message_as_the_csvs_row(written):
    bag, expected = written
    got = []
    with open(bag / "twist.mcap", "rb") as f:
        reader = make_reader(f, decoder_factories=[DecoderFactory()])
        assert reader.get_header().profile == "ros2"
        for schema, channel, message, twist in reader.iter_decoded_messages():
            assert (channel.topic, channel.message_encoding) == ("/cmd_vel", "cdr")
            assert (schema.name, schema.encoding) == ("geometry_msgs/msg/Twist", "ros2msg")
            assert message.publish_time == message.log_time
            assert (twist.linear.y, twist.linear.z, twist.angular.x, twist.angular.y) == (0.0, 0.0, 0.0, 0.0)
            got.append((message.log_time, twist.linear.x, twist.angular.z))
    assert got == expected
    # Published every profile step within a test.
    steps = {b[0] - a[0] for a, b in zip(got, got[1:])}
    assert STEP_NS in steps and min(steps) == STEP_NS


@pytest.mark.parametrize("store", [Stores.ROS2_JAZZY, Stores.ROS2_HUMBLE])
def test_rosbags_plays_the_bag_as_the_csvs_rows(written, store):
    bag, expected = written
    typestore = get_typestore(store)
    got = []
    with Reader(bag) as reader:
        assert [(c.topic, c.msgtype) for c in reader.connections] == [("/cmd_vel", "geometry_msgs/msg/Twist")]
        assert reader.message_count == len(expected)
        assert reader.start_time == START_NS
        for c, t_ns, raw in reader.messages():
            twist = typestore.deserialize_cdr(raw, c.msgtype)
            got.append((t_ns, twist.linear.x, twist.angular.z))
    assert got == expected
