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
its boundary conditions (``fem.solid3d.elastic.dirichlet_dofs``: bottom clamped, u_y = 0
on the symmetry plane) at one displacement component of the contact nodes.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from skfem import Basis, ElementTetP2, FacetBasis, LinearForm, asm

from fem.condense import Condensation
from fem.solid3d.elastic import boundary_nodes3d, dirichlet_dofs, node_coords3d, node_dofs3d


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


def _scalar_p2_dofs(mesh) -> np.ndarray:
    """DOF number of P2 node k (vertices, then edge midpoints) in a scalar P2 basis of the mesh."""
    sb = Basis(mesh, ElementTetP2(), intorder=2)
    return np.concatenate([sb.nodal_dofs[0], sb.edge_dofs[0]])


def contact_nodes(mesh, boundary: str = "contact", intorder: int = 4) -> ContactNodes:
    """Contact nodes, coordinates and tributary area weights (integral of the P2 basis function
    over the contact facets = row sums of the P2 surface mass matrix, assembled as the linear
    form of the constant 1 on a scalar P2 ``FacetBasis``)."""
    nodes = boundary_nodes3d(mesh, boundary)
    fb = FacetBasis(mesh, ElementTetP2(), facets=mesh.boundaries[boundary], intorder=intorder)

    @LinearForm
    def one(v, w):
        return v

    wall = asm(one, fb)
    sdofs = _scalar_p2_dofs(mesh)
    X = node_coords3d(mesh)[:, nodes]
    return ContactNodes(nodes=nodes, x=X[0], y=X[1], r=np.hypot(X[0], X[1]), w=wall[sdofs[nodes]],
                        is_vertex=nodes < mesh.p.shape[1])


def contact_flexibility(K, basis, mesh, cn: ContactNodes, component: int = 2, probe_dofs=(),
                        backend=None) -> Condensation:
    """Flexibility (m x m, m/N) of the half model at one displacement component (0: x, 1: y,
    2: z) of the contact nodes, with the block's boundary conditions."""
    dofs = node_dofs3d(basis)[component, cn.nodes]
    return Condensation(K, dirichlet_dofs(basis, mesh), dofs, probe_dofs=probe_dofs, backend=backend)


# --------------------------------------------------------------------- mortar interface
#
# Contact tractions as a P1 field on the contact facets (values at the mesh vertices),
# displacements P2: the pairing of the two is the mortar matrix
#
#     B_jk = integral over the contact facets of phi_j psi_k dA
#
# (phi_j the P1 hat function of vertex j, psi_k the P2 basis function of node k). A traction
# field t = sum_j t_j phi_j gives the consistent P2 nodal forces f = B^T t; the weighted
# displacement of vertex j is (B u)_j, and row sums A_j = sum_k B_jk = integral phi_j dA
# (the partition of unity of the P2 basis) are the vertex areas. This is the standard
# P2-displacement / P1-multiplier pairing (Wohlmuth, Acta Numerica 20 (2011) 569; the
# contact constraints are imposed on the weighted gap (B g)_j), and it removes the zero
# vertex weights of P2 triangles: every multiplier has A_j > 0.


@dataclass(frozen=True)
class MortarInterface:
    """P1 multiplier vertices of the contact facets and the mortar matrix.

    ``vertices`` mesh vertex numbers (n); ``x``, ``y``, ``r`` (m); ``A`` vertex areas
    (integral of phi_j, m^2); ``on_plane`` vertices on the symmetry plane y = 0 (their q_y
    vanishes by symmetry); ``B`` (n, m) CSR mortar matrix against the P2 nodes ``nodes``.
    """

    vertices: np.ndarray
    x: np.ndarray
    y: np.ndarray
    r: np.ndarray
    A: np.ndarray
    on_plane: np.ndarray
    B: object
    nodes: ContactNodes

    @property
    def n(self) -> int:
        return self.vertices.size


def mortar_interface(mesh, boundary: str = "contact", intorder: int = 4) -> MortarInterface:
    """Mortar matrix of the contact facets (P1 multipliers against P2 displacements)."""
    from skfem import BilinearForm, ElementTetP1

    cn = contact_nodes(mesh, boundary, intorder)
    F = mesh.boundaries[boundary]
    fb2 = FacetBasis(mesh, ElementTetP2(), facets=F, intorder=intorder)
    fb1 = FacetBasis(mesh, ElementTetP1(), facets=F, intorder=intorder)

    @BilinearForm
    def mass(u, v, w):
        return u * v

    Bfull = asm(mass, fb2, fb1).tocsr()  # rows: P1 DOFs (vertices), columns: P2 DOFs
    sdofs = _scalar_p2_dofs(mesh)
    verts = np.unique(mesh.facets[:, F])
    B = Bfull[verts][:, sdofs[cn.nodes]].tocsr()
    B.eliminate_zeros()
    X = mesh.p[:, verts]
    tol = 1e-9 * float(np.max(np.abs(X)))
    return MortarInterface(vertices=verts, x=X[0], y=X[1], r=np.hypot(X[0], X[1]),
                           A=np.asarray(B.sum(axis=1)).ravel(), on_plane=np.abs(X[1]) <= tol, B=B, nodes=cn)


def mortar_flexibility(K, basis, mesh, mi: MortarInterface, components=(0, 1, 2), backend=None,
                       chunk: int = 512, timings: dict | None = None):
    """Weighted flexibility of the block at the multiplier vertices, (3 n, 3 n) (m^3/N... per Pa).

    Entry ((c1, j1), (c2, j2)) is the weighted displacement (B u_c1)_j1 (m^3) of vertex j1 in
    component c1 for a unit traction (1 Pa, P1 field phi_j2) in component c2 on the contact
    facets; rows and columns ordered component-major (x block, y block, z block). Components
    not in ``components`` are left zero. Forces at DOFs fixed by the boundary conditions (u_y on
    the symmetry plane) are reactions and move nothing. Solves in chunks of ``chunk``
    right-hand sides and keeps only the contact rows, so memory is O(free DOFs * chunk).
    Returns ``(D, backend_name, factor)``; ``timings`` (a dict), if given, gains the seconds of
    the ``factorisation`` and of the ``condensation`` (the solves and the weighting), added to
    what it holds.
    """

    from fem.solvers import blas_threads, factorize

    n_dof = K.shape[0]
    fixed = np.zeros(n_dof, dtype=bool)
    fixed[dirichlet_dofs(basis, mesh)] = True
    free = np.flatnonzero(~fixed)
    loc = -np.ones(n_dof, dtype=np.int64)
    loc[free] = np.arange(free.size)
    nd = node_dofs3d(basis)
    n, m = mi.n, mi.nodes.m
    # R[c] (free, n): the P2 nodal forces of traction phi_j in component c
    BT = mi.B.T.tocsr()  # (m, n)
    rows_c = [loc[nd[c, mi.nodes.nodes]] for c in range(3)]  # free position of each node's DOF
    D = np.zeros((3 * n, 3 * n))
    Kff = K[free][:, free].tocsc()
    t0 = time.perf_counter()
    with blas_threads(1):
        fac = factorize(Kff, backend)
        t1 = time.perf_counter()
        cols = [(c, j) for c in components for j in range(n)]
        for s in range(0, len(cols), chunk):
            part = cols[s:s + chunk]
            R = np.zeros((free.size, len(part)))
            for q, (c, j) in enumerate(part):
                ok = rows_c[c] >= 0
                col = BT[:, [j]].toarray().ravel()
                R[rows_c[c][ok], q] += col[ok]
            X = fac.solve(R)
            for c1 in range(3):
                U = np.zeros((m, len(part)))
                ok = rows_c[c1] >= 0
                U[ok] = X[rows_c[c1][ok]]
                W = mi.B @ U  # (n, chunk) weighted displacements
                for q, (c2, j2) in enumerate(part):
                    D[c1 * n:(c1 + 1) * n, c2 * n + j2] = W[:, q]
    D = 0.5 * (D + D.T)
    if timings is not None:
        timings["factorisation"] = timings.get("factorisation", 0.0) + (t1 - t0)
        timings["condensation"] = timings.get("condensation", 0.0) + (time.perf_counter() - t1)
    return D, fac.backend, fac


def probe_response(fac, basis, mesh, mi: MortarInterface, point) -> np.ndarray:
    """Weighted displacements of the contact vertices for unit point forces at ``point`` (3,) (m).

    Returns R (3, 3, n): R[d, c, j] = (B u_c)_j (m^3/N) for a unit force in direction d at the
    point, i.e. by reciprocity the displacement of the point in direction d (m/Pa) for a unit
    traction field phi_j in component c on the contact facets. The point force is spread to
    the P2 nodes of the tetrahedron holding the point by their shape functions (the transpose
    of P2 interpolation, so both readings agree exactly); ``fac`` factorises the stiffness on
    the DOFs free of the block's boundary conditions (``mortar_flexibility``'s third result).
    """
    n_dof = basis.N
    fixed = np.zeros(n_dof, dtype=bool)
    fixed[dirichlet_dofs(basis, mesh)] = True
    free = np.flatnonzero(~fixed)
    sb = Basis(mesh, ElementTetP2(), intorder=2)
    P = sb.probes(np.asarray(point, dtype=float).reshape(3, 1)).tocoo()
    nd = node_dofs3d(basis)
    sdofs = _scalar_p2_dofs(mesh)
    node_of = np.empty(sdofs.size, dtype=np.int64)
    node_of[sdofs] = np.arange(sdofs.size)
    F = np.zeros((n_dof, 3))
    for d in range(3):
        np.add.at(F[:, d], nd[d, node_of[P.col]], P.data)
    U = np.zeros((n_dof, 3))
    U[free] = fac.solve(F[free])
    R = np.empty((3, 3, mi.n))
    for c in range(3):
        R[:, c, :] = (mi.B @ U[nd[c, mi.nodes.nodes]]).T
    return R


def hat_integrals(mesh, mi: MortarInterface, func, boundary: str = "contact", intorder: int = 6) -> np.ndarray:
    """Integrals over the contact facets of phi_j func(x, y) for every multiplier vertex j (n,):
    ``func`` maps arrays x, y (m) to values."""
    from skfem import ElementTetP1

    fb = FacetBasis(mesh, ElementTetP1(), facets=mesh.boundaries[boundary], intorder=intorder)

    @LinearForm
    def form(v, w):
        return func(w.x[0], w.x[1]) * v

    return asm(form, fb)[mi.vertices]
