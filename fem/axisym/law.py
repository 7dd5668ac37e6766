"""The FE frictional contact law: the contact-law protocol of ``mdr.protocol`` on the FE model.

One object holds the two-body axisymmetric FE model of a profile (mode 0 for
the pressure, ``fem.axisym.model``/``fem.axisym.normal``; mode 1 for the tangential load,
``fem.axisym.mode1``), condensed once to the contact pairs. A step is a pure function
of an explicit, immutable state (:class:`FEState`), exactly like
``mdr.law.MDRContact.step``:

1. normal: mode 0 is solved at the step's normal force F_N (or plate approach
   d); its pair forces lam_i set the slip limits g_i = mu lam_i (results are
   cached per load value, so constant-load cycles solve it once);
2. tangential: one return-map increment on the condensed interface
   (``fem.axisym.friction``) to the plate displacement u or total force Fx. Pairs
   out of contact (lam_i = 0) carry no force and their plastic slip follows
   the relative displacement, so a pair entering contact starts unstrained and
   a pair leaving releases its force.

Boundary conditions of mode 1: block bottom clamped; the indenter's top face
is a rigid plate translated by u along x (no tilt, D = W = 0 there); D = W = 0
on the axis. No mode-1 normal traction is transmitted (Mindlin's assumption:
no normal-tangential coupling).

Displacement measure (docs/design.md, section 4). The law's ``u`` is the x translation
of the indenter's top plate relative to the clamped block bottom: it contains
the tangential compliance of the finite bodies, which a half-space (MDR, Mindlin)
does not have. Far from the contact this extra compliance responds to the
resultant force only: it is a linear spring c_bulk in series with the contact,
u = u_contact + c_bulk Fx. A series spring stores and returns energy without
dissipating, and the map (u, Fx) -> (u - c_bulk Fx, Fx) is a shear of the loop
plane, which preserves areas: under force control the dissipation, the stick
radius and the force history equal the half-space ones; under displacement
control a loop of plate amplitude u_A is the half-space loop of amplitude
u_A - c_bulk Fx_A. c_bulk is measured as the normal indentation's bulk
correction is (``fem.bulk.normal_indentation``): FE x displacements at axis probes in both
bodies plus Cerruti's half-space displacement there for the FE's own pair
forces; the definition, its probe depth and its measured mesh and F_N
dependence are in ``fem.bulk`` (the only place). It uses no half-space contact
stiffness, so the FE's initial tangential stiffness in this measure is a
result, not an input (:meth:`FEContact.plate_bulk_compliance`,
:meth:`FEContact.bulk_compliance`, :meth:`FEContact.contact_displacement`).

Approach ``d`` (input and output) is the plate approach of ``fem.axisym.normal``
(also including the bulk compliance); force control ``F_N`` is the clean input.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from common.errors import ConvergenceError, InputError, nonnegative, positive, positive_int
from mdr.law import History, StepResult
from mdr.materials import Materials
from mdr.profiles import FlatPunch, Profile
from mdr.stick import at_limit, per_step
from meshes.axisym import H_CONTACT_DEFAULT

from fem.bulk import DEFAULT_PROBE_DEPTH, axis_point, bulk_probe, contact_from_plate
from fem.condense import Condensation
from fem.axisym.friction import DEFAULT_FRICTION_AL_TOL, _Factors, slip_update, solve_increment
from fem.axisym.mode1 import fixed_dofs_mode1, node_dofs_mode1, stiffness_mode1
from fem.axisym.model import build_model
from fem.axisym.normal import DEFAULT_AL_TOL, DEFAULT_PENALTY, penalty_stiffness, solve_normal
from fem.solvers import blas_threads



def _frozen(a):
    a = np.array(a, dtype=float if np.asarray(a).dtype.kind == "f" else np.asarray(a).dtype)
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class FEState:
    """History of the FE contact (read-only arrays over the n pairs): tangential pair forces
    ``T`` (N), plastic slip ``p`` (m), normal pair forces ``lam`` (N), last sliding sets
    ``sgn`` (warm start), plate displacement ``u`` and approach ``d`` (m)."""

    T: np.ndarray
    p: np.ndarray
    lam: np.ndarray
    sgn: np.ndarray
    u: float
    d: float


class FEContact:
    """FE contact law of one profile and two materials (the protocol of ``mdr.protocol``).

    Parameters: ``profile`` (mdr Profile: Sphere, TruncatedSphere, FlatPunch),
    ``materials``, ``mu``; ``F_max`` the largest normal force (sizes the mesh's
    contact segment, a_ref = its half-space contact radius; not needed for the
    flat punch); mesh options ``h_contact`` (element size / a_ref), ``contact_extent``,
    ``block_size``, ``cache_dir`` (further ``meshes.AxisymMeshParams`` fields as keywords); ``penalty`` (dimensionless, eps = penalty E*/h
    for normal and tangential pairs), ``al_tol`` (normal augmented Lagrangian),
    ``friction_al_tol`` (tangential: largest multiplier change / largest slip
    limit; 0 = pure penalty), ``friction_exact_start`` (True: the tangential AL starts
    from the exact Coulomb solution, :meth:`_tangential`; False: the classical start from
    the previous forces), ``backend`` (sparse solver), ``displacement``:
    ``"plate"`` (default: u is the plate displacement) or ``"contact"`` (u is the
    half-space comparable u_plate - c_bulk Fx of ``fem.bulk``, c_bulk taken at
    F_max (its F_N dependence is below 2 %, 3e-4 of the contact compliance);
    the flexibility becomes Ct - c_bulk 1 1^T, still symmetric positive definite
    because c_bulk is ~1 % of the contact's full-stick compliance);
    ``bulk_probe_depth``: depth of the axis probes of ``fem.bulk`` / a_ref. Use
    ``"contact"`` to put the FE law where a half-space law is expected (e.g. in
    the apparatus model, whose machine compliances would otherwise also get the
    FE bodies' bulk compliance).
    """

    def __init__(self, profile: Profile, materials: Materials | None = None, mu=0.2, *, F_max=None,
                 h_contact=H_CONTACT_DEFAULT, contact_extent=1.25, block_size=None, cache_dir=None,
                 penalty=DEFAULT_PENALTY, al_tol=DEFAULT_AL_TOL, friction_al_tol=DEFAULT_FRICTION_AL_TOL,
                 backend=None, max_al=50, displacement="plate", bulk_probe_depth=DEFAULT_PROBE_DEPTH,
                 friction_exact_start=True, **mesh_kw):
        from meshes import cached_mesh

        from fem.axisym.normal_run import mesh_params

        if not isinstance(profile, Profile) or profile.describe().get("profile") == "general":
            raise InputError(f"profile must be a Sphere, TruncatedSphere or FlatPunch, got {profile!r}")
        t0 = time.perf_counter()
        self.profile = profile
        self.materials = materials if materials is not None else Materials()
        if np.ndim(mu) != 0:
            raise InputError(f"mu must be one number (the FE law has no batch), got an array of shape {np.shape(mu)}")
        self.mu = float(nonnegative("mu", mu))
        self.penalty = float(positive("penalty", penalty))
        self.al_tol = float(nonnegative("al_tol", al_tol))
        self.friction_al_tol = float(nonnegative("friction_al_tol", friction_al_tol))
        self.max_al = positive_int("max_al", max_al)
        if not isinstance(friction_exact_start, (bool, np.bool_)):
            raise InputError(f"friction_exact_start must be True or False, got {friction_exact_start!r}")
        self.friction_exact_start = bool(friction_exact_start)
        if displacement not in ("plate", "contact"):
            raise InputError(f"displacement must be 'plate' or 'contact', got {displacement!r}")
        self.displacement = displacement
        if np.ndim(bulk_probe_depth) != 0 or not np.isfinite(bulk_probe_depth):
            raise InputError(f"bulk_probe_depth must be one finite number (probe depth / a_ref, in (contact_extent, "
                             f"0.8 * body height / a_ref)), got {bulk_probe_depth!r}")
        self.bulk_probe_depth = float(bulk_probe_depth)
        desc = profile.describe()
        kind = "truncated" if desc["profile"] == "rounded" else desc["profile"]  # a rounded kink: the sharp cap's mesh
        R, b = desc.get("R"), float(desc.get("b") or 0.0)
        if isinstance(profile, FlatPunch):
            F_ref = 1.0 if F_max is None else F_max
        else:
            if F_max is None:
                raise InputError("FEContact needs F_max (> 0, the largest normal force) to size its mesh")
            F_ref = F_max
        F_ref = positive("F_max", F_ref)
        self.F_max = F_ref
        params = mesh_params(kind, R, b, F_ref, self.materials, h_contact=h_contact, block_size=block_size,
                             contact_extent=contact_extent, **mesh_kw)
        self.amesh = cached_mesh(params, cache_dir)
        t1 = time.perf_counter()
        self.model = build_model(self.amesh, self.materials, profile, backend=backend)
        self._build_mode1(backend)
        it = self.model.interface
        self.k = penalty_stiffness(self.penalty, self.materials.E_star, it)
        self._normal_cache = {}
        # steps: committed steps; trial_solves: tangential return-map solves (an apparatus step tries
        # several displacements before it commits one); newton, al: iterations of those solves
        self.stats = {"steps": 0, "trial_solves": 0, "newton": 0, "al": 0, "normal_solves": 0, "al_change_max": 0.0}
        self.c_bulk = 0.0
        if displacement == "contact":
            # u measured without the bodies' series compliance: s = u_c + (c_bulk 1 1^T - Ct) T
            self.c_bulk = self.plate_bulk_compliance(F_ref)
            self.Ct = self.Ct - self.c_bulk
        self.M = self.Ct + np.diag(1.0 / self.k)
        self._fac = _Factors(self.M, size=16)
        self._fac_exact = _Factors(self.Ct, size=16)  # the AL's limit (exact Coulomb): Ct itself
        self.timings = {"mesh": t1 - t0, "setup": time.perf_counter() - t1}

    # ----------------------------------------------------------------- model
    def _build_mode1(self, backend):
        it = self.model.interface
        m = self.materials
        bodies = self.model.bodies
        # tangential bulk correction (fem.bulk): axis probes at depth L in each body
        p = self.amesh.params
        L = self.bulk_probe_depth * p.a_ref
        lo, hi = p.r_contact / p.a_ref, 0.8 * min(p.block_height, p.indenter_height) / p.a_ref
        if not lo < self.bulk_probe_depth < hi:
            raise InputError(f"bulk_probe_depth must be in ({lo:.4g}, {hi:.4g}) (probe depth / a_ref: beyond the "
                             f"contact segment, inside both bodies), got {self.bulk_probe_depth!r}")
        out, rows = {}, {}
        for name, E, nu, z in (("indenter", m.E1, m.nu1, L), ("block", m.E2, m.nu2, -L)):
            mesh = bodies[name].mesh
            K, basis = stiffness_mode1(mesh, E, nu)
            dofs = node_dofs_mode1(basis)
            fixed = fixed_dofs_mode1(mesh, basis, "top" if name == "indenter" else "bottom")
            nodes = it.ind_nodes if name == "indenter" else it.blk_nodes
            pnodes, wts = axis_point(mesh, z)
            cond = Condensation(K, fixed, dofs[0, nodes],
                                probe_dofs=dofs[0, pnodes], backend=backend)
            rows[name] = wts @ cond.P
            out[name] = (K, basis, dofs, cond)
        self.mode1 = out
        N = it.N
        C2 = out["block"][3].C
        self.Ct = out["indenter"][3].C + N @ (N @ C2).T
        self.Ct = 0.5 * (self.Ct + self.Ct.T)
        self.Ct_plate = self.Ct.copy()
        self.bulk = bulk_probe(it, m, rows, L)

    @property
    def dofs(self) -> int:
        """Total DOFs of the mode-0 and mode-1 models of both bodies."""
        return int(self.model.dofs + sum(v[1].N for v in self.mode1.values()))

    @property
    def n_pairs(self) -> int:
        return self.model.interface.n

    def describe(self) -> dict:
        p = self.amesh.params
        return {"law": "fem", "dofs": self.dofs, "pairs": self.n_pairs, "penalty": self.penalty,
                "al_tol": self.al_tol, "friction_al_tol": self.friction_al_tol,
                "displacement": self.displacement, "c_bulk": self.c_bulk,
                "bulk_probe_depth": self.bulk_probe_depth,
                "mesh": dict(p.as_dict(), key=self.amesh.key), "backend": self.model.backend}

    def solver_summary(self) -> dict:
        """Solver settings and counters of the steps run so far (the ``solver`` key of results).

        ``friction_penalty_error``: the largest last multiplier change / largest slip limit
        (pure penalty: the relative size of the penalty's elastic slip). ``steps`` counts committed
        steps, ``trial_solves`` the return-map solves (more than the steps in the apparatus, whose
        equilibrium tries several displacements per step); ``*_per_step`` are per committed step,
        ``*_per_solve`` per solve."""
        st, n, ns = self.stats, max(self.stats["steps"], 1), max(self.stats["trial_solves"], 1)
        return {"backend": self.model.backend, "pairs": self.n_pairs, "penalty": self.penalty,
                "al_tol": self.al_tol, "friction_al_tol": self.friction_al_tol, "steps": st["steps"],
                "trial_solves": st["trial_solves"], "newton_per_step": st["newton"] / n,
                "al_per_step": st["al"] / n, "newton_per_solve": st["newton"] / ns, "al_per_solve": st["al"] / ns,
                "normal_solves": st["normal_solves"], "friction_penalty_error": st["al_change_max"]}

    def result_keys(self, F_N, t0, t1, t2) -> dict:
        """The keys every FE run adds to its law-independent result (``python -m fem contact``,
        ``python -m mdr apparatus --law fem``, the validation runner; the one home of this
        post-processing): ``contact_radius``, ``pressure_radius`` and ``indentation``, the FE's own
        at ``F_N`` (half-space comparable, ``fem.axisym.normal``), ``bulk_compliance`` (m/N, the bodies' series
        compliance in the plate measure at ``F_N``: plate = contact + bulk_compliance * Fx,
        :meth:`plate_bulk_compliance`), ``dofs``, ``mesh``, ``solver`` and ``runtime_s``
        {setup, cycles, total} from the times t0 (start), t1 (law set up), t2 (runs done)."""
        nr = self.normal(F_N=F_N)
        return {"contact_radius": float(nr.contact_radius), "pressure_radius": float(nr.pressure_radius),
                "indentation": float(nr.indentation), "bulk_compliance": self.plate_bulk_compliance(F_N),
                "dofs": self.dofs, "mesh": self.mesh_summary(), "solver": self.solver_summary(),
                "runtime_s": {"setup": t1 - t0, "cycles": t2 - t1, "total": t2 - t0}}

    def mesh_summary(self) -> dict:
        """The mesh parameters, cache key and cache use (the ``mesh`` key of results)."""
        return dict(self.amesh.params.as_dict(), key=self.amesh.key, cache=self.amesh.info.get("cache"))

    # ----------------------------------------------------------------- state
    def contact_at(self, F_N) -> dict:
        """``mdr.protocol.ContactLaw.contact_at``: the FE's own contact radius and half-space comparable
        indentation (``fem.axisym.normal``) at ``F_N``."""
        nr = self.normal(F_N=F_N)
        return {"contact_radius": float(nr.contact_radius), "indentation": float(nr.indentation)}

    def normal_load(self, F_N) -> dict:
        """Normal forces as ``prepare``/``step`` take them (``mdr.protocol``): the force, solved per step."""
        return {"F_N": np.asarray(F_N, dtype=float)}

    def rest_state(self) -> FEState:
        n = self.n_pairs
        z = _frozen(np.zeros(n))
        return FEState(T=z, p=z, lam=z, sgn=_frozen(np.zeros(n, dtype=np.int8)), u=0.0, d=0.0)

    def plate_bulk_compliance(self, F_N) -> float:
        """c_bulk (m/N) at normal force F_N (> 0) in the plate measure: the bodies' series compliance
        from the axis probes and Cerruti's half-space solution (``fem.bulk``), weighted by the
        full-stick pair forces at F_N. Uses no half-space contact stiffness."""
        res = self.normal(F_N=float(positive("F_N", F_N)))
        return self.bulk.scalar(self.Ct_plate, res.lam > 0)

    def bulk_compliance(self, F_N) -> float:
        """c_bulk (m/N) at F_N still contained in the law's displacement ``u``: the plate measure's
        :meth:`plate_bulk_compliance` minus the ``c_bulk`` already removed (``displacement="contact"``:
        c_bulk at F_max, so this is its F_N dependence only, below 2 % of c_bulk)."""
        return self.plate_bulk_compliance(F_N) - self.c_bulk

    def contact_displacement(self, u, Fx, F_N):
        """Half-space-comparable displacement u - bulk_compliance(F_N) Fx of the law's u (see
        ``fem.bulk``); F_N <= 0 (no contact) leaves u unchanged."""
        F_N = np.asarray(F_N, dtype=float)
        cb = np.vectorize(lambda f: self.bulk_compliance(f) if f > 0 else 0.0)(F_N)
        return contact_from_plate(np.asarray(u, dtype=float), np.asarray(Fx, dtype=float), cb)

    def normal(self, *, F_N=None, d=None):
        """Mode-0 normal result at force F_N (> 0) or plate approach d (> 0), cached."""
        key = ("F", float(f"{F_N:.13g}")) if F_N is not None else ("d", float(f"{d:.13g}"))
        res = self._normal_cache.get(key)
        if res is None:
            if len(self._normal_cache) > 4096:
                self._normal_cache.clear()
            res = solve_normal(self.model, force=F_N, approach=d, penalty=self.penalty, al_tol=self.al_tol)
            self.stats["normal_solves"] += 1
            self._normal_cache[key] = res
        return res

    # ------------------------------------------------------------------ step
    def step(self, state: FEState, u=None, *, d=None, F_N=None, Fx=None):
        """Advance by one step; pure (``state`` is not modified). Normal load as plate
        approach ``d`` (m) or force ``F_N`` (N, >= 0; 0 = contact lost, history released);
        tangential load as plate displacement ``u`` (m) or force ``Fx`` (N, |Fx| < mu F_N).
        Returns (mdr.law.StepResult, FEState)."""
        if (d is None) == (F_N is None):
            raise InputError("step needs exactly one of d (approach) or F_N (normal force)")
        if (u is None) == (Fx is None):
            raise InputError("step needs exactly one of u (tangential displacement) or Fx (tangential force)")
        if Fx is None:
            u = float(u)
            if not np.isfinite(u):
                raise InputError(f"u must be finite, got {u!r}")
        else:
            Fx = float(Fx)
            if not np.isfinite(Fx):
                raise InputError(f"Fx must be finite, got {Fx!r}")
        ctx = self._normal_part(state, d, F_N)
        ctx["u"] = u
        res, new = self._finish(ctx, self._tangential(ctx, u, Fx))
        self.stats["steps"] += 1
        return res, new

    def prepare(self, state: FEState, *, d=None, F_N=None) -> "FETrial":
        """Normal part of a step, for many trial tangential displacements (as
        ``mdr.law.MDRContact.prepare``): ``force(u)`` gives (Fx, dFx/du), ``commit(u)``
        the result of ``step(state, u, ...)``. Lets the apparatus use Newton steps."""
        if (d is None) == (F_N is None):
            raise InputError("prepare needs exactly one of d (approach) or F_N (normal force)")
        return FETrial(self, self._normal_part(state, d, F_N))

    def _normal_part(self, state, d, F_N):
        n = self.n_pairs
        if F_N is not None:
            F_N = float(nonnegative("F_N (normal force; no adhesion, so >= 0)", F_N))
            lost = F_N == 0.0
        else:
            d = float(d)
            if not np.isfinite(d):
                raise InputError(f"d must be finite, got {d!r}")
            lost = d <= 0.0
        if lost:
            lam = np.zeros(n)
            FN, dd, a = 0.0, (0.0 if d is None else d), 0.0
        else:
            res = self.normal(F_N=F_N, d=d)
            lam, FN, dd, a = res.lam, res.force, res.approach, res.contact_radius
        T_old = np.asarray(state.T)
        s_old = state.u - self.Ct @ T_old
        g = self.mu * lam
        contact = g > 0
        any_contact = bool(contact.any())
        return {"state": state, "lam": lam, "FN": FN, "d": dd, "a": a, "g": g, "T_old": T_old,
                "p_old": np.where(np.asarray(state.lam) > 0, state.p, s_old), "contact": contact,
                "any_contact": any_contact, "gmax": float(g.max()) if any_contact else 0.0,
                "sgn_old": np.asarray(state.sgn), "u": None}

    def _tangential(self, ctx, u, Fx):
        """Tangential return map of a step at plate displacement ``u`` or force ``Fx``: the
        solve only, returns the dict of :meth:`_finish` (no contact: None) with the forces
        ``T``, displacement ``u``, sets ``sgn``, last multipliers ``lbar`` and the tangent
        ``slope`` dFx/du of the stick set.

        Augmented Lagrangian (``fem.axisym.friction``): passes lbar <- T until the largest change is
        below ``friction_al_tol`` of the largest slip limit. Its limit lbar = T is the exact
        Coulomb return map: the box QP of ``fem.axisym.friction`` with M = Ct (no penalty) and
        b = -p_old, whose active-set iteration has the same set test as an AL pass at that
        limit. With ``friction_exact_start`` that problem is solved first and its forces
        start the AL, so the first pass normally meets the tolerance (it then checks the
        solution, and carries on from it if not; should that solve fail, the classical start
        is taken); otherwise the passes start from the
        previous forces clipped to the new limits (about four passes at the default
        tolerance). The tangent is that of the map the passes converge to: sum Ct_ff^-1 1
        over the sticking pairs f with the exact start (the AL limit), sum M_ff^-1 1 without
        (one pass, the classical path), and with the pure penalty."""
        n = self.n_pairs
        FN, g = ctx["FN"], ctx["g"]
        T_old, p_old = ctx["T_old"], ctx["p_old"]
        if Fx is not None and abs(Fx) >= self.mu * FN * (1 - 1e-12) and Fx != 0.0:
            raise InputError(f"tangential force Fx={Fx:.4g} N must stay below the friction limit "
                             f"mu*F_N={self.mu * FN:.4g} N under force control")
        contact = ctx["contact"]
        if not ctx["any_contact"]:
            return None
        k = self.k
        sgn = ctx["sgn_old"]
        newton = 0
        exact = self.friction_al_tol > 0 and self.friction_exact_start
        with blas_threads(1):
            if exact:
                try:
                    lbar, _, sgn, nit, _ = solve_increment(self.Ct, self._fac_exact, -p_old, g, k, sgn, u=u, F=Fx)
                    newton += nit
                except (ConvergenceError, np.linalg.LinAlgError):  # the classical start below instead
                    exact = False
            if not exact:
                lbar = np.clip(T_old, -g, g) if self.friction_al_tol > 0 else np.zeros(n)
            for n_al in range(1, self.max_al + 1):
                b = lbar / k - p_old
                T, uu, sgn, nit, trial = solve_increment(self.M, self._fac, b, g, k, sgn, u=u, F=Fx)
                newton += nit
                change = float(np.max(np.abs(T - lbar)) / ctx["gmax"])
                if self.friction_al_tol == 0 or change <= self.friction_al_tol:
                    break
                lbar = T
            else:
                raise ConvergenceError(f"friction augmented Lagrangian: multiplier change {change:.3g} of "
                                       f"mu max(lam) after {self.max_al} passes (friction_al_tol="
                                       f"{self.friction_al_tol:g})")
            free = (sgn == 0) & contact
            slope = ((self._fac_exact if exact else self._fac).get(free).ysum if free.any() else 0.0)
        self.stats["trial_solves"] += 1
        self.stats["newton"] += newton
        self.stats["al"] += n_al
        self.stats["al_change_max"] = max(self.stats.get("al_change_max", 0.0), change)
        return {"T": T, "u": float(uu), "sgn": sgn, "lbar": lbar, "slope": float(slope), "Fx": float(T.sum())}

    def _finish(self, ctx, sol):
        """(StepResult, FEState) of a solved step (``sol`` from :meth:`_tangential`): the slip
        update, the slack to the slip limit, the slip flags and the stick radius of the step."""
        n = self.n_pairs
        state, lam, FN, dd, a, g = ctx["state"], ctx["lam"], ctx["FN"], ctx["d"], ctx["a"], ctx["g"]
        if sol is None:  # no pair in contact: no force, the plastic slip follows the plate
            uu = state.u if ctx["u"] is None else ctx["u"]
            z = np.zeros(n)
            new = FEState(T=_frozen(z), p=_frozen(np.full(n, uu)), lam=_frozen(z),
                          sgn=_frozen(np.zeros(n, dtype=np.int8)), u=float(uu), d=float(dd))
            return StepResult(Fx=0.0, FN=FN, d=dd, a=a, c=0.0, u=float(uu), work=0.0, slack=z,
                              slipping=np.ones(n, dtype=bool)), new
        T, uu, sgn = sol["T"], sol["u"], sol["sgn"]
        contact = ctx["contact"]
        s = uu - self.Ct @ T
        p_new, work = slip_update(s, T, sol["lbar"], self.k, contact, ctx["p_old"])
        w = self.model.interface.w
        slack = np.where(contact, (g - np.abs(T)) / w, 0.0)  # mu p - |tau| at the pairs
        slipping = (sgn != 0) | ~contact | at_limit(slack, g / w)
        c = float(per_step(self.stick_nodes, slack, slipping, a, self.stick_onset))
        new = FEState(T=_frozen(T), p=_frozen(p_new), lam=_frozen(lam), sgn=_frozen(sgn),
                      u=float(uu), d=float(dd))
        return StepResult(Fx=sol["Fx"], FN=float(FN), d=float(dd), a=float(a), c=c, u=float(uu),
                          work=work, slack=slack, slipping=slipping), new

    #: the traction slack mu p - |tau| falls as sqrt(c - r) towards a stick edge (``mdr.stick``)
    stick_onset = 0.5
    #: one scene per law (``mdr.protocol``: the batch shape)
    batch = ()

    @property
    def stick_nodes(self):
        """Radii of the contact pairs, the nodes the stick radius is resolved on."""
        return self.model.interface.r

    # ------------------------------------------------------------------ runs
    def run(self, u=None, *, F_N=None, d=None, Fx=None, state: FEState | None = None,
            record_from: int | None = None) -> History:
        """Run a load history (arrays of shape (T,)); returns mdr.law.History. ``record_from``
        (a step index): keep the pairs' slack and slip flags from there on (``mdr.stick``)."""
        with blas_threads(1):
            return step_history(self, self.n_pairs, u=u, F_N=F_N, d=d, Fx=Fx, state=state, record_from=record_from)


def step_history(law, n_nodes, *, u=None, F_N=None, d=None, Fx=None, state=None, record_from=None,
                 on_step=None) -> History:
    """The ``run`` of a law that advances one ``step`` at a time (the FE laws): a load history of
    arrays (T,) from ``state`` (default the law's rest state); the slack and slip flags of the
    ``n_nodes`` stick nodes kept from step ``record_from`` on; ``on_step(t, result, state)``
    called after every step. Returns mdr.law.History."""
    if (d is None) == (F_N is None):
        raise InputError("run needs exactly one of d (approach history) or F_N (normal force history)")
    if (u is None) == (Fx is None):
        raise InputError("run needs exactly one of u (displacement history) or Fx (force history)")
    drive = np.atleast_1d(np.asarray(u if u is not None else Fx, dtype=float))
    nT = drive.shape[-1]
    normal = np.broadcast_to(np.asarray(F_N if F_N is not None else d, dtype=float), (nT,))
    state = state if state is not None else law.rest_state()
    out = {k: np.empty(nT) for k in ("u", "Fx", "FN", "d", "a", "c", "work")}
    rec0 = nT if record_from is None else int(record_from)
    if not 0 <= rec0 <= nT:
        raise InputError(f"record_from must be a step index in [0, {nT}], got {record_from!r}")
    rec = {"slack": np.empty((nT - rec0, n_nodes)), "slipping": np.empty((nT - rec0, n_nodes), bool)}
    for t in range(nT):
        kw = {"F_N": normal[t]} if F_N is not None else {"d": normal[t]}
        res, state = law.step(state, **({"u": drive[t]} if u is not None else {"Fx": drive[t]}), **kw)
        for key in out:
            out[key][t] = getattr(res, key)
        if t >= rec0:
            rec["slack"][t - rec0] = res.slack
            rec["slipping"][t - rec0] = res.slipping
        if on_step is not None:
            on_step(t, res, state)
    return History(state=state, **out, **(rec if record_from is not None else {}))


class FETrial:
    """A prepared step of an FEContact (see :meth:`FEContact.prepare`); pure like ``step``."""

    def __init__(self, law: FEContact, ctx: dict):
        self.law, self.ctx = law, ctx
        self._last = None

    def _at(self, u):
        u = float(u)
        if not np.isfinite(u):
            raise InputError(f"u must be finite, got {u!r}")
        if self._last is None or self._last[0] != u:
            self._last = (u, self.law._tangential(self.ctx, u, None))
        return self._last[1]

    def force(self, u):
        """(Fx, dFx/du) at plate (or contact) displacement u; dFx/du is the stick-set tangent."""
        sol = self._at(u)
        return (0.0, 0.0) if sol is None else (sol["Fx"], sol["slope"])

    def commit(self, u):
        """(StepResult, FEState) of the step to displacement u (counted as a committed step);
        the slip update and the step's stick radius are worked out here, not for every trial."""
        sol = self._at(u)
        res, new = self.law._finish(dict(self.ctx, u=float(u)), sol)
        self.law.stats["steps"] += 1
        return res, new
