"""The CalculiX input deck of the witness (``validation.calculix``): ``write_inp``.

Model (the project's, ``fem.axisym.model``): u_r = 0 on the axis of both bodies; the block bottom clamped;
the indenter top a rigid frictionless plate (``*EQUATION``: every top node has the u_z of the top
node on the axis, u_r free) carrying the normal force F (``*CLOAD`` on that node). Frictionless
contact is CalculiX's face-to-face penalty contact (``*CONTACT PAIR, TYPE=SURFACE TO SURFACE``,
linear pressure-overclosure with slope K = ``penalty`` E / h, E the smaller Young modulus, h the
contact element size), indenter surface as slave, block top as master. Small deformation (no NLGEOM).
Units of the deck: mm, N, MPa (``MM``).

Facts about CalculiX 2.20 the deck relies on (checked by ``tests/test_calculix.py``):

- CAX elements are expanded internally into a 2-degree sector of 3D elements. Concentrated forces
  (``*CLOAD``) are given for the full circumference (CalculiX manual, CAX8 section), while printed
  reaction forces and contact forces refer to the 2-degree sector, i.e. are 1/180 of the total
  (``validation.calculix_run.SECTOR``): ``run_ccx`` multiplies them by 180 and checks that the
  block's reaction and the contact force equal F.
- The master surface must not contain an edge with a node on the axis (manual, ``*CONTACT PAIR``):
  the block's first contact edge is left out of the master surface. CalculiX's surface values near
  the axis are wrong (``validation.calculix_run``) and are not used.
- Force control needs contact at the start of the step (else the indenter is a free body): step 1
  prescribes a plate displacement of the Hertz approach (``PRELOAD``), step 2 replaces it by the force F
  in one increment. The bodies are elastic and frictionless, so the answer does not depend on that path,
  only CalculiX's contact iterations do: on the 200 a bodies at a/80 they are 27 with this start against
  72 with a plate displacement of 0.4 times the Hertz approach and the force in two increments (12 s
  against 27 s on two threads), the approaches and the fitted p0 and a within 1e-6 of each other.
"""
from __future__ import annotations

from common.errors import positive
from mdr.reference import hertz

from .calculix_mesh import _FACES, H_DEFAULT, Geometry, QuadMesh, build_quad_mesh

#: default penalty factor: K = PENALTY_DEFAULT * E / h
PENALTY_DEFAULT = 100.0
#: step 1's plate displacement as a fraction of the Hertz approach (the bodies' own compliance makes the
#: force of that displacement below F, which step 2 then applies)
PRELOAD = 1.0
#: length unit of the deck (m): CalculiX rejects element Jacobians below 1e-20 in the deck's units,
#: which the 2-degree sector of a sub-micrometre element near the axis falls below in metres
MM = 1e-3


# --------------------------------------------------------------------------- deck


def _num(x) -> str:
    """A real as CalculiX reads it: at most 20 characters a field (13 significant digits)."""
    return f"{float(x):.12e}"


def _lines(values, per_line=8):
    values = list(values)
    return "\n".join(", ".join(str(v) for v in values[i:i + per_line]) for i in range(0, len(values), per_line))


def write_inp(path, geometry: Geometry, h: float = H_DEFAULT, *, penalty: float = PENALTY_DEFAULT,
              mesh: QuadMesh | None = None, preload: float = PRELOAD) -> QuadMesh:
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
            "*STEP", "*STATIC", "1.0, 1.0, 1e-3, 1.0", "*BOUNDARY, OP=NEW", "NAXIS, 1, 1", "NBOTTOM, 1, 2",
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
