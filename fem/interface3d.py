"""Condensation of the 3D half-model to its contact interface (issue 13, second increment).

The contact unknowns live at the P2 nodes (vertices and edge midpoints) of the
``contact`` facets (the half disk r <= contact_extent * a_ref on z = 0, y >= 0).
Each node carries a tributary area w_i = integral of its P2 basis function over
the contact half disk, so a pressure field p_i acts as the nodal forces
f_i = -p_i w_i (exact, the consistent load, for a uniform pressure).

Note: for P2 triangles the integral of a vertex basis function is zero and that
of an edge-midpoint function is 1/3 of the triangle area (Zienkiewicz & Taylor,
*The Finite Element Method*, vol. 1, 6th ed., 2005, ch. 8, the "row-sum lumping"
of quadratic triangles). Vertex weights are therefore 0 (to round-off): a
nodal-force contact solver built on these weights transmits force only through
midpoint nodes, which is expected, not a bug.

The flexibilities are ``fem.condense.Condensation`` of the block's stiffness with
its boundary conditions (``fem.elastic3d.dirichlet_dofs``: bottom clamped, u_y = 0
on the symmetry plane) at one displacement component of the contact nodes.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from skfem import Basis, ElementTetP2, FacetBasis, LinearForm, asm

from .condense import Condensation
from .elastic3d import boundary_nodes3d, dirichlet_dofs, node_coords3d, node_dofs3d


@dataclass(frozen=True)
class ContactNodes:
    """P2 nodes of the contact facets: ``nodes`` (node numbers as in ``node_coords3d``),
    ``x``, ``y``, ``r`` (m), ``w`` tributary areas (m^2), ``is_vertex``."""

    nodes: np.ndarray
    x: np.ndarray
    y: np.ndarray
    r: np.ndarray
    w: np.ndarray
    is_vertex: np.ndarray

    @property
    def m(self) -> int:
        return self.nodes.size


def contact_nodes(mesh, boundary: str = "contact", intorder: int = 4) -> ContactNodes:
    """Contact nodes, coordinates and tributary area weights (integral of the P2 basis function
    over the contact facets = row sums of the P2 surface mass matrix, assembled as the linear
    form of the constant 1 on a scalar P2 ``FacetBasis``)."""
    nodes = boundary_nodes3d(mesh, boundary)
    sb = Basis(mesh, ElementTetP2(), intorder=2)
    fb = FacetBasis(mesh, sb.elem, facets=mesh.boundaries[boundary], intorder=intorder)

    @LinearForm
    def one(v, w):
        return v

    wall = asm(one, fb)
    sdofs = np.concatenate([sb.nodal_dofs[0], sb.edge_dofs[0]])  # scalar DOF of node k
    X = node_coords3d(mesh)[:, nodes]
    return ContactNodes(nodes=nodes, x=X[0], y=X[1], r=np.hypot(X[0], X[1]), w=wall[sdofs[nodes]],
                        is_vertex=nodes < mesh.p.shape[1])


def contact_flexibility(K, basis, mesh, cn: ContactNodes, component: int = 2, probe_dofs=(),
                        backend=None) -> Condensation:
    """Flexibility (m x m, m/N) of the half model at one displacement component (0: x, 1: y,
    2: z) of the contact nodes, with the block's boundary conditions."""
    dofs = node_dofs3d(basis)[component, cn.nodes]
    return Condensation(K, dirichlet_dofs(basis, mesh), dofs, probe_dofs=probe_dofs, backend=backend)
