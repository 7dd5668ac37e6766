"""3D isotropic linear elasticity of the half-model block (issue 13, first increment).

Assumptions: small strains, homogeneous isotropic linear elastic block,
geometry and loads symmetric about the plane y = 0, so only y >= 0 is
modelled (``meshes.half3d``) with u_y = 0 on the plane (``symmetry``). The
bottom z = -height is clamped. Forces assembled here are those on the half
model (half the total force of the full body).

Elements: P2 tetrahedra (``ElementVector(ElementTetP2())``) on the linear
``MeshTet1``; the map is affine, so the stiffness (products of linear
gradients) is integrated exactly by ``intorder=2``. The weak form is scikit-fem's
``linear_elasticity`` with ``lame_parameters`` (Zienkiewicz & Taylor, *The
Finite Element Method*, vol. 1, 6th ed., 2005, ch. 6).

Sparse solves go through ``fem.solvers.factorize`` (CHOLMOD when
scikit-sparse is installed, else SuperLU).
"""
from __future__ import annotations

import numpy as np
from skfem import Basis, ElementTetP2, ElementVector, FacetBasis, LinearForm, asm
from skfem.models.elasticity import lame_parameters, linear_elasticity

from common.errors import InputError, in_range, positive

from fem.solvers import blas_threads, factorize


def check_material(E, nu):
    positive("E", E)
    in_range("nu", nu, -1.0, 0.5, lo_open=True, hi_open=True)


def vector_basis3d(mesh, intorder: int = 2) -> Basis:
    """P2 vector basis (u_x, u_y, u_z) on a linear tetrahedral mesh."""
    return Basis(mesh, ElementVector(ElementTetP2()), intorder=intorder)


def stiffness3d(mesh, E, nu, intorder: int = 2):
    """Unconstrained stiffness (CSR, N/m) and basis of the block."""
    check_material(E, nu)
    basis = vector_basis3d(mesh, intorder=intorder)
    lam, mu = lame_parameters(E, nu)
    return asm(linear_elasticity(lam, mu), basis).tocsr(), basis


def node_dofs3d(basis) -> np.ndarray:
    """DOF numbers of the P2 nodes, shape (3, n_nodes): rows u_x, u_y, u_z; nodes are the
    vertices 0..nv-1, then the edge midpoints nv + edge index."""
    return np.hstack([basis.nodal_dofs, basis.edge_dofs])


def node_coords3d(mesh) -> np.ndarray:
    """Coordinates (3, n_nodes) of the P2 nodes (vertices, then edge midpoints)."""
    mid = 0.5 * (mesh.p[:, mesh.edges[0]] + mesh.p[:, mesh.edges[1]])
    return np.hstack([mesh.p, mid])


def boundary_nodes3d(mesh, name) -> np.ndarray:
    """Sorted unique P2 nodes (vertices and edge midpoints) on the named boundary."""
    if name not in mesh.boundaries:
        raise InputError(f"boundary must be one of {', '.join(sorted(mesh.boundaries))}; got {name!r}")
    facets = mesh.boundaries[name]
    verts = np.unique(mesh.facets[:, facets])
    fe = np.unique(mesh.f2e[:, facets])  # the three edges of each boundary facet
    return np.concatenate([verts, mesh.p.shape[1] + fe])


def dirichlet_dofs(basis, mesh) -> np.ndarray:
    """Fixed DOFs of the half model: all of ``bottom``, u_y on ``symmetry``."""
    nd = node_dofs3d(basis)
    bottom = nd[:, boundary_nodes3d(mesh, "bottom")].ravel()
    sym = nd[1, boundary_nodes3d(mesh, "symmetry")]
    return np.unique(np.concatenate([bottom, sym]))


def pressure_load(mesh, basis, p, boundary: str = "contact", intorder: int = 4) -> np.ndarray:
    """Load vector of a uniform pressure ``p`` (Pa, > 0 pushes into the block: traction -p e_z on
    the top face) on the named boundary."""
    fb = FacetBasis(mesh, basis.elem, facets=mesh.boundaries[boundary], intorder=intorder)

    @LinearForm
    def form(v, w):
        return -p * v[2]

    return asm(form, fb)


def solve_dirichlet(K, f, fixed, backend=None):
    """Solve K u = f with u = 0 on ``fixed``; returns (u, factor)."""
    n = K.shape[0]
    mask = np.ones(n, dtype=bool)
    mask[fixed] = False
    free = np.flatnonzero(mask)
    Kff = K[free][:, free].tocsc()
    u = np.zeros(n)
    with blas_threads(1):
        fac = factorize(Kff, backend)
        u[free] = fac.solve(np.asarray(f, dtype=float)[free])
    return u, fac
