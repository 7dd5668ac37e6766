"""Benchmark of the compiled MDR loops (mdr.kernels): the targets, as ratios measured in one run.

    python benchmarks/bench_mdr_kernel.py [--repeat 15]

Scene (as in benchmarks/bench_mdr.py): truncated sphere R = 6 mm, b = 20 um, steel,
mu = 0.2, F_N = 0.5 + 0.1 sin(2 pi t) N, u = 150 nm sin(2 pi t), 3 cycles x 400 steps.

1. Displacement control against a plain numpy loop over point springs (the simplest
   MDR: springs at the cell midpoints of the same breakpoint-aware grid, one clip of the
   stop operator per time step, ``plain_loop`` below). Accuracy: the dissipation of the
   last cycle against the same method with 16000 springs (cells) on the same time steps;
   each method at the smallest size of its list with an error <= 2e-6 (target: the
   compiled law at least 2x faster), and at the sizes named in the README.
2. Force control (F_x = 0.06 sin, same F_N) against displacement control (target: within 3x).
3. One apparatus scene at the study resolution (``studies.study.RES``; target < 20 ms) and the
   Fig. 8 + Fig. 9 studies (target < 1 s of compute).
4. Import and first-call cost in a fresh interpreter, with an empty numba cache (compiles)
   and with the cache filled by that first run.
The step-API path (``mdr.kernels.ENABLED = False``, what runs without numba) is timed beside.
Timings are medians; compare ratios, not absolute numbers (the machine is shared).
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # run from a checkout without installing

from bench_mdr import median_time  # noqa: E402  (this directory is on sys.path when run as a script)
from mdr import Materials, MDRContact, TruncatedSphere, kernels  # noqa: E402
from mdr.grid import make_grid  # noqa: E402
from mdr.loops import loop_integral  # noqa: E402
from mdr.normal import approach_from_force  # noqa: E402
from studies.study import R_IND, _slip_index, fig8, fig9  # noqa: E402

MAT = Materials()
MU, STEPS = 0.2, 400
PROF = TruncatedSphere(6e-3, 20e-6)
T = np.arange(3 * STEPS + 1) / STEPS
FN = 0.5 + 0.1 * np.sin(2 * np.pi * T)
U = 150e-9 * np.sin(2 * np.pi * T)
FX = 0.06 * np.sin(2 * np.pi * T)


def plain_loop(n, u=U, F_N=FN, prof=PROF, mat=MAT, mu=MU):
    """The simplest MDR in numpy: n point springs at the cell midpoints of a grid with nodes
    at the flat-face edge b and at the smallest and largest contact radius; each time step
    one clip of the stop operator v <- clip(v + du, -v_max, v_max), with the slip limit
    v_max = mu E* (d - g(x))_+ / G* of the step's approach d (0 out of contact: released)."""
    a_max = prof.g_inv(approach_from_force(prof, mat, np.max(F_N)))
    a_min = prof.g_inv(approach_from_force(prof, mat, np.min(F_N)))
    grid = make_grid(prof, a_max, n=n, a_min=a_min)
    x, w = grid.mid, grid.width
    d = approach_from_force(prof, mat, F_N)
    g = prof.g(x)
    k = 2.0 * mat.G_star * w          # both halves x < 0 and x > 0
    c = mu * mat.E_star / mat.G_star
    v = np.zeros(n)
    Fx = np.empty(u.size)
    u_prev = 0.0
    for i in range(u.size):
        vmax = np.maximum(d[i] - g, 0.0) * c
        v = np.clip(v + (u[i] - u_prev), -vmax, vmax)
        Fx[i] = k @ v
        u_prev = u[i]
    return Fx


def dissipation(Fx, u=U):
    return loop_integral(u[2 * STEPS:], Fx[2 * STEPS:])


def law(n):
    return MDRContact(PROF, MAT, MU, F_max=0.6, F_min=0.4, n=n)


def step_api(fn, repeat):
    """fn timed through the step API (the path without numba)."""
    kernels.ENABLED = False
    try:
        return median_time(fn, repeat)
    finally:
        kernels.ENABLED = True


COLD = """
import time
t0 = time.perf_counter()
import numpy as np
from mdr import Materials, MDRContact, TruncatedSphere
from mdr.apparatus import Apparatus, run_apparatus
from mdr.loading import Loading
t1 = time.perf_counter()
t = np.arange(1201) / 400
law = MDRContact(TruncatedSphere(6e-3, 20e-6), Materials(), 0.2, F_max=0.6, F_min=0.4)
law.run(u=150e-9 * np.sin(2 * np.pi * t), F_N=0.5 + 0.1 * np.sin(2 * np.pi * t))
law.run(Fx=0.06 * np.sin(2 * np.pi * t), F_N=0.5)
run_apparatus(MDRContact(TruncatedSphere(6e-3, 50e-6), Materials(), 0.2, F_max=0.6, F_min=0.4, n=100),
              Apparatus(kx=2e6), Loading.apparatus(0.5, 0.1, 0.0, 150e-9, cycles=3, steps=120))
t2 = time.perf_counter()
print(f"{t1 - t0:.3f} {t2 - t1:.3f}")
"""


def first_call_costs():
    """(import s, first calls s) with an empty numba cache, then with the cache filled."""
    out = []
    with tempfile.TemporaryDirectory(prefix="numba-cache-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, PYTHONPATH=str(ROOT))
        for _ in range(2):
            res = subprocess.run([sys.executable, "-c", COLD], env=env, capture_output=True, text=True, check=True)
            out.append(tuple(float(v) for v in res.stdout.split()))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=15)
    args = ap.parse_args(argv)
    rep = args.repeat
    if not kernels.enabled():
        sys.exit("numba is not installed (pip install .[fast]): nothing compiled to benchmark")
    (imp_cold, call_cold), (imp_warm, call_warm) = first_call_costs()
    print(f"fresh interpreter: import {imp_cold:.2f} s, first calls (run u, run Fx, apparatus) {call_cold:.2f} s "
          f"with an empty numba cache (compiling); import {imp_warm:.2f} s, first calls {call_warm:.2f} s cached")

    # 1. displacement control at equal accuracy
    W_law = dissipation(law(16000).run(u=U, F_N=FN).Fx)
    W_plain = dissipation(plain_loop(16000))
    print(f"\n1. displacement control, dW of the last cycle against 16000 springs/cells on the same steps "
          f"(the two references differ by {W_plain / W_law - 1:.1e}: time discretisation)")
    print(f"{'method':>28} {'size':>6} {'dW error':>10} {'ms':>8}")
    rows = {}
    for n in (50, 100, 200, 400):
        lw = law(n)
        err = dissipation(lw.run(u=U, F_N=FN).Fx) / W_law - 1
        rows["law", n] = (err, median_time(lambda: lw.run(u=U, F_N=FN), rep))
    for n in (250, 500, 1000, 2000):
        err = dissipation(plain_loop(n)) / W_plain - 1
        rows["plain", n] = (err, median_time(lambda: plain_loop(n), max(3, rep // 3)))
    for (kind, n), (err, tm) in rows.items():
        name = "MDRContact.run (compiled)" if kind == "law" else "plain numpy loop"
        print(f"{name:>28} {n:>6} {err:>10.1e} {tm * 1e3:>8.2f}")
    t_py = step_api(lambda: law(400).run(u=U, F_N=FN), max(3, rep // 3))
    print(f"{'MDRContact.run (step API)':>28} {400:>6} {rows['law', 400][0]:>10.1e} {t_py * 1e3:>8.2f}")
    ok = lambda kind: min(n for (k, n), (e, _) in rows.items() if k == kind and abs(e) <= 2e-6)  # noqa: E731
    n_law, n_plain = ok("law"), ok("plain")
    t_disp = rows["law", n_law][1]
    print(f"   at |dW error| <= 2e-6: compiled law ({n_law} cells) {rows['plain', n_plain][1] / t_disp:.1f}x faster "
          f"than the plain loop ({n_plain} springs) (target >= 2x); default 400 cells against 250 springs: "
          f"{rows['plain', 250][1] / rows['law', 400][1]:.1f}x")

    # 2. force control
    l400 = law(400)
    t_u = median_time(lambda: l400.run(u=U, F_N=FN), rep)
    t_f = median_time(lambda: l400.run(Fx=FX, F_N=FN), rep)
    t_f_py = step_api(lambda: l400.run(Fx=FX, F_N=FN), 3)
    print(f"\n2. force control (400 cells): {t_f * 1e3:.2f} ms = {t_f / t_u:.2f} x displacement control "
          f"({t_u * 1e3:.2f} ms; target <= 3x); step API {t_f_py * 1e3:.0f} ms ({t_f_py / t_f:.0f}x slower)")

    # 3. apparatus and studies
    scene = lambda: _slip_index(TruncatedSphere(R_IND, 50e-6), 2e6)  # noqa: E731
    t_app = median_time(scene, rep)
    t_app_py = step_api(scene, 3)
    print(f"\n3. apparatus, one scene at the study resolution (3 cycles x 120 steps, 100 cells, truncated "
          f"b = 50 um, k_x = 2 N/um): {t_app * 1e3:.1f} ms (target < 20 ms); step API {t_app_py * 1e3:.0f} ms")
    fig8(), fig9()
    t_figs = median_time(lambda: (fig8(), fig9()), max(3, rep // 3))
    print(f"   Fig. 8 + Fig. 9 (290 scenes): {t_figs:.2f} s (target < 1 s) = {t_figs / t_app:.0f} single-scene times")


if __name__ == "__main__":
    main()
