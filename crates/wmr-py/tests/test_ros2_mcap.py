"""`wmr-cli run --profile ros2` (issue 43 item 1): every message of the MCAP read with
`rosbags` (its ROS 2 Jazzy and Humble typestores) and with `mcap-ros2-support`, fields
checked against the CSV of the same run to the bit, schemas against the ROS 2 definitions
the typestores carry (rosbags' own copy of common_interfaces and geometry2)."""

from __future__ import annotations

import csv
import math
import os
import pathlib
import struct
import subprocess

import pytest

from test_scenario import build_cli

REPO = pathlib.Path(__file__).resolve().parents[3]
FIXTURES = REPO / "crates" / "wmr-cli" / "tests" / "fixtures"

rosbags = pytest.importorskip("rosbags", reason="rosbags is not installed (scripts/python-test-requirements.txt)")
mcap_ros2 = pytest.importorskip("mcap_ros2", reason="mcap-ros2-support is not installed")
from mcap.reader import make_reader  # noqa: E402
from mcap_ros2.decoder import DecoderFactory  # noqa: E402
from rosbags.rosbag2 import Reader  # noqa: E402
from rosbags.typesys import Stores, get_types_from_msg, get_typestore  # noqa: E402

#: Every column of wmr_msgs/Sample, in order (the CSV's groups, every one).
SAMPLE_FIELDS = (
    "t x y theta v omega phi_r phi_l omega_r omega_l tau_r tau_l e_s e_theta dl "
    "x_meas y_meas theta_meas x_odom y_odom theta_odom "
    "slip_r slip_l v_lat fx_r fx_l fy_r fy_l n_r n_l "
    "x_ref y_ref theta_ref v_ref omega_ref "
    "v_cmd omega_cmd "
    "tau_dist_r tau_dist_l"
).split()

PER_SAMPLE = ("tf", "odom", "joint_states", "wmr/sample")


def bits(v: float) -> int:
    return struct.unpack("<q", struct.pack("<d", v))[0]


def same(a: float, b: float) -> bool:
    """Equal to the bit; any NaN equals any NaN, and -0.0 equals 0 (the CSV writes both as 0)."""
    return (math.isnan(a) and math.isnan(b)) or bits(a) == bits(b) or a == b == 0.0


@pytest.fixture(scope="module")
def cli() -> pathlib.Path:
    return build_cli()


def run(cli: pathlib.Path, scenario: pathlib.Path, out: pathlib.Path, *extra: str) -> None:
    subprocess.run([str(cli), "run", str(scenario), "-o", str(out), *extra], check=True, capture_output=True)


def read_csv(path: pathlib.Path) -> dict[int, list[dict[str, float]]]:
    rows: dict[int, list[dict[str, float]]] = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            rows.setdefault(int(row["run"]), []).append({k: float(v) for k, v in row.items() if k != "run"})
    return rows


def ns_of(stamp) -> int:
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def quat_yaw(q) -> tuple[float, float, float, float]:
    return (q.x, q.y, q.z, q.w)


def yaw_q(theta: float) -> tuple[float, float, float, float]:
    return (0.0, 0.0, math.sin(0.5 * theta), math.cos(0.5 * theta))


def names(runs: int, i: int) -> tuple[str, str]:
    """(topic namespace, frame prefix) of run i of runs."""
    return (f"/run{i}", f"run{i}/") if runs > 1 else ("", "")


CASES = ["odometry-3s.toml", "two-runs-every-topic.toml", "slip-3s.toml"]


@pytest.fixture(scope="module", params=CASES)
def written(request, cli, tmp_path_factory):
    d = tmp_path_factory.mktemp("ros2")
    scenario = FIXTURES / request.param
    run(cli, scenario, d / "run.mcap", "--profile", "ros2")
    run(cli, scenario, d / "run.csv")
    return d / "run.mcap", read_csv(d / "run.csv"), request.param


@pytest.mark.parametrize("store", [Stores.ROS2_JAZZY, Stores.ROS2_HUMBLE])
def test_rosbags_reads_every_message_and_the_fields_equal_the_csv(written, store):
    path, csv_runs, name = written
    typestore = get_typestore(store)
    with Reader(path) as reader:
        conns = {c.topic: c for c in reader.connections}
        for c in reader.connections:
            # The schemas: each type the file defines parses to the fields of the typestore's
            # ROS 2 definition (wmr_msgs/Sample: the repository's .msg file).
            types = get_types_from_msg(c.msgdef.data, c.msgtype)
            for t, definition in types.items():
                if t.startswith("wmr_msgs/"):
                    assert [f[0] for f in definition[1]] == ["header", *SAMPLE_FIELDS], definition
                    continue
                assert definition == typestore.fielddefs[t], (t, definition, typestore.fielddefs[t])
            typestore.register({t: d for t, d in types.items() if t.startswith("wmr_msgs/")})
        msgs: dict[str, list] = {}
        for c, _, raw in reader.messages():
            msgs.setdefault(c.topic, []).append(typestore.deserialize_cdr(raw, c.msgtype))
        assert reader.message_count == sum(len(v) for v in msgs.values())
    runs = len(csv_runs)
    for i, rows in csv_runs.items():
        ns, fp = names(runs, i)
        for t in PER_SAMPLE:
            assert len(msgs[f"{ns}/{t}"]) == len(rows), (t, name)
        assert len(msgs[f"{ns}/tf_static"]) == 1 and len(msgs[f"{ns}/goal_pose"]) == 1
        static = msgs[f"{ns}/tf_static"][0].transforms[0]
        assert (static.header.frame_id, static.child_frame_id) == (f"{fp}base_link", f"{fp}caster_link")
        assert conns[f"{ns}/tf"].msgtype == "tf2_msgs/msg/TFMessage"
        for k, row in enumerate(rows):
            want_ns = round(row["t"] * 1e9)
            sample = msgs[f"{ns}/wmr/sample"][k]
            assert ns_of(sample.header.stamp) == want_ns
            for f in SAMPLE_FIELDS:
                assert same(getattr(sample, f), row.get(f, math.nan)), (name, k, f)
            used = (row["x_meas"], row["y_meas"], row["theta_meas"]) if "x_meas" in row else None
            odom = msgs[f"{ns}/odom"][k]
            assert (odom.header.frame_id, odom.child_frame_id) == (f"{fp}odom", f"{fp}base_link")
            assert ns_of(odom.header.stamp) == want_ns
            p = odom.pose.pose
            if used is not None:
                assert all(same(a, b) for a, b in zip((p.position.x, p.position.y), used[:2]))
                assert all(same(a, b) for a, b in zip(quat_yaw(p.orientation), yaw_q(used[2])))
            assert same(odom.twist.twist.linear.x, row["v"]) and same(odom.twist.twist.angular.z, row["omega"])
            assert same(odom.twist.twist.linear.y, row.get("v_lat", 0.0))
            js = msgs[f"{ns}/joint_states"][k]
            assert list(js.name) == ["wheel_left_joint", "wheel_right_joint"]
            assert all(same(a, b) for a, b in zip(js.position, (row["phi_l"], row["phi_r"])))
            assert all(same(a, b) for a, b in zip(js.velocity, (row["omega_l"], row["omega_r"])))
            assert all(same(a, b) for a, b in zip(js.effort, (row["tau_l"], row["tau_r"])))
            tf = msgs[f"{ns}/tf"][k].transforms
            pairs = [(x.header.frame_id, x.child_frame_id) for x in tf]
            assert pairs == [
                ("map", f"{fp}odom"),
                (f"{fp}odom", f"{fp}base_link"),
                (f"{fp}base_link", f"{fp}wheel_left_link"),
                (f"{fp}base_link", f"{fp}wheel_right_link"),
            ]
            # REP 105: map -> odom -> base_link is the true pose (composed: to rounding).
            m, o = tf[0].transform, tf[1].transform
            ym = 2 * math.atan2(m.rotation.z, m.rotation.w)
            yo = 2 * math.atan2(o.rotation.z, o.rotation.w)
            x = m.translation.x + math.cos(ym) * o.translation.x - math.sin(ym) * o.translation.y
            y = m.translation.y + math.sin(ym) * o.translation.x + math.cos(ym) * o.translation.y
            assert abs(x - row["x"]) < 1e-12 and abs(y - row["y"]) < 1e-12, (name, k)
            assert abs(math.remainder(ym + yo - row["theta"], math.tau)) < 1e-12
            if used is not None:
                assert (o.translation.x, o.translation.y) == used[:2]
            # The wheels turn about y by their joint angle.
            assert same(tf[2].transform.rotation.y, math.sin(0.5 * row["phi_l"]))
            assert same(tf[3].transform.rotation.y, math.sin(0.5 * row["phi_r"]))
        # /cmd_vel (issue 43 item 1): the twist the law demanded, the CSV's v_cmd and
        # omega_cmd to the bit, for a law that demands a twist (kanayama); none otherwise
        # (the paper's law demands wheel angles).
        assert ("v_cmd" in rows[0]) == (name == "two-runs-every-topic.toml"), name
        if "v_cmd" in rows[0]:
            assert conns[f"{ns}/cmd_vel"].msgtype == "geometry_msgs/msg/TwistStamped"
            cmds = msgs[f"{ns}/cmd_vel"]
            assert len(cmds) == len(rows), name
            for cmd, row in zip(cmds, rows):
                assert ns_of(cmd.header.stamp) == round(row["t"] * 1e9)
                assert cmd.header.frame_id == f"{fp}base_link"
                tw = cmd.twist
                assert same(tw.linear.x, row["v_cmd"]) and same(tw.angular.z, row["omega_cmd"]), (name, row["t"])
                assert (tw.linear.y, tw.linear.z, tw.angular.x, tw.angular.y) == (0.0, 0.0, 0.0, 0.0)
            assert any(c.twist.linear.x != 0.0 for c in cmds) and any(c.twist.angular.z != 0.0 for c in cmds)
        else:
            assert f"{ns}/cmd_vel" not in msgs, name
        if "x_ref" in rows[0]:
            plan = msgs[f"{ns}/plan"][0]
            assert len(plan.poses) == len(rows)
            for pose, row in zip(plan.poses, rows):
                assert same(pose.pose.position.x, row["x_ref"]) and same(pose.pose.position.y, row["y_ref"])
                assert all(same(a, b) for a, b in zip(quat_yaw(pose.pose.orientation), yaw_q(row["theta_ref"])))
        else:
            assert f"{ns}/plan" not in msgs


def test_channels_follow_the_ros2_profile(written):
    path, csv_runs, _ = written
    with open(path, "rb") as f:
        reader = make_reader(f)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        assert summary is not None
        from rosbags.rosbag2.metadata import parse_qos

        for ch in summary.channels.values():
            schema = summary.schemas[ch.schema_id]
            assert ch.message_encoding == "cdr" and schema.encoding == "ros2msg"
            assert "/msg/" in schema.name
            qos = parse_qos(ch.metadata["offered_qos_profiles"])
            assert len(qos) == 1
            latched = ch.topic.endswith("/tf_static") or ch.topic.endswith("/robot_description")
            want = "TRANSIENT_LOCAL" if latched else "VOLATILE"
            assert qos[0].durability.name == want, ch.topic
            assert qos[0].reliability.name == "RELIABLE"


def test_mcap_ros2_support_decodes_every_message(written):
    path, csv_runs, name = written
    count: dict[str, int] = {}
    samples: dict[str, list] = {}
    with open(path, "rb") as f:
        for _, channel, _, msg in make_reader(f, decoder_factories=[DecoderFactory()]).iter_decoded_messages():
            count[channel.topic] = count.get(channel.topic, 0) + 1
            if channel.topic.endswith("/wmr/sample"):
                samples.setdefault(channel.topic, []).append(msg)
    runs = len(csv_runs)
    for i, rows in csv_runs.items():
        ns, _ = names(runs, i)
        for t in PER_SAMPLE:
            assert count[f"{ns}/{t}"] == len(rows)
        for s, row in zip(samples[f"{ns}/wmr/sample"], rows):
            for f in SAMPLE_FIELDS:
                assert same(getattr(s, f), row.get(f, math.nan)), (name, f)


def test_the_profile_flag_is_refused_where_it_means_nothing(cli, tmp_path):
    scenario = FIXTURES / "odometry-3s.toml"
    for extra in (["-o", str(tmp_path / "a.csv"), "--profile", "ros2"], ["--profile", "ros2"]):
        r = subprocess.run([str(cli), "run", str(scenario), *extra], capture_output=True, text=True)
        assert r.returncode == 2, r
        assert "--profile" in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr
    r = subprocess.run([str(cli), "run", str(scenario), "-o", str(tmp_path / "b.mcap"), "--profile", "ros9"],
                       capture_output=True, text=True)
    assert r.returncode == 2 and "ros9" in r.stderr


def test_the_foxglove_default_is_unchanged_and_both_holds_both(cli, tmp_path):
    scenario = FIXTURES / "two-runs-every-topic.toml"
    run(cli, scenario, tmp_path / "default.mcap")
    run(cli, scenario, tmp_path / "fox.mcap", "--profile", "foxglove")
    assert (tmp_path / "default.mcap").read_bytes() == (tmp_path / "fox.mcap").read_bytes()
    run(cli, scenario, tmp_path / "both.mcap", "--profile", "both")
    with open(tmp_path / "both.mcap", "rb") as f:
        summary = make_reader(f).get_summary()
    encodings = {ch.message_encoding for ch in summary.channels.values()}
    assert encodings == {"protobuf", "cdr"}
    topics = {ch.topic for ch in summary.channels.values()}
    assert {"/run0/tf", "/run1/sample", "/run0/odom", "/run1/wmr/sample"} <= topics


def test_rosbag2_makes_the_folder_a_bag_rosbags_reads_by_its_metadata(cli, tmp_path):
    """`--rosbag2`: metadata.yaml beside the file, in rosbag2's Humble form (version 5, each
    topic's QoS one YAML string), read by rosbags' directory reader, which takes the topics,
    types, counts and QoS from metadata.yaml and the messages from the file it names."""
    from ruamel.yaml import YAML

    scenario = FIXTURES / "two-runs-every-topic.toml"
    bag = tmp_path / "bag"
    bag.mkdir()
    run(cli, scenario, bag / "run.mcap", "--profile", "ros2", "--rosbag2")
    info = YAML(typ="safe").load((bag / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    assert info["version"] == 5 and info["storage_identifier"] == "mcap"
    assert info["relative_file_paths"] == ["run.mcap"]
    assert all(isinstance(t["topic_metadata"]["offered_qos_profiles"], str) for t in info["topics_with_message_count"])
    # What the file itself holds, read without metadata.yaml (its summary and its messages).
    with open(bag / "run.mcap", "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        counted: dict[str, int] = {}
        first, last = None, None
        for _, channel, message in reader.iter_messages():
            counted[channel.topic] = counted.get(channel.topic, 0) + 1
            first = message.log_time if first is None else min(first, message.log_time)
            last = message.log_time if last is None else max(last, message.log_time)
    types = {ch.topic: summary.schemas[ch.schema_id].name for ch in summary.channels.values()}
    with Reader(bag) as r:
        assert {c.topic: c.msgcount for c in r.connections} == counted
        assert {c.topic: c.msgtype for c in r.connections} == types
        assert r.message_count == sum(counted.values())
        assert r.start_time == first and r.end_time == last + 1  # rosbags' end is exclusive
        durability = {c.topic: c.ext.offered_qos_profiles[0].durability.name for c in r.connections}
        assert durability["/run0/tf_static"] == "TRANSIENT_LOCAL" and durability["/run0/odom"] == "VOLATILE"
        assert sum(1 for _ in r.messages()) == sum(counted.values())


def test_rosbag2_is_refused_where_no_bag_can_be_made(cli, tmp_path):
    scenario = FIXTURES / "odometry-3s.toml"
    cases = (
        ["-o", str(tmp_path / "a.mcap"), "--rosbag2"],  # Foxglove channels
        ["-o", str(tmp_path / "b.mcap"), "--profile", "both", "--rosbag2"],
        ["-o", "-", "--format", "mcap", "--profile", "ros2", "--rosbag2"],  # stdout
        ["-o", str(tmp_path / "metadata.yaml"), "--format", "mcap", "--profile", "ros2", "--rosbag2"],
    )
    for extra in cases:
        r = subprocess.run([str(cli), "run", str(scenario), *extra], capture_output=True, text=True)
        assert r.returncode == 2, (extra, r)
        assert "--rosbag2" in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == []
