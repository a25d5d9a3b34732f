"""Issue 44: ``wmr_py.identify`` is the fit of ``wmr-cli identify`` (docs/identify.md).

The same log (``wmr-cli excite --log``, the worked example's DC-motor robot with 1 %
encoder noise and 5 ms jitter; and a wmr run written as a ROS 2 MCAP) identified by the
CLI and by Python gives the same robot file bit for bit; the fitted robot runs as a
``Robot`` and as a scenario's robot exactly as ``[robot] from`` the CLI's file; a
parameter the log does not determine raises a ``ParameterError`` naming it.
"""

from __future__ import annotations

import math
import pathlib
import subprocess

import pytest

import wmr_py
from conftest import REPO
from test_scenario import build_cli

ROBOT = REPO / "examples" / "identify" / "robot.toml"


def _cli(args: list, cwd: pathlib.Path) -> subprocess.CompletedProcess:
    return subprocess.run([str(build_cli())] + args, cwd=cwd, capture_output=True, text=True, timeout=600)


@pytest.fixture(scope="module")
def dc_log(tmp_path_factory: pytest.TempPathFactory) -> pathlib.Path:
    d = tmp_path_factory.mktemp("identify")
    done = _cli(
        ["excite", "-o", "profile.csv", "--robot", str(ROBOT), "--log", "log.csv",
         "--encoder-noise", "0.01", "--jitter", "0.005", "--seed", "44"],
        d,
    )
    assert done.returncode == 0, done.stderr
    return d / "log.csv"


def test_identify_equals_the_cli_robot_file_bit_for_bit(dc_log: pathlib.Path) -> None:
    d = dc_log.parent
    done = _cli(["identify", "log.csv", "--drive", "dc_motor", "--robot", str(ROBOT), "-o", "cli.toml"], d)
    assert done.returncode == 0, done.stderr
    cli_text = (d / "cli.toml").read_text()
    # The same path as the CLI was given (it is written into the file's comments).
    import os

    here = os.getcwd()
    os.chdir(d)
    try:
        fitted = wmr_py.identify("log.csv", drive="dc_motor", robot=str(ROBOT))
    finally:
        os.chdir(here)
    assert fitted.toml == cli_text
    assert isinstance(fitted, wmr_py.IdentifiedRobot)
    # Every fitted value with its standard error; the defaults held for a DC motor.
    assert set(fitted.held) == {"mass", "viscous_friction", "armature_resistance"}
    assert set(fitted.std_errors) == {
        "wheel_inertia", "platform_inertia", "coulomb_friction", "torque_constant", "back_emf_constant"
    }
    for key, se in fitted.std_errors.items():
        assert se > 0 and math.isfinite(se), key
        # The file's comment carries the same standard error.
        mantissa, exponent = f"{se:.3e}".split("e")  # as Rust writes it: 1.017e-5
        assert f"fitted: +- {mantissa}e{int(exponent)} (standard error), from log.csv" in cli_text
    # The values are the file's, to the bit (repr of an f64 round-trips).
    for key in ("wheel_inertia", "platform_inertia", "coulomb_friction"):
        assert f"{key} = {fitted.values[key]!r} " in cli_text
        assert getattr(fitted.robot, key) == fitted.values[key]
    assert f"torque_constant = {fitted.values['torque_constant']!r} " in cli_text
    # Against the file's true values (docs/identify.md's worked example).
    assert fitted.values["platform_inertia"] == pytest.approx(0.3, rel=0.03)
    assert fitted.values["wheel_inertia"] == pytest.approx(0.004, rel=0.05)


def test_the_fitted_robot_is_a_scenario_robot(dc_log: pathlib.Path) -> None:
    d = dc_log.parent
    fitted = wmr_py.identify(dc_log, drive="dc_motor", robot=ROBOT)
    (d / "fitted.toml").write_text(fitted.toml)
    # dt 0.25 ms: the robot's Coulomb friction is too stiff for RK4 at the default 1 ms
    # (examples/identify/robot.toml says so; the fit keeps it).
    run = {"sim": {"t_end": 1.0, "dt": 2.5e-4}, "run": [{"goal": {"x": 1.0, "y": 0.5, "theta_deg": 0.0}}]}
    from_dict = wmr_py.run_scenario({**fitted.to_dict(), **run})
    (d / "scenario.toml").write_text(
        '[robot]\nfrom = "fitted.toml"\n\n[sim]\nt_end = 1.0\ndt = 2.5e-4\n\n[[run]]\ngoal = { x = 1.0, y = 0.5, theta_deg = 0.0 }\n'
    )
    from_file = wmr_py.run_scenario(str(d / "scenario.toml"))
    assert from_dict[0].x.tolist() == from_file[0].x.tolist()
    assert from_dict[0].omega_r.tolist() == from_file[0].omega_r.tolist()


def test_a_ros2_mcap_log(tmp_path: pathlib.Path) -> None:
    done = _cli(["run", str(REPO / "examples" / "paper" / "fig7.toml"), "-o", "fig7.mcap", "--profile", "ros2"], tmp_path)
    assert done.returncode == 0, done.stderr
    done = _cli(["identify", "fig7.mcap", "-o", "cli.toml"], tmp_path)
    assert done.returncode == 0, done.stderr
    fitted = wmr_py.identify(tmp_path / "fig7.mcap")
    assert fitted.toml == (tmp_path / "cli.toml").read_text().replace("fig7.mcap", str(tmp_path / "fig7.mcap"))
    assert fitted.zeroed == ["coulomb_friction"]
    assert fitted.to_dict()["drive"]["kind"] == "torque"


def test_an_unidentifiable_parameter_raises_naming_it(dc_log: pathlib.Path) -> None:
    # A voltage log gives the torque only up to the motor's scale: with only R_a held,
    # the mass is refused, named.
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.identify(dc_log, drive="dc_motor", robot=ROBOT, hold=["armature_resistance"])
    assert e.value.key == "mass"
    assert str(e.value).startswith("mass: not identifiable from this log")
    assert 'hold=["mass"]' in str(e.value)
    # The CLI refuses the same, exit 2.
    done = _cli(["identify", str(dc_log), "--drive", "dc_motor", "--robot", str(ROBOT), "-o", "m.toml",
                 "--hold", "armature_resistance"], dc_log.parent)
    assert done.returncode == 2
    assert "mass: not identifiable" in done.stderr


def test_bad_arguments_raise_naming_them(tmp_path: pathlib.Path, dc_log: pathlib.Path) -> None:
    with pytest.raises(FileNotFoundError):
        wmr_py.identify(tmp_path / "nope.csv")
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.identify(dc_log, drive="voltage")
    assert e.value.key == "drive"
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.identify(dc_log, drive="dc_motor", hold=["mass", "wheel_mass"])
    assert e.value.key == "hold"
    bad = tmp_path / "bad.csv"
    bad.write_text("t,u_r,u_l,phi_r\n0,1,1,0\n")
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.identify(bad, drive="dc_motor")
    assert e.value.key == "log"
    assert "missing column" in str(e.value)
    with pytest.raises(wmr_py.ParameterError) as e:
        wmr_py.identify(dc_log, namespace="/run1")
    assert e.value.key == "namespace"
