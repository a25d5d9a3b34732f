"""One MPPI cycle side by side (wmr issue 41): wmr with its dynamic model, wmr with nav2's
kinematic model, and pytorch-mppi (PyPI `pytorch-mppi`, on the CPU) with the same
kinematic model, batch and horizon (1000 samples x 56 steps of 0.05 s, one iteration).

    python benches/mppi_peer.py [--cycles 200] [--rounds 5]

wmr runs through wmr_py: `MppiController.update` with control_dt = 0.01 s plans at every
fifth call (model_dt = 0.05 s), so a cycle is five calls; a call's own cost is
microseconds against the plan's milliseconds. The three are
timed in turn, round after round, on the same machine in the same run, and the ratios are
printed pair by pair: a ratio, not an absolute figure, is what carries to another
machine. pytorch-mppi missing (it needs torch) is said and counted as skipped.

pytorch-mppi's model: nav2's DiffDrive (the sampled (vx, wz) within the acceleration
limits of the speed of the step before, then the pose by Euler, heading first), written
in torch over the batch; its cost: nav2's goal critic (weight 5 x the distance to the goal,
summed per step) and its control cost (pytorch-mppi's own, lambda = temperature = 0.3).
The critics differ in detail from nav2's (pytorch-mppi sums a running cost per step);
what is compared is the work of a cycle: sampling, rolling out, scoring, averaging.
"""

import argparse
import math
import os
import sys
import time

import wmr_py

BATCH, STEPS, DT = 1000, 56, 0.05
AX_MAX, AX_MIN, AZ_MAX = 3.0, -3.0, 3.5
GOAL = (1.0, 0.2, 0.2)
START = (0.2, 0.1, 0.3)
SPEED = (0.3, 0.4)  # m/s, rad/s


def wmr_controller(model):
    robot = wmr_py.Robot()
    ctl = wmr_py.MppiController(
        GOAL,
        robot,
        {"kind": "dc_motor"},
        motion_model=model,
        control_dt=0.01,
    )
    r, big_r = robot.wheel_radius, robot.half_track
    speeds = ((SPEED[0] + big_r * SPEED[1]) / r, (SPEED[0] - big_r * SPEED[1]) / r)
    ticks = round(DT / 0.01)

    def cycle():
        for _ in range(ticks):
            ctl.update(START, (0.0, 0.0), speeds)

    return cycle


def torch_controller(threads):
    import torch
    from pytorch_mppi import MPPI

    torch.set_num_threads(threads)
    dtype = torch.float64
    goal = torch.tensor(GOAL[:2], dtype=dtype)

    def dynamics(state, action):
        # state (K, 5): x, y, yaw, vx, wz; action (K, 2): the sampled vx, wz.
        x, y, yaw, vx, wz = state.unbind(1)
        lo = torch.where(vx > 0, vx + DT * AX_MIN, vx - DT * AX_MAX)
        hi = torch.where(vx > 0, vx + DT * AX_MAX, vx - DT * AX_MIN)
        vx1 = torch.minimum(torch.maximum(action[:, 0], lo), hi)
        wz1 = torch.minimum(torch.maximum(action[:, 1], wz - DT * AZ_MAX), wz + DT * AZ_MAX)
        yaw1 = yaw + wz1 * DT
        return torch.stack((x + vx1 * torch.cos(yaw) * DT, y + vx1 * torch.sin(yaw) * DT, yaw1, vx1, wz1), 1)

    def running_cost(state, action):
        return 5.0 * torch.linalg.norm(state[:, :2] - goal, dim=1)

    sigma = torch.diag(torch.tensor([0.2**2, 0.4**2], dtype=dtype))
    mppi = MPPI(
        dynamics,
        running_cost,
        5,
        sigma,
        num_samples=BATCH,
        horizon=STEPS,
        device="cpu",
        lambda_=0.3,
        u_min=torch.tensor([-0.35, -1.9], dtype=dtype),
        u_max=torch.tensor([0.5, 1.9], dtype=dtype),
    )
    state = torch.tensor([*START, *SPEED], dtype=dtype)
    return lambda: mppi.command(state)


def per_cycle_ms(step, cycles):
    step()  # warm up (allocations, lazy initialisation)
    t0 = time.perf_counter()
    for _ in range(cycles):
        step()
    return 1e3 * (time.perf_counter() - t0) / cycles


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cycles", type=int, default=200, help="cycles per timing (default 200)")
    ap.add_argument("--rounds", type=int, default=5, help="rounds of the three timings (default 5)")
    ap.add_argument("--threads", type=int, default=1, help="torch's CPU threads (default 1: one core, as wmr)")
    a = ap.parse_args()
    runs = {"wmr dynamic": wmr_controller("dynamic"), "wmr kinematic": wmr_controller("kinematic")}
    try:
        runs["pytorch-mppi kinematic"] = torch_controller(a.threads)
    except Exception as e:  # ImportError, or torch without its libraries
        print(f"pytorch-mppi: skipped ({type(e).__name__}: {e})")
    times = {k: [] for k in runs}
    for _ in range(a.rounds):
        for name, step in runs.items():
            times[name].append(per_cycle_ms(step, a.cycles))
    cpu = "unknown CPU"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    print(f"one MPPI cycle, {BATCH} x {STEPS} x {DT} s, {cpu}, {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.2f}")
    for name, t in times.items():
        t = sorted(t)
        print(f"  {name:<24} median {t[len(t) // 2]:8.3f} ms per cycle (best {t[0]:.3f}, {a.rounds} rounds of {a.cycles})")
    base = times.get("pytorch-mppi kinematic")
    if base:
        for name in ("wmr kinematic", "wmr dynamic"):
            ratios = sorted(b / w for b, w in zip(base, times[name]))
            print(f"  pytorch-mppi / {name}: {ratios[len(ratios) // 2]:.1f}x (round by round: {', '.join(f'{r:.1f}' for r in ratios)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
