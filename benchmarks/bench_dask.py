"""Benchmark: validation.compare on a Dask LocalCluster of 2 worker processes against --jobs 2.

    python benchmarks/bench_dask.py [--scenes sphere-md,geom-flat,...] [--repeat 3]

Runs the quick ladders of the given scenes (default: the ``--quick`` subset) with
``--force --no-fields --no-hard-cases`` into a temporary directory, alternating

- ``--jobs 2`` (a ProcessPoolExecutor of 2 spawned processes, started by the command), and
- ``--scheduler ADDRESS`` of a ``LocalCluster(n_workers=2, threads_per_worker=1,
  processes=True)`` started once before (as a user's running cluster; its start-up time
  is printed separately),

and prints the median wall time of each and their ratio (Dask / jobs). Serial
(``--jobs 1``) is timed once for scale. Compare ratios, not absolute numbers: the
machine is shared and noisy. Needs the ``dist`` extra.
"""
from __future__ import annotations

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # run from a checkout without installing

from validation import compare
from validation.catalogue import CATALOGUE


def timed(argv):
    t0 = time.perf_counter()
    rc = compare.main(argv)
    if rc != 0:
        raise SystemExit(f"compare {' '.join(argv)} failed with exit code {rc}")
    return time.perf_counter() - t0


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scenes", default=",".join(s.name for s in CATALOGUE.values() if s.quick))
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    from distributed import LocalCluster

    base = ["--quick", "--scenes", args.scenes, "--force", "--no-fields", "--no-hard-cases"]
    with tempfile.TemporaryDirectory(prefix="bench-dask-") as tmp:
        out = lambda tag: ["--out", os.path.join(tmp, tag)]  # noqa: E731
        timed(base + ["--jobs", "2"] + out("warm"))  # meshes into the cache, files into the page cache
        t_serial = timed(base + out("serial"))
        t0 = time.perf_counter()
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
            t_start = time.perf_counter() - t0
            t_jobs, t_dask = [], []
            for _ in range(args.repeat):
                t_jobs.append(timed(base + ["--jobs", "2"] + out("jobs")))
                t_dask.append(timed(base + ["--scheduler", cluster.scheduler_address] + out("dask")))
    mj, md = statistics.median(t_jobs), statistics.median(t_dask)
    n = len(args.scenes.split(","))
    print(f"\n{n} scenes (quick ladders, no field plots), medians of {args.repeat} alternating runs, "
          f"{os.cpu_count()} cores:")
    print(f"  serial (--jobs 1, once)         {t_serial:7.1f} s")
    print(f"  --jobs 2                        {mj:7.1f} s   (runs: {', '.join(f'{t:.1f}' for t in t_jobs)})")
    print(f"  --scheduler (LocalCluster 2x1)  {md:7.1f} s   (runs: {', '.join(f'{t:.1f}' for t in t_dask)})")
    print(f"  LocalCluster start-up           {t_start:7.1f} s (once)")
    print(f"  ratio Dask / --jobs 2: {md / mj:.2f}; --jobs 2 speed-up over serial {t_serial / mj:.2f}, "
          f"Dask {t_serial / md:.2f}")


if __name__ == "__main__":
    main()
