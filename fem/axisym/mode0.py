"""Axisymmetric linear elasticity: weak forms of Fourier mode 0 on the r-z section.

Assumptions: small strains, homogeneous isotropic linear elastic body, geometry
and loads independent of the angle theta (mode 0: u = (u_r(r, z), 0, u_z(r, z))).
Coordinates of the section are x[0] = r >= 0, x[1] = z. Strains

    e_rr = du_r/dr,  e_zz = du_z/dz,  e_tt = u_r / r,  e_rz = (du_r/dz + du_z/dr) / 2,

stress sigma = lame_lambda tr(e) I + 2 lame_mu e, and the stiffness is the integral over the
body's volume, dV = 2 pi r dr dz, so assembled forces are total forces (N) on
the full ring. Regularity on the axis requires u_r = 0 at r = 0 (a Dirichlet
condition set by the caller); quadrature points are interior, so the hoop term
u_r/r is never evaluated at r = 0. Zienkiewicz & Taylor, *The Finite Element
Method*, vol. 1, 6th ed., Elsevier 2005, ch. 10.

Elements: P2 (``ElementVector(ElementTriP2())``) on the straight-sided
``MeshTri1`` of ``meshes.axisym``. The r-weighted integrand of the stiffness is
not a polynomial (hoop term); ``intorder=4`` (6 points) makes the quadrature
error far below the discretisation error (checked in the tests against the
closed form of a loaded cylinder).

The mode-1 forms (tangential loading) are in ``fem.axisym.mode1`` (``stiffness_mode1``),
which builds on this module (never the other way round); they share the node
numbering of :func:`node_dofs`.
"""
from __future__ import annotations

import numpy as np
from skfem import Basis, BilinearForm, ElementTriP2, ElementVector, asm

TWO_PI = 2.0 * np.pi


def lame(E, nu):
    """Lame constants (lame_lambda, lame_mu) of an isotropic material."""
    return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def strain_mode0(u, r):
    """(e_rr, e_zz, e_tt, e_rz) of a mode-0 field (skfem DiscreteField) at radii r."""
    grad = u.grad
    return grad[0, 0], grad[1, 1], u[0] / r, 0.5 * (grad[0, 1] + grad[1, 0])


def elasticity_mode0(lame_lambda, lame_mu):
    """Bilinear form of mode-0 axisymmetric elasticity, integrated over the full ring (2 pi r)."""

    @BilinearForm
    def form(u, v, w):
        r = w.x[0]
        a = strain_mode0(u, r)
        b = strain_mode0(v, r)
        tr_a = a[0] + a[1] + a[2]
        tr_b = b[0] + b[1] + b[2]
        dev = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2.0 * a[3] * b[3]
        return TWO_PI * r * (lame_lambda * tr_a * tr_b + 2.0 * lame_mu * dev)

    return form


def vector_basis(mesh, intorder: int = 4) -> Basis:
    """P2 vector basis (u_r, u_z) on a straight-sided triangle mesh."""
    return Basis(mesh, ElementVector(ElementTriP2()), intorder=intorder)


def node_dofs(basis) -> np.ndarray:
    """DOF numbers of the P2 nodes, shape (2, n_nodes): row 0 u_r, row 1 u_z.

    Node numbering is that of a scalar P2 basis on the same mesh: the vertices
    0..nv-1, then the facet midpoints nv + facet index.
    """
    return np.hstack([basis.nodal_dofs, basis.facet_dofs])


def node_coords(mesh) -> np.ndarray:
    """Coordinates (2, n_nodes) of the P2 nodes (vertices, then facet midpoints)."""
    mid = 0.5 * (mesh.p[:, mesh.facets[0]] + mesh.p[:, mesh.facets[1]])
    return np.hstack([mesh.p, mid])


def facet_nodes(mesh, facets) -> np.ndarray:
    """P2 nodes (3, n) of the given facets: the two vertices and the midpoint."""
    facets = np.asarray(facets)
    return np.vstack([mesh.facets[0, facets], mesh.facets[1, facets], mesh.p.shape[1] + facets])


def boundary_nodes(mesh, name) -> np.ndarray:
    """Sorted unique P2 nodes on the named boundary."""
    return np.unique(facet_nodes(mesh, mesh.boundaries[name]))


def stiffness(mesh, E, nu, mode: int = 0, intorder: int = 4):
    """Stiffness matrix (CSR, N/m) and basis of one body for the Fourier ``mode``.

    Mode 0: axisymmetric (normal contact), DOFs (u_r, u_z). Mode 1 (tangential
    loading along x, DOFs (S, D, W)) is ``fem.axisym.mode1.stiffness_mode1``.
    """
    if mode != 0:
        raise NotImplementedError(f"fem.axisym.mode0 has the Fourier mode-0 forms (mode {mode!r} asked); "
                                  "mode 1 is fem.axisym.mode1.stiffness_mode1, higher modes are not implemented")
    basis = vector_basis(mesh, intorder=intorder)
    lame_lambda, lame_mu = lame(E, nu)
    K = asm(elasticity_mode0(lame_lambda, lame_mu), basis)
    return K.tocsr(), basis


def stress_mode0(basis, u, E, nu):
    """Stresses at the quadrature points: dict of (n_elems, n_qp) arrays and their points.

    Keys ``srr, szz, stt, srz, mises`` (Pa) and ``r``, ``z`` (m).
    """
    lame_lambda, lame_mu = lame(E, nu)
    uf = basis.interpolate(u)
    r = basis.mapping.F(basis.quadrature[0])
    err, ezz, ett, erz = strain_mode0(uf, r[0])
    tr = err + ezz + ett
    s = {"srr": lame_lambda * tr + 2 * lame_mu * err, "szz": lame_lambda * tr + 2 * lame_mu * ezz,
         "stt": lame_lambda * tr + 2 * lame_mu * ett, "srz": 2 * lame_mu * erz}
    s["mises"] = np.sqrt(0.5 * ((s["srr"] - s["szz"]) ** 2 + (s["szz"] - s["stt"]) ** 2
                                + (s["stt"] - s["srr"]) ** 2) + 3.0 * s["srz"] ** 2)
    s["r"], s["z"] = r[0], r[1]
    return s
