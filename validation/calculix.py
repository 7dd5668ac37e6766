"""CalculiX (``ccx``) as an independent witness of the axisymmetric normal contact of ``fem normal``.

The same finite bodies as ``fem.axisym.normal_run.run_normal`` (resolved ``meshes.AxisymMeshParams``: a spherical cap
of radius R and height ``indenter_height`` on a cylindrical block of radius and height ``block_size``,
both given here in units of the Hertz contact radius a_ref) are meshed anew with gmsh as 8-node
quadrilaterals (CAX8, the few triangles left by the recombination as CAX6; midside nodes on the
exact sphere), written as a CalculiX input deck and solved by ``ccx``. Nothing of the project's
solver is used on the CalculiX side: not its mesh, its pairing, its condensation nor its contact
algorithm. Only the geometry parameters and the two post-processing formulas named below are shared.

Model (the project's, ``fem.axisym.model``): u_r = 0 on the axis of both bodies; the block bottom clamped;
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
  the block's first contact edge is left out of the master surface. CalculiX's surface values near
  the axis are wrong (below) and are not used.
- Force control needs contact at the start of the step (else the indenter is a free body): step 1
  prescribes a plate displacement of 0.4 times the Hertz approach, step 2 replaces it by the force F.

Read back (each the same quantity as the project's, never a differently defined one):

- ``approach``: -u_z of the loaded plate (the block bottom is clamped), the project's ``approach``;
- ``probe_approach``: u_z,block(0, -z0) - u_z,indenter(0, +z0) at the resolved ``probe_depth`` z0
  (the meshes have nodes there), the project's ``probe["u_block"] - probe["u_indenter"]``;
- ``indentation``: ``probe_approach`` plus the Boussinesq displacement below the probes
  (``fem.bulk.boussinesq_axis``, the project's formula, here summed over ring forces from the
  indenter's nodal traction below, trapezoidal ring areas, scaled to carry F), the project's
  half-space-comparable ``indentation``;
- ``p0`` and ``contact_radius`` from a least-squares line p^2 = c0 + c1 r^2 through the nodal normal
  contact traction p = -n.sigma.n of CalculiX's (extrapolated, averaged) nodal stresses at the contact
  nodes, for 0.25 a <= r <= 0.7 a (Hertz: p^2 = p0^2 (1 - r^2/a^2), so p0 = sqrt(c0),
  a = sqrt(-c0/c1); Hertz, J. reine angew. Math. 92 (1882) 156), fitted on each body's surface and
  averaged. The same fit is applied to the project's nodal pressure (the project side's ``fit_p0``,
  ``fit_contact_radius``); the project's own extrapolated ``p0`` and edge ``contact_radius`` are
  compared as well (``p0_own``, ``contact_radius_own``). The window keeps away from the axis, where
  CalculiX's surface values are wrong (the first nodes read 0 or -0.6 p0 instead of p0), and from
  the edge, where they oscillate.
- CalculiX's own nodal contact pressure (``CPRESS`` of ``*CONTACT FILE``) is read and fitted too
  (``fit_cpress``), but not compared: for these CAX8 faces it is biased. Measured (block and cap
  200 a, a/80): it falls below both the project's pressure and CalculiX's own surface traction
  (which agree to 2e-4) by 0.07 % at 0.2 a growing to 0.6 % at 0.7 a; at a/40 it is negative
  (down to -p0) on the first nodes outside the contact; its fitted radius is 0.5 % below the
  traction's at a/40 and a/80 alike (no convergence). Over the five geometries at the fine level
  (``LEVELS``) that radius deficit ranges from 0.01 % to 0.6 %, so it depends on the mesh.

Error bars (:func:`witness_levels`): each code is run at two mesh levels, ``LEVELS``: (a/40,
grading 0.25, the project's default) and (a/80, grading 0.125), the fine one halving every element
size of the graded mesh (h_min + growth * distance; the far-field cap h_max stays). The bar of a
quantity is |q(fine) - q(coarse)| / |q(fine)|, the change on halving the element size. This change
estimates the error of the coarser level; taking it as the error of the finer one is conservative
for a converging quantity, but it is no bound. Halving the contact size alone is not enough: the
probes sit where the element size is set by the grading (``fem.bulk``), and with block and cap 3 a
the probes' approach of the two codes differed by 4.8e-4 at a/80 with the default grading, against
h-halving bars of 0.4e-4 (CalculiX) and 2.5e-4 (project); grading 0.1 brought the difference to
0.4e-4 (the project's reading moved by 3.8e-4, CalculiX's by 1.3e-4). The bar is a discretisation
bar only: it says nothing about modelling errors both codes share (small strain, linear elasticity,
the geometry). CalculiX's penalty error is not removed (no augmented Lagrangian) and a bar at a fixed
penalty factor does not see it; its size is estimated as ``penalty_error`` = p0 / K / approach (the
largest penetration relative to the approach: 4e-5 at a/80) and added by the tests.
"""
from __future__ import annotations

import dataclasses
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass

import numpy as np

from fem.bulk import boussinesq_axis
from fem.axisym.normal_run import mesh_params, run_normal
from meshes import AxisymMeshParams
from meshes.axisym import GMSH_LOCK, contact_size_field  # gmsh's state is global: one mesher at a time
from common.errors import ConvergenceError, InputError, positive
from common.io import check_output_path, write_json
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
#: the project's far-field grading (element size h_min + growth * distance from the contact)
GROWTH_DEFAULT = AxisymMeshParams.growth
#: the two mesh levels (h / a_ref, growth) of the error bars: the fine one halves every graded size
LEVELS = ((1.0 / 40.0, GROWTH_DEFAULT), (1.0 / 80.0, GROWTH_DEFAULT / 2.0))
#: r / a window of the p^2-linear-in-r^2 fit
FIT_WINDOW = (0.25, 0.7)
#: length unit of the deck (m): CalculiX rejects element Jacobians below 1e-20 in the deck's units,
#: which the 2-degree sector of a sub-micrometre element near the axis falls below in metres
MM = 1e-3
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
    growth: float | None = None  # far-field grading of both meshes (None: the project's default)

    @property
    def a_ref(self) -> float:
        return float(hertz(self.F, self.R, self.materials.E_star)["a"])

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
    out = ["** CalculiX witness of fem normal: sphere cap on a cylindrical block, axisymmetric",
           f"** {geometry.name}; R = {geometry.R!r} m, F = {geometry.F!r} N, h = {m.h!r} m",
           "** units: mm, N, MPa (N/mm^2); penalty slope N/mm^3", "*NODE, NSET=NALL"]
    out += [f"{n}, {_num(x / MM)}, {_num(y / MM)}, 0.0" for n, (x, y) in sorted(m.nodes.items())]
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
        out += [f"*MATERIAL, NAME=M{body.upper()}", "*ELASTIC", f"{_num(E * MM**2)}, {_num(nu)}",
                f"*SOLID SECTION, ELSET=E{body.upper()}, MATERIAL=M{body.upper()}"]
    out += ["*SURFACE INTERACTION, NAME=SI", "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR", _num(K * MM**3),
            "*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE", "SIND, SBLK"]
    # rigid frictionless plate: u_z of every top node equals that of the load node
    out.append("*EQUATION")
    for n in m.sets["top"]:
        if n != m.load_node:
            out += ["2", f"{n}, 2, 1.0, {m.load_node}, 2, -1.0"]
    out += ["*BOUNDARY", "NAXIS, 1, 1", "NBOTTOM, 1, 2"]
    # step 1: plate displacement (contact established); step 2: the force F
    out += ["*STEP", "*STATIC", "1.0, 1.0", "*BOUNDARY", f"NLOAD, 2, 2, {_num(-preload * d_h / MM)}", "*END STEP",
            "*STEP", "*STATIC", "0.5, 1.0, 1e-3, 1.0", "*BOUNDARY, OP=NEW", "NAXIS, 1, 1", "NBOTTOM, 1, 2",
            "*CLOAD", f"NLOAD, 2, {_num(-geometry.F)}",
            "*NODE PRINT, NSET=NPROBE", "U", "*NODE PRINT, NSET=NLOAD", "U",
            "*NODE PRINT, NSET=NBOTTOM, TOTALS=ONLY", "RF",
            "*CONTACT PRINT, SLAVE=SIND, MASTER=SBLK", "CFN",
            "*NODE FILE", "U, S", "*CONTACT FILE", "CSTR", "*END STEP"]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")
    return m


def _touches_axis(m: QuadMesh, e, k, body):
    for eid, npe, conn in m.elements[body]:
        if eid == e:
            i, j = _FACES[npe][k - 1]
            return m.nodes[conn[i]][0] == 0.0 or m.nodes[conn[j]][0] == 0.0
    raise KeyError(e)


# --------------------------------------------------------------------------- output


def parse_dat(text: str) -> dict:
    """The last increment's values of the ``.dat`` file written by the deck of :func:`write_inp`:
    ``u_probe`` {node: u_z}, ``u_load`` (u_z of the plate), ``rf_bottom`` (total u_z reaction of
    the block bottom) and ``contact_normal_force`` (CalculiX's printed values, i.e. per 2-degree
    sector)."""
    out = {}
    probe, load, rf, cfn = None, None, None, None
    lines = text.splitlines()
    for i, ln in enumerate(lines):
        head = ln.strip()
        if not head or head[0].isdigit() or head[0] in "-+":
            continue
        data = []
        for nxt in lines[i + 1:]:
            if nxt.strip():
                if not re.match(r"^\s*[-+]?\d", nxt):
                    break
                data.append(nxt.split())
            elif data:
                break
        if head.startswith("displacements") and "NPROBE" in head:
            probe = {int(f[0]): float(f[2]) for f in data}
        elif head.startswith("displacements") and "NLOAD" in head:
            load = float(data[0][2])
        elif head.startswith("total force") and "NBOTTOM" in head:
            rf = float(data[0][1])
        elif head.startswith("area,") and "normal force" in head:
            cfn = float(data[0][1])
    if probe is None or load is None or rf is None:
        raise ConvergenceError("ccx wrote no displacement / reaction output (did the step converge?)")
    out.update(u_probe=probe, u_load=load, rf_bottom=rf, contact_normal_force=cfn)
    return out


def parse_frd(text: str, block: str) -> dict:
    """{node: [values]} of the last result block named ``block`` (``STRESS``, ``CONTACT``, ``DISP``)
    of an ASCII ``.frd`` file (fixed format: node in columns 4-13, values 12 characters each)."""
    start = text.rfind(f" -4  {block}")
    if start < 0:
        raise ConvergenceError(f"ccx wrote no {block} block to the .frd file")
    out = {}
    for ln in text[start:].splitlines()[1:]:
        if ln.startswith(" -3"):
            break
        if ln.startswith(" -1"):
            n = (len(ln.rstrip()) - 13) // 12
            out[int(ln[3:13])] = [float(ln[13 + 12 * k:25 + 12 * k]) for k in range(n)]
    return out


def fit_hertz(r, p, a_guess, window=FIT_WINDOW, iterations=4) -> dict:
    """p0 and contact radius a of a line p^2 = c0 + c1 r^2 fitted (least squares) to the nodal
    pressures with window[0] a <= r <= window[1] a; a starts at ``a_guess`` and is refined from the
    fit until the node set repeats. Returns ``p0``, ``a``, ``nodes`` (used) and ``rms`` (relative
    rms residual of p^2)."""
    r = np.asarray(r, dtype=float)
    p = np.asarray(p, dtype=float)
    a = float(a_guess)
    used = None
    for _ in range(iterations):
        sel = (r >= window[0] * a) & (r <= window[1] * a)
        if sel.sum() < 3:
            raise ConvergenceError(f"too few pressure nodes ({int(sel.sum())}) in {window[0]:g}..{window[1]:g} a "
                                   "for the p^2 fit: refine the mesh")
        c1, c0 = np.polyfit(r[sel] ** 2, p[sel] ** 2, 1)
        if c0 <= 0 or c1 >= 0:
            raise ConvergenceError(f"p^2 = {c0:.4g} + {c1:.4g} r^2 is no Hertz-like profile")
        a = math.sqrt(-c0 / c1)
        key = tuple(np.flatnonzero(sel))
        if key == used:
            break
        used = key
    res = p[sel] ** 2 - (c0 + c1 * r[sel] ** 2)
    return {"p0": math.sqrt(c0), "a": a, "nodes": int(sel.sum()), "rms": float(np.sqrt(np.mean(res**2)) / c0)}


def _ring_forces(r, p):
    """Ring forces (N) of nodal pressures p at radii r (trapezoidal rule of 2 pi r p dr)."""
    r = np.asarray(r, dtype=float)
    dr = np.gradient(r) if r.size > 1 else np.zeros(1)
    w = 2.0 * np.pi * r * dr
    w[0] = 2.0 * np.pi * r[0] * 0.5 * (r[1] - r[0]) if r.size > 1 else 0.0
    return p * w


# --------------------------------------------------------------------------- runs


def run_ccx(geometry: Geometry, h: float = H_DEFAULT, *, penalty: float = PENALTY_DEFAULT,
            timeout: float = TIMEOUT_DEFAULT, threads: int = 1, workdir=None, keep: bool = False) -> dict:
    """Mesh, write, run ``ccx`` (in a temporary directory, ``timeout`` s of wall time) and read back
    (module docstring): ``approach``, ``probe_approach``, ``indentation``, ``p0``,
    ``contact_radius``, the pressure profile, checks and runtimes (s)."""
    exe = require_ccx()
    positive("timeout", timeout)
    t0 = time.perf_counter()
    p = geometry.params(h)
    mesh = build_quad_mesh(p)
    t1 = time.perf_counter()
    tmp = tempfile.mkdtemp(prefix="ccx-witness-", dir=workdir)
    try:
        write_inp(os.path.join(tmp, "witness.inp"), geometry, h, penalty=penalty, mesh=mesh)
        env = dict(os.environ, OMP_NUM_THREADS=str(threads), CCX_NPROC_EQUATION_SOLVER=str(threads),
                   CCX_NPROC_RESULTS=str(threads), CCX_NPROC_STIFFNESS=str(threads))
        t2 = time.perf_counter()
        try:
            proc = subprocess.run([exe, "-i", "witness"], cwd=tmp, env=env, capture_output=True, text=True,
                                  timeout=timeout)
        except subprocess.TimeoutExpired:
            raise ConvergenceError(f"ccx did not finish within {timeout:g} s ({geometry.name}, h = a/{1 / h:.3g})") \
                from None
        t3 = time.perf_counter()
        log = proc.stdout + proc.stderr
        if proc.returncode != 0 or "*ERROR" in log:
            err = [ln.strip() for ln in log.splitlines() if "ERROR" in ln][:3]
            raise ConvergenceError(f"ccx failed (exit {proc.returncode}): {' | '.join(err) or log[-300:]}")
        with open(os.path.join(tmp, "witness.dat")) as f:
            dat = parse_dat(f.read())
        with open(os.path.join(tmp, "witness.frd")) as f:
            frd = f.read()
        stress, cont = parse_frd(frd, "STRESS"), parse_frd(frd, "CONTACT")
    finally:
        if not keep:
            shutil.rmtree(tmp, ignore_errors=True)
    R = geometry.R
    a_ref = geometry.a_ref
    prof = {}
    for body, name in (("indenter", "ind_contact"), ("block", "blk_contact")):
        ns = sorted(mesh.sets[name], key=lambda n: mesh.nodes[n][0])
        r = np.array([mesh.nodes[n][0] for n in ns])
        z = np.array([mesh.nodes[n][1] for n in ns])
        # outward unit normal: the sphere's (centre (0, R)) for the indenter, +z for the block
        nr, nz = (r / R, (z - R) / R) if body == "indenter" else (0.0 * r, 1.0 + 0.0 * r)
        s_ = np.array([stress[n] for n in ns]) * MM**-2  # MPa -> Pa: SXX (r), SYY (z), SZZ (hoop), SXY (rz)
        p_n = -(nr * nr * s_[:, 0] + nz * nz * s_[:, 1] + 2.0 * nr * nz * s_[:, 3])
        prof[body] = (r, p_n)
    fits = {b: fit_hertz(r_, p_, a_ref) for b, (r_, p_) in prof.items()}
    fit = {"p0": 0.5 * (fits["indenter"]["p0"] + fits["block"]["p0"]),
           "a": 0.5 * (fits["indenter"]["a"] + fits["block"]["a"])}
    slave = sorted((n for n in mesh.sets["ind_contact"] if n in cont), key=lambda n: mesh.nodes[n][0])
    r_c = np.array([mesh.nodes[n][0] for n in slave])
    cpress = np.array([cont[n][3] for n in slave]) * MM**-2
    fit_cpress = fit_hertz(r_c, cpress, a_ref)
    r, pres = prof["indenter"]
    F = geometry.F
    mat = geometry.materials
    u_ind, u_blk = (MM * dat["u_probe"][mesh.probe[b]] for b in ("indenter", "block"))  # mm -> m
    lam = _ring_forces(r, pres)
    force_p = float(lam.sum())
    lam_F = lam * (F / force_p)  # the Boussinesq weights carry F (pressure near the axis is unreliable)
    z0 = p.probe_depth
    w = boussinesq_axis(lam_F, r, z0, mat.E1, mat.nu1) + boussinesq_axis(lam_F, r, z0, mat.E2, mat.nu2)
    approach = -MM * dat["u_load"]
    checks = {"reaction": SECTOR * dat["rf_bottom"] / F,
              "contact_force": (-SECTOR * dat["contact_normal_force"] / F
                                if dat["contact_normal_force"] is not None else None),
              "pressure_force": force_p / F}
    for k in ("reaction", "contact_force"):
        if checks[k] is not None and abs(checks[k] - 1.0) > 1e-3:
            raise ConvergenceError(f"ccx {k} x {SECTOR:g} is {checks[k]:.6g} F, not F: the 2-degree sector "
                                   "scaling of this CalculiX version differs from the one assumed")
    K = penalty * min(mat.E1, mat.E2) / mesh.h
    return {"approach": approach, "probe_approach": u_blk - u_ind, "indentation": u_blk - u_ind + w,
            "p0": fit["p0"], "contact_radius": fit["a"], "fit": fits, "fit_cpress": fit_cpress,
            "pressure": {"r": r.tolist(), "p": pres.tolist(), "cpress": cpress.tolist()},
            "penalty_slope": K, "penalty_error": fit["p0"] / K / approach, "checks": checks,
            "probe_depth": z0, "nodes": len(mesh.nodes), "elements": {"CAX8": mesh.n_quads, "CAX6": mesh.n_tris},
            "node_spacing": 0.5 * mesh.h, "h": h,
            "runtime_s": {"mesh": t1 - t0, "ccx": t3 - t2, "total": t3 - t0}}


def run_fem(geometry: Geometry, h: float = H_DEFAULT, *, cache_dir=None) -> dict:
    """The project's ``fem.axisym.normal_run.run_normal`` for the same bodies at contact size h * a_ref, with the
    quantities of :func:`run_ccx` (``fit_p0`` / ``fit_contact_radius``: the same p^2 fit applied to the
    project's nodal pressure). ``cache_dir`` None: a fresh directory, so the runtime includes meshing."""
    import warnings

    tmp = None
    if cache_dir is None:
        tmp = cache_dir = tempfile.mkdtemp(prefix="ccx-witness-fem-")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # coarse-mesh notice at h > a/10
            o = run_normal("sphere", R=geometry.R, F=geometry.F, materials=geometry.materials, h_contact=h,
                           cache_dir=cache_dir, **geometry.run_kwargs())
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
    r, pres = np.asarray(o["pressure"]["r"]), np.asarray(o["pressure"]["p"])
    fit = fit_hertz(r, pres, geometry.a_ref)
    return {"approach": o["approach"], "probe_approach": o["probe"]["u_block"] - o["probe"]["u_indenter"],
            "indentation": o["indentation"], "p0": o["p0"], "contact_radius": o["contact_radius"],
            "fit_p0": fit["p0"], "fit_contact_radius": fit["a"], "fit": fit,
            "probe_depth": o["probe"]["z0"], "dofs": o["dofs"], "node_spacing": 0.5 * h * geometry.a_ref, "h": h,
            "runtime_s": o["runtime_s"]}


#: quantities compared; for p0 and the contact radius the CalculiX fit is compared with the same fit
#: of the project's pressure (``like``) and with the project's own values (``own``)
COMPARED = {"approach": "approach", "probe_approach": "probe_approach", "indentation": "indentation",
            "p0": "fit_p0", "contact_radius": "fit_contact_radius",
            "p0_own": "p0", "contact_radius_own": "contact_radius"}


def witness(geometry: Geometry, h: float = H_DEFAULT, **kw) -> dict:
    """Both codes on ``geometry`` at contact size h * a_ref (and the grading ``geometry.growth``):
    ``calculix`` (:func:`run_ccx`), ``fem`` (:func:`run_fem`), ``diff`` {quantity: (CalculiX -
    project) / project} (``COMPARED``) and ``runtime_ratio`` (CalculiX total / project total).
    Keywords go to :func:`run_ccx` (``cache_dir`` to :func:`run_fem`)."""
    cache_dir = kw.pop("cache_dir", None)
    c = run_ccx(geometry, h, **kw)
    f = run_fem(geometry, h, cache_dir=cache_dir)
    diff = {q: (c[q.replace("_own", "")] - f[k]) / f[k] for q, k in COMPARED.items()}
    return {"geometry": {"block": geometry.block, "cap": geometry.cap, "R": geometry.R, "F": geometry.F,
                         "a_ref": geometry.a_ref},
            "h": h, "growth": geometry.params(h).growth, "calculix": c, "fem": f, "diff": diff,
            "runtime_ratio": c["runtime_s"]["total"] / f["runtime_s"]["total"]}


def witness_levels(geometry: Geometry, levels=LEVELS, **kw) -> dict:
    """:func:`witness` at each mesh level (h, growth) of ``levels``, coarse to fine (``growth`` None:
    the project's default). Returns ``levels`` and, for every compared quantity, the finest level's
    relative difference ``diff`` and the two codes' error bars ``bar_calculix``, ``bar_fem``
    (relative change between the two finest levels; module docstring)."""
    if len(levels) < 2:
        raise InputError(f"levels needs at least two (h, growth) mesh levels (coarse, fine), got {levels!r}")
    runs = [witness(dataclasses.replace(geometry, growth=g), h, **kw) for h, g in levels]
    fine, coarse = runs[-1], runs[-2]
    out = {}
    for q, k in COMPARED.items():
        qc = q.replace("_own", "")
        out[q] = {"diff": fine["diff"][q],
                  "bar_calculix": abs(fine["calculix"][qc] - coarse["calculix"][qc]) / abs(fine["calculix"][qc]),
                  "bar_fem": abs(fine["fem"][k] - coarse["fem"][k]) / abs(fine["fem"][k])}
    return {"geometry": fine["geometry"], "levels": [[r["h"], r["growth"]] for r in runs], "runs": runs,
            "compare": out}


def table(results) -> str:
    """Plain-text table of :func:`witness_levels` results (one block of rows per geometry)."""
    rows = []
    for res in results:
        g = res["geometry"]
        fine, coarse = res["runs"][-1], res["runs"][-2]
        tc, tf = (fine["calculix"]["runtime_s"]["total"], coarse["calculix"]["runtime_s"]["total"]), \
            (fine["fem"]["runtime_s"]["total"], coarse["fem"]["runtime_s"]["total"])
        rows.append(f"block {g['block']:g} a, cap {g['cap']:g} a: fine a/{1 / fine['h']:.3g} growth "
                    f"{fine['growth']:g}, coarse a/{1 / coarse['h']:.3g} growth {coarse['growth']:g}; runtime fine "
                    f"(coarse): CalculiX {tc[0]:.1f} s ({tc[1]:.1f} s), fem {tf[0]:.2f} s ({tf[1]:.2f} s), "
                    f"ratio {fine['runtime_ratio']:.0f} ({coarse['runtime_ratio']:.0f}); "
                    f"CalculiX penalty error {fine['calculix']['penalty_error']:.1e}")
        for q, k in COMPARED.items():
            c = res["compare"][q]
            qc = q.replace("_own", "")
            rows.append(f"  {q:20s} ccx {fine['calculix'][qc]:.7g}  fem {fine['fem'][k]:.7g}  diff {c['diff']:+.2e}  "
                        f"bar ccx {c['bar_calculix']:.1e}  bar fem {c['bar_fem']:.1e}")
    return "\n".join(rows)


def agrees(res) -> dict:
    """Per compared quantity of a :func:`witness_levels` result: whether the two codes agree within
    both error bars (|diff| <= bar_calculix + bar_fem + the CalculiX penalty error), or None where a
    number is missing."""
    fine = (res.get("runs") or [{}])[-1]
    pen = (fine.get("calculix") or {}).get("penalty_error") or 0.0
    out = {}
    for q, c in (res.get("compare") or {}).items():
        nums = (c.get("diff"), c.get("bar_calculix"), c.get("bar_fem"))
        out[q] = None if any(x is None or not math.isfinite(x) for x in nums) else \
            bool(abs(nums[0]) <= nums[1] + nums[2] + pen)
    return out


def witness_cached(out, log=print, force: bool = False, levels=LEVELS) -> list:
    """The five geometries (``GEOMETRIES``) through :func:`witness_levels`, stored in
    ``out/witness_calculix.json`` per code version (``validation.store.cached``: a rerun with unchanged
    code reads them back, unless ``force``): ``python -m validation.compare --witness``. Needs ccx
    (``require_ccx``)."""
    from pathlib import Path

    from .store import cached

    def compute():
        require_ccx()
        results = []
        for block, cap in GEOMETRIES:
            log(f"  CalculiX witness: block {block:g} a, cap {cap:g} a (two mesh levels, about a minute)")
            try:
                results.append(witness_levels(Geometry(block, cap), tuple(levels)))
            except (ConvergenceError, RuntimeError, subprocess.SubprocessError, OSError) as e:
                # one geometry that fails is reported as such (undetermined in the report); the others go on
                log(f"  CalculiX witness FAILED for block {block:g} a, cap {cap:g} a: {type(e).__name__}: {e}")
                results.append({"geometry": {"block": block, "cap": cap}, "error": f"{type(e).__name__}: {e}",
                                "runs": [], "compare": {}})
        return results

    return cached(Path(out) / "witness_calculix.json", "results", compute, what="CalculiX witness", force=force,
                  log=log)


def _level(text):
    h, _, g = text.partition(":")
    return float(h), (float(g) if g else None)


def main(argv=None) -> int:
    """``python -m validation.calculix [--levels H:GROWTH ...] [--json PATH]``: the five geometries,
    table to stdout (about 5 min of CalculiX at the default levels)."""
    import argparse

    from common.cli import OneLineParser

    ap = OneLineParser(prog="python -m validation.calculix", description=__doc__.splitlines()[0])
    ap.add_argument("--levels", type=_level, nargs="+", default=list(LEVELS), metavar="H[:GROWTH]",
                    help="mesh levels coarse to fine: contact size / a and far-field grading (default "
                         + " ".join(f"{h:g}:{g:g}" for h, g in LEVELS) + ")")
    ap.add_argument("--json", default=None, help="write the full results to this JSON file")
    ap.add_argument("--threads", type=int, default=1, help="ccx threads (default 1)")
    args = ap.parse_args(argv)
    try:
        require_ccx()
        if args.json and args.json != "-":
            check_output_path(args.json, "--json")
    except (MissingDependency, InputError) as exc:
        sys.stderr.write(f"python -m validation.calculix: error: {exc}\n")
        return 2
    results = []
    for block, cap in GEOMETRIES:
        results.append(witness_levels(Geometry(block, cap), tuple(args.levels), threads=args.threads))
        print(table(results[-1:]), flush=True)
    if args.json:
        write_json(args.json, results)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
