"""Benchmark of the paper's parameter studies (Willert, Machines 11 (2023) 484, Figs. 8-9).

    python benchmarks/bench_studies.py [--repeat 5]

Times (medians of repeated runs, no file output):
- the full Fig. 8 + Fig. 9 studies (all points, stationary cycles, as ``studies.study``
  runs them: one batch pass per study and kind of profile),
- one single scene at the same resolution (truncated sphere b = 50 um, k_x = 2 N/um,
  Table 2 load),
- the sensitivity study (``python -m mdr study sensitivity``).
Prints the number of scenes and the study time as a multiple of the single-scene
time. Compare ratios, not absolute numbers: the machine is shared and noisy.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # run from a checkout without installing

from mdr.profiles import TruncatedSphere
from studies.study import R_IND, _slip_index, fig8, fig9, run_studies, sensitivity


def median_time(fn, repeat):
    ts, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts)), out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)

    t_single, _ = median_time(lambda: _slip_index(TruncatedSphere(R_IND, 50e-6), 2e6), args.repeat)
    t_f8, rows8 = median_time(fig8, args.repeat)
    t_f9, rows9 = median_time(fig9, args.repeat)
    t_sens, rows_s = median_time(sensitivity, args.repeat)
    # fig8 runs every point twice (truncated sphere and the flat punch beside it)
    n8, n9, ns = 2 * len(rows8), len(rows9), len(rows_s)
    n, t = n8 + n9, t_f8 + t_f9
    print(f"single scene (3 cycles x 120 steps, 100 cells): {t_single * 1e3:.0f} ms")
    print(f"fig8: {n8} scenes in {t_f8:.2f} s; fig9: {n9} scenes in {t_f9:.2f} s")
    print(f"fig8 + fig9: {n} scenes in {t:.2f} s = {t / t_single:.1f} single-scene times "
          f"(scene by scene: {n} single-scene times; batch speed-up {n * t_single / t:.1f}x)")
    print(f"sensitivity: {ns} scenes in {t_sens:.2f} s = {t_sens / t_single:.1f} single-scene times")
    # the command as a user runs it: python -m mdr study fig8,fig9 --jobs 2 (files written, spawned workers)
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        t_par, _ = median_time(lambda: run_studies(["fig8", "fig9"], tmp, jobs=2), args.repeat)
        t_seq, _ = median_time(lambda: run_studies(["fig8", "fig9"], tmp, jobs=1), args.repeat)
    print(f"python -m mdr study fig8,fig9 (CSV + PNG): {t_seq:.2f} s in one process, {t_par:.2f} s with --jobs 2 "
          f"= {t_par / t_single:.1f} single-scene times")


if __name__ == "__main__":
    main()
