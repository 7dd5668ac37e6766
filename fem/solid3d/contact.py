"""Frictional contact of two bodies on the condensed 3D mortar interface (issue 13).

Unknowns are P1 traction fields on the contact facets (``fem.solid3d.interface.MortarInterface``):
at every multiplier vertex j the pressure p_j >= 0 and the tangential traction
q_j = (q_x, q_y) on the block (Pa); q_y = 0 on the symmetry plane y = 0. The kinematics
are weighted by the mortar matrix, so every displacement-like quantity below is a
weighted one (m^3: integral of phi_j times a displacement):

    gap_j  = gap0_j - d A_j + (D_n p)_j           (weighted normal gap, >= 0)
    s_j    = u A_j e_x - (D_t q)_j                (weighted relative tangential displacement,
                                                  indenter minus block)

with gap0_j = (B f)_j the weighted initial gap of the profile f, d the approach and u the
tangential displacement of the indenter's clamped top against the block's clamped bottom,
A_j the vertex areas, D_n = D1_zz + D2_zz and D_t = D1_tt + D2_tt the relative
flexibilities of block (1) and indenter (2). The indenter is modelled as the mirror image
of the block's mesh (z -> -z) with its own elastic constants, so both contact faces are
flat and the profile enters only through the initial gap (module ``fem.solid3d.law``). For
identical materials the normal-tangential cross terms of the two bodies cancel exactly
(Dundurs' beta = 0); for dissimilar ones they enter as the antisymmetric coupling
``K = D1_tz - D2_tz`` (see :class:`RelativeFlexibility`).

Conditions (exact, no penalty): Signorini p >= 0, gap >= 0, p gap = 0 at every vertex;
Coulomb with the slip limit g_j = mu p_j: |q_j| <= g_j, the slip increment
s_j - P_j,old (P the weighted slip of the last step) vanishes where |q_j| < g_j and is
parallel to q_j where |q_j| = g_j. Each increment is the convex programme

    min_q 1/2 q^T D_t q - q^T (u A e_x - P_old),   |q_j| <= g_j,

(force control: sum_j A_j q_xj = F_x/2 with u its multiplier; the half model carries
half of every force). Both problems are solved by semi-smooth Newton methods on their
nonlinear complementarity functions, the min-map for Signorini and the disk projection
for Coulomb (Alart & Curnier, Comput. Methods Appl. Mech. Eng. 92 (1991) 353; Hueeber,
Stadler & Wohlmuth, SIAM J. Sci. Comput. 30 (2008) 572):

    R_n = p - max(0, p - c gap),   R_t,j = q_j - proj_{|.| <= g_j}(q_j + c_j (s_j - P_j,old)),

with c = 1 / diag(D). For the normal problem the full Newton step is the primal-dual
active-set method. A step that does not lower ||R|| is backtracked; if Newton stalls, the
increment falls back to an accelerated projected gradient method (FISTA with restart;
Beck & Teboulle, SIAM J. Imaging Sci. 2 (2009) 183), which converges for any convex
problem of this kind. A solve that does not reach its tolerance raises
``ConvergenceError`` with the residual.

Here: the normal solve, the tangential increment and its history. The coupled increment of a
dissimilar pair is ``fem.solid3d.coupled``; the packed layout, the Newton blocks and the operators kept
per law are ``fem.solid3d.newton_blocks``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial

import numpy as np
import scipy.linalg as sla

from common.errors import ConvergenceError
from mdr.solve import regula_falsi_increasing

from fem.solvers import blas_threads
from fem.solid3d.newton_blocks import (Operators, _contact_block, _newton_blocks, _pack, _reduced,
                                       _unpack)

#: relative tolerance of the complementarity residuals (of the largest pressure / slip limit)
TOL = 1e-10
#: the whole contact's share over the half model's (y >= 0): every force, area, moment and work of the
#: whole contact is WHOLE times the half model's (its one home: the solvers, the law, the estimators)
WHOLE = 2.0


@dataclass
class RelativeFlexibility:
    """Relative weighted flexibilities of the contact pair at the multiplier vertices.

    ``Dn`` (n, n) normal, ``Dt`` (2n, 2n) tangential (x block, then y block), ``K`` (2n, n)
    the normal-tangential coupling (weighted tangential displacement per unit pressure,
    ``D1_tz - D2_tz``; zero for identical materials). The matrices are fixed once made: the
    ``operators`` the solves form from them are kept with them.
    """

    Dn: np.ndarray
    Dt: np.ndarray
    K: np.ndarray | None = None
    #: the operators its solves keep between increments (``fem.solid3d.newton_blocks.Operators``)
    operators: Operators = field(default_factory=Operators, repr=False, compare=False)

    @classmethod
    def from_bodies(cls, D1, D2):
        """From the block's and the (mirrored) indenter's weighted flexibilities (3n, 3n),
        component-major as returned by ``fem.solid3d.interface.mortar_flexibility``. The indenter's
        normal component is mirrored: its z-z block enters with the same sign, its cross terms
        with the opposite one, so they cancel for identical bodies."""
        n = D1.shape[0] // 3
        t, z = slice(0, 2 * n), slice(2 * n, 3 * n)
        Dn = D1[z, z] + D2[z, z]
        Dt = D1[t, t] + D2[t, t]
        K = D1[t, z] - D2[t, z]
        if np.max(np.abs(K)) <= 1e-12 * np.max(np.abs(Dt)):
            K = None
        return cls(Dn=Dn, Dt=Dt, K=K)


def _factor(M):
    return sla.lu_factor(M, check_finite=False)


def solve_normal3d(Dn, gap0, A, *, force=None, approach=None, p0=None, max_iter=100):
    """Signorini problem of the weighted gap (module docstring).

    Give the half model's normal force ``force`` (N; sum A_j p_j) or the ``approach`` d (m).
    Returns ``(p, d, gap, iterations)``.
    """
    if (force is None) == (approach is None):
        raise ValueError("give exactly one of force and approach")
    n = A.size
    c = 1.0 / np.diag(Dn)
    d = 0.0 if approach is None else float(approach)
    if p0 is not None and np.any(np.asarray(p0) > 0):
        act = np.asarray(p0) > 0
    elif force is not None:  # rigid-indenter guess: the vertices of smallest initial gap
        act = gap0 / A <= np.quantile(gap0 / A, 0.1)
    else:
        act = gap0 - d * A < 0
    scale_gap = float(np.max(np.abs(gap0))) + abs(d) * float(np.max(A)) + 1e-300
    seen = set()
    for it in range(1, max_iter + 1):
        ia = np.flatnonzero(act)
        p = np.zeros(n)
        if ia.size == 0:
            if force is not None and force > 0:
                raise ConvergenceError("normal contact: no vertex in contact under a positive force")
            return p, d, gap0 - d * A, it
        M = Dn[np.ix_(ia, ia)]
        cho = sla.cho_factor(M, check_finite=False)
        if force is None:
            p[ia] = sla.cho_solve(cho, d * A[ia] - gap0[ia], check_finite=False)
        else:
            x = sla.cho_solve(cho, -gap0[ia], check_finite=False)
            y = sla.cho_solve(cho, A[ia], check_finite=False)
            d = (force - A[ia] @ x) / (A[ia] @ y)
            p[ia] = x + d * y
        gap = gap0 - d * A + Dn @ p
        new = p - c * gap > TOL * float(np.max(np.abs(p)) + 1e-300)
        if np.array_equal(new, act) and np.all(p >= 0) and np.all(gap[~act] >= -TOL * scale_gap):
            return p, d, gap, it
        key = new.tobytes()
        if key in seen:
            break
        seen.add(key)
        act = new
    raise ConvergenceError(f"normal contact: the active set cycled or did not settle in {it} iterations "
                           f"({int(act.sum())} of {n} vertices active, min p {p.min():.3g} Pa)")


def project_disk(z, g):
    """Project the rows of z (n, 2) onto the disks |z_j| <= g_j (the Coulomb cones of a given pressure:
    the return map of a trial traction; g_j >= 0)."""
    nz = np.hypot(z[:, 0], z[:, 1])
    f = np.where(nz > g, g / np.maximum(nz, 1e-300), 1.0)
    return z * f[:, None]


@dataclass
class TangentialResult:
    q: np.ndarray  # (n, 2) tangential traction on the block (Pa)
    u: float  # tangential displacement of the indenter's top (m)
    s: np.ndarray  # (n, 2) weighted relative tangential displacement (m^3)
    iterations: int
    method: str


def solve_tangential3d(rf, A, g, P_old, qy_zero, *, u=None, force=None, q0=None, u0=None,
                       max_iter=50, fista_iter=20000):
    """One Coulomb increment (module docstring) of the pair ``rf`` (a :class:`RelativeFlexibility`: its Dt and
    the operators kept with it): displacement ``u`` (m) or the half model's
    tangential force ``force`` (N; sum A_j q_xj) prescribed. ``g`` (n,) slip limits mu p (Pa),
    ``P_old`` (n, 2) the weighted slip of the last step, ``qy_zero`` (n,) the vertices whose q_y is held
    at 0: those on the symmetry plane y = 0 (the traction of free direction), or all of them (Mindlin's
    traction along x; ``fem.solid3d.law``). ``q0``, ``u0``: a start (e.g. the previous step); by default under force
    control the full-stick solution scaled to the force. Returns a :class:`TangentialResult`."""
    if (force is None) == (u is None):
        raise ValueError("give exactly one of force and u")
    n = A.size
    # unknown layout: q_x (n), q_y at vertices off the plane (ny), [u]
    yi, D, cd, dz_dv = _reduced(rf, qy_zero)
    m = D.shape[0]
    ex = np.concatenate([A, np.zeros(yi.size)])  # d s / d u, restricted
    Pold = _pack(np.asarray(P_old), yi)
    c = cd[:n]
    cy = np.zeros(n)
    cy[yi] = cd[n:]
    gmax = float(np.max(g)) if np.any(g > 0) else 1.0
    fc = force is not None
    if fc and abs(force) >= float(A @ g) * (1 - 1e-12) and force != 0:
        raise ConvergenceError(f"Coulomb increment: |F_x|/2 = {abs(force):.6g} N exceeds the friction limit "
                               f"sum A mu p = {float(A @ g):.6g} N of the half model (gross slip has no "
                               "force-controlled solution; drive the displacement instead)")

    unpack, pack = partial(_unpack, n=n, yi=yi), partial(_pack, yi=yi)
    plane = np.asarray(qy_zero, dtype=bool).tobytes()

    def residual(v, dl):
        # the weighted relative displacement; D's product on the columns of the nonzero tractions (the
        # contact's, once projected), gathered once per pattern: the same sums of the same nonzero terms
        iv = np.flatnonzero(v)
        s = dl * ex - rf.operators.last(("columns", plane), iv.tobytes(), lambda: D[:, iv]) @ v[iv]
        r = unpack(s - Pold)  # slip increments (n, 2)
        q = unpack(v)
        z = q + np.column_stack([c * r[:, 0], cy * r[:, 1]])
        pz = project_disk(z, g)
        R = pack(q - pz)
        if fc:
            R = np.append(R, (A @ q[:, 0] - force) / (A.sum() + 1e-300))
        return R, s, z

    v = pack(q0) if q0 is not None else np.zeros(m)
    v = pack(project_disk(unpack(v), g))
    dl = float(u) if u is not None else (0.0 if u0 is None else float(u0))
    if fc and q0 is None:  # full stick of the vertices in contact, scaled to the force
        kin = np.flatnonzero(np.concatenate([g > 0, g[yi] > 0]))
        if kin.size:
            x0, x1 = np.zeros(m), np.zeros(m)
            sol = sla.solve(D[np.ix_(kin, kin)], np.column_stack([-Pold[kin], ex[kin]]), assume_a="pos",
                            check_finite=False)
            x0[kin], x1[kin] = sol[:, 0], sol[:, 1]
            dl = (force - A @ x0[:n]) / max(A @ x1[:n], 1e-300)
            v = pack(project_disk(unpack(x0 + dl * x1), g))
    tolR = TOL * gmax
    dscale = 1.0 / float(np.mean(c * A))  # u column scaling: O(1) entries (u in m, q in Pa)
    Cvec = np.concatenate([c, cy[yi]])  # = cd; dz/dv = I - C D (C = diag(c), ``_reduced``), dz/du = C ex
    dz_du = Cvec * ex
    off = np.concatenate([g <= 0, g[yi] <= 0])  # packed unknowns of vertices out of contact
    kept = np.flatnonzero(np.append(~off, True) if fc else ~off)
    out = np.flatnonzero(off)
    R, s, z = residual(v, dl)
    block, lu = None, None
    for it in range(1, max_iter + 1):
        if np.max(np.abs(R)) <= tolR:
            return TangentialResult(unpack(v), dl, unpack(s), it - 1, "newton")
        nr0 = np.linalg.norm(R)
        if lu is not None:  # the chord step: the last factorised Jacobian, taken whole if it halves ||R||
            step = np.zeros_like(R)
            step[kept] = -sla.lu_solve(lu, R[kept], check_finite=False)
            Rt, st, zt = residual(v + step[:m], dl + (step[m] * dscale if fc else 0.0))
            if np.linalg.norm(Rt) < 0.5 * nr0:
                v, dl, R, s, z = v + step[:m], dl + (step[m] * dscale if fc else 0.0), Rt, st, zt
                continue
        # generalized Jacobian of R (module docstring); the rows of vertices out of contact (g = 0) are
        # identity rows (their traction is zero): eliminated, so the dense solve has the size of the
        # contact, not of the candidate disk, and only the kept rows are formed. Those rows hold q = 0
        # from the start (the projection), so their residual is 0 and their columns are needed only
        # where it is not; then the contact's block of dz/dv, gathered once per step, serves every
        # iteration (``_ContactBlock``), and its factorisation the following ones while their steps
        # contract (the chord method above: the iterations depend on it, not the solution)
        step = -R.copy()
        try:
            if np.any(R[out]):
                Jkk, Jko = _newton_blocks(z, g, yi, dz_dv, dz_du, kept, out, fc, A, dscale)
                step[kept] = -sla.solve(Jkk, R[kept] - Jko @ R[out], check_finite=False)
                lu = None
            else:
                block = block or _contact_block(rf, qy_zero, kept[kept < m], n, yi, dz_dv, dz_du)
                lu = sla.lu_factor(block.matrix(z, g, fc, A, dscale), check_finite=False)
                step[kept] = -sla.lu_solve(lu, R[kept], check_finite=False)
        except (sla.LinAlgError, ValueError):
            break
        dv = step[:m]
        ddl = step[m] * dscale if fc else 0.0
        t = 1.0
        for _ in range(30):
            Rt, st, zt = residual(v + t * dv, dl + t * ddl)
            if np.linalg.norm(Rt) < (1 - 1e-4 * t) * nr0:
                break
            t *= 0.5
        else:
            break
        v, dl, R, s, z = v + t * dv, dl + t * ddl, Rt, st, zt
    if fc:
        return _tangential_force_by_secant(rf, A, g, P_old, qy_zero, force, q0, fista_iter)
    vq, r = _fista(D, dl * ex - Pold, unpack, pack, g, fista_iter, tolR, v)
    return TangentialResult(unpack(vq), dl, unpack(r + Pold), fista_iter, "fista")


def tangential_slope(rf, A, g, qy_zero, q, r) -> float:
    """d(sum_j A_j q_xj)/du (N/m, half model) of a displacement-controlled Coulomb increment at
    its solution: traction ``q`` (n, 2), slip increments ``r`` (n, 2) = s - P_old (weighted, m^3).
    The consistent tangent of the semi-smooth residual (:func:`solve_tangential3d`): stick
    vertices follow the elastic flexibility, slipping ones keep |q_j| = g_j and turn with their
    slip direction, vertices out of contact carry nothing. At fixed slip limits (a dissimilar
    pair's pressure change with u is left out: a secant-free, O(beta^2) approximation there).
    Where a vertex is exactly at the stick-slip switch it is the one-sided derivative of the
    side the projection picks (the force is piecewise smooth in u, so Newton on it still
    converges)."""
    n = A.size
    if not np.any(g > 0):
        return 0.0
    yi, D, cd, dz_dv = _reduced(rf, qy_zero)
    ex = np.concatenate([A, np.zeros(yi.size)])
    c = cd[:n]
    cy = np.zeros(n)
    cy[yi] = cd[n:]
    z = q + np.column_stack([c * r[:, 0], cy * r[:, 1]])
    Cvec = np.concatenate([c, cy[yi]])
    # a vertex out of contact has P' = 0: its rows are the identity's with nothing on the right, its dv 0;
    # the system is solved on the unknowns of the vertices in contact alone (the same solution, a
    # fraction of the cost: the contact is part of the meshed interface)
    inside = g > 0
    kv = np.flatnonzero(np.concatenate([inside, inside[yi]]))
    J, Pdu = _contact_block(rf, qy_zero, kv, n, yi, dz_dv, Cvec * ex).tangent(z, g)
    dv = sla.solve(J, Pdu, check_finite=False)
    return float(A[kv[kv < n]] @ dv[kv < n])


def _fista(D, b, unpack, pack, g, max_iter, tolR, v0):
    """Accelerated projected gradient with adaptive restart for min 1/2 v^T D v - v^T b over
    the disks (O'Donoghue & Candes, Found. Comput. Math. 15 (2015) 715). Returns (v, s) with
    s = b + P_old - D v the weighted relative displacement."""
    L = float(sla.eigh(D, eigvals_only=True, subset_by_index=[D.shape[0] - 1, D.shape[0] - 1])[0])
    x = v0.copy()
    y = x.copy()
    tk = 1.0
    cmin = 1.0 / np.max(np.diag(D))
    for it in range(max_iter):
        grad = D @ y - b
        xn = pack(project_disk(unpack(y - grad / L), g))
        if (xn - x) @ (y - xn) > 0:  # restart when the momentum points uphill
            tk = 1.0
            y = xn.copy()
        tn = 0.5 * (1 + np.sqrt(1 + 4 * tk * tk))
        y = xn + (tk - 1) / tn * (xn - x)
        x, tk = xn, tn
        if it % 50 == 0:
            r = b - D @ x  # slip increments
            R = np.max(np.abs(x - pack(project_disk(unpack(x + cmin * r), g))))
            if R <= tolR:
                return x, r
    raise ConvergenceError(f"Coulomb increment: projected gradient did not converge in {max_iter} iterations "
                           f"(residual {R / (np.max(g) + 1e-300):.3g} of the largest slip limit)")


def _tangential_force_by_secant(rf, A, g, P_old, qy_zero, force, q0, fista_iter):
    """Force control fallback: the total force is continuous and nondecreasing in u; regula
    falsi (Illinois) on displacement-controlled increments."""
    def total(dl):
        out = solve_tangential3d(rf, A, g, P_old, qy_zero, u=dl, q0=q0, fista_iter=fista_iter)
        return A @ out.q[:, 0] - force, out

    scale = float(np.max(np.abs(P_old)) / np.min(A) + np.max(g) * np.max(np.diag(rf.Dt)) / np.min(A)) + 1e-300
    _, out = regula_falsi_increasing(total, -scale, scale, 1e-10 * float(np.sum(A * g)),
                                     what="Coulomb increment under force control: secant search on u")
    out.method = "secant"
    return out


@dataclass
class Cycle3D:
    """A tangential history at fixed pressure (half model; forces and work of the full body)."""

    Fx: np.ndarray  # (k,) tangential force, full body (N)
    u: np.ndarray  # (k,) tangential displacement of the indenter's top (m)
    work: np.ndarray  # (k,) friction work of each increment, full body (J)
    q: list  # tractions (n, 2) per step
    P: list  # weighted slip (n, 2) per step


def tangential_history(rf, A, g, qy_zero, Fx=None, u=None):
    """Run a tangential history (full-body forces ``Fx`` or displacements ``u``, starting from
    a tangentially unloaded contact) at fixed slip limits ``g`` (Pa). The friction work of an
    increment is sum_j q_j . (P_j,new - P_j,old) over the vertices in contact (weighted slip,
    exact for the P1 traction field: the power of q against the slip rate), doubled for the
    full body; it is >= 0 by the normal-cone condition of the Coulomb law."""
    if (Fx is None) == (u is None):
        raise ValueError("give exactly one of Fx and u")
    hist = np.asarray(Fx if Fx is not None else u, dtype=float)
    n = A.size
    P = np.zeros((n, 2))
    q, dl = None, None
    out = Cycle3D(np.zeros(hist.size), np.zeros(hist.size), np.zeros(hist.size), [], [])
    contact = g > 0
    with blas_threads(1):
        return _history(rf, A, g, qy_zero, Fx, hist, P, q, dl, out, contact)


def _history(rf, A, g, qy_zero, Fx, hist, P, q, dl, out, contact):
    for k, load in enumerate(hist):
        if Fx is not None:
            r = solve_tangential3d(rf, A, g, P, qy_zero, force=load / WHOLE, q0=q, u0=dl)
        else:
            r = solve_tangential3d(rf, A, g, P, qy_zero, u=load, q0=q)
        q, dl = r.q, r.u
        Pn = r.s
        out.work[k] = WHOLE * float(np.sum((r.q * (Pn - P))[contact]))
        P = Pn
        out.Fx[k] = WHOLE * float(A @ r.q[:, 0])
        out.u[k] = r.u
        out.q.append(r.q)
        out.P.append(P)
    return out


def predict(state, A, g, u, Fx):
    """Start of a Coulomb increment from a 3D law's state (``fem.solid3d.law.FE3DState``): the last
    step's increments (``state.dq``, ``state.du``)
    extrapolated to the new load (F_x or u) when it moves on in the same direction (secant
    predictor), else the state itself (a reversal sticks first). Projected onto the new slip
    disks g. ``A`` the vertex areas. Only the iteration count depends on it (measured on the sphere
    at 453 vertices: 14 semi-smooth Newton iterations per force step without it, 4.4 with it)."""
    q = np.asarray(state.q)
    if state.dq is None:
        return q, state.u
    dq = np.asarray(state.dq)
    if Fx is not None:
        last = WHOLE * float(A @ dq[:, 0])
        ahead = Fx - WHOLE * float(A @ q[:, 0])
    else:
        last, ahead = state.du, u - state.u
    if not (last != 0.0 and 0.0 < ahead / last <= 4.0):
        return q, state.u
    f = ahead / last
    return project_disk(q + f * dq, g), state.u + f * state.du


def coulomb_increment(rf, A, g, P_old, qy_zero, state, *, u=None, Fx=None) -> TangentialResult:
    """The Coulomb increment of an uncoupled pair at fixed slip limits ``g`` = mu p: displacement-driven
    (``u``) or force-driven (``Fx``, the whole model's: the half model carries half), started from the
    last step's state moved by ``predict``; without any slip limit the contact takes the displacement."""
    if not np.any(g > 0):
        return solve_tangential3d(rf, A, g, P_old, qy_zero, u=float(state.u if u is None else u))
    if u is not None:
        q0, _ = predict(state, A, g, u, None)
        return solve_tangential3d(rf, A, g, P_old, qy_zero, u=u, q0=q0)
    q0, u0 = predict(state, A, g, None, Fx)
    return solve_tangential3d(rf, A, g, P_old, qy_zero, force=Fx / WHOLE, q0=q0, u0=u0)
