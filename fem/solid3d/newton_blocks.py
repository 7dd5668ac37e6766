"""The semi-smooth Newton methods' building blocks of the 3D contact solves (``fem.solid3d.contact``,
``fem.solid3d.coupled``): the packed layout of the tangential tractions (q_x of every vertex, q_y of the
vertices not in ``qy_zero``: off the symmetry plane, or none under Mindlin's traction along x), the
flexibility reduced to it, the disk projection's derivative and the Jacobian blocks built from it, and the
operators a pair's solves keep between increments (``Operators``, owned by the pair's flexibility).
"""
from __future__ import annotations

import numpy as np


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


class Operators:
    """The operators a pair's solves keep between increments, owned by its flexibility
    (``fem.solid3d.contact.RelativeFlexibility.operators``: they go with the model). ``held``: formed
    once per name and set ``qy_zero`` (read-only; a law's flexibility is fixed, its steps many);
    ``last``: per slot, what was built last and the key it was built for (the same kept unknowns: at
    a constant normal force the contact, and so the key, mostly stays from one increment to the next).
    Only the cost depends on them, not the numbers."""

    def __init__(self):
        self._held, self._last = {}, {}

    def held(self, name: str, qy_zero, build) -> tuple:
        """``build()``'s arrays (made read-only), formed once per ``name`` and ``qy_zero``."""
        key = (name, np.asarray(qy_zero, dtype=bool).tobytes())
        out = self._held.get(key)
        if out is None:
            out = build()
            for a in out:
                a.setflags(write=False)
            self._held[key] = out
        return out

    def last(self, slot, key, build):
        """``build()``, or what it built last in ``slot`` for the same ``key``."""
        hit = self._last.get(slot)
        if hit is not None and hit[0] == key:
            return hit[1]
        out = build()
        self._last[slot] = (key, out)
        return out


def _reduced(rf, qy_zero) -> tuple:
    """(yi, D, cd, dz_dv) of the packed layout: the vertices ``yi`` not in ``qy_zero`` (their q_y is free), the
    flexibility's Dt (``rf``: a ``fem.solid3d.contact.RelativeFlexibility``) restricted to q_x of every vertex
    and q_y of ``yi``, cd = 1 / diag(D) and dz/dv = I - diag(cd) D. Formed once per flexibility and
    ``qy_zero`` (read-only, held by ``rf.operators``)."""
    def build():
        n = np.size(qy_zero)
        yi = np.flatnonzero(~np.asarray(qy_zero, dtype=bool))
        idx = np.concatenate([np.arange(n), n + yi])  # rows/cols of Dt kept
        D = rf.Dt[np.ix_(idx, idx)]
        cd = 1.0 / np.diag(D)  # c = 1 / diag(D): the scaling of the slip increments in z
        return yi, D, cd, np.eye(idx.size) - cd[:, None] * D

    return rf.operators.held("reduced", qy_zero, build)


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


def _contact_block(rf, qy_zero, kv, n, yi, dz_dv, dz_du) -> "_ContactBlock":
    """``_ContactBlock(kv, n, yi, dz_dv, dz_du)``, or the one built last for the same flexibility ``rf``, plane
    set, contact and dz/du (a Coulomb increment and its tangent, and the increments of a constant contact,
    share it; ``rf.operators``)."""
    plane = np.asarray(qy_zero, dtype=bool).tobytes()
    return rf.operators.last(("contact block", plane), (kv.tobytes(), dz_du.tobytes()),
                             lambda: _ContactBlock(kv, n, yi, dz_dv, dz_du))


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
