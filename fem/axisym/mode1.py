"""Fourier mode 1 of axisymmetric elasticity: the weak form for tangential (x) loading.

Assumptions: small strains, homogeneous isotropic linear elastic body of
revolution, loads proportional to cos(theta) (a force along x). The
displacement field is

    u_r = U(r, z) cos(theta),   u_theta = -V(r, z) sin(theta),   u_z = W(r, z) cos(theta),

so a rigid translation by 1 along x is U = V = 1, W = 0, and a rigid tilt by
beta about the y axis is U = V = beta z, W = -beta r. The strain amplitudes
(cylindrical components; e_rt and e_tz multiply sin(theta), the others cos(theta)) are

    e_rr = U_r,  e_zz = W_z,  e_tt = (U - V)/r,  e_rz = (U_z + W_r)/2,
    e_rt = -(V_r + (U - V)/r)/2,   e_tz = -(V_z + W/r)/2,

and the energy integrated over theta gives the factor pi (int cos^2 = int sin^2
= pi) instead of mode 0's 2 pi. Zienkiewicz & Taylor, *The Finite Element
Method*, vol. 1, 6th ed., Elsevier 2005, sec. 10.5 (non-symmetric loading of
axisymmetric bodies).

Axis regularity (r = 0). A smooth field of Cartesian components requires
U = V and W = 0 on the axis, otherwise (U - V)/r and W/r blow up. The unknowns
are therefore the combinations

    S = (U + V)/2,   D = (U - V)/2,    (U = S + D, V = S - D)

with the Dirichlet conditions D = W = 0 on the axis (S is free: it is the
x-displacement of the axis). S is also the natural interface variable: a
traction tau(r) along x (t_r = tau cos, t_theta = -tau sin) does the work
2 pi int tau S r dr, so the generalised force conjugate to S is the x force
of the ring, and D is not loaded (Mindlin's assumption of a traction along x).

Elements and quadrature as in ``fem.axisym.mode0`` (P2, intorder 4). DOF layout:
``ElementVector(ElementTriP2(), 3)`` with components (S, D, W).
"""
from __future__ import annotations

import numpy as np
from skfem import Basis, BilinearForm, ElementTriP2, ElementVector, asm

from fem.axisym.mode0 import boundary_nodes, lame, node_coords


def strain_mode1(u, r):
    """Strain amplitudes (e_rr, e_zz, e_tt, e_rz, e_rt, e_tz) of a mode-1 field (S, D, W)."""
    D, W = u[1], u[2]
    gS, gD, gW = u.grad[0], u.grad[1], u.grad[2]
    U_r, U_z = gS[0] + gD[0], gS[1] + gD[1]
    V_r, V_z = gS[0] - gD[0], gS[1] - gD[1]
    UmV_r = 2.0 * D / r
    return (U_r, gW[1], UmV_r, 0.5 * (U_z + gW[0]), -0.5 * (V_r + UmV_r), -0.5 * (V_z + W / r))


def elasticity_mode1(lame_lambda, lame_mu):
    """Bilinear form of mode-1 elasticity integrated over theta (factor pi r)."""

    @BilinearForm
    def form(u, v, w):
        r = w.x[0]
        a = strain_mode1(u, r)
        b = strain_mode1(v, r)
        tr_a = a[0] + a[1] + a[2]
        tr_b = b[0] + b[1] + b[2]
        dev = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5])
        return np.pi * r * (lame_lambda * tr_a * tr_b + 2.0 * lame_mu * dev)

    return form


def vector_basis_mode1(mesh, intorder: int = 4) -> Basis:
    """P2 basis of the three mode-1 components (S, D, W)."""
    return Basis(mesh, ElementVector(ElementTriP2(), 3), intorder=intorder)


def node_dofs_mode1(basis) -> np.ndarray:
    """DOF numbers (3, n_nodes): rows S, D, W; nodes numbered as in ``fem.axisym.mode0.node_dofs``."""
    return np.hstack([basis.nodal_dofs, basis.facet_dofs])


def stiffness_mode1(mesh, E, nu, intorder: int = 4):
    """Mode-1 stiffness (CSR, N/m per unit amplitude) and basis of one body."""
    basis = vector_basis_mode1(mesh, intorder=intorder)
    lame_lambda, lame_mu = lame(E, nu)
    return asm(elasticity_mode1(lame_lambda, lame_mu), basis).tocsr(), basis


def fixed_dofs_mode1(mesh, basis, clamped: str) -> np.ndarray:
    """Dirichlet DOFs of one body in mode 1 (sorted, unique): D = W = 0 on the axis
    (regularity, module docstring) and S = D = W = 0 on the ``clamped`` face (the
    indenter's "top", moved rigidly by the plate displacement, or the block's "bottom")."""
    dofs = node_dofs_mode1(basis)
    ax = boundary_nodes(mesh, "axis")
    clamp = boundary_nodes(mesh, clamped)
    return np.unique(np.concatenate([dofs[1, ax], dofs[2, ax], dofs[:, clamp].ravel()]))


def stress_mode1(basis, u, E, nu) -> dict:
    """Mode-1 stress amplitudes at the quadrature points: ``srr, szz, stt, srz`` multiply
    cos(theta), ``srt, stz`` sin(theta) (Pa per unit load of the field ``u`` = (S, D, W))."""
    lame_lambda, lame_mu = lame(E, nu)
    uf = basis.interpolate(u)
    r = basis.mapping.F(basis.quadrature[0])[0]
    err, ezz, ett, erz, ert, etz = strain_mode1(uf, r)
    tr = err + ezz + ett
    return {"srr": lame_lambda * tr + 2 * lame_mu * err, "szz": lame_lambda * tr + 2 * lame_mu * ezz,
            "stt": lame_lambda * tr + 2 * lame_mu * ett,
            "srz": 2 * lame_mu * erz, "srt": 2 * lame_mu * ert, "stz": 2 * lame_mu * etz}


def rigid_fields(mesh) -> dict:
    """Nodal (S, D, W) vectors (3, n_nodes) of a unit x translation and a unit tilt about y."""
    r, z = node_coords(mesh)
    zero = np.zeros_like(r)
    # translation: U = V = 1 -> S = 1, D = 0; tilt: U = V = z, W = -r
    return {"translation": np.vstack([np.ones_like(r), zero, zero]),
            "tilt": np.vstack([z, zero, -r])}
