"""Fig. 7 run time from Python vs the same work in Rust, in one process.

    python crates/wmr-py/bench_fig7.py [N]

Python: wmr_py.run_scenario("examples/paper/fig7.toml"): parse, run (60 s, dt = 1 ms,
60 000 RK4 steps, 6001 samples), columns handed to numpy, RunResult built.
Rust:   wmr_py._native._time_run_rust(path, N): the same parse + run + column building
timed inside Rust with Instant (GIL released, no Python objects), i.e. what the CLI does
minus writing the file. Both are best of N. The ratio is the cost of the binding.
"""

from __future__ import annotations

import pathlib
import sys
import time

import wmr_py
from wmr_py import _native

REPO = pathlib.Path(__file__).resolve().parents[2]


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20
    path = REPO / "examples" / "paper" / "fig7.toml"
    source = str(path) if path.is_file() else {
        "sim": {"t_end": 60.0, "dt": 1e-3, "log_dt": 0.01},
        "run": [{"start": {"x": 0, "y": 0, "theta_deg": 0}, "goal": {"x": 1, "y": 1, "theta_deg": 120}}],
    }
    wmr_py.run_scenario(source)  # warm up
    best_py = float("inf")
    for _ in range(n):
        t0 = time.perf_counter()
        wmr_py.run_scenario(source)
        best_py = min(best_py, time.perf_counter() - t0)
    best_rust = _native._time_run_rust(source, n)
    print(f"Fig. 7 ({'examples/paper/fig7.toml' if isinstance(source, str) else 'built-in dict'}), best of {n}:")
    print(f"  Python wmr_py.run_scenario : {best_py * 1e3:8.3f} ms")
    print(f"  Rust in-process            : {best_rust * 1e3:8.3f} ms")
    print(f"  ratio Python / Rust        : {best_py / best_rust:8.3f}")


if __name__ == "__main__":
    main()
