#!/usr/bin/env python3
"""MERL-layout tables of a material sweep, baked across a Dask cluster.

A training set for neural BRDFs, or a benchmark suite: N Disney-principled materials spread over
base colour, metallic, roughness, specular, sheen and clearcoat by a Halton sequence (deterministic:
the same N gives the same materials), each tabulated in MERL's 90 x 90 x 180 layout.

    # 1,000 tables as MERL binaries (33 MiB each, with a .json of metadata beside each)
    python examples/merl_sweep.py --count 1000 --output out/merl

    # the same as float32 NumPy shards of 16 tables each (shape (16, 90, 90, 180, 3)), for ML
    python examples/merl_sweep.py --count 1000 --output out/merl_npy --npy-shards 16

    # on an existing cluster (dask-jobqueue, dask-kubernetes, `dask scheduler` + `dask worker`)
    python examples/merl_sweep.py --count 1000 --output /shared/merl --scheduler tcp://head:8786

    # the single-process baseline: the same tasks one after the other in this process, no Dask
    python examples/merl_sweep.py --count 1000 --output out/merl --single-process

It prints the throughput in tables per second (and, with --json, a line of JSON for
docs/BENCHMARKS.md). The output root must be visible to every worker (a shared file system on a
real cluster); every file is written atomically, so a partial file never appears there.
"""

from __future__ import annotations

import argparse
import colorsys
import json
import logging
import os
import sys
import time
from typing import Dict, List

import brdfbake
import brdfbake.dask as bdask


def halton(index: int, base: int) -> float:
    """The radical inverse of index in base: a low-discrepancy point in [0, 1)."""
    f, r = 1.0, 0.0
    while index > 0:
        f /= base
        r += f * (index % base)
        index //= base
    return r


def sweep(count: int) -> List[Dict]:
    """count Disney materials over a 7-dimensional Halton sequence (skipping its first point, 0)."""
    primes = (2, 3, 5, 7, 11, 13, 17)
    materials = []
    for i in range(1, count + 1):
        u = [halton(i, p) for p in primes]
        r, g, b = colorsys.hsv_to_rgb(u[0], 0.1 + 0.8 * u[1], 0.05 + 0.9 * u[2])
        materials.append({
            "name": f"sweep-{i - 1:05d}",
            "model": "disney",
            "baseColor": [round(r, 6), round(g, 6), round(b, 6)],
            "metallic": round(1.0 if u[3] > 0.7 else 0.0, 6),  # mostly dielectrics, 30% metals
            "roughness": round(0.02 + 0.98 * u[4], 6),
            "specular": round(u[5], 6),
            "clearcoat": round(u[6] if u[6] > 0.8 else 0.0, 6),
        })
    return materials


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=1000, help="how many materials (default 1000)")
    ap.add_argument("--output", required=True, help="the output root (shared by every worker)")
    ap.add_argument("--npy-shards", type=int, default=0, metavar="K",
                    help="write float32 .npy shards of K tables instead of MERL binaries")
    ap.add_argument("--workers", type=int, default=2, help="local cluster: worker processes (default 2)")
    ap.add_argument("--scheduler", help="the address of an existing Dask scheduler (default: a LocalCluster)")
    ap.add_argument("--resources", help="worker resources each task needs, e.g. GPU=1")
    ap.add_argument("--device", help="device selector on every worker (default: each worker's default)")
    ap.add_argument("--single-process", action="store_true", help="bake in this process, without Dask")
    ap.add_argument("--progress", action="store_true", help="show Dask's progress bar")
    ap.add_argument("--json", action="store_true", help="print the measurement as one line of JSON")
    args = ap.parse_args()
    if args.count < 1:
        ap.error("--count must be at least 1")

    materials = sweep(args.count)
    # What it will write, before anything is baked (brdfbake.dask also refuses a batch larger than
    # the free space under --output, and warns above 1 GiB).
    per_table = bdask._table_bytes("tabulate", {"parameters": {"layout": "merl"}}, "npy" if args.npy_shards else None)
    print(f"merl_sweep: {args.count} MERL tables, about {bdask._gib(per_table * args.count)} to write under "
          f"{args.output}", file=sys.stderr)
    mode = "single process" if args.single_process else (args.scheduler or f"LocalCluster({args.workers})")
    started = time.perf_counter()
    setup = 0.0
    output = dict(output_root=args.output, output_format="npy" if args.npy_shards else None,
                  shard_size=args.npy_shards or None, device=args.device)
    if args.single_process:
        # The same tasks as the workers run, one after the other in this process.
        brdfbake.lut(size=1, device=args.device)  # open the device first, as DevicePlugin does on workers
        setup = time.perf_counter() - started
        batch = bdask.bake(None, materials, kind="tabulate", layout="merl", **output)
        seconds = batch.seconds
        failed = len(batch.failed)
        for o in batch.failed:
            print(f"{o.name}: {o.error_type}: {o.error}", file=sys.stderr)
    else:
        from distributed import Client, LocalCluster

        cluster = None
        if args.scheduler:
            client = Client(args.scheduler)
        else:
            cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                                   silence_logs=logging.ERROR)
            client = Client(cluster)
        try:
            client.register_plugin(bdask.DevicePlugin(args.device))  # each worker opens its device now
            setup = time.perf_counter() - started
            resources = None
            if args.resources:
                key, _, value = args.resources.partition("=")
                resources = {key: float(value or 1)}
            batch = bdask.bake(client, materials, kind="tabulate", layout="merl", resources=resources,
                               progress=args.progress, **output)
            seconds = batch.seconds
            for o in batch.failed:
                print(f"{o.name}: {o.error_type}: {o.error}", file=sys.stderr)
            failed = len(batch.failed)
        finally:
            client.close()
            if cluster is not None:
                cluster.close()

    baked = args.count - failed
    rate = baked / seconds if seconds > 0 else float("inf")
    fmt = f".npy shards of {args.npy_shards}" if args.npy_shards else "MERL binaries"
    print(f"{baked} of {args.count} MERL tables ({fmt}) in {seconds:.1f} s on {mode}: {rate:.2f} tables/s "
          f"(start-up {setup:.1f} s not counted) -> {args.output}")
    if args.json:
        print(json.dumps({"count": args.count, "baked": baked, "failed": failed, "mode": mode, "output": fmt,
                          "seconds": round(seconds, 3), "setup_seconds": round(setup, 3),
                          "tables_per_second": round(rate, 3), "load": os.getloadavg()}))
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
