"""Command line: ``python -m fem {normal,contact} ...`` (axisymmetric or 3D FE contact, SI units).

Same convention as ``python -m mdr`` (``common.cli``): the profile, material,
load flags are ``mdr.flags``, the ``--json`` flag ``common.cli``'s (JSON to stdout by default),
bad input exits 2, a solver that does not converge 3, one line on stderr. The
FE model flags are declared once, in :func:`add_fe_options`.
"""
from __future__ import annotations

import argparse
import sys

from common.cli import OneLineParser, add_output_args, run_command
from common.errors import InputError
from mdr.flags import (add_contact_args, add_material_args, add_profile_args, materials_from_args,
                       profile_from_args)
from meshes.axisym import CONTACT_EXTENT_DEFAULT, H_CONTACT_DEFAULT, H_CONTACT_RANGE
from meshes.half3d import H_CONTACT_3D_DEFAULT, H_CONTACT_3D_RANGE, Refinement

from fem.axisym.friction import DEFAULT_FRICTION_AL_TOL
from fem.axisym.normal import DEFAULT_AL_TOL, DEFAULT_PENALTY
from fem.options import FEOptions
from mdr.loading import Loading


def add_fe_options(c, friction: bool = True):
    """The FE model flags of ``python -m fem normal|contact`` and ``python -m mdr apparatus --law fem``
    (``friction=False``: without the tangential ``--friction-al-tol``)."""
    group = c.add_argument_group("FE model (mesh, penalty, solver)")
    group.add_argument("--h-contact", type=float, default=None,
                   help=f"element size in the contact zone / contact radius at the largest normal force "
                        f"(range [{H_CONTACT_RANGE[0]:g}, {H_CONTACT_RANGE[1]:g}]; default "
                        f"{H_CONTACT_DEFAULT:g} = a/{1 / H_CONTACT_DEFAULT:.0f}; --model 3d: range "
                        f"[{H_CONTACT_3D_RANGE[0]:g}, {H_CONTACT_3D_RANGE[1]:g}], default {H_CONTACT_3D_DEFAULT:g})")
    group.add_argument("--contact-extent", type=float, default=None,
                   help="radius of the finely meshed contact segment / a (> 1; default 1.25; --model 3d with the "
                        "flat punch: its face, 1)")
    group.add_argument("--block-size", type=float, default=None,
                   help="block radius and height in m (default 200 a; also bounds the indenter cap height)")
    group.add_argument("--penalty", type=float, default=None,
                   help=f"penalty factor alpha (> 0): normal{' and tangential' if friction else ''} stiffness "
                        f"alpha * E* / h per unit area (default {DEFAULT_PENALTY:g})")
    group.add_argument("--al-tol", type=float, default=None,
                   help=f"normal augmented-Lagrangian stop: largest penetration / approach; 0 = pure penalty "
                        f"(default {DEFAULT_AL_TOL:g})")
    if friction:
        group.add_argument("--friction-al-tol", type=float, default=None,
                       help=f"tangential augmented-Lagrangian stop: largest multiplier change / largest slip "
                            f"limit; 0 = pure penalty (default {DEFAULT_FRICTION_AL_TOL:g})")
    group.add_argument("--solver", choices=("auto", "cholmod", "pardiso", "superlu"), default="auto",
                   help="sparse factorisation backend (default auto)")
    group.add_argument("--cache-dir", default=None,
                   help="mesh cache directory (default $FRETTING_MESH_CACHE or ~/.cache/fretting-meshes)")


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(prog="python -m fem", description=(
        "Finite-element contact of two finite elastic bodies (gmsh + scikit-fem). "
        "All quantities in SI units (m, N, Pa)."))
    sub = p.add_subparsers(dest="command", parser_class=OneLineParser, required=True)
    n = sub.add_parser("normal", help="axisymmetric frictionless normal contact under a force F",
                       description=(
                           "Axisymmetric FE normal contact (Fourier mode 0, P2 triangles) of an elastic "
                           "indenter (sphere cap, truncated sphere, or flat punch) on an elastic cylindrical "
                           "block. The stiffness is factorised once and condensed to the contact interface; "
                           "penalty contact with augmented-Lagrangian iterations. Writes contact_radius, "
                           "pressure_radius (the pressure's second-moment radius sqrt(5 M2 / (2 F)), "
                           "M2 = int p r^2 dA), "
                           "indentation (half-space comparable: finite-body bulk compliance removed with "
                           "probes at depth 20 a and the Boussinesq solution), approach (raw FE), "
                           "normal_force, pressure {r, p}, dofs, mesh, runtime_s {mesh, setup, solve, total}. "
                           "Exit 2: bad input; exit 3: a solver did not converge."))
    add_profile_args(n)
    add_material_args(n)
    n.add_argument("--F", type=float, required=True, help="normal force in N (> 0)")
    add_fe_options(n, friction=False)
    n.add_argument("--vtu", default=None, metavar="PATH", help="also write displacements and stresses to this .vtu file")
    add_output_args(n)
    n.set_defaults(func=_normal)

    c = sub.add_parser("contact", help="FE fretting cycles with the contact driven directly",
                       description=(
                           "Axisymmetric FE frictional contact (Fourier mode 0 for the pressure, mode 1 for "
                           "the tangential load, Coulomb friction with penalty return map and augmented "
                           "Lagrangian on the condensed interface) driven with the harmonic loads of "
                           "'python -m mdr contact' (same flags and JSON keys). Adds pressure_radius (at F0, as "
                           "in fem normal), dofs, mesh, solver, displacement, bulk_compliance and runtime_s "
                           "{setup, cycles, total}. Displacements "
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
    c.add_argument("--displacement", choices=("contact", "plate"), default=None,
                   help="measure of --ua and the output displacements: 'contact' (default; half-space "
                        "comparable, as in python -m mdr contact) or 'plate' (indenter top plate vs block bottom, "
                        "includes the finite bodies' compliance)")
    c.add_argument("--vtu", default=None, metavar="PATH",
                   help="also write the fields at the drive's peak in the last cycle to this .vtu file "
                        "(axisymmetric model: displacements, von Mises stress and the stress components, contact "
                        "pressure, shear traction, stick/slip status, slip; --model 3d: the contact disk with the "
                        "pressure, both shear traction components, stick/slip status and slip)")
    c.add_argument("--model", choices=("axisym", "3d"), default="axisym",
                   help="'axisym' (default): Fourier modes 0 + 1, traction along x (Mindlin's assumption); '3d': "
                        "the 3D half model (y >= 0) with a two-component traction of free direction and exact "
                        "contact constraints, normal and tangential coupled for a dissimilar pair (sphere or "
                        "truncated sphere; --penalty, --al-tol, --friction-al-tol do not apply; --block-size "
                        "default 20 a); the normal load is applied in 20 steps with friction active before the "
                        "cycles. Adds model, vertices, beta (Dundurs), stick_radius_x, stick_radius_y, "
                        "stick_axis_x, stick_axis_y (the stick set's ellipse, one vertex at a time), "
                        "stick_fit_x, stick_fit_y (the ellipse fitted to the slack, exact for "
                        "Cattaneo-Mindlin), traction_angle_max (at the peak of F_x of the last cycle), "
                        "stick_center_x and "
                        "pressure_center_x (at the first peak of F_x) and "
                        "peak_memory_bytes (every contact run has dissipation_first_cycle, the friction work of the "
                        "first cycle +Q -> -Q -> +Q after the normal loading, and dissipation_open_path, "
                        "0 -> +Q -> -Q -> 0 from rest); and tilt, contact_area_fraction (contact area at the peak normal "
                        "force F0 + |dF| over the punch face's for a flat punch, over the aligned contact's "
                        "otherwise), contact_x_min, contact_x_max (the contact's extent along x there)")
    c.add_argument("--tilt", type=float, default=0.0, metavar="RAD",
                   help="--model 3d: tilt of the indenter's flat face about the y axis in rad (|tilt| <= 0.01; "
                        "> 0 lifts the +x side; the rotation held by the mount, the load line through the "
                        "face centre; default 0)")
    c.add_argument("--traction", choices=("free", "x"), default=None,
                   help="--model 3d only: 'free' (default) a two-component tangential traction of free "
                        "direction; 'x' q_y = 0 everywhere (Mindlin's assumption, as --model axisym and MDR), "
                        "so that the pair of runs on one mesh isolates the effect of the direction")
    c.add_argument("--paired", action="store_true",
                   help="--model 3d only: also run the twin along x (--traction x) on the same mesh in lockstep and "
                        "add 'paired': the dissipation as MDR's on the same loading (exact in the half space under "
                        "Mindlin's assumption) times the ratio free / twin, in which the error the two runs share "
                        "(the mesh's, the time step's) cancels (within 0.1 %% of the half-space answer on the "
                        "sphere's ring mesh at a/7, where one run is off by up to 1.3 %%; docs/fem3d.md); with "
                        "direction_effect, twin_dissipation, mindlin_dissipation, twin_error. Needs the traction of "
                        "free direction, no tilt, no normal-tangential coupling (Dundurs' beta = 0, as for identical "
                        "bodies), --displacement contact, no --vtu; a note on stderr where the twin is more than 10 %% "
                        "off MDR (a mesh that does not resolve the contact)")
    c.add_argument("--ring", type=float, nargs=3, default=None, metavar=("R", "W", "H"),
                   help="--model 3d only: refine the mesh to element size H within W of the circle r = R of the "
                        "contact face (all / a_ref, H <= --h-contact): the slip annulus and the contact edge of "
                        "a partial-slip cycle (the sphere at F_x = mu F_N / 2: 0.9 0.18 H)")
    add_output_args(c)
    c.set_defaults(func=_contact)
    return p


def _contact(args) -> dict:
    from fem.contact_run import run_fem_contact

    if args.model != "3d":  # the flags of the 3D model, named as the user gave them
        for flag, given in (("--traction", args.traction is not None), ("--ring", args.ring is not None),
                            ("--tilt", args.tilt != 0), ("--paired", args.paired)):
            if given:
                raise InputError(f"{flag} applies to --model 3d only (the axisymmetric model: traction along x, "
                                 "no tilt, no refined ring)")
    else:
        for flag in ("penalty", "al_tol", "friction_al_tol"):
            if getattr(args, flag) is not None:
                raise InputError(f"--{flag.replace('_', '-')} applies to --model axisym only (the 3D model's "
                                 "contact constraints are exact)")
    options = fe_options(args, model=args.model, displacement=args.displacement or "contact")
    loading = Loading.of(args.F0, args.dF, args.alpha, ua=args.ua, fa=args.fa, cycles=args.cycles, steps=args.steps)
    out = run_fem_contact(profile_from_args(args), materials_from_args(args), args.mu, loading, options, vtu=args.vtu,
                          paired=args.paired, log=lambda msg: print(f"python -m fem contact: {msg}", file=sys.stderr,
                                                                    flush=True))
    if args.paired:
        from fem.contact_run import paired_note

        note = paired_note(out["paired"])
        if note:
            sys.stderr.write(f"python -m fem contact: note: {note}\n")
    return out


def _normal(args) -> dict:
    from fem.axisym.normal_run import run_normal

    out, model, res = run_normal(
        args.profile, R=args.R, b=0.0 if args.b is None else args.b, F=args.F, exact=args.exact_cap, fillet=args.fillet,
        materials=materials_from_args(args), return_model=True, **_normal_options(fe_options(args)))
    if args.vtu:
        from fem.axisym.output import write_vtu

        write_vtu(model, res, args.vtu)
    return out


def main(argv=None) -> int:
    return run_command(build_parser(), argv)


def fe_options(args, **extra) -> FEOptions:
    """The FE options (``fem.options.FEOptions``, checked here once) from the flags of
    :func:`add_fe_options`; ``extra``: further fields (the model and its own flags). Flags not given
    are None: the model's defaults."""
    opts = dict(h_contact=args.h_contact, contact_extent=args.contact_extent, block_size=args.block_size,
                penalty=args.penalty, al_tol=args.al_tol, friction_al_tol=getattr(args, "friction_al_tol", None),
                cache_dir=args.cache_dir, backend=None if args.solver == "auto" else args.solver)
    if extra.get("model") == "3d":
        opts.update(traction=args.traction, tilt=args.tilt,
                    refinement=Refinement(ring=None if args.ring is None else tuple(args.ring)))
    return FEOptions(**opts, **extra)


def _normal_options(o: FEOptions) -> dict:
    """The keywords of ``fem.axisym.normal_run.run_normal`` from FE options (the normal run: no friction)."""
    given = {k: getattr(o, k) for k in ("penalty", "al_tol") if getattr(o, k) is not None}
    return dict(h_contact=o.h, contact_extent=CONTACT_EXTENT_DEFAULT if o.contact_extent is None else o.contact_extent,
                block_size=o.block_size, cache_dir=o.cache_dir, backend=o.backend, **given)


class _FEApparatusLaw:
    """The FE law as a plugin of ``python -m mdr apparatus --law fem`` (``common.plugins``)."""

    help = ("the axisymmetric FE model (fem.axisym.law.FEContact with displacement='contact'; adds dofs, mesh, "
            "solver and runtime_s {setup, cycles, total} to the JSON)")
    add_arguments = staticmethod(add_fe_options)

    @staticmethod
    def apparatus_result(profile, materials, app, mu, loading, args) -> dict:
        from fem.apparatus import fem_apparatus_result  # the FE model's imports only when it is used

        return fem_apparatus_result(profile, materials, app, mu, loading, fe_options(args))

    @staticmethod
    def session():
        """One BLAS thread for the whole block (the law's many small dense solves)."""
        from fem.solvers import blas_threads

        return blas_threads(1)

    @staticmethod
    def make_law(profile, materials, mu, F_max, args, coarsen=1.0):
        """The apparatus' FE law at ``coarsen`` times the element size of ``--h-contact``."""
        from fem.apparatus import fem_apparatus_law

        opts = fe_options(args)
        return fem_apparatus_law(profile, materials, mu, F_max, opts.replace(h_contact=opts.h * coarsen))


#: the FE law of ``python -m mdr apparatus/study --law fem`` (``studies.cli.contact_laws``)
FE_LAW = _FEApparatusLaw()
