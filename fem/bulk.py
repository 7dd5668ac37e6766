"""Half-space-comparable displacements of the FE model: the finite bodies' bulk compliance
removed, normal and tangential (the one home of both corrections).

Normal indentation (:func:`normal_indentation`, called by ``fem.axisym.normal.solve_normal``).
Half-space theory (Hertz, MDR) measures the
approach between points far inside two semi-infinite bodies. The FE bodies
are finite, so their approach ``d`` also contains the compliance of the
bulk (block height, indenter cap, clamping). Following docs/design.md (section 4),
the FE axial displacements are read at two probe points on the axis at depth
z0 (default 20 a_ref) inside each body, where the field is still the
half-space field up to a rigid shift, and the half-space (Boussinesq)
displacement of those points is added back:

    d_hs = [u_z,block(0, -z0) - u_z,indenter(0, +z0)] + w_1(z0) + w_2(z0),
    w_j(z0) = sum_i lam_i (1 + nu_j) / (2 pi E_j rho_i) [2 (1 - nu_j) + z0^2 / rho_i^2],
    rho_i = sqrt(r_i^2 + z0^2),

i.e. the Boussinesq (1885) point-load solution summed over the FE pair forces
(Johnson, *Contact Mechanics*, CUP 1985, eq. 3.21). The relative approach of the
probes removes everything outside the slab |z| < z0; the Boussinesq term puts
back what two half-spaces would add below the probes. A rigid indenter has
w_1 = 0 and u_z,indenter = -d.

Tangential displacement (:class:`BulkProbe`, :func:`bulk_probe`, used by ``fem.axisym.law``;
:func:`contact_from_plate` / :func:`plate_from_contact` convert between the two measures).
The FE law's plate displacement u (indenter top plate relative to the clamped
block bottom, ``fem.axisym.law``) contains the tangential compliance of the finite
bodies, which a half-space law (Mindlin, MDR) does not have. As for the normal
indentation (above: probes plus Boussinesq), it is removed with probe
points and a half-space Green's function, never with the half-space contact
stiffness:

    u_contact = [u_x,indenter(0, +L) + sum_i T_i g_1(r_i, L)]
              - [u_x,block(0, -L)    - sum_i T_i g_2(r_i, L)]      = u - c . T,

with u_x the FE mode-1 x displacement on the axis at depth L in each body
(interpolated with the P2 shape functions of the axis edge that holds it),
T_i the pair forces along x (rings of radius r_i; the indenter carries -T) and
g_j the x displacement on the axis at depth L of a half-space under a unit
ring of x traction (Cerruti 1882, Atti Accad. Lincei, Mem. fis. mat.; Johnson,
*Contact Mechanics*, Cambridge UP 1985, eq. 2.19, averaged over the ring):

    g(r, L) = 1/(4 pi G) [1/rho + r^2/(2 rho^3) + (1 - 2 nu)(1/(rho + L) - r^2/(2 rho (rho + L)^2))],
    rho = sqrt(r^2 + L^2)      (r = 0: (3 - 2 nu)/(8 pi G L)).

The FE probe readings remove everything outside the slab |z| < L (clamp, block
size, cap height); the Cerruti terms put back what two half-spaces add beyond
the probes. c (m/N, one value per pair) is a property of the meshes and the
elastic constants only: it does not depend on F_N. Its spread over the pairs
in contact is below 3 % of its value (6e-11 m/N, 3e-4 of the contact
compliance 1/(2 G* a)), so it is used as the scalar

    c_bulk(F_N) = c . T_stick / sum(T_stick),

T_stick the FE's own full-stick pair forces at F_N (weights only). A scalar
keeps the condensed flexibility Ct - c_bulk 1 1^T symmetric (Cholesky).

Probe depth. The block reading is flat in L (c_block = 0.38-0.41e-9 m/N for
L = 1-20 a; it falls beyond 40 a, where the clamp 200 a below is felt). The
indenter's is not: c_indenter falls by 0.27e-9 m/N per unit of ln L (1.72,
1.43, 1.09, 0.91, 0.66e-9 m/N at L = 1, 3, 10, 20, 40 a; R = 6 mm, a = 27 um,
the same at a/20..a/160). This is the sphere cap, not the mesh: the drift is
the same with the far-field grading 0.1 instead of 0.25 (which moves c by
3e-11 m/N), and it is 12x smaller at R = 60 mm for the same a (it scales as
1/R): the cross-section of a paraboloid grows as 2 pi R z instead of the
half-space's 2 pi z^2, which adds a shear compliance ~ ln(L)/(2 pi G R) with no
finite limit. That compliance is no half-space's, and a deeper probe counts
more of it as contact: 0.13 % of 1/(2 G* a) per unit ln L, i.e. -0.4 % of the
Mindlin-Deresiewicz dissipation at u*/2 per unit ln L (d ln W / d ln u_A = 3.2
there). The probes therefore sit as shallow as the FE field allows, just below
the contact segment (r_contact = 1.25 a_ref): L = ``DEFAULT_PROBE_DEPTH`` =
1.5 a_ref in both bodies (a_ref: the mesh's reference contact radius at
F_max). Shallower probes read a less converged field; this one trades a mesh
spread of 1.5e-4 of the contact compliance for 0.09 % less cap compliance
than at 3 a_ref.

Measured (sphere R = 6 mm, steel, F_max = 0.6 N, L = 1.5 a_ref, F_N = 0.5 N):
c_bulk = 1.964, 1.994, 1.963, 1.984e-9 m/N at h = a/20, a/40, a/80, a/160
(spread 1.6 % of c_bulk, 1.5e-4 of the contact compliance ~2.0e-7 m/N). This
spread has no trend with h because the element size at the probe is set by
the far-field grading (h = h_min + growth * distance), not by h: with growth
0.1 (0.05) instead of the default 0.25, c_bulk = 1.9863 (1.9815), 1.9819
(1.9807), 1.9802 (1.9806)e-9 m/N at a/20, a/40, a/80, converging to
1.981e-9 m/N; the default grading's reading is within 1 % of it. Over
F_N = 0.1-0.6 N
c_bulk varies by 1.3-1.4 % (a/20, a/80) and 0.2-0.3 % (a/40, a/160). The
calibration this replaces (FE full-stick compliance minus 1/(2 G* a)) spread
by 77 % over the same meshes (1.17..2.07e-9 m/N) and changed sign with F_N at
a/20. The FE full-stick stiffness in this measure, 1/(1/k_FE - c_bulk), is
within -0.08..-0.03 % of Mindlin's 2 G* a at a/160 and -0.40..+0.24 % at a/80
(F_N = 0.1-0.6 N: the contact's own discretisation error, the full-stick
traction being singular at the edge). Displacement-controlled dissipation
against Mindlin-Deresiewicz (F_max = F_N = 0.5 N, 100 steps per cycle):
-0.33, -0.42, -0.43, -0.41 % at u_A = u*/2 and -0.17 % at 2 u* (a/20..a/160);
with L = 3 a_ref it would be -0.62 % at u*/2.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fem.axisym.mode0 import facet_nodes, node_coords

#: probe depth / a_ref of the tangential bulk correction (see module docstring)
DEFAULT_PROBE_DEPTH = 1.5


def boussinesq_axis(lam, r, z, E, nu):
    """Axial displacement (m, towards the body) at depth z on the axis of a half-space
    loaded by normal ring forces lam_i (N) at radii r_i (Boussinesq 1885)."""
    rho = np.sqrt(r**2 + z**2)
    return float(np.sum(lam * (1.0 + nu) / (2.0 * np.pi * E * rho) * (2.0 * (1.0 - nu) + z**2 / rho**2)))


def normal_indentation(model, lam, d) -> tuple[float, dict]:
    """Half-space-comparable indentation d_hs (m) of a normal solution of ``model``
    (``fem.axisym.model.TwoBodyModel``-like: probe rows ``P_blk``/``P_ind``, ``probe_depth``)
    with pair forces ``lam`` (N) and plate approach ``d`` (m): the probes' relative
    approach plus Boussinesq below them (module docstring). Returns ``(d_hs, probe)``,
    ``probe`` the readings (``z0``, ``u_indenter``, ``u_block``, ``w_halfspace_*``)."""
    iface = model.interface
    z0 = model.probe_depth
    m = model.materials
    u_blk = float(model.P_blk @ lam)
    if model.rigid_indenter:
        u_ind = -d
        w1 = 0.0
    else:
        u_ind = -d + float(model.P_ind @ lam)
        w1 = boussinesq_axis(lam, iface.r, z0, m.E1, m.nu1)
    w2 = boussinesq_axis(lam, iface.r, z0, m.E2, m.nu2)
    d_hs = u_blk - u_ind + w1 + w2
    probe = {"z0": z0, "u_indenter": u_ind, "u_block": u_blk, "w_halfspace_indenter": w1,
             "w_halfspace_block": w2}
    return d_hs, probe


def contact_from_plate(u, Fx, c_bulk):
    """Half-space-comparable (contact) displacement of a plate displacement ``u`` carrying the
    tangential force ``Fx``: ``u - c_bulk Fx`` (the bodies' series compliance removed)."""
    return u - c_bulk * Fx


def plate_from_contact(u, Fx, c_bulk):
    """Plate displacement of a contact displacement ``u`` carrying ``Fx``: ``u + c_bulk Fx``
    (the inverse of :func:`contact_from_plate`)."""
    return u + c_bulk * Fx


def cerruti_axis(r, L, G, nu):
    """x displacement (m/N) on the axis at depth L (m) of a half-space (shear modulus G, Poisson
    ratio nu) per unit x force spread uniformly over a surface ring of radius r (Cerruti 1882)."""
    r = np.asarray(r, dtype=float)
    rho = np.sqrt(r**2 + L**2)
    return (1.0 / rho + r**2 / (2.0 * rho**3)
            + (1.0 - 2.0 * nu) * (1.0 / (rho + L) - r**2 / (2.0 * rho * (rho + L) ** 2))) / (4.0 * np.pi * G)


def cerruti_point_x(x, y, L, G, nu):
    """x displacement (m/N) on the axis at depth L (m) of a half-space (shear modulus G, Poisson
    ratio nu) per unit x force at the surface point (x, y) (Cerruti 1882; Johnson, *Contact
    Mechanics*, Cambridge UP 1985, eq. 2.19). Its average over a ring of radius r is
    :func:`cerruti_axis`."""
    x = np.asarray(x, dtype=float)
    rho = np.sqrt(x**2 + np.asarray(y, dtype=float) ** 2 + L**2)
    return (1.0 / rho + x**2 / rho**3
            + (1.0 - 2.0 * nu) * (1.0 / (rho + L) - x**2 / (rho * (rho + L) ** 2))) / (4.0 * np.pi * G)


def boussinesq_point_z(x, y, L, G, nu):
    """Displacement into the body (m/N) on the axis at depth L (m) of a half-space per unit normal
    force (into the body) at the surface point (x, y) (Boussinesq 1885; Johnson 1985, eq. 3.21):
    (L^2 / rho^3 + 2 (1 - nu) / rho) / (4 pi G), rho the distance; summed over rings it is
    :func:`boussinesq_axis`."""
    rho = np.sqrt(np.asarray(x, dtype=float) ** 2 + np.asarray(y, dtype=float) ** 2 + L**2)
    return (L**2 / rho**3 + 2.0 * (1.0 - nu) / rho) / (4.0 * np.pi * G)


def axis_point(mesh, z):
    """P2 nodes (3,) of the axis edge holding (0, z) and their shape-function weights (3,)."""
    el = facet_nodes(mesh, mesh.boundaries["axis"])
    zz = node_coords(mesh)[1]
    z0, z1 = zz[el[0]], zz[el[1]]
    lo, hi = np.minimum(z0, z1), np.maximum(z0, z1)
    tol = 1e-9 * max(abs(z), 1e-30)
    k = np.flatnonzero((lo - tol <= z) & (z <= hi + tol))
    if k.size == 0:
        raise ValueError(f"no axis edge at z = {z:.6g} m")
    k = int(k[0])
    t = (z - z0[k]) / (z1[k] - z0[k])
    return el[:, k], np.array([(1 - t) * (1 - 2 * t), t * (2 * t - 1), 4 * t * (1 - t)])


@dataclass(frozen=True)
class BulkProbe:
    """The tangential bulk correction u_contact = u_plate - c . T (module docstring).

    ``depth`` L (m); ``c`` (n,) per pair (m/N); ``c_indenter``, ``c_block`` its two bodies' parts
    (FE probe reading minus Cerruti), so ``c = c_indenter + c_block``."""

    depth: float
    c_indenter: np.ndarray
    c_block: np.ndarray

    @property
    def c(self) -> np.ndarray:
        return self.c_indenter + self.c_block

    def scalar(self, Ct, active) -> float:
        """c_bulk (m/N): c weighted by the full-stick pair forces of flexibility ``Ct`` (plate
        measure) on the ``active`` pairs."""
        A = np.asarray(active, dtype=bool)
        if not np.any(A):
            return float(np.mean(self.c))
        T = np.linalg.solve(Ct[np.ix_(A, A)], np.ones(int(A.sum())))
        return float(self.c[A] @ T / T.sum())


def bulk_probe(interface, materials, rows, depth) -> BulkProbe:
    """BulkProbe from the mode-1 probe rows: ``rows[body]`` (m,) is the x displacement of that
    body's axis point at depth ``depth`` per unit x force on each of its interface DOFs."""
    m = materials
    g1 = cerruti_axis(interface.r, depth, m.E1 / (2 * (1 + m.nu1)), m.nu1)
    g2 = cerruti_axis(interface.r, depth, m.E2 / (2 * (1 + m.nu2)), m.nu2)
    return BulkProbe(float(depth), np.asarray(rows["indenter"]) - g1, interface.N @ np.asarray(rows["block"]) - g2)
