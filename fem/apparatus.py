"""The FE contact law in the apparatus: ``python -m mdr apparatus --law fem``.

The command (``studies.cli``, a layer above ``fem``) takes :data:`fem.cli.FE_LAW` (in ``fem.cli``,
so building the parser stays cheap): it adds the FE flags and calls :func:`fem_apparatus_result`
here. The apparatus model itself (``mdr.apparatus``) knows only the contact-law protocol.
"""
from __future__ import annotations

import time

import numpy as np

from mdr.apparatus import Apparatus, apparatus_result
from mdr.loading import Loading
from common.errors import InputError, in_range, nonnegative, positive
from meshes.axisym import H_CONTACT_DEFAULT, H_CONTACT_RANGE

from fem.axisym.friction import DEFAULT_FRICTION_AL_TOL
from fem.axisym.law import FEContact
from fem.axisym.normal import DEFAULT_AL_TOL, DEFAULT_PENALTY
from fem.solvers import blas_threads


def fem_apparatus_law(profile, materials, mu, F_max, *, h_contact=H_CONTACT_DEFAULT, contact_extent=1.25,
                      block_size=None, penalty=None, al_tol=None, friction_al_tol=None, cache_dir=None,
                      backend=None) -> FEContact:
    """The FE law of the apparatus: ``fem.axisym.law.FEContact(..., displacement="contact")``, its
    options validated before the (costly) set-up. Its displacement excludes the finite
    bodies' bulk compliance, so it stands where the half-space law stands and the apparatus
    compliances are not counted twice (see ``fem.axisym.law``). The law is pure (explicit state):
    one law serves every apparatus scene of its geometry, materials, mu and F_max."""
    penalty = DEFAULT_PENALTY if penalty is None else penalty
    al_tol = DEFAULT_AL_TOL if al_tol is None else al_tol
    friction_al_tol = DEFAULT_FRICTION_AL_TOL if friction_al_tol is None else friction_al_tol
    nonnegative("mu", mu)
    in_range("h_contact", h_contact, *H_CONTACT_RANGE)
    positive("penalty", penalty)
    nonnegative("al_tol", al_tol)
    nonnegative("friction_al_tol", friction_al_tol)
    if block_size is not None:
        positive("block_size", block_size)
    if not (np.ndim(contact_extent) == 0 and np.isfinite(contact_extent) and contact_extent > 1):
        raise InputError(f"contact_extent must be > 1 (finite), got {contact_extent!r}")
    return FEContact(profile, materials, mu, F_max=F_max, h_contact=h_contact, contact_extent=contact_extent,
                     block_size=block_size, penalty=penalty, al_tol=al_tol, friction_al_tol=friction_al_tol,
                     cache_dir=cache_dir, backend=backend, displacement="contact")


def fem_apparatus_result(profile, materials, app: Apparatus, mu, loading: Loading, **fe_options) -> dict:
    """One apparatus scene with the FE contact law (``python -m mdr apparatus --law fem``).

    The law is :func:`fem_apparatus_law` with ``F_max = F0 + dF`` of ``loading``
    (``Loading.apparatus``) (``fe_options``: its
    keyword arguments). Keys: those of :func:`apparatus_result` (with
    ``contact_radius``/``indentation`` the FE's own at F0) plus ``dofs``, ``mesh``,
    ``solver`` and ``runtime_s`` = {setup, cycles, total} like ``python -m fem contact``.
    The load is checked (a ``Loading``) before the (costly) FE set-up.
    """
    t0 = time.perf_counter()
    with blas_threads(1):  # once for the whole run: the law's steps are many small dense solves
        law = fem_apparatus_law(profile, materials, mu, loading.F_max, **fe_options)
        t1 = time.perf_counter()
        out = apparatus_result(law, app, loading)
    t2 = time.perf_counter()
    out.update(law.result_keys(loading.F0, t0, t1, t2))
    out["inputs"]["law"] = law.describe()
    return out
