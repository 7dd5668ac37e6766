"""Command line: ``python -m fem normal ...`` (axisymmetric FE normal contact, SI units)."""
from __future__ import annotations

import argparse
import sys

from mdr.errors import ConvergenceError, InputError
from mdr.io import check_output_path, write_json

from .friction import DEFAULT_FRICTION_AL_TOL
from .normal import DEFAULT_AL_TOL, DEFAULT_PENALTY
from .run import H_CONTACT_RANGE


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors and exit code 2."""

    def error(self, message):
        sys.stderr.write(f"{self.prog}: error: {message}\n")
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="python -m fem", description=(
        "Finite-element contact of two finite elastic bodies (gmsh + scikit-fem). "
        "All quantities in SI units (m, N, Pa)."))
    sub = p.add_subparsers(dest="command", parser_class=_Parser, required=True)
    n = sub.add_parser("normal", formatter_class=argparse.ArgumentDefaultsHelpFormatter,
                       help="axisymmetric frictionless normal contact under a force F",
                       description=(
                           "Axisymmetric FE normal contact (Fourier mode 0, P2 triangles) of an elastic "
                           "indenter (sphere cap, truncated sphere, or flat punch) on an elastic cylindrical "
                           "block. The stiffness is factorised once and condensed to the contact interface; "
                           "penalty contact with augmented-Lagrangian iterations. Writes contact_radius, "
                           "indentation (half-space comparable: finite-body bulk compliance removed with "
                           "probes at depth 20 a and the Boussinesq solution), approach (raw FE), "
                           "normal_force, pressure {r, p}, dofs, mesh, runtime_s {mesh, setup, solve, total}."))
    n.add_argument("--profile", choices=("sphere", "truncated", "flat"), required=True,
                   help="indenter profile")
    n.add_argument("--R", type=float, default=None, help="sphere radius (m); sphere and truncated")
    n.add_argument("--b", type=float, default=0.0, help="flat-face / punch radius (m); truncated and flat")
    n.add_argument("--F", type=float, required=True, help="normal force (N), > 0")
    n.add_argument("--E1", type=float, default=200e9, help="indenter Young's modulus (Pa)")
    n.add_argument("--nu1", type=float, default=0.29, help="indenter Poisson ratio")
    n.add_argument("--E2", type=float, default=200e9, help="block Young's modulus (Pa)")
    n.add_argument("--nu2", type=float, default=0.29, help="block Poisson ratio")
    n.add_argument("--h-contact", type=float, default=0.0125,
                   help=f"element size in the contact zone as a fraction of the contact radius a "
                        f"(range [{H_CONTACT_RANGE[0]:g}, {H_CONTACT_RANGE[1]:g}]; 0.0125 = a/80)")
    n.add_argument("--contact-extent", type=float, default=1.25,
                   help="radius of the finely meshed contact segment / a (> 1)")
    n.add_argument("--block-size", type=float, default=None,
                   help="block radius and height (m); default 200 a (also bounds the indenter cap height)")
    n.add_argument("--penalty", type=float, default=DEFAULT_PENALTY,
                   help="penalty factor alpha (> 0): stiffness alpha * E* / h per unit area")
    n.add_argument("--al-tol", type=float, default=DEFAULT_AL_TOL,
                   help="augmented-Lagrangian stop: largest penetration / approach; 0 = pure penalty")
    n.add_argument("--solver", choices=("auto", "cholmod", "pardiso", "superlu"), default="auto",
                   help="sparse factorisation backend")
    n.add_argument("--cache-dir", default=None,
                   help="mesh cache directory (default $FRETTING_MESH_CACHE or ~/.cache/fretting-meshes)")
    n.add_argument("--vtu", default=None, help="also write displacements and stresses to this .vtu file")
    n.add_argument("--json", required=True, help="output JSON path ('-' for stdout)")
    _add_contact_parser(sub)
    return p


def add_fe_options(c):
    """The FE model flags of ``python -m fem contact`` and ``python -m mdr apparatus --law fem``."""
    g = c.add_argument_group("FE model (mesh, penalty, solver)")
    g.add_argument("--h-contact", type=float, default=0.0125,
                   help=f"element size in the contact zone / contact radius at F0 + dF "
                        f"(range [{H_CONTACT_RANGE[0]:g}, {H_CONTACT_RANGE[1]:g}]; 0.0125 = a/80)")
    g.add_argument("--contact-extent", type=float, default=1.25,
                   help="radius of the finely meshed contact segment / a (> 1)")
    g.add_argument("--block-size", type=float, default=None,
                   help="block radius and height (m); default 200 a")
    g.add_argument("--penalty", type=float, default=DEFAULT_PENALTY,
                   help="penalty factor alpha (> 0): normal and tangential stiffness alpha * E* / h per unit area")
    g.add_argument("--al-tol", type=float, default=DEFAULT_AL_TOL,
                   help="normal augmented-Lagrangian stop: largest penetration / approach; 0 = pure penalty")
    g.add_argument("--friction-al-tol", type=float, default=DEFAULT_FRICTION_AL_TOL,
                   help="tangential augmented-Lagrangian stop: largest multiplier change / largest slip "
                        "limit; 0 = pure penalty")
    g.add_argument("--solver", choices=("auto", "cholmod", "pardiso", "superlu"), default="auto",
                   help="sparse factorisation backend")
    g.add_argument("--cache-dir", default=None,
                   help="mesh cache directory (default $FRETTING_MESH_CACHE or ~/.cache/fretting-meshes)")


def _add_contact_parser(sub):
    from mdr.cli import add_contact_args, add_material_args, add_output_args, add_profile_args

    c = sub.add_parser("contact", help="FE fretting cycles with the contact driven directly",
                       description=(
                           "Axisymmetric FE frictional contact (Fourier mode 0 for the pressure, mode 1 for "
                           "the tangential load, Coulomb friction with penalty return map and augmented "
                           "Lagrangian on the condensed interface) driven with the harmonic loads of "
                           "'python -m mdr contact' (same flags and JSON keys). Adds dofs, mesh, solver, "
                           "displacement, bulk_compliance and runtime_s {setup, cycles, total}. Displacements "
                           "(--ua, loop du, displacement_amplitude) are in the measure --displacement: "
                           "'contact' (default) is the half-space comparable relative displacement that "
                           "'python -m mdr contact' uses (the finite bodies' series compliance bulk_compliance, "
                           "measured at axis probes with Cerruti's half-space solution, removed); 'plate' the "
                           "indenter's top plate relative to the block bottom (= contact + bulk_compliance * Fx). "
                           "Exit 2: bad input; exit 3: a solver did not converge."))
    add_profile_args(c)
    add_material_args(c)
    add_contact_args(c)
    add_fe_options(c)
    c.add_argument("--displacement", choices=("contact", "plate"), default="contact",
                   help="measure of --ua and the output displacements: 'contact' (half-space comparable, as in "
                        "python -m mdr contact) or 'plate' (indenter top plate vs block bottom, includes the "
                        "finite bodies' compliance)")
    add_output_args(c)


def _contact(args) -> int:
    try:
        from mdr.cli import materials_from_args, profile_from_args

        from .contact_run import run_fem_contact

        out = run_fem_contact(profile_from_args(args), materials_from_args(args), args.mu, args.F0, args.dF,
                              args.alpha, ua=args.ua, fa=args.fa, cycles=args.cycles, steps=args.steps,
                              **fe_options(args),
                              displacement=args.displacement)
    except InputError as exc:
        sys.stderr.write(f"python -m fem contact: error: {exc}\n")
        return 2
    except ConvergenceError as exc:
        sys.stderr.write(f"python -m fem contact: solver failed: {exc}\n")
        return 3
    write_json(args.json, out)
    return 0


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:  # output paths are checked before the run, so a bad one costs nothing and leaves no file
        if args.json != "-":
            check_output_path(args.json, "--json")
        if getattr(args, "vtu", None):
            check_output_path(args.vtu, "--vtu")
    except InputError as exc:
        sys.stderr.write(f"python -m fem {args.command}: error: {exc}\n")
        return 2
    if args.command == "contact":
        return _contact(args)
    try:
        from mdr.materials import Materials

        from .run import run_normal

        mats = Materials(args.E1, args.nu1, args.E2, args.nu2)
        out, model, res = run_normal(
            args.profile, R=args.R, b=args.b, F=args.F, materials=mats, h_contact=args.h_contact,
            block_size=args.block_size, contact_extent=args.contact_extent, penalty=args.penalty,
            al_tol=args.al_tol, cache_dir=args.cache_dir,
            backend=None if args.solver == "auto" else args.solver, return_model=True)
        if args.vtu:
            from .output import write_vtu

            write_vtu(model, res, args.vtu)
    except InputError as exc:
        sys.stderr.write(f"python -m fem normal: error: {exc}\n")
        return 2
    except ConvergenceError as exc:  # same convention as python -m mdr and python -m fem contact
        sys.stderr.write(f"python -m fem normal: solver failed: {exc}\n")
        return 3
    write_json(args.json, out)
    return 0


def fe_options(args) -> dict:
    """Keyword arguments of the FE law from the flags of :func:`add_fe_options`."""
    return dict(h_contact=args.h_contact, contact_extent=args.contact_extent, block_size=args.block_size,
                penalty=args.penalty, al_tol=args.al_tol, friction_al_tol=args.friction_al_tol,
                cache_dir=args.cache_dir, backend=None if args.solver == "auto" else args.solver)


class _FEApparatusLaw:
    """The FE law as a plugin of ``python -m mdr apparatus --law fem`` (``mdr.plugins``)."""

    help = ("the axisymmetric FE model (fem.law.FEContact with displacement='contact'; adds dofs, mesh, "
            "solver and runtime_s {setup, cycles, total} to the JSON)")
    add_arguments = staticmethod(add_fe_options)

    @staticmethod
    def apparatus_result(profile, materials, app, mu, F0, dF, alpha, ua, cycles, steps, args) -> dict:
        from .apparatus import fem_apparatus_result  # the FE model's imports only when it is used

        return fem_apparatus_result(profile, materials, app, mu, F0, dF, alpha, ua, cycles=cycles, steps=steps,
                                    **fe_options(args))


#: entry point ``fem`` of the group ``fretting.contact_laws`` (pyproject.toml)
FE_LAW = _FEApparatusLaw()
