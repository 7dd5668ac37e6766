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

Layout: this module holds the law (``FEContact``: setup, protocol methods, reports); one step as
functions of the law and a state (``FEState``, the normal part, the return map, the result,
``FETrial``) is in ``fem.axisym.law_step``, and ``frozen``/``step_history``, which the 3D law
shares, in ``fem.stepping``; all of them are importable from here.
"""
from __future__ import annotations

import time

import numpy as np

from common.errors import InputError, nonnegative, positive, positive_int
from mdr.law import History
from mdr.protocol import check_loads
from mdr.materials import Materials
from mdr.profiles import FlatPunch, Profile
from meshes.axisym import CONTACT_EXTENT_DEFAULT, H_CONTACT_DEFAULT

from fem.bulk import DEFAULT_PROBE_DEPTH, axis_point, bulk_probe, contact_from_plate
from fem.condense import Condensation
from fem.axisym.friction import DEFAULT_FRICTION_AL_TOL, SetFactors
from fem.axisym.law_step import FEState, FETrial, finish, normal_part, tangential
from fem.axisym.mode1 import fixed_dofs_mode1, node_dofs_mode1, stiffness_mode1
from fem.axisym.model import build_model
from fem.axisym.normal import DEFAULT_AL_TOL, DEFAULT_PENALTY, penalty_stiffness, solve_normal
from fem.solvers import blas_threads
from fem.stepping import frozen, step_history

#: ``_frozen``: the name ``frozen`` had here before it moved to ``fem.stepping``
_frozen = frozen

__all__ = ["FEContact", "FEState", "FETrial", "frozen", "step_history"]


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
                 h_contact=H_CONTACT_DEFAULT, contact_extent=CONTACT_EXTENT_DEFAULT, block_size=None, cache_dir=None,
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
        # mode 1 of both bodies condensed to the pairs, their flexibility Ct and the bulk probes (from the
        # disk cache beside the meshes; the bodies' factorisations, for the field output, on demand)
        self._mode1, self._backend = None, backend
        self.Ct, self.bulk, self._mode1_ndofs, self.condensed_cache = cached_mode1(
            self.model, self.amesh, self.materials, self.bulk_probe_depth, backend, cache_dir)
        self.Ct_plate = self.Ct.copy()
        iface = self.model.interface
        self.k = penalty_stiffness(self.penalty, self.materials.E_star, iface)
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
        self._fac = SetFactors(self.M, size=16)
        self._fac_exact = SetFactors(self.Ct, size=16)  # the AL's limit (exact Coulomb): Ct itself
        self.timings = {"mesh": t1 - t0, "setup": time.perf_counter() - t1}

    # ----------------------------------------------------------------- model
    @property
    def mode1(self) -> dict:
        """Mode 1 of both bodies, {name: (K, basis, dofs, Condensation)}, for the field output (which
        recovers the bodies' displacements through their factorisations): built on first use, the
        factorisations alone (the law runs on the cached flexibility; ``condensed_mode1`` condenses)."""
        if self._mode1 is None:
            L = _probe_depth(self.amesh, self.bulk_probe_depth)
            self._mode1 = _condense_bodies(self.model, self.amesh, self.materials, L, self._backend,
                                           flexibility=False)[0]
        return self._mode1

    @property
    def dofs(self) -> int:
        """Total DOFs of the mode-0 and mode-1 models of both bodies."""
        return int(self.model.dofs + sum(self._mode1_ndofs.values()))

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
        z = frozen(np.zeros(n))
        return FEState(T=z, slip=z, lam=z, sgn=frozen(np.zeros(n, dtype=np.int8)), u=0.0, d=0.0)

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
        check_loads("step", d=d, F_N=F_N, u=u, Fx=Fx)
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
        check_loads("prepare", d=d, F_N=F_N)
        return FETrial(self, self._normal_part(state, d, F_N))

    def _normal_part(self, state, d, F_N):
        """``fem.axisym.law_step.normal_part``."""
        return normal_part(self, state, d, F_N)

    def _tangential(self, ctx, u, Fx):
        """The tangential return map of a step (``fem.axisym.law_step.tangential``: the augmented
        Lagrangian, its exact start and the tangent)."""
        return tangential(self, ctx, u, Fx)

    def _finish(self, ctx, sol):
        """(StepResult, FEState) of a solved step (``fem.axisym.law_step.finish``)."""
        return finish(self, ctx, sol)

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


def cached_mode1(model, amesh, materials, bulk_probe_depth, backend, cache_dir=None) -> tuple:
    """``condensed_mode1``'s flexibility Ct and bulk probes, each body's mode-1 DOF count and what the
    cache did (hit, miss, rebuilt, unsaved), from the disk cache beside the meshes
    (``fem.axisym.condensed``: keyed by the mesh, the materials, the probe's depth and the solver;
    verified on read), condensed and stored on a miss."""
    from fem.axisym.condensed import CondensedMode1, CondensedMode1Params, cached_condensed_mode1
    from fem.solvers import resolve_backend

    L = _probe_depth(amesh, bulk_probe_depth)
    m = materials
    params = CondensedMode1Params(mesh_key=amesh.key, E1=float(m.E1), nu1=float(m.nu1), E2=float(m.E2),
                                  nu2=float(m.nu2), probe_depth=float(L), backend=resolve_backend(backend))

    def build():
        out, rows = _condense_bodies(model, amesh, materials, L, params.backend)
        return CondensedMode1(params=params, C={b: out[b][3].C for b in out}, rows=rows,
                              ndofs={b: int(out[b][1].N) for b in out})

    c = cached_condensed_mode1(params, build, cache_dir)
    return _flexibility(model.interface, c.C["indenter"], c.C["block"]), \
        bulk_probe(model.interface, materials, c.rows, L), dict(c.ndofs), c.info["cache"]


def _probe_depth(amesh, bulk_probe_depth) -> float:
    """The bulk probes' depth (m), ``bulk_probe_depth`` a_ref, checked: beyond the contact segment,
    inside both bodies."""
    p = amesh.params
    lo, hi = p.r_contact / p.a_ref, 0.8 * min(p.block_height, p.indenter_height) / p.a_ref
    if not lo < bulk_probe_depth < hi:
        raise InputError(f"bulk_probe_depth must be in ({lo:.4g}, {hi:.4g}) (probe depth / a_ref: beyond the "
                         f"contact segment, inside both bodies), got {bulk_probe_depth!r}")
    return bulk_probe_depth * p.a_ref


def _flexibility(iface, C_indenter, C_block) -> np.ndarray:
    """The pairs' symmetric tangential flexibility: the indenter's plus the block's through the
    interface map N."""
    N = iface.N
    Ct = C_indenter + N @ (N @ C_block).T
    return 0.5 * (Ct + Ct.T)


def _condense_bodies(model, amesh, materials, L, backend, flexibility: bool = True) -> tuple:
    """Each body's mode 1 condensed to its contact nodes, {name: (K, basis, dofs, Condensation)}, and
    its axis probe's row at depth L (m); ``flexibility=False``: the factorisations alone (no rows)."""
    iface = model.interface
    m = materials
    bodies = model.bodies
    out, rows = {}, {}
    for name, E, nu, z in (("indenter", m.E1, m.nu1, L), ("block", m.E2, m.nu2, -L)):
        mesh = bodies[name].mesh
        K, basis = stiffness_mode1(mesh, E, nu)
        dofs = node_dofs_mode1(basis)
        fixed = fixed_dofs_mode1(mesh, basis, "top" if name == "indenter" else "bottom")
        nodes = iface.ind_nodes if name == "indenter" else iface.blk_nodes
        pnodes, wts = axis_point(mesh, z)
        cond = Condensation(K, fixed, dofs[0, nodes], probe_dofs=dofs[0, pnodes], backend=backend,
                            flexibility=flexibility)
        if flexibility:
            rows[name] = wts @ cond.P
        out[name] = (K, basis, dofs, cond)
    return out, rows


def condensed_mode1(model, amesh, materials, bulk_probe_depth, backend):
    """Mode 1 (``fem.axisym.mode1``) of both bodies condensed to the contact pairs: the bodies'
    {name: (K, basis, dofs, Condensation)}, the symmetric tangential flexibility Ct of the pairs
    (indenter plus block through the interface map N) and the tangential bulk probes of
    ``fem.bulk`` at depth ``bulk_probe_depth`` a_ref on the axis of each body."""
    L = _probe_depth(amesh, bulk_probe_depth)
    out, rows = _condense_bodies(model, amesh, materials, L, backend)
    return out, _flexibility(model.interface, out["indenter"][3].C, out["block"][3].C), \
        bulk_probe(model.interface, materials, rows, L)
