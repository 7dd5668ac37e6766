"""Condensation of the 3D half-model to the contact interface (issue 13, second increment).

One graded mesh: contact half disk of radius c = 1.25 with h = 0.25 (m = 227 P2 contact
nodes), block radius and height 20 c, about 14k DOFs; each condensation ~2.5 s on 2 cores.
Closed forms: Boussinesq and Cerruti point-load surface displacements of the half-space
(Johnson 1985, Contact Mechanics, ch. 3: concentrated normal and tangential forces).
"""
import numpy as np
import pytest

from fem.solid3d.elastic import dirichlet_dofs, node_dofs3d, pressure_load, solve_dirichlet, stiffness3d
from fem.solid3d.interface import contact_flexibility, contact_nodes
from meshes.half3d import Half3DMeshParams, build_mesh3d

E, NU, P = 200e9, 0.3, 1e8
C = 1.25  # contact disk radius (a_ref = 1, contact_extent = 1.25)
L = 20 * C


@pytest.fixture(scope="module")
def model():
    m = build_mesh3d(Half3DMeshParams(a_ref=1.0, h_contact=0.25, contact_extent=C, size=L, height=L)).mesh
    K, b = stiffness3d(m, E, NU)
    return m, K, b, contact_nodes(m)


@pytest.fixture(scope="module")
def normal(model):
    m, K, b, cn = model
    # probe rows at the interface DOFs themselves: the raw (unsymmetrised) solves
    return contact_flexibility(K, b, m, cn, component=2, probe_dofs=node_dofs3d(b)[2, cn.nodes])


def test_contact_node_weights(model):
    m, _, _, cn = model
    assert 150 < cn.m < 400
    assert np.unique(cn.nodes).size == cn.m
    assert np.all(cn.r <= C + 1e-9) and np.all(cn.y >= -1e-12)
    # all weights >= 0; P2 triangles: vertex weights vanish, midpoints carry 1/3 of each triangle
    assert np.all(cn.w >= -1e-15)
    assert np.max(np.abs(cn.w[cn.is_vertex])) < 1e-14 * cn.w.max()
    assert np.all(cn.w[~cn.is_vertex] > 0)
    # the sum is exactly the area of the facets (the inscribed polygonal half disk) ...
    fa = m.boundaries["contact"]
    X = m.p[:, m.facets[:, fa]]
    area = 0.5 * np.linalg.norm(np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0], axis=0), axis=0).sum()
    assert abs(cn.w.sum() / area - 1) < 1e-12  # measured 2e-15
    # ... which is inside the exact half disk pi c^2 / 2 by the polygon approximation of the arc:
    # measured -0.64 % at h = c/5
    half_disk = np.pi * C**2 / 2
    assert -0.01 < cn.w.sum() / half_disk - 1 < 0


def test_normal_flexibility_matches_sparse_solve(model, normal):
    """Forces -p w_i on the contact z-DOFs through C reproduce the sparse solve of the uniform
    pressure load (the consistent load of a uniform pressure is exactly -p w_i on the z-DOFs):
    measured 2e-16 relative at the centre, 2e-15 over all contact nodes."""
    m, K, b, cn = model
    f = pressure_load(m, b, P)
    zd = node_dofs3d(b)[2, cn.nodes]
    assert np.max(np.abs(f[zd] + P * cn.w)) < 1e-12 * np.max(np.abs(f))
    u, _ = solve_dirichlet(K, f, dirichlet_dofs(b, m))
    uz = normal.C @ (-P * cn.w)
    i0 = np.argmin(cn.r)
    assert cn.r[i0] < 1e-12
    assert abs(uz[i0] / u[zd[i0]] - 1) < 1e-10
    assert np.max(np.abs(uz - u[zd])) < 1e-10 * np.max(np.abs(uz))
    # the finite clamped block (20 c) on this coarse mesh vs the half-space mean over the disk,
    # 16 (1 - nu^2) p c / (3 pi E): measured -4.46 % (-3.9 % at h = c/12.5, tests/test_fem3d.py)
    w_mean = -(cn.w @ uz) / cn.w.sum()
    assert -0.055 < w_mean / (16 * (1 - NU**2) * P * C / (3 * np.pi * E)) - 1 < -0.03


def test_normal_flexibility_spd(normal):
    Cm, raw = normal.C, normal.P
    # Condensation stores (C + C^T) / 2; the raw m solves are symmetric to round-off
    assert np.max(np.abs(raw - raw.T)) <= 1e-12 * np.max(np.abs(raw))
    assert np.max(np.abs(raw - Cm)) <= 1e-12 * np.max(np.abs(raw))
    np.linalg.cholesky(Cm)  # raises if not positive definite
    assert np.all(np.diag(Cm) > 0)


def test_tangential_flexibility_cerruti(model):
    """Uniform shear q (x direction) on the contact half disk, x-DOF flexibility. Half-space mean
    u_x over the disk: the Cerruti surface displacement of a point force Q_x (Johnson 1985,
    ch. 3, concentrated tangential force), u_x = (1 + nu) Q / (2 pi E rho) [2 (1 - nu) + 2 nu x^2 / rho^2], averaged over the disk
    pairs (isotropic, so <x^2/rho^3> = <1/rho> / 2, and <1/rho> * area = 16 c / 3 from the
    Boussinesq mean 16 (1 - nu^2) p c / (3 pi E)): u_mean = 8 (1 + nu) (2 - nu) q c / (3 pi E)
    = 4 (2 - nu) q c / (3 pi G). Consistent with Johnson ch. 3's q0 (1 - r^2/a^2)^(-1/2) traction results (shear/normal ratio
    (2 - nu) / (2 (1 - nu)) for the same traction).
    Measured: +3.19 % for the 20 c block; +7.2 % at 10 c, +1.2 % at 40 c: the finite block with
    free sides is more compliant in shear and the difference vanishes as the block grows (the
    u_y = 0 symmetry condition is exact for x shear: u_x even, u_y odd in y)."""
    m, K, b, cn = model
    cx = contact_flexibility(K, b, m, cn, component=0)
    np.linalg.cholesky(cx.C)
    ux = cx.C @ (P * cn.w)
    u_mean = cn.w @ ux / cn.w.sum()
    ref = 8 * (1 + NU) * (2 - NU) * P * C / (3 * np.pi * E)
    assert 0.015 < u_mean / ref - 1 < 0.05
    assert np.all(ux > 0)
