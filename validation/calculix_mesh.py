"""The bodies of the CalculiX witness (``validation.calculix``) and their quadratic mesh.

``Geometry`` is the scene: sphere radius, force, materials, and the block and cap sizes in units of
the Hertz contact radius a_ref, resolved into the project's own mesh parameters
(``fem.axisym.normal_run.mesh_params``), so both codes model the same finite bodies and probe depth.
``build_quad_mesh`` meshes them anew with gmsh as CAX8 quadrilaterals (the few triangles the
recombination leaves as CAX6).

Assumptions: the sphere profile only; the indenter a cap of the sphere centred at (0, R) touching
the block at the origin, the block a cylinder below z = 0; the geometry and size field those of
``meshes.axisym`` (uniform size h_min on the contact curves r <= r_contact, growing as
h_min + growth * distance up to h_max), with the same number of uniform elements on both contact
curves; midside nodes on the exact geometry, nodes on the axis at r = 0 exactly; elements
counter-clockwise, as CalculiX expects. gmsh's state is global: one mesher at a time
(``meshes.axisym.GMSH_LOCK``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from common.errors import InputError
from fem.axisym.normal_run import mesh_params, reference_radius
from mdr.materials import Materials
from mdr.paper import R_INDENTER
from meshes.axisym import GMSH_LOCK, contact_size_field  # gmsh's state is global: one mesher at a time

#: default contact element size / a_ref (as ``fem normal``)
H_DEFAULT = 1.0 / 80.0


# --------------------------------------------------------------------------- geometry


@dataclass(frozen=True)
class Geometry:
    """Scene of the witness: sphere radius ``R`` (m), force ``F`` (N), materials, and the block and cap
    sizes in units of the Hertz contact radius (the project's ``block_size`` and ``indenter_height``
    divided by a_ref)."""

    block: float = 200.0
    cap: float = 200.0
    R: float = R_INDENTER
    F: float = 0.5
    materials: Materials = Materials()
    growth: float | None = None  # far-field grading of both meshes (None: the project's default)

    @property
    def a_ref(self) -> float:
        return reference_radius("sphere", self.R, 0.0, self.F, self.materials.E_star)  # the FE mesh's a_ref

    def run_kwargs(self) -> dict:
        """Keywords of ``fem.axisym.normal_run.run_normal`` for these bodies."""
        a = self.a_ref
        kw = {"block_size": self.block * a, "indenter_height": self.cap * a}
        if self.growth is not None:
            kw["growth"] = self.growth
        return kw

    def params(self, h: float):
        """The project's resolved mesh parameters (bodies, probe depth, grading) at contact size h * a_ref."""
        return mesh_params("sphere", self.R, 0.0, self.F, self.materials, h_contact=h,
                           **self.run_kwargs()).resolved()

    @property
    def name(self) -> str:
        return f"block {self.block:g} a, cap {self.cap:g} a"

# --------------------------------------------------------------------------- mesh


@dataclass
class QuadMesh:
    """Both bodies' CAX8/CAX6 elements: ``nodes`` {tag: (r, z)} (m), ``elements`` {body: [(element id,
    nodes per element 8 or 6, node tags counter-clockwise)]}, and the node / face sets the deck needs."""

    nodes: dict
    elements: dict
    contact_faces: dict      # body -> [(element id, face number)] along the contact curve
    sets: dict               # name -> sorted node tags
    probe: dict              # body -> node tag at (0, +-z0)
    load_node: int
    h: float
    n_quads: int = 0
    n_tris: int = 0


_FACES = {8: ((0, 1), (1, 2), (2, 3), (3, 0)), 6: ((0, 1), (1, 2), (2, 0))}


def build_quad_mesh(p) -> QuadMesh:
    """gmsh quadratic quadrilateral mesh of the resolved ``AxisymMeshParams`` ``p`` (sphere only).

    The geometry and size field follow ``meshes.axisym`` (uniform size h_min on the contact curves
    r <= r_contact, growing as h_min + growth * distance up to h_max), but the elements are
    recombined quadrilaterals (Blossom) with midside nodes on the exact geometry."""
    import gmsh

    if p.profile != "sphere":
        raise InputError(f"the CalculiX witness models the sphere only, got profile {p.profile!r}")
    with GMSH_LOCK:
        return _gmsh_quad_mesh(gmsh, p)


def _gmsh_quad_mesh(gmsh, p) -> QuadMesh:
    R, rc, hmin = p.R, p.r_contact, p.h_min
    L, Hb, H1, z0 = p.block_radius, p.block_height, p.indenter_height, p.probe_depth
    gmsh.initialize(argv=["ccx-witness"], readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("witness")
        g = gmsh.model.geo
        ncont = max(2, int(math.ceil(rc / hmin - 1e-9)) + 1)
        # indenter: cap of the sphere centred at (0, R), bottom point at the origin
        C = g.addPoint(0.0, R, 0.0)
        P0 = g.addPoint(0.0, 0.0, 0.0)
        Pc = g.addPoint(rc, R - math.sqrt(R * R - rc * rc), 0.0)
        Prim = g.addPoint(math.sqrt(R * R - (R - H1) ** 2), H1, 0.0)
        Ptop = g.addPoint(0.0, H1, 0.0)
        Pz = g.addPoint(0.0, z0, 0.0)
        i_contact = g.addCircleArc(P0, C, Pc)
        i_free = g.addCircleArc(Pc, C, Prim)
        i_top = g.addLine(Prim, Ptop)
        i_axis = [g.addLine(Ptop, Pz), g.addLine(Pz, P0)]
        s_ind = g.addPlaneSurface([g.addCurveLoop([i_contact, i_free, i_top] + i_axis)])
        # block
        Q0 = g.addPoint(0.0, 0.0, 0.0)
        Qz = g.addPoint(0.0, -z0, 0.0)
        Qbl = g.addPoint(0.0, -Hb, 0.0)
        Qbr = g.addPoint(L, -Hb, 0.0)
        Qr = g.addPoint(L, 0.0, 0.0)
        Qc = g.addPoint(rc, 0.0, 0.0)
        b_axis = [g.addLine(Q0, Qz), g.addLine(Qz, Qbl)]
        b_bottom = g.addLine(Qbl, Qbr)
        b_free = [g.addLine(Qbr, Qr), g.addLine(Qr, Qc)]
        b_contact = g.addLine(Qc, Q0)
        s_blk = g.addPlaneSurface([g.addCurveLoop(b_axis + [b_bottom] + b_free + [b_contact])])
        for c in (i_contact, b_contact):
            g.mesh.setTransfiniteCurve(c, ncont)
        g.synchronize()
        contact_size_field(gmsh, [i_contact, b_contact], p, hmin, rc)
        for opt, val in (("Mesh.MeshSizeExtendFromBoundary", 0), ("Mesh.MeshSizeFromPoints", 0),
                         ("Mesh.MeshSizeFromCurvature", 0), ("Mesh.Algorithm", 8),
                         ("Mesh.RecombineAll", 1), ("Mesh.RecombinationAlgorithm", 1),
                         ("Mesh.SecondOrderIncomplete", 1), ("Mesh.SecondOrderLinear", 0)):
            gmsh.option.setNumber(opt, val)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        xyz = xyz.reshape(-1, 3)
        nodes = {int(t): (float(x[0]), float(x[1])) for t, x in zip(tags, xyz)}
        # exact zeros on the axis (u_r = 0 there; gmsh places them at round-off)
        elements, faces, nq, nt = {}, {}, 0, 0
        eid = 0
        edge_of = {}
        for body, s in (("indenter", s_ind), ("block", s_blk)):
            lst = []
            types, etags, enodes = gmsh.model.mesh.getElements(2, s)
            for et, en in zip(types, enodes):
                npe = {16: 8, 9: 6}.get(int(et))
                if npe is None:
                    raise RuntimeError(f"unexpected gmsh element type {et} (expected quad8 or tri6)")
                for conn in np.asarray(en, dtype=np.int64).reshape(-1, npe):
                    conn = [int(c) for c in conn]
                    nc = 4 if npe == 8 else 3
                    xy = np.array([nodes[c] for c in conn[:nc]])
                    area2 = np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1])
                    if area2 < 0:  # clockwise: reverse the corners and the midside nodes consistently
                        corners = conn[:nc][::-1]
                        mids = conn[nc:][::-1]
                        mids = mids[1:] + mids[:1]
                        conn = corners + mids
                    eid += 1
                    lst.append((eid, npe, conn))
                    for k, (i, j) in enumerate(_FACES[npe]):
                        edge_of[frozenset((conn[i], conn[j]))] = (eid, k + 1)
                    nq += npe == 8
                    nt += npe == 6
            elements[body] = lst

        def curve_nodes(c):
            t, _, _ = gmsh.model.mesh.getNodes(1, c, includeBoundary=True)
            return [int(x) for x in t]

        def curve_faces(c):
            out = []
            _, _, en = gmsh.model.mesh.getElements(1, c)
            for conn in np.asarray(en[0], dtype=np.int64).reshape(-1, 3):
                out.append(edge_of[frozenset((int(conn[0]), int(conn[1])))])
            return out

        used = {c for lst in elements.values() for _, _, conn in lst for c in conn}
        nodes = {n: xy for n, xy in nodes.items() if n in used}  # drops the sphere's centre point
        faces = {"indenter": curve_faces(i_contact), "block": curve_faces(b_contact)}
        sets = {
            "axis": sorted(set(sum((curve_nodes(c) for c in i_axis + b_axis), []))),
            "bottom": sorted(set(curve_nodes(b_bottom))),
            "top": sorted(set(curve_nodes(i_top))),
            "ind_contact": sorted(set(curve_nodes(i_contact))),
            "blk_contact": sorted(set(curve_nodes(b_contact))),
        }
        for n in sets["axis"]:
            nodes[n] = (0.0, nodes[n][1])
        probe = {"indenter": _node_at(nodes, sets["axis"], 0.0, z0),
                 "block": _node_at(nodes, sets["axis"], 0.0, -z0)}
        load = _node_at(nodes, sets["top"], 0.0, H1)
    finally:
        gmsh.finalize()
    return QuadMesh(nodes, elements, faces, sets, probe, load, hmin, nq, nt)


def _node_at(nodes, candidates, r, z):
    best = min(candidates, key=lambda n: math.hypot(nodes[n][0] - r, nodes[n][1] - z))
    if math.hypot(nodes[best][0] - r, nodes[best][1] - z) > 1e-9 * max(abs(z), 1e-12):
        raise RuntimeError(f"no mesh node at ({r:g}, {z:g})")
    return best
