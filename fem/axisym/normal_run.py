"""One FE normal-contact run from scene parameters: mesh (cached) -> model -> solve -> plain data.

The mesh's reference contact radius ``a_ref`` is the half-space estimate for
the load (Hertz, truncated-sphere closed form, or b for the flat punch, from
``mdr.reference``); the uniformly fine contact segment extends to
``contact_extent * a_ref`` (1.25 by default) and the block and indenter
default to 200 a_ref. A contact that reaches the end of the segment is an
error (raise ``contact_extent``), never a silent truncation.
"""
from __future__ import annotations

import time
import warnings

from common.errors import ConvergenceError, in_range, positive
from mdr.materials import Materials
from mdr.profiles import make_profile
from mdr.reference import hertz, truncated_contact_radius
from meshes import AxisymMeshParams, cached_mesh
from meshes.axisym import CONTACT_EXTENT_DEFAULT, H_CONTACT_DEFAULT, H_CONTACT_RANGE  # noqa: F401 (one home: meshes.axisym)

from fem.axisym.model import build_model
from fem.axisym.normal import DEFAULT_AL_TOL, DEFAULT_PENALTY, solve_normal

#: coarser than this (h > a/10) the contact holds fewer than ~20 pairs: warned (see mesh_params)
H_CONTACT_COARSE = 0.1


def reference_radius(profile: str, R, b, F, E_star) -> float:
    """Half-space contact radius for the load (the mesh's a_ref)."""
    if profile == "sphere":
        return float(hertz(F, R, E_star)["a"])
    if profile == "truncated":
        return float(truncated_contact_radius(F, R, b, E_star))
    return float(b)


def mesh_params(profile, R, b, F, materials: Materials, *, h_contact=H_CONTACT_DEFAULT, block_size=None,
                contact_extent=CONTACT_EXTENT_DEFAULT, a_ref=None, **kw) -> AxisymMeshParams:
    """Mesh parameters for a scene (validates the scene's input)."""
    make_profile(profile, R, b)  # validates profile, R, b (b < R, b > 0 for flat)
    positive("F", F)
    in_range("h_contact", h_contact, *H_CONTACT_RANGE)
    if h_contact > H_CONTACT_COARSE:
        warnings.warn(f"coarse contact mesh h_contact = {h_contact:g} (a/{1 / h_contact:.3g}): the contact radius "
                      f"holds about {2 / h_contact:.0f} pairs; expect errors of several % in the stick radius "
                      f"and dissipation (4-6 % at a/5, < 0.5 % at a/80)", RuntimeWarning, stacklevel=3)
    if block_size is not None:
        positive("block_size", block_size)
    a = a_ref if a_ref is not None else reference_radius(profile, R, b, F, materials.E_star)
    return AxisymMeshParams(profile, None if profile == "flat" else R, 0.0 if profile == "sphere" else b, a,
                            h_contact=h_contact, contact_extent=contact_extent, block_radius=block_size,
                            block_height=block_size, **kw)


def run_normal(profile, *, R=None, b=0.0, F, materials: Materials | None = None, h_contact=H_CONTACT_DEFAULT,
               block_size=None, contact_extent=CONTACT_EXTENT_DEFAULT, penalty=DEFAULT_PENALTY, al_tol=DEFAULT_AL_TOL,
               cache_dir=None, backend=None, rigid_indenter=False, return_model=False, exact=False, fillet=None,
               **mesh_kw):
    """FE normal contact at force F; returns the result dict of ``python -m fem normal``.

    ``exact``: the exact spherical cap instead of the parabola (sphere, truncated; the
    ``--exact-cap`` of the commands; the mesh is the same). ``fillet`` (m, truncated): the kink rounded
    (``mdr.profiles.RoundedTruncatedSphere``; the gap of the contact pairs, on the sharp cap's mesh:
    the fillet changes the surface by at most w b / (2R), nanometres, far below an element)."""
    materials = materials or Materials()
    # validates names and rejects conflicting parameters (b of a sphere, R of a flat punch, a fillet without a kink)
    prof = make_profile(profile, R, b, exact=exact, fillet=fillet)
    if profile == "sphere":
        b = 0.0
    t0 = time.perf_counter()
    params = mesh_params(profile, R, b, F, materials, h_contact=h_contact, block_size=block_size,
                         contact_extent=contact_extent, **mesh_kw)
    amesh = cached_mesh(params, cache_dir)
    t1 = time.perf_counter()
    model = build_model(amesh, materials, prof, backend=backend,
                        rigid_indenter=rigid_indenter)
    t2 = time.perf_counter()
    res = solve_normal(model, force=F, penalty=penalty, al_tol=al_tol)
    t3 = time.perf_counter()
    if not model.profile.edge_fixed and res.lam[-1] > 0:
        raise ConvergenceError(f"the contact reaches the end of the contact segment "
                               f"(r = {model.interface.r[-1]:.4g} m): raise contact_extent "
                               f"(now {contact_extent:g})")
    out = {
        "contact_radius": res.contact_radius,
        "pressure_radius": res.pressure_radius,
        "indentation": res.indentation,
        "normal_force": res.force,
        "pressure": {"r": res.r, "p": res.pressure},
        "approach": res.approach,
        "p0": res.p0,
        "penalty_error": res.penetration,
        "dofs": model.dofs,
        "interface_pairs": model.interface.n,
        "solver": {"backend": model.backend, "newton_iterations": res.newton_iterations,
                   "al_iterations": res.al_iterations, "penalty": penalty, "al_tol": al_tol,
                   "rigid_indenter": rigid_indenter},
        "probe": res.probe,
        "materials": materials.as_dict(),
        "profile": model.profile.describe(),
        "mesh": dict(amesh.params.as_dict(), key=amesh.key, cache=amesh.info.get("cache")),
        "runtime_s": {"mesh": t1 - t0, "setup": t2 - t1, "solve": t3 - t2, "total": t3 - t0},
    }
    if return_model:
        return out, model, res
    return out
