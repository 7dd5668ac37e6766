"""The 3D FE contact law: the contact-law protocol of ``mdr.protocol`` on the 3D half model.

Where the axisymmetric law (``fem.axisym.law.FEContact``) assumes with Mindlin that the tangential
traction points along x and that the pressure does not feel the tangential load, this law
solves the contact on the 3D half model (y >= 0) with a two-component traction of free
direction (``fem.solid3d.contact``), so both assumptions become results.

Model (assumptions, each stated where it lives):

- block: the graded half cylinder of ``meshes.half3d`` (radius and height ``block_size``,
  default 20 a_ref), P2 tetrahedra, bottom clamped, u_y = 0 on the symmetry plane
  (``fem.solid3d.elastic``), condensed to the P1 traction vertices of the contact half disk
  (``fem.solid3d.interface``, mortar pairing);
- indenter: the block's mirror image (z -> -z) with the indenter's elastic constants, so
  both contact faces are flat and the profile (sphere, truncated sphere) enters as the
  initial gap, interpolated in the P2 space (exact for the parabola). What this leaves out,
  the cap's curvature and the indenter's real shape and size, the axisymmetric model
  measures (README: validity-curvature, validity). The edge r = b of a truncated sphere's
  flat face is a circle of the mesh (``meshes.half3d``, ``edge``). The flat punch of
  radius b: the candidate disk is the punch face r <= b (a_ref = b, contact_extent 1, its
  rim the punch edge), zero gap on it; outside it the two faces are free surfaces (both
  bodies large against b, as in the half-space theory of the punch);
- tilt theta (rad, |theta| <= ``TILT_MAX``): the indenter rotated rigidly about the y axis
  through the centre of its face, the rotation prescribed (held by the mount, the moment
  reacted) and the load line through the face centre. Small slopes: the gap gains the
  linear term theta * x (theta > 0 lifts the +x side), the half model's symmetry about
  y = 0 is kept. The plate displacements do not contain the rigid rotation;
- any pair of isotropic elastic materials: for identical ones (Dundurs' beta = 0) the
  normal-tangential coupling of the two bodies cancels exactly and the normal contact is
  solved once per load; for a dissimilar pair the two are solved together at every step
  (``fem.solid3d.contact.solve_coupled3d``), so a tangential load moves the pressure and a normal
  load with friction locks tangential traction in (Spence 1975, J. Elasticity 5, 297);
- small sliding, quasi-static, rate-independent Coulomb friction with constant mu.

Displacement measure (``displacement``), as in ``fem.axisym.law``: "contact" (the command's default) the half-space
comparable tangential displacement, the plate displacement minus the bodies' series compliance
c_bulk F_x read at axis probes in both bodies and put back with Cerruti's half-space solution
(``fem.bulk``; here the probes' responses to every traction vertex, ``_bulk_rows``); "plate" the
displacement of the indenter's clamped top against the block's clamped bottom (the law's
default, as ``fem.axisym.law.FEContact``'s). Under force
control the loop area (dissipation), the stick zone and the force history do not depend on it
(a series spring is a shear of the loop plane). The approach ``d`` is the plate approach in
both; ``indentation`` (a result key) is its half-space comparable counterpart (Boussinesq).
The probes see the finite block's bending under F_x, which no half-space has. Measured (the
sphere, full stick, h = a/4): the contact measure's stiffness is 0.977, 0.980, 0.981 of
Mindlin's 2 G* a on blocks of 10, 20, 40 a (the rest is the mesh error), the plate measure's
0.908, 0.943, 0.962 (``tests/test_contact3d.py``: 10 a and 20 a).

Stick zone (``mdr.stick``, onset 1/2 as for any traction): along the x axis from the
vertices on the symmetry plane (+x and -x separately), along y from the vertices within
``SECTOR`` of the y axis; ``stick_nodes`` are the +x vertices (the protocol's one stick
radius is the extent along +x).
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from common.errors import ConvergenceError, InputError, nonnegative, positive
from mdr.normal import moment_radius
from mdr.law import History, StepResult
from mdr.materials import Materials
from mdr.profiles import FlatPunch, Profile, Sphere, TruncatedSphere
from mdr.stick import at_limit, per_step
from meshes.half3d import H_CONTACT_3D_DEFAULT, H_CONTACT_3D_RANGE, Half3DMeshParams, cached_mesh3d

from fem.solid3d.contact import (RelativeFlexibility, project_disk, solve_coupled3d, solve_normal3d, solve_tangential3d,
                        tangential_slope)
from fem.solid3d.condensed import condensed_body
from fem.bulk import DEFAULT_PROBE_DEPTH, boussinesq_point_z, cerruti_point_x
from fem.solid3d.interface import hat_integrals, mortar_interface
from fem.stepping import frozen as _frozen, step_history
from fem.axisym.normal_run import reference_radius
from fem.solvers import blas_threads

#: half-angle of the vertex sector around the y axis that resolves the stick extent along y (rad)
SECTOR = np.deg2rad(12.0)
#: the tangential traction: "free" (two components, free direction) or "x" (q_y = 0 everywhere,
#: Mindlin's assumption, as in the axisymmetric model and MDR: on the same mesh, the pair of the
#: two isolates the effect of the direction from the discretisation error)
TRACTIONS = ("free", "x")
#: largest |tilt| (rad): the tilted gap theta * x is the small-slope linearisation of the rotation
#: (cos theta = 1 within 5e-5); the paper's bound on its flat faces' tilt is pi/3600 = 8.7e-4 rad
TILT_MAX = 1e-2
#: default block radius and height / a_ref (the Cerruti mean shear of a 20 a block is +3 %
#: of the half-space's; it is a series compliance, see the module docstring)
BLOCK_SIZE_DEFAULT = 20.0


def _check_assumptions(traction, coupling) -> tuple[str, bool]:
    if traction not in TRACTIONS:
        raise InputError(f"traction must be one of {', '.join(TRACTIONS)}, got {traction!r}")
    if coupling not in (True, False):
        raise InputError(f"coupling must be True or False, got {coupling!r}")
    return traction, bool(coupling)


def _qy_zero(mi, traction) -> np.ndarray:
    """Vertices whose q_y is held at zero: the symmetry plane, or all under traction 'x'."""
    return mi.on_plane if traction == "free" else np.ones(mi.n, dtype=bool)


def _check_tilt(tilt) -> float:
    if np.ndim(tilt) != 0 or not np.isfinite(tilt) or abs(float(tilt)) > TILT_MAX:
        raise InputError(f"tilt must be one finite number in [-{TILT_MAX:g}, {TILT_MAX:g}] rad (small slopes), "
                         f"got {tilt!r}")
    return float(tilt)


@dataclass(frozen=True)
class FE3DState:
    """History of the 3D law: tractions ``q`` (n, 2) and pressures ``p`` (n,) at the vertices (Pa),
    weighted slip ``P`` (n, 2) (m^3), tangential displacement ``u`` and approach ``d`` (m).
    ``dq`` (n, 2) and ``du``: the last step's increments of q and u, which only start the next
    step's iteration (:meth:`FEContact3D._predict`); the answer does not depend on them."""

    q: np.ndarray
    P: np.ndarray
    p: np.ndarray
    u: float
    d: float
    dq: np.ndarray | None = None
    du: float = 0.0


@dataclass(frozen=True)
class Normal3D:
    """Normal contact at one load: vertex pressures ``p`` (Pa), full-body force ``force`` (N),
    plate ``approach`` (m), ``contact_radius`` (m, :meth:`FEContact3D._contact_radius`)."""

    p: np.ndarray
    force: float
    approach: float
    contact_radius: float
    iterations: int


class FEContact3D:
    """3D FE contact law of one profile (see the module docstring for the model).

    ``profile``: Sphere, TruncatedSphere or FlatPunch; ``materials``; ``mu``;
    ``F_max`` (N) sizes the mesh (a_ref = the half-space contact radius at F_max; the flat
    punch: a_ref = b, F_max optional);
    ``h_contact`` element size on the contact half disk / a_ref (range
    ``meshes.half3d.H_CONTACT_3D_RANGE``); ``contact_extent`` contact disk radius / a_ref
    (default 1.25; the flat punch: 1, its face, and nothing else is accepted);
    ``block_size`` block radius and height (m; default ``BLOCK_SIZE_DEFAULT`` a_ref);
    ``tilt`` (rad, module docstring); ``cache_dir``; ``backend`` (sparse solver); ``traction``
    (``TRACTIONS``); ``coupling`` (False: a dissimilar pair's normal-tangential coupling left out,
    as in MDR and Mindlin's theory; the pressure then never feels the tangential traction);
    ``refine``: None or (x, h, radius) in units of a_ref, element size h (<= h_contact) within the
    ball of that radius around (x, 0, 0) (``meshes.half3d``, ``refine_*``): the loaded edge of a
    tilted flat face, (-1, h, radius) for the flat punch at theta > 0. The tilt variants share it.
    ``ring``: None or (r, width, h) in units of a_ref, element size h (<= h_contact) within
    ``width`` of the circle of radius r on the contact face (``meshes.half3d``: the band around the
    whole circle, ``band_r = r``, ``band_angle = pi``; not together with ``band``): the
    slip annulus and the contact edge of a partial-slip cycle, where the stick radius and the
    dissipation are decided (the sphere at F_x = mu F_N / 2: (0.9, 0.18, h) covers 0.72-1.08 a).
    ``band``: None or (h, width, angle[, growth]): element size h / a_ref (<= h_contact) within
    width / a_ref of the flat face's edge circle (r = b; the flat punch: its rim) on the arc
    |phi - pi| <= angle (rad), graded at growth outside (default the mesh's) (``meshes.half3d``, ``band_*``): the thin edge crescent of a face tilted far beyond
    theta_c (theta > 0 loads the -x side). It assumes the crescent lies within the band; the tilt
    variants share it.
    """

    stick_onset = 0.5
    batch = ()

    def __init__(self, profile: Profile, materials: Materials | None = None, mu=0.2, *, F_max=None,
                 h_contact=H_CONTACT_3D_DEFAULT, contact_extent=None, block_size=None,
                 cache_dir=None, backend=None, displacement="plate", tilt=0.0, traction="free", coupling=True,
                 refine=None, ring=None, band=None):
        if not isinstance(profile, (Sphere, TruncatedSphere, FlatPunch)):
            kind = profile.describe()["profile"] if isinstance(profile, Profile) else type(profile).__name__
            raise InputError(f"profile must be sphere, truncated or flat for the 3D model, got {kind!r}")
        self.profile = profile
        self.flat = flat = isinstance(profile, FlatPunch)
        self.tilt = _check_tilt(tilt)
        if flat:
            if contact_extent is not None and contact_extent != 1.0:
                raise InputError("contact_extent is the punch face for the flat punch (1, its radius b); got "
                                 f"{contact_extent!r}")
            contact_extent = 1.0
        elif contact_extent is None:
            contact_extent = 1.25
        self.materials = m = materials if materials is not None else Materials()
        if displacement not in ("contact", "plate"):
            raise InputError(f"displacement must be 'contact' or 'plate', got {displacement!r}")
        self.displacement = displacement
        self.traction, self.coupling = _check_assumptions(traction, coupling)
        if np.ndim(mu) != 0:
            raise InputError(f"mu must be one number, got an array of shape {np.shape(mu)}")
        self.mu = float(nonnegative("mu", mu))
        if F_max is None and not flat:
            raise InputError("FEContact3D needs F_max (> 0, the largest normal force) to size its mesh")
        self.F_max = None if F_max is None else float(positive("F_max", F_max))
        if not H_CONTACT_3D_RANGE[0] <= h_contact <= H_CONTACT_3D_RANGE[1]:
            raise InputError(f"h_contact must be in [{H_CONTACT_3D_RANGE[0]:g}, {H_CONTACT_3D_RANGE[1]:g}] for the "
                             f"3D model, got {h_contact!r}")
        desc = profile.describe()
        kind = desc["profile"]
        b = float(desc.get("b") or 0.0)
        a_ref = reference_radius(kind, desc.get("R"), b, self.F_max, m.E_star)
        L = BLOCK_SIZE_DEFAULT * a_ref if block_size is None else float(positive("block_size", block_size))
        t0 = time.perf_counter()
        edge = b / a_ref if b > 0 and not flat else None  # the flat face's edge: a circle of the mesh
        if refine is None:
            refine = (None, None, None)
        elif np.ndim(refine) != 1 or np.size(refine) != 3:
            raise InputError(f"refine must be None or (x, h, radius) / a_ref (the refined ball of the mesh), got "
                             f"{refine!r}")
        if ring is not None:  # a band around the whole circle r
            if band is not None:
                raise InputError("give ring or band, not both (a ring is the band around a whole circle)")
            if np.ndim(ring) != 1 or np.size(ring) != 3:
                raise InputError(f"ring must be None or (r, width, h) / a_ref (the refined ring of the mesh), got "
                                 f"{ring!r}")
        if band is None:
            band = (None, None, None, None)
        elif np.ndim(band) != 1 or np.size(band) not in (3, 4):
            raise InputError(f"band must be None or (h / a_ref, width / a_ref, angle in rad[, growth]) (the refined "
                             f"band along the loaded edge), got {band!r}")
        band = tuple(band) + (None,) * (4 - len(band))
        band_r = None
        if ring is not None:
            band_r, band = ring[0], (ring[2], ring[1], np.pi, None)
        params = Half3DMeshParams(a_ref=a_ref, h_contact=h_contact, contact_extent=contact_extent, size=L, height=L,
                                  edge=edge, refine_x=refine[0], refine_h=refine[1], refine_radius=refine[2],
                                  band_h=band[0], band_width=band[1], band_angle=band[2], band_growth=band[3],
                                  band_r=band_r)
        self.hmesh = cached_mesh3d(params, cache_dir)
        mesh = self.hmesh.mesh
        t1 = time.perf_counter()
        self.mi = mi = mortar_interface(mesh)
        parts = {"assembly": time.perf_counter() - t1}
        # the axis probes of the contact measure: as shallow as in the axisymmetric law, below the contact
        # disk (inside the bodies: the mesh is deeper than 2 contact_extent a_ref)
        zp = max(DEFAULT_PROBE_DEPTH, contact_extent + 0.25) * a_ref
        # each body's condensed interface (for E = 1 Pa: scaled by 1/E), cached on disk beside the mesh
        blk = condensed_body(self.hmesh, mi, m.nu2, zp, backend=backend, cache_dir=cache_dir, timings=parts)
        self.backend, self.ndofs = blk.params.backend, blk.ndofs
        D_blk, R_blk = blk.D / m.E2, blk.R / m.E2
        self.condensed = {"block": {"cache": blk.info.get("cache"), "key": blk.key}}
        if m.nu1 == m.nu2:  # the flexibility of one mesh scales with 1/E at fixed nu
            D_ind, R_ind = blk.D / m.E1, blk.R / m.E1
        else:
            ind = condensed_body(self.hmesh, mi, m.nu1, zp, backend=backend, cache_dir=cache_dir, timings=parts)
            D_ind, R_ind = ind.D / m.E1, ind.R / m.E1
            self.condensed["indenter"] = {"cache": ind.info.get("cache"), "key": ind.key}
            self.ndofs *= 2
        self.rf = RelativeFlexibility.from_bodies(D_blk, D_ind)
        self._Dt_plate = self.rf.Dt
        self.bulk = self._bulk_rows(zp, R_blk, R_ind)
        #: Dundurs' second constant of the pair (Dundurs 1969, J. Appl. Mech. 36, 650; 0: the normal and
        #: tangential problems decouple), signed positive when the block (body 2) is the more
        #: compressible one (steel on aluminium: +0.11)
        G1, G2 = m.G1, m.G2
        self.beta = 0.5 * ((1 - 2 * m.nu2) / G2 - (1 - 2 * m.nu1) / G1) / ((1 - m.nu2) / G2 + (1 - m.nu1) / G1)
        if flat:  # every node of the candidate disk (the punch face, its faceted rim included) is on the face
            f = np.zeros(mi.nodes.m)
        else:
            with np.errstate(invalid="ignore"):
                f = np.asarray(profile.f(mi.nodes.r), dtype=float)
        self.g0_aligned = mi.B @ f  # the profile in the P2 space, weighted by the P1 hats
        self._g_tilt = mi.B @ mi.nodes.x  # the weighted gap of a unit tilt, theta x (exact in the P2 space)
        self.g0 = self.g0_aligned + self.tilt * self._g_tilt
        #: vertices on the symmetry plane by increasing x (the contact's extent along x)
        self._plane = np.flatnonzero(mi.on_plane)[np.argsort(mi.x[mi.on_plane])]
        #: vertices whose q_y is held at zero: the symmetry plane, or every vertex under Mindlin's
        #: assumption (``traction="x"``)
        self._qy_zero = _qy_zero(mi, traction)
        xp = np.flatnonzero(mi.on_plane & (mi.x >= 0))
        xm = np.flatnonzero(mi.on_plane & (mi.x <= 0))
        phi = np.arctan2(mi.y, mi.x)
        ys = np.flatnonzero((np.abs(phi - np.pi / 2) <= SECTOR) | (mi.r == 0))
        self._ys = ys
        self._rays = {"+x": xp[np.argsort(mi.x[xp])], "-x": xm[np.argsort(-mi.x[xm])],
                      "y": ys[np.argsort(mi.r[ys])]}
        tri = np.searchsorted(mi.vertices, mesh.facets[:, mesh.boundaries["contact"]])  # (3, k) vertex positions
        e = np.concatenate([tri[[0, 1]], tri[[1, 2]], tri[[2, 0]]], axis=1)
        self._adj = sp.coo_matrix((np.ones(e.shape[1]), (e[0], e[1])), shape=(mi.n, mi.n)).tocsr()
        self._rim = mi.r >= (1 - 1e-6) * float(mi.r.max())
        self._normal_cache = {}
        self._r2_hat = None
        self.stats = {"steps": 0, "trial_solves": 0, "newton": 0, "normal_solves": 0}
        #: the bodies' series compliance (m/N) at F_max (the flat punch: its face): plate displacement
        #: = contact + c_bulk F_x
        self.c_bulk = self.plate_bulk_compliance(self.F_max) if self.F_max is not None else \
            self._bulk_scalar(np.ones(mi.n, dtype=bool))
        if displacement == "contact":  # u measured without it: s = u_c A e_x - (Dt - 2 c_bulk A A^T) q
            Dt = self.rf.Dt.copy()
            Dt[:mi.n, :mi.n] -= 2.0 * self.c_bulk * np.outer(mi.A, mi.A)
            self.rf = RelativeFlexibility(Dn=self.rf.Dn, Dt=Dt, K=self.rf.K)
        #: seconds: mesh (gmsh or the cache), setup (all after the mesh), of which assembly (stiffness,
        #: mortar matrix; for a dissimilar pair the first body's), factorisation and condensation
        #: (``fem.solid3d.interface.mortar_flexibility``, both bodies)
        self.timings = {"mesh": t1 - t0, "setup": time.perf_counter() - t1, **parts}
        self.last_run = None

    def _bulk_rows(self, L, R_blk, R_ind) -> dict:
        """Per-vertex bulk corrections of the axis probes at depth ``L`` in both bodies (``fem.bulk``
        in 3D): FE probe reading minus the half-space's (Cerruti, Boussinesq; the half model's
        vertex hats doubled by their mirror images). ``x`` (n,): x displacement of the indenter's
        probe relative to the block's per unit x traction field phi_j on the block, both bodies'
        parts (m/Pa); ``z`` (n,): both bodies' compression between clamp and probe per unit
        pressure field (m/Pa)."""
        m, mesh, mi = self.materials, self.hmesh.mesh, self.mi
        out = {"depth": L, "x": np.zeros(mi.n), "z": np.zeros(mi.n)}
        for R, E, nu in ((R_blk, m.E2, m.nu2), (R_ind, m.E1, m.nu1)):
            G = E / (2.0 * (1.0 + nu))
            out["x"] += R[0, 0] - 2.0 * hat_integrals(mesh, mi, lambda x, y: cerruti_point_x(x, y, L, G, nu))
            out["z"] += R[2, 2] - 2.0 * hat_integrals(mesh, mi, lambda x, y: boussinesq_point_z(x, y, L, G, nu))
        return out

    def plate_bulk_compliance(self, F_N) -> float:
        """c_bulk (m/N): the bodies' series compliance in the plate measure, from the axis probes and
        Cerruti's half-space solution (``fem.bulk``), weighted by the full-stick x tractions at F_N
        (> 0). Uses no half-space contact stiffness. The y tractions' share is left out (at most
        the traction angle, ~0.1, times a term odd in y that the mirror halves cancel to leading
        order)."""
        return self._bulk_scalar(self.normal(F_N=float(positive("F_N", F_N))).p > 0)

    def _bulk_scalar(self, c) -> float:
        """c_bulk weighted by the full-stick x tractions on the vertices ``c`` (plate measure)."""
        mi = self.mi
        q = np.linalg.solve(self._Dt_plate[:mi.n, :mi.n][np.ix_(c, c)], mi.A[c])
        return float(self.bulk["x"][c] @ q / (2.0 * mi.A[c] @ q))

    def indentation(self, nr: "Normal3D") -> float:
        """Half-space comparable indentation (m) of a normal solution: the plate approach minus both
        bodies' compression between clamp and probe plus the half-space's below the probes
        (``fem.bulk.normal_indentation`` in 3D)."""
        return float(nr.approach - self.bulk["z"] @ nr.p)

    def variant(self, *, traction=None, coupling=None, tilt=None) -> "FEContact3D":
        """The same model (mesh, flexibilities, probes shared, not copied: nothing is rebuilt) with
        another ``traction``, ``coupling`` or ``tilt`` (rad): the pair of runs isolates that
        assumption from the discretisation, and a tilt sweep pays for one set-up."""
        import copy

        new = copy.copy(self)
        new.traction, new.coupling = _check_assumptions(self.traction if traction is None else traction,
                                                        self.coupling if coupling is None else coupling)
        new._qy_zero = _qy_zero(self.mi, new.traction)
        new.tilt = self.tilt if tilt is None else _check_tilt(tilt)
        new.g0 = self.g0_aligned + new.tilt * self._g_tilt
        new._normal_cache = dict(self._normal_cache) if new.tilt == self.tilt else {}
        new.stats = dict.fromkeys(self.stats, 0)
        new.last_run = None
        return new

    # ----------------------------------------------------------------- info
    @property
    def stick_nodes(self):
        return self.mi.r[self._rays["+x"]]

    @property
    def x_ray(self) -> np.ndarray:
        """The vertices on the symmetry plane with x >= 0, by increasing x (the +x axis)."""
        return self._rays["+x"]

    @property
    def n(self) -> int:
        return self.mi.n

    def describe(self) -> dict:
        return {"law": "fem3d", "dofs": self.ndofs, "vertices": self.n, "displacement": self.displacement,
                "traction": self.traction, "coupling": self.coupling, "tilt": self.tilt,
                "mesh": dict(self.hmesh.params.as_dict(), key=self.hmesh.key), "backend": self.backend}

    def mesh_summary(self) -> dict:
        return dict(self.hmesh.params.as_dict(), key=self.hmesh.key, cache=self.hmesh.info.get("cache"),
                    condensed=self.condensed)

    def contact_at(self, F_N) -> dict:
        """``mdr.protocol.ContactLaw.contact_at``: the 3D model's own contact radius and half-space
        comparable indentation at ``F_N`` (without tangential traction)."""
        nr = self.normal(F_N=F_N)
        return {"contact_radius": float(nr.contact_radius), "indentation": float(self.indentation(nr))}

    def normal_load(self, F_N) -> dict:
        return {"F_N": np.asarray(F_N, dtype=float)}

    def rest_state(self) -> FE3DState:
        z2, z = _frozen(np.zeros((self.n, 2))), _frozen(np.zeros(self.n))
        return FE3DState(q=z2, P=z2, p=z, u=0.0, d=0.0)

    # ----------------------------------------------------------------- normal
    def normal(self, *, F_N=None, d=None, aligned=False) -> Normal3D:
        """Normal contact at full-body force F_N (> 0) or plate approach d, cached per value;
        ``aligned``: without the tilt (the reference of ``contact_area_fraction``)."""
        key = ("F", float(f"{F_N:.13g}")) if F_N is not None else ("d", float(f"{d:.13g}"))
        aligned = aligned or self.tilt == 0.0
        key = key + ("aligned",) if aligned else key
        res = self._normal_cache.get(key)
        if res is None:
            mi = self.mi
            g0 = self.g0_aligned if aligned else self.g0
            with blas_threads(1):
                p, dd, _, it = solve_normal3d(self.rf.Dn, g0, mi.A, force=None if F_N is None else F_N / 2,
                                              approach=d)
            self._check_rim(p)
            a = self._contact_radius(p, aligned)
            res = Normal3D(p=p, force=2.0 * float(mi.A @ p), approach=float(dd), contact_radius=a, iterations=it)
            self._normal_cache[key] = res
            self.stats["normal_solves"] += 1
        return res

    def _contact_radius(self, p, aligned) -> float:
        """The contact radius: of the aligned flat punch its radius b (once in contact), of an aligned
        sphere or truncated sphere :meth:`_edge_radius`; of a tilted contact the half-width of its
        extent along x (:meth:`contact_extent_x`)."""
        if not np.any(p > 0):
            return 0.0
        if aligned and self.flat:
            return float(self.profile.b)
        if aligned:
            return self._edge_radius(p)
        x0, x1 = self.contact_extent_x(p)
        return 0.5 * (x1 - x0)

    def contact_extent_x(self, p) -> tuple:
        """(x_min, x_max) of the contact along the symmetry plane (m): the outermost loaded vertices
        on y = 0, each moved towards the free vertex beyond it to the zero of p^2 extrapolated
        linearly from the last two loaded vertices (p ~ sqrt of the distance to a smooth edge,
        as in :meth:`_edge_radius`), clipped to that interval; at the rim of the candidate disk
        the rim. Assumes the loaded vertices on the plane form one interval."""
        pl = self._plane
        x, pp = self.mi.x[pl], p[pl]
        k = np.flatnonzero(self.contact_mask(p)[pl])
        if k.size == 0:
            return 0.0, 0.0
        ends = []
        for j, step in ((k[0], -1), (k[-1], 1)):
            xe = float(x[j])
            if 0 <= j + step < x.size and 0 <= j - step < x.size and pp[j - step] > 0:
                w1, w2 = pp[j] ** 2, pp[j - step] ** 2
                if w2 > w1:
                    xr = x[j] + w1 * (x[j] - x[j - step]) / (w2 - w1)
                    lo, hi = sorted((float(x[j]), float(x[j + step])))
                    xe = float(np.clip(xr, lo, hi))
            ends.append(xe)
        return ends[0], ends[1]

    def pressure_radius(self, p) -> float:
        """The pressure's second-moment radius (m, ``mdr.normal.moment_radius``) about the load axis,
        of the P1 pressure field sum_j p_j phi_j integrated exactly (int phi_j r^2 dA by
        ``fem.solid3d.interface.hat_integrals``, once per law). Unlike :meth:`_edge_radius` it needs no
        edge located between vertices: a vertex whose hat straddles the edge has a positive
        weighted gap and carries no pressure, which puts the read edge inside by a fraction of an
        element (the sphere: 0.4-1.7 % of a on meshes of h = a/5 ... a/14, graded or not), while
        this integral is within 0.25 % of MDR's on the same meshes, 0.15 % from a/7 on
        (``tests/test_contact3d.py``).
        NaN without contact."""
        if self._r2_hat is None:
            self._r2_hat = hat_integrals(self.hmesh.mesh, self.mi, lambda x, y: x * x + y * y)
        return moment_radius(2.0 * float(self.mi.A @ p), 2.0 * float(self._r2_hat @ p))

    def contact_mask(self, p) -> np.ndarray:
        """The vertices in contact: the loaded ones (p > 0) and the free ones enclosed by them, i.e.
        the connected sets of free vertices (along the contact facets' edges) that reach no vertex
        of the candidate disk's rim. The filling is for the flat punch: its P1 pressure oscillates
        next to the singular edge, and the Signorini solution leaves a few vertices of the ring
        next to the rim at zero pressure (with a weighted gap below 0.5 % of d A_j at b/5) inside
        a contact that the theory has complete."""
        from scipy.sparse.csgraph import connected_components

        free = ~(p > 0)
        if not np.any(free):
            return ~free
        idx = np.flatnonzero(free)
        _, lab = connected_components(self._adj[idx][:, idx], directed=False)
        open_ = np.unique(lab[self._rim[idx]])
        mask = ~free
        mask[idx[~np.isin(lab, open_)]] = True
        return mask

    def contact_area(self, p) -> float:
        """Contact area of the full body (m^2): twice the sum of the vertex areas A_j (the
        integrals of the P1 hats) of the vertices in contact (:meth:`contact_mask`), i.e. the
        contact edge half way between a loaded and a free vertex (first order in the element
        size)."""
        return 2.0 * float(self.mi.A[self.contact_mask(p)].sum())

    def _check_rim(self, p):
        """A contact that reaches the rim of the meshed contact disk is an error, never a silent
        truncation (the flat punch: its rim is the punch edge, where contact belongs)."""
        if self.flat:
            return
        rim = float(self.mi.r.max())
        if np.any(p[self.mi.r >= 0.999 * rim] > 0):
            raise ConvergenceError(f"the contact reaches the rim of the contact disk (r = {rim:.4g} m): raise "
                                   "contact_extent")

    def _edge_radius(self, p) -> float:
        """Contact radius from the vertex pressures: near a smooth edge p^2 is linear in r^2 (exact
        for Hertz, first order for the truncated sphere), so a least-squares line through
        (r^2, p^2) of the loaded vertices within 2 h of the outermost one is extrapolated to
        p = 0, clipped to [outermost loaded vertex, innermost free vertex beyond it]. All angles together: assumes a
        circular contact (the aligned sphere and truncated sphere)."""
        mi = self.mi
        loaded = p > 0
        if not np.any(loaded):
            return 0.0
        h = self.hmesh.params.h_min
        r1 = float(mi.r[loaded].max())
        sel = loaded & (mi.r >= r1 - 2.0 * h)
        if sel.sum() < 3:
            return r1
        k, c0 = np.polyfit(mi.r[sel] ** 2, p[sel] ** 2, 1)
        a = np.sqrt(-c0 / k) if k < 0 and c0 > 0 else r1
        beyond = mi.r[~loaded & (mi.r > r1)]
        return float(np.clip(a, r1, beyond.min() if beyond.size else r1 + h))

    # ------------------------------------------------------------------ step
    def step(self, state: FE3DState, u=None, *, d=None, F_N=None, Fx=None):
        """One step, pure (``state`` not modified): normal load ``F_N`` (N, >= 0) or ``d``; tangential
        ``u`` (m) or ``Fx`` (N, |Fx| < mu F_N). Returns (StepResult, FE3DState)."""
        if (d is None) == (F_N is None):
            raise InputError("step needs exactly one of d (approach) or F_N (normal force)")
        if (u is None) == (Fx is None):
            raise InputError("step needs exactly one of u (tangential displacement) or Fx (tangential force)")
        res, new, _ = self._tangential(self._normal_part(state, d, F_N), u, Fx)
        self.stats["steps"] += 1
        return res, new

    def prepare(self, state: FE3DState, *, d=None, F_N=None) -> "FE3DTrial":
        """The normal part of a step, for many trial tangential displacements (``mdr.protocol``;
        the apparatus): ``force(u)`` gives (Fx, dFx/du), ``commit(u)`` the result of
        ``step(state, u, ...)``. For identical materials (or ``coupling=False``) the normal
        contact is solved here once (cached per load); for a dissimilar pair with coupling the
        pressure depends on u, so each trial solves the coupled increment at its u."""
        if (d is None) == (F_N is None):
            raise InputError("prepare needs exactly one of d (approach) or F_N (normal force)")
        return FE3DTrial(self, self._normal_part(state, d, F_N))

    def _normal_part(self, state, d, F_N) -> dict:
        """What a step needs before its tangential load: the normal solution (None when the bodies
        are apart or when the dissimilar pair's coupled solve does both at once)."""
        if F_N is not None:
            F_N = float(nonnegative("F_N (normal force; no adhesion, so >= 0)", F_N))
            touching = F_N > 0
        else:
            d = float(d)
            if not np.isfinite(d):
                raise InputError(f"d must be finite, got {d!r}")
            touching = d > 0
        coupled = touching and self.rf.K is not None and self.coupling
        nr = None
        if touching and not coupled:
            with blas_threads(1):
                nr = self.normal(F_N=F_N) if F_N is not None else self.normal(d=d)
        return {"state": state, "F_N": F_N, "d": d, "touching": touching, "coupled": coupled, "nr": nr}

    def _tangential(self, ctx, u, Fx):
        """The tangential part of a step from :meth:`_normal_part`: returns (StepResult, FE3DState,
        (g, TangentialResult, slip increments)) for the trial's slope."""
        state, F_N, d, nr = ctx["state"], ctx["F_N"], ctx["d"], ctx["nr"]
        if u is not None:
            u = float(u)
            if not np.isfinite(u):
                raise InputError(f"u must be finite, got {u!r}")
        mi = self.mi
        q0 = np.asarray(state.q)
        with blas_threads(1):
            if ctx["coupled"]:  # dissimilar pair: both together
                if F_N is not None:  # (under approach control the Coulomb solve itself refuses)
                    self._check_force_limit(Fx, F_N)
                p, dd, res, _ = solve_coupled3d(
                    self.rf, self.g0, mi.A, self.mu, np.asarray(state.P), self._qy_zero,
                    F_n=None if F_N is None else F_N / 2, d=d, delta=u,
                    F_t=None if Fx is None else Fx / 2, q0=q0, delta0=state.u,
                    p0=np.asarray(state.p) if np.any(np.asarray(state.p) > 0) else None)
                self.stats["normal_solves"] += 1
                self._check_rim(p)
                nr = Normal3D(p=p, force=2.0 * float(mi.A @ p), approach=float(dd),
                              contact_radius=self._contact_radius(p, self.tilt == 0.0), iterations=0)
                g = self.mu * p
            else:
                p = nr.p if nr is not None else np.zeros(self.n)
                g = self.mu * p
                self._check_force_limit(Fx, nr.force if nr is not None else 0.0)
                if not np.any(g > 0):
                    uu = float(state.u if u is None else u)
                    res = solve_tangential3d(self.rf.Dt, mi.A, g, np.asarray(state.P), self._qy_zero, delta=uu)
                elif u is not None:
                    q0, _ = self._predict(state, g, u, None)
                    res = solve_tangential3d(self.rf.Dt, mi.A, g, np.asarray(state.P), self._qy_zero,
                                             delta=u, q0=q0)
                else:
                    q0, u0 = self._predict(state, g, None, Fx)
                    res = solve_tangential3d(self.rf.Dt, mi.A, g, np.asarray(state.P), self._qy_zero,
                                             force=Fx / 2, q0=q0, delta0=u0)
        FN = nr.force if nr is not None else 0.0
        contact = g > 0
        work = 2.0 * float(np.sum((res.q * (res.s - np.asarray(state.P)))[contact]))
        qn = np.hypot(res.q[:, 0], res.q[:, 1])
        slack = np.where(contact, g - qn, 0.0)
        slipping = ~contact | at_limit(slack, g)
        ray = self._rays["+x"]
        a = nr.contact_radius if nr is not None else 0.0
        a_x = self._ray_caps(p, a)["+x"]
        c = float(per_step(mi.x[ray], slack[ray], slipping[ray], a_x, self.stick_onset))
        self.stats["trial_solves"] += 1
        self.stats["newton"] += res.iterations
        new = FE3DState(q=_frozen(res.q), P=_frozen(res.s), p=_frozen(p), u=float(res.delta),
                        d=float(nr.approach if nr is not None else (d or 0.0)),
                        dq=_frozen(res.q - np.asarray(state.q)), du=float(res.delta) - float(state.u))
        return StepResult(Fx=2.0 * float(mi.A @ res.q[:, 0]), FN=FN, d=new.d, a=a, c=c, u=new.u, work=work,
                          slack=slack[ray], slipping=slipping[ray]), new, (g, res, res.s - np.asarray(state.P))

    def _predict(self, state: FE3DState, g, u, Fx):
        """Start of a Coulomb increment: the last step's increments (``state.dq``, ``state.du``)
        extrapolated to the new load (F_x or u) when it moves on in the same direction (secant
        predictor), else the state itself (a reversal sticks first). Projected onto the new slip
        disks. Only the iteration count depends on it (measured on the sphere at 453 vertices:
        14 semi-smooth Newton iterations per force step without it, 4.4 with it)."""
        q = np.asarray(state.q)
        if state.dq is None:
            return q, state.u
        dq = np.asarray(state.dq)
        if Fx is not None:
            last = 2.0 * float(self.mi.A @ dq[:, 0])
            ahead = Fx - 2.0 * float(self.mi.A @ q[:, 0])
        else:
            last, ahead = state.du, u - state.u
        if not (last != 0.0 and 0.0 < ahead / last <= 4.0):
            return q, state.u
        f = ahead / last
        return project_disk(q + f * dq, g), state.u + f * state.du

    def _check_force_limit(self, Fx, FN):
        """A prescribed tangential force must stay below mu F_N (no force-controlled gross slip)."""
        if Fx is not None and Fx != 0.0 and abs(Fx) >= self.mu * FN * (1 - 1e-12):
            raise InputError(f"tangential force Fx={Fx:.4g} N must stay below the friction limit "
                             f"mu*F_N={self.mu * FN:.4g} N under force control")

    # ------------------------------------------------------------------ runs
    def run(self, u=None, *, F_N=None, d=None, Fx=None, state: FE3DState | None = None,
            record_from: int | None = None) -> History:
        """A load history (arrays (T,)); returns mdr.law.History. The tractions and pressures of every
        step are kept in ``last_run`` (for the 3D keys of :meth:`result_keys`)."""
        kept = {"q": [], "p": [], "Fx": [], "a": [], "first": 0}

        def keep(t, res, st):
            kept["q"].append(st.q)
            kept["p"].append(st.p)
            kept["Fx"].append(res.Fx)
            kept["a"].append(res.a)

        H = step_history(self, self._rays["+x"].size, u=u, F_N=F_N, d=d, Fx=Fx, state=state,
                         record_from=record_from, on_step=keep)
        kept["first"] = H.u.size if record_from is None else int(record_from)
        self.last_run = kept
        return H

    # ------------------------------------------------------------------ 3D keys
    def _ray_caps(self, p, a) -> dict:
        """The contact's extent along each stick ray (m), the cap of its stick extent: ``a`` for
        every ray of an aligned contact; of a tilted one x_max, -x_min (``contact_extent_x``) and
        the outermost loaded vertex within ``SECTOR`` of the y axis."""
        if self.tilt == 0.0:
            return {"+x": a, "-x": a, "y": a}
        x0, x1 = self.contact_extent_x(p)
        ly = self._ys[self.contact_mask(p)[self._ys]]
        return {"+x": max(x1, 0.0), "-x": max(-x0, 0.0), "y": float(self.mi.r[ly].max()) if ly.size else 0.0}

    def stick_zone(self, q, p, a) -> dict:
        """Stick extents of one instant (m): ``stick_radius_x`` (mean of +x and -x),
        ``stick_center_x`` (their half difference), ``stick_radius_y``, each from the vertices of
        one ray (``mdr.stick``: resolved to a fraction of the element); ``stick_axis_x``,
        ``stick_axis_y``, the semi-axes of the ellipse with the stick set's area and second moments
        (every vertex that sticks, weighted by its area A_j: a = sqrt(4 I_x / area), so a change of
        the stick set by one vertex moves them by ~A_j / area, far less than an element);
        ``stick_axis_quantum`` (m), their resolution: the change of an axis when one vertex of median
        area joins the stick set, axis * A_median / (2 area);
        ``stick_fit_x``, ``stick_fit_y``, ``stick_fit_center_x`` (m): the stick ellipse fitted to the
        slack s = mu p - |q| of the sticking vertices, s^2 = A0 - B (x - x0)^2 - C y^2
        (:func:`stick_ellipse_fit`; semi-axes sqrt(A0 / B), sqrt(A0 / C), centre x0; NaN where it
        cannot be fitted): exact for Cattaneo-Mindlin, whose slack is (mu p0 / a) sqrt(c^2 - r^2)
        (Hertz pressure, traction along x), an approximation elsewhere. It uses every sticking
        vertex, so it moves almost continuously with the solution (a small jump when a vertex of
        near-zero slack joins the stick set) instead of by one vertex at a time. It assumes that
        form: at a constant normal force the traction of free direction stays close to it (the fit
        converges, ``tests/test_contact3d.py``); under a varying normal force the stick zone's slack
        carries its history and the fit is no estimate (the assumptions-3d scene's Table 2 loading:
        the fitted axes of the sphere's free-direction run and of its twin along x on one mesh
        differed by 1.5-15 % of a, where the two stick sets were identical);
        ``traction_angle_max``, the largest |q_y|/|q| over the vertices in contact that slip;
        ``pressure_center_x``, the x of the pressure's centroid (m)."""
        mi = self.mi
        g = self.mu * p
        qn = np.hypot(q[:, 0], q[:, 1])
        contact = g > 0
        slack = np.where(contact, g - qn, 0.0)
        slipping = ~contact | at_limit(slack, g)
        ext = {}
        caps = self._ray_caps(p, a)
        for name, ray in self._rays.items():
            r = np.abs(mi.x[ray]) if name != "y" else mi.r[ray]
            ext[name] = float(per_step(r, slack[ray], slipping[ray], caps[name], self.stick_onset))
        slip = contact & slipping
        ang = float(np.max(np.abs(q[slip, 1]) / qn[slip])) if np.any(slip) else 0.0
        w = mi.A * p
        st = contact & ~slipping
        area = float(mi.A[st].sum())
        if area > 0:
            xc = float(mi.A[st] @ mi.x[st]) / area
            axes = (np.sqrt(4.0 * float(mi.A[st] @ (mi.x[st] - xc) ** 2) / area),
                    np.sqrt(4.0 * float(mi.A[st] @ mi.y[st] ** 2) / area))
            quantum = 0.5 * max(axes) * float(np.median(mi.A[st])) / area
        else:
            axes, quantum = (0.0, 0.0), 0.0
        fit = stick_ellipse_fit(mi.x[st], mi.y[st], slack[st], mi.A[st])
        return {"stick_radius_x": 0.5 * (ext["+x"] + ext["-x"]), "stick_center_x": 0.5 * (ext["+x"] - ext["-x"]),
                "stick_fit_x": fit[0], "stick_fit_y": fit[1], "stick_fit_center_x": fit[2],
                "stick_radius_y": ext["y"], "stick_axis_x": float(axes[0]), "stick_axis_y": float(axes[1]),
                "stick_axis_quantum": quantum, "traction_angle_max": ang,
                "pressure_center_x": float(w @ mi.x / w.sum()) if w.sum() > 0 else 0.0}

    def result_keys(self, F_N, t0, t1, t2, F_peak=None) -> dict:
        """The keys a 3D run adds (``python -m fem contact --model 3d``): the FE's own contact radius
        and approach at F_N without tangential traction (for a dissimilar pair the run's coupled
        steps differ slightly: see ``pressure_center_x``),
        ``dofs``, ``vertices``, ``beta``, ``mesh``, ``solver``, ``runtime_s`` (setup, cycles, total,
        and of the set-up the factorisation and the condensation: :attr:`timings`); ``tilt``, and
        at the peak normal force ``F_peak`` (default F_N) without tangential traction
        ``contact_area_fraction`` (:meth:`contact_area` over that of the punch face, pi b^2 up to
        the faceting of the meshed rim, for the flat punch; over the aligned contact's for a
        sphere or truncated sphere, the same estimator) and ``contact_x_min``, ``contact_x_max``
        (:meth:`contact_extent_x`); from the last run:
        ``stick_radius_x``, ``stick_radius_y`` and ``traction_angle_max`` at the peak of F_x of its
        recorded window (the last cycle), ``stick_center_x`` and ``pressure_center_x`` at its first
        peak of F_x (the first local maximum). ``pressure_radius`` (:meth:`pressure_radius`) at F_N
        without tangential traction."""
        nr = self.normal(F_N=F_N)
        out = {"contact_radius": nr.contact_radius, "pressure_radius": self.pressure_radius(nr.p),
               "approach": nr.approach, "indentation": self.indentation(nr),
               "bulk_compliance": self.plate_bulk_compliance(F_N), "displacement": self.displacement,
               "traction": self.traction,
               "coupling": self.coupling, "dofs": self.ndofs, "vertices": self.n, "beta": self.beta,
               "mesh": self.mesh_summary(),
               "solver": {"backend": self.backend, **self.stats},
               "runtime_s": {"setup": t1 - t0, "cycles": t2 - t1, "total": t2 - t0,
                             **{k: self.timings[k] for k in ("factorisation", "condensation")}}}
        out.update(self.tilt_keys(F_N if F_peak is None else F_peak))
        run = self.last_run
        if run and run["q"]:
            k = self._window_peak(run)
            z = self.stick_zone(run["q"][k], run["p"][k], run["a"][k])
            out.update({key: z[key] for key in ("stick_radius_x", "stick_radius_y", "stick_axis_x", "stick_axis_y",
                                                "stick_axis_quantum", "stick_fit_x", "stick_fit_y",
                                                "traction_angle_max")})
            out.update(self.first_loading_keys())
        return out

    @staticmethod
    def _window_peak(run) -> int:
        """The step of the peak of F_x in a run's recorded window (the last cycle)."""
        Fx = np.asarray(run["Fx"])
        k0 = run["first"] if run["first"] < Fx.size else 0
        return k0 + int(np.argmax(Fx[k0:]))

    def first_loading_keys(self) -> dict:
        """``stick_center_x`` and ``pressure_center_x`` at the last run's first peak of F_x (its first
        loading; without one, the peak of its recorded window); empty where it kept no tractions."""
        run = self.last_run
        if not run or not run["q"]:
            return {}
        Fx = np.asarray(run["Fx"])
        peaks = np.flatnonzero((Fx[1:-1] >= Fx[:-2]) & (Fx[1:-1] > Fx[2:]) & (Fx[1:-1] > 0)) + 1
        k1 = int(peaks[0]) if peaks.size else self._window_peak(run)
        z1 = self.stick_zone(run["q"][k1], run["p"][k1], run["a"][k1])
        return {"stick_center_x": z1["stick_center_x"], "pressure_center_x": z1["pressure_center_x"]}

    #: the stick-zone keys of :meth:`cycle_keys`: those :meth:`result_keys` reports at the last cycle's peak
    CYCLE_KEYS = ("stick_radius_x", "stick_radius_y", "stick_axis_x", "stick_axis_y", "traction_angle_max")

    def cycle_keys(self, steps: int) -> dict:
        """The stick-zone keys (``CYCLE_KEYS``) at the peak of F_x of every full cycle of the last run
        (cycles of ``steps`` steps from its first sample; a run from rest or from the normal ramp's
        state), lists over the cycles: how the last cycle's values of :meth:`result_keys` settled
        (``common.ladder.settling_error``). Empty where the last run kept no tractions."""
        run = self.last_run
        if not run or not run["q"]:
            return {}
        Fx = np.asarray(run["Fx"])
        out = {key: [] for key in self.CYCLE_KEYS}
        for k in range((Fx.size - 1) // int(steps)):
            j = k * steps + int(np.argmax(Fx[k * steps:(k + 1) * steps + 1]))
            z = self.stick_zone(run["q"][j], run["p"][j], run["a"][j])
            for key in out:
                out[key].append(None if not np.isfinite(z[key]) else float(z[key]))
        return out

    def tilt_keys(self, F_N) -> dict:
        """``tilt``, ``contact_area_fraction``, ``contact_x_min``, ``contact_x_max`` at the normal
        force F_N without tangential traction (see :meth:`result_keys`)."""
        nr = self.normal(F_N=F_N)
        ref = float(2.0 * self.mi.A.sum()) if self.flat else self.contact_area(self.normal(F_N=F_N, aligned=True).p)
        x0, x1 = self.contact_extent_x(nr.p)
        return {"tilt": self.tilt, "contact_area_fraction": self.contact_area(nr.p) / ref,
                "contact_x_min": x0, "contact_x_max": x1}


def stick_ellipse_fit(x, y, slack, w) -> tuple:
    """(semi-axis x, semi-axis y, centre x) (m) of the ellipse where the fitted squared slack of the
    sticking vertices vanishes: weighted least squares (weights ``w``, the vertex areas) of
    s^2 = A + D x - B x^2 - C y^2 (the half model, symmetric in y), i.e. A0 - B (x - x0)^2 - C y^2
    with x0 = D / (2 B), A0 = A + B x0^2. Exact for a Cattaneo-Mindlin stick zone (slack
    proportional to sqrt(c^2 - r^2)); NaNs with fewer than 5 vertices or B, C or A0 <= 0."""
    nan = (float("nan"),) * 3
    if np.size(x) < 5:
        return nan
    sw = np.sqrt(np.asarray(w, dtype=float))
    M = np.column_stack([np.ones(np.size(x)), -np.square(x), -np.square(y), x]) * sw[:, None]
    (A, B, C, D), *_ = np.linalg.lstsq(M, np.square(slack) * sw, rcond=None)
    if not (B > 0 and C > 0):
        return nan
    x0 = D / (2.0 * B)
    A0 = A + B * x0 ** 2  # s^2 = A0 - B (x - x0)^2 - C y^2
    if not A0 > 0:
        return nan
    return float(np.sqrt(A0 / B)), float(np.sqrt(A0 / C)), float(x0)


class FE3DTrial:
    """A prepared step of an FEContact3D (:meth:`FEContact3D.prepare`); pure like ``step``. The
    tangential solve of the last u asked is kept, so ``commit`` after ``force`` at the same u
    costs nothing."""

    def __init__(self, law: FEContact3D, ctx: dict):
        self.law, self.ctx = law, ctx
        self._last = None

    def _at(self, u):
        u = float(u)
        if self._last is None or self._last[0] != u:
            self._last = (u, self.law._tangential(self.ctx, u, None))
        return self._last[1]

    def force(self, u):
        """(Fx, dFx/du) at displacement u (the law's measure), full body; dFx/du is the consistent
        tangent of the Coulomb increment at fixed pressure (``fem.solid3d.contact.tangential_slope``;
        for a dissimilar pair with coupling the pressure's own change with u is left out)."""
        res, _, (g, tr, r) = self._at(u)
        law = self.law
        with blas_threads(1):
            k = tangential_slope(law.rf.Dt, law.mi.A, g, law._qy_zero, tr.q, r)
        return res.Fx, 2.0 * k

    def commit(self, u):
        """(StepResult, FE3DState) of the step to displacement u, equal to ``step(state, u, ...)``."""
        res, new, _ = self._at(u)
        self.law.stats["steps"] += 1
        return res, new
