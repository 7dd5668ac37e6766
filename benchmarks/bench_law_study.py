"""Benchmark: the FE-backed studies of Figs. 8 and 9 (``python -m mdr study fig8,fig9 --law fem``).

    python benchmarks/bench_law_study.py [--h-contact 0.1] [--points 5] [--levels 2] [--jobs 2]
                                          [--repeat 5] [--point-only]

Times, in one run (files into a temporary directory):

- the MDR-only studies fig8 + fig9 (``python -m mdr study fig8,fig9``, one process),
- one FE apparatus scene as ``python -m mdr apparatus --law fem`` runs it at the study
  resolution (truncated sphere b = 50 um, k_x = 2 N/um, Table 2 load, 3 cycles x 120
  steps, set-up included),
- the CPU time of one apparatus point on a built FE law with and without the plugin's
  ``session()`` (one BLAS thread for the whole block instead of entering it at every step),
- the CPU time of one apparatus point inside the session (median of ``--repeat`` runs; the
  number to compare between commits) and where it goes: the FE contact law (``prepare``,
  the trials' ``force`` and ``commit``), the MDR bedding law, and the rest (the apparatus
  loop, its Newton iteration, the cycle analysis); with the force evaluations per step and
  the FE law's return-map solves, active-set iterations and augmented-Lagrangian passes,
- the FE-backed fig8 + fig9 at ``--points`` points per curve on ``--levels`` mesh levels
  (``--jobs`` processes, or ``--scheduler ADDRESS``),

(skipped with ``--point-only``) and prints the FE-backed time, its ratio to the MDR studies and to the one FE scene, the
number of FE apparatus runs and the largest FE own error on delta. Compare ratios, not
absolute numbers: the machine is shared and noisy.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # run from a checkout without installing

from studies.cli import build_parser
from fem.cli import FE_LAW
from studies.study import R_IND, RES, TABLE2, run_studies
from mdr.loading import Loading


class _Timed:
    """A contact law (or its trial) whose method calls add their CPU time to ``clock[name]``."""

    def __init__(self, inner, clock, name):
        self._inner, self._clock, self._name = inner, clock, name

    def __getattr__(self, attr):
        value = getattr(self._inner, attr)
        if attr not in ("prepare", "force", "commit", "approach"):
            return value

        def timed(*a, **kw):
            c0 = time.process_time()
            out = value(*a, **kw)
            self._clock[self._name] += time.process_time() - c0
            return _Timed(out, self._clock, self._name) if attr == "prepare" else out
        return timed


def point_breakdown(law, app, repeat):
    """CPU time of one apparatus point (median of ``repeat`` runs, inside the plugin's session)
    and its split {fe, bedding, rest} (s, from the median run), with the solver counters."""
    from mdr.apparatus import _mdr_bedding, run_apparatus

    runs = []
    for _ in range(repeat):
        clock = {"fe": 0.0, "bedding": 0.0}
        bed = lambda *a: _Timed(_mdr_bedding(*a), clock, "bedding")  # noqa: E731
        n0 = dict(law.stats)
        c0 = time.process_time()
        out = run_apparatus(_Timed(law, clock, "fe"), app, Loading.apparatus(TABLE2["F0"], dF=TABLE2["dF"], alpha=0.0, ua=TABLE2["ua"], cycles=RES["cycles"], steps=RES["steps"]), bed_law_factory=bed)
        total = time.process_time() - c0
        counts = {k: law.stats[k] - n0[k] for k in ("steps", "trial_solves", "newton", "al")}
        runs.append((total, dict(clock, rest=total - clock["fe"] - clock["bedding"]), counts, out))
    runs.sort(key=lambda r: r[0])
    return runs[len(runs) // 2]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--h-contact", type=float, default=0.1)
    ap.add_argument("--points", type=int, default=5)
    ap.add_argument("--levels", type=int, default=2)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--scheduler", default=None)
    ap.add_argument("--repeat", type=int, default=5, help="runs of the one-point CPU time (median)")
    ap.add_argument("--point-only", action="store_true", help="only the one-point CPU time and its split")
    args = ap.parse_args(argv)
    warnings.filterwarnings("ignore", message="coarse contact mesh")
    from mdr.apparatus import Apparatus
    from mdr.materials import Materials
    from mdr.profiles import TruncatedSphere

    fe = FE_LAW
    law_args = build_parser().parse_args(["study", "fig8", "--law", "fem", "--h-contact", str(args.h_contact)])
    # one apparatus point on a built law: CPU time and where it goes
    law = fe.make_law(TruncatedSphere(R_IND, 50e-6), Materials(), TABLE2["mu1"], TABLE2["F0"] + TABLE2["dF"],
                      law_args)
    with fe.session():
        total, split, counts, pout = point_breakdown(law, Apparatus(kx=2e6, mu2=TABLE2["mu2"]), args.repeat)
    tr = max(counts["trial_solves"], 1)
    print(f"one FE apparatus point (b = 50 um, k_x = 2 N/um, a/{1 / args.h_contact:g}, {law.n_pairs} pairs, "
          f"{counts['steps']} steps), CPU time in the session, median of {args.repeat}: {total:.3f} s, "
          f"delta = {float(pout['slip_index']):.10f}")
    print("  split: " + ", ".join(f"{k} {v:.3f} s ({v / total:.0%})" for k, v in
                                  (("FE contact law", split["fe"]), ("MDR bedding law", split["bedding"]),
                                   ("apparatus loop and Newton", split["rest"]))))
    print(f"  {pout['evaluations_per_step']:.2f} force evaluations per step; FE law: "
          f"{counts['trial_solves'] / max(counts['steps'], 1):.2f} return-map solves per step, "
          f"{counts['newton'] / tr:.2f} active-set iterations and {counts['al'] / tr:.2f} "
          f"augmented-Lagrangian passes per solve")
    if args.point_only:
        return
    with tempfile.TemporaryDirectory(prefix="bench-law-study-") as tmp:
        t0 = time.perf_counter()
        run_studies(["fig8", "fig9"], tmp)
        t_mdr = time.perf_counter() - t0
        t0 = time.perf_counter()
        one = fe.apparatus_result(TruncatedSphere(R_IND, 50e-6), Materials(), Apparatus(kx=2e6, mu2=TABLE2["mu2"]),
                                  TABLE2["mu1"], Loading.apparatus(TABLE2["F0"], TABLE2["dF"], 0.0, TABLE2["ua"],
                                                                   cycles=RES["cycles"], steps=RES["steps"]), law_args)
        t_one = time.perf_counter() - t0
        # the same point with and without the plugin's session (one BLAS thread)
        import contextlib

        from mdr.apparatus import run_apparatus

        cpu = {}
        for name, ctx in (("without", contextlib.nullcontext), ("with", fe.session)):
            c0 = time.process_time()
            with ctx():
                run_apparatus(law, Apparatus(kx=2e6, mu2=TABLE2["mu2"]), Loading.apparatus(TABLE2["F0"], dF=TABLE2["dF"], alpha=0.0, ua=TABLE2["ua"], cycles=RES["cycles"], steps=RES["steps"]))
            cpu[name] = time.process_time() - c0
        t0 = time.perf_counter()
        out = run_studies(["fig8", "fig9"], tmp, jobs=1 if args.scheduler else args.jobs, scheduler=args.scheduler,
                          law="fem", plugin=fe, law_args=law_args, points=args.points, levels=args.levels)
        t_fem = time.perf_counter() - t0
    runs = sum(t["points"] for s in out for t in s["tasks"])
    rows = [r for s in out for r in s["rows"]]
    setup = sum(t["setup_s"] for s in out for t in s["tasks"])
    busy = sum(t["runtime_s"] for s in out for t in s["tasks"])
    print(f"MDR-only fig8 + fig9 (all points):          {t_mdr:7.2f} s")
    print(f"one FE apparatus scene (b = 50 um, a/{1 / args.h_contact:g}): {t_one:7.2f} s "
          f"(set-up {one['runtime_s']['setup']:.2f} s), delta = {one['slip_index']:.4f}")
    print(f"one FE apparatus point, CPU time: {cpu['without']:.2f} s without the plugin session, "
          f"{cpu['with']:.2f} s with it (one BLAS thread for the block)")
    print(f"FE-backed fig8 + fig9: {len(rows)} points x {args.levels} levels = {runs} FE apparatus runs, "
          f"{out[0]['executor']}: {t_fem:7.2f} s (task time {busy:.0f} s of which set-up {setup:.0f} s)")
    print(f"  ratio to the MDR-only studies {t_fem / t_mdr:.0f}, to one FE scene {t_fem / t_one:.1f}; "
          f"largest FE own error on delta {max(r['fem_error'] for r in rows):.2g}, "
          f"largest |FE - MDR| {max(abs(r['difference']) for r in rows):.2g}")


if __name__ == "__main__":
    main()
