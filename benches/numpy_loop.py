"""The Fig. 7 closed loop written in numpy, the way a notebook user would: the paper's
controller, the two PD wheel servos, the torque drive's clamp, RK4 and the dynamic
model (15), with wmr's defaults (docs/model.md). It is the yardstick for the
"pure-numpy loop vs Rust" row of benches/compare, and it checks itself against
wmr_py.simulate on the same horizon.

    python benches/numpy_loop.py [T_END_S]      (default 5 s; prints key=value)
"""

from __future__ import annotations

import sys
import time

import numpy as np

# The paper's robot (docs/model.md).
m, r, R, d, I_m, I_p, k_t = 5.0, 0.1, 0.2, 0.25, 0.002, 0.005, 0.1
M11 = m + 2 * I_m / r**2
M22 = I_p + 2 * R**2 * I_m / r**2 + m * d**2
TAU_MAX = 0.2 / k_t  # wheel torque limit, N m
# The paper's law and the wheel servos (docs/model.md).
KP_TH, KI_TH, KP_S, KI_S = 2.0, 0.1, 1.0, 0.25
SERVO_KP, SERVO_KD = 14.0, 1.4
GOAL_R, HOLD_R, DT = 1e-3, 5e-3, 1e-3


def derivative(y: np.ndarray, tau: np.ndarray) -> np.ndarray:
    x, yy, th, v, om, _, _ = y
    w_r, w_l = (v + R * om) / r, (v - R * om) / r
    return np.array([
        v * np.cos(th),
        v * np.sin(th),
        om,
        ((tau[0] + tau[1]) / r + m * d * om * om) / M11,
        (R / r * (tau[0] - tau[1]) - m * d * v * om) / M22,
        w_r,
        w_l,
    ])


def rk4(y: np.ndarray, tau: np.ndarray, h: float) -> np.ndarray:
    k1 = derivative(y, tau)
    k2 = derivative(y + h / 2 * k1, tau)
    k3 = derivative(y + h / 2 * k2, tau)
    k4 = derivative(y + h * k3, tau)
    return y + h / 6 * (k1 + 2 * (k2 + k3) + k4)


def wrap(a: float) -> float:
    return (a + np.pi) % (2 * np.pi) - np.pi if not (-np.pi < a <= np.pi) else a


def run(t_end: float, start=(0.0, 0.0, 0.0), goal=(1.0, 1.0, np.radians(120.0))) -> np.ndarray:
    y = np.array([start[0], start[1], start[2], 0.0, 0.0, 0.0, 0.0])
    int_th = int_s = 0.0
    last_alpha = None
    for _ in range(int(round(t_end / DT))):
        # Controller (every step: control_dt = dt).
        dx, dy = goal[0] - y[0], goal[1] - y[1]
        dl = np.hypot(dx, dy)
        if dl > GOAL_R:
            last_alpha = np.arctan2(dy, dx)
        alpha = last_alpha if last_alpha is not None else goal[2]
        th_ref = 2 * alpha - goal[2]
        if dl < HOLD_R:
            e_s = e_th = 0.0
        else:
            e_s = dl * np.cos(th_ref - y[2])
            e_th = wrap(th_ref - y[2])
            int_s += e_s * DT
            int_th += e_th * DT
        u_s = KP_S * e_s + KI_S * int_s
        u_th = KP_TH * e_th + KI_TH * int_th
        ref = np.array([(u_s + R * u_th) / r, (u_s - R * u_th) / r])
        w = np.array([(y[3] + R * y[4]) / r, (y[3] - R * y[4]) / r])
        tau = np.clip(SERVO_KP * (ref - y[5:7]) - SERVO_KD * w, -TAU_MAX, TAU_MAX)
        y = rk4(y, tau, DT)
    return y


def main() -> None:
    t_end = float(sys.argv[1]) if len(sys.argv) > 1 else 5.0
    t0 = time.perf_counter()
    y = run(t_end)
    wall = time.perf_counter() - t0
    steps = int(round(t_end / DT))
    line = f"impl=numpy t_end={t_end} steps={steps} x={float(y[0])!r} y={float(y[1])!r} theta={float(y[2])!r} step_ns={wall / steps * 1e9:.0f}"
    try:
        import wmr_py

        ref = wmr_py.simulate((0, 0, 0), {"x": 1, "y": 1, "theta_deg": 120}, t_end=t_end)
        gap = max(abs(ref.x[-1] - y[0]), abs(ref.y[-1] - y[1]), abs(ref.theta[-1] - y[2]))
        line += f" max_gap_vs_wmr_py={gap:.3e}"
    except ImportError:
        line += " max_gap_vs_wmr_py=skipped"
    print(line)


if __name__ == "__main__":
    main()
