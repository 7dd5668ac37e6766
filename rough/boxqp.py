"""The convex problem behind the rough contact's solves: minimise (1/2) q.Kq + q.s with a prescribed
total over a set per cell.

- A box |q| <= lim (``solve_box``; ``rough.tangential``'s Coulomb along x, and ``rough.normal``'s
  pressure capped at the hardness, 0 <= p <= H shifted to a symmetric box): a projected conjugate
  gradient on the free cells (Polonsky & Keer 1999, Wear 231, 206, with a two-sided box) whose steps
  keep the total exactly (``shift_to_total``).
- The same box without a prescribed total (``solve_box_free``; the displacement-controlled Coulomb of
  ``rough.law``): the projected conjugate gradient on the free cells.
- A disk |q| <= lim of a two-component q (``solve_disk``; Coulomb with the traction free to turn): an
  accelerated projected gradient whose projections keep the total (``project_disks_to_total``).
"""
from __future__ import annotations

import os

import numpy as np

from common.errors import ConvergenceError

try:  # optional dependency (pip install .[fast]): the dense box solve compiled
    import numba
except ImportError:  # pragma: no cover - the fallback is tested through COMPILED
    numba = None

#: solve the dense box problems compiled (``solve_box_free_dense``; False: numpy, the same iterates up to
#: round-off); off without numba or with the environment variable ROUGH_PURE_PYTHON=1
COMPILED = numba is not None and os.environ.get("ROUGH_PURE_PYTHON", "").strip() in ("", "0")

#: the projected CG's largest number of iterations
MAX_ITER = 5000
#: the floor of the residual's scale, as a fraction of the range of K lim (the displacement of the largest
#: traction the limits allow): the scale is the range of the current K q, which vanishes with q where the
#: answer is no traction at all (a contact that never slipped, unloaded to Q = 0: the problem is then
#: homogeneous, its residual over the range of K q scale-free, and the criterion could never be met)
SCALE_FLOOR = 1e-3


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


def _cg_step(apply_K, r, free, d, G_old, free_old, *, zero_mean: bool):
    """One step of the box solves' projected conjugate gradient from the residual ``r`` on the ``free``
    cells: the direction (conjugate to the last one ``d`` while the free set stays, steepest descent where
    it changed; zero off the free cells, and of zero mean on them where the total is prescribed) and the
    exact minimiser tau of the quadratic along it (steepest descent where the direction has no positive
    curvature). Returns (direction, tau, r.r)."""
    G = float(np.sum(r * r))
    if G_old is None or free_old is None or not np.array_equal(free, free_old):
        d = -r
    else:
        d = -r + (G / G_old) * d
    d = np.where(free, d, 0.0)
    if zero_mean:
        d[free] -= np.mean(d[free])
    curv = float(np.sum(d * apply_K(d)))
    if curv <= 0:
        d = -r
        curv = float(np.sum(d * apply_K(d)))
    return d, -float(np.sum(r * d)) / curv, G


def solve_box(apply_K, s, lim, Q, q, dA, tol, what="contact"):
    """The q minimising (1/2) q.Kq + q.s over |q| <= lim cell by cell with sum(q) dA = Q (``apply_K``: q ->
    K q, a symmetric positive semi-definite convolution whose mean mode is 0; cells of lim = 0 carry
    nothing), from the start ``q`` (clipped), to ``tol`` of the range of K q (at least ``SCALE_FLOOR`` of the range of K lim): its optimality conditions
    are, with delta the multiplier of the total, Kq + s = delta inside the box and on the side of each
    bound that keeps it there."""
    inside = lim > 0
    q = shift_to_total(q, lim, inside, Q, dA)
    d = np.zeros_like(q)
    G_old, free_old = None, None
    floor = SCALE_FLOOR * float(np.ptp(apply_K(lim)))
    for it in range(MAX_ITER):
        u = apply_K(q)
        g = u + s
        interior = inside & (np.abs(q) < lim * (1 - 1e-12))
        delta = float(np.mean(g[interior])) if interior.any() else float(np.mean(g[inside]))
        # a cell at its bound is free to leave it where its gradient points inwards
        free = interior | (inside & (q >= lim) & (g > delta)) | (inside & (q <= -lim) & (g < delta))
        r = np.where(free, g - np.mean(g[free]), 0.0)
        if np.max(np.abs(r)) <= tol * max(float(np.ptp(u)), floor, 1e-300):  # SCALE_FLOOR
            return q
        d, tau, G = _cg_step(apply_K, r, free, d, G_old, free_old, zero_mean=True)
        q = shift_to_total(np.clip(q + tau * d, -lim, lim), lim, free, Q, dA)
        G_old, free_old = G, free
    raise ConvergenceError(f"the {what} solve did not converge in {MAX_ITER} iterations")


def solve_box_free(apply_K, b, lim, q, tol, what="contact"):
    """The q minimising (1/2) q.Kq + q.b over |q| <= lim cell by cell, without a prescribed total
    (``apply_K``: q -> K q, symmetric positive definite: the window's Cerruti kernel, which holds the
    rigid mode; cells of lim = 0 carry nothing), from the start ``q`` (clipped), to ``tol`` of the largest
    |K q| (at least ``SCALE_FLOOR`` of the largest |K lim|): the projected conjugate gradient of
    ``solve_box`` without its total, the displacement control of ``rough.law`` (b = s - u, the slip
    so far minus the imposed displacement). Its optimality conditions: K q + b = 0 inside the box, and
    at a bound of the sign that keeps it there."""
    inside = lim > 0
    q = np.where(inside, np.clip(q, -lim, lim), 0.0)
    d = np.zeros_like(q)
    G_old, free_old = None, None
    # K is definite (no rigid mode to leave undetermined): the scales are magnitudes, not ranges (the range
    # of K q over a contact of one cell is 0, a criterion round-off never meets)
    floor = SCALE_FLOOR * float(np.max(np.abs(apply_K(lim)), initial=0.0))
    for it in range(MAX_ITER):
        u = apply_K(q)
        g = u + b
        interior = inside & (np.abs(q) < lim * (1 - 1e-12))
        free = interior | (inside & (q >= lim) & (g > 0)) | (inside & (q <= -lim) & (g < 0))
        r = np.where(free, g, 0.0)
        if np.max(np.abs(r), initial=0.0) <= tol * max(float(np.max(np.abs(u), initial=0.0)), floor, 1e-300):
            return q
        d, tau, G = _cg_step(apply_K, r, free, d, G_old, free_old, zero_mean=False)
        q = np.clip(q + tau * d, -lim, lim)
        G_old, free_old = G, free
    raise ConvergenceError(f"the {what} solve did not converge in {MAX_ITER} iterations")


def solve_box_free_dense(K: np.ndarray, b, lim, q, tol, what="contact"):
    """``solve_box_free`` with K a dense matrix (m, m) (float64; the rough law's compliance among a
    contact's cells): the same projected conjugate gradient, compiled where numba is installed
    (``COMPILED``; a small problem, so the cost of numpy's calls, not of the products, would dominate),
    else ``solve_box_free`` with K's product. The same iterates up to round-off (the sums' order)."""
    if not COMPILED:
        return solve_box_free(K.__matmul__, b, lim, q, tol, what)
    K = np.ascontiguousarray(K, dtype=float)
    lim = np.ascontiguousarray(lim, dtype=float)
    floor = SCALE_FLOOR * float(np.max(np.abs(K @ lim), initial=0.0))
    out, ok = _box_free_kernel(K, np.ascontiguousarray(b, dtype=float), lim,
                               np.ascontiguousarray(q, dtype=float), float(tol), floor, MAX_ITER)
    if not ok:
        raise ConvergenceError(f"the {what} solve did not converge in {MAX_ITER} iterations")
    return out


def _box_free_loop(K, b, lim, q0, tol, floor, max_iter):
    """``solve_box_free``'s iteration written out cell by cell (compiled by numba as ``_box_free_kernel``):
    returns (q, converged)."""
    m = b.size
    q = np.zeros(m)
    for i in range(m):
        if lim[i] > 0:
            q[i] = min(max(q0[i], -lim[i]), lim[i])
    d, r = np.zeros(m), np.zeros(m)
    free, free_old = np.zeros(m, dtype=np.bool_), np.zeros(m, dtype=np.bool_)
    G_old, first = 0.0, True
    for _ in range(max_iter):
        u = K @ q
        rmax, umax = 0.0, 0.0
        for i in range(m):
            g, li, qi = u[i] + b[i], lim[i], q[i]
            inside = li > 0
            f = inside and (abs(qi) < li * (1 - 1e-12) or (qi >= li and g > 0) or (qi <= -li and g < 0))
            free[i] = f
            r[i] = g if f else 0.0
            rmax, umax = max(rmax, abs(r[i])), max(umax, abs(u[i]))
        if rmax <= tol * max(umax, floor, 1e-300):
            return q, True
        G = 0.0
        for i in range(m):
            G += r[i] * r[i]
        same = not first
        if same:
            for i in range(m):
                if free[i] != free_old[i]:
                    same = False
                    break
        beta = G / G_old if same else 0.0
        for i in range(m):
            d[i] = (-r[i] + beta * d[i]) if free[i] else 0.0
        Kd = K @ d
        curv = 0.0
        for i in range(m):
            curv += d[i] * Kd[i]
        if curv <= 0:
            for i in range(m):
                d[i] = -r[i]
            Kd = K @ d
            curv = 0.0
            for i in range(m):
                curv += d[i] * Kd[i]
        rd = 0.0
        for i in range(m):
            rd += r[i] * d[i]
        tau = -rd / curv
        for i in range(m):
            q[i] = min(max(q[i] + tau * d[i], -lim[i]), lim[i])
        G_old, first = G, False
        free_old[:] = free
    return q, False


_box_free_kernel = numba.njit(cache=True, error_model="numpy")(_box_free_loop) if numba is not None else _box_free_loop


#: the disk solve's largest number of iterations (an accelerated projected gradient converges linearly,
#: slower than the box's conjugate gradient: its rate is 1 - 1 / sqrt(condition))
MAX_ITER_DISK = 20000


def project_disks_to_total(v, lim, inside, T, dA, start=None, with_multiplier=False):
    """The Euclidean projection of the traction field ``v`` (2, n, n) onto {|q_i| <= lim_i cell by cell,
    sum(q) dA = T} (T a 2-vector; cells outside ``inside`` carry nothing): q_i = P_i(v_i + c) with P_i
    the projection onto cell i's disk and c the multiplier of the total, the minimiser of the convex
    phi(c) = sum_i e_i(v_i + c) - c.T / dA (grad e_i = P_i), found by Newton's method with a
    backtracking line search on phi, from ``start`` (a previous projection's c; default 0). With
    ``with_multiplier`` it returns (q, c)."""
    x, l = v[:, inside], lim[inside]
    target = np.asarray(T, dtype=float) / dA
    scale_T = float(l.sum()) + float(np.hypot(*target))

    def parts(c):
        w = x + c[:, None]
        r = np.hypot(w[0], w[1])
        out = r > l
        f = np.where(out, l / np.where(out, r, 1.0), 1.0)
        return w, r, out, f

    def phi(c):
        """phi(c) and the size of its terms (the scale of its round-off)."""
        w, r, out, _ = parts(c)
        e = float(np.sum(0.5 * r ** 2 - 0.5 * np.where(out, r - l, 0.0) ** 2))
        return e - float(c @ target), abs(e) + abs(float(c @ target))

    def gradient(c):
        w, r, out, f = parts(c)
        return (w * f).sum(axis=1) - target

    c = np.zeros(2) if start is None else np.array(start, dtype=float)
    for _ in range(200):
        w, r, out, f = parts(c)
        grad = (w * f).sum(axis=1) - target
        g_norm = float(np.hypot(*grad))
        if g_norm <= 1e-12 * scale_T:
            break
        u = np.where(out, w / np.where(r > 0, r, 1.0), 0.0)
        H = np.eye(2) * float(np.count_nonzero(~out))
        fo = f[out]
        H += np.eye(2) * float(fo.sum()) - np.einsum("k,ik,jk->ij", fo, u[:, out], u[:, out])
        H += np.eye(2) * 1e-12 * max(float(np.trace(H)), 1.0)
        dc = -np.linalg.solve(H, grad)
        (p0, size), slope, t = phi(c), float(grad @ dc), 1.0

        def accepted(t):
            # Armijo's decrease, or, where the decrease is below phi's round-off (near the root), a
            # smaller gradient: phi can no longer tell the steps apart, its gradient still can
            p1, _ = phi(c + t * dc)
            if p1 <= p0 + 1e-4 * t * slope:
                return True
            return abs(p1 - p0) <= 1e-12 * size and float(np.hypot(*gradient(c + t * dc))) < g_norm

        while not accepted(t) and t > 1e-12:
            t *= 0.5
        if t <= 1e-12 or np.all(c + t * dc == c):  # round-off: phi no longer decreases
            break
        c = c + t * dc
    w, r, out, f = parts(c)
    q = np.zeros_like(v)
    q[:, inside] = w * f
    return (q, c) if with_multiplier else q


def solve_disk(apply_K, s, lim, Q, q, dA, tol, L, what="contact"):
    """The q (2, n, n) minimising (1/2) q.Kq + q.s over the disks |q_i| <= lim_i with sum(q) dA = Q (a
    2-vector; ``apply_K``: q -> K q, symmetric positive semi-definite with largest eigenvalue at most
    ``L``), from the start ``q``, to ``tol`` (``_disk_residual``): an accelerated projected gradient
    (Nesterov's, FISTA; Beck & Teboulle 2009, SIAM J. Imaging Sci. 2, 183) with the adaptive restart of
    O'Donoghue & Candes (2015, Found. Comput. Math. 15, 715), each step projected onto the disks and the
    total (``project_disks_to_total``). Its fixed point is Coulomb's law with a turning traction: with
    delta the multiplier of the total, K q + s = delta where |q| < lim, and q = lim times the unit
    vector of delta - K q - s where that would leave the disk."""
    inside = lim > 0
    q = project_disks_to_total(q, lim, inside, Q, dA)
    y, t, c = q.copy(), 1.0, None
    floor = SCALE_FLOOR * float(np.ptp(np.hypot(*apply_K(np.stack([lim, np.zeros_like(lim)])))))
    for it in range(MAX_ITER_DISK):
        u = apply_K(y)
        # the multiplier moves little from one iteration to the next: each projection starts from the last
        q_new, c = project_disks_to_total(y - (u + s) / L, lim, inside, Q, dA, start=c, with_multiplier=True)
        step = y - q_new
        if it % 10 == 0 and _disk_residual(apply_K, s, lim, inside, q_new, floor) <= tol:
            return q_new
        if float(np.sum(step * (q_new - q))) > 0.0:  # the momentum points uphill: restart
            t = 1.0
        t_new = 0.5 * (1.0 + np.sqrt(1.0 + 4.0 * t * t))
        y = q_new + ((t - 1.0) / t_new) * (q_new - q)
        q, t = q_new, t_new
    raise ConvergenceError(f"the {what} solve did not converge in {MAX_ITER_DISK} iterations")


def _disk_residual(apply_K, s, lim, inside, q, floor=0.0) -> float:
    """Coulomb's law with a turning traction violated, relative to the range of |K q| (at least ``floor``,
    ``SCALE_FLOOR``): with g = K q + s
    and delta its mean over the cells inside their disks, the largest of |g - delta| inside a disk and,
    on a disk's rim, of the slip increment delta - g across q and against it (every cell counts,
    however small its limit: a residual in q would let the rim cells of a vanishing pressure point
    anywhere)."""
    u = apply_K(q)
    g = u + s
    mag = np.hypot(q[0], q[1])
    interior = inside & (mag < lim * (1 - 1e-12))
    delta = g[:, interior if interior.any() else inside].mean(axis=1)
    ds = delta[:, None, None] - g
    rim = inside & ~interior
    qh = q / np.where(mag > 0, mag, 1.0)
    along = np.sum(ds * qh, axis=0)
    across = np.hypot(ds[0] - along * qh[0], ds[1] - along * qh[1])
    res = np.where(interior, np.hypot(ds[0], ds[1]), 0.0)
    res = np.maximum(res, np.where(rim, across + np.maximum(-along, 0.0), 0.0))
    return float(np.max(res)) / max(float(np.ptp(np.hypot(u[0], u[1]))), floor, 1e-300)
