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
"""
from __future__ import annotations

import weakref
from dataclasses import dataclass
from functools import partial

import numpy as np
import scipy.linalg as sla

from common.errors import ConvergenceError
from mdr.solve import regula_falsi_increasing

from fem.solvers import blas_threads

#: relative tolerance of the complementarity residuals (of the largest pressure / slip limit)
TOL = 1e-10


@dataclass
class RelativeFlexibility:
    """Relative weighted flexibilities of the contact pair at the multiplier vertices.

    ``Dn`` (n, n) normal, ``Dt`` (2n, 2n) tangential (x block, then y block), ``K`` (2n, n)
    the normal-tangential coupling (weighted tangential displacement per unit pressure,
    ``D1_tz - D2_tz``; zero for identical materials).
    """

    Dn: np.ndarray
    Dt: np.ndarray
    K: np.ndarray | None = None

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


def solve_tangential3d(Dt, A, g, P_old, on_plane, *, u=None, force=None, q0=None, u0=None,
                       max_iter=50, fista_iter=20000):
    """One Coulomb increment (module docstring): displacement ``u`` (m) or the half model's
    tangential force ``force`` (N; sum A_j q_xj) prescribed. ``g`` (n,) slip limits mu p (Pa),
    ``P_old`` (n, 2) the weighted slip of the last step, ``on_plane`` (n,) vertices on y = 0
    (q_y = 0 there). ``q0``, ``u0``: a start (e.g. the previous step); by default under force
    control the full-stick solution scaled to the force. Returns a :class:`TangentialResult`."""
    if (force is None) == (u is None):
        raise ValueError("give exactly one of force and u")
    n = A.size
    # unknown layout: q_x (n), q_y at vertices off the plane (ny), [u]
    yi, D, cd, dz_dv = _reduced(Dt, on_plane)
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

    def residual(v, dl):
        # the weighted relative displacement; D's product on the columns of the nonzero tractions (the
        # contact's, once projected), gathered once per pattern: the same sums of the same nonzero terms
        iv = np.flatnonzero(v)
        s = dl * ex - _last_blocks(D, iv.tobytes(), lambda: D[:, iv], _COLUMNS) @ v[iv]
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
                block = block or _contact_block(kept[kept < m], n, yi, dz_dv, dz_du)
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
        return _tangential_force_by_secant(Dt, A, g, P_old, on_plane, force, q0, fista_iter)
    vq, r = _fista(D, dl * ex - Pold, unpack, pack, g, fista_iter, tolR, v)
    return TangentialResult(unpack(vq), dl, unpack(r + Pold), fista_iter, "fista")


def _unpack(v, n, yi):
    """The (n, 2) tractions of the packed layout of ``_reduced`` (q_x of every vertex, then q_y of the
    vertices ``yi`` off the plane; q_y = 0 on it)."""
    q = np.zeros((n, 2))
    q[:, 0] = v[:n]
    q[yi, 1] = v[n:]
    return q


def _pack(q, yi):
    """The packed layout of ``_reduced`` of the (n, 2) tractions ``q``."""
    return np.concatenate([q[:, 0], q[yi, 1]])


#: the reduced operators of the last few (Dt, on_plane) pairs (``_reduced``): a law's flexibility is
#: fixed, its steps many
_REDUCED: dict = {}
_REDUCED_MAX = 4


def _held_by(cache: dict, M, on_plane, build) -> tuple:
    """``build()``'s read-only arrays, kept in ``cache`` per matrix ``M`` and plane set ``on_plane``
    (at most ``_REDUCED_MAX`` entries). ``M`` is held weakly: its entry goes when the law's flexibility
    does (no memory kept for a finished law), and a new matrix at a reused address is never taken for
    the old one."""
    key = (id(M), np.asarray(on_plane, dtype=bool).tobytes())
    hit = cache.get(key)
    if hit is not None and hit[0]() is M:
        return hit[1]
    out = build()
    for a in out:
        a.setflags(write=False)
    if len(cache) >= _REDUCED_MAX:
        cache.pop(next(iter(cache)))
    cache[key] = (weakref.ref(M), out)
    weakref.finalize(M, cache.pop, key, None)  # the law's flexibility gone: its operators too
    return out


def _reduced(Dt, on_plane) -> tuple:
    """(yi, D, cd, dz_dv) of the packed layout: the vertices off the plane ``yi`` (their q_y is free), Dt
    restricted to q_x of every vertex and q_y of ``yi``, cd = 1 / diag(D) and dz/dv = I - diag(cd) D.
    Formed once per flexibility and plane set (read-only and shared, ``_held_by``)."""
    def build():
        n = np.size(on_plane)
        yi = np.flatnonzero(~np.asarray(on_plane, dtype=bool))
        idx = np.concatenate([np.arange(n), n + yi])  # rows/cols of Dt kept
        D = Dt[np.ix_(idx, idx)]
        cd = 1.0 / np.diag(D)  # c = 1 / diag(D): the scaling of the slip increments in z
        return yi, D, cd, np.eye(idx.size) - cd[:, None] * D

    return _held_by(_REDUCED, Dt, on_plane, build)


def _partners(kv, n, yi, m) -> tuple:
    """Of the packed unknowns ``kv`` (sorted: q_x of vertices, then q_y of vertices off the plane ``yi``; m
    packed unknowns in all): each one's vertex, whether it is a q_x, the position in ``kv`` of its partner
    (the other component of its vertex: a q_y's is its vertex's q_x, a q_x's its vertex's q_y where it has
    one; -1 where that is not in ``kv``) and whether it has one there."""
    ypos = np.full(n, -1)
    ypos[yi] = np.arange(yi.size)
    is_x = kv < n
    vertex = kv.copy()
    vertex[~is_x] = yi[kv[~is_x] - n]
    where = np.full(m, -1)
    where[kv] = np.arange(kv.size)
    partner = vertex.copy()  # a q_y's partner: its vertex's q_x
    yx = ypos[kv[is_x]]  # a q_x's partner: its vertex's q_y, where it has one
    partner[is_x] = np.where(yx >= 0, n + yx, -1)
    partner = np.where(partner >= 0, where[np.maximum(partner, 0)], -1)
    return vertex, is_x, partner, partner >= 0


def _partner_rows(rows, partner, has) -> np.ndarray:
    """Each row's partner row among ``rows`` (``_partners``), a row of zeros where it has none."""
    out = np.zeros_like(rows)
    out[has] = rows[partner[has]]
    return out


class _ContactBlock:
    """The Newton matrix of ``_newton_blocks`` restricted to the unknowns ``kv`` of the vertices in contact
    (packed, sorted: their q_x, then their q_y off the plane), without the columns out of contact: the
    block of dz/dv on ``kv`` gathered once, each unknown's partner (the other component of its vertex,
    where it has one) located in it, so that a row of P' dz/dv is s1 times its own row plus s2 times its
    partner's (``_projection_jacobian``'s chain rule: P'_xx, P'_xy for a q_x row, P'_yy, P'_xy for a
    q_y row). The same entries as ``_newton_blocks``, in as many floating-point operations."""

    def __init__(self, kv, n, yi, dz_dv, dz_du):
        self.kv = kv
        self.D = dz_dv[np.ix_(kv, kv)]
        self.vertex, self.is_x, self.partner, self.has_partner = _partners(kv, n, yi, dz_dv.shape[0])
        self.du = dz_du[self.vertex]  # dz/du of the vertex's x unknown (dz_y/du = 0)
        self.D_partner = _partner_rows(self.D, self.partner, self.has_partner)

    def _fill(self, z, g, J):
        """Write I - P' dz/dv on the contact's unknowns at z into J[:t, :t]; return P' dz/du (t,)."""
        Pxx, Pyy, Pxy = _projection_derivative(z, g)
        j = self.vertex
        s1 = np.where(self.is_x, Pxx[j], Pyy[j])
        s2 = np.where(self.has_partner, Pxy[j], 0.0)
        t = self.kv.size
        # -(s1 own + s2 partner), as (-s1) own - s2 partner: the same numbers (IEEE rounding is symmetric)
        np.multiply(-s1[:, None], self.D, out=J[:t, :t])
        J[:t, :t] -= s2[:, None] * self.D_partner
        J[np.arange(t), np.arange(t)] += 1.0
        return np.where(self.is_x, s1, s2) * self.du

    def matrix(self, z, g, fc, A, dscale):
        """The Newton matrix on the contact's unknowns at z (with ``fc`` the u column and the force row)."""
        t = self.kv.size
        J = np.empty((t + (1 if fc else 0),) * 2)
        Pu = self._fill(z, g, J)
        if fc:
            J[:t, -1] = -Pu * dscale
            row = np.zeros(t)
            row[self.is_x] = A[self.kv[self.is_x]] / (A.sum() + 1e-300)
            J[-1, :t] = row
            J[-1, -1] = 0.0
        return J

    def tangent(self, z, g):
        """(I - P' dz/dv, P' dz/du) on the contact's unknowns at z: the system of d v / d u."""
        J = np.empty((self.kv.size,) * 2)
        return J, self._fill(z, g, J)


#: the last contact block of each reduced flexibility (``_contact_block``)
_CONTACT_BLOCKS: dict = {}


def _contact_block(kv, n, yi, dz_dv, dz_du) -> "_ContactBlock":
    """``_ContactBlock(kv, n, yi, dz_dv, dz_du)``, or the one built last for the same flexibility, contact
    and dz/du (a Coulomb increment and its tangent, and the increments of a constant contact, share it)."""
    return _last_blocks(dz_dv, (kv.tobytes(), dz_du.tobytes()), lambda: _ContactBlock(kv, n, yi, dz_dv, dz_du),
                        _CONTACT_BLOCKS)


def _newton_blocks(z, g, yi, dz_dv, dz_du, kept, out, fc, A, dscale) -> tuple:
    """The semi-smooth Newton matrix of ``solve_tangential3d`` at z, restricted to the ``kept`` unknowns
    (rows and columns; with ``fc`` the last is u, scaled by ``dscale``) and its columns ``out``: the
    entries of I - P' dz/dv (``_projection_jacobian``), -P' dz/du dscale and the force row A / sum A,
    formed for the kept rows only (the rows out of contact are identity rows)."""
    m = dz_dv.shape[0]
    kv = kept[kept < m]
    Pk, Puk = _projection_jacobian(z, g, yi, dz_dv, dz_du, rows=kv)
    k = kept.size
    Jkk = np.zeros((k, k))
    Jkk[:kv.size, :kv.size] = np.eye(kv.size) - Pk[:, kv]
    Jko = np.zeros((k, out.size))
    Jko[:kv.size] = 0.0 - Pk[:, out]
    if fc:
        n = A.size
        row = np.zeros(m)
        row[:n] = A / (A.sum() + 1e-300)
        Jkk[:kv.size, -1] = -Puk * dscale
        Jkk[-1, :kv.size] = row[kv]
        Jko[-1] = row[out]
    return Jkk, Jko


def _projection_derivative(z, g) -> tuple:
    """The entries (P'_xx, P'_yy, P'_xy) per vertex of the 2x2 derivative of the projection onto the disk
    |q| <= g at z: fac (I - t t^T) where z slips (|z| > g, t its direction, fac = g / |z|), I where it
    sticks and 0 out of contact (g = 0)."""
    nz = np.hypot(z[:, 0], z[:, 1])
    slip = (nz > g) & (g > 0)
    tx = np.where(slip, z[:, 0] / np.maximum(nz, 1e-300), 0.0)
    ty = np.where(slip, z[:, 1] / np.maximum(nz, 1e-300), 0.0)
    fac = np.where(g <= 0, 0.0, np.where(slip, g / np.maximum(nz, 1e-300), 1.0))
    return fac * (1 - tx * tx), fac * (1 - ty * ty), -fac * tx * ty


def _projection_jacobian(z, g, yi, dz_dv, dz_du, rows=None):
    """The chain rule through the disk projections of the Coulomb residual: (P' dz/dv, P' dz/du)
    in the packed layout (q_x of every vertex, q_y of the vertices ``yi`` off the plane), with the
    per-vertex 2x2 derivative P'_j = fac_j (I - t_j t_j^T) where z_j slips (|z_j| > g_j, t_j its
    direction, fac_j = g_j / |z_j|), I where it sticks and 0 out of contact (g_j = 0). ``rows``: only
    those packed rows (sorted), each entry computed as in the whole."""
    n = z.shape[0]
    Pxx, Pyy, Pxy = _projection_derivative(z, g)
    if rows is not None:
        jx = rows[rows < n]  # x rows: vertex j
        iy = rows[rows >= n] - n  # y rows: position in yi
        ypos = np.full(n, -1)
        ypos[yi] = np.arange(yi.size)
        rows_x = Pxx[jx, None] * dz_dv[jx]
        has_y = ypos[jx] >= 0
        rows_x[has_y] += Pxy[jx[has_y], None] * dz_dv[n + ypos[jx[has_y]]]
        jy = yi[iy]
        rows_y = Pyy[jy, None] * dz_dv[n + iy] + Pxy[jy, None] * dz_dv[jy]
        return np.vstack([rows_x, rows_y]), np.concatenate([Pxx[jx] * dz_du[jx], Pxy[jy] * dz_du[jy]])
    rows_x = Pxx[:, None] * dz_dv[:n]
    rows_x[yi] += Pxy[yi, None] * dz_dv[n:]
    rows_y = Pyy[yi, None] * dz_dv[n:] + Pxy[yi, None] * dz_dv[yi]
    Pdz = np.vstack([rows_x, rows_y])
    Pdu = np.concatenate([Pxx * dz_du[:n], Pxy[yi] * dz_du[yi]])  # dz_y/du = 0
    return Pdz, Pdu


def tangential_slope(Dt, A, g, on_plane, q, r) -> float:
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
    yi, D, cd, dz_dv = _reduced(Dt, on_plane)
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
    J, Pdu = _contact_block(kv, n, yi, dz_dv, Cvec * ex).tangent(z, g)
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


def _tangential_force_by_secant(Dt, A, g, P_old, on_plane, force, q0, fista_iter):
    """Force control fallback: the total force is continuous and nondecreasing in u; regula
    falsi (Illinois) on displacement-controlled increments."""
    def total(dl):
        out = solve_tangential3d(Dt, A, g, P_old, on_plane, u=dl, q0=q0, fista_iter=fista_iter)
        return A @ out.q[:, 0] - force, out

    scale = float(np.max(np.abs(P_old)) / np.min(A) + np.max(g) * np.max(np.diag(Dt)) / np.min(A)) + 1e-300
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


def tangential_history(Dt, A, g, on_plane, Fx=None, u=None):
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
        return _history(Dt, A, g, on_plane, Fx, hist, P, q, dl, out, contact)


def _history(Dt, A, g, on_plane, Fx, hist, P, q, dl, out, contact):
    for k, h in enumerate(hist):
        if Fx is not None:
            r = solve_tangential3d(Dt, A, g, P, on_plane, force=h / 2, q0=q, u0=dl)
        else:
            r = solve_tangential3d(Dt, A, g, P, on_plane, u=h, q0=q)
        q, dl = r.q, r.u
        Pn = r.s
        out.work[k] = 2.0 * float(np.sum((r.q * (Pn - P))[contact]))
        P = Pn
        out.Fx[k] = 2.0 * float(A @ r.q[:, 0])
        out.u[k] = r.u
        out.q.append(r.q)
        out.P.append(P)
    return out


def solve_coupled3d(rf: RelativeFlexibility, gap0, A, mu, P_old, on_plane, *, F_n=None, d=None, u=None,
                    F_t=None, q0=None, u0=None, p0=None, tol=1e-9, max_iter=200, method="newton"):
    """One increment of the coupled problem of a dissimilar pair (module docstring): the normal
    gap feels the tangential traction and the slip the pressure through ``rf.K``,

        gap = gap0 - d A + D_n p - K^T q,     s = u A e_x - D_t q + K p.

    ``method="newton"`` (default): one semi-smooth Newton method on both complementarity functions
    at once (``_coupled_newton``), started from the Signorini solve at the last traction; where it
    does not converge, the alternation. ``method="alternate"``: the Signorini and the Coulomb solves
    in turn (block Gauss-Seidel) until the pressure and the traction change by less than ``tol`` of
    their largest values; the coupling of elastic pairs is weak (its size is Dundurs' beta,
    |beta| <= 1/2 and ~0.1 for steel on aluminium), so this converges linearly at a rate of about
    beta^2 (five passes per increment for steel on aluminium). Both solve the same equations to
    their tolerances. ``F_n``/``d``: half-model normal force or approach; ``u``/``F_t``: tangential
    displacement or half-model force; ``P_old`` the weighted slip (true, including K p) of the
    last step. Returns ``(p, d, TangentialResult with s the true slip, iterations)``; raises
    ``ConvergenceError`` if neither settles."""
    if method not in ("newton", "alternate"):
        raise ValueError(f"method must be 'newton' or 'alternate', got {method!r}")
    if method == "newton" and rf.K is not None:
        out = _coupled_newton(rf, gap0, A, mu, P_old, on_plane, F_n=F_n, d=d, u=u, F_t=F_t, q0=q0, u0=u0, p0=p0)
        if out is not None:
            return out
    n = A.size
    K = rf.K
    q = np.zeros((n, 2)) if q0 is None else np.asarray(q0, dtype=float)
    p = p0
    dl = u0
    for it in range(1, max_iter + 1):
        qv = np.concatenate([q[:, 0], q[:, 1]])
        p_new, dd, _, _ = solve_normal3d(rf.Dn, gap0 - (K.T @ qv if K is not None else 0.0), A, force=F_n, approach=d,
                                         p0=p)
        Kp = K @ p_new if K is not None else np.zeros(2 * n)
        Kp2 = np.column_stack([Kp[:n], Kp[n:]])
        res = solve_tangential3d(rf.Dt, A, mu * p_new, np.asarray(P_old) - Kp2, on_plane, u=u,
                                 force=F_t, q0=q, u0=dl)
        dp = np.max(np.abs(p_new - p)) if p is not None else np.inf
        dq = np.max(np.abs(res.q - q))
        p, q, dl = p_new, res.q, res.u
        scale = max(float(np.max(p)), 1e-300)
        if K is None or (dp <= tol * scale and dq <= tol * mu * scale):
            res.s = res.s + Kp2
            return p, dd, res, it
    raise ConvergenceError(f"coupled normal-tangential increment: the alternation did not settle in {max_iter} "
                           f"passes (last change {dp / scale:.3g} of the largest pressure, {dq / scale:.3g} in q)")


#: the packed coupling operators of the last few (K, on_plane) pairs (``_coupled_operators``)
_COUPLED: dict = {}


def _coupled_operators(rf: RelativeFlexibility, on_plane) -> tuple:
    """(Kp, Kp^T, dz/d(p, v)) of a dissimilar pair in the packed layout of ``_reduced``: K's rows of the
    packed unknowns (m, n), its transpose, and [diag(c) Kp, dz/dv] (m, n + m), the derivative of the
    trial traction z by the pressures and the tractions. Formed once per flexibility and plane set
    (``_held_by``)."""
    def build():
        n = rf.K.shape[1]
        yi, _, cd, dz_dv = _reduced(rf.Dt, on_plane)
        Kp = rf.K[np.concatenate([np.arange(n), n + yi])]
        return Kp, np.ascontiguousarray(Kp.T), np.hstack([cd[:, None] * Kp, dz_dv])

    return _held_by(_COUPLED, rf.K, on_plane, build)


def _coupled_newton(rf, gap0, A, mu, P_old, on_plane, *, F_n, d, u, F_t, q0, u0, p0, max_iter=100):
    """``solve_coupled3d`` by one semi-smooth Newton method on the unknowns (p, q, [d], [u]) and the
    residuals

        R_n = p - max(0, p - c_n gap),   R_t,j = q_j - proj_{|.| <= mu max(p_j, 0)}(q_j + c_j (s_j - P_j,old)),

    with the force rows (sum A p - F_n) / sum A and (sum A q_x - F_t) / sum A where a force is
    prescribed (c_n = 1 / diag D_n, c = 1 / diag D_t as in the uncoupled solves). Its generalized
    Jacobian couples them through K (dgap/dq = -K^T, ds/dp = K) and the slip limit (a slipping
    vertex's traction grows with its pressure: d proj / d g = its slip direction). Rows of vertices
    out of contact are identity rows (p = 0 off the active set, q = 0 where p <= 0): set to zero, the
    rest solved densely on the contact. Starts from the Signorini solve at the traction ``q0``.
    Converged when every residual is within ``TOL`` of the largest pressure (mu times it for the
    tangential rows); returns ``solve_coupled3d``'s tuple, or None where it does not converge (the
    caller alternates then). The steps: the split Jacobian first (``_CoupledFactor``), reused while
    its steps halve ||R|| (the chord method) and refactorised at x when they do not or the kept
    unknowns change; where a fresh split one does not halve ||R||, its step backtracked (up to five
    halvings) until ||R|| decreases, and where that fails too, the whole Jacobian, backtracked the same
    way. Only the iterations depend on these choices, not the solution."""
    n = A.size
    yi, D, cd, dz_dv = _reduced(rf.Dt, on_plane)
    m = D.shape[0]
    Kp, KpT, dz_dpv = _coupled_operators(rf, on_plane)
    Dn = rf.Dn
    cn = 1.0 / np.diag(Dn)
    ex = np.concatenate([A, np.zeros(yi.size)])
    Pold = _pack(np.asarray(P_old), yi)
    dz_du = cd * ex
    fn, ft = F_n is not None, F_t is not None
    sA = float(A.sum())
    sn = 1.0 / float(np.mean(cn * A))  # column scalings of d and u: O(1) entries (m against Pa)
    st = 1.0 / float(np.mean(cd[:n] * A))
    N = n + m + fn + ft

    unpack, pack = partial(_unpack, n=n, yi=yi), partial(_pack, yi=yi)

    def split(x):
        dd = x[n + m] * sn if fn else d
        uu = x[N - 1] * st if ft else u
        return x[:n], x[n:n + m], dd, uu

    plane = np.asarray(on_plane, dtype=bool).tobytes()

    def residual(x):
        p, v, dd, uu = split(x)
        # the products on the columns of the unknowns that are not 0 (p: the active set, v: the contact,
        # after the first iterate), gathered once per pattern: the same sums of the same nonzero terms
        ip, iv = np.flatnonzero(p), np.flatnonzero(v)
        Dn_, KpT_, D_, Kp_ = _last_blocks(rf.K, (plane, ip.tobytes(), iv.tobytes()),
                                          lambda: (Dn[:, ip], KpT[:, iv], D[:, iv], Kp[:, ip]), _COLUMNS)
        pi, vi = p[ip], v[iv]
        gap = gap0 - dd * A + Dn_ @ pi - KpT_ @ vi
        s = uu * ex - D_ @ vi + Kp_ @ pi
        z = unpack(v + cd * (s - Pold))
        g = mu * np.maximum(p, 0.0)
        R = np.concatenate([p - np.maximum(0.0, p - cn * gap), v - pack(project_disk(z, g))])
        if fn:
            R = np.append(R, (A @ p - F_n) / sA)
        if ft:
            R = np.append(R, (A @ v[:n] - F_t) / sA)
        return R, s, z, g, p - cn * gap > 0

    def backtrack(dx, Rt_, nr0, tries):
        """(step, residual) of the first of 1, 1/2, 1/4, ... (``tries`` of them) along dx where ||R||
        decreases (Armijo), or None; ``Rt_`` the residual at the full step."""
        step = 1.0
        for _ in range(tries):
            if np.linalg.norm(Rt_[0]) < (1 - 1e-4 * step) * nr0:
                return step, Rt_
            step *= 0.5
            Rt_ = residual(x + step * dx)
        return None

    v0 = np.zeros(m) if q0 is None else pack(np.asarray(q0, dtype=float))
    try:
        p, dd, _, _ = solve_normal3d(Dn, gap0 - KpT @ v0, A, force=F_n, approach=d, p0=p0)
    except ConvergenceError:
        return None
    x = np.concatenate([p, pack(project_disk(unpack(v0), mu * p))] + ([[dd / sn]] if fn else [])
                       + ([[(0.0 if u0 is None else float(u0)) / st]] if ft else []))
    R, s, z, g, act = residual(x)
    scale = lambda x_: max(float(np.max(x_[:n])), 1e-300)  # noqa: E731
    wt = np.concatenate([np.ones(n), np.full(m, 1.0 / max(mu, 1e-300)), np.ones(fn + ft)])
    fac, fac_key, split_ok = None, None, True
    for it in range(1, max_iter + 1):
        if np.max(np.abs(R) * wt) <= TOL * scale(x):
            p, v, dd, uu = split(x)
            return p, dd, TangentialResult(unpack(v), float(uu), unpack(s), it - 1, "coupled newton"), it - 1
        on = np.concatenate([g > 0, g[yi] > 0])  # packed tangential unknowns in contact
        keep = np.concatenate([act, on, np.ones(fn + ft, bool)])
        if np.any(x[~keep]):  # identity rows (off the active set, out of contact): their unknowns are 0
            x = np.where(keep, x, 0.0)
            R, s, z, g, act = residual(x)
            continue
        key = keep.tobytes()
        kept = np.flatnonzero(keep)
        if key != fac_key:  # a new set of kept unknowns: a new Jacobian
            fac = None
        nr0 = np.linalg.norm(R)
        while True:
            fresh = fac is None
            if fresh:  # the Jacobian at x, factorised (kept while the steps contract)
                ia, kv = np.flatnonzero(act), np.flatnonzero(on)
                blocks = _last_blocks(rf.K, (plane, key, fn),
                                      lambda: _coupled_blocks(Dn, cn, KpT, dz_dpv, A, sA, ia, kv, n, sn, fn, yi))
                tt, tn = _coupled_jacobian(blocks, z, g, dz_du, mu, ia.size, n, A, sA, st, fn, ft)
                try:
                    fac, fac_key = _CoupledFactor(blocks, tt, tn, ia.size, kv.size, fn, ft, split_ok), key
                except (sla.LinAlgError, ValueError):
                    return None
            dx = np.zeros(N)
            dx[kept] = -fac.solve(R[kept])
            Rt_ = residual(x + dx)
            if np.linalg.norm(Rt_[0]) < 0.5 * nr0:  # a step that halves ||R||: taken whole
                step = 1.0
                break
            if not fresh:  # a reused factorisation that no longer contracts: the Jacobian at x
                fac = None
                continue
            # a fresh Jacobian whose step does not halve ||R||: backtracked until ||R|| decreases; the split one
            # a few halvings (the weak coupling left out), then the whole one; the whole one 30 halvings
            found = backtrack(dx, Rt_, nr0, 6 if fac.split else 30)
            if found is not None:
                step, Rt_ = found
                break
            if fac.split:
                split_ok, fac = False, None
                continue
            return None
        x = x + step * dx
        R, s, z, g, act = Rt_
    return None


class _CoupledFactor:
    """The factorised Jacobian of ``_coupled_newton`` (unknowns [p_ia, v_kv, d, u]). ``split``: the
    normal rows' dependence on the tractions (-c_n K^T, of the size of Dundurs' beta) left out, so J is
    block lower-triangular and two LU factorisations of its blocks (the normal one [p, d]; the
    tangential one [v, u]) replace one of the whole (a quasi-Newton step that contracts at a rate of
    about beta^2; the caller falls back to the whole J where it does not halve ||R||)."""

    def __init__(self, b, tt, tn, r0, t, fn, ft, split):
        self.iN, self.iT = _split_index(r0, t, fn, ft)
        self.split = bool(split and self.iN.size and self.iT.size)
        if self.split:
            self.lu_n = b["lu_n"]  # the normal block depends on the kept unknowns alone (``_coupled_blocks``)
            self.lu_t = sla.lu_factor(tt, check_finite=False)
            self.Jtn = tn
        else:
            self.lu = sla.lu_factor(_whole_jacobian(b, tt, tn, r0, t, fn, ft), check_finite=False)

    def solve(self, r):
        if not self.split:
            return sla.lu_solve(self.lu, r, check_finite=False)
        y = np.empty_like(r)
        y[self.iN] = sla.lu_solve(self.lu_n, r[self.iN], check_finite=False)
        y[self.iT] = sla.lu_solve(self.lu_t, r[self.iT] - self.Jtn @ y[self.iN], check_finite=False)
        return y


#: the last gathered blocks of each dissimilar pair's coupling (``_last_blocks``)
_BLOCKS: dict = {}
#: the last gathered columns of each operator in a residual (``solve_tangential3d``'s, ``_coupled_newton``'s)
_COLUMNS: dict = {}


def _last_blocks(K, key, build, cache: dict = _BLOCKS):
    """``build()``, or what it built last for the coupling ``K`` under the same ``key`` (the same kept
    unknowns: at a constant normal force the contact, and so the key, mostly stays from one increment to
    the next). One entry per K in ``cache``, held weakly as ``_held_by`` holds its operators."""
    hit = cache.get(id(K))
    if hit is not None and hit[0]() is K and hit[1] == key:
        return hit[2]
    blocks = build()
    if hit is None or hit[0]() is not K:
        weakref.finalize(K, cache.pop, id(K), None)
    cache[id(K)] = (weakref.ref(K), key, blocks)
    return blocks


def _coupled_blocks(Dn, cn, KpT, dz_dpv, A, sA, ia, kv, n, sn, fn, yi) -> dict:
    """The parts of ``_coupled_newton``'s Jacobian that depend only on the kept unknowns (the active
    pressures ``ia``, the packed tractions in contact ``kv``): the normal rows' columns, the rows of
    dz/d(p, v) of the kept tractions and of their partners on the kept columns (per column block), and
    the normal block [p, d] factorised (``_CoupledFactor``'s split step), gathered once per set."""
    cols = np.concatenate([ia, n + kv])
    normal = np.zeros((ia.size, cols.size + fn))
    normal[:, :ia.size] = cn[ia, None] * Dn[np.ix_(ia, ia)]
    normal[:, ia.size:cols.size] = -cn[ia, None] * KpT[np.ix_(ia, kv)]
    if fn:
        normal[:, -1] = -cn[ia] * A[ia] * sn
    where = np.full(n, -1)
    where[ia] = np.arange(ia.size)
    Jnn = np.zeros((ia.size + fn, ia.size + fn))  # the rows and columns [p_ia, d] of the Jacobian
    Jnn[:ia.size, :ia.size] = normal[:, :ia.size]
    if fn:
        Jnn[:ia.size, -1] = normal[:, -1]
        Jnn[-1, :ia.size] = A[ia] / sA
    lu_n = sla.lu_factor(Jnn, check_finite=False) if Jnn.size else None
    # the rows of dz/d(p, v) on the kept columns that P' dz/d(p, v) reads for the kept tractions kv: each
    # one's own row and its partner's (``_partners``: the other component of its vertex, in contact with
    # it; a row of zeros where it has none), in kv's order, per column block (the pressures', the tractions')
    vertex, is_x, partner, has = _partners(kv, n, yi, dz_dpv.shape[0])
    out = {}
    for part, cc in (("p", ia), ("v", n + kv)):
        out["rows_" + part] = dz_dpv[np.ix_(kv, cc)]
        out["partner_" + part] = _partner_rows(out["rows_" + part], partner, has)
    return {**out, "normal": normal, "Jnn": Jnn, "kv": kv, "has_partner": has, "is_x": is_x,
            "vertex": vertex, "where": where, "lu_n": lu_n}


def _coupled_jacobian(b, z, g, dz_du, mu, r0, n, A, sA, st, fn, ft) -> tuple:
    """``_coupled_newton``'s generalized Jacobian on the kept unknowns [p_ia, v_kv, d (fn), u (ft)]: the
    blocks of its tangential rows (the kept tractions', then u's force row), ``(tt, tn)``: against the
    tangential unknowns [v_kv, u] (I - P' dz/dv, -P' dz/du; the force row), and against the normal ones
    [p_ia, d] (-P' dz/dp, -mu t where a vertex slips: d proj / d g is its slip direction; nothing in d).
    The normal rows (c_n dgap, the force row of d) depend on the kept unknowns alone
    (``_coupled_blocks``); ``_whole_jacobian`` joins them."""
    t = b["vertex"].size
    # P' dz/d(p, v) on the kept rows and columns, as ``_projection_jacobian`` forms it (a row: s1 times its
    # own, plus s2 times its partner's), from the rows gathered once per set (``_coupled_blocks``)
    Pxx, Pyy, Pxy = _projection_derivative(z, g)
    vx = b["vertex"]
    s1 = np.where(b["is_x"], Pxx[vx], Pyy[vx])
    s2 = Pxy[vx]
    s2p = np.where(b["has_partner"], s2, 0.0)  # a row without a partner: its partner row is 0
    tt, tn = np.empty((t + ft, t + ft)), np.empty((t + ft, r0 + fn))
    for out, part in ((tt[:t, :t], "v"), (tn[:t, :r0], "p")):
        # -(s1 own + s2 partner), as (-s1) own - s2 partner: the same numbers (IEEE rounding is symmetric)
        np.multiply(-s1[:, None], b["rows_" + part], out=out)
        out -= s2p[:, None] * b["partner_" + part]
    tt[np.arange(t), np.arange(t)] += 1.0
    nz = np.hypot(z[:, 0], z[:, 1])
    slip = (nz[vx] > g[vx]) & (g[vx] > 0)
    comp = np.where(b["is_x"], z[vx, 0], z[vx, 1])
    col = b["where"][vx]
    sel = slip & (col >= 0)
    tn[np.flatnonzero(sel), col[sel]] -= mu * comp[sel] / nz[vx][sel]  # d proj / d g = the slip direction
    if fn:
        tn[:t, -1] = 0.0
    if ft:
        tt[:t, -1] = -(np.where(b["is_x"], s1, s2) * dz_du[vx]) * st
        tt[-1, :t] = np.where(b["is_x"], A[np.minimum(b["kv"], n - 1)], 0.0) / sA
        tt[-1, -1] = 0.0
        tn[-1] = 0.0
    return tt, tn


def _whole_jacobian(b, tt, tn, r0, t, fn, ft) -> np.ndarray:
    """The whole Jacobian of ``_coupled_newton`` [p_ia, v_kv, d, u] from its normal rows (``_coupled_blocks``)
    and its tangential ones (``_coupled_jacobian``)."""
    K = r0 + t + fn + ft
    iN, iT = _split_index(r0, t, fn, ft)
    J = np.zeros((K, K))
    J[np.ix_(iN, iN)] = b["Jnn"]
    J[:r0, r0:r0 + t] = b["normal"][:, r0:r0 + t]
    J[np.ix_(iT, iT)] = tt
    J[np.ix_(iT, iN)] = tn
    return J


def _split_index(r0, t, fn, ft) -> tuple:
    """The positions of the normal unknowns [p_ia, d] and the tangential ones [v_kv, u] in [p_ia, v_kv, d, u]."""
    K = r0 + t + fn + ft
    return (np.concatenate([np.arange(r0), [r0 + t] if fn else []]).astype(int),
            np.concatenate([np.arange(r0, r0 + t), [K - 1] if ft else []]).astype(int))


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
        last = 2.0 * float(A @ dq[:, 0])
        ahead = Fx - 2.0 * float(A @ q[:, 0])
    else:
        last, ahead = state.du, u - state.u
    if not (last != 0.0 and 0.0 < ahead / last <= 4.0):
        return q, state.u
    f = ahead / last
    return project_disk(q + f * dq, g), state.u + f * state.du
