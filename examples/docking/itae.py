"""ITAE of a step test (examples/docking/README.md, "The step test"): for each step of
the scenario (its pushes' and its payload's times), the integral of (t - t_step) |e| dt
over the window from that step to the next (or to the run's end), with and without the
disturbance observer, and their ratio. |e| is the distance of C from the goal (a run
holding a goal) or from the reference point C_ref (a tracking run: the CSV's x_ref,
y_ref), from the true state; trapezoids over the CSV's samples.

    python3 examples/docking/itae.py SCENARIO.toml WITHOUT.csv WITH.csv
"""

import csv
import math
import sys
import tomllib


def steps(scenario):
    """The step times (s) and names, in order: each push's start, the payload's t."""
    world = scenario.get("world", {})
    out = [(p["t"], "push") for p in world.get("push", [])]
    payload = world.get("payload")
    if payload and payload.get("mass", 0.0) > 0.0:
        out.append((payload.get("t", 0.0), "payload"))
    return sorted(out)


def error_series(path, goal):
    """(t, |e|) of run 0 of a CSV written by `wmr-cli run`."""
    with open(path, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["run"] == "0"]
    if "x_ref" in rows[0]:
        return [(float(r["t"]), math.hypot(float(r["x"]) - float(r["x_ref"]), float(r["y"]) - float(r["y_ref"]))) for r in rows]
    gx, gy = goal
    return [(float(r["t"]), math.hypot(float(r["x"]) - gx, float(r["y"]) - gy)) for r in rows]


def itae(series, t0, t1):
    """The integral of (t - t0) |e| dt over [t0, t1] by trapezoids on the samples."""
    pts = [(t, e) for t, e in series if t0 <= t <= t1]
    return sum(0.5 * (b[0] - a[0]) * ((a[0] - t0) * a[1] + (b[0] - t0) * b[1]) for a, b in zip(pts, pts[1:]))


def main(scenario_path, without, with_observer):
    with open(scenario_path, "rb") as f:
        scenario = tomllib.load(f)
    goal = scenario["run"][0].get("goal", {"x": 0.0, "y": 0.0})
    plain = error_series(without, (goal["x"], goal["y"]))
    dob = error_series(with_observer, (goal["x"], goal["y"]))
    t_end = plain[-1][0]
    times = steps(scenario)
    print(f"{'step':<22} {'window s':>12} {'ITAE without':>14} {'ITAE with':>12} {'ratio':>8} {'reduction':>10}")
    for i, (t0, name) in enumerate(times):
        t1 = times[i + 1][0] if i + 1 < len(times) else t_end
        a, b = itae(plain, t0, t1), itae(dob, t0, t1)
        print(f"{name:<22} {f'{t0:g}-{t1:g}':>12} {a:>14.4e} {b:>12.4e} {b / a:>8.4f} {100 * (1 - b / a):>9.1f}%")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
