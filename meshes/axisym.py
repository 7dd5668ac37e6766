"""r-z section of an axisymmetric indenter on a cylindrical block, meshed with gmsh.

Geometry (z is the contact normal, the indenter above the block, first contact
at the origin; all lengths in m):

- **Indenter** (profile ``sphere`` or ``truncated``): a cap of the sphere of
  radius ``R`` with a flat face of radius ``b`` at z = 0 (b = 0: sphere). The
  cap is cut by the plane z = ``indenter_height`` (at most the sphere's equator).
  Its bottom surface inside the *contact segment* r <= ``r_contact`` is its own
  gmsh curve(s) (flat face and arc, with a node at the kink r = b).
- **Indenter** (profile ``flat``): the flat punch is modelled as the contact of
  two half-space-like bodies through the disk r <= b (the punch protrudes by an
  infinitesimal height), which is the assumption behind F = 2 E* b d. The
  indenter is a cylinder of the block's radius and height ``indenter_height``
  with a flat bottom; contact pairs exist only for r <= b (the gap is infinite
  beyond), and a node sits at the edge r = b.
- **Block**: a cylinder of radius ``block_radius`` and height ``block_height``
  (both default to 200 times the reference contact radius ``a_ref``; the effect
  of this size on the answer is measured in tests/benchmarks, not assumed).
  Its top surface r <= ``r_contact`` is the block's contact curve.
- Both axes are split at the *probe depth* ``probe_depth`` (a node at (0, +-z0)),
  where the FE model measures the axial displacement used to remove the finite
  bodies' bulk compliance (see ``fem.bulk``).

Mesh size: the contact curves are meshed uniformly with ``h_min = h_contact *
a_ref`` (transfinite curves, identical node counts on both bodies so that the
two surfaces' nodes pair up under the small-sliding assumption); away from them
the size grows linearly with the distance d to the contact curves,
``h = min(h_max, h_min + growth * d)``, i.e. geometrically from element to
element (ratio about 1 + growth), up to ``h_max`` (mm far away).

Elements: gmsh second-order triangles with straight edges (``Mesh.SecondOrderLinear``;
the chord error of the sphere is h^2/(8R), below 1e-11 m in the contact zone).
They are read through meshio (triangle6 + line3). scikit-fem's meshio reader
drops the named boundaries of second-order meshes (its boundary type for
``triangle6`` is ``line``, while gmsh writes ``line3``), so :func:`from_meshio`
here tags the facets from the line3 cells itself. Because the edges are
straight, the mesh is returned as a linear skfem ``MeshTri1`` of the vertices
on which ``ElementTriP2`` places its midside DOFs exactly at gmsh's line3 /
triangle6 midside nodes (checked on conversion); this keeps the map affine,
so assembly is fast and exact with low-order quadrature.

Physical groups (names used everywhere): indenter: ``axis``, ``contact``,
``top`` (loaded), ``free``; block: ``axis``, ``contact``, ``bottom`` (clamped),
``free`` (the rest of the top surface and the side).
"""
from __future__ import annotations

import contextlib
import io
import math
import os
import tempfile
import threading
from dataclasses import asdict, dataclass, field

import numpy as np

from common.errors import InputError, in_range, nonnegative, positive
from common.io import write_vtu_atomic

PROFILES = ("sphere", "truncated", "flat")
BODIES = ("indenter", "block")
#: bump when the geometry or the stored format changes (part of the cache key)
MESH_FORMAT_VERSION = 1

GMSH_LOCK = threading.Lock()


#: element size in the contact zone / a_ref: the default (a/80) and the allowed range, for every
#: package (fem.axisym.normal_run, fem.axisym.law, the commands' --h-contact): one home
H_CONTACT_DEFAULT = 0.0125
H_CONTACT_RANGE = (1.0 / 1000.0, 0.25)
#: the candidate contact disk's radius / a_ref where none is given, both models (the 3D flat punch:
#: its face, 1): room for the contact to grow past a_ref, e.g. under a tilt or a larger load
CONTACT_EXTENT_DEFAULT = 1.25


class ContactZoneParams:
    """What every mesh's parameters share (a mixin of the frozen parameter dataclasses): the
    contact zone r <= contact_extent * a_ref meshed at h_contact * a_ref, graded with ``growth``
    up to ``h_max``; the checks of these common fields."""

    @property
    def h_min(self) -> float:
        return self.h_contact * self.a_ref

    @property
    def r_contact(self) -> float:
        return self.contact_extent * self.a_ref

    def _check_zone(self, h_range, optional_sizes, extent_min_closed=False):
        """a_ref > 0, h_contact in ``h_range``, contact_extent in (1, 5] ([1, 5] with
        ``extent_min_closed``), growth in [0.02, 1], each of ``optional_sizes`` positive when given."""
        positive("a_ref", self.a_ref)
        in_range("h_contact", self.h_contact, *h_range)
        in_range("contact_extent", self.contact_extent, 1.0, 5.0, lo_open=not extent_min_closed)
        in_range("growth", self.growth, 0.02, 1.0)
        for name in optional_sizes:
            v = getattr(self, name)
            if v is not None:
                positive(name, v)

    def _check_h_max(self):
        if self.h_max < self.h_min:
            raise InputError(f"h_max must be >= h_min = h_contact * a_ref = {self.h_min:.4g} m, got {self.h_max!r}")


@dataclass(frozen=True)
class AxisymMeshParams(ContactZoneParams):
    """All parameters that determine a mesh (SI). Resolve defaults with :meth:`resolved`.

    ``a_ref`` is the largest contact radius the mesh must serve (the scene's
    a_max); ``h_contact`` the element size in the contact zone as a fraction of
    it (1/40 .. 1/160 typical; allowed ``H_CONTACT_RANGE`` = [1/1000, 1/4]); ``contact_extent`` the
    radius of the contact segment (uniformly fine mesh, potential contact zone,
    interface of the condensation) as a multiple of a_ref.
    """

    profile: str
    R: float | None
    b: float
    a_ref: float
    h_contact: float = H_CONTACT_DEFAULT
    contact_extent: float = CONTACT_EXTENT_DEFAULT
    block_radius: float | None = None
    block_height: float | None = None
    indenter_height: float | None = None
    probe_depth: float | None = None
    growth: float = 0.25
    h_max: float | None = None

    def __post_init__(self):
        if self.profile not in PROFILES:
            raise InputError(f"profile must be one of {', '.join(PROFILES)}; got {self.profile!r}")
        nonnegative("b", self.b)
        if self.profile in ("sphere", "truncated"):
            if self.R is None:
                raise InputError(f"R must be given (> 0) for profile {self.profile!r}")
            positive("R", self.R)
            if self.b >= self.R:
                raise InputError(f"b must be in [0, R) (flat face inside the sphere), got b={self.b!r}, R={self.R!r}")
            if self.profile == "sphere" and self.b != 0:
                raise InputError(f"b must be 0 for profile 'sphere', got {self.b!r}")
        else:
            positive("b", self.b)
        self._check_zone(H_CONTACT_RANGE, ("block_radius", "block_height", "indenter_height", "probe_depth", "h_max"))

    # ------------------------------------------------------------------ derived
    def resolved(self) -> "AxisymMeshParams":
        """Fill the size defaults from a_ref (the cache key uses the resolved values)."""
        L_r = self.block_radius if self.block_radius is not None else 200.0 * self.a_ref
        L_h = self.block_height if self.block_height is not None else L_r
        if self.indenter_height is not None:
            H1 = self.indenter_height
        else:
            H1 = L_h
        if self.profile != "flat":
            zc = math.sqrt(self.R**2 - self.b**2)
            H1 = min(H1, zc)
        if self.probe_depth is not None:
            z0 = self.probe_depth
        else:  # 20 a_ref, or midway in the allowed range when the bodies are shallower (short cap)
            z0 = min(20.0 * self.a_ref, 0.5 * (self.contact_extent * self.a_ref + 0.8 * min(L_h, H1)))
        # far-field element size: 1 mm, or 5 a_ref for large contacts (a 0.6 mm flat face would
        # otherwise fill a 120 mm block with 1 mm elements), at most an eighth of the body
        hmax = self.h_max if self.h_max is not None else min(max(1e-3, 5.0 * self.a_ref), max(L_r, L_h, H1) / 8.0)
        p = AxisymMeshParams(self.profile, None if self.profile == "flat" else float(self.R), float(self.b),
                             float(self.a_ref), float(self.h_contact), float(self.contact_extent),
                             float(L_r), float(L_h), float(H1), float(z0), float(self.growth), float(hmax))
        p._check_sizes()
        return p

    def _check_sizes(self):
        rc = self.r_contact
        if self.block_radius <= 2.0 * rc:
            raise InputError(f"block_radius must be > 2 * contact_extent * a_ref = {2 * rc:.4g} m, "
                             f"got {self.block_radius!r}")
        if self.block_height <= 2.0 * rc:
            raise InputError(f"block_height must be > {2 * rc:.4g} m, got {self.block_height!r}")
        if self.indenter_height <= 2.0 * rc:
            raise InputError(f"indenter_height must be > {2 * rc:.4g} m (2 * contact zone; for a sphere "
                             f"at most sqrt(R^2-b^2)), got {self.indenter_height!r}")
        zmax = 0.8 * min(self.block_height, self.indenter_height)
        if not (rc < self.probe_depth < zmax):
            raise InputError(f"probe_depth must be in ({rc:.4g}, {zmax:.4g}) m (beyond the contact zone, "
                             f"inside both bodies), got {self.probe_depth!r}")
        self._check_h_max()
        if self.profile != "flat":
            if self.r_contact >= 0.5 * self.R:
                raise InputError(f"contact_extent * a_ref = {rc:.4g} m must be < R/2 (small contact against "
                                 f"the sphere), got R={self.R!r}")
            if self.profile == "truncated" and self.b >= rc:
                raise InputError(f"b must be < contact_extent * a_ref = {rc:.4g} m for a truncated sphere "
                                 f"(the contact segment must reach beyond the flat face), got {self.b!r}")
        elif self.b >= rc:
            raise InputError(f"contact_extent must be > 1 for the flat punch, got {self.contact_extent!r}")

    def as_dict(self) -> dict:
        return asdict(self)


# --------------------------------------------------------------------- gmsh model


def _indenter_surface_z(p: AxisymMeshParams, r):
    """Exact cap surface height at radius r (0 on the flat face)."""
    if p.profile == "flat":
        return 0.0
    zc = math.sqrt(p.R**2 - p.b**2)
    return zc - math.sqrt(p.R**2 - max(r, p.b) ** 2) if r > p.b else 0.0


def _build_gmsh_model(p: AxisymMeshParams):
    """Create geometry, physical groups and the size field in the current gmsh model."""
    import gmsh

    g = gmsh.model.geo
    rc, hmin = p.r_contact, p.h_min
    L, Hb, H1, z0 = p.block_radius, p.block_height, p.indenter_height, p.probe_depth
    groups = {}  # (body, name) -> list of curve tags
    contact_curves = []

    def n_nodes(length):
        return max(2, int(math.ceil(length / hmin - 1e-9)) + 1)

    # ---------------- indenter
    P0 = g.addPoint(0.0, 0.0, 0.0)
    pts_bottom = [(P0, 0.0)]
    has_kink = p.b > 0
    if has_kink:
        pts_bottom.append((g.addPoint(p.b, 0.0, 0.0), p.b))
    pts_bottom.append((g.addPoint(rc, _indenter_surface_z(p, rc), 0.0), rc))
    ind_contact = []
    if p.profile == "flat":
        for (pa, ra), (pb_, rb) in zip(pts_bottom[:-1], pts_bottom[1:]):
            c = g.addLine(pa, pb_)
            ind_contact.append((c, rb - ra))
        Pc = pts_bottom[-1][0]
        Prim = g.addPoint(L, 0.0, 0.0)
        Ptop_r = g.addPoint(L, H1, 0.0)
        free = [g.addLine(Pc, Prim), g.addLine(Prim, Ptop_r)]
        Ptop = g.addPoint(0.0, H1, 0.0)
        top = g.addLine(Ptop_r, Ptop)
    else:
        zc = math.sqrt(p.R**2 - p.b**2)
        C = g.addPoint(0.0, zc, 0.0)
        if has_kink:
            ind_contact.append((g.addLine(pts_bottom[0][0], pts_bottom[1][0]), p.b))
        ind_contact.append((g.addCircleArc(pts_bottom[-2][0], C, pts_bottom[-1][0]), rc - p.b))
        Pc = pts_bottom[-1][0]
        r_rim = math.sqrt(p.R**2 - (zc - H1) ** 2)
        Prim = g.addPoint(r_rim, H1, 0.0)
        free = [g.addCircleArc(Pc, C, Prim)]
        Ptop = g.addPoint(0.0, H1, 0.0)
        top = g.addLine(Prim, Ptop)
    Pz = g.addPoint(0.0, z0, 0.0)
    axis = [g.addLine(Ptop, Pz), g.addLine(Pz, P0)]
    loop = [c for c, _ in ind_contact] + free + [top] + axis
    s_ind = g.addPlaneSurface([g.addCurveLoop(loop)])
    groups[("indenter", "contact")] = [c for c, _ in ind_contact]
    groups[("indenter", "free")] = free
    groups[("indenter", "top")] = [top]
    groups[("indenter", "axis")] = axis
    contact_curves += ind_contact

    # ---------------- block
    Q0 = g.addPoint(0.0, 0.0, 0.0)
    Qz = g.addPoint(0.0, -z0, 0.0)
    Qbl = g.addPoint(0.0, -Hb, 0.0)
    Qbr = g.addPoint(L, -Hb, 0.0)
    Qr = g.addPoint(L, 0.0, 0.0)
    Qc = g.addPoint(rc, 0.0, 0.0)
    b_axis = [g.addLine(Q0, Qz), g.addLine(Qz, Qbl)]
    b_bottom = [g.addLine(Qbl, Qbr)]
    b_free = [g.addLine(Qbr, Qr), g.addLine(Qr, Qc)]
    blk_contact = []
    if has_kink:
        Qb = g.addPoint(p.b, 0.0, 0.0)
        blk_contact = [(g.addLine(Qc, Qb), rc - p.b), (g.addLine(Qb, Q0), p.b)]
    else:
        blk_contact = [(g.addLine(Qc, Q0), rc)]
    loop = b_axis + b_bottom + b_free + [c for c, _ in blk_contact]
    s_blk = g.addPlaneSurface([g.addCurveLoop(loop)])
    groups[("block", "contact")] = [c for c, _ in blk_contact]
    groups[("block", "free")] = b_free
    groups[("block", "bottom")] = b_bottom
    groups[("block", "axis")] = b_axis
    contact_curves += blk_contact

    # uniform contact segments: same node counts on both bodies
    for c, length in contact_curves:
        g.mesh.setTransfiniteCurve(c, n_nodes(length))
    g.synchronize()

    for (body, name), curves in groups.items():
        tag = gmsh.model.addPhysicalGroup(1, curves)
        gmsh.model.setPhysicalName(1, tag, f"{body}:{name}")
    for body, s in (("indenter", s_ind), ("block", s_blk)):
        tag = gmsh.model.addPhysicalGroup(2, [s])
        gmsh.model.setPhysicalName(2, tag, body)

    contact_size_field(gmsh, [c for c, _ in contact_curves], p, hmin, rc)
    for opt, val in (("Mesh.MeshSizeExtendFromBoundary", 0), ("Mesh.MeshSizeFromPoints", 0),
                     ("Mesh.MeshSizeFromCurvature", 0), ("Mesh.Algorithm", 5),
                     ("Mesh.SecondOrderLinear", 1), ("Mesh.ElementOrder", 2),
                     ("Mesh.Binary", 0), ("Mesh.MshFileVersion", 4.1)):
        gmsh.option.setNumber(opt, val)


def contact_size_field(gmsh, curves, p: AxisymMeshParams, h_min: float, r_contact: float) -> None:
    """The element size of the bodies' meshes (the module docstring's grading law), as gmsh's background
    field: min(h_max, h_min + growth * distance to the contact ``curves``), the distance sampled finely
    enough along the contact zone of radius ``r_contact`` to see ``h_min``. One home for every mesher
    of these bodies (also the CalculiX witness's, ``validation.calculix``)."""
    fm = gmsh.model.mesh.field
    dist = fm.add("Distance")
    fm.setNumbers(dist, "CurvesList", list(curves))
    fm.setNumber(dist, "Sampling", int(4 * r_contact / h_min) + 20)
    size = fm.add("MathEval")
    fm.setString(size, "F", f"min({p.h_max!r}, {h_min!r} + {p.growth!r} * F{dist})")
    fm.setAsBackgroundMesh(size)


def generate_meshio(params: AxisymMeshParams):
    """Run gmsh on the (resolved) parameters; return the meshio mesh (triangle6 + line3)."""
    import meshio

    p = params.resolved()
    try:
        import gmsh
    except OSError as exc:  # pragma: no cover - depends on the machine image
        raise RuntimeError(f"gmsh could not load a system library ({exc}); install the Debian package "
                           "that provides it (e.g. libglu1-mesa, libxrender1, libxcursor1, libxft2, "
                           "libxinerama1)") from exc
    with GMSH_LOCK, tempfile.TemporaryDirectory() as tmp:
        gmsh.initialize(argv=["fretting"], readConfigFiles=False, interruptible=False)
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.model.add("axisym")
            _build_gmsh_model(p)
            gmsh.model.mesh.generate(2)
            gmsh.model.mesh.setOrder(2)
            path = os.path.join(tmp, "axisym.msh")
            gmsh.write(path)
        finally:
            gmsh.finalize()
        with contextlib.redirect_stdout(io.StringIO()):  # meshio's gmsh reader prints a blank line
            return meshio.read(path)


# ------------------------------------------------------------ meshio -> skfem


@dataclass
class AxisymMesh:
    """The two bodies' skfem meshes (``MeshTri1`` vertices; use ``ElementTriP2``).

    ``bodies[name]`` carries named boundaries ``axis``, ``contact``, ``top`` /
    ``bottom``, ``free`` (facet indices). ``params`` are the resolved
    parameters, ``key`` the cache hash.
    """

    params: AxisymMeshParams
    bodies: dict
    key: str = ""
    info: dict = field(default_factory=dict)

    @property
    def indenter(self):
        return self.bodies["indenter"]

    @property
    def block(self):
        return self.bodies["block"]

    def summary(self) -> dict:
        out = {"params": self.params.as_dict(), "key": self.key}
        for name, m in self.bodies.items():
            out[name] = {"vertices": int(m.p.shape[1]), "elements": int(m.t.shape[1]),
                         "p2_nodes": int(m.p.shape[1] + m.facets.shape[1])}
        return out


def _facet_lookup(mesh):
    f = np.sort(mesh.facets, axis=0).astype(np.int64)
    keys = f[0] * mesh.p.shape[1] + f[1]
    order = np.argsort(keys)
    return keys[order], order


def from_meshio(m, body: str):
    """skfem ``MeshTri1`` (with named boundaries) of one body of a gmsh order-2 meshio mesh.

    Handles what ``skfem.io.meshio.from_meshio`` does not: boundaries given as
    ``line3`` cells. Each line3 cell is matched to the mesh facet joining its
    two end vertices; its midside node must coincide with the facet midpoint
    (straight-sided P2, checked).
    """
    from skfem import MeshTri1

    tri = m.cells_dict["triangle6"]
    sets = m.cell_sets_dict
    if body not in sets or "triangle6" not in sets[body]:
        raise ValueError(f"meshio mesh has no triangle6 physical group named {body!r}")
    tri = tri[sets[body]["triangle6"]]
    verts = np.unique(tri[:, :3])
    pts = np.asarray(m.points[:, :2], dtype=float)
    t = np.searchsorted(verts, tri[:, :3]).T.astype(np.int32)
    mesh = MeshTri1(np.ascontiguousarray(pts[verts].T), np.ascontiguousarray(t))
    # midside nodes of the triangles must be the edge midpoints (affine P2)
    for (i, j), k in (((0, 1), 3), ((1, 2), 4), ((2, 0), 5)):
        mid = 0.5 * (pts[tri[:, i]] + pts[tri[:, j]])
        err = np.max(np.abs(mid - pts[tri[:, k]]))
        scale = np.max(np.abs(pts))
        if err > 1e-9 * scale:
            raise ValueError(f"triangle6 midside nodes are not at edge midpoints (error {err:.3g} m): "
                             "the mesh is not straight-sided")
    keys, order = _facet_lookup(mesh)
    nv = mesh.p.shape[1]
    boundaries = {}
    prefix = f"{body}:"
    for name, cells in sets.items():
        if not name.startswith(prefix) or "line3" not in cells:
            continue
        lines = m.cells_dict["line3"][cells["line3"]]
        ends = np.searchsorted(verts, lines[:, :2])
        ok = (ends < verts.size) & (verts[np.minimum(ends, verts.size - 1)] == lines[:, :2])
        if not np.all(ok):
            raise ValueError(f"boundary {name!r} has vertices outside body {body!r}")
        e = np.sort(ends, axis=1).astype(np.int64)
        k = e[:, 0] * nv + e[:, 1]
        pos = np.searchsorted(keys, k)
        pos = np.minimum(pos, keys.size - 1)
        if not np.all(keys[pos] == k):
            raise ValueError(f"boundary {name!r}: line3 cells do not match facets of the triangles")
        mid = 0.5 * (pts[lines[:, 0]] + pts[lines[:, 1]])
        if np.max(np.abs(mid - pts[lines[:, 2]])) > 1e-9 * np.max(np.abs(pts)):
            raise ValueError(f"boundary {name!r}: line3 midside nodes off the edge midpoints")
        boundaries[name[len(prefix):]] = np.sort(order[pos]).astype(np.int32)
    return mesh.with_boundaries(boundaries)


def build_mesh(params: AxisymMeshParams) -> AxisymMesh:
    """Mesh from scratch (no cache): gmsh -> meshio -> skfem, per body."""
    p = params.resolved()
    m = generate_meshio(p)
    bodies = {b: from_meshio(m, b) for b in BODIES}
    return AxisymMesh(params=p, bodies=bodies)


# --------------------------------------------------------------------- export


def export_vtu(amesh: AxisymMesh, path, point_data=None):
    """Write both bodies as quadratic triangles (VTK triangle6) to ``path`` (.vtu), atomically.

    ``point_data``: ``{name: {body: array over the body's P2 nodes (n,) or (n, k)}}``
    in skfem's P2 DOF order (vertices, then facets). A ``body`` cell field
    (0 indenter, 1 block) is always written. Coordinates are (r, z, 0).
    """
    import meshio
    from skfem import Basis, ElementTriP2

    pts, cells, bodyid, pdata = [], [], [], {}
    offset = 0
    for i, name in enumerate(BODIES):
        mesh = amesh.bodies[name]
        basis = Basis(mesh, ElementTriP2(), intorder=1)
        xy = basis.doflocs
        pts.append(np.column_stack([xy.T, np.zeros(xy.shape[1])]))
        cells.append(basis.element_dofs.T + offset)
        bodyid.append(np.full(mesh.t.shape[1], i, dtype=np.int32))
        for key, per_body in (point_data or {}).items():
            pdata.setdefault(key, []).append(np.asarray(per_body[name], dtype=float))
        offset += xy.shape[1]
    out = meshio.Mesh(np.vstack(pts), [("triangle6", np.vstack(cells))],
                      point_data={k: np.concatenate(v) for k, v in pdata.items()},
                      cell_data={"body": [np.concatenate(bodyid)]})
    return write_vtu_atomic(out, path)

