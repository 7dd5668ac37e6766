"""Compiled time loops of the MDR contact law (numba): whole histories at compiled speed.

The step API of ``mdr.law`` (``step``, ``prepare``/``force``/``commit``) stays the
reference; these loops run the same arithmetic, spring cell by spring cell, for a
whole history and for every scene of a batch (scene by scene):

- ``law_history``: ``MDRContact.run`` under displacement control (u given) and under
  force control (F_x given). Within a step the tangential force of the cells is
  piecewise linear and nondecreasing in the step's displacement, so force control
  solves for it in the loop with the safeguarded Newton iteration of
  ``mdr.solve.solve_increasing`` (same bracket, start and tolerance), which ends
  exactly once it lands on the right linear piece.
- ``apparatus_loop``: the step loop of ``mdr.apparatus.run_apparatus`` with the MDR
  law and its MDR bedding spheres (one front, two equal rear ones) (Hertz approach, sphere normal phase and the
  moment coupling of the bedding loads in the loop), the same Newton iteration per step.
- ``approach_truncated_sphere``: ``mdr.normal.approach_from_force`` of the parabolic
  truncated sphere, the same batch iteration (identical to the last bit).

What stays in numpy, vectorised over all steps: the contact radius of each step and
the integral of g over its one partly covered cell (``normal_inputs``; any profile),
and the stick radius over a window (``mdr.stick.stick_radius``). Results equal those
of the step API to round-off (sums in another order; tests/test_mdr_kernels.py).

numba is optional (``pip install .[fast]``): without it, or with the environment
variable ``MDR_PURE_PYTHON=1``, or with ``ENABLED = False``, every history runs
through the step API. Compiled code is cached on disk (``cache=True``), so only the
first call after installation pays the compilation.
"""
from __future__ import annotations

import dataclasses
import math
import os

import numpy as np

from common.errors import ConvergenceError, InputError
from .profiles import TruncatedSphere
from .solve import MAX_ITER
from .stick import AT_LIMIT

try:  # optional dependency
    import numba
except ImportError:  # pragma: no cover - exercised by the fallback test through ENABLED
    numba = None

#: run histories through the compiled loops (False: the step API of mdr.law everywhere)
ENABLED = numba is not None and os.environ.get("MDR_PURE_PYTHON", "").strip() in ("", "0")

# status codes of a scene (the loop stops that scene at the first failing step)
OK, BEYOND_FRICTION, NO_CONVERGENCE, LIFT_OFF, BEYOND_GRID = 0, 1, 2, 3, 4


def enabled() -> bool:
    """True when the compiled loops are used (numba importable and not switched off)."""
    return bool(ENABLED) and numba is not None


if numba is not None:
    _jit = numba.njit(cache=True, error_model="numpy", nogil=True)
    # sums in any order (vectorised): only for sums, whose order is a round-off
    _jit_sum = numba.njit(cache=True, error_model="numpy", nogil=True, fastmath={"reassoc", "nsz"})
else:  # pragma: no cover
    def _jit(f):
        return f
    _jit_sum = _jit


# ------------------------------------------------------------------ one step, one scene
@_jit
def _count_full(a, lo, width):
    """Number of cells fully in contact at contact radius a (a prefix of the cells:
    a - lo_j >= width_j, the test of ``MDRContact.normal_phase``)."""
    i0, i1 = 0, lo.shape[0]
    while i0 < i1:
        m = (i0 + i1) // 2
        if a - lo[m] >= width[m]:
            i0 = m + 1
        else:
            i1 = m
    return i0


@_jit
def full_cells(a, lo, width, out):
    """``_count_full`` for every scene s and step t: a (S, T), lo/width (S, n) -> out (S, T)."""
    for s in range(a.shape[0]):
        for t in range(a.shape[1]):
            out[s, t] = _count_full(a[s, t], lo[s], width[s])


@_jit_sum
def _sum(x):
    """Sum of the elements (in any order: vectorised; the order is the only difference
    from numpy's pairwise sum, a round-off)."""
    s = 0.0
    for j in range(x.shape[0]):
        s += x[j]
    return s


@_jit
def _phase(dp, a, kk, part, lo, width, int_g, E, G, mu, ell_old, v, ell, N, vmax, carried, v1):
    """Normal update of one step (``normal_phase``, ``_carry`` and the clip of ``prepare``):
    fills ell, N, vmax, carried, v1 (n,); returns F_N. kk: the partly covered cell
    (-1: none), part: its integral of g. Elementwise, as numpy computes it."""
    for j in range(lo.shape[0]):
        e = min(max(a - lo[j], 0.0), width[j])
        ig = int_g[j] if e >= width[j] else 0.0
        ig = part if j == kk else ig
        Nj = E * max(dp * e - ig, 0.0)
        pos = e > 0.0
        vm = mu * Nj / (G * e) if pos else 0.0
        c = v[j] * (min(1.0, ell_old[j] / e) if pos else 0.0)
        ell[j] = e
        N[j] = Nj
        vmax[j] = vm
        carried[j] = c
        v1[j] = min(max(c, -vm), vm)
    return 2.0 * _sum(N)


@_jit_sum
def _force(v1, vmax, ell, G2, x):
    """Tangential force sum 2 G* ell clip(v1 + x) and its slope in x (``Trial.force``; summed
    in any order)."""
    f = 0.0
    s = 0.0
    for j in range(v1.shape[0]):
        k = G2 * ell[j]
        t = v1[j] + x
        m = vmax[j]
        f += k * min(max(t, -m), m)
        s += k if abs(t) < m else 0.0
    return f, s


@_jit
def _stick_one(r, slack, j, a, p):
    """Instantaneous stick radius (``mdr.stick._one_instant``; j: first slipping node, -1: none)."""
    if j < 0:
        return a
    if j == 0:
        return 0.0
    if p == 1.0:
        w1, w0 = slack[j - 1], slack[j]
    else:
        w1 = math.copysign(abs(slack[j - 1]) ** p, slack[j - 1])
        w0 = math.copysign(abs(slack[j]) ** p, slack[j])
    r1, r0 = r[j - 1], r[j]
    root = np.inf
    w2 = -np.inf
    if j >= 2:
        w2 = slack[j - 2] if p == 1.0 else math.copysign(abs(slack[j - 2]) ** p, slack[j - 2])
    if j >= 2 and w2 > w1 and w1 > 0.0:
        root = r1 + w1 * (r1 - r[j - 2]) / (w2 - w1)
    if w1 > 0.0 and w0 < w1:
        root = min(root, r1 + w1 * (r0 - r1) / (w1 - w0))
    if not math.isfinite(root):
        root = r0
    return min(max(min(root, a), r1), r0, a)


@_jit
def _commit(du, v1, vmax, ell, carried, nodes, a, p, at_lim, v, slack, slip, tmp1, tmp2):
    """Tangential update of one step by du (``Trial.commit``): writes the new v, the slack
    and slip flags; returns (sum ell v, sum ell vmax slip, stick radius). tmp1, tmp2: scratch."""
    n = v1.shape[0]
    for j in range(n):
        vm = vmax[j]
        tr = v1[j] + du
        v2 = min(max(tr, -vm), vm)
        tmp1[j] = ell[j] * v2
        tmp2[j] = ell[j] * vm * (abs(carried[j] - v1[j]) + abs(tr - v2))
        sk = vm - abs(tr)
        slack[j] = sk
        slip[j] = sk <= at_lim * vm or abs(carried[j]) > vm or ell[j] <= 0.0
        v[j] = v2
    first = -1
    for j in range(n):
        if slip[j]:
            first = j
            break
    return _sum(tmp1), _sum(tmp2), _stick_one(nodes, slack, first, a, p)


@_jit
def _newton_step(x, r, slope, lo, hi):
    """One step of the safeguarded Newton iteration of ``mdr.solve.solve_increasing`` (the one
    home of its update in the compiled loops) for a nondecreasing function whose residual at x
    is r with slope ``slope``, on the bracket [lo, hi]: the bracket shrinks to the root's side
    (r < 0: lo = x; r > 0: hi = x), then the Newton step, or the bisection of the bracket when
    that step is not finite or leaves the open bracket. Returns (x, lo, hi). The callers keep
    their own loops around it: each residual reads its own arrays (one law's cells; the law,
    the compliances and the bedding spheres; a batch of profiles) and stops on its own test,
    and one shared loop would take the residual as a closure over those arrays, which numba
    does not compile as an argument."""
    if r < 0:
        lo = x
    if r > 0:
        hi = x
    xn = x - r / slope
    if not np.isfinite(xn) or xn <= lo or xn >= hi:
        xn = 0.5 * (lo + hi)
    return xn, lo, hi


# ------------------------------------------------------------------ MDRContact.run
@_jit
def run_law(force_mode, dp, a, kk, part, drive, lo, width, int_g, nodes, E, G, mu, p, at_lim,
            v, ell, u, rec0, o_u, o_Fx, o_FN, o_c, o_work, r_slack, r_slip, bad, status, info):
    """History of S scenes over T steps (arrays (S, T) per step, (S, n) per cell).

    force_mode False: ``drive`` is the total displacement u; True: the tangential force.
    v, ell, u: the state, updated in place. Steps t >= rec0 record slack and slip flags.
    Force control: ``bad`` flags steps with |F_x| >= mu F_N (1 - 1e-12); a scene stops at
    such a step when F_x != 0 (status BEYOND_FRICTION) or when Newton fails
    (NO_CONVERGENCE, info = step, residual, tolerance).
    """
    S, T = dp.shape
    n = lo.shape[1]
    ellN = np.empty(n)
    N = np.empty(n)
    vmax = np.empty(n)
    carried = np.empty(n)
    v1 = np.empty(n)
    slack = np.empty(n)
    slip = np.empty(n, dtype=np.bool_)
    tmp1 = np.empty(n)
    tmp2 = np.empty(n)
    G2 = 2.0 * G
    for s in range(S):
        vs = v[s]
        ells = ell[s]
        us = u[s]
        for t in range(T):
            FN = _phase(dp[s, t], a[s, t], kk[s, t], part[s, t], lo[s], width[s], int_g[s], E, G, mu[s],
                        ells, vs, ellN, N, vmax, carried, v1)
            o_FN[s, t] = FN
            if force_mode:
                target = drive[s, t]
                muFN = mu[s] * FN
                if abs(target) >= muFN * (1 - 1e-12):
                    bad[s, t] = True
                    if abs(target) > 0:
                        status[s] = BEYOND_FRICTION
                        info[s, 0] = t
                        break
                lo_x = np.inf
                hi_x = -np.inf
                for j in range(n):
                    lj = -vmax[j] - v1[j] if ellN[j] > 0 else 0.0
                    hj = vmax[j] - v1[j] if ellN[j] > 0 else 0.0
                    lo_x = min(lo_x, lj)
                    hi_x = max(hi_x, hj)
                atol = 1e-12 * max(muFN, 1e-300)
                x = min(max(0.0, lo_x), hi_x)
                done = False
                r = 0.0
                for it in range(MAX_ITER):
                    f, sl = _force(v1, vmax, ellN, G2, x)
                    r = f - target
                    if abs(r) <= atol or hi_x - lo_x <= 0.0:
                        done = True
                        break
                    x, lo_x, hi_x = _newton_step(x, r, sl, lo_x, hi_x)
                if not done:
                    f, sl = _force(v1, vmax, ellN, G2, x)
                    status[s] = NO_CONVERGENCE
                    info[s, 0] = t
                    info[s, 1] = abs(f - target)
                    info[s, 2] = atol
                    break
                du = (us + x) - us
                unew = us + du
            else:
                unew = drive[s, t]
                du = unew - us
            Fx, W, c = _commit(du, v1, vmax, ellN, carried, nodes[s], a[s, t], p, at_lim, vs, slack, slip, tmp1, tmp2)
            for j in range(n):
                ells[j] = ellN[j]
            us = unew
            o_u[s, t] = unew
            o_Fx[s, t] = G2 * Fx
            o_work[s, t] = G2 * W
            o_c[s, t] = c
            if t >= rec0:
                for j in range(n):
                    r_slack[s, t - rec0, j] = slack[j]
                    r_slip[s, t - rec0, j] = slip[j]
        u[s] = us


# ------------------------------------------------------------------ apparatus
@_jit
def _sphere_phase(N_b, R, Eb, Gb, mu, xmax, lo, width, int_g, ell_old, v, ell, N, vmax, carried, v1):
    """Normal update of a parabolic bedding sphere at normal force N_b > 0 (Hertz approach of
    ``mdr.normal.approach_from_force``, contact radius and cell integrals of
    ``TruncatedSphere`` with b = 0). Returns (F_N, ok); ok False: the contact radius exceeds
    the spring grid."""
    ah = (3.0 * N_b * R / (4.0 * Eb)) ** (1.0 / 3.0)
    d = ah**2 / R
    dp = max(d, 0.0)
    a = math.sqrt(0.5 * (0.0 + math.sqrt(0.0 + 4.0 * R**2 * dp**2))) if d > 0 else 0.0
    if a > xmax * (1 + 1e-9):
        return 0.0, False
    a = min(a, xmax)
    n = lo.shape[0]
    k = _count_full(a, lo, width)
    kk = -1
    part = 0.0
    if k < n and a > 0:
        kk = k
        if a > lo[k]:
            hi = max(a, lo[k])
            part = max(hi**2 - 0.0, 0.0) ** 1.5 / (3.0 * R) - max(lo[k] ** 2 - 0.0, 0.0) ** 1.5 / (3.0 * R)
    return _phase(dp, a, kk, part, lo, width, int_g, Eb, Gb, mu, ell_old, v, ell, N, vmax, carried, v1), True


@_jit
def run_apparatus_loop(dp, a, kk, part, FNp, u3, lo, width, int_g, nodes, E, G, mu, p, at_lim,
                       use_bed, blo, bwidth, bint_g, bxmax, bR, bmu, Eb, Gb,
                       cx, cp, W0, l1, l2, h, h2, mu2, xtol, rec0, state_at,
                       o_Fx, o_FN, o_u1, o_u2, o_du, o_Fbed, o_c, o_evals, r_slack, r_slip,
                       sa_v, sa_ell, sa_u, status, info):
    """The step loop of ``run_apparatus`` for S scenes (see its docstring for the model).

    Per step: bedding loads from F_N and the previous step's moment, the normal updates,
    the equilibrium r(du) = u_3 - u_2 - c_p (F_x + F_bed) = 0 by the safeguarded Newton
    iteration of ``solve_increasing`` (atol = xtol) from the predictor of ``run_apparatus``, the
    commits. A scene stops at a failing step with status LIFT_OFF, BEYOND_GRID or
    NO_CONVERGENCE (info = step, residual, tolerance).
    """
    S, T = dp.shape
    n = lo.shape[1]
    nb = blo.shape[2]
    G2 = 2.0 * G
    Gb2 = 2.0 * Gb
    ellN = np.empty(n)
    N = np.empty(n)
    vmax = np.empty(n)
    carried = np.empty(n)
    v1 = np.empty(n)
    slack = np.empty(n)
    slip = np.empty(n, dtype=np.bool_)
    tmp1 = np.empty(n)
    tmp2 = np.empty(n)
    tmpb = np.empty(nb)
    v = np.empty(n)
    ell = np.empty(n)
    vb = np.empty((2, nb))
    ellb = np.empty((2, nb))
    ellNb = np.empty((2, nb))
    Nb = np.empty((2, nb))
    vmaxb = np.empty((2, nb))
    carriedb = np.empty((2, nb))
    v1b = np.empty((2, nb))
    ub = np.empty(2)
    for s in range(S):
        v[:] = 0.0
        ell[:] = 0.0
        vb[:, :] = 0.0
        ellb[:, :] = 0.0
        ub[:] = 0.0
        u_old = 0.0
        du_prev = 0.0
        slope = 1.0  # of the equilibrium at the previous step's solution (the predictor of run_apparatus)
        M = 0.0
        for k in range(T):
            if use_bed:
                W = W0[s] + FNp[s, k]
                L = l1[s] + l2[s]
                N1 = (W * l2[s] + M) / L
                N2 = (W * l1[s] - M) / (2.0 * L)
                if N1 <= 0 or N2 <= 0:
                    status[s] = LIFT_OFF
                    info[s, 0] = k
                    break
                ok = True
                for i in range(2):
                    _, ok_i = _sphere_phase(N1 if i == 0 else N2, bR[s, i], Eb, Gb, bmu[s, i], bxmax[s, i],
                                            blo[s, i], bwidth[s, i], bint_g[s, i], ellb[i], vb[i], ellNb[i],
                                            Nb[i], vmaxb[i], carriedb[i], v1b[i])
                    ok = ok and ok_i
                if not ok:
                    status[s] = BEYOND_GRID
                    info[s, 0] = k
                    break
            FN = _phase(dp[s, k], a[s, k], kk[s, k], part[s, k], lo[s], width[s], int_g[s], E, G, mu[s],
                        ell, v, ellN, N, vmax, carried, v1)
            span = (mu[s] * FNp[s, k] + (mu2[s] * (W0[s] + FNp[s, k]) if use_bed else 0.0)) * (cp[s] + cx[s]) + 1e-12
            lo_x = u3[k] - span
            hi_x = u3[k] + span
            step = u3[k] - u3[max(k - 1, 0)]
            x = min(max(du_prev + step / (slope if np.isfinite(slope) and slope > 0 else 1.0), lo_x), hi_x)
            done = False
            r = 0.0
            calls = 0
            for it in range(MAX_ITER):
                F, kF = _force(v1, vmax, ellN, G2, x - u_old)
                u2 = x + cx[s] * F
                du2 = 1.0 + cx[s] * kF
                Fb = 0.0
                kb = 0.0
                if use_bed:
                    Fb0, kb0 = _force(v1b[0], vmaxb[0], ellNb[0], Gb2, u2 - ub[0])
                    Fb1, kb1 = _force(v1b[1], vmaxb[1], ellNb[1], Gb2, u2 - ub[1])
                    Fb = Fb0 + 2.0 * Fb1
                    kb = kb0 + 2.0 * kb1
                r = u2 + cp[s] * (F + Fb) - u3[k]
                sl = du2 + cp[s] * (kF + kb * du2)
                slope = sl
                calls += 1
                if abs(r) <= xtol or hi_x - lo_x <= xtol:
                    done = True
                    break
                x, lo_x, hi_x = _newton_step(x, r, sl, lo_x, hi_x)
            o_evals[s, k] = calls
            if not done:
                status[s] = NO_CONVERGENCE
                info[s, 0] = k
                info[s, 1] = abs(r)
                info[s, 2] = xtol
                break
            du_c = x - u_old
            Fx, _, c = _commit(du_c, v1, vmax, ellN, carried, nodes[s], a[s, k], p, at_lim, v, slack, slip, tmp1, tmp2)
            Fx = G2 * Fx
            for j in range(n):
                ell[j] = ellN[j]
            u_old = u_old + du_c
            u2 = x + cx[s] * Fx
            Fbed = 0.0
            if use_bed:
                Fb0 = 0.0
                for i in range(2):
                    dub = u2 - ub[i]
                    for j in range(nb):
                        vm = vmaxb[i, j]
                        v2 = min(max(v1b[i, j] + dub, -vm), vm)
                        vb[i, j] = v2
                        ellb[i, j] = ellNb[i, j]
                        tmpb[j] = ellNb[i, j] * v2
                    ub[i] = ub[i] + dub
                    if i == 0:
                        Fb0 = Gb2 * _sum(tmpb)
                    else:
                        Fbed = Fb0 + 2.0 * (Gb2 * _sum(tmpb))
                M = -Fx * h[s] + (Fx + Fbed) * h2[s]
            du_prev = x
            o_Fx[s, k] = Fx
            o_FN[s, k] = FN
            o_u1[s, k] = cx[s] * Fx
            o_u2[s, k] = u2
            o_du[s, k] = x
            o_Fbed[s, k] = Fbed
            o_c[s, k] = c
            if k >= rec0:
                for j in range(n):
                    r_slack[s, k - rec0, j] = slack[j]
                    r_slip[s, k - rec0, j] = slip[j]
            if k == state_at:
                for j in range(n):
                    sa_v[s, j] = v[j]
                    sa_ell[s, j] = ell[j]
                sa_u[s] = u_old


# ------------------------------------------------------------------ glue (numpy side)
def normal_inputs(law, d):
    """Per step of the approaches d (shape batch + (T,)): (d_+, contact radius a, index of the
    one partly covered cell or -1, integral of g over its part in contact), exactly as
    ``MDRContact.normal_phase`` computes them (same calls of the profile)."""
    g = law.grid
    batch = law.batch
    n = g.n
    dp = np.maximum(d, 0.0)
    a = np.where(d > 0, law.profile.g_inv(dp), 0.0)
    x_max = g.x_max.reshape(batch + (1,))
    if np.any(a > x_max * (1 + 1e-9)):
        raise InputError("the contact radius exceeds the spring grid: build the law with a larger F_max (or a_max)")
    a = np.minimum(a, x_max)
    S, T = int(np.prod(batch, dtype=int)), d.shape[-1]
    k = np.empty((S, T), dtype=np.int64)
    full_cells(_flat(a, batch, (T,)), _flat(g.lo, batch, (n,)), _flat(g.width, batch, (n,)), k)
    k = k.reshape(batch + (T,))
    has = (k < n) & (a > 0)
    kk = np.minimum(k, n - 1)
    lo_k = np.take_along_axis(np.broadcast_to(g.lo, batch + (n,)), kk, axis=-1)
    part = np.where(has & (a > lo_k), law.profile.cell_integral(lo_k, np.maximum(a, lo_k)), 0.0)
    return dp, a, np.where(has, kk, -1), part


def _flat(x, batch, tail=()):
    """x broadcast to batch + tail, as a new writable C array of shape (S,) + tail (one
    type for every call: the compiled loops are specialised once)."""
    return np.array(np.broadcast_to(np.asarray(x, dtype=float), tuple(batch) + tuple(tail)), dtype=float,
                    order="C").reshape((-1,) + tuple(tail))


def law_history(law, drive, d, state, force, rec0):
    """``MDRContact.run`` through the compiled loop. drive, d: batch + (T,) arrays; state: the
    LawState to start from; rec0: first recorded step (T: none). Returns a dict of the
    History's fields (arrays batch + (T,)), the recorded slack/slipping and the final
    (v, ell, u) of the state; raises as the step API does."""
    batch = law.batch
    T = drive.shape[-1]
    n = law.grid.n
    S = int(np.prod(batch, dtype=int))
    dp, a, kk, part = normal_inputs(law, d)
    g = law.grid
    cells = lambda x: _flat(x, batch, (n,))  # noqa: E731
    steps = lambda x: _flat(x, batch, (T,))  # noqa: E731
    v, ell, u = cells(state.v), cells(state.ell), _flat(state.u, batch)
    out = {key: np.zeros((S, T)) for key in ("u", "Fx", "FN", "c", "work")}
    r_slack = np.zeros((S, T - rec0, n))
    r_slip = np.zeros((S, T - rec0, n), dtype=bool)
    bad = np.zeros((S, T), dtype=bool)
    status = np.zeros(S, dtype=np.int64)
    info = np.zeros((S, 3))
    run_law(bool(force), steps(dp), steps(a), np.array(np.broadcast_to(kk, batch + (T,)), dtype=np.int64, order="C").reshape(S, T),
            steps(part), steps(drive), cells(g.lo), cells(g.width), cells(g.int_g), cells(law.stick_nodes),
            float(law.E_star), float(law.G_star), _flat(law.mu, batch), 1.0 / float(law.stick_onset), AT_LIMIT,
            v, ell, u, int(rec0), out["u"], out["Fx"], out["FN"], out["c"], out["work"], r_slack, r_slip,
            bad, status, info)
    if force:
        _raise_force_control(law, drive.reshape(S, T), out["FN"], bad, status, info)
    shape = batch + (T,)
    res = {key: val.reshape(shape) for key, val in out.items()}
    res["d"], res["a"] = dp, a
    res["slack"] = r_slack.reshape(batch + (T - rec0, n))
    res["slipping"] = r_slip.reshape(batch + (T - rec0, n))
    res["state"] = (v.reshape(batch + (n,)), ell.reshape(batch + (n,)), u.reshape(batch))
    return res


def _raise_force_control(law, target, FN, bad, status, info):
    """The errors of ``MDRContact.step`` under force control, at the first failing step."""
    T = target.shape[1]
    beyond = np.any(bad, axis=0) & np.any(np.abs(target) > 0, axis=0)
    t_in = int(np.argmax(beyond)) if np.any(beyond) else T
    failed = status == NO_CONVERGENCE
    t_nc = int(np.min(info[failed, 0])) if np.any(failed) else T
    if t_in < T and t_in <= t_nc:
        sel = bad[:, t_in]
        mu_FN = _flat(law.mu, law.batch)[sel] * FN[sel, t_in]
        raise InputError(f"tangential force Fx={float(np.max(np.abs(target[sel, t_in]))):.4g} N "
                         f"must stay below the friction limit mu*F_N={float(np.min(mu_FN)):.4g} N "
                         f"under force control (beyond it the contact slides without equilibrium)")
    if t_nc < T:
        sel = failed & (info[:, 0] == t_nc)
        raise ConvergenceError(f"MDR tangential force control: safeguarded Newton did not converge in {MAX_ITER} "
                               f"iterations (worst residual {float(np.max(info[sel, 1])):.3e}, tolerance "
                               f"{float(np.max(info[sel, 2])):.3e})")


def _plain_sphere_bedding(law, bed, batch):
    """True if the bedding law is an MDR law of parabolic spheres (b = 0), shape batch + (2,)."""
    prof = getattr(bed, "profile", None)
    return (type(bed) is type(law) and isinstance(prof, TruncatedSphere) and not prof.exact
            and not np.any(np.asarray(prof.b) > 0) and tuple(bed.batch) == tuple(batch) + (2,))


def apparatus_loop(law, bed, app, mu, FN, d, u3, cx, cp, first, state_at, g_acc, xtol):
    """The step loop of ``run_apparatus`` compiled, for an MDR law and (``bed``, or None
    without bedding) the MDR bedding of parabolic spheres; None when not applicable (the
    caller then runs its step loop). Returns (out, window, evaluations) as that loop
    leaves them."""
    batch = tuple(law.batch)
    if not enabled() or (bed is not None and not _plain_sphere_bedding(law, bed, batch)):
        return None
    T = u3.size
    n = law.grid.n
    S = int(np.prod(batch, dtype=int))
    shape = batch + (T,)
    FN = np.broadcast_to(np.asarray(FN, dtype=float), shape)
    d = np.broadcast_to(np.asarray(d, dtype=float), shape)
    dp, a, kk, part = normal_inputs(law, d)
    g = law.grid
    cells = lambda x: _flat(x, batch, (n,))  # noqa: E731
    steps = lambda x: _flat(x, batch, (T,))  # noqa: E731
    per = lambda x: _flat(x, batch)  # noqa: E731
    use_bed = bed is not None
    if use_bed:
        nb = bed.grid.n
        bcells = lambda x: _flat(x, batch, (2, nb))  # noqa: E731
        bsph = lambda x: _flat(x, batch, (2,))  # noqa: E731
        bargs = (bcells(bed.grid.lo), bcells(bed.grid.width), bcells(bed.grid.int_g), bsph(bed.grid.x_max),
                 bsph(bed.profile.R), bsph(bed.mu), float(bed.E_star), float(bed.G_star))
    else:
        z2 = np.zeros((S, 2, 1))
        bargs = (z2, z2 + 1.0, z2, np.ones((S, 2)), np.ones((S, 2)), np.zeros((S, 2)), 1.0, 1.0)
    names = ("Fx", "FN", "u1", "u2", "du", "Fbed", "c")
    o = {key: np.zeros((S, T)) for key in names}
    evals = np.zeros((S, T), dtype=np.int64)
    W = T - first
    r_slack = np.zeros((S, W, n))
    r_slip = np.zeros((S, W, n), dtype=bool)
    sa_v, sa_ell, sa_u = np.zeros((S, n)), np.zeros((S, n)), np.zeros(S)
    status = np.zeros(S, dtype=np.int64)
    info = np.zeros((S, 3))
    sa = -1 if state_at is None else int(state_at)
    run_apparatus_loop(steps(dp), steps(a), np.array(kk.reshape(S, T), dtype=np.int64, order="C"), steps(part), steps(FN),
                       np.array(u3, dtype=float, order="C"), cells(g.lo), cells(g.width), cells(g.int_g),
                       cells(law.stick_nodes), float(law.E_star), float(law.G_star), per(law.mu),
                       1.0 / float(law.stick_onset), AT_LIMIT, use_bed, *bargs,
                       per(cx), per(cp), per(app.m1 * g_acc), per(app.l1), per(app.l2), per(app.h), per(app.h2),
                       per(app.mu2 if use_bed else 0.0), float(xtol), int(first), sa,
                       o["Fx"], o["FN"], o["u1"], o["u2"], o["du"], o["Fbed"], o["c"], evals, r_slack, r_slip,
                       sa_v, sa_ell, sa_u, status, info)
    if np.any(status != OK):
        k = int(np.min(info[status != OK, 0]))
        code = int(np.min(status[(status != OK) & (info[:, 0] == k)]))
        if code == LIFT_OFF:
            raise InputError("the block lifts off a bedding sphere: tangential moment too large for the bedding geometry")
        if code == BEYOND_GRID:
            raise InputError("the contact radius exceeds the spring grid: build the law with a larger F_max (or a_max)")
        sel = (status == NO_CONVERGENCE) & (info[:, 0] == k)
        raise ConvergenceError(f"apparatus equilibrium: safeguarded Newton did not converge in {MAX_ITER} iterations "
                               f"(worst residual {float(np.max(info[sel, 1])):.3e}, tolerance {float(xtol):.3e})")
    out = {key: o[key].reshape(shape) for key in names}
    out["a"] = a
    if state_at is not None:
        out["state_at"] = dataclasses.replace(law.rest_state(), v=sa_v.reshape(batch + (n,)),
                                              ell=sa_ell.reshape(batch + (n,)), u=sa_u.reshape(batch),
                                              d=np.array(dp[..., sa]))
    slack = r_slack.reshape(batch + (W, n))
    slipping = r_slip.reshape(batch + (W, n))
    window = [(slack[..., i, :], slipping[..., i, :]) for i in range(W)]
    # the step loop counts the evaluations of the whole batch: the slowest scene of each step
    evaluations = int(np.sum(np.max(evals, axis=0))) if S else 0
    return out, window, evaluations


# ------------------------------------------------------------------ normal contact
@_jit
def _truncated_force(a, R, b, Es):
    """F_N(a) = 2 E* (a g(a) - G(a)) of the parabolic truncated sphere (``mdr.normal``)."""
    s2 = max(a**2 - b**2, 0.0)
    return 2.0 * Es * (a * (a * math.sqrt(s2) / R) - s2**1.5 / (3.0 * R))


@_jit
def approach_truncated_sphere(F, R, b, Es, rtol, d):
    """``mdr.normal.approach_from_force`` for the parabolic truncated sphere, the same
    iteration over all elements at once: the bracket from the flat-face radius, doubled
    until F(hi) >= F, then the safeguarded Newton iteration on the contact radius, which
    freezes converged elements and stops when every element is converged or took a step
    below rtol (a step criterion shared by the batch, as numpy's loop has it).
    Returns 0, or 1 (bracket failed), 2 (no convergence; residuals in d)."""
    m = F.shape[0]
    Fp = np.maximum(F, 0.0)
    lo = np.maximum(np.zeros(m), b)
    hi = np.maximum(lo * 2.0, 1e-9)
    ok = False
    for _ in range(200):
        need = False
        for i in range(m):
            if _truncated_force(hi[i], R[i], b[i], Es) < Fp[i]:
                hi[i] = hi[i] * 2.0
                need = True
        if not need:
            ok = True
            break
    if not ok:
        return 1
    a = 0.5 * (lo + hi)
    res = np.empty(m)
    a_new = np.empty(m)
    frozen = np.zeros(m, dtype=np.bool_)  # converged: a, and so res, stay as they are
    ok = False
    for it in range(200):
        all_done = True
        for i in range(m):
            if frozen[i]:
                continue
            res[i] = _truncated_force(a[i], R[i], b[i], Es) - Fp[i]
            if not (abs(res[i]) <= 1e-14 * Fp[i] or Fp[i] == 0):
                all_done = False
        if all_done:
            ok = True
            break
        small = True
        for i in range(m):
            if frozen[i]:
                a_new[i] = a[i]
                continue
            ai, bi = a[i], b[i]
            dg = (2.0 * ai**2 - bi**2) / (R[i] * math.sqrt(ai**2 - bi**2)) if ai > bi else 0.0
            # (res = 0 is converged and frozen below, so its bracket no longer matters)
            an, lo[i], hi[i] = _newton_step(ai, res[i], 2.0 * Es * ai * dg, lo[i], hi[i])
            done = abs(res[i]) <= 1e-14 * Fp[i] or Fp[i] == 0
            if done:
                an = ai
                frozen[i] = True
            a_new[i] = an
            if not (done or abs(an - ai) <= rtol * max(ai, 1e-300)):
                small = False
        if small:
            a[:] = a_new
            ok = True
            break
        a[:] = a_new
    if not ok:
        d[:] = res
        return 2
    for i in range(m):
        d[i] = a[i] * math.sqrt(max(a[i]**2 - b[i]**2, 0.0)) / R[i] if F[i] > 0 else 0.0
    return 0
