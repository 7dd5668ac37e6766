"""Speed against error of the FE frictional contact (sphere, steel/steel, constant F_N).

    python benchmarks/bench_fem_contact.py [--levels 20,40,80] [--steps 100] [--json PATH]

Per refinement level h = a/N: DOFs (mode 0 + mode 1, both bodies), pairs, set-up
time (mesh from cache + assembly + factorisation + condensation of both modes),
time of one stationary force-controlled cycle (``--steps`` steps, after one cycle
from rest), steps/s, Newton (active-set) iterations and augmented-Lagrangian
passes per step, and the errors of the stationary dissipation against
Mindlin-Deresiewicz and of the stick radius at the force peak against
Cattaneo-Mindlin. Force amplitude: u_A = u*/2 (partial slip).
Goals (issue 5): at a/80 one cycle of >= 100 steps under 1 s after a set-up under
3 s, dissipation error under 0.2 %. Timings are measured here, never asserted in tests.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fem.axisym.law import FEContact  # noqa: E402
from common.io import write_json  # noqa: E402
from mdr.loops import loop_integral  # noqa: E402
from mdr.materials import Materials  # noqa: E402
from mdr.profiles import make_profile  # noqa: E402
from mdr.reference import (cattaneo_mindlin_force, cattaneo_mindlin_stick_radius,  # noqa: E402
                           gross_slip_displacement, hertz, mindlin_deresiewicz_dissipation_force)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--levels", default="20,40,80", help="N of h = a/N, comma separated")
    ap.add_argument("--steps", type=int, default=100, help="steps per cycle")
    ap.add_argument("--R", type=float, default=6e-3)
    ap.add_argument("--F", type=float, default=0.5)
    ap.add_argument("--mu", type=float, default=0.2)
    ap.add_argument("--penalty", type=float, default=100.0)
    ap.add_argument("--friction-al-tol", type=float, default=1e-7)
    ap.add_argument("--solver", default="auto")
    ap.add_argument("--cache-dir", default=None, help="mesh cache (default: a fresh temporary directory, "
                                                      "meshed once before timing)")
    ap.add_argument("--json", default=None)
    args = ap.parse_args(argv)
    mats = Materials()
    F, mu, n = args.F, args.mu, args.steps
    h = hertz(F, args.R, mats.E_star)
    us = gross_slip_displacement(h["d"], mu, mats.E_star, mats.G_star)
    FA = float(cattaneo_mindlin_force(0.5 * us, F, mu, us))
    ref_dW = mindlin_deresiewicz_dissipation_force(FA, F, mu, us)
    ref_c = float(cattaneo_mindlin_stick_radius(FA, F, mu, h["a"]))
    prof = make_profile("sphere", args.R)
    cache = args.cache_dir or tempfile.mkdtemp(prefix="bench_fem_contact_")
    backend = None if args.solver == "auto" else args.solver
    rows = []
    t = np.arange(2 * n + 1) / n
    fx = FA * np.sin(2 * np.pi * t)
    for N in (int(x) for x in args.levels.split(",")):
        kw = dict(F_max=F, h_contact=1.0 / N, cache_dir=cache, penalty=args.penalty,
                  friction_al_tol=args.friction_al_tol, backend=backend)
        FEContact(prof, mats, mu, **kw)  # mesh into the cache (gmsh time is not set-up time)
        t0 = time.perf_counter()
        law = FEContact(prof, mats, mu, **kw)
        law.normal(F_N=F)
        t_setup = time.perf_counter() - t0
        H1 = law.run(Fx=fx[: n + 1], F_N=np.full(n + 1, F))
        law.stats.update(steps=0, newton=0, al=0)
        t0 = time.perf_counter()
        H2 = law.run(Fx=fx[n:], F_N=np.full(n + 1, F), state=H1.state)
        t_cycle = time.perf_counter() - t0
        dW = abs(loop_integral(H2.u, H2.Fx))
        c_peak = float(H2.c[n // 4])
        st = law.stats
        rows.append({"N": N, "dofs": law.dofs, "pairs": law.n_pairs, "setup_s": t_setup, "cycle_s": t_cycle,
                     "steps_per_s": n / t_cycle, "newton_per_step": st["newton"] / st["steps"],
                     "al_per_step": st["al"] / st["steps"], "dissipation_error": dW / ref_dW - 1,
                     "work_error": float(np.sum(H2.work[1:])) / ref_dW - 1,
                     "stick_radius_error": c_peak / ref_c - 1, "backend": law.model.backend})
    print(f"FE frictional contact, sphere R={args.R:g} m, F_N={F:g} N, mu={mu:g}, F_A={FA:.4g} N "
          f"(u_A = u*/2), {n} steps/cycle, penalty {args.penalty:g}, friction AL tol {args.friction_al_tol:g}")
    print("| h | DOFs | pairs | set-up s | cycle s | steps/s | Newton/step | AL/step | dW err | work err | c err |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| a/{r['N']} | {r['dofs']} | {r['pairs']} | {r['setup_s']:.2f} | {r['cycle_s']:.3f} | "
              f"{r['steps_per_s']:.0f} | {r['newton_per_step']:.2f} | {r['al_per_step']:.2f} | "
              f"{100 * r['dissipation_error']:+.3f} % | {100 * r['work_error']:+.3f} % | "
              f"{100 * r['stick_radius_error']:+.2f} % |")
    if args.json:
        write_json(args.json, {"rows": rows, "inputs": vars(args)})
    return 0


if __name__ == "__main__":
    sys.exit(main())
