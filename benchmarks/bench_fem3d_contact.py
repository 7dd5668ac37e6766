"""Convergence and cost of the 3D frictional contact (issue 13): one force-controlled fretting run
per mesh level, each in its own process (peak memory per level).

Sphere R = 6 mm on a block, identical steel bodies, F_N = 0.5 N, mu = 0.2, tangential force
amplitude mu F_N / 2 (Mindlin & Deresiewicz partial slip), 3 cycles; the stationary cycle's
dissipation against Mindlin & Deresiewicz and the ladder's extrapolation
(``validation.metrics.ladder_error``). Run:

    python benchmarks/bench_fem3d_contact.py [--steps 100] [--ring R W F] [h_contact ...]

``--ring R W F``: every 3D level h gets the refined ring (R, W, F h) (``FEContact3D(ring=)``), fine in
the slip annulus and at the contact edge, coarse (h) elsewhere; e.g. ``--ring 0.9 0.18 0.5 0.2 0.14 0.1``.
"""
import argparse
import json
import subprocess
import sys
from mdr.loading import Loading


R, F0, MU = 6e-3, 0.5, 0.2


def md_references():
    """(Mindlin-Deresiewicz dissipation (J), Cattaneo-Mindlin stick radius (m)) of this loading."""
    from mdr import reference as ref
    from mdr.materials import Materials

    mat = Materials()
    hz = ref.hertz(F0, R, mat.E_star)
    us = ref.gross_slip_displacement(hz["d"], MU, mat.E_star, mat.G_star)
    return (ref.mindlin_deresiewicz_dissipation_force(0.5 * MU * F0, F0, MU, us),
            ref.cattaneo_mindlin_stick_radius(0.5 * MU * F0, F0, MU, hz["a"]))


def one(h, steps, model="3d", ring=None):
    from fem.contact_run import run_fem_contact
    from fem.options import FEOptions
    from meshes.half3d import Refinement
    from mdr.materials import Materials
    from mdr.profiles import Sphere

    out = run_fem_contact(Sphere(R), Materials(), MU, Loading.of(F0, fa=0.5 * MU * F0, cycles=3, steps=steps), FEOptions(model=model, h_contact=h, displacement="plate", refinement=Refinement(ring=None if ring is None else (ring[0], ring[1], ring[2] * h))))
    if model != "3d":
        return {k: out[k] for k in ("dissipation", "dofs", "runtime_s")}
    keys = ("contact_radius", "pressure_radius", "stick_radius", "stick_radius_x", "stick_radius_y", "stick_axis_x",
            "stick_axis_y", "stick_axis_quantum", "traction_angle_max",
            "dissipation", "dofs", "vertices", "runtime_s", "peak_memory_bytes")
    return {k: out[k] for k in keys}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--one", type=float, default=None, help=argparse.SUPPRESS)
    ap.add_argument("--model", default="3d", help=argparse.SUPPRESS)
    ap.add_argument("--ring", type=float, nargs=3, default=None, metavar=("R", "W", "F"),
                    help="refined ring of every 3D level h: element size F h within W of r = R (/ a)")
    ap.add_argument("--axisym", type=float, nargs="*", default=[1 / 10, 1 / 20, 1 / 40],
                    help="levels h/a of the axisymmetric model for the cost ratio at equal error")
    ap.add_argument("levels", type=float, nargs="*", default=[0.2, 0.14, 0.1, 0.07])
    args = ap.parse_args(argv)
    if args.one is not None:
        print(json.dumps(one(args.one, args.steps, args.model, args.ring)))
        return
    from validation.metrics import ladder_error

    W_md, c_cm = md_references()
    from mdr import reference as ref
    from mdr.materials import Materials

    a_hz = ref.hertz(F0, R, Materials().E_star)["a"]
    rows = []
    print("| h / a | DOFs | vertices | setup (s) | of which factorisation, condensation (s) | cycles (s) | per step (ms) "
          "| peak memory (GB) | dW / MD | c_x / CM | c_y / CM | max angle | pressure radius / Hertz a |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for h in args.levels:
        ring = [] if args.ring is None else ["--ring", *map(str, args.ring)]
        res = subprocess.run([sys.executable, __file__, "--steps", str(args.steps), "--one", str(h), *ring],
                             capture_output=True, text=True, check=True)
        r = json.loads(res.stdout.strip().splitlines()[-1])
        r["h"] = h
        rows.append(r)
        t = r["runtime_s"]
        print(f"| {h:g} | {r['dofs']} | {r['vertices']} | {t['setup']:.1f} | {t['factorisation']:.1f}, "
              f"{t['condensation']:.1f} | {t['cycles']:.1f} | {1e3 * t['per_step']:.0f} | "
              f"{r['peak_memory_bytes'] / 1e9:.2f} | "
              f"{r['dissipation'] / W_md:.4f} | {r['stick_radius_x'] / c_cm:.4f} | {r['stick_radius_y'] / c_cm:.4f} | "
              f"{r['traction_angle_max']:.3f} | {r['pressure_radius'] / a_hz:.4f} |", flush=True)
    if len(rows) >= 3:
        for key, scale in (("dissipation", W_md), ("traction_angle_max", 1.0), ("stick_radius_x", c_cm)):
            e = ladder_error([r["h"] for r in rows], [r[key] / scale for r in rows])
            print(f"{key}: {json.dumps(e, default=float)}")
    # the axisymmetric model (Fourier modes 0 + 1) on the same loading: cost at equal dissipation error
    print("\n| axisymmetric h / a | DOFs | set-up (s) | cycles (s) | dW / Mindlin-Deresiewicz |\n|---|---|---|---|---|")
    ax = []
    for h in args.axisym:
        res = subprocess.run([sys.executable, __file__, "--steps", str(args.steps), "--one", str(h), "--model",
                              "axisym"], capture_output=True, text=True, check=True)
        r = json.loads(res.stdout.strip().splitlines()[-1])
        r["h"] = h
        ax.append(r)
        print(f"| {h:g} | {r['dofs']} | {r['runtime_s']['setup']:.2f} | {r['runtime_s']['cycles']:.2f} | "
              f"{r['dissipation'] / W_md:.4f} |", flush=True)
    for tol in (0.02, 0.003):
        c3 = [r for r in rows if abs(r["dissipation"] / W_md - 1) <= tol]
        ca = [r for r in ax if abs(r["dissipation"] / W_md - 1) <= tol]
        if c3 and ca:
            t3, ta = c3[0]["runtime_s"]["total"], ca[0]["runtime_s"]["total"]
            print(f"dissipation within {tol:.1%} of Mindlin-Deresiewicz: 3D at h = a/{1 / c3[0]['h']:.0f} in {t3:.1f} s, "
                  f"axisymmetric at a/{1 / ca[0]['h']:.0f} in {ta:.2f} s: ratio {t3 / ta:.0f} (coarsest level within it; "
                  "the 3D ladder is non-monotone, so a level within it is not a converged error)")
        else:
            print(f"dissipation within {tol:.1%}: no 3D level ({len(c3)}) or no axisymmetric level ({len(ca)}) reaches it")


if __name__ == "__main__":
    main()
