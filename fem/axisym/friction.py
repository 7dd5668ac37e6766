"""Coulomb friction on the condensed interface: penalty return map, augmented Lagrangian,
and a primal-dual active-set (semi-smooth Newton) solver of each load increment.

Assumptions (the FE analogue of the Hertz-Mindlin / MDR assumptions):

- local Coulomb friction with a constant coefficient mu; the tangential traction
  is along x everywhere (Mindlin 1949, J. Appl. Mech. 16, 259), so each contact
  pair i carries one tangential force T_i (N, on the block, +x), conjugate to the
  mode-1 variable S (``fem.axisym.mode1``);
- the slip limit of pair i is g_i = mu lam_i with lam_i its mode-0 normal pair
  force at the same instant (no normal-tangential coupling: exact for equal
  materials in the half-space limit, neglected otherwise, as in MDR);
- rate independence: a load step is one increment of the return map.

Kinematics: the relative tangential displacement of pair i (indenter minus block)
is ``s = u 1 - Ct T`` with ``u`` the x translation of the indenter's top plate
(the block's bottom clamped) and ``Ct = C_t,indenter + N C_t,block N^T`` the
mode-1 interface flexibility. Each pair has a plastic (slip) displacement p_i
(the history variable). Penalty law with augmented-Lagrangian multiplier lbar:

    T_i = proj_[-g_i, g_i]( lbar_i + k_i (s_i - p_i,old) ),   k_i = eps w_i,

(the classical return map; Simo & Laursen, Computers & Structures 42 (1992) 97;
Wriggers, *Computational Contact Mechanics*, Springer 2006, ch. 10). For fixed
lbar this is the optimality condition of the strictly convex box-constrained
quadratic programme

    min_T  1/2 T^T M T - T^T (b + u 1),   |T_i| <= g_i,
    M = Ct + diag(1/k),   b = lbar/k - slip_old,

(with u as the multiplier of sum T = Fx under force control). It is solved by the
primal-dual active-set method, the semi-smooth Newton method of this problem
(Hintermueller, Ito & Kunisch, SIAM J. Optim. 13 (2002) 865): every pair is
free, sliding forward (+1) or sliding backward (-1), so the convergence test
includes the slip direction, not just the stick/slip split. The sets are
updated from the trial force ``T - k grad`` (which is the return-map trial).
If they cycle, the iteration is damped: the Newton candidate is accepted with
Armijo backtracking on the (convex) potential along the projected path, which
makes it monotone. The Uzawa / augmented-Lagrangian loop then sets lbar <- T
until the largest change is below ``al_tol`` times the largest slip limit;
at that point the stick pairs do not move relative to each other (exact
Coulomb), so the penalty error is removed, not just made small. That limit
(lbar = T) is itself the box QP above with M = Ct and b = -slip_old (the 1/k terms
cancel), so the same solver reaches it directly; ``fem.axisym.law.FEContact`` starts the
AL loop there, and its first pass checks the answer.
"""
from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from common.errors import ConvergenceError
from mdr.solve import regula_falsi_increasing

DEFAULT_FRICTION_AL_TOL = 1e-7


_POTRF, _POTRS = sla.get_lapack_funcs(("potrf", "potrs"), (np.zeros(1),))


class SetFactor:
    """Cholesky factor of M restricted to one free set, with y = M_ff^-1 1 and its sum (the
    stick-set tangent). Solves through LAPACK's potrs directly: these systems are small
    (tens of pairs) and solved thousands of times, so the checks of ``scipy.linalg.cho_solve``
    would cost more than the solve."""

    __slots__ = ("c", "y", "ysum")

    def __init__(self, Mff):
        c, info = _POTRF(Mff, lower=1, clean=1)
        if info != 0:
            raise np.linalg.LinAlgError(f"the flexibility restricted to the {Mff.shape[0]} pairs of a set "
                                        f"is not positive definite (LAPACK potrf info {info})")
        self.c = c
        self.y = self.solve(np.ones(Mff.shape[0]))
        self.ysum = float(self.y.sum())

    def solve(self, rhs):
        x, info = _POTRS(self.c, rhs, lower=1)
        if info != 0:  # pragma: no cover - only for malformed arguments
            raise ValueError(f"LAPACK potrs: illegal argument {-info}")
        return x


class SetFactors:
    """Factors of M restricted to free sets (:class:`SetFactor`), cached by the set (the last ``size``
    sets): the friction's pairs here, the normal solver's active sets (``fem.axisym.normal``)."""

    def __init__(self, M, size=8):
        self.M = M
        self.size = size
        self.cache = {}

    def get(self, free) -> SetFactor:
        key = free.tobytes()
        f = self.cache.get(key)
        if f is None:
            if len(self.cache) >= self.size:
                self.cache.pop(next(iter(self.cache)))
            f = SetFactor(self.M[np.ix_(free, free)])
            self.cache[key] = f
        return f


def _solve_sets(M, fac, b, g, sgn, u, F):
    """Linear solve for fixed sets: free pairs sgn == 0 (with g > 0), bound T = sgn g."""
    T = np.where(sgn != 0, sgn * g, 0.0)
    free = (sgn == 0) & (g > 0)
    if not free.any():
        if u is None:  # force control with every pair sliding: u from the mean residual
            c = g > 0
            u = float(np.mean((M @ T - b)[c])) if c.any() else 0.0
        return T, u
    f = fac.get(free)
    x = f.solve(b[free] - (M @ T)[free])  # T = 0 on the free pairs: (M T)_free = M_fA T_A
    if F is not None:
        u = (F - T.sum() - x.sum()) / f.ysum
    T[free] = x + u * f.y
    return T, u


def _potential(M, b, u, T):
    return 0.5 * T @ (M @ T) - T @ (b + u)


def _signs(trial, g):
    return np.where(g > 0, np.where(trial > g, 1, np.where(trial < -g, -1, 0)), 0).astype(np.int8)


def solve_increment(M, fac, b, g, k, sgn0, *, u=None, F=None, max_iter=60):
    """Solve the box QP of one augmented-Lagrangian pass (see module docstring).

    Give the plate displacement ``u`` or the total force ``F``. Returns
    (T, u, sgn, iterations, trial): forces, plate displacement, final sets
    (+1/-1 sliding, 0 sticking), Newton iterations and the trial forces.
    Primal-dual active sets first; if the sets cycle, a projected Newton method
    with Armijo line search on the potential (displacement control), or a
    safeguarded secant search on the monotone force-displacement relation
    (force control).
    """
    sgn = np.where(g > 0, sgn0, 0).astype(np.int8)
    seen = set()
    for it in range(1, max_iter + 1):
        T, uu = _solve_sets(M, fac, b, g, sgn, u, F)
        grad = M @ T - b - uu
        trial = T - k * grad
        new = _signs(trial, g)
        if np.array_equal(new, sgn) and np.all(np.abs(T) <= g * (1 + 1e-12) + 1e-300):
            return T, uu, sgn, it, trial
        key = new.tobytes()
        if key in seen:
            break
        seen.add(key)
        sgn = new
    if F is not None:
        return _force_by_secant(M, fac, b, g, k, sgn, F, max_iter, it)
    return _projected_newton(M, fac, b, g, k, u, np.clip(T, -g, g), max_iter, it)


def slip_update(s, T, lbar, k, contact, slip_old):
    """Plastic slip and friction work after a converged increment of :func:`solve_increment`.

    ``s``: relative tangential displacements ``u 1 - Ct T`` (module docstring), ``T`` the
    pair forces, ``lbar`` the augmented-Lagrangian multipliers of the last pass, ``k`` the
    penalty stiffnesses, ``contact`` the pairs with a slip limit g > 0, ``slip_old`` the slip of
    the previous step. Returns ``(slip_new, work)``: the penalty law's elastic part removed,
    ``slip_new = s - (T - lbar)/k`` in contact (the pair's new plastic slip), ``slip_new = s`` out of
    contact (a free pair follows the relative displacement); ``work`` the friction work of the
    increment, the sum over the contact pairs of the positive parts of ``T (slip_new - slip_old)`` (J).
    """
    slip_new = np.where(contact, s - (T - lbar) / k, s)
    work = float(np.sum(np.maximum(np.where(contact, T * (slip_new - slip_old), 0.0), 0.0)))
    return slip_new, work


def _projected_newton(M, fac, b, g, k, u, T, max_iter, it0):
    """Projected Newton (Bertsekas, SIAM J. Control Optim. 20 (1982) 221) for the box QP at
    fixed u: Newton steps on the pairs not held at a bound by the gradient, projected Armijo
    line search on the convex potential; monotone, so it cannot cycle."""
    gmax = float(np.max(g))
    c = g > 0
    absM = np.abs(M)
    for it in range(1, 20 * max_iter + 1):
        grad = M @ T - b - u
        trial = T - k * grad
        resid = np.abs(T - np.clip(trial, -g, g))
        # roundoff floor of the residual: grad is a difference of displacements of size
        # |M||T| + |b| + |u|, amplified by k; with a very stiff penalty this floor exceeds
        # 1e-10 gmax and the test could never be met (hard case "penalty too stiff")
        floor = 64.0 * np.finfo(float).eps * k * (absM @ np.abs(T) + np.abs(b) + abs(u))
        if np.all(resid <= 1e-10 * gmax + floor):
            return T, u, _signs(trial, g), it0 + it, trial
        eps = min(1e-9 * gmax, float(np.max(resid)))
        hold = ((T >= g - eps) & (grad < 0)) | ((T <= -g + eps) & (grad > 0)) | ~c
        free = ~hold
        d = np.zeros_like(T)
        if np.any(free):
            d[free] = -fac.get(free).solve(grad[free])
        phi0 = _potential(M, b, u, T)
        t = 1.0
        while True:
            Tt = np.clip(T + t * d, -g, g)
            if _potential(M, b, u, Tt) <= phi0 + 1e-4 * grad @ (Tt - T) or t < 1e-12:
                break
            t *= 0.5
        T = Tt
    raise ConvergenceError(f"friction projected Newton did not converge in {20 * max_iter} iterations "
                           f"(KKT residual {np.max(resid) / gmax:.3g} of the largest slip limit)")


def _force_by_secant(M, fac, b, g, k, sgn, F, max_iter, it0):
    """Force control fallback: sum T(u) is continuous and nondecreasing in u; bracket the
    target and use regula falsi (Illinois variant) on displacement-controlled solves."""
    def total(u):
        out = solve_increment(M, fac, b, g, k, sgn, u=u, max_iter=max_iter)
        return out[0].sum() - F, out

    scale = float(np.max(np.abs(b)) + np.max(g) * np.max(np.abs(np.diag(M)))) + 1e-300
    _, (T, u, s, it, trial) = regula_falsi_increasing(
        total, -scale, scale, 1e-12 * float(np.sum(g)), xtol=1e-15 * scale,
        what="friction force control: secant search on the plate displacement")
    return T, u, s, it0 + it, trial
