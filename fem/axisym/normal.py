"""Frictionless normal contact on the condensed interface: penalty + augmented Lagrangian.

Problem (pairs i of ``fem.axisym.interface``, forces lam_i >= 0 in compression):

    gap_i = gap0_i - d + (C lam)_i,        C = C_indenter + N C_block N^T,

with either the force ``F = sum lam_i`` or the approach ``d`` prescribed.
Contact law (penalty, augmented Lagrangian form):

    lam_i = max(0, lbar_i - k_i gap_i),        k_i = eps * w_i,  eps = penalty * E* / h,

with w_i the pair area and h the contact element size. ``lbar = 0`` is the pure
penalty method; its error is the penetration max(-gap) > 0 (the pressure
equals eps times the penetration). Uzawa / augmented Lagrangian iterations
(Powell 1969, Hestenes 1969; for contact: Simo & Laursen, Computers &
Structures 42 (1992) 97) set lbar <- lam and re-solve until the largest
penetration is below ``al_tol`` times the approach: this drives the penalty
error to zero without ill-conditioning. Each solve is a semi-smooth Newton
method, which for this piecewise-linear law is a primal-dual active-set
iteration (Hintermueller, Ito & Kunisch, SIAM J. Optim. 13 (2002) 865): on the
active set A the equations are linear and symmetric,

    (C_AA + diag(1/k_A)) lam_A - d 1 = lbar_A / k_A - gap0_A,   1^T lam_A = F,

solved by a dense Cholesky of an |A| x |A| matrix; A is updated from the sign of
lbar - k gap until it repeats.

Outputs (``NormalResult``): F_N, the approach ``d`` (indenter top to block
bottom, includes the finite bodies' bulk compliance), the half-space-comparable
indentation (``fem.bulk``), nodal pressures p_i = lam_i / w_i, the contact radius and
the penalty error (relative penetration), and ``pressure_radius``, the pressure's
second-moment radius (``mdr.normal.moment_radius``) from the pair forces, sum lam_i r_i^2.

Half-space-comparable indentation: the approach of two axis probes plus the Boussinesq
displacement below them, ``fem.bulk.normal_indentation`` (the one home of both bulk
corrections, normal and tangential).

Contact radius. The nodal spacing is h/2; the edge is located between the
last loaded node and the next from the pressure profile: near a smooth
contact edge p^2 is linear in r^2 (exact for Hertz), so a straight line through
(r^2, p^2) of the last three loaded nodes is extrapolated to p = 0 (clipped to
the bracketing nodes). For a fixed edge (flat punch) it is the punch radius.
The pressure on the axis (where the pair area is zero) is extrapolated from
the first three pairs: p interpolated as a quadratic in r^2 (p is even in r),
exact to O(r^6).
"""
from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from common.errors import ConvergenceError, InputError, nonnegative, positive, positive_int
from fem.axisym.friction import SetFactors
from mdr.normal import moment_radius

from fem.bulk import normal_indentation
from fem.solvers import blas_threads

DEFAULT_PENALTY = 100.0
DEFAULT_AL_TOL = 1e-8
#: pure penalty (al_tol = 0) with a relative penetration above this is warned (a too soft penalty)
PENALTY_WARN = 1e-3


@dataclass
class NormalResult:
    force: float
    approach: float
    indentation: float
    contact_radius: float
    r: np.ndarray
    pressure: np.ndarray
    lam: np.ndarray
    gap: np.ndarray
    p0: float
    penetration: float
    active: int
    newton_iterations: int
    al_iterations: int
    probe: dict = field(default_factory=dict)
    runtime_s: float = 0.0
    pressure_radius: float = float("nan")


def _active_solve(fac, gap0, k, lbar, A, force, approach):
    """Solve the linear equations on active set A (``fac``: the factors of C + diag(1/k) by set); return
    (lam, d)."""
    n = gap0.size
    lam = np.zeros(n)
    if not np.any(A):
        if force is not None:
            raise ConvergenceError("empty active set under a positive force")
        return lam, approach
    f = fac.get(A)
    x = f.solve(lbar[A] / k[A] - gap0[A])
    d = approach if force is None else (force - x.sum()) / f.ysum
    lam[A] = x + d * f.y
    return lam, d


def _semismooth_newton(C, fac, gap0, k, lbar, force, approach, A0, max_iter):
    A = A0.copy()
    seen = set()
    for it in range(1, max_iter + 1):
        lam, d = _active_solve(fac, gap0, k, lbar, A, force, approach)
        gap = gap0 - d + C @ lam
        A_new = (lbar - k * gap) > 0.0
        if np.array_equal(A_new, A):
            return np.maximum(lam, 0.0), d, gap, A, it
        key = A_new.tobytes()
        if key in seen:
            # cycling between active sets: damp by keeping the union (monotone safeguard)
            A_new = A_new | A
        seen.add(key)
        A = A_new
    raise ConvergenceError(f"semi-smooth Newton: active set not settled after {max_iter} iterations")


def _set_factors(model, penalty, k) -> SetFactors:
    """The factors of C + diag(1/k) on active sets, kept on ``model`` per penalty: the passes of the
    augmented Lagrangian and the solves at nearby loads mostly meet the sets again (the same factor,
    so the same numbers)."""
    facs = model.normal_factors
    if penalty not in facs:
        facs[penalty] = SetFactors(model.C + np.diag(1.0 / k), size=8)
    return facs[penalty]


def _edge_radius(r, p, lam):
    """Contact edge from the pressure profile (see module docstring)."""
    act = np.flatnonzero(lam > 0)
    if act.size == 0:
        return 0.0
    j = act[-1]
    r_hi = r[j + 1] if j + 1 < r.size else r[j]
    if j < 2:
        return float(r[j])
    sel = slice(j - 2, j + 1)
    x, y = r[sel] ** 2, p[sel] ** 2
    slope, icpt = np.polyfit(x, y, 1)
    if slope >= 0:
        return float(r[j])
    a2 = -icpt / slope
    a = np.sqrt(max(a2, 0.0))
    return float(np.clip(a, r[j], r_hi))


def _axis_pressure(r, p):
    if r.size < 3:
        return float(p[0])
    c = np.polyfit(r[:3] ** 2, p[:3], 2 if r.size >= 3 else 1)
    return float(np.polyval(c, 0.0))


def penalty_stiffness(penalty, E_star, interface):
    """Penalty stiffness k_i = eps w_i (N/m) of the contact pairs, eps = penalty E* / h (N/m^3):
    the normal pairs here and the tangential ones of ``fem.axisym.law`` (the one home of the formula)."""
    eps = penalty * E_star / interface.h
    return eps * interface.w


def solve_normal(model, *, force=None, approach=None, penalty=DEFAULT_PENALTY, al_tol=DEFAULT_AL_TOL,
                 max_al=50, max_newton=100) -> NormalResult:
    """Normal contact under a prescribed ``force`` (N) or ``approach`` (m, indenter top to
    block bottom). ``penalty``: dimensionless, eps = penalty * E*/h; ``al_tol``: relative
    penetration (max(-gap)/d) at which augmented-Lagrangian iterations stop (0: pure
    penalty, one solve)."""
    t0 = time.perf_counter()
    if (force is None) == (approach is None):
        raise InputError("give exactly one of force (N, > 0) or approach (m, > 0)")
    if force is not None:
        force = positive("F", force)
    else:
        approach = positive("approach", approach)
    penalty = positive("penalty", penalty)
    al_tol = nonnegative("al_tol", al_tol)
    max_al = positive_int("max_al", max_al)
    iface = model.interface
    C, gap0 = model.C, iface.gap0
    k = penalty_stiffness(penalty, model.materials.E_star, iface)
    fac = _set_factors(model, penalty, k)
    lbar = np.zeros(iface.n)
    A = gap0 <= np.min(gap0) + 1e-300  # start from first contact
    if force is not None:
        # a better start: pairs inside a rough contact radius (fewer Newton steps)
        A = gap0 <= np.quantile(gap0, 0.5)
    n_newton = 0
    with blas_threads(1):
        for n_al in range(1, max_al + 1):
            lam, d, gap, A, nit = _semismooth_newton(C, fac, gap0, k, lbar, force, approach, A, max_newton)
            n_newton += nit
            pen = max(float(np.max(-gap[lam > 0], initial=0.0)), 0.0)
            rel_pen = pen / abs(d) if d != 0 else np.inf
            if al_tol == 0.0 or rel_pen <= al_tol:
                break
            lbar = lam.copy()
        else:
            raise ConvergenceError(f"augmented Lagrangian: penetration {rel_pen:.3g} (relative) above "
                                   f"al_tol={al_tol:g} after {max_al} iterations")
    if al_tol == 0.0 and rel_pen > PENALTY_WARN:
        warnings.warn(f"pure penalty (al_tol = 0): the penetration is {rel_pen:.3g} of the approach, above "
                      f"{PENALTY_WARN:g}; raise the penalty (now {penalty:g}) or use the augmented Lagrangian "
                      f"(al_tol > 0) to remove this error", RuntimeWarning, stacklevel=2)
    p = lam / iface.w
    F = float(lam.sum())
    if getattr(model.profile, "edge_fixed", False):
        a = float(model.profile.b)
    else:
        a = _edge_radius(iface.r, p, lam)
    p0 = _axis_pressure(iface.r, p)
    d_hs, probe = normal_indentation(model, lam, d)  # half-space-comparable indentation
    return NormalResult(force=F, approach=float(d), indentation=float(d_hs), contact_radius=a,
                        r=np.concatenate([[0.0], iface.r]), pressure=np.concatenate([[p0], p]), lam=lam,
                        gap=gap, p0=p0, penetration=rel_pen, active=int(np.count_nonzero(lam > 0)),
                        newton_iterations=n_newton, al_iterations=n_al, probe=probe,
                        runtime_s=time.perf_counter() - t0,
                        pressure_radius=moment_radius(F, float(lam @ iface.r ** 2)))
