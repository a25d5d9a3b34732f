"""`wmr-cli log2csv` (issue 43 item 3): a ROS 2 MCAP's /cmd_vel, /joint_states and /odom
read back into wmr's columns, on a file `wmr-cli run --profile ros2` wrote (against the CSV
of the same run, to the bit where the message carries the f64 itself) and on a bag
`rosbags` writes here (unstamped Twist on /cmd_vel, joints in another order and with an
extra joint, several rates)."""

from __future__ import annotations

import csv
import math
import pathlib
import subprocess

import pytest

from test_scenario import build_cli

REPO = pathlib.Path(__file__).resolve().parents[3]
FIXTURES = REPO / "crates" / "wmr-cli" / "tests" / "fixtures"

pytest.importorskip("rosbags", reason="rosbags is not installed (scripts/python-test-requirements.txt)")
from rosbags.rosbag2 import StoragePlugin, Writer  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402


@pytest.fixture(scope="module")
def cli() -> pathlib.Path:
    return build_cli()


def rows_of(path: pathlib.Path) -> list[dict[str, str]]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_a_wmr_ros2_file_reads_back_to_its_csv(cli, tmp_path):
    scenario = FIXTURES / "two-runs-every-topic.toml"
    subprocess.run([str(cli), "run", str(scenario), "-o", str(tmp_path / "r.mcap"), "--profile", "ros2"], check=True,
                   capture_output=True)
    subprocess.run([str(cli), "run", str(scenario), "-o", str(tmp_path / "r.csv")], check=True, capture_output=True)
    # Two robots in the file: without --namespace, a one-line error naming the choice.
    r = subprocess.run([str(cli), "log2csv", str(tmp_path / "r.mcap")], capture_output=True, text=True)
    assert r.returncode == 2 and "--namespace /run0" in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr
    truth = [row for row in rows_of(tmp_path / "r.csv") if row["run"] == "1"]
    subprocess.run([str(cli), "log2csv", str(tmp_path / "r.mcap"), "--namespace", "/run1", "-o",
                    str(tmp_path / "back.csv")], check=True, capture_output=True)
    back = rows_of(tmp_path / "back.csv")
    assert len(back) == len(truth)
    for b, t in zip(back, truth):
        # Equal text is equal f64: both are the shortest text that reads back to the value.
        assert b["t"] == t["t"]
        for ours, theirs in (("x", "x_meas"), ("y", "y_meas"), ("v", "v"), ("omega", "omega"), ("phi_r", "phi_r"),
                             ("phi_l", "phi_l"), ("omega_r", "omega_r"), ("omega_l", "omega_l"),
                             ("tau_r", "tau_r"), ("tau_l", "tau_l")):
            assert b[ours] == t[theirs], (ours, b, t)
        assert abs(math.remainder(float(b["theta"]) - float(t["theta_meas"]), math.tau)) < 1e-15
        # /cmd_vel: the twist kanayama demanded, the CSV's command columns.
        assert (b["v_cmd"], b["omega_cmd"]) == (t["v_cmd"], t["omega_cmd"]), (b, t)


def test_a_bag_written_by_rosbags_reads_back(cli, tmp_path):
    store = get_typestore(Stores.ROS2_JAZZY)
    Twist = store.types["geometry_msgs/msg/Twist"]
    Vector3 = store.types["geometry_msgs/msg/Vector3"]
    JointState = store.types["sensor_msgs/msg/JointState"]
    Odometry = store.types["nav_msgs/msg/Odometry"]
    Header = store.types["std_msgs/msg/Header"]
    Time = store.types["builtin_interfaces/msg/Time"]
    Pose = store.types["geometry_msgs/msg/Pose"]
    Point = store.types["geometry_msgs/msg/Point"]
    Quaternion = store.types["geometry_msgs/msg/Quaternion"]
    PoseWC = store.types["geometry_msgs/msg/PoseWithCovariance"]
    TwistWC = store.types["geometry_msgs/msg/TwistWithCovariance"]
    import numpy as np

    bag = tmp_path / "bag"
    t0 = 1_700_000_000_000_000_000
    with Writer(bag, version=9, storage_plugin=StoragePlugin.MCAP) as w:
        c_cmd = w.add_connection("/cmd_vel", Twist.__msgtype__, typestore=store)
        c_js = w.add_connection("/joint_states", JointState.__msgtype__, typestore=store)
        c_odom = w.add_connection("/odom", Odometry.__msgtype__, typestore=store)
        for k in range(4):  # 10 Hz commands, stamped by log time only
            msg = Twist(linear=Vector3(x=0.1 * k, y=0.0, z=0.0), angular=Vector3(x=0.0, y=0.0, z=-0.3 * k))
            w.write(c_cmd, t0 + k * 100_000_000, store.serialize_cdr(msg, Twist.__msgtype__))
        for k in range(8):  # 20 Hz joints: right first, and a third joint
            stamp = t0 + k * 50_000_000 + 1
            msg = JointState(
                header=Header(stamp=Time(sec=stamp // 10**9, nanosec=stamp % 10**9), frame_id=""),
                name=["wheel_right_joint", "lidar_joint", "wheel_left_joint"],
                position=np.array([1.0 * k, 9.0, -1.0 * k]),
                velocity=np.array([2.5, 9.0, -2.5]),
                effort=np.array([], dtype=np.float64),
            )
            w.write(c_js, stamp, store.serialize_cdr(msg, JointState.__msgtype__))
        theta = 2.5
        stamp = t0 + 2
        odom = Odometry(
            header=Header(stamp=Time(sec=stamp // 10**9, nanosec=stamp % 10**9), frame_id="odom"),
            child_frame_id="base_link",
            pose=PoseWC(pose=Pose(position=Point(x=1.25, y=-0.5, z=0.0),
                                  orientation=Quaternion(x=0.0, y=0.0, z=math.sin(theta / 2), w=math.cos(theta / 2))),
                        covariance=np.zeros(36)),
            twist=TwistWC(twist=Twist(linear=Vector3(x=0.75, y=0.0, z=0.0), angular=Vector3(x=0.0, y=0.0, z=0.125)),
                          covariance=np.zeros(36)),
        )
        w.write(c_odom, stamp, store.serialize_cdr(odom, Odometry.__msgtype__))
    mcap = next(bag.glob("*.mcap"))
    out = subprocess.run([str(cli), "log2csv", str(mcap)], check=True, capture_output=True, text=True).stdout
    rows = list(csv.DictReader(out.splitlines()))
    times = sorted({t0 + k * 100_000_000 for k in range(4)} | {t0 + k * 50_000_000 + 1 for k in range(8)} | {t0 + 2})
    assert [float(r["t"]) for r in rows] == [t / 1e9 for t in times]
    first = rows[0]  # t0: the first command only
    assert (first["v_cmd"], first["omega_cmd"], first["x"], first["phi_r"]) == ("0", "0", "", "")
    last = rows[-1]
    assert float(last["phi_r"]) == 7.0 and float(last["phi_l"]) == -7.0
    assert float(last["omega_r"]) == 2.5 and float(last["omega_l"]) == -2.5
    assert last["tau_r"] == "" and last["tau_l"] == ""  # no efforts in the message
    assert float(last["x"]) == 1.25 and float(last["y"]) == -0.5 and float(last["v"]) == 0.75
    assert abs(float(last["theta"]) - theta) < 1e-15 and float(last["omega"]) == 0.125
    assert float(last["v_cmd"]) == 0.1 * 3 and float(last["omega_cmd"]) == -0.3 * 3


def test_what_is_not_a_ros2_log_is_one_line_exit_2(cli, tmp_path):
    fox = tmp_path / "fox.mcap"
    subprocess.run([str(cli), "run", str(FIXTURES / "odometry-3s.toml"), "-o", str(fox)], check=True,
                   capture_output=True)
    bad = tmp_path / "bad.mcap"
    bad.write_bytes(b"not an mcap")
    for path in (fox, bad, tmp_path / "missing.mcap"):
        r = subprocess.run([str(cli), "log2csv", str(path)], capture_output=True, text=True)
        assert r.returncode == 2 and len(r.stderr.strip().splitlines()) == 1, (path, r.stderr)
        assert "panicked" not in r.stderr
