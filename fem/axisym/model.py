"""The two-body axisymmetric model set up once per mesh, materials and profile.

Boundary conditions (mode 0):

- both bodies: u_r = 0 on the axis (regularity);
- block: bottom clamped (u_r = u_z = 0);
- indenter: the top face moves as a rigid, frictionless plate: u_z = -d
  (d, the *approach* of the indenter top to the block bottom, is an
  unknown when the force is prescribed), u_r free. Because the elastic field
  of the prescribed translation alone is a rigid translation (no stress), the
  indenter's interface displacement is -d + C1 lam: the condensation
  with the top clamped covers everything else. The normal force F is the
  reaction of the plate (= the sum of the pair forces).

``rigid_indenter=True`` skips the indenter's elasticity (C1 = 0): a rigid
indenter pressed into the block, for checks against the equivalent-modulus
single-body problem.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from mdr.materials import Materials

from fem.axisym.mode0 import boundary_nodes, node_coords, node_dofs, stiffness
from fem.condense import Condensation
from fem.axisym.interface import ContactInterface, build_interface


@dataclass
class Body:
    """One elastic body: mesh, material, basis, stiffness, DOF maps and condensation."""

    name: str
    mesh: object
    E: float
    nu: float
    basis: object
    K: object
    dofs: np.ndarray          # (2, n_nodes) u_r, u_z DOF numbers per P2 node
    fixed: np.ndarray
    probe_node: int
    cond: Condensation | None = None

    @property
    def ndofs(self) -> int:
        return self.basis.N


def _probe_node(mesh, z):
    xy = node_coords(mesh)
    k = int(np.argmin(np.hypot(xy[0], xy[1] - z)))
    if abs(xy[0, k]) > 1e-12 or abs(xy[1, k] - z) > 1e-9 * max(abs(z), 1e-30):
        raise ValueError(f"no mesh node on the axis at z = {z:.6g} m")
    return k


def _make_body(name, mesh, E, nu, probe_z):
    K, basis = stiffness(mesh, E, nu, mode=0)
    dofs = node_dofs(basis)
    fixed = [dofs[0, boundary_nodes(mesh, "axis")]]
    if name == "indenter":
        fixed.append(dofs[1, boundary_nodes(mesh, "top")])
    else:
        bn = boundary_nodes(mesh, "bottom")
        fixed += [dofs[0, bn], dofs[1, bn]]
    return Body(name, mesh, E, nu, basis, K, dofs, np.unique(np.concatenate(fixed)),
                _probe_node(mesh, probe_z))


@dataclass
class AxisymContactModel:
    """Everything the contact solvers need, built once (see :func:`build_model`).

    ``C`` is the pair flexibility (n x n, m/N): the gap of the pairs is
    ``gap0 - d + C @ lam`` for pair forces ``lam`` (N, compressive > 0).
    ``P_ind``, ``P_blk`` (n,) give the axial displacement of the two probe
    points per unit pair force (the indenter probe also moves by -d).
    """

    amesh: object
    materials: Materials
    profile: object
    interface: ContactInterface
    bodies: dict
    C: np.ndarray
    P_ind: np.ndarray
    P_blk: np.ndarray
    rigid_indenter: bool = False
    timings: dict = field(default_factory=dict)
    backend: str = ""
    #: the normal solver's factors of C + diag(1/k) on active sets, per penalty (``fem.axisym.normal``)
    normal_factors: dict = field(default_factory=dict, repr=False, compare=False)

    @property
    def dofs(self) -> int:
        return int(sum(b.ndofs for b in self.bodies.values()))

    @property
    def probe_depth(self) -> float:
        return float(self.amesh.params.probe_depth)

    def fields(self, lam, d):
        """Full displacement vectors {body: u} for pair forces ``lam`` and approach ``d``."""
        iface = self.interface
        out = {}
        ind = self.bodies["indenter"]
        if ind.cond is not None:
            rigid = np.zeros(ind.ndofs)
            rigid[ind.dofs[1]] = -d
            out["indenter"] = ind.cond.displacement(lam, u_fixed=rigid)
        blk = self.bodies["block"]
        out["block"] = blk.cond.displacement(-(iface.N.T @ lam))
        return out


def build_model(amesh, materials: Materials | None = None, profile=None, *, backend=None,
                rigid_indenter: bool = False) -> AxisymContactModel:
    """Assemble, factorise and condense both bodies for normal (mode-0) contact."""
    from mdr.profiles import make_profile

    materials = materials or Materials()
    p = amesh.params
    if profile is None:
        profile = make_profile(p.profile, p.R, p.b)
    t0 = time.perf_counter()
    interface = build_interface(amesh, profile)
    z0 = p.probe_depth
    bodies = {"indenter": _make_body("indenter", amesh.indenter, materials.E1, materials.nu1, z0),
              "block": _make_body("block", amesh.block, materials.E2, materials.nu2, -z0)}
    t_asm = time.perf_counter() - t0
    blk = bodies["block"]
    blk.cond = Condensation(blk.K, blk.fixed, blk.dofs[1, interface.blk_nodes],
                            probe_dofs=[blk.dofs[1, blk.probe_node]], backend=backend)
    N = interface.N
    C = N @ (N @ blk.cond.C).T          # N C2 N^T (C2 symmetric)
    P_blk = -(N @ blk.cond.P[0])        # block probe per unit pair force (force -N^T lam)
    P_ind = np.zeros(interface.n)
    if not rigid_indenter:
        ind = bodies["indenter"]
        ind.cond = Condensation(ind.K, ind.fixed, ind.dofs[1, interface.ind_nodes],
                                probe_dofs=[ind.dofs[1, ind.probe_node]], backend=backend)
        C = C + ind.cond.C
        P_ind = ind.cond.P[0].copy()
    C = 0.5 * (C + C.T)
    t_tot = time.perf_counter() - t0
    return AxisymContactModel(amesh=amesh, materials=materials, profile=profile, interface=interface,
                              bodies=bodies, C=C, P_ind=P_ind, P_blk=P_blk,
                              rigid_indenter=rigid_indenter, backend=blk.cond.backend,
                              timings={"assembly": t_asm, "factor_condense": t_tot - t_asm, "setup": t_tot})
