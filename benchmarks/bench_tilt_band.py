"""The truncated sphere b = 0.6 mm of the paper's experiments (R = 6 mm) at its tilt bound pi/3600
(274 theta_c at the Table 2 force) on meshes with a band along the loaded rim arc
(``FEContact3D(..., band=(h, width, angle, growth))``, ``meshes.half3d`` ``band_*``), finer than the
``tilt`` scene's banded row (``TILT_BAND``: band_h = b/33, b/50): by default b/50 and b/70.

The scene's loading and metrics (``validation.families.tilt.run``: Table 2 loading F0 = 0.5 N,
dF = 0.1 N, mu = 0.2, force amplitude 0.06 N, 4 cycles of 40 steps; the tilt against the aligned
face on the same banded mesh, error bar the two-level ladder of the band size, the face elsewhere at
h = 0.3 b). Not in the scene: the b/70 level has 560 interface vertices and its tilted run (the
crescent slips) took 22 min on the shared 2-core machine, 31 min in all. Run:

    python benchmarks/bench_tilt_band.py [--h-contact 0.3] [--width 0.06] [--angle 0.45] [band_h ...]
"""
import argparse
import time
import warnings


def main(argv=None):
    from validation import runner
    from validation.catalogue import CATALOGUE
    from validation.scenes import TILT_BOUND

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--h-contact", type=float, default=0.3, help="element size on the face elsewhere / b")
    ap.add_argument("--width", type=float, default=0.06, help="half width of the band about r = b, / b")
    ap.add_argument("--angle", type=float, default=0.45, help="half angle of the band's arc about phi = pi (rad)")
    ap.add_argument("--growth", type=float, default=1.0, help="size growth outside the band")
    ap.add_argument("bands", type=float, nargs="*", default=[0.02, 0.014], help="band element sizes / b, coarse first")
    args = ap.parse_args(argv)
    base = CATALOGUE["tilt"]
    v = {"profile": "truncated", "b": 0.6e-3, "tilts": (TILT_BOUND,), "fe_levels": (args.h_contact,) * len(args.bands),
         "band": tuple((h, args.width, args.angle, args.growth) for h in args.bands)}
    from dataclasses import replace

    s = replace(base, name="tilt-band", variants=(v,))
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = runner.run_scene(s, None, log=print)
    row = res["tilt"][0]
    pt = row["points"][0]
    print(f"b = 0.6 mm at pi/3600 = {pt['ratio']:.0f} theta_c; band (width {args.width:g} b, angle {args.angle:g} rad, "
          f"growth {args.growth:g}), face at h = {args.h_contact:g} b; {time.perf_counter() - t0:.0f} s in all")
    print("| band h / b | vertices | set-up (s) | contact vertices | contact area fraction | x_max / b | "
          "slip index (aligned) | slip index (tilted) | runs (s) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for lv in row["levels"]:
        a, t = lv["runs"]
        print(f"| {lv['band']:g} | {lv['vertices']} | {lv['setup_s']:.0f} | {t['contact_vertices']} | "
              f"{t['contact_area_fraction']:.5f} | {t['contact_x_max'] / 0.6e-3:.4f} | {a['slip_index']:.3g} | "
              f"{t['slip_index']:.5f} | {a['runtime_s']:.0f} + {t['runtime_s']:.0f} |")
    print("| effect of the tilt (finest, two-level error) | value | error | tolerance | aligned answer holds |")
    print("|---|---|---|---|---|")
    for q, x in pt["aligned"].items():
        print(f"| {q} | {x['effect']:.4g} | {x['error']:.2g} | {x['tolerance']} | {x['holds']} |")
    unit = row["dissipation_unit"]
    print(f"(dissipation in units of {unit}; resolved: {pt['resolved']}; stationary: {pt['stationary']})")
    return res


if __name__ == "__main__":
    main()
