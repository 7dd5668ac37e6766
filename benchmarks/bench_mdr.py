"""Benchmark of the MDR contact law: speed against error (medians of repeated runs).

    python benchmarks/bench_mdr.py [--repeat 15]

Reports, in one run on this machine:
- speed against error of the tangential law by grid size (sphere, Mindlin-Deresiewicz
  partial slip at constant load, closed-form dissipation; truncated sphere b = 20 um with
  dF = 0.1 N against a 16x finer grid),
- steps per second, time of one stationary cycle and of three cycles of 400 steps,
- a batch: one call over S scenes against S single-scene runs (with numba the compiled
  loop runs the scenes one by one, so about S single-scene times; ``bench_mdr_kernel.py``
  has the compiled loop against a plain numpy loop and the step API).
Timings are medians; compare ratios, not absolute numbers (machines are noisy).
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from mdr import Materials, MDRContact, Sphere, TruncatedSphere
from mdr import reference as ref
from mdr.loops import loop_integral


def median_time(fn, repeat):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=15)
    args = ap.parse_args(argv)
    mat = Materials()
    R, F0, mu, steps = 6e-3, 0.5, 0.2, 400
    h = ref.hertz(F0, R, mat.E_star)
    us = ref.gross_slip_displacement(h["d"], mu, mat.E_star, mat.G_star)
    uA = 0.5 * us
    t = np.arange(3 * steps + 1) / steps
    u = uA * np.sin(2 * np.pi * t)
    FN = np.full(t.size, F0)
    W_ref = ref.mindlin_deresiewicz_dissipation(uA, F0, mu, us)
    FNv = F0 + 0.1 * np.sin(2 * np.pi * t)
    trunc = TruncatedSphere(R, 20e-6)

    def trunc_W(n):
        law = MDRContact(trunc, mat, mu, F_max=0.6, F_min=0.4, n=n)
        H = law.run(u=12e-9 * np.sin(2 * np.pi * t), F_N=FNv)
        return loop_integral(H.u[2 * steps:], H.Fx[2 * steps:]), law

    W_fine, _ = trunc_W(6400)
    print("speed against error (3 cycles x 400 steps, medians)")
    print(f"{'cells':>6} {'sphere dW err':>14} {'|Fx-CM|/muF':>12} {'3 cycles ms':>12} {'steps/s':>10}"
          f" {'trunc dW err':>13} {'trunc ms':>9}")
    for n in (50, 100, 200, 400, 800, 1600):
        law = MDRContact(Sphere(R), mat, mu, F_max=F0, n=n)
        H = law.run(u=u, F_N=FN)
        err = loop_integral(H.u[2 * steps:], H.Fx[2 * steps:]) / W_ref - 1
        k = slice(0, steps // 4 + 1)
        eFx = np.max(np.abs(H.Fx[k] - ref.cattaneo_mindlin_force(u[k], F0, mu, us))) / (mu * F0)
        tm = median_time(lambda: law.run(u=u, F_N=FN), args.repeat)
        Wt, lawt = trunc_W(n)
        tt = median_time(lambda: lawt.run(u=12e-9 * np.sin(2 * np.pi * t), F_N=FNv), max(3, args.repeat // 3))
        print(f"{n:>6} {err:>14.2e} {eFx:>12.2e} {tm * 1e3:>12.2f} {t.size / tm:>10.0f} {Wt / W_fine - 1:>13.2e} {tt * 1e3:>9.2f}")

    law = MDRContact(Sphere(R), mat, mu, F_max=F0)
    one = median_time(lambda: law.run(u=u[: steps + 1], F_N=FN[: steps + 1]), args.repeat)
    three = median_time(lambda: law.run(u=u, F_N=FN), args.repeat)
    print(f"\ndefault grid ({law.grid.n} cells): one cycle of {steps} steps {one * 1e3:.2f} ms, "
          f"three cycles {three * 1e3:.2f} ms (target < 20 ms)")

    S = 200
    Rs = np.full(S, R)
    bs = np.geomspace(1e-6, 1e-3, S)
    batch = MDRContact(TruncatedSphere(Rs, bs), mat, mu, F_max=0.6, F_min=0.4)
    Ub = np.broadcast_to(150e-9 * np.sin(2 * np.pi * t), (S, t.size))
    FNb = np.broadcast_to(FNv, (S, t.size))
    tb = median_time(lambda: batch.run(u=Ub, F_N=FNb), 3)
    single = MDRContact(TruncatedSphere(R, 20e-6), mat, mu, F_max=0.6, F_min=0.4)
    ts = median_time(lambda: single.run(u=Ub[0], F_N=FNv), args.repeat)
    print(f"batch of {S} truncated spheres (b = 1 um..1 mm, dF = 0.1 N): {tb:.3f} s in one pass = "
          f"{tb / ts:.1f} single-scene times")


if __name__ == "__main__":
    main()
