#!/usr/bin/env python3
"""A sweep on a Dask LocalCluster against the same sweep run locally (issue 14).

examples/compare.toml (1,000 seeded starts x 4 laws) with t_end shortened to T_END s
(default 60; `--t-end 180` for the file's own), run by `wmr_py.sweep` locally (rayon over
every core) and on `LocalCluster(n_workers=WORKERS, threads_per_worker=1, processes=True)`
(parts of the sweep, one thread each). Prints both wall times, the cluster's start-up
time apart, and checks that the results are identical bit for bit.

Run: `python crates/wmr-py/bench_executor.py [--workers 2] [--t-end 60]`. Needs wmr_py
and dask[distributed].
"""

import argparse
import os
import pathlib
import re
import sys
import time

import numpy as np

import wmr_py

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--t-end", type=float, default=60.0)
    args = ap.parse_args()
    from distributed import Client, LocalCluster

    text = (ROOT / "examples" / "compare.toml").read_text()
    text = re.sub(r"(?m)^t_end = [0-9.]+", f"t_end = {args.t_end}", text)
    print(f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} CPUs; compare.toml with t_end = {args.t_end} s")

    t0 = time.perf_counter()
    local = wmr_py.sweep(text)
    t_local = time.perf_counter() - t0
    print(f"  local (rayon)                      {t_local:7.2f} s   {len(local)} runs")

    t0 = time.perf_counter()
    cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=":0")
    client = Client(cluster)
    t_start = time.perf_counter() - t0
    try:
        t0 = time.perf_counter()
        remote = wmr_py.sweep(text, executor=client)
        t_dask = time.perf_counter() - t0
    finally:
        client.close()
        cluster.close()
    print(f"  Dask LocalCluster, {args.workers} workers       {t_dask:7.2f} s   (+ {t_start:.2f} s to start the cluster)")
    print(f"  ratio Dask / local                 {t_dask / t_local:7.2f}x")
    same = all(
        (remote[k] == local[k]) if k in ("law", "table") else np.array_equal(remote[k], local[k], equal_nan=True)
        for k in local
    )
    print(f"  identical bit for bit: {same}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
