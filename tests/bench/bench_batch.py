#!/usr/bin/env python3
"""Frames per second of mereo.batch against the number of Dask workers, and what would limit it
past one machine (the scheduler's overhead per task, the bytes sent back per frame).

    python tests/bench/bench_batch.py [--sequences 4] [--frames 10] [--workers 1 2]

The anchor is one process without Dask (mereo.batch.recognize with no client: the same tasks in
order). Frames are rendered orbits (synthetic:SEED, tracked within each sequence); each task reads
its own frames, so only the input's name goes to a worker and only the JSON results come back.
"""
from __future__ import annotations

import argparse
import json
import sys
import time


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sequences", type=int, default=4)
    ap.add_argument("--frames", type=int, default=10)
    ap.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    args = ap.parse_args(argv)
    from dask.distributed import Client, LocalCluster

    from mereo import batch

    inputs = [f"synthetic:{300 + k}" for k in range(args.sequences)]
    n = args.sequences * args.frames
    t = time.perf_counter()
    one = batch.recognize(inputs, frames=args.frames, progress=False)
    base = n / (time.perf_counter() - t)
    bytes_per_frame = sum(len(json.dumps(r)) for r in one) / n
    print(f"{n} frames in {args.sequences} sequences; results {bytes_per_frame / 1024:.1f} KiB per frame (JSON)")
    print(f"{'run':<28} {'frames/s':>9} {'vs one process':>15}")
    print(f"{'one process (anchor)':<28} {base:9.2f} {1.0:15.2f}")
    for w in args.workers:
        with LocalCluster(n_workers=w, threads_per_worker=1, processes=True, dashboard_address=None) as cl, \
                Client(cl) as client:
            client.submit(lambda: 0).result()  # workers up
            t = time.perf_counter()
            many = batch.recognize(inputs, client=client, frames=args.frames, progress=False)
            fps = n / (time.perf_counter() - t)
            same = [{k: v for k, v in r.items() if k != "timing_ms"} for r in many] == \
                   [{k: v for k, v in r.items() if k != "timing_ms"} for r in one]
            print(f"{f'Dask, {w} worker(s)':<28} {fps:9.2f} {fps / base:15.2f}   same results: {same}")
            if w == args.workers[-1]:
                # the scheduler's cost per task: round trips of empty tasks
                t = time.perf_counter()
                client.gather(client.map(lambda x: x, range(200), pure=False))
                per_task = (time.perf_counter() - t) / 200 * 1000
                print(f"scheduler overhead: {per_task:.2f} ms per task ({w} worker(s)); "
                      f"a task here is a sequence of {args.frames} frames, {args.frames / base * 1000:.0f} ms of work")
    return 0


if __name__ == "__main__":
    sys.exit(main())
