"""CalculiX (``ccx``) as an independent witness of the axisymmetric normal contact of ``fem normal``.

The same finite bodies as ``fem.run.run_normal`` (resolved ``meshes.AxisymMeshParams``: a spherical cap
of radius R and height ``indenter_height`` on a cylindrical block of radius and height ``block_size``,
both given here in units of the Hertz contact radius a_ref) are meshed anew with gmsh as 8-node
quadrilaterals (CAX8, the few triangles left by the recombination as CAX6; midside nodes on the
exact sphere), written as a CalculiX input deck and solved by ``ccx``. Nothing of the project's
solver is used on the CalculiX side: not its mesh, its pairing, its condensation nor its contact
algorithm. Only the geometry parameters and the two post-processing formulas named below are shared.

Model (the project's, ``fem.model``): u_r = 0 on the axis of both bodies; the block bottom clamped;
the indenter top a rigid frictionless plate (``*EQUATION``: every top node has the u_z of the top
node on the axis, u_r free) carrying the normal force F (``*CLOAD`` on that node). Frictionless
contact is CalculiX's face-to-face penalty contact (``*CONTACT PAIR, TYPE=SURFACE TO SURFACE``,
linear pressure-overclosure with slope K = ``penalty`` E / h, E the smaller Young modulus, h the
contact element size), indenter surface as slave, block top as master. Small deformation (no NLGEOM).

Facts about CalculiX 2.20 the deck relies on (checked by ``tests/test_calculix.py``):

- CAX elements are expanded internally into a 2-degree sector of 3D elements. Concentrated forces
  (``*CLOAD``) are given for the full circumference (CalculiX manual, CAX8 section), while printed
  reaction forces and contact forces refer to the 2-degree sector, i.e. are 1/180 of the total
  (``SECTOR``): :func:`run_ccx` multiplies them by 180 and checks that the block's reaction and the
  contact force equal F.
- The master surface must not contain an edge with a node on the axis (manual, ``*CONTACT PAIR``):
  the block's first contact edge is left out of the master surface, and CalculiX's pressure is not
  used within about three elements of the axis.
- Force control needs contact at the start of the step (else the indenter is a free body): step 1
  prescribes a plate displacement of 0.4 times the Hertz approach, step 2 replaces it by the force F.

Read back (each the same quantity as the project's, never a differently defined one):

- ``approach``: -u_z of the loaded plate (the block bottom is clamped), the project's ``approach``;
- ``probe_approach``: u_z,block(0, -z0) - u_z,indenter(0, +z0) at the resolved ``probe_depth`` z0
  (the meshes have nodes there), the project's ``probe["u_block"] - probe["u_indenter"]``;
- ``indentation``: ``probe_approach`` plus the Boussinesq displacement below the probes
  (``fem.bulk.boussinesq_axis``, the project's formula, here summed over ring forces from CalculiX's
  nodal pressure with trapezoidal ring areas), the project's half-space-comparable ``indentation``;
- ``p0`` and ``contact_radius`` from a least-squares line p^2 = c0 + c1 r^2 through CalculiX's nodal
  contact pressure (``CPRESS``) for 0.25 a <= r <= 0.7 a (Hertz: p^2 = p0^2 (1 - r^2/a^2), so
  p0 = sqrt(c0), a = sqrt(-c0/c1); Hertz, J. reine angew. Math. 92 (1882) 156). The same fit is
  applied to the project's nodal pressure (``fit_p0``, ``fit_contact_radius`` of the project side),
  and the project's own extrapolated ``p0`` and edge ``contact_radius`` are reported beside it.

Error bars (:func:`witness_levels`): each code is run at two mesh sizes, h and 2h, and the bar of a
quantity is |q(h) - q(2h)|, the change on halving the element size, i.e. a Richardson-type estimate
of the error of the coarser level that is taken (conservatively for a converging quantity) as the
error of the finer one. It is a discretisation bar only; it says nothing about modelling errors
both codes share (small strain, linear elasticity, the geometry). For CalculiX it also contains the
penalty error, which is not removed (no augmented Lagrangian), and which the bar at a fixed penalty
factor does not see; its size is estimated separately as ``penalty_error`` = p0 / K / approach
(the largest penetration relative to the approach).
"""
from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import tempfile
import time
from dataclasses import dataclass

import numpy as np

from fem.bulk import boussinesq_axis
from fem.run import mesh_params, run_normal
from mdr.errors import ConvergenceError, InputError, positive
from mdr.materials import Materials
from mdr.reference import hertz

#: the executable names tried by :func:`ccx_executable`
CCX_NAMES = ("ccx", "ccx_2.21", "ccx_2.20", "ccx_2.19")
#: how to get it on Debian
INSTALL_HINT = "apt-get install calculix-ccx"
#: CalculiX's axisymmetric elements model a 2-degree sector: printed forces are 1/180 of the total
SECTOR = 180.0
#: the five (block, cap) sizes in units of the contact radius a_ref
GEOMETRIES = ((200.0, 200.0), (10.0, 200.0), (10.0, 10.0), (3.0, 200.0), (3.0, 3.0))
#: default contact element size / a_ref (as ``fem normal``)
H_DEFAULT = 1.0 / 80.0
#: default penalty factor: K = PENALTY_DEFAULT * E / h
PENALTY_DEFAULT = 100.0
#: r / a window of the p^2-linear-in-r^2 fit
FIT_WINDOW = (0.25, 0.7)
#: default wall-time limit of one ccx run (s)
TIMEOUT_DEFAULT = 900.0


class MissingDependency(RuntimeError):
    """An optional external program is not installed (the message names the install command)."""


def ccx_executable() -> str | None:
    """Path of the CalculiX solver (``$CCX`` if set, else the first of ``CCX_NAMES`` on PATH), or None."""
    env = os.environ.get("CCX")
    if env:
        return shutil.which(env) or (env if os.path.isfile(env) and os.access(env, os.X_OK) else None)
    for name in CCX_NAMES:
        path = shutil.which(name)
        if path:
            return path
    return None


def require_ccx() -> str:
    """The ccx path, or :class:`MissingDependency` naming the install command."""
    path = ccx_executable()
    if path is None:
        raise MissingDependency(f"CalculiX (ccx) not found on PATH: install it with `{INSTALL_HINT}` "
                                "(Debian package calculix-ccx) or set $CCX to the executable")
    return path


# --------------------------------------------------------------------------- geometry


@dataclass(frozen=True)
class Geometry:
    """Scene of the witness: sphere radius ``R`` (m), force ``F`` (N), materials, and the block and cap
    sizes in units of the Hertz contact radius (the project's ``block_size`` and ``indenter_height``
    divided by a_ref)."""

    block: float = 200.0
    cap: float = 200.0
    R: float = 6e-3
    F: float = 0.5
    materials: Materials = Materials()

    @property
    def a_ref(self) -> float:
        return float(hertz(self.F, self.R, self.materials.E_star)["a"])

    def run_kwargs(self) -> dict:
        """Keywords of ``fem.run.run_normal`` for these bodies."""
        a = self.a_ref
        return {"block_size": self.block * a, "indenter_height": self.cap * a}

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
    """Both bodies' CAX8/CAX6 elements: ``nodes`` {tag: (r, z)}, ``elements`` {body: [(type, tags)]},
    and the node / edge sets the deck needs."""

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
        fm = gmsh.model.mesh.field
        dist = fm.add("Distance")
        fm.setNumbers(dist, "CurvesList", [i_contact, b_contact])
        fm.setNumber(dist, "Sampling", int(4 * rc / hmin) + 20)
        size = fm.add("MathEval")
        fm.setString(size, "F", f"min({p.h_max!r}, {hmin!r} + {p.growth!r} * F{dist})")
        fm.setAsBackgroundMesh(size)
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


# --------------------------------------------------------------------------- deck


def _num(x) -> str:
    """A real as CalculiX reads it: at most 20 characters a field (13 significant digits)."""
    return f"{float(x):.12e}"


def _lines(values, per_line=8):
    values = list(values)
    return "\n".join(", ".join(str(v) for v in values[i:i + per_line]) for i in range(0, len(values), per_line))


def write_inp(path, geometry: Geometry, h: float = H_DEFAULT, *, penalty: float = PENALTY_DEFAULT,
              mesh: QuadMesh | None = None, preload: float = 0.4) -> QuadMesh:
    """Write the CalculiX deck of ``geometry`` at contact element size ``h`` * a_ref to ``path``;
    return the mesh (module docstring: model, boundary conditions, two load steps).

    ``penalty``: K = penalty * min(E1, E2) / h (N/m^3); ``preload``: the plate displacement of step 1
    as a fraction of the Hertz approach (establishes contact before the force is applied)."""
    positive("h", h)
    positive("penalty", penalty)
    p = geometry.params(h)
    m = mesh or build_quad_mesh(p)
    mat = geometry.materials
    K = penalty * min(mat.E1, mat.E2) / m.h
    d_h = float(hertz(geometry.F, geometry.R, mat.E_star)["d"])
    out = ["** CalculiX witness of fem normal: sphere cap on a cylindrical block, axisymmetric (SI units)",
           f"** {geometry.name}; R = {geometry.R!r} m, F = {geometry.F!r} N, h = {m.h!r} m", "*NODE, NSET=NALL"]
    out += [f"{n}, {_num(x)}, {_num(y)}, 0.0" for n, (x, y) in sorted(m.nodes.items())]
    for body in ("indenter", "block"):
        for npe, typ in ((8, "CAX8"), (6, "CAX6")):
            els = [(e, conn) for e, k, conn in m.elements[body] if k == npe]
            if els:
                out.append(f"*ELEMENT, TYPE={typ}, ELSET=E{body.upper()}")
                out += [f"{e}, " + ", ".join(str(c) for c in conn) for e, conn in els]
    for name, nodes in m.sets.items():
        out += [f"*NSET, NSET=N{name.upper()}", _lines(nodes)]
    out += ["*NSET, NSET=NLOAD", str(m.load_node), "*NSET, NSET=NPROBE",
            f"{m.probe['indenter']}, {m.probe['block']}"]
    # slave: the indenter's contact curve; master: the block's, without the edge on the axis
    out.append("*SURFACE, NAME=SIND, TYPE=ELEMENT")
    out += [f"{e}, S{k}" for e, k in m.contact_faces["indenter"]]
    out.append("*SURFACE, NAME=SBLK, TYPE=ELEMENT")
    blk = [(e, k) for e, k in m.contact_faces["block"] if not _touches_axis(m, e, k, "block")]
    out += [f"{e}, S{k}" for e, k in blk]
    for body, E, nu in (("indenter", mat.E1, mat.nu1), ("block", mat.E2, mat.nu2)):
        out += [f"*MATERIAL, NAME=M{body.upper()}", "*ELASTIC", f"{_num(E)}, {_num(nu)}",
                f"*SOLID SECTION, ELSET=E{body.upper()}, MATERIAL=M{body.upper()}"]
    out += ["*SURFACE INTERACTION, NAME=SI", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR", _num(K),
            "*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE", "SIND, SBLK"]
    # rigid frictionless plate: u_z of every top node equals that of the load node
    out.append("*EQUATION")
    for n in m.sets["top"]:
        if n != m.load_node:
            out += ["2", f"{n}, 2, 1.0, {m.load_node}, 2, -1.0"]
    out += ["*BOUNDARY", "NAXIS, 1, 1", "NBOTTOM, 1, 2"]
    # step 1: plate displacement (contact established); step 2: the force F
    out += ["*STEP", "*STATIC", "1.0, 1.0", "*BOUNDARY", f"NLOAD, 2, 2, {_num(-preload * d_h)}", "*END STEP",
            "*STEP", "*STATIC", "0.5, 1.0, 1e-3, 1.0", "*BOUNDARY, OP=NEW", "NAXIS, 1, 1", "NBOTTOM, 1, 2",
            "*CLOAD", f"NLOAD, 2, {_num(-geometry.F)}",
            "*NODE PRINT, NSET=NPROBE", "U", "*NODE PRINT, NSET=NLOAD", "U",
            "*NODE PRINT, NSET=NBOTTOM, TOTALS=ONLY", "RF",
            "*CONTACT PRINT, SLAVE=SIND, MASTER=SBLK", "CFN",
            "*NODE FILE", "U", "*CONTACT FILE", "CSTR", "*END STEP"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    m.K = K
    return m


def _touches_axis(m: QuadMesh, e, k, body):
    for eid, npe, conn in m.elements[body]:
        if eid == e:
            i, j = _FACES[npe][k - 1]
            return m.nodes[conn[i]][0] == 0.0 or m.nodes[conn[j]][0] == 0.0
    raise KeyError(e)
