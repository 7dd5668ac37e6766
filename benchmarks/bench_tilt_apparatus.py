"""The apparatus with the tilted 3D law: one experiment of the paper (Figs. 6, 7: truncated sphere
b = 0.6 mm, R = 6 mm, k_x = 1.9 N/um, ``studies.study.LOOP_CASES``) read again with a misaligned face.

The MDR law and the 3D law (``fem.solid3d.law.FEContact3D``, contact measure, trial steps) in the same
apparatus (``mdr.apparatus.run_apparatus``, default plates, dF = 0.2 F0 as in ``studies.study.loops``):
the slip index of the aligned face and of faces tilted by multiples of theta_c = F0 / (4 E* b^2)
up to the paper's bound pi/3600, each tilt on the same mesh as the aligned face
(``FEContact3D.assuming``), at two mesh levels; ``contact vertices`` counts the vertices in contact
at F0 (half model): below 10 the contact is not resolved (``validation.families.tilt.TILT_MIN_VERTICES``).
``--band H ...`` (one per level): the loaded rim arc banded, ``FEContact3D(band=(H, width, angle,
growth))`` (sizes / b), to resolve the edge crescent at pi/3600. Run:

    python benchmarks/bench_tilt_apparatus.py [--case fig6] [--cycles 3] [--steps 80] [h ...]
    python benchmarks/bench_tilt_apparatus.py --ratios --band 0.02 0.014 -- 0.3 0.3   # pi/3600, banded meshes
"""
import argparse
import time
import warnings

import numpy as np
from mdr.loading import Loading


def main(argv=None):
    from fem.solid3d import estimators as est
    from fem.solid3d.law import FEContact3D
    from mdr.apparatus import Apparatus, run_apparatus
    from mdr.law import MDRContact
    from mdr.materials import Materials
    from mdr.profiles import TruncatedSphere
    from studies.study import LOOP_CASES, R_IND, TABLE1_B, TABLE1_KX
    from validation.families.tilt import TILT_MIN_VERTICES
    from validation.scenes import TILT_BOUND, tilt_critical

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--case", default="fig6", choices=("fig6", "fig7"))
    ap.add_argument("--cycles", type=int, default=3)
    ap.add_argument("--steps", type=int, default=80)
    ap.add_argument("--ratios", type=float, nargs="*", default=[1.0, 3.0, 10.0],
                    help="tilts as multiples of theta_c (pi/3600 is always added)")
    ap.add_argument("--band", type=float, nargs="*", default=None,
                    help="band element size / b per level (the loaded rim arc; none: no band)")
    ap.add_argument("--band-shape", type=float, nargs=3, default=[0.06, 0.45, 1.0],
                    help="the band's half width / b, half angle (rad) and growth")
    ap.add_argument("levels", type=float, nargs="*", default=[0.3, 0.2])
    args = ap.parse_args(argv)
    if args.band is not None and len(args.band) != len(args.levels):
        ap.error(f"--band needs one size per level ({len(args.levels)}), got {len(args.band)}")
    bands = [None] * len(args.levels) if args.band is None else [(h, *args.band_shape) for h in args.band]
    kind, F0, ua, mu1, mu2 = LOOP_CASES[args.case]
    assert kind == "truncated"
    mat, prof = Materials(), TruncatedSphere(R_IND, TABLE1_B)
    dF = 0.2 * F0
    app = Apparatus(kx=TABLE1_KX, mu2=mu2)
    kw = dict(dF=dF, alpha=0.0, ua=ua, cycles=args.cycles, steps=args.steps)
    thc = tilt_critical(F0, TABLE1_B, mat.E_star)
    tilts = [0.0] + [r * thc for r in args.ratios if r * thc < TILT_BOUND] + [TILT_BOUND]
    t0 = time.perf_counter()
    d_md = float(run_apparatus(MDRContact(prof, mat, mu1, F_max=F0 + dF, F_min=F0 - dF, n=400), app, Loading.apparatus(F0, **kw))["slip_index"])
    print(f"{args.case}: b = {TABLE1_B * 1e3:g} mm, F0 = {F0} N, u_A = {ua * 1e9:g} nm, mu1 = {mu1}, mu2 = {mu2}, "
          f"k_x = {TABLE1_KX / 1e6:g} N/um; theta_c = {thc:.3g} rad; {args.cycles} cycles x {args.steps} steps")
    print(f"MDR (aligned): slip index {d_md:.5f} ({time.perf_counter() - t0:.1f} s)")
    print("| h / b | band h / b | tilt (rad) | tilt / theta_c | slip index | tilted / aligned - 1 | contact vertices "
          "| resolved | evaluations per step | run (s) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for h, band in zip(args.levels, bands):
        law = FEContact3D(prof, mat, mu1, F_max=F0 + dF, h_contact=h, displacement="contact", band=band)
        d0 = None
        for th in tilts:
            lt = law.assuming(tilt=th)
            t1 = time.perf_counter()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                out = run_apparatus(lt, app, Loading.apparatus(F0, **kw))
            d = float(out["slip_index"])
            d0 = d if th == 0.0 else d0
            nv = int(est.contact_mask(lt.model, lt.normal(F_N=F0).p).sum())
            print(f"| {h:g} | {'-' if band is None else f'{band[0]:g}'} | {th:.3g} | {th / thc:.3g} | {d:.5f} | {d / d0 - 1:+.3%} | {nv} | "
                  f"{'yes' if nv >= TILT_MIN_VERTICES else 'no'} | {out['evaluations_per_step']:.2f} | "
                  f"{time.perf_counter() - t1:.1f} |", flush=True)


if __name__ == "__main__":
    main()
