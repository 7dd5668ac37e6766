"""The spring cells of the MDR contact law as functions: what ``mdr.law.MDRContact`` does to them.

- ``law_grid``: the spring grid of a profile, sized by the largest normal force (or contact
  radius) of the history, with a node at the smallest contact radius when given.
- ``normal_phase``: the normal update at an approach d: contact radius, in-contact length,
  normal force and tangential slip limit of every cell (exact cell integrals of ``mdr.grid``).
- ``carry``, ``tangential_force``, ``cell_slack``: the tangential displacement kept when a cell's
  contact length changes, the tangential force of the cells, and their slack to the slip limit
  with the slip flags (the input of ``mdr.stick``).
- ``flat_radius``, ``stick_nodes``: the radius of a flat face and the nodes the stick radius is
  resolved on.
- ``solve_du``: the tangential increment of a step under force control.

Assumptions: Popov & Hess's incremental MDR model as in ``mdr.law`` (independent springs, local
Coulomb friction with one mu, no normal-tangential coupling); every array has the law's batch
shape in front (cells: batch + (n,), steps: batch + (T,)); nothing here keeps state.
"""
from __future__ import annotations

import numpy as np

from common.errors import InputError, nonnegative, positive
from .grid import SpringGrid, make_grid
from .law_types import NormalPhase
from .normal import approach_from_force
from .profiles import FlatPunch, TruncatedSphere
from .solve import solve_increasing
from .stick import at_limit


def law_grid(profile, materials, *, F_max=None, a_max=None, n, F_min=None, refine=0.0) -> SpringGrid:
    """Spring grid of ``profile`` to a_max (the flat punch: its radius; otherwise the contact
    radius at F_max unless a_max is given), with a node at the contact radius at F_min > 0."""
    if isinstance(profile, FlatPunch):
        a_max = profile.b
    elif a_max is None:
        if F_max is None:
            raise InputError("MDRContact needs F_max (> 0, the largest normal force) or a_max to size its spring grid")
        F_max = positive("F_max", F_max)
        a_max = profile.g_inv(approach_from_force(profile, materials, F_max))
    a_min = None
    if F_min is not None:
        F_min = nonnegative("F_min", F_min)
    if F_min is not None and not isinstance(profile, FlatPunch) and np.all(np.asarray(F_min) > 0):
        a_min = profile.g_inv(approach_from_force(profile, materials, F_min))
    return make_grid(profile, a_max, n=n, a_min=a_min, refine=refine)


def normal_phase(profile, grid: SpringGrid, batch: tuple, E_star, G_star, mu, d) -> NormalPhase:
    """Normal contact for approach ``d`` of shape batch or batch + (T,)."""
    d = np.asarray(d, dtype=float)
    nb = len(batch)
    extra = d.ndim - nb
    if extra not in (0, 1) or d.shape[:nb] != batch:
        raise InputError(f"approach d must have shape {batch} or {batch} + (T,), got {d.shape}")

    def cells(arr):  # batch + (n,) -> batch + (1,)*extra + (n,)
        return arr.reshape(batch + (1,) * extra + (arr.shape[-1],))

    lo, width, int_g = cells(grid.lo), cells(grid.width), cells(grid.int_g)
    dp = np.maximum(d, 0.0)
    touching = d > 0
    a = np.where(touching, profile.g_inv(dp), 0.0)
    x_max = grid.x_max.reshape(batch + (1,) * extra)
    if np.any(a > x_max * (1 + 1e-9)):
        raise InputError("the contact radius exceeds the spring grid: build the law with a larger F_max (or a_max)")
    a = np.minimum(a, x_max)
    ell = np.clip(a[..., None] - lo, 0.0, width)
    full = ell >= width
    ig = np.where(full, int_g, 0.0)
    # the one partly covered cell: exact integral of g over [lo_k, a]
    k = np.sum(full, axis=-1, keepdims=True)
    has_partial = (k < width.shape[-1]) & (a[..., None] > 0)
    kk = np.minimum(k, width.shape[-1] - 1)
    lo_k = np.take_along_axis(np.broadcast_to(lo, ell.shape), kk, axis=-1)[..., 0]
    part = np.where(has_partial[..., 0] & (a > lo_k), profile.cell_integral(lo_k, np.maximum(a, lo_k)), 0.0)
    np.put_along_axis(ig, kk, np.where(has_partial, part[..., None], np.take_along_axis(ig, kk, axis=-1)), axis=-1)
    N = E_star * np.maximum(dp[..., None] * ell - ig, 0.0)
    mu = np.asarray(mu, dtype=float).reshape(batch + (1,) * (extra + 1)) if np.ndim(mu) else mu
    with np.errstate(divide="ignore", invalid="ignore"):
        vmax = np.where(ell > 0, mu * N / (G_star * ell), 0.0)
    return NormalPhase(d=dp, a=a, ell=ell, N=N, vmax=vmax, FN=2.0 * np.sum(N, axis=-1))


def carry(v, ell_old, ell_new):
    """Tangential displacement after the contact length of each cell changed."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(ell_new > 0, np.minimum(1.0, ell_old / ell_new), 0.0)
    return v * ratio


def tangential_force(G_star, ell, v):
    """Tangential force 2 G* sum ell v of the cells (both sides of the symmetric row)."""
    return 2.0 * G_star * np.sum(ell * v, axis=-1)


def cell_slack(phase: NormalPhase, trial, carried):
    """Per cell: slack vmax - |trial| to the slip limit, and slipping (at the limit, clipped
    in the normal update, or out of contact); the input of ``mdr.stick``."""
    slack = phase.vmax - np.abs(trial)
    return slack, at_limit(slack, phase.vmax) | (np.abs(carried) > phase.vmax) | (phase.ell <= 0)


def flat_radius(profile, batch: tuple):
    """Radius b of the flat face (batch array), or None for a profile without one."""
    if not isinstance(profile, (FlatPunch, TruncatedSphere)):
        return None
    b = np.asarray(getattr(profile, "b", 0.0), dtype=float)
    return None if not np.any(b > 0) else np.broadcast_to(b, batch)


def stick_nodes(grid: SpringGrid, b):
    """Radii of the nodes the stick radius is resolved on (batch + (n,)): the cell midpoints,
    and the outer edge of a cell of a flat face of radius ``b`` (``flat_radius``; None: no flat
    face). The springs of such a cell are identical: where one sticks, the whole cell sticks."""
    if b is None:
        return grid.mid
    return np.where(grid.edges[..., 1:] <= b[..., None] * (1 + 1e-12), grid.edges[..., 1:], grid.mid)


def solve_du(phase: NormalPhase, v1, target, mu, G_star):
    """Tangential increment du of a step under force control: the total force of the cells at
    v1 + du equals ``target`` (safeguarded Newton, ``mdr.solve.solve_increasing``); raises when
    |target| reaches the friction limit mu F_N."""
    mu_FN = np.asarray(mu) * phase.FN
    if np.any(np.abs(target) >= mu_FN * (1 - 1e-12)) and np.any(np.abs(target) > 0):
        bad = np.abs(target) >= mu_FN * (1 - 1e-12)
        raise InputError(f"tangential force Fx={float(np.max(np.abs(target[bad]) if np.ndim(target) else abs(target))):.4g} N "
                         f"must stay below the friction limit mu*F_N={float(np.min(mu_FN[bad]) if np.ndim(mu_FN) else mu_FN):.4g} N "
                         f"under force control (beyond it the contact slides without equilibrium)")
    lo = np.min(np.where(phase.ell > 0, -phase.vmax - v1, 0.0), axis=-1)
    hi = np.max(np.where(phase.ell > 0, phase.vmax - v1, 0.0), axis=-1)
    k = 2.0 * G_star * phase.ell

    def fun(du):
        t = v1 + du[..., None]
        stick = np.abs(t) < phase.vmax
        return np.sum(k * np.clip(t, -phase.vmax, phase.vmax), axis=-1), np.sum(k * stick, axis=-1)

    scale = np.maximum(mu_FN, 1e-300)
    return solve_increasing(fun, target, lo, hi, x0=np.zeros_like(target), atol=1e-12 * scale,
                            what="MDR tangential force control")
