"""The command-line flags of the physics that ``python -m mdr`` and ``python -m fem`` share: the
indenter profile, the two materials and the harmonic fretting load (SI), and their conversion to
``mdr`` objects. The parser and the exit codes are ``common.cli``'s."""
from __future__ import annotations

from .materials import STEEL_E, STEEL_NU, Materials
from .profiles import make_profile


def add_profile_args(p):
    group = p.add_argument_group("indenter profile (SI units)")
    group.add_argument("--profile", choices=["sphere", "truncated", "flat"], required=True,
                   help="sphere (parabolic), truncated sphere (flat face of radius b), flat punch (radius b)")
    group.add_argument("--R", type=float, default=None, help="sphere radius R in m (sphere, truncated)")
    group.add_argument("--b", type=float, default=None, help="flat-face / punch radius b in m (truncated, flat)")
    group.add_argument("--exact-cap", action="store_true",
                   help="exact spherical cap instead of the parabolic approximation (sphere, truncated)")
    group.add_argument("--fillet", type=float, default=None, metavar="W",
                   help="truncated: the kink at r = b rounded by a circular fillet of radial width W in m "
                        "(mdr.profiles.RoundedTruncatedSphere; default: the sharp kink)")


def add_material_args(p):
    group = p.add_argument_group("materials: indenter 1, block 2 (Pa)")
    group.add_argument("--E1", type=float, default=STEEL_E, help="Young's modulus of the indenter (default 200e9)")
    group.add_argument("--nu1", type=float, default=STEEL_NU, help="Poisson ratio of the indenter (default 0.29)")
    group.add_argument("--E2", type=float, default=STEEL_E, help="Young's modulus of the block (default 200e9)")
    group.add_argument("--nu2", type=float, default=STEEL_NU, help="Poisson ratio of the block (default 0.29)")


def add_contact_args(p):
    group = p.add_argument_group("fretting load: F_N = F0 + dF sin(2 pi t + alpha); u = ua sin(2 pi t) or F_x = fa sin(2 pi t)")
    group.add_argument("--mu", type=float, required=True, help="coefficient of friction (>= 0)")
    group.add_argument("--F0", type=float, required=True, help="mean normal force in N (> 0)")
    group.add_argument("--dF", type=float, default=0.0, help="normal force amplitude in N (0 <= dF <= F0)")
    group.add_argument("--alpha", type=float, default=0.0, help="phase of the normal force in rad")
    drive = group.add_mutually_exclusive_group(required=True)
    drive.add_argument("--ua", type=float, help="tangential displacement amplitude in m (displacement control)")
    drive.add_argument("--fa", type=float, help="tangential force amplitude in N (force control, < mu F_N)")
    group.add_argument("--cycles", type=int, default=3, help="number of cycles (>= 2; the last one is reported; default 3)")
    group.add_argument("--steps", type=int, default=400, help="time steps per cycle (multiple of 4; default 400)")


def profile_from_args(args):
    return make_profile(args.profile, R=args.R, b=args.b, exact=getattr(args, "exact_cap", False),
                        fillet=getattr(args, "fillet", None))


def materials_from_args(args):
    return Materials(args.E1, args.nu1, args.E2, args.nu2)
