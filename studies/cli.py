"""Command line of the MDR contact law: ``python -m mdr {normal,contact} ...``.

Flags are shared with ``python -m fem`` through ``add_profile_args``,
``add_material_args`` and ``add_contact_args``; the parser class and the exit
codes (bad input 2, a solver that does not converge 3, one line on stderr)
are those of ``common.cli``. All values SI.
"""
from __future__ import annotations

import sys
import time

import numpy as np

from mdr.apparatus import PLATE_MODELS
from common.cli import OneLineParser, add_output_args, run_command
from common.errors import InputError
from mdr.loading import Loading
from mdr.paper import KX_TABLE1
from mdr.flags import (add_contact_args, add_material_args, add_profile_args, materials_from_args,
                       profile_from_args)
from common.plugins import GROUP, law_plugins
from fem.cli import FE_LAW


def _cmd_normal(args):
    from mdr.normal import approach_from_force, contact_radius, pressure, pressure_radius
    from common.errors import positive

    t0 = time.perf_counter()
    prof = profile_from_args(args)
    mat = materials_from_args(args)
    F = positive("F", args.F)
    d = float(approach_from_force(prof, mat, F))
    a = float(contact_radius(prof, d))
    from common.errors import positive_int

    n = positive_int("points", args.points, minimum=8)
    # radii avoid r = a (and r = b) where the pressure may be singular
    r = (np.arange(n) + 0.5) / n * a
    p = pressure(prof, mat, d, r)
    return {"contact_radius": a, "pressure_radius": pressure_radius(prof, mat, d), "indentation": d,
            "normal_force": F,
            "pressure": {"r": r.tolist(), "p": p.tolist()},
            "runtime_s": time.perf_counter() - t0,
            "inputs": {**prof.describe(), **mat.as_dict(), "F": F}}


def _cmd_contact(args):
    from mdr.drive import run_mdr_contact

    loading = Loading.of(args.F0, args.dF, args.alpha, ua=args.ua, fa=args.fa, cycles=args.cycles, steps=args.steps)
    return run_mdr_contact(profile_from_args(args), materials_from_args(args), args.mu, loading, n=args.cells)


def _cmd_apparatus(args):
    from mdr.apparatus import Apparatus, mdr_apparatus_result

    app = Apparatus(kx=args.kx, mu2=args.mu2, R_bed=args.R_bed, plate_model=args.plate_model,
                    bedding=not args.no_bedding)
    prof, mat = profile_from_args(args), materials_from_args(args)
    loading = Loading.apparatus(args.F0, args.dF, args.alpha, args.ua, cycles=args.cycles, steps=args.steps)
    if args.law != "mdr":  # the FE law (fem.cli.FE_LAW) or a third-party one (common.plugins)
        return args.law_plugins[args.law].apparatus_result(prof, mat, app, args.mu, loading, args)
    return mdr_apparatus_result(prof, mat, app, args.mu, loading, n=args.cells)


def _cmd_study(args):
    from .study import run_studies, study_names

    names = study_names(args.name)
    if args.law == "mdr" and (args.points is not None or args.levels is not None):
        raise InputError("--points and --levels apply to a plugin law's study points; give --law too (e.g. --law fem)")
    t0 = time.perf_counter()
    app_kw = {k: v for k, v in (("plate_model", args.plate_model), ("R_bed", args.R_bed)) if v is not None}
    say = lambda m: sys.stderr.write(m + "\n")  # noqa: E731
    out = run_studies(names, args.out, jobs=args.jobs, app_kw=app_kw or None, scheduler=args.scheduler, law=args.law,
                      plugin=args.law_plugins.get(args.law), law_args=args, points=args.points, levels=args.levels,
                      log=say)
    for res in out:
        sys.stderr.write(f"study {res['study']}: {len(res['rows'])} points in {res['runtime_s']:.2f} s on "
                         f"{res['worker']} -> {args.out}\n")
    if len(out) > 1:
        sys.stderr.write(f"{len(out)} studies in {time.perf_counter() - t0:.2f} s ({out[0]['executor']})\n")
    return out[0] if len(out) == 1 else {"studies": out}


PLATE_HELP = ("brass plates: axial = loaded along their length (default), bending = bent across their thickness, "
              "inplane = bent in their plane, rigid, tilt = axial with the block tilting on its bedding, "
              "parallel = parallelogram at the block's bottom and top, block tilting (mdr/apparatus.py, A3)")


def contact_laws() -> dict:
    """{name: law} of the laws besides MDR that ``--law`` offers: the FE law (``fem``, built in) and
    any third-party law registered under the entry-point group ``common.plugins.GROUP``."""
    return {"fem": FE_LAW, **law_plugins(builtin=("mdr", "fem"))}


def build_parser():
    parser = OneLineParser(prog="python -m mdr", description=(
        "MDR (method of dimensionality reduction) contact law for axisymmetric profiles: "
        "normal contact and frictional fretting loads. SI units throughout."))
    sub = parser.add_subparsers(dest="command", required=True, parser_class=OneLineParser)

    pn = sub.add_parser("normal", help="normal contact: approach, contact radius, pressure p(r) at force F",
                        description="Frictionless normal contact at normal force F (half-space, MDR).")
    add_profile_args(pn)
    add_material_args(pn)
    pn.add_argument("--F", type=float, required=True, help="normal force in N (> 0)")
    pn.add_argument("--points", type=int, default=200, help="radial points of the pressure profile")
    add_output_args(pn)
    pn.set_defaults(func=_cmd_normal)

    pc = sub.add_parser("contact", help="fretting cycles with the contact driven directly",
                        description="Drive the contact with harmonic normal force and tangential displacement "
                                    "(or force); report the stationary last cycle.")
    add_profile_args(pc)
    add_material_args(pc)
    add_contact_args(pc)
    pc.add_argument("--cells", type=int, default=400, help="spring cells of the MDR grid (default 400)")
    add_output_args(pc)
    pc.set_defaults(func=_cmd_contact)

    pa = sub.add_parser("apparatus", help="fretting in the paper's apparatus (quasi-static reconstruction)",
                        description="The contact inside the apparatus of Willert (2023): indenter on a normal axis "
                                    "of tangential stiffness kx, block on three Si3N4 half-spheres pushed by a piezo "
                                    "through two brass plates. Defaults from Table 1; see mdr/apparatus.py for "
                                    "the reconstructed assumptions.")
    add_profile_args(pa)
    add_material_args(pa)
    g = pa.add_argument_group("load and apparatus (SI)")
    g.add_argument("--mu", type=float, required=True, help="friction of the fretting contact (mu1)")
    g.add_argument("--mu2", type=float, default=0.1, help="friction of the bedding (default 0.1)")
    g.add_argument("--kx", type=float, default=KX_TABLE1, help="tangential stiffness of the normal axis in N/m (default 1.9e6)")
    g.add_argument("--F0", type=float, required=True, help="mean normal force in N")
    g.add_argument("--dF", type=float, default=0.1, help="normal force amplitude in N (default 0.1)")
    g.add_argument("--alpha", type=float, default=0.0, help="phase of the normal force in rad")
    g.add_argument("--ua", type=float, required=True, help="piezo amplitude u_A in m")
    g.add_argument("--cycles", type=int, default=4, help="cycles (the last one is reported; default 4)")
    g.add_argument("--steps", type=int, default=200, help="steps per cycle (multiple of 4; default 200)")
    g.add_argument("--R-bed", dest="R_bed", type=float, default=5e-3, help="radius of the bedding half-spheres in m")
    g.add_argument("--plate-model", choices=list(PLATE_MODELS), default="axial",
                   help=PLATE_HELP)
    g.add_argument("--no-bedding", action="store_true", help="frictionless bedding (no bedding contacts)")
    plugins = contact_laws()
    pa.add_argument("--law", choices=["mdr", *plugins], default="mdr",
                    help="contact law of the fretting contact: mdr (default)"
                         + "".join(f"; {name}: {p.help}" for name, p in plugins.items())
                         + " (further laws: plugins of the entry-point group " + GROUP + ", see common.plugins)")
    pa.add_argument("--cells", type=int, default=400, help="spring cells of the MDR grid (--law mdr)")
    for plugin in plugins.values():
        plugin.add_arguments(pa)
    add_output_args(pa)
    pa.set_defaults(func=_cmd_apparatus, law_plugins=plugins)

    ps = sub.add_parser("study", help="parameter studies of the paper: fig8, fig9, loops (Figs. 4-7), "
                                      "sensitivity, plates, or all (comma-separated)",
                        description="Slip index against b (fig8) and against k_x (fig9) with Table 2 values, the "
                                    "four experiment loops of Figs. 4-7 (loops), or the slip index at the Table 2 "
                                    "point as each reconstructed apparatus quantity varies (sensitivity: CSV + "
                                    "markdown table), or every reading of the brass plates against the paper's "
                                    "Figs. 4-9 (plates: CSV + markdown table). Writes CSV/JSON and PNG to --out.")
    ps.add_argument("name", help="fig8, fig9, loops, sensitivity or plates, a comma list of them, or all")
    ps.add_argument("--jobs", type=int, default=1, metavar="N",
                    help="run several studies in N parallel processes (default 1)")
    ps.add_argument("--scheduler", metavar="ADDRESS",
                    help="run the studies on the workers of a running Dask scheduler (e.g. tcp://host:8786; "
                         "needs the dist extra; excludes --jobs)")
    ps.add_argument("--out", default="results/study", help="output directory (default results/study)")
    ps.add_argument("--plate-model", choices=list(PLATE_MODELS), default=None,
                    help="fig8, fig9, loops: reading of the brass plates (default axial; " + PLATE_HELP + ")")
    ps.add_argument("--R-bed", dest="R_bed", type=float, default=None,
                    help="fig8, fig9, loops: radius of the bedding half-spheres in m (default 5e-3)")
    ps.add_argument("--json", default=None, metavar="PATH", help="also write the rows as JSON")
    ps.add_argument("--law", choices=["mdr", *plugins], default="mdr",
                    help="mdr (default), or a plugin law run beside MDR at --points points per curve of fig8/fig9 "
                         "(writes NAME_LAW.csv/png; see studies/law_study.py)")
    ps.add_argument("--points", type=int, default=None, metavar="N",
                    help="with --law: points per curve, evenly spread, ends included (default 5)")
    ps.add_argument("--levels", type=int, default=None, metavar="L",
                    help="with --law: mesh levels for the law's own error, element size 2^(L-1)..2, 1 times "
                         "its own (default 2)")
    for plugin in plugins.values():
        plugin.add_arguments(ps)
    ps.set_defaults(func=_cmd_study, law_plugins=plugins)
    return parser


def main(argv=None, parser=None):
    return run_command(parser or build_parser(), argv)
