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
  (``fem.solid3d.coupled.solve_coupled3d``), so a tangential load moves the pressure and a normal
  load with friction locks tangential traction in (Spence 1975, J. Elasticity 5, 297);
- small sliding, quasi-static, rate-independent Coulomb friction with constant mu.

Displacement measure (``displacement``), as in ``fem.axisym.law``: "contact" (the command's default) the
half-space comparable tangential displacement, the plate displacement minus the bodies' series compliance
c_bulk F_x read at axis probes in both bodies and put back with Cerruti's half-space solution (``fem.bulk``;
here the probes' responses to every traction vertex, ``_bulk_rows``); "plate" the displacement of the
indenter's clamped top against the block's clamped bottom (the law's default). Under force control the
loop area, the stick zone and the force history do not depend on it (a series spring shears the loop).
The approach ``d`` is the plate approach in both; ``indentation`` its half-space counterpart (Boussinesq).
The probes see the finite block's bending under F_x, which no half-space has. Measured (the
sphere, full stick, h = a/4): the contact measure's stiffness is 0.977, 0.980, 0.981 of
Mindlin's 2 G* a on blocks of 10, 20, 40 a (the rest is the mesh error), the plate measure's
0.908, 0.943, 0.962 (``tests/test_contact3d.py``: 10 a and 20 a).

Stick zone (``mdr.stick``, onset 1/2 as for any traction; ``fem.solid3d.estimators``): along x from the
vertices on the symmetry plane (+x and -x separately), along y from those within ``SECTOR`` of the y axis;
``stick_nodes`` are the +x vertices (the protocol's one stick radius is the extent along +x).

Layout: the model (mesh, condensed bodies, probes, gaps: built once, read only) is ``fem.solid3d.model``;
what the vertex fields say (contact radius, area, extent, stick zone) ``fem.solid3d.estimators``; the keys
of a run's recorded fields ``fem.solid3d.runs``; this module the law: the assumptions of a run (friction,
traction direction, coupling, tilt) and its step.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, replace

import numpy as np

from common.assumptions import TRACTIONS, check_traction
from common.errors import InputError, nonnegative, positive
from mdr.law import History, StepResult
from mdr.protocol import check_loads
from mdr.materials import Materials
from mdr.profiles import FlatPunch, Profile, Sphere, TruncatedSphere
from meshes.axisym import CONTACT_EXTENT_DEFAULT
from meshes.half3d import H_CONTACT_3D_DEFAULT, H_CONTACT_3D_RANGE, Refinement

from fem.solid3d import estimators as est
from fem.solid3d import runs
from fem.solid3d.contact import WHOLE, RelativeFlexibility, coulomb_increment, predict, tangential_slope
from fem.solid3d.coupled import solve_coupled3d
from fem.solid3d.model import BLOCK_SIZE_DEFAULT, SECTOR, Model3D, build_model3d, normal_solution
from fem.stepping import frozen as _frozen, step_history
from fem.solvers import blas_threads

__all__ = ["BLOCK_SIZE_DEFAULT", "SECTOR", "TILT_MAX", "TRACTIONS", "FE3DState", "FEContact3D", "FE3DTrial",
           "Normal3D", "RelativeFlexibility"]

#: largest |tilt| (rad): the tilted gap theta * x is the small-slope linearisation of the rotation
#: (cos theta = 1 within 5e-5); the paper's bound on its flat faces' tilt is pi/3600 = 8.7e-4 rad
TILT_MAX = 1e-2


def check_assumptions(traction, coupling) -> tuple[str, bool]:
    check_traction(traction)
    if coupling not in (True, False):
        raise InputError(f"coupling must be True or False, got {coupling!r}")
    return traction, bool(coupling)


def _qy_zero(mi, traction) -> np.ndarray:
    """Vertices whose q_y is held at zero: the symmetry plane, or all under traction 'x'."""
    return mi.on_plane if traction == "free" else np.ones(mi.n, dtype=bool)


def check_tilt(tilt) -> float:
    if np.ndim(tilt) != 0 or not np.isfinite(tilt) or abs(float(tilt)) > TILT_MAX:
        raise InputError(f"tilt must be one finite number in [-{TILT_MAX:g}, {TILT_MAX:g}] rad (small slopes), "
                         f"got {tilt!r}")
    return float(tilt)


@dataclass(frozen=True)
class FE3DState:
    """History of the 3D law: tractions ``q`` (n, 2) and pressures ``p`` (n,) at the vertices (Pa),
    weighted slip ``P`` (n, 2) (m^3), tangential displacement ``u`` and approach ``d`` (m).
    ``dq`` (n, 2) and ``du``: the last step's increments of q and u, which only start the next
    step's iteration (``fem.solid3d.contact.predict``); the answer does not depend on them."""

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
    plate ``approach`` (m), ``contact_radius`` (m, ``fem.solid3d.estimators.contact_radius``)."""

    p: np.ndarray
    force: float
    approach: float
    contact_radius: float
    iterations: int


def _checked(profile, materials, mu, F_max, h_contact, contact_extent, displacement, tilt, traction, coupling):
    """The inputs of ``FEContact3D`` checked (InputError naming the parameter) and completed:
    (materials, mu, F_max, contact_extent, tilt, traction, coupling)."""
    if not isinstance(profile, (Sphere, TruncatedSphere, FlatPunch)):
        kind = profile.describe()["profile"] if isinstance(profile, Profile) else type(profile).__name__
        raise InputError(f"profile must be sphere, truncated or flat for the 3D model, got {kind!r}")
    flat = isinstance(profile, FlatPunch)
    tilt = check_tilt(tilt)
    if flat:
        if contact_extent is not None and contact_extent != 1.0:
            raise InputError("contact_extent is the punch face for the flat punch (1, its radius b); got "
                             f"{contact_extent!r}")
        contact_extent = 1.0
    elif contact_extent is None:
        contact_extent = CONTACT_EXTENT_DEFAULT
    m = materials if materials is not None else Materials()
    if displacement not in ("contact", "plate"):
        raise InputError(f"displacement must be 'contact' or 'plate', got {displacement!r}")
    traction, coupling = check_assumptions(traction, coupling)
    if np.ndim(mu) != 0:
        raise InputError(f"mu must be one number, got an array of shape {np.shape(mu)}")
    mu = float(nonnegative("mu", mu))
    if F_max is None and not flat:
        raise InputError("FEContact3D needs F_max (> 0, the largest normal force) to size its mesh")
    F_max = None if F_max is None else float(positive("F_max", F_max))
    if not H_CONTACT_3D_RANGE[0] <= h_contact <= H_CONTACT_3D_RANGE[1]:
        raise InputError(f"h_contact must be in [{H_CONTACT_3D_RANGE[0]:g}, {H_CONTACT_3D_RANGE[1]:g}] for the "
                         f"3D model, got {h_contact!r}")
    return m, mu, F_max, contact_extent, tilt, traction, coupling


def surface_heights(mi, surface) -> np.ndarray:
    """The heights ``surface(x, y)`` (m) at the interface's P2 nodes, finite and even in y (the half
    model's symmetry plane), else one-line errors."""
    x, y = mi.nodes.x, mi.nodes.y
    h, mirrored = (np.broadcast_to(np.asarray(surface(x, s * y), dtype=float), x.shape) for s in (1.0, -1.0))
    if not np.isfinite(h).all():
        raise InputError("surface: heights must be finite at every interface node")
    if np.max(np.abs(h - mirrored), initial=0.0) > 1e-9 * max(np.max(np.abs(h), initial=0.0), 1e-300):
        raise InputError("surface: heights must be even in y (the half model's symmetry plane y = 0)")
    return np.array(h)


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
    ``refine``, ``ring``, ``band``: the mesh's local refinements (``meshes.half3d.Refinement``, in
    units of a_ref): ``refine`` = (x, h, radius), the ball around (x, 0, 0), the loaded edge of a
    tilted flat face ((-1, h, radius) for the flat punch at theta > 0); ``ring`` = (r, width, h), the
    whole circle r, the slip annulus and contact edge of a partial-slip cycle (the sphere at
    F_x = mu F_N / 2: (0.9, 0.18, h) covers 0.72-1.08 a); ``band`` = (h, width, angle[, growth]),
    the arc |phi - pi| <= angle of the flat face's edge circle (the flat punch: its rim), the thin
    edge crescent of a face tilted far beyond theta_c (theta > 0 loads the -x side; it assumes the
    crescent lies within the band). Every h <= h_contact. The laws of :meth:`assuming` share them.

    The built model is ``model`` (``fem.solid3d.model.Model3D``), shared by :meth:`assuming`; the law
    adds the assumptions of a run and a cache of normal solutions per load (a memo: the answer does
    not depend on it). ``stats`` counts the steps and solves (diagnostics).
    """

    stick_onset = est.STICK_ONSET
    batch = ()
    #: how a dissimilar pair's coupled increment is solved (``fem.solid3d.coupled.solve_coupled3d``):
    #: "newton" (one Newton method on both problems) or "alternate" (the two solves in turn); the same
    #: equations to the solvers' tolerances
    coupled_method = "newton"

    def __init__(self, profile: Profile, materials: Materials | None = None, mu=0.2, *, F_max=None,
                 h_contact=H_CONTACT_3D_DEFAULT, contact_extent=None, block_size=None,
                 cache_dir=None, backend=None, displacement="plate", tilt=0.0, traction="free", coupling=True,
                 refine=None, ring=None, band=None):
        m, mu, F_max, contact_extent, tilt, traction, coupling = _checked(
            profile, materials, mu, F_max, h_contact, contact_extent, displacement, tilt, traction, coupling)
        model = build_model3d(profile, m, F_max=F_max, h_contact=h_contact, contact_extent=contact_extent,
                              block_size=block_size, refinement=Refinement(refine=refine, ring=ring, band=band),
                              displacement=displacement, cache_dir=cache_dir, backend=backend)
        self._assume(model, mu, traction, coupling, tilt)

    def _assume(self, model: Model3D, mu, traction, coupling, tilt, surface=None):
        """Set the model and the assumptions of a run (checked), with an empty normal cache (seeded
        with the model's aligned solution at F_max where the face is the profile's own)."""
        self.model, self.mu, self.traction, self.coupling, self.tilt = model, mu, traction, coupling, tilt
        self.surface = surface
        h = 0.0 if surface is None else model.mi.B @ surface_heights(model.mi, surface)
        self.gap0 = model.gap(tilt) - h  # the weighted initial gap of the (tilted) face
        self._gap0_aligned = model.gap0_aligned - h
        #: vertices whose q_y is held at zero: the symmetry plane, or every vertex under Mindlin's
        #: assumption (``traction="x"``)
        self._qy_zero = _qy_zero(model.mi, traction)
        self._normal_cache = {}
        self.stats = {"steps": 0, "trial_solves": 0, "newton": 0, "normal_solves": 0}
        if model.normal_at_F_max is not None and tilt == 0.0 and surface is None:
            p, dd, it = model.normal_at_F_max
            self._normal_cache[("F", float(f"{model.F_max:.13g}"), "aligned")] = self._normal3d(p, dd, it, True)
            self.stats["normal_solves"] = 1

    def assuming(self, *, traction=None, coupling=None, tilt=None) -> "FEContact3D":
        """The same model (mesh, flexibilities, probes shared, not copied: nothing is rebuilt) with
        another ``traction``, ``coupling`` or ``tilt`` (rad): the pair of runs isolates that
        assumption from the discretisation, and a tilt sweep pays for one set-up."""
        new = copy.copy(self)
        traction, coupling = check_assumptions(self.traction if traction is None else traction,
                                                self.coupling if coupling is None else coupling)
        tilt = self.tilt if tilt is None else check_tilt(tilt)
        cache = dict(self._normal_cache) if tilt == self.tilt else {}
        new._assume(self.model, self.mu, traction, coupling, tilt, self.surface)
        new._normal_cache, new.stats["normal_solves"] = cache, 0
        return new

    def with_surface(self, surface) -> "FEContact3D":
        """The same model and assumptions with heights ``surface(x, y)`` (m, vectorised over the
        interface nodes' coordinates; None: the profile's own face) added to the indenter's face towards
        the block: the gap shrinks by them (the rough half-space's convention, ``rough.normal``). The
        half model's symmetry plane y = 0 needs them even in y (checked at the nodes); the mesh must
        resolve them (an assumption: its elements are not refined for them)."""
        new = copy.copy(self)
        new._assume(self.model, self.mu, self.traction, self.coupling, self.tilt, surface)
        new.stats["normal_solves"] = 0
        return new

    # ----------------------------------------------------------------- info
    @property
    def profile(self) -> Profile:
        return self.model.profile

    @property
    def materials(self) -> Materials:
        return self.model.materials

    @property
    def displacement(self) -> str:
        return self.model.displacement

    @property
    def stick_nodes(self):
        return self.model.mi.r[self.model.rays["+x"]]

    @property
    def x_ray(self) -> np.ndarray:
        """The vertices on the symmetry plane with x >= 0, by increasing x (the +x axis)."""
        return self.model.rays["+x"]

    @property
    def n(self) -> int:
        return self.model.n

    @property
    def tilted(self) -> bool:
        return self.tilt != 0.0

    def describe(self) -> dict:
        m = self.model
        return {"law": "fem3d", "dofs": m.ndofs, "vertices": m.n, "displacement": m.displacement,
                "traction": self.traction, "coupling": self.coupling, "tilt": self.tilt,
                "mesh": dict(m.hmesh.params.as_dict(), key=m.hmesh.key), "backend": m.backend}

    def mesh_summary(self) -> dict:
        m = self.model
        return dict(m.hmesh.params.as_dict(), key=m.hmesh.key, cache=m.hmesh.info.get("cache"),
                    condensed=m.condensed)

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

    def indentation(self, nr: Normal3D) -> float:
        """Half-space comparable indentation (m) of a normal solution: the plate approach minus both
        bodies' compression between clamp and probe plus the half-space's below the probes
        (``fem.bulk.normal_indentation`` in 3D)."""
        return float(nr.approach - self.model.bulk["z"] @ nr.p)

    def plate_bulk_compliance(self, F_N) -> float:
        """c_bulk (m/N): the bodies' series compliance in the plate measure, from the axis probes and
        Cerruti's half-space solution (``fem.bulk``), weighted by the full-stick x tractions at F_N
        (> 0) of this law's face (``Model3D.stick_x_compliance``). Uses no half-space contact stiffness."""
        return self.model.stick_x_compliance(self.normal(F_N=float(positive("F_N", F_N))).p > 0)

    # ----------------------------------------------------------------- normal
    def _normal3d(self, p, dd, it, aligned) -> Normal3D:
        return Normal3D(p=p, force=WHOLE * float(self.model.mi.A @ p), approach=dd,
                        contact_radius=est.contact_radius(self.model, p, aligned), iterations=it)

    def normal(self, *, F_N=None, d=None, aligned=False) -> Normal3D:
        """Normal contact at full-body force F_N (> 0) or plate approach d, cached per value;
        ``aligned``: without the tilt (the reference of ``contact_area_fraction``)."""
        key = ("F", float(f"{F_N:.13g}")) if F_N is not None else ("d", float(f"{d:.13g}"))
        aligned = aligned or self.tilt == 0.0
        key = key + ("aligned",) if aligned else key
        res = self._normal_cache.get(key)
        if res is None:
            gap0 = self._gap0_aligned if aligned else self.gap0
            res = self._normal3d(*normal_solution(self.model, gap0, F_N=F_N, d=d), aligned)
            self._normal_cache[key] = res
            self.stats["normal_solves"] += 1
        return res

    # ------------------------------------------------------------------ step
    def step(self, state: FE3DState, u=None, *, d=None, F_N=None, Fx=None):
        """One step, pure (``state`` not modified): normal load ``F_N`` (N, >= 0) or ``d``; tangential
        ``u`` (m) or ``Fx`` (N, |Fx| < mu F_N). Returns (StepResult, FE3DState)."""
        check_loads("step", d=d, F_N=F_N, u=u, Fx=Fx)
        res, new, _ = self._tangential(self._normal_part(state, d, F_N), u, Fx)
        self.stats["steps"] += 1
        return res, new

    def prepare(self, state: FE3DState, *, d=None, F_N=None) -> "FE3DTrial":
        """The normal part of a step, for many trial tangential displacements (``mdr.protocol``;
        the apparatus): ``force(u)`` gives (Fx, dFx/du), ``commit(u)`` the result of
        ``step(state, u, ...)``. For identical materials (or ``coupling=False``) the normal
        contact is solved here once (cached per load); for a dissimilar pair with coupling the
        pressure depends on u, so each trial solves the coupled increment at its u."""
        check_loads("prepare", d=d, F_N=F_N)
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
        coupled = touching and self.model.rf.K is not None and self.coupling
        nr = None
        if touching and not coupled:
            with blas_threads(1):
                nr = self.normal(F_N=F_N) if F_N is not None else self.normal(d=d)
        return {"state": state, "F_N": F_N, "d": d, "touching": touching, "coupled": coupled, "nr": nr}

    def _coulomb(self, ctx, u, Fx):
        """The Coulomb increment of a step: (pressures p, normal solution or None, TangentialResult)."""
        state, F_N, d, nr = ctx["state"], ctx["F_N"], ctx["d"], ctx["nr"]
        m, mi = self.model, self.model.mi
        q0 = np.asarray(state.q)
        if ctx["coupled"]:  # dissimilar pair: both together
            if F_N is not None:  # (under approach control the Coulomb solve itself refuses)
                self._check_force_limit(Fx, F_N)
            q0, u0 = predict(state, mi.A, self.mu * np.asarray(state.p), u, Fx)
            p, dd, res, _ = solve_coupled3d(
                m.rf, self.gap0, mi.A, self.mu, np.asarray(state.P), self._qy_zero,
                F_n=None if F_N is None else F_N / WHOLE, d=d, u=u,
                F_t=None if Fx is None else Fx / WHOLE, q0=q0, u0=u0, method=self.coupled_method,
                p0=np.asarray(state.p) if np.any(np.asarray(state.p) > 0) else None)
            self.stats["normal_solves"] += 1
            m.check_rim(p)
            return p, self._normal3d(p, float(dd), 0, not self.tilted), res
        p = nr.p if nr is not None else np.zeros(self.n)
        self._check_force_limit(Fx, nr.force if nr is not None else 0.0)
        return p, nr, coulomb_increment(m.rf, mi.A, self.mu * p, np.asarray(state.P), self._qy_zero, state, u=u,
                                        Fx=Fx)

    def _tangential(self, ctx, u, Fx):
        """The tangential part of a step from :meth:`_normal_part`: returns (StepResult, FE3DState,
        (g, TangentialResult, slip increments)) for the trial's slope."""
        state, d = ctx["state"], ctx["d"]
        if u is not None:
            u = float(u)
            if not np.isfinite(u):
                raise InputError(f"u must be finite, got {u!r}")
        with blas_threads(1):
            p, nr, res = self._coulomb(ctx, u, Fx)
        m = self.model
        g = self.mu * p
        work = WHOLE * float(np.sum((res.q * (res.s - np.asarray(state.P)))[g > 0]))
        slack, slipping = est.slip_state(g, res.q)
        ray = m.rays["+x"]
        a = nr.contact_radius if nr is not None else 0.0
        c = est.stick_radius_x(m, slack, slipping, p, a, self.tilted)
        self.stats["trial_solves"] += 1
        self.stats["newton"] += res.iterations
        new = FE3DState(q=_frozen(res.q), P=_frozen(res.s), p=_frozen(p), u=float(res.u),
                        d=float(nr.approach if nr is not None else (d or 0.0)),
                        dq=_frozen(res.q - np.asarray(state.q)), du=float(res.u) - float(state.u))
        return StepResult(Fx=WHOLE * float(m.mi.A @ res.q[:, 0]), FN=nr.force if nr is not None else 0.0, d=new.d,
                          a=a, c=c, u=new.u, work=work, slack=slack[ray], slipping=slipping[ray]), new, \
            (g, res, res.s - np.asarray(state.P))

    def _check_force_limit(self, Fx, FN):
        """A prescribed tangential force must stay below mu F_N (no force-controlled gross slip)."""
        if Fx is not None and Fx != 0.0 and abs(Fx) >= self.mu * FN * (1 - 1e-12):
            raise InputError(f"tangential force Fx={Fx:.4g} N must stay below the friction limit "
                             f"mu*F_N={self.mu * FN:.4g} N under force control")

    # ------------------------------------------------------------------ runs
    def run(self, u=None, *, F_N=None, d=None, Fx=None, state: FE3DState | None = None,
            record_from: int | None = None) -> History:
        """A load history (arrays (T,)); returns mdr.law.History whose ``fields`` hold the vertex
        tractions ``q`` and pressures ``p`` of every step (tuples of T read-only arrays), read by
        ``fem.solid3d.runs``."""
        q, p = [], []

        def keep(t, res, st):
            q.append(st.q)
            p.append(st.p)

        H = step_history(self, self.model.rays["+x"].size, u=u, F_N=F_N, d=d, Fx=Fx, state=state,
                         record_from=record_from, on_step=keep)
        return replace(H, fields={"q": tuple(q), "p": tuple(p)})

    # ------------------------------------------------------------------ keys
    def result_keys(self, F_N, t0, t1, t2, F_peak=None) -> dict:
        """The keys of this law that need no run (``fem.solid3d.runs.law_keys``)."""
        return runs.law_keys(self, F_N, t0, t1, t2, F_peak)

    def tilt_keys(self, F_N) -> dict:
        """The contact's area fraction and extent at F_N (``fem.solid3d.runs.tilt_keys``)."""
        return runs.tilt_keys(self, F_N)

    def stick_zone(self, q, p, a) -> dict:
        """``fem.solid3d.estimators.stick_zone`` of tractions q and pressures p at contact radius a
        under this law's friction and tilt."""
        return est.stick_zone(self.model, self.mu, q, p, a, self.tilted)


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
            k = tangential_slope(law.model.rf, law.model.mi.A, g, law._qy_zero, tr.q, r)
        return res.Fx, WHOLE * k

    def commit(self, u):
        """(StepResult, FE3DState) of the step to displacement u, equal to ``step(state, u, ...)``."""
        res, new, _ = self._at(u)
        self.law.stats["steps"] += 1
        return res, new
