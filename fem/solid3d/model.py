"""The 3D half model of one contact pair, built once and then only read (``build_model3d``).

What is built (the assumptions are those of ``fem.solid3d.law``'s module docstring):

- the mesh: the graded half cylinder of ``meshes.half3d`` (radius and height ``block_size``,
  default ``BLOCK_SIZE_DEFAULT`` a_ref, a_ref the half-space contact radius at F_max; the flat
  punch: its radius b), cached on disk;
- the mortar interface of the contact half disk (``fem.solid3d.interface``) and each body's
  condensed flexibility at its P1 traction vertices (``fem.solid3d.condensed``, cached on disk beside
  the mesh), combined into the pair's relative flexibilities (``RelativeFlexibility``);
- the axis probes of the contact measure (``fem.bulk`` in 3D): per-vertex bulk corrections and the
  series compliance ``c_bulk`` at F_max, weighted by the full-stick x tractions of the aligned contact
  (the flat punch: its whole face);
- the profile as a weighted gap in the P2 space (exact for the parabola), the weighted gap of a
  unit tilt, and the vertex sets the estimators read (the rays of the stick zone, the contact
  facets' adjacency, the rim).

A model knows nothing of friction, of the traction's direction, of the tilt or of any load history:
those belong to the law (``fem.solid3d.law.FEContact3D``), so one model serves every law built on it
(``FEContact3D.assuming``).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
import scipy.sparse as sp

from common.errors import ConvergenceError, positive
from mdr.materials import Materials
from mdr.profiles import FlatPunch, Profile
from meshes.half3d import Half3DMesh, Half3DMeshParams, Refinement, cached_mesh3d

from fem.axisym.normal_run import reference_radius
from fem.bulk import DEFAULT_PROBE_DEPTH, boussinesq_point_z, cerruti_point_x
from fem.solid3d.condensed import condensed_body
from fem.solid3d.contact import WHOLE, RelativeFlexibility, solve_normal3d
from fem.solid3d.interface import hat_integrals, mortar_interface
from fem.solvers import blas_threads

#: half-angle of the vertex sector around the y axis that resolves the stick extent along y (rad)
SECTOR = np.deg2rad(12.0)
#: default block radius and height / a_ref (the Cerruti mean shear of a 20 a block is +3 %
#: of the half-space's; it is a series compliance, see ``fem.solid3d.law``)
BLOCK_SIZE_DEFAULT = 20.0


@dataclass(frozen=True, eq=False)
class Model3D:
    """The built 3D half model (``build_model3d``); read only.

    ``rf``: the relative flexibilities in the law's displacement measure (``displacement``: "plate",
    or "contact", the bodies' series compliance taken out of Dt); ``Dt_plate`` the tangential one of
    the plate measure; ``bulk``: the axis probes' per-vertex corrections (``depth`` m, ``x`` and
    ``z`` (n,) m/Pa); ``c_bulk`` (m/N) the series compliance; ``beta`` Dundurs' second constant
    (Dundurs 1969, J. Appl. Mech. 36, 650), positive when the block (body 2) is the more compressible
    one (steel on aluminium: +0.11); ``gap0_aligned`` (n,) the weighted gap of the aligned profile,
    ``gap_tilt`` (n,) that of a unit tilt (theta x); ``plane`` the vertices on the symmetry plane by
    increasing x; ``rays`` the stick rays "+x", "-x" (on the plane) and "y" (within ``SECTOR``),
    ``ys`` the vertices of the y sector; ``adj`` the contact facets' vertex adjacency; ``rim`` the
    vertices on the candidate disk's rim; ``timings`` (s): mesh, setup and its parts;
    ``normal_at_F_max``: the aligned normal solution at F_max that set ``c_bulk`` (``normal_solution``'s
    tuple; None for the flat punch without F_max)."""

    profile: Profile
    materials: Materials
    flat: bool
    F_max: float | None
    a_ref: float
    refinement: Refinement
    hmesh: Half3DMesh
    mi: object
    rf: RelativeFlexibility
    Dt_plate: np.ndarray
    bulk: dict
    c_bulk: float
    beta: float
    gap0_aligned: np.ndarray
    gap_tilt: np.ndarray
    plane: np.ndarray
    rays: dict
    ys: np.ndarray
    adj: sp.csr_matrix
    rim: np.ndarray
    displacement: str
    backend: str
    ndofs: int
    condensed: dict
    timings: dict
    normal_at_F_max: tuple | None = None

    @property
    def n(self) -> int:
        """The number of traction vertices."""
        return self.mi.n

    def gap(self, tilt: float) -> np.ndarray:
        """The weighted initial gap (n,) of the face tilted by ``tilt`` (rad; small slopes)."""
        return self.gap0_aligned + tilt * self.gap_tilt

    @cached_property
    def r2_hat(self) -> np.ndarray:
        """int phi_j r^2 dA of every vertex hat (m^4), for the pressure's second moment."""
        return hat_integrals(self.hmesh.mesh, self.mi, lambda x, y: x * x + y * y)

    def check_rim(self, p):
        """A contact that reaches the rim of the meshed contact disk is an error, never a silent
        truncation (the flat punch: its rim is the punch edge, where contact belongs)."""
        if self.flat:
            return
        rim = float(self.mi.r.max())
        if np.any(p[self.mi.r >= 0.999 * rim] > 0):
            raise ConvergenceError(f"the contact reaches the rim of the contact disk (r = {rim:.4g} m): raise "
                                   "contact_extent")

    def stick_x_compliance(self, c) -> float:
        """c_bulk (m/N, plate measure) weighted by the full-stick x tractions on the vertices ``c``
        (the contact): the axis probes' x correction over twice the tractions' force. The y
        tractions' share is left out (at most the traction angle, ~0.1, times a term odd in y that
        the mirror halves cancel to leading order)."""
        mi = self.mi
        q = np.linalg.solve(self.Dt_plate[:mi.n, :mi.n][np.ix_(c, c)], mi.A[c])
        return float(self.bulk["x"][c] @ q / (WHOLE * mi.A[c] @ q))


def _bulk_rows(hmesh, mi, materials: Materials, depth, R_blk, R_ind) -> dict:
    """Per-vertex bulk corrections of the axis probes at ``depth`` in both bodies (``fem.bulk`` in 3D):
    FE probe reading minus the half-space's (Cerruti, Boussinesq; the half model's vertex hats
    doubled by their mirror images). ``x`` (n,): x displacement of the indenter's probe relative to
    the block's per unit x traction field phi_j on the block, both bodies' parts (m/Pa); ``z`` (n,):
    both bodies' compression between clamp and probe per unit pressure field (m/Pa)."""
    m, mesh = materials, hmesh.mesh
    out = {"depth": depth, "x": np.zeros(mi.n), "z": np.zeros(mi.n)}
    for R, E, nu in ((R_blk, m.E2, m.nu2), (R_ind, m.E1, m.nu1)):
        G = E / (2.0 * (1.0 + nu))
        out["x"] += R[0, 0] - 2.0 * hat_integrals(mesh, mi, lambda x, y: cerruti_point_x(x, y, depth, G, nu))
        out["z"] += R[2, 2] - 2.0 * hat_integrals(mesh, mi, lambda x, y: boussinesq_point_z(x, y, depth, G, nu))
    return out


def _vertex_sets(mesh, mi) -> dict:
    """The vertex sets the estimators read: the symmetry plane by increasing x, the stick rays, the y
    sector, the contact facets' adjacency and the rim."""
    plane = np.flatnonzero(mi.on_plane)[np.argsort(mi.x[mi.on_plane])]
    xp = np.flatnonzero(mi.on_plane & (mi.x >= 0))
    xm = np.flatnonzero(mi.on_plane & (mi.x <= 0))
    phi = np.arctan2(mi.y, mi.x)
    ys = np.flatnonzero((np.abs(phi - np.pi / 2) <= SECTOR) | (mi.r == 0))
    rays = {"+x": xp[np.argsort(mi.x[xp])], "-x": xm[np.argsort(-mi.x[xm])], "y": ys[np.argsort(mi.r[ys])]}
    tri = np.searchsorted(mi.vertices, mesh.facets[:, mesh.boundaries["contact"]])  # (3, k) vertex positions
    e = np.concatenate([tri[[0, 1]], tri[[1, 2]], tri[[2, 0]]], axis=1)
    adj = sp.coo_matrix((np.ones(e.shape[1]), (e[0], e[1])), shape=(mi.n, mi.n)).tocsr()
    rim = mi.r >= (1 - 1e-6) * float(mi.r.max())
    return {"plane": plane, "rays": rays, "ys": ys, "adj": adj, "rim": rim}


def build_model3d(profile: Profile, materials: Materials, *, F_max, h_contact, contact_extent, block_size,
                  refinement: Refinement, displacement: str, cache_dir=None, backend=None) -> Model3D:
    """The 3D half model of ``profile`` on ``materials`` (parameters checked by the caller, the law's
    edge): mesh, interface, condensed bodies, probes, gaps and vertex sets. ``F_max`` (N) sizes the
    mesh (None for the flat punch: a_ref = b) and sets ``c_bulk``."""
    m = materials
    flat = isinstance(profile, FlatPunch)
    desc = profile.describe()
    b = float(desc.get("b") or 0.0)
    a_ref = reference_radius(desc["profile"], desc.get("R"), b, F_max, m.E_star)
    L = BLOCK_SIZE_DEFAULT * a_ref if block_size is None else float(positive("block_size", block_size))
    t0 = time.perf_counter()
    edge = b / a_ref if b > 0 and not flat else None  # the flat face's edge: a circle of the mesh
    params = Half3DMeshParams(a_ref=a_ref, h_contact=h_contact, contact_extent=contact_extent, size=L, height=L,
                              edge=edge, **refinement.mesh_fields())
    hmesh = cached_mesh3d(params, cache_dir)
    mesh = hmesh.mesh
    t1 = time.perf_counter()
    mi = mortar_interface(mesh)
    parts = {"assembly": time.perf_counter() - t1}
    # the axis probes of the contact measure: as shallow as in the axisymmetric law, below the contact
    # disk (inside the bodies: the mesh is deeper than 2 contact_extent a_ref)
    zp = max(DEFAULT_PROBE_DEPTH, contact_extent + 0.25) * a_ref
    # each body's condensed interface (for E = 1 Pa: scaled by 1/E), cached on disk beside the mesh
    blk = condensed_body(hmesh, mi, m.nu2, zp, backend=backend, cache_dir=cache_dir, timings=parts)
    ndofs = blk.ndofs
    D_blk, R_blk = blk.D / m.E2, blk.R / m.E2
    condensed = {"block": {"cache": blk.info.get("cache"), "key": blk.key}}
    if m.nu1 == m.nu2:  # the flexibility of one mesh scales with 1/E at fixed nu
        D_ind, R_ind = blk.D / m.E1, blk.R / m.E1
    else:
        ind = condensed_body(hmesh, mi, m.nu1, zp, backend=backend, cache_dir=cache_dir, timings=parts)
        D_ind, R_ind = ind.D / m.E1, ind.R / m.E1
        condensed["indenter"] = {"cache": ind.info.get("cache"), "key": ind.key}
        ndofs *= 2
    rf = RelativeFlexibility.from_bodies(D_blk, D_ind)
    if flat:  # every node of the candidate disk (the punch face, its faceted rim included) is on the face
        f = np.zeros(mi.nodes.m)
    else:
        with np.errstate(invalid="ignore"):
            f = np.asarray(profile.f(mi.nodes.r), dtype=float)
    plate = Model3D(profile=profile, materials=m, flat=flat, F_max=F_max, a_ref=a_ref, refinement=refinement,
                    hmesh=hmesh, mi=mi, rf=rf, Dt_plate=rf.Dt, bulk=_bulk_rows(hmesh, mi, m, zp, R_blk, R_ind),
                    c_bulk=float("nan"), beta=m.dundurs_beta,
                    gap0_aligned=mi.B @ f,  # the profile in the P2 space, weighted by the P1 hats
                    gap_tilt=mi.B @ mi.nodes.x,  # the weighted gap of a unit tilt, theta x (exact in the P2 space)
                    **_vertex_sets(mesh, mi), displacement=displacement, backend=blk.params.backend, ndofs=ndofs,
                    condensed=condensed, timings={})
    # the bodies' series compliance (m/N) at F_max (the flat punch: its face): plate = contact + c_bulk F_x
    seed = None
    if F_max is not None:
        seed = normal_solution(plate, plate.gap0_aligned, F_N=F_max)
        c_bulk = plate.stick_x_compliance(seed[0] > 0)
    else:
        c_bulk = plate.stick_x_compliance(np.ones(mi.n, dtype=bool))
    if displacement == "contact":  # u measured without it: s = u_c A e_x - (Dt - 2 c_bulk A A^T) q
        Dt = rf.Dt.copy()
        Dt[:mi.n, :mi.n] -= WHOLE * c_bulk * np.outer(mi.A, mi.A)
        rf = RelativeFlexibility(Dn=rf.Dn, Dt=Dt, K=rf.K)
    # seconds: mesh (gmsh or the cache), setup (all after the mesh), of which assembly (the mortar
    # matrix), factorisation and condensation (``fem.solid3d.interface.mortar_flexibility``, both bodies)
    timings = {"mesh": t1 - t0, "setup": time.perf_counter() - t1, **parts}
    return replace(plate, rf=rf, c_bulk=c_bulk, normal_at_F_max=seed, timings=timings)


def normal_solution(model: Model3D, gap0, *, F_N=None, d=None) -> tuple:
    """The frictionless normal contact of the weighted gap ``gap0`` at full-body force F_N or plate
    approach d: (vertex pressures p, plate approach, iterations); a contact reaching the rim of the
    candidate disk is an error (``Model3D.check_rim``)."""
    with blas_threads(1):
        p, dd, _, it = solve_normal3d(model.rf.Dn, gap0, model.mi.A, force=None if F_N is None else F_N / WHOLE,
                                      approach=d)
    model.check_rim(p)
    return p, float(dd), it
