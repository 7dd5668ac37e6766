"""Fourier mode 1 (tangential loading): zero-energy rigid modes and the bonded-disk stiffness."""
import numpy as np
import pytest
from scipy.sparse.linalg import spsolve

from fem.axisym.mode0 import boundary_nodes, node_coords, stiffness
from fem.axisym.mode1 import node_dofs_mode1, rigid_fields, stiffness_mode1
from fem.axisym.normal_run import mesh_params
from mdr.materials import Materials
from meshes import cached_mesh

MAT = Materials()


@pytest.fixture(scope="module")
def block(tmp_path_factory):
    p = mesh_params("sphere", 6e-3, 0.0, 0.5, MAT, h_contact=1 / 40)
    am = cached_mesh(p, tmp_path_factory.mktemp("m1"))
    K, basis = stiffness_mode1(am.block, MAT.E2, MAT.nu2)
    return am, K, basis


def test_rigid_translation_and_tilt_store_no_energy(block):
    am, K, basis = block
    dofs = node_dofs_mode1(basis)
    rng = np.random.default_rng(0)
    u_rand = rng.standard_normal(K.shape[0]) * 1e-6
    e_scale = u_rand @ (K @ u_rand)
    for name, f in rigid_fields(am.block).items():
        u = np.zeros(K.shape[0])
        u[dofs] = f * 1e-6
        assert abs(u @ (K @ u)) < 1e-12 * e_scale, name
        # and the rigid mode is in the null space (zero forces), not just orthogonal
        assert np.max(np.abs(K @ u)) < 1e-9 * np.max(np.abs(K @ u_rand))


def test_bonded_rigid_disk_has_the_half_space_tangential_stiffness(block):
    """A rigid disk of radius a bonded to the block and translated along x (normal traction
    free, Mindlin's approximation): F_x / u = 8 G a / (2 - nu) (Johnson 1985, eq. 7.39), up to
    the finite-body effect of a 200 a block and the discretised edge singularity (< 1 %)."""
    am, K, basis = block
    blk = am.block
    dofs = node_dofs_mode1(basis)
    xy = node_coords(blk)
    cn = boundary_nodes(blk, "contact")
    a = am.params.a_ref
    disk = cn[xy[0, cn] <= a * (1 + 1e-9)]
    ax, bot = boundary_nodes(blk, "axis"), boundary_nodes(blk, "bottom")
    fixed = np.unique(np.concatenate([dofs[1, ax], dofs[2, ax], dofs[:, bot].ravel(),
                                      dofs[0, disk], dofs[1, disk]]))
    u = np.zeros(K.shape[0])
    u[dofs[0, disk]] = 1.0  # S = 1, D = 0: u_x = 1 on the disk
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    u[free] = spsolve(K[free][:, free].tocsc(), -(K[free][:, fixed] @ u[fixed]))
    Fx = (K @ u)[dofs[0, disk]].sum()
    G = MAT.E2 / (2 * (1 + MAT.nu2))
    ref = 8 * G * xy[0, disk].max() / (2 - MAT.nu2)
    assert abs(Fx / ref - 1) < 0.01


def test_unknown_mode_is_not_implemented(block):
    am = block[0]
    for mode in (1, 2):  # fem.axisym.mode0 has mode 0 only; mode 1 is fem.axisym.mode1.stiffness_mode1
        with pytest.raises(NotImplementedError):
            stiffness(am.block, MAT.E2, MAT.nu2, mode=mode)


def test_fretting_fields_cerruti_far_field_and_rigid_plate():
    """Field recovery of the FE law's tangential state (fem.axisym.output.fretting_fields).

    - A tangential force Q on the block's surface: its surface displacement along x
      falls off as Cerruti's u_x(rho) = Q (1 + nu) / (pi E rho) at theta = 0 (Cerruti 1882;
      Johnson, Contact Mechanics, 1985, eq. 2.19). The finite block adds a nearly uniform
      shear offset (its bulk compliance), so the decay between 3a and 10a is compared.
    - A plate displacement alone (no pair forces) is a rigid translation: no mode-1 stress.
    """
    from fem.axisym.mode0 import node_coords
    from fem.axisym.law import FEContact
    from fem.axisym.output import fretting_fields
    from mdr import Materials
    from mdr.profiles import Sphere

    m = Materials()
    law = FEContact(Sphere(6e-3), m, 0.2, F_max=0.5, h_contact=1 / 20)
    res, st = law.step(law.rest_state(), F_N=0.5, Fx=0.05)
    f = fretting_fields(law, st, 0.5)
    r, z = node_coords(law.model.bodies["block"].mesh)
    top = np.isclose(z, z.max())
    ux = f["u_x0"]["block"][:, 0] - f["u"]["block"][:, 0]
    a, Q = res.a, res.Fx

    def at(rho):
        i = np.flatnonzero(top)[np.argmin(np.abs(r[top] - rho))]
        return ux[i], Q * (1 + m.nu2) / (np.pi * m.E2 * r[i])

    (u3, c3), (u10, c10) = at(3 * a), at(10 * a)
    assert (u3 - u10) / (c3 - c10) == pytest.approx(1.0, abs=0.03)
    # theta = 0 and theta = pi halves average to the mode-0 field
    for body in ("indenter", "block"):
        mean = 0.5 * (f["u_x0"][body] + f["u_x180"][body])
        assert np.allclose(mean, f["u"][body], atol=1e-15)
    # rigid plate displacement without pair forces: no mode-1 stress anywhere
    st0 = type(st)(T=np.zeros_like(st.T), slip=st.slip, lam=st.lam, sgn=st.sgn, u=1e-8, d=st.d)
    f0 = fretting_fields(law, st0, 0.5)
    assert np.allclose(f0["u_x0"]["indenter"][:, 0] - f0["u"]["indenter"][:, 0], 1e-8, rtol=1e-12)
    assert np.allclose(f0["mises_x0"]["indenter"], f0["mises_x180"]["indenter"], rtol=1e-9, atol=1.0)
