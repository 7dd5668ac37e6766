"""The coupled increment of a dissimilar pair on the 3D mortar interface: the normal gap feels the
tangential traction and the slip the pressure through the antisymmetric coupling K = D1_tz - D2_tz
(``fem.solid3d.contact.RelativeFlexibility``; zero for one material, Dundurs' beta = 0). One semi-smooth
Newton method on both complementarity functions at once, or the Signorini and Coulomb solves of
``fem.solid3d.contact`` in turn (``solve_coupled3d``).
"""
from __future__ import annotations

from functools import partial

import numpy as np
import scipy.linalg as sla

from common.errors import ConvergenceError

from fem.solid3d.contact import (TOL, RelativeFlexibility, TangentialResult, project_disk, solve_normal3d,
                                 solve_tangential3d)
from fem.solid3d.newton_blocks import (_pack, _partner_rows, _partners, _projection_derivative, _reduced,
                                       _unpack)


def solve_coupled3d(rf: RelativeFlexibility, gap0, A, mu, P_old, qy_zero, *, F_n=None, d=None, u=None,
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
        out = _coupled_newton(rf, gap0, A, mu, P_old, qy_zero, F_n=F_n, d=d, u=u, F_t=F_t, q0=q0, u0=u0, p0=p0)
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
        res = solve_tangential3d(rf, A, mu * p_new, np.asarray(P_old) - Kp2, qy_zero, u=u,
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


def _coupled_operators(rf: RelativeFlexibility, qy_zero) -> tuple:
    """(Kp, Kp^T, dz/d(p, v)) of a dissimilar pair in the packed layout of ``_reduced``: K's rows of the
    packed unknowns (m, n), its transpose, and [diag(c) Kp, dz/dv] (m, n + m), the derivative of the
    trial traction z by the pressures and the tractions. Formed once per flexibility and plane set
    (held by ``rf.operators``)."""
    def build():
        n = rf.K.shape[1]
        yi, _, cd, dz_dv = _reduced(rf, qy_zero)
        Kp = rf.K[np.concatenate([np.arange(n), n + yi])]
        return Kp, np.ascontiguousarray(Kp.T), np.hstack([cd[:, None] * Kp, dz_dv])

    return rf.operators.held("coupled", qy_zero, build)


# 131 lines, above the house limit of 120 for a stated reason: one Newton solve whose residual, line search
# and factorisation share the iterate's split and the kept unknowns; apart they would pass a dozen arrays
def _coupled_newton(rf, gap0, A, mu, P_old, qy_zero, *, F_n, d, u, F_t, q0, u0, p0, max_iter=100):
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
    yi, D, cd, dz_dv = _reduced(rf, qy_zero)
    m = D.shape[0]
    Kp, KpT, dz_dpv = _coupled_operators(rf, qy_zero)
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

    plane = np.asarray(qy_zero, dtype=bool).tobytes()

    def residual(x):
        p, v, dd, uu = split(x)
        # the products on the columns of the unknowns that are not 0 (p: the active set, v: the contact,
        # after the first iterate), gathered once per pattern: the same sums of the same nonzero terms
        ip, iv = np.flatnonzero(p), np.flatnonzero(v)
        Dn_, KpT_, D_, Kp_ = rf.operators.last("coupled columns", (plane, ip.tobytes(), iv.tobytes()),
                                               lambda: (Dn[:, ip], KpT[:, iv], D[:, iv], Kp[:, ip]))
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
                blocks = rf.operators.last("coupled blocks", (plane, key, fn),
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
