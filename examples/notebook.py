# %% [markdown]
# # wmr_py: Figs. 7-9 of the paper from Python
#
# Start (0, 0, 0), goal (1, 1, 120 deg), every default (docs/model.md).
# Install: `pip install ./crates/wmr-py matplotlib`; run as a script or cell by cell
# (VS Code / Jupytext `# %%` cells). matplotlib is optional: without it the script
# prints the summary and stops. Run headless (`python examples/notebook.py`, no display),
# it prints the summaries and a table of the run, and saves the figure to
# notebook-figs7-9.png (or the path in $WMR_NOTEBOOK_OUT) and says where.
# For more, see examples/notebooks/ (paper.ipynb, tune_gains.ipynb).

# %%
import math
import os
import pathlib

import numpy as np

import wmr_py

here = pathlib.Path(__file__).resolve().parent if "__file__" in globals() else pathlib.Path("examples")
fig7 = here / "paper" / "fig7.toml"
if fig7.is_file():
    (run,) = wmr_py.run_scenario(fig7)
else:  # the same run without the file
    run = wmr_py.simulate((0.0, 0.0, 0.0), (1.0, 1.0, math.radians(120.0)))
print(run.summary)

# %% A loop closed in Python: the same controller with a noisy pose sensor.
robot = wmr_py.Robot()
ctrl = wmr_py.PaperController((1.0, 1.0, math.radians(120.0)), robot)
rng = np.random.default_rng(0)
state, tau, dt = np.zeros(7), (0.0, 0.0), 1e-3
noisy_path = []
for k in range(20_000):  # 20 s
    if k % round(ctrl.control_dt / dt) == 0:
        pose = state[:3] + rng.normal(0.0, [2e-3, 2e-3, 2e-3])
        cmd = ctrl.update(pose, state[5:7], robot.wheel_speeds(state))
        tau = tuple(np.clip(cmd, -2.0, 2.0))  # torque drive: |tau| <= 0.2 N m / k_t
    state = robot.step(state, tau, dt)
    noisy_path.append(state[:2].copy())
noisy_path = np.array(noisy_path)
print(f"noisy sensor, after 20 s: dl = {math.hypot(1 - state[0], 1 - state[1]):.4f} m")

# %% The run as a table (pandas is optional).
try:
    table = run.to_pandas()
except ImportError as e:
    print(e)
else:
    print(table[["t", "x", "y", "theta", "omega_r", "omega_l", "dl"]].iloc[::1000].to_string(index=False))

# %%
try:
    import matplotlib.pyplot as plt
except ImportError:  # optional
    plt = None
    print("matplotlib not installed: pip install matplotlib to see the figures")

if plt is not None:
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    ax[0].plot(run.x, run.y, label="C (Fig. 7)")
    ax[0].plot(noisy_path[:, 0], noisy_path[:, 1], lw=0.8, alpha=0.7, label="noisy sensor, 20 s")
    ax[0].plot([0, 1], [0, 1], "k+", ms=12)
    ax[0].set(xlabel="x (m)", ylabel="y (m)", title="Fig. 7: path of C", aspect="equal")
    ax[0].legend()
    ax[1].plot(run.t, run.omega_r, label="omega_r")
    ax[1].plot(run.t, run.omega_l, label="omega_l")
    ax[1].set(xlabel="t (s)", ylabel="rad/s", title="Fig. 8: wheel speeds")
    ax[1].legend()
    ax[2].plot(run.t, run.dl, label="dl (m)")
    ax[2].plot(run.t, run.e_s, label="e_s (m)")
    ax[2].plot(run.t, run.e_theta, label="e_theta (rad)")
    ax[2].set(xlabel="t (s)", title="Fig. 9: errors")
    ax[2].legend()
    fig.tight_layout()
    out = pathlib.Path(os.environ.get("WMR_NOTEBOOK_OUT", "notebook-figs7-9.png"))
    fig.savefig(out, dpi=120)
    print(f"figure saved to {out.resolve()}")
    if plt.get_backend().lower() not in ("agg", "pdf", "svg", "ps", "cairo", "template"):
        plt.show()
