"""Fields for plotting: displacements and stresses of a solved normal contact, VTU export.

Stresses are evaluated at the quadrature points (``fem.axisym.stress_mode0``)
and averaged to the P2 nodes per body (volume-weighted nodal averaging of the
element values), which is what a field plot needs; they are not used in any
check of the physics.
"""
from __future__ import annotations

import numpy as np
from skfem import Basis, ElementTriP2

from meshes import export_vtu

from .axisym import node_dofs, stress_mode0

STRESS_KEYS = ("srr", "szz", "stt", "srz", "mises")


def nodal_fields(model, res) -> dict:
    """{"u": {body: (n, 3) (u_r, u_z, 0)}, "srr": {body: (n,)}, ...} at the P2 nodes (Pa, m)."""
    us = model.fields(res.lam, res.approach)
    out = {"u": {}}
    for k in STRESS_KEYS:
        out[k] = {}
    for name, body in model.bodies.items():
        if name not in us:  # rigid indenter
            n = Basis(body.mesh, ElementTriP2(), intorder=1).N
            out["u"][name] = np.column_stack([np.zeros(n), np.full(n, -res.approach), np.zeros(n)])
            for k in STRESS_KEYS:
                out[k][name] = np.zeros(n)
            continue
        u = us[name]
        nd = node_dofs(body.basis)
        out["u"][name] = np.column_stack([u[nd[0]], u[nd[1]], np.zeros(nd.shape[1])])
        s = stress_mode0(body.basis, u, body.E, body.nu)
        sb = Basis(body.mesh, ElementTriP2(), quadrature=body.basis.quadrature)
        wts = np.abs(sb.dx)  # (nelem, nqp) quadrature weights * |J|
        edofs = sb.element_dofs  # (6, nelem)
        vol = np.zeros(sb.N)
        np.add.at(vol, edofs, np.broadcast_to(wts.sum(1), edofs.shape))
        for k in STRESS_KEYS:
            acc = np.zeros(sb.N)
            np.add.at(acc, edofs, np.broadcast_to((s[k] * wts).sum(1), edofs.shape))
            out[k][name] = acc / vol
    return out


def write_vtu(model, res, path):
    """Write displacement and stresses of both bodies to a .vtu file (ParaView)."""
    f = nodal_fields(model, res)
    return export_vtu(model.amesh, path, point_data=f)
