"""The one convex problem behind the rough contact's two solves (``rough.tangential``: Coulomb's box
|q| <= mu p; ``rough.normal``: a pressure capped at the hardness, 0 <= p <= H shifted to a symmetric
box): minimise (1/2) q.Kq + q.s over a box |q| <= lim cell by cell with a prescribed total, by a
projected conjugate gradient on the free cells (Polonsky & Keer 1999, Wear 231, 206, with a two-sided
box) whose steps keep the total exactly (``shift_to_total``).
"""
from __future__ import annotations

import numpy as np

from common.errors import ConvergenceError

#: the projected CG's largest number of iterations
MAX_ITER = 5000


def shift_to_total(q, lim, free, Q, dA):
    """q + c on the free cells, clipped to the box |q| <= lim, with the total Q (sum(q) dA): the one c
    where the clipped sum, piecewise linear and non-decreasing in c, meets Q (exact: its kinks sorted,
    the crossing interpolated on its linear piece; on a flat piece at Q, its left end)."""
    x, l = q[free], lim[free]
    fixed = float(np.clip(np.where(free, 0.0, q), -lim, lim).sum())
    target = float(Q) / dA - fixed
    # sum_i clip(x_i + c, -l_i, l_i) = -sum(l) + sum_i (c - lo_i)_+ - sum_i (c - hi_i)_+
    lo, hi = np.sort(-l - x), np.sort(l - x)
    knots = np.concatenate([lo, hi])
    knots.sort()
    c_lo, c_hi = np.cumsum(lo), np.cumsum(hi)

    def clipped_sum(c):
        i, j = np.searchsorted(lo, c, side="right"), np.searchsorted(hi, c, side="right")
        return (-float(l.sum()) + (i * c - (c_lo[i - 1] if i else 0.0))
                - (j * c - (c_hi[j - 1] if j else 0.0)))

    if knots.size == 0:
        return np.clip(q, -lim, lim)
    vals = np.array([clipped_sum(c) for c in (knots[0], knots[-1])])
    if target <= vals[0]:
        c = knots[0]
    elif target >= vals[1]:
        c = knots[-1]
    else:
        # bisection over the sorted knots for the piece that holds the target, then linear on it
        a, b = 0, knots.size - 1
        while b - a > 1:
            m = (a + b) // 2
            if clipped_sum(knots[m]) < target:
                a = m
            else:
                b = m
        fa, fb = clipped_sum(knots[a]), clipped_sum(knots[b])
        c = knots[a] if fb == fa else knots[a] + (target - fa) * (knots[b] - knots[a]) / (fb - fa)
    return np.clip(np.where(free, q + c, q), -lim, lim)


def solve_box(apply_K, s, lim, Q, q, dA, tol, what="contact"):
    """The q minimising (1/2) q.Kq + q.s over |q| <= lim cell by cell with sum(q) dA = Q (``apply_K``: q ->
    K q, a symmetric positive semi-definite convolution whose mean mode is 0; cells of lim = 0 carry
    nothing), from the start ``q`` (clipped), to ``tol`` of the range of K q: its optimality conditions
    are, with delta the multiplier of the total, Kq + s = delta inside the box and on the side of each
    bound that keeps it there."""
    inside = lim > 0
    q = shift_to_total(q, lim, inside, Q, dA)
    d = np.zeros_like(q)
    G_old, free_old = None, None
    for it in range(MAX_ITER):
        u = apply_K(q)
        g = u + s
        interior = inside & (np.abs(q) < lim * (1 - 1e-12))
        delta = float(np.mean(g[interior])) if interior.any() else float(np.mean(g[inside]))
        # a cell at its bound is free to leave it where its gradient points inwards
        free = interior | (inside & (q >= lim) & (g > delta)) | (inside & (q <= -lim) & (g < delta))
        r = np.where(free, g - np.mean(g[free]), 0.0)
        if np.max(np.abs(r)) <= tol * max(float(np.ptp(u)), 1e-300):  # the step's elastic displacement
            return q
        G = float(np.sum(r * r))
        if G_old is None or free_old is None or not np.array_equal(free, free_old):
            d = -r
        else:
            d = -r + (G / G_old) * d
        d = np.where(free, d, 0.0)
        d[free] -= np.mean(d[free])
        Kd = apply_K(d)
        curv = float(np.sum(d * Kd))
        if curv <= 0:
            d, Kd = -r, apply_K(-r)
            curv = float(np.sum(d * Kd))
        tau = -float(np.sum(r * d)) / curv
        q = shift_to_total(np.clip(q + tau * d, -lim, lim), lim, free, Q, dA)
        G_old, free_old = G, free
    raise ConvergenceError(f"the {what} solve did not converge in {MAX_ITER} iterations")
