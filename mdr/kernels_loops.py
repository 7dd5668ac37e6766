"""The time loops of the MDR law, compiled (numba): whole histories of a batch of scenes, scene
by scene and step by step.

- ``run_law``: the loop of ``MDRContact.run`` under displacement control (u given) and under
  force control (F_x given; the safeguarded Newton iteration of ``mdr.solve.solve_increasing``
  per step, same bracket, start and tolerance).
- ``run_apparatus_loop``: the step loop of ``mdr.apparatus.run_apparatus`` with the MDR law and
  its MDR bedding spheres (one front, two equal rear ones); ``_sphere_phase`` is the normal
  update of a parabolic bedding sphere.
- ``bedding_normal``, ``bedding_force``, ``bedding_commit``: one step of those bedding spheres
  alone, for the step loop of ``run_apparatus`` around any other contact law (``mdr.kernels.
  CompiledBedding``), from the one-scene pieces ``_bedding_phase``, ``_bedding_force`` and
  ``_bedding_commit`` that ``run_apparatus_loop`` steps its bedding with too.

Built from the one-step functions of ``mdr.kernels_step`` and called through ``mdr.kernels``,
which prepares the inputs with numpy (contact radii, partly covered cells) and turns the status
codes into the step API's errors. Assumptions: every per-scene input is a C-contiguous float64
array flattened to (S, ...) (``mdr.kernels._flat``); the outputs are allocated by the caller
and written in place; a scene stops at its first failing step with a status code (info: step,
residual, tolerance). Disk cache: see ``mdr.kernels_step`` (its import removes the
cached loops here that are older than the code they call).
"""
from __future__ import annotations

import math

import numpy as np

from .kernels_step import (BEYOND_FRICTION, BEYOND_GRID, LIFT_OFF, NO_CONVERGENCE, _commit, _count_full, _force,
                           _jit, _newton_step, _phase, _sum)
from .solve import MAX_ITER


# ------------------------------------------------------------------ MDRContact.run
@_jit
def run_law(force_mode, dp, a, kk, part, load, lo, width, int_g, nodes, E, G, mu, p, at_lim,
            v, ell, u, rec0, o_u, o_Fx, o_FN, o_c, o_work, r_slack, r_slip, bad, status, info):
    """History of S scenes over T steps (arrays (S, T) per step, (S, n) per cell).

    force_mode False: ``load`` is the total displacement u; True: the tangential force.
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
                target = load[s, t]
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
                unew = load[s, t]
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


# 123 lines, above the house limit of 120 for a stated reason: a numba kernel, the time loop of
# ``mdr.apparatus.run_apparatus`` compiled whole (a call out of a compiled loop per step costs its speed)
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
                if not _bedding_phase(N1, N2, bR[s], Eb, Gb, bmu[s], bxmax[s], blo[s], bwidth[s], bint_g[s],
                                      ellb, vb, ellNb, Nb, vmaxb, carriedb, v1b):
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
                    Fb, kb = _bedding_force(v1b, vmaxb, ellNb, Gb2, u2, ub)
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
                Fbed = _bedding_commit(v1b, vmaxb, ellNb, Gb2, u2, ub, ellb, vb, tmpb)
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


# ------------------------------------------------------------------ the bedding, one step
@_jit
def _bedding_phase(N1, N2, R, Eb, Gb, mu, xmax, lo, width, int_g, ell, v, ellN, N, vmax, carried, v1):
    """Normal update of one scene's bedding spheres (sphere 0 the front one at N1, sphere 1 a rear one
    at N2; per-sphere inputs (2,), cells (2, nb)): the state (ell, v) read, the step's (ellN, N, vmax,
    carried, v1) written. Returns False where a contact radius exceeds its spring grid."""
    ok = True
    for i in range(2):
        _, ok_i = _sphere_phase(N1 if i == 0 else N2, R[i], Eb, Gb, mu[i], xmax[i], lo[i], width[i], int_g[i],
                                ell[i], v[i], ellN[i], N[i], vmax[i], carried[i], v1[i])
        ok = ok and ok_i
    return ok


@_jit
def _bedding_force(v1, vmax, ellN, Gb2, x, ub):
    """One scene's bedding force (the front sphere and twice a rear one) and its slope at the
    bedding-plane displacement x of a prepared step, from the state's displacements ub (2,)."""
    Fb0, kb0 = _force(v1[0], vmax[0], ellN[0], Gb2, x - ub[0])
    Fb1, kb1 = _force(v1[1], vmax[1], ellN[1], Gb2, x - ub[1])
    return Fb0 + 2.0 * Fb1, kb0 + 2.0 * kb1


@_jit
def _bedding_commit(v1, vmax, ellN, Gb2, x, ub, ell, v, tmp):
    """Commit of one scene's prepared bedding step at x: the state (v, ell, ub) updated in place; returns
    the bedding's tangential force. tmp: scratch (nb,)."""
    Fb0 = 0.0
    Fbed = 0.0
    for i in range(2):
        dub = x - ub[i]
        for j in range(v1.shape[1]):
            vm = vmax[i, j]
            v2 = min(max(v1[i, j] + dub, -vm), vm)
            v[i, j] = v2
            ell[i, j] = ellN[i, j]
            tmp[j] = ellN[i, j] * v2
        ub[i] = ub[i] + dub
        if i == 0:
            Fb0 = Gb2 * _sum(tmp)
        else:
            Fbed = Fb0 + 2.0 * (Gb2 * _sum(tmp))
    return Fbed


@_jit
def bedding_normal(N1, N2, R, Eb, Gb, mu, xmax, lo, width, int_g, ell, v, ellN, N, vmax, carried, v1):
    """``_bedding_phase`` for S scenes (N1, N2 (S,); per-sphere inputs (S, 2), cells (S, 2, nb)). Returns
    False where a contact radius exceeds its spring grid."""
    ok = True
    for s in range(N1.shape[0]):
        ok_s = _bedding_phase(N1[s], N2[s], R[s], Eb, Gb, mu[s], xmax[s], lo[s], width[s], int_g[s], ell[s], v[s],
                              ellN[s], N[s], vmax[s], carried[s], v1[s])
        ok = ok and ok_s
    return ok


@_jit
def bedding_force(v1, vmax, ellN, Gb2, x, ub, F, k):
    """``_bedding_force`` for S scenes at x (S,): written to F, k (S,)."""
    for s in range(x.shape[0]):
        F[s], k[s] = _bedding_force(v1[s], vmax[s], ellN[s], Gb2, x[s], ub[s])


@_jit
def bedding_commit(v1, vmax, ellN, Gb2, x, ub, ell, v, F, tmp):
    """``_bedding_commit`` for S scenes at x (S,): the forces written to F (S,)."""
    for s in range(x.shape[0]):
        F[s] = _bedding_commit(v1[s], vmax[s], ellN[s], Gb2, x[s], ub[s], ell[s], v[s], tmp)
