"""Fields for plotting: displacements and stresses of a solved normal contact, VTU export.

Stresses are evaluated at the quadrature points (``fem.axisym.mode0.stress_mode0``)
and averaged to the P2 nodes per body (volume-weighted nodal averaging of the
element values), which is what a field plot needs; they are not used in any
check of the physics.
"""
from __future__ import annotations

import numpy as np
from skfem import Basis, ElementTriP2

from meshes import export_vtu

from fem.axisym.mode0 import node_dofs, stress_mode0
from fem.bulk import plate_from_contact
from fem.axisym.mode1 import node_dofs_mode1, stress_mode1

STRESS_KEYS = ("srr", "szz", "stt", "srz", "mises")
#: the stress components (Pa, r-z axes)
COMPONENTS = STRESS_KEYS[:4]


def _nodal_average(mesh, quadrature, values: dict) -> dict:
    """Volume-weighted average of element quadrature values {key: (nelem, nqp)} to the P2 nodes."""
    sb = Basis(mesh, ElementTriP2(), quadrature=quadrature)
    wts = np.abs(sb.dx)  # (nelem, nqp) quadrature weights * |J|
    edofs = sb.element_dofs  # (6, nelem)
    vol = np.zeros(sb.N)
    np.add.at(vol, edofs, np.broadcast_to(wts.sum(1), edofs.shape))
    out = {}
    for k, v in values.items():
        acc = np.zeros(sb.N)
        np.add.at(acc, edofs, np.broadcast_to((v * wts).sum(1), edofs.shape))
        out[k] = acc / vol
    return out


def _mises(srr, szz, stt, srz):
    return np.sqrt(0.5 * ((srr - szz) ** 2 + (szz - stt) ** 2 + (stt - srr) ** 2) + 3.0 * srz**2)


def fretting_fields(law, state, F_N) -> dict:
    """Displacements and von Mises stress in the plane of the tangential load (FE contact law).

    Superposes mode 0 (normal force ``F_N``) and mode 1 (the pair forces ``state.T``
    of an ``fem.axisym.law.FEState``; indenter top moved by the plate displacement) on the
    x-z plane: theta = 0 (the +x half) and theta = pi (the -x half), where the
    sin(theta) stresses vanish. Returns point data over each body's P2 nodes (for
    ``meshes.export_vtu``): ``u_x0``/``u_x180`` ((n, 3): x, z, 0 of each half, the
    x component given as the radial one, u_r = +-u_x), ``mises_x0``/``mises_x180`` and the stress
    components ``srr_x0``, ``szz_x0``, ``stt_x0``, ``srz_x0`` and their ``_x180`` (Pa; at theta = pi the
    radial direction is -x, so ``srz_x180`` is the shear on the -x side in r-z axes), and the contact
    fields at theta = 0 (``contact_fields``: pressure, shear traction, status, slip).
    Assumes linear elasticity (superposition) and the law's small-sliding pairing.
    """
    model = law.model
    iface = model.interface
    res = law.normal(F_N=float(F_N))
    base = nodal_fields(model, res)
    T = np.asarray(state.T, dtype=float)
    u_plate = plate_from_contact(float(state.u), float(T.sum()), law.c_bulk)  # law.u may exclude c_bulk
    out = {k: {} for k in ("u_x0", "u_x180", "mises_x0", "mises_x180",
                           *(f"{c}_{half}" for c in COMPONENTS for half in ("x0", "x180")))}
    for name in ("indenter", "block"):
        _, basis, dofs, cond = law.mode1[name]
        body = model.bodies[name]
        if name == "indenter":
            rigid = np.zeros(basis.N)
            rigid[dofs[0]] = u_plate  # S = u_plate: a rigid translation along x
            u1 = cond.displacement(-T, u_fixed=rigid)
        else:
            u1 = cond.displacement(iface.N.T @ T)
        nd = node_dofs_mode1(basis)
        U, W = u1[nd[0]] + u1[nd[1]], u1[nd[2]]  # U = S + D
        s1 = stress_mode1(basis, u1, body.E, body.nu)
        a1 = _nodal_average(body.mesh, basis.quadrature, {k: s1[k] for k in ("srr", "szz", "stt", "srz")})
        ur0, uz0 = base["u"][name][:, 0], base["u"][name][:, 1]
        z = np.zeros_like(U)
        # theta = 0: u_r = ur0 + U, u_z = uz0 + W; theta = pi: u_r = ur0 - U, u_z = uz0 - W
        out["u_x0"][name] = np.column_stack([ur0 + U, uz0 + W, z])
        out["u_x180"][name] = np.column_stack([ur0 - U, uz0 - W, z])
        for half, sg in (("x0", 1.0), ("x180", -1.0)):
            comps = {k: base[k][name] + sg * a1[k] for k in ("srr", "szz", "stt", "srz")}
            out[f"mises_{half}"][name] = _mises(*comps.values())
            for k in COMPONENTS:
                out[f"{k}_{half}"][name] = comps[k]
    out.update({k: base[k] for k in ("u", "mises")})
    out.update(contact_fields(law, state, res))
    return out


#: ``contact_status`` values: no contact, stick, slip
STATUS = {"none": 0, "stick": 1, "slip": 2}


def contact_fields(law, state, res) -> dict:
    """The contact fields at the indenter's contact nodes (the pairs' slave points; 0 at every other
    node of both bodies), in the plane of the tangential load at theta = 0: ``contact_pressure``
    (Pa, the pair force over its weight), ``shear_traction_x`` (Pa, the mode-1 pair force over its
    weight: the traction along x), ``contact_status`` (``STATUS``: 0 no contact, 1 stick, 2 slip)
    and ``slip_x`` (m, the accumulated plastic slip of the pair). ``res``: the normal solution at the
    state's normal force; ``state``: an ``fem.axisym.law.FEState``."""
    iface = law.model.interface
    lam = np.asarray(state.lam, dtype=float)
    values = {"contact_pressure": lam / iface.w, "shear_traction_x": np.asarray(state.T, dtype=float) / iface.w,
              "contact_status": np.where(lam > 0, np.where(np.asarray(state.sgn) != 0, STATUS["slip"],
                                                           STATUS["stick"]), STATUS["none"]).astype(float),
              "slip_x": np.asarray(state.slip, dtype=float)}
    nodes = {name: Basis(body.mesh, ElementTriP2(), intorder=1).N for name, body in law.model.bodies.items()}
    out = {}
    for key, v in values.items():
        out[key] = {name: np.zeros(n) for name, n in nodes.items()}
        out[key]["indenter"][iface.ind_nodes] = v
    return out


def write_fretting_vtu(law, state, F_N, path):
    """VTU of :func:`fretting_fields` plus the mode-0 fields (``u``, ``mises``) at ``F_N``."""
    return export_vtu(law.model.amesh, path, point_data=fretting_fields(law, state, F_N))


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
        avg = _nodal_average(body.mesh, body.basis.quadrature, {k: s[k] for k in STRESS_KEYS})
        for k in STRESS_KEYS:
            out[k][name] = avg[k]
    return out


def write_vtu(model, res, path):
    """Write displacement and stresses of both bodies to a .vtu file (ParaView)."""
    f = nodal_fields(model, res)
    return export_vtu(model.amesh, path, point_data=f)
