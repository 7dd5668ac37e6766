"""3D half-model (y >= 0) of the block, meshed with gmsh tetrahedra (issue 13, first increment).

Geometry (z is the contact normal, the block below its top face z = 0, the
contact centred at the origin; all lengths in m):

- ``shape="cylinder"`` (default): the half (y >= 0) of a cylinder of radius
  ``size`` and height ``height`` (both default 20 ``a_ref``), i.e. the same
  block as the axisymmetric model of ``meshes.axisym`` cut along its symmetry
  plane, so the two models can be compared without a finite-body difference.
- ``shape="box"``: x in [-size, size], y in [0, size], z in [-height, 0].

The candidate contact zone is the half disk r <= ``contact_extent * a_ref``
(default 1.25 a_ref) of the top face, its own gmsh surface. ``edge`` (radius / a_ref,
optional) embeds the half circle r = edge * a_ref in it (the half disk is split into the
inner half disk and the annulus), so that vertices lie on the edge of a flat face, where
the gap has its kink and the pressure its singularity (truncated sphere, flat punch). Tetrahedra are
graded from ``h_min = h_contact * a_ref`` on that half disk to ``h_max`` far
away: a gmsh ``Distance`` field from the half disk and a ``Threshold`` field,
``h = h_min`` on the disk, growing linearly with the distance d,
``h = h_min + growth * d``, capped at ``h_max``.
Optionally (``refine_x``, ``refine_h``, ``refine_radius``) a ball around (refine_x, 0, 0) gets the
finer size ``refine_h`` (a gmsh ``MathEval`` distance and a second ``Threshold``, the smaller of
the two sizes wins through a ``Min`` field): the loaded edge of a tilted flat face, whose edge
contact is a narrow crescent.
Optionally (``band_h``, ``band_width``, ``band_angle``) a band along an arc of a circle of the top
face gets the finer size ``band_h``: within ``band_width`` of the circle r = ``band_r`` (default:
the edge circle r = edge * a_ref, the rim without an edge) on the arc |phi - pi| <= ``band_angle``
(the -x side; phi the polar angle in the top face), graded at ``band_growth`` (default ``growth``)
outside (a ``MathEval`` distance to the arc, a ``Threshold``, the finest size wins). Two uses: the
loaded edge of a flat face tilted far beyond its loss of full contact, whose edge contact is a
thin crescent along the rim (an arc of the edge circle); and, with band_angle = pi, the ring of
a partial-slip contact between the stick edge and the contact edge, the only place where a
fretting cycle's tractions change their state, so the rest of the disk can stay coarse.

Physical groups (names used by ``fem.solid3d.elastic``): surfaces ``contact`` (the
half disk), ``top`` (the rest of the top face), ``bottom`` (z = -height,
clamped), ``symmetry`` (y = 0), ``sides`` (the rest); volume ``block``.

Elements: linear tetrahedra from gmsh, returned as a skfem ``MeshTet1`` with
named boundaries (facet indices); the FE model puts P2 elements
(``ElementVector(ElementTetP2())``) on it, as the 2D code does with order-1
meshes: the map stays affine (exact low-order quadrature). On the curved side
of the cylinder and the rim of the disk the geometry is the faceted one.

Cache: like ``meshes.cache`` (SHA-256 of the resolved parameters, the format
version and gmsh's major.minor; ``.npz`` written atomically, verified on read),
file ``<cache_dir>/half3d-<key[:24]>.npz``.
"""
from __future__ import annotations

import hashlib
import json
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from common.errors import InputError

from .axisym import CONTACT_EXTENT_DEFAULT, GMSH_LOCK, ContactZoneParams
from .cache import _gmsh_version, cached_artifact, read_verified, write_verified

SHAPES = ("cylinder", "box")
GROUPS = ("contact", "top", "bottom", "symmetry", "sides")
#: bump when the geometry or the stored format changes (part of the cache key)
MESH3D_FORMAT_VERSION = 2
#: element size on the contact disk / a_ref: default and allowed range (3D meshes are coarser
#: than the 2D ones: a/10 already gives ~50k P2 DOFs)
H_CONTACT_3D_DEFAULT = 0.1
H_CONTACT_3D_RANGE = (1.0 / 200.0, 0.5)


def _number(v) -> bool:
    """One real number (no bool, no array)."""
    return not isinstance(v, bool) and isinstance(v, (int, float, np.integer, np.floating))


@dataclass(frozen=True)
class Half3DMeshParams(ContactZoneParams):
    """All parameters that determine a 3D half-model mesh (SI). Defaults via :meth:`resolved`.

    ``a_ref`` reference contact radius; ``h_contact`` element size on the
    contact disk as a fraction of it (range ``H_CONTACT_3D_RANGE``);
    ``contact_extent`` radius of the contact disk / a_ref in (1, 5];
    ``size`` block radius (cylinder) or half-width (box), ``height`` its depth
    (default 20 a_ref each, > 2 * contact_extent * a_ref); ``growth`` in
    [0.02, 1]; ``h_max`` far-field size (default size / 4, >= h_min); ``edge`` radius of
    an embedded half circle / a_ref in (0, contact_extent] (None: none; equal to
    contact_extent: the rim itself, nothing to embed). The contact extent may be 1 here
    (the flat punch: the candidate disk is the punch face). ``refine_x``, ``refine_h``,
    ``refine_radius`` (together or none; / a_ref): element size ``refine_h`` (<= h_contact) within
    the ball of radius ``refine_radius`` around (refine_x, 0, 0), |refine_x| <= contact_extent,
    graded at ``growth`` outside it (the loaded edge of a tilted flat face). ``band_h``, ``band_width``,
    ``band_angle`` (together or none): element size ``band_h`` (/ a_ref, <= h_contact)
    within ``band_width`` (/ a_ref, in (0, contact_extent]) of the circle r = ``band_r`` (/ a_ref, in
    (0, contact_extent]; None: the edge circle, or the rim r = contact_extent without an edge) on the
    arc |phi - pi| <= ``band_angle`` (rad, in (0, pi]; pi: the whole circle, a ring),
    graded at ``band_growth`` (in [0.02, 1]; None: ``growth``) outside (a thin edge crescent of a face
    tilted about y, lifted at +x; a steeper grading than the volume's keeps the interface small).
    ``None`` values are left out of :meth:`as_dict`, so the meshes without an edge, a refinement or
    a band keep their cache keys.
    """

    a_ref: float
    h_contact: float = H_CONTACT_3D_DEFAULT
    contact_extent: float = CONTACT_EXTENT_DEFAULT
    shape: str = "cylinder"
    size: float | None = None
    height: float | None = None
    growth: float = 0.3
    h_max: float | None = None
    edge: float | None = None
    refine_x: float | None = None
    refine_h: float | None = None
    refine_radius: float | None = None
    band_h: float | None = None
    band_width: float | None = None
    band_angle: float | None = None
    band_growth: float | None = None
    band_r: float | None = None

    def __post_init__(self):
        if self.shape not in SHAPES:
            raise InputError(f"shape must be one of {', '.join(SHAPES)}; got {self.shape!r}")
        self._check_zone(H_CONTACT_3D_RANGE, ("size", "height", "h_max"), extent_min_closed=True)
        if self.edge is not None and not (np.ndim(self.edge) == 0 and 0 < self.edge <= self.contact_extent):
            raise InputError(f"edge must be in (0, contact_extent = {self.contact_extent:g}] (the flat face's edge "
                             f"radius / a_ref inside the candidate disk), got {self.edge!r}")
        self._check_refine()
        self._check_band()

    def _check_band(self):
        if not self._together("band_h", "band_width", "band_angle"):
            for name in ("band_growth", "band_r"):
                if getattr(self, name) is not None:
                    raise InputError(f"{name} needs a band (band_h, band_width, band_angle), got "
                                     f"{getattr(self, name)!r}")
            return
        if not H_CONTACT_3D_RANGE[0] <= self.band_h <= self.h_contact:
            raise InputError(f"band_h must be in [{H_CONTACT_3D_RANGE[0]:g}, h_contact = {self.h_contact:g}] "
                             f"(element size in the band / a_ref), got {self.band_h!r}")
        if not 0 < self.band_width <= self.contact_extent:
            raise InputError(f"band_width must be in (0, contact_extent = {self.contact_extent:g}] (half width of "
                             f"the band about its circle / a_ref), got {self.band_width!r}")
        if not 0 < self.band_angle <= np.pi:
            raise InputError(f"band_angle must be in (0, pi] (half angle of the band's arc about phi = pi, rad), "
                             f"got {self.band_angle!r}")
        br = self.band_r
        if br is not None and not (_number(br) and 0 < br <= self.contact_extent):
            raise InputError(f"band_r must be in (0, contact_extent = {self.contact_extent:g}] (radius of the band's "
                             f"circle / a_ref) or None (the edge circle), got {br!r}")
        g = self.band_growth
        if g is not None and not (_number(g) and 0.02 <= g <= 1):
            raise InputError(f"band_growth must be in [0.02, 1] (size growth per unit distance outside the band) "
                             f"or None, got {g!r}")

    def _together(self, *names) -> bool:
        """Whether the option group ``names`` is given: all None (False) or all finite numbers (True),
        else InputError naming the parameter."""
        vals = tuple(getattr(self, n) for n in names)
        if all(v is None for v in vals):
            return False
        if any(v is None for v in vals):
            raise InputError(f"{', '.join(names[:-1])} and {names[-1]} go together (all given or none), got {vals!r}")
        for name, v in zip(names, vals):
            if not (_number(v) and np.isfinite(v)):
                raise InputError(f"{name} must be one finite number, got {v!r}")
        return True

    def _check_refine(self):
        if not self._together("refine_x", "refine_h", "refine_radius"):
            return
        ce = self.contact_extent
        if not (np.ndim(self.refine_x) == 0 and np.isfinite(self.refine_x) and abs(self.refine_x) <= ce):
            raise InputError(f"refine_x must be in [-{ce:g}, {ce:g}] (x of the refined spot / a_ref, inside the "
                             f"candidate disk), got {self.refine_x!r}")
        if not (np.ndim(self.refine_h) == 0 and H_CONTACT_3D_RANGE[0] <= self.refine_h <= self.h_contact):
            raise InputError(f"refine_h must be in [{H_CONTACT_3D_RANGE[0]:g}, h_contact = {self.h_contact:g}] "
                             f"(element size at the refined spot / a_ref), got {self.refine_h!r}")
        if not (np.ndim(self.refine_radius) == 0 and 0 < self.refine_radius <= 2 * ce):
            raise InputError(f"refine_radius must be in (0, 2 contact_extent = {2 * ce:g}] (radius of the refined "
                             f"ball / a_ref), got {self.refine_radius!r}")

    def resolved(self) -> "Half3DMeshParams":
        L = self.size if self.size is not None else 20.0 * self.a_ref
        H = self.height if self.height is not None else L
        hmax = self.h_max if self.h_max is not None else max(L, H) / 4.0
        p = Half3DMeshParams(float(self.a_ref), float(self.h_contact), float(self.contact_extent),
                             self.shape, float(L), float(H), float(self.growth), float(hmax),
                             None if self.edge is None else float(self.edge),
                             *(None if v is None else float(v)
                               for v in (self.refine_x, self.refine_h, self.refine_radius,
                                         self.band_h, self.band_width, self.band_angle, self.band_growth,
                                         self.band_r)))
        rc = p.r_contact
        if p.size <= 2.0 * rc:
            raise InputError(f"size must be > 2 * contact_extent * a_ref = {2 * rc:.4g} m, got {p.size!r}")
        if p.height <= 2.0 * rc:
            raise InputError(f"height must be > 2 * contact_extent * a_ref = {2 * rc:.4g} m, got {p.height!r}")
        p._check_h_max()
        return p

    @property
    def r_edge(self) -> float | None:
        """Radius of the embedded half circle (m), None without one or when it is the rim."""
        if self.edge is None or self.edge >= self.contact_extent * (1 - 1e-12):
            return None
        return self.edge * self.a_ref

    def as_dict(self) -> dict:
        d = asdict(self)
        for k in ("edge", "refine_x", "refine_h", "refine_radius", "band_h", "band_width", "band_angle",
                  "band_growth", "band_r"):
            if d[k] is None:
                del d[k]
        return d


@dataclass(frozen=True)
class Refinement:
    """The local refinements of a 3D half-model mesh as a user names them (lengths / a_ref), checked
    for shape once here and for range by :class:`Half3DMeshParams` (:meth:`mesh_fields`).

    ``refine``: None or (x, h, radius), element size h within the ball of that radius around
    (x, 0, 0) (the loaded edge of a tilted flat face); ``ring``: None or (r, width, h), element size
    h within ``width`` of the circle of radius r on the contact face, the whole circle (the slip
    annulus and contact edge of a partial-slip cycle); ``band``: None or (h, width, angle[, growth]),
    element size h within ``width`` of the flat face's edge circle on the arc |phi - pi| <= angle,
    graded at ``growth`` outside (a thin edge crescent). A ring is a band around a whole circle, so
    ``ring`` and ``band`` exclude each other. The values are kept as given (the mesh's cache key
    is built from them).
    """

    refine: tuple | None = None
    ring: tuple | None = None
    band: tuple | None = None

    def __post_init__(self):
        if self.refine is not None:
            if np.ndim(self.refine) != 1 or np.size(self.refine) != 3:
                raise InputError(f"refine must be None or (x, h, radius) / a_ref (the refined ball of the mesh), "
                                 f"got {self.refine!r}")
            object.__setattr__(self, "refine", tuple(self.refine))
        if self.ring is not None:
            if self.band is not None:
                raise InputError("give ring or band, not both (a ring is the band around a whole circle)")
            if np.ndim(self.ring) != 1 or np.size(self.ring) != 3:
                raise InputError(f"ring must be None or (r, width, h) / a_ref (the refined ring of the mesh), got "
                                 f"{self.ring!r}")
            object.__setattr__(self, "ring", tuple(self.ring))
        if self.band is not None:
            if np.ndim(self.band) != 1 or np.size(self.band) not in (3, 4):
                raise InputError(f"band must be None or (h / a_ref, width / a_ref, angle in rad[, growth]) (the "
                                 f"refined band along the loaded edge), got {self.band!r}")
            object.__setattr__(self, "band", tuple(self.band))

    def mesh_fields(self) -> dict:
        """The keywords of :class:`Half3DMeshParams` this refinement sets (``refine_*``, ``band_*``)."""
        x, h, radius = self.refine if self.refine is not None else (None, None, None)
        band = tuple(self.band or ()) + (None,) * (4 - len(self.band or ()))
        band_r = None
        if self.ring is not None:  # the band around the whole circle r
            band_r, band = self.ring[0], (self.ring[2], self.ring[1], np.pi, None)
        return {"refine_x": x, "refine_h": h, "refine_radius": radius, "band_h": band[0], "band_width": band[1],
                "band_angle": band[2], "band_growth": band[3], "band_r": band_r}


@dataclass
class Half3DMesh:
    """skfem ``MeshTet1`` with boundaries ``contact, top, bottom, symmetry, sides``."""

    params: Half3DMeshParams
    mesh: object
    key: str = ""
    info: dict = field(default_factory=dict)

    def summary(self) -> dict:
        m = self.mesh
        return {"params": self.params.as_dict(), "key": self.key, "vertices": int(m.p.shape[1]),
                "elements": int(m.t.shape[1]), "p2_nodes": int(m.p.shape[1] + m.edges.shape[1])}


# --------------------------------------------------------------------- gmsh


def _classify(p: Half3DMeshParams, bb):
    """Name of a boundary surface of the block from its bounding box."""
    tol = 1e-6 * p.size
    xmin, ymin, zmin, xmax, ymax, zmax = bb
    if abs(zmax) < tol and abs(zmin) < tol:
        return "contact" if max(abs(xmin), abs(xmax), abs(ymax)) <= p.r_contact + tol else "top"
    if abs(zmax + p.height) < tol and abs(zmin + p.height) < tol:
        return "bottom"
    if abs(ymax) < tol and abs(ymin) < tol:
        return "symmetry"
    return "sides"


def _size_field(gmsh, p: Half3DMeshParams, contact) -> None:
    """The element size as gmsh's background field: ``h_min`` on the ``contact`` surfaces growing to
    ``h_max``, the finer of that and the refined ball around (``refine_x``, 0, 0) and the rim's band."""
    fm = gmsh.model.mesh.field
    dist = fm.add("Distance")
    fm.setNumbers(dist, "SurfacesList", contact)
    fm.setNumber(dist, "Sampling", int(2 * p.r_contact / p.h_min) + 20)
    thr = fm.add("Threshold")
    fm.setNumber(thr, "InField", dist)
    fm.setNumber(thr, "SizeMin", p.h_min)
    fm.setNumber(thr, "SizeMax", p.h_max)
    fm.setNumber(thr, "DistMin", 0.0)
    fm.setNumber(thr, "DistMax", (p.h_max - p.h_min) / p.growth)
    if p.refine_x is not None:  # the refined ball around (refine_x, 0, 0), the finer size wins
        ball = fm.add("MathEval")
        fm.setString(ball, "F", f"Sqrt((x - ({p.refine_x!r}))^2 + y^2 + z^2)")
        thr2 = fm.add("Threshold")
        fm.setNumber(thr2, "InField", ball)
        fm.setNumber(thr2, "SizeMin", p.refine_h)
        fm.setNumber(thr2, "SizeMax", p.h_max)
        fm.setNumber(thr2, "DistMin", p.refine_radius)
        fm.setNumber(thr2, "DistMax", p.refine_radius + (p.h_max - p.refine_h) / p.growth)
        both = fm.add("Min")
        fm.setNumbers(both, "FieldsList", [thr, thr2])
        thr = both
    if p.band_h is not None:  # the band along the arc |phi - pi| <= band_angle of the circle r = rb
        rb = p.band_r if p.band_r is not None else p.edge if p.edge is not None else p.contact_extent
        band = fm.add("MathEval")  # distance to the arc: radial, normal and (beyond its ends) along it
        fm.setString(band, "F", f"Sqrt((Sqrt(x^2 + y^2) - {rb!r})^2 + z^2 + ({rb!r} * Max(0, "
                                f"Acos(-x / (Sqrt(x^2 + y^2) + 1e-12)) - {p.band_angle!r}))^2)")
        thr3 = fm.add("Threshold")
        fm.setNumber(thr3, "InField", band)
        fm.setNumber(thr3, "SizeMin", p.band_h)
        fm.setNumber(thr3, "SizeMax", p.h_max)
        fm.setNumber(thr3, "DistMin", p.band_width)
        gb = p.growth if p.band_growth is None else p.band_growth
        fm.setNumber(thr3, "DistMax", p.band_width + (p.h_max - p.band_h) / gb)
        both = fm.add("Min")
        fm.setNumbers(both, "FieldsList", [thr, thr3])
        thr = both
    fm.setAsBackgroundMesh(thr)


def _generate(p: Half3DMeshParams):
    """Run gmsh; return (points (3, n), tets (4, m), {group: boundary triangles (k, 3)}) in gmsh node
    order (compacted to the used nodes). gmsh runs in units of ``a_ref`` and the points are scaled back to metres: OpenCASCADE pads
    bounding boxes by an absolute tolerance (about 1e-7), larger than a micrometre contact
    would allow the surface classification."""
    unit = p.a_ref
    p = replace(p, a_ref=1.0, size=p.size / unit, height=p.height / unit, h_max=p.h_max / unit)
    try:
        import gmsh
    except OSError as exc:  # pragma: no cover - depends on the machine image
        raise RuntimeError(f"gmsh could not load a system library ({exc})") from exc
    L, H, rc = p.size, p.height, p.r_contact
    with GMSH_LOCK:
        gmsh.initialize(argv=["fretting"], readConfigFiles=False, interruptible=False)
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.model.add("half3d")
            occ = gmsh.model.occ
            if p.shape == "cylinder":
                cyl = occ.addCylinder(0, 0, -H, 0, 0, H, L)
                cut = occ.addBox(-2 * L, -2 * L, -2 * H, 4 * L, 2 * L, 4 * H)
                (vol,), _ = occ.cut([(3, cyl)], [(3, cut)])
            else:
                vol = (3, occ.addBox(-L, 0, -H, 2 * L, L, H))
            disk = occ.addDisk(0, 0, 0, rc, rc)
            cut2 = occ.addRectangle(-2 * rc, -2 * rc, 0, 4 * rc, 2 * rc)
            (hdisk,), _ = occ.cut([(2, disk)], [(2, cut2)])
            tools = [hdisk]
            if p.r_edge is not None:  # the inner half disk r <= edge: splits the contact half disk
                inner = occ.addDisk(0, 0, 0, p.r_edge, p.r_edge)
                cut3 = occ.addRectangle(-2 * rc, -2 * rc, 0, 4 * rc, 2 * rc)
                (hin,), _ = occ.cut([(2, inner)], [(2, cut3)])
                tools.append(hin)
            occ.fragment([vol], tools)
            occ.synchronize()
            vols = gmsh.model.getEntities(3)
            if len(vols) != 1:
                raise RuntimeError(f"gmsh geometry: expected one volume, got {len(vols)}")
            groups = {g: [] for g in GROUPS}
            for dim, tag in gmsh.model.getBoundary(vols, oriented=False):
                bb = gmsh.model.getBoundingBox(dim, tag)
                groups[_classify(p, bb)].append(tag)
            missing = [g for g in GROUPS if not groups[g]]
            if missing:
                raise RuntimeError(f"gmsh geometry: no surface classified as {missing}")
            for g, tags in groups.items():
                gmsh.model.setPhysicalName(2, gmsh.model.addPhysicalGroup(2, tags), g)
            gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [vols[0][1]]), "block")
            _size_field(gmsh, p, groups["contact"])
            for opt, val in (("Mesh.MeshSizeExtendFromBoundary", 0), ("Mesh.MeshSizeFromPoints", 0),
                             ("Mesh.MeshSizeFromCurvature", 0), ("Mesh.Algorithm", 6),
                             ("Mesh.Algorithm3D", 1), ("Mesh.ElementOrder", 1),
                             ("Mesh.Optimize", 1), ("General.NumThreads", 1)):
                gmsh.option.setNumber(opt, val)
            gmsh.model.mesh.generate(3)
            tags, coords, _ = gmsh.model.mesh.getNodes()
            coords = coords.reshape(-1, 3)
            _, etags, enodes = gmsh.model.mesh.getElements(3, vols[0][1])
            tets = np.asarray(enodes[0], dtype=np.int64).reshape(-1, 4)
            tris = {}
            for g, stags in groups.items():
                parts = []
                for s in stags:
                    types, _, nodes = gmsh.model.mesh.getElements(2, s)
                    for ty, nd in zip(types, nodes):
                        if ty != 2:
                            raise RuntimeError(f"unexpected surface element type {ty}")
                        parts.append(np.asarray(nd, dtype=np.int64).reshape(-1, 3))
                tris[g] = np.vstack(parts)
        finally:
            gmsh.finalize()
    # compact gmsh tags -> 0..n-1 over the nodes used by tetrahedra
    tagpos = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    tagpos[np.asarray(tags, dtype=np.int64)] = np.arange(tags.size)
    used = np.unique(tets)
    newidx = np.full(tagpos.size, -1, dtype=np.int64)
    newidx[used] = np.arange(used.size)
    pts = coords[tagpos[used]].T
    t = newidx[tets].T
    tris = {g: newidx[v] for g, v in tris.items()}
    for g, v in tris.items():
        if np.any(v < 0):
            raise RuntimeError(f"boundary {g!r} has nodes outside the tetrahedra")
    return np.ascontiguousarray(pts * unit), np.ascontiguousarray(t, dtype=np.int32), tris


def _facet_keys(tri, nv):
    s = np.sort(np.asarray(tri, dtype=np.int64), axis=-1)
    return (s[..., 0] * nv + s[..., 1]) * nv + s[..., 2]


def to_skfem(pts, t, tris):
    """``MeshTet1`` with named boundaries from triangles given by vertex triples."""
    from skfem import MeshTet1

    mesh = MeshTet1(pts, t)
    nv = mesh.p.shape[1]
    if nv >= 2_000_000:  # pragma: no cover - key would overflow int64
        raise InputError(f"mesh too large for the facet lookup ({nv} vertices, at most 2e6)")
    fkeys = _facet_keys(mesh.facets.T, nv)
    order = np.argsort(fkeys)
    sk = fkeys[order]
    bnd = {}
    for g, tri in tris.items():
        k = _facet_keys(tri, nv)
        pos = np.minimum(np.searchsorted(sk, k), sk.size - 1)
        if not np.all(sk[pos] == k):
            raise RuntimeError(f"boundary {g!r}: triangles do not match facets of the tetrahedra")
        bnd[g] = np.sort(order[pos]).astype(np.int32)
    return mesh.with_boundaries(bnd)


def build_mesh3d(params: Half3DMeshParams) -> Half3DMesh:
    """Mesh from scratch (no cache)."""
    p = params.resolved()
    pts, t, tris = _generate(p)
    return Half3DMesh(params=p, mesh=to_skfem(pts, t, tris))


# --------------------------------------------------------------------- cache


def mesh3d_key(params: Half3DMeshParams) -> str:
    p = params.resolved()
    blob = json.dumps({"params": p.as_dict(), "format": MESH3D_FORMAT_VERSION, "gmsh": _gmsh_version(),
                       "kind": "half3d"}, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(blob.encode()).hexdigest()


def _arrays(hm: Half3DMesh) -> dict:
    m = hm.mesh
    arrs = {"p": np.ascontiguousarray(m.p, dtype=np.float64), "t": np.ascontiguousarray(m.t, dtype=np.int32)}
    for name, facets in sorted(m.boundaries.items()):
        # stored as vertex triples: facet numbering is skfem's, the triples are not
        arrs[f"boundary/{name}"] = np.ascontiguousarray(m.facets[:, facets].T, dtype=np.int32)
    return arrs


def save_mesh3d(hm: Half3DMesh, path) -> Path:
    return write_verified(path, {"params": hm.params.as_dict(), "key": hm.key, "format": MESH3D_FORMAT_VERSION,
                                 "info": {k: v for k, v in hm.info.items() if k != "cache"}}, _arrays(hm))


def load_mesh3d(path, expected: Half3DMeshParams | None = None) -> Half3DMesh:
    """Read and verify a cached 3D mesh; :class:`meshes.cache.CacheError` if anything is off."""
    header, arrs, params = read_verified(path, MESH3D_FORMAT_VERSION, "half3d mesh", Half3DMeshParams, expected)
    tris = {k.split("/", 1)[1]: v for k, v in arrs.items() if k.startswith("boundary/")}
    mesh = to_skfem(arrs["p"], arrs["t"], tris)
    return Half3DMesh(params=params, mesh=mesh, key=header.get("key", ""), info=header.get("info", {}))


def cached_mesh3d(params: Half3DMeshParams, cache_dir=None, *, refresh: bool = False) -> Half3DMesh:
    """The mesh for ``params`` from the cache if valid, else built and stored.

    ``info["cache"]``: ``hit``, ``miss``, ``rebuilt`` or ``unsaved`` (as ``meshes.cache.cached_mesh``).
    """
    return cached_artifact(params, cache_dir, refresh, prefix="half3d", key_of=mesh3d_key, load=load_mesh3d,
                           build=build_mesh3d, save=save_mesh3d)
