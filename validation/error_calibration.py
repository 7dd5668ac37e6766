"""The calibration of ``validation.error_models``' bounds: one side's errors on a scene over a dense set of
mesh sizes (grids) against the same side far beyond them (``measure``), and the command that prints each
metric's envelope beside the bound in use::

    python -m validation.error_calibration sphere-md               # the FE model, a/20 .. a/160 against a/320
    python -m validation.error_calibration geom-b20um --side mdr   # MDR, 25 .. 1600 cells against 12800

``tests/test_error_models.py`` runs ``measure`` on held-out scenes to show the bounds contain the errors.
"""
from __future__ import annotations

from .error_models import SAFETY, bound, envelope

#: the scalar metrics a calibration measures, in their bounds' units (the distances: those of the scene's
#: ``validation.families.pair._distances``)
SCALARS = ("contact_radius", "stick_radius", "slip_index")


def measure(scene, sizes, reference: float, *, side: str = "fem", log=None) -> dict:
    """One side's errors on a scene over a dense set of ``sizes`` (FE: h_contact, element size / a_ref;
    MDR: cells) against the same side at ``reference`` (a far finer mesh or grid): per metric, the sizes
    in the bounds' unit (h / a, 1 / cells) and the errors in the metric's (radii over the reference's
    contact radius). The distance metrics are measured to the other side's run at ``reference`` (MDR at
    ``MDR_REFERENCE_CELLS`` for the FE calibration, the FE model at a/80 for MDR's), so their error is the
    change of the distance the verdict reads. Returns {metric: {"sizes", "errors"}, "reference": ...,
    "class": the class of bounds they are held to (``families.pair.ladder_class``; gross slip where every run's
    stick radius, the other side's included, is 0)}."""
    from .families.pair import _distances, ladder_class
    from .scenes import a_ref
    from .sides import run_fe, run_mdr

    log = log or (lambda msg: None)
    run = (lambda x: run_fe(scene, x)[0]) if side == "fem" else (lambda x: run_mdr(scene, int(x)))
    other = run_mdr(scene, MDR_REFERENCE_CELLS) if side == "fem" else run_fe(scene, 1 / 80)[0]
    pair = (lambda res: _distances(scene, other, res)) if side == "fem" else (lambda res: _distances(scene, res, other))
    ref = run(reference)
    a = float(ref["contact_radius"])
    unit = a_ref(scene) / a if side == "fem" else None  # FE: h_contact (of a_ref) in units of a
    h_of = (lambda x: float(x) * unit) if side == "fem" else (lambda x: 1.0 / float(x))
    d_ref = pair(ref)
    out = {q: {"sizes": [], "errors": []} for q in SCALARS + tuple(d_ref)}
    runs = []
    for x in sizes:
        res = run(x)
        runs.append(res)
        h = h_of(x)
        d = pair(res)
        for q in SCALARS:
            out[q]["sizes"].append(h)
            out[q]["errors"].append((float(res[q]) - float(ref[q])) / (a if q.endswith("radius") else 1.0))
        for q in d_ref:
            out[q]["sizes"].append(h)
            out[q]["errors"].append(float(d[q]) - float(d_ref[q]))
        log(f"  {scene.name} {side} {x:g}: " + ", ".join(f"{q} {out[q]['errors'][-1]:+.2e}" for q in out))
    out["reference"] = reference
    mine, theirs = runs + [ref], [other]
    out["class"] = ladder_class(scene, *((mine, theirs) if side == "fem" else (theirs, mine)))
    return out


#: MDR's grid for the FE calibration's distances (its own error is below 1e-5 of every distance there)
MDR_REFERENCE_CELLS = 6400


def _main(argv=None) -> int:
    import sys

    from common.cli import OneLineParser
    from .catalogue import CATALOGUE

    ap = OneLineParser(prog="python -m validation.error_calibration",
                       description="Measure one side's discretisation errors on a catalogue scene over a dense "
                                   "set of mesh sizes (grids) against a reference far beyond them, and print "
                                   "each metric's envelope max |error| / h next to the calibrated bound's.")
    ap.add_argument("scene", choices=sorted(CATALOGUE), metavar="SCENE", help="a catalogue scene of the pair family")
    ap.add_argument("--side", choices=("fem", "mdr"), default="fem")
    ap.add_argument("--sizes", default=None,
                    help="comma-separated h_contact (fem, default 1/20 .. 1/160 in 15 steps) or cells (mdr)")
    ap.add_argument("--reference", type=float, default=None, help="h_contact (default 1/320) or cells (12800)")
    args = ap.parse_args(argv)
    s = CATALOGUE[args.scene]
    if s.family != "pair" or s.fe_model != "axisym":
        ap.error(f"scene: {args.scene} is not an axisymmetric pair scene")
    if args.sizes:
        sizes = [float(x) for x in args.sizes.split(",")]
    else:
        sizes = ([1 / n for n in (20, 24, 28, 34, 40, 48, 56, 68, 80, 96, 113, 136, 160)] if args.side == "fem"
                 else [25, 32, 40, 50, 64, 80, 100, 128, 160, 200, 256, 320, 400, 512, 640, 800, 1024, 1280, 1600])
    reference = args.reference or (1 / 320 if args.side == "fem" else 12800)
    m = measure(s, sizes, reference, side=args.side, log=lambda msg: print(msg, file=sys.stderr, flush=True))
    print(f"class of bounds: {m['class']}")
    for q, v in m.items():
        if q in ("reference", "class"):
            continue
        b = bound(args.side, q, m["class"])
        print(f"{q:18s} envelope {envelope(v['sizes'], v['errors'], 1.0 if b is None else b.p):.3g}"
              + ("" if b is None else f"   bound's C {b.C:.3g} ({b.C / SAFETY:.3g} x {SAFETY:g})"))
    return 0


if __name__ == "__main__":
    raise SystemExit(_main())
