"""The 3D sphere's dissipation and the effect of the traction direction over an ensemble of ring
meshes (issue 13): the error a single unstructured mesh cannot show.

Why: on graded ring meshes (``FEContact3D(ring=)``) the 3D dissipation is within 0.45 % of
Mindlin & Deresiewicz from a/7 on, but the ladder is not monotone (the stick and contact edges
cross the vertices of an unstructured mesh, so each mesh carries its own quantisation error of
a few 0.1 %). A structured, edge-aligned (polar) annulus does not remove it: the whole vertex
ring at the stick edge switches at once, and the dissipation follows which ring the stick zone
ends on at the load reversal (measured: 0.993, 0.984, 0.996 of Mindlin-Deresiewicz at radial
sizes a/20, a/28, a/40, the stick edge on a ring at 1.008, 0.990, 1.008 of Cattaneo-Mindlin).
So every level here is an ensemble of meshes of the same resolution whose ring circle r = R
varies (0.88-0.92 a; the refined annulus R -+ 0.18 a always covers the slip zone 0.79-1 a): the
ensemble mean and its standard error, and the ladder of the means
(``common.ladder.ladder_error``).

Each member runs the sphere twice on its mesh (``FEContact3D.assuming``): the tangential traction
of free direction and along x (Mindlin's assumption, as MDR), so the paired difference measures
what the direction costs, against the half-space boundary-element solution without Mindlin's
approximation (an independent boundary-element ladder: dissipation -0.43 +- 0.01 %, the stick zone
unchanged within 0.02 %). The stick zone is read three ways:
the stick set's axes (``stick_axis_x/y``: one vertex at a time; over an ensemble the mean of a
quantised estimator is dithered), the ray radii, and the ellipse fitted to the slack
(``stick_fit_x/y``: continuous in the solution; on the runs along x it is compared with
Cattaneo-Mindlin, the exact half-space answer under Mindlin's assumption).

Sphere R = 6 mm, identical steel bodies, F_N = 0.5 N, mu = 0.2, force amplitude mu F_N / 2, 3 cycles
of 100 steps (the loading of ``bench_fem3d_contact.py``). Run:

    python benchmarks/bench_fem3d_ensemble.py [--steps 100] [--radii R ...] [-- h ...]

(h: the coarse size / a, the ring at h / 2; default 0.2 0.14 0.12 0.1; --radii default 0.88 0.89 0.9
0.91 0.92; one member's pair of runs took 16-22, 37-46, 58-64 and 138-159 s on one core,
OMP_NUM_THREADS=1, so the default about 25 min.)
"""
import argparse
import json
import time

import numpy as np
from bench_fem3d_contact import F0, MU, R, md_references  # the same loading and closed forms
from mdr.loading import Loading

RING_WIDTH = 0.18


def member(h, ring_r, steps):
    """One mesh of the ensemble: the free and the x-traction runs on it."""
    from fem.contact_run import drive_3d
    from fem.solid3d.law import FEContact3D
    from mdr.materials import Materials
    from mdr.profiles import Sphere

    law = FEContact3D(Sphere(R), Materials(), MU, F_max=F0, h_contact=h, ring=(ring_r, RING_WIDTH, 0.5 * h),
                      displacement="plate")
    out = {}
    for side, v in (("free", law.assuming(traction="free")), ("x", law.assuming(traction="x"))):
        o = drive_3d(v, Loading.of(F0, dF=0.0, alpha=0.0, fa=0.5 * MU * F0, cycles=3, steps=steps))
        out[side] = {k: o[k] for k in ("dissipation", "stick_axis_x", "stick_axis_y", "stick_radius_x",
                                       "stick_radius_y", "stick_fit_x", "stick_fit_y", "stick_axis_quantum",
                                       "contact_radius", "traction_angle_max")}
    out["vertices"] = law.n
    return out


def stats(x):
    x = np.asarray(x, dtype=float)
    sd = float(np.std(x, ddof=1)) if x.size > 1 else float("nan")
    return float(np.mean(x)), sd / np.sqrt(x.size)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=100, help="steps per cycle (default 100)")
    ap.add_argument("--radii", type=float, nargs="+", default=[0.88, 0.89, 0.9, 0.91, 0.92],
                    help="ring circles r = R / a of the ensemble's meshes (each in [0.85, 0.95])")
    ap.add_argument("levels", type=float, nargs="*", default=[0.2, 0.14, 0.12, 0.1],
                    help="coarse element sizes h / a, the ring at h / 2 (after --, following --radii)")
    args = ap.parse_args(argv)
    if any(not 0.85 <= r <= 0.95 for r in args.radii):
        ap.error(f"--radii must lie in [0.85, 0.95] (the annulus R -+ {RING_WIDTH} a must cover the slip zone "
                 f"0.79-1 a), got {args.radii}")
    W_md, c_cm = md_references()
    levels = []
    for h in args.levels:
        rows = []
        for rr in args.radii:
            t = time.perf_counter()
            m = member(h, rr, args.steps)
            f, x = m["free"], m["x"]
            row = {"ring_r": rr, "vertices": m["vertices"], "W": f["dissipation"] / W_md,
                   "W_x": x["dissipation"] / W_md,
                   "dW_dir": (f["dissipation"] - x["dissipation"]) / x["dissipation"],
                   **{f"d_{k}": (f[k] - x[k]) / c_cm for k in ("stick_axis_x", "stick_axis_y", "stick_radius_x",
                                                                "stick_radius_y", "stick_fit_x", "stick_fit_y")},
                   "fit_x": x["stick_fit_x"] / c_cm - 1, "fit_y": x["stick_fit_y"] / c_cm - 1,
                   "quantum": x["stick_axis_quantum"] / c_cm, "angle": f["traction_angle_max"],
                   "seconds": time.perf_counter() - t}
            rows.append(row)
            print(f"h = a/{1 / h:.3g}, ring r = {rr:g} a ({row['vertices']} vertices, {row['seconds']:.0f} s): "
                  f"dW / MD {row['W']:.4f} (along x {row['W_x']:.4f}), direction effect: dissipation "
                  f"{row['dW_dir']:+.3%}, stick axes x, y {row['d_stick_axis_x']:+.3%}, {row['d_stick_axis_y']:+.3%} "
                  f"of c (quantum {row['quantum']:.3%}), rays x, y {row['d_stick_radius_x']:+.3%}, "
                  f"{row['d_stick_radius_y']:+.3%}, fitted ellipse x, y {row['d_stick_fit_x']:+.3%}, "
                  f"{row['d_stick_fit_y']:+.3%} (along x: {row['fit_x']:+.3%}, {row['fit_y']:+.3%} off "
                  f"Cattaneo-Mindlin)", flush=True)
        lv = {"h": h, "members": rows}
        for k in ("W", "W_x", "dW_dir", "d_stick_axis_x", "d_stick_axis_y", "d_stick_radius_x", "d_stick_radius_y",
                  "d_stick_fit_x", "d_stick_fit_y", "fit_x", "fit_y", "quantum", "angle"):
            lv[k] = stats([r[k] for r in rows])
        levels.append(lv)
    print("\n| h / a (ring) | members | vertices | dW / MD (free) | dW / MD (along x) | direction: dissipation | "
          "stick axis x | stick axis y | ray x | ray y | fitted x | fitted y | axis quantum | fit along x - C-M (x, y) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for lv in levels:
        h = lv["h"]
        cell = lambda k, pct: (f"{lv[k][0]:+.2%} +- {lv[k][1]:.2%}" if pct  # noqa: E731
                               else f"{lv[k][0]:.4f} +- {lv[k][1]:.4f}")
        print(f"| 1/{1 / h:.3g} (1/{2 / h:.3g}) | {len(lv['members'])} | "
              f"{int(np.median([r['vertices'] for r in lv['members']]))} | {cell('W', False)} | {cell('W_x', False)} | "
              f"{cell('dW_dir', True)} | {cell('d_stick_axis_x', True)} | {cell('d_stick_axis_y', True)} | "
              f"{cell('d_stick_radius_x', True)} | {cell('d_stick_radius_y', True)} | {cell('d_stick_fit_x', True)} | "
              f"{cell('d_stick_fit_y', True)} | {lv['quantum'][0]:.2%} | {lv['fit_x'][0]:+.2%}, {lv['fit_y'][0]:+.2%} |")
    print("(means +- standard errors over the members; stick effects in % of the Cattaneo-Mindlin radius)")
    if len(levels) >= 2:
        for k in ("W", "W_x", "dW_dir", "d_stick_fit_x", "d_stick_fit_y", "fit_x", "fit_y"):
            err = ensemble_error([lv["h"] for lv in levels], [lv[k] for lv in levels])
            print(f"{k}: {json.dumps(err, default=float)}")


def ensemble_error(sizes, means_se) -> dict:
    """Error bar of the finest ensemble mean: ``ladder_error`` of the means, plus two standard
    errors of the finest mean; where a step between the three finest means is below two of its
    standard errors no order can be observed, and the error is their spread plus two standard errors
    (the rule of a ladder without an observed order)."""
    from common.ladder import ladder_error

    m = [x[0] for x in means_se]
    se = [x[1] for x in means_se]
    lad = ladder_error(sizes, m)
    out = {"value": m[-1], "ladder": lad, "standard_error": se[-1]}
    tail = list(zip(m[-3:], se[-3:]))
    noisy = any(abs(b[0] - a[0]) < 2 * np.hypot(a[1], b[1]) for a, b in zip(tail, tail[1:]))
    if noisy and len(tail) == 3:
        out.update(status="steps within two standard errors: no order observed",
                   error=float(np.ptp([t[0] for t in tail]) + 2 * se[-1]))
    else:
        out.update(status=lad["status"], error=(lad["error"] if lad["error"] is not None else float("nan")) + 2 * se[-1])
    return out


if __name__ == "__main__":
    main()
