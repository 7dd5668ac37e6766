"""The MDR frictional contact law: a pure step function over an explicit state.

Model (Popov & Hess, *Method of Dimensionality Reduction in Contact Mechanics
and Friction*, Springer 2015, ch. 5; the incremental form for arbitrary
normal and tangential histories): the 3D axisymmetric contact is replaced by a
row of independent springs on x in [-a, a], normal stiffness E* dx and
tangential stiffness G* dx, indented by d - g(x). A spring of normal force
dN carries a tangential force of at most mu dN (local Coulomb friction with
a constant coefficient, Mindlin's assumption that the traction is along x).
Each time step:

1. normal update: the new approach d fixes a, the in-contact length and the
   normal force of every cell (exact integrals, ``mdr.grid``). Springs that
   leave contact lose their tangential displacement; springs that enter start
   with none (a partly covered cell keeps its tangential force and spreads it
   over the new length). A smaller slip limit makes springs slip.
2. tangential update: every spring in contact is displaced by the increment
   du of the tangential relative displacement and clipped to the slip limit
   |v| <= mu E* (d - g) / G*.

This is exact for the axisymmetric half-space problem with Coulomb friction
under the Hertz-Mindlin assumptions (no normal-tangential coupling: equal
materials or incompressible, or coupling neglected). Rate independent: the
time steps only need to resolve the load path (include its turning points).

State (``LawState``) is immutable: ``step`` returns a new state and leaves
the old one untouched, so a caller can try a step and discard it. Everything
is vectorised over a batch of scenes (profile parameters and mu may be
arrays of one shape ``batch``).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import kernels
from common.errors import InputError, finite, nonnegative, positive
from .grid import DEFAULT_CELLS, SpringGrid, make_grid
from .materials import Materials
from .normal import approach_from_force
from .profiles import FlatPunch, Profile, TruncatedSphere
from .solve import solve_increasing
from .stick import at_limit, per_step, stick_radius


@dataclass(frozen=True)
class LawState:
    """History of the contact: per-cell elastic tangential displacement ``v``,
    in-contact cell length ``ell`` (both batch + (n,)), total tangential relative
    displacement ``u`` and approach ``d`` (batch)."""

    v: np.ndarray
    ell: np.ndarray
    u: np.ndarray
    d: np.ndarray


@dataclass(frozen=True)
class NormalPhase:
    """Normal contact at approach d: contact radius a, per-cell in-contact
    length ell, normal force N (one side, N >= 0) and tangential slip limit vmax."""

    d: np.ndarray
    a: np.ndarray
    ell: np.ndarray
    N: np.ndarray
    vmax: np.ndarray
    FN: np.ndarray


@dataclass(frozen=True)
class StepResult:
    """Outputs of one step (SI): forces, approach, contact and stick radii, the
    tangential relative displacement and the friction work done in the step;
    per node of the law's ``stick_nodes``, the slack to the slip limit and whether
    the node slipped or was out of contact in the step (``mdr.stick``)."""

    Fx: np.ndarray
    FN: np.ndarray
    d: np.ndarray
    a: np.ndarray
    c: np.ndarray
    u: np.ndarray
    work: np.ndarray
    slack: np.ndarray | None = field(default=None, compare=False, repr=False)
    slipping: np.ndarray | None = field(default=None, compare=False, repr=False)


@dataclass(frozen=True)
class Trial:
    """A prepared step of an MDRContact (see ``MDRContact.prepare``)."""

    law: "MDRContact"
    state: LawState
    phase: NormalPhase
    v: np.ndarray
    v1: np.ndarray

    def force(self, u):
        """(F_x, dF_x/du) at total tangential displacement u (batch)."""
        t = self.v1 + (np.asarray(u, dtype=float) - self.state.u)[..., None]
        k = 2.0 * self.law.G_star * self.phase.ell
        vm = self.phase.vmax
        return np.sum(k * np.minimum(np.maximum(t, -vm), vm), axis=-1), np.sum(k * (np.abs(t) < vm), axis=-1)

    def commit(self, u):
        """StepResult and new state of the step to total displacement u."""
        ph, st = self.phase, self.state
        du = np.broadcast_to(np.asarray(u, dtype=float), self.law.batch) - st.u
        trial = self.v1 + du[..., None]
        v2 = np.clip(trial, -ph.vmax, ph.vmax)
        slip = np.abs(self.v - self.v1) + np.abs(trial - v2)
        work = 2.0 * np.sum(self.law.G_star * ph.ell * ph.vmax * slip, axis=-1)
        slack, slipping = self.law._slack(ph, trial, self.v)
        res = StepResult(Fx=self.law._tangential_force(ph.ell, v2), FN=ph.FN, d=ph.d, a=ph.a,
                         c=per_step(self.law.stick_nodes, slack, slipping, ph.a, self.law.stick_onset),
                         u=st.u + du, work=work, slack=slack, slipping=slipping)
        return res, LawState(v=v2, ell=ph.ell, u=st.u + du, d=ph.d)


@dataclass
class History:
    """Time series of a run (arrays batch + (T,)) and the final state."""

    u: np.ndarray
    Fx: np.ndarray
    FN: np.ndarray
    d: np.ndarray
    a: np.ndarray
    c: np.ndarray
    work: np.ndarray
    state: LawState = field(repr=False)
    slack: np.ndarray | None = field(default=None, repr=False)
    slipping: np.ndarray | None = field(default=None, repr=False)
    #: what a law records per step beyond the protocol's arrays: {name: sequence over the T steps}
    #: (the 3D FE law's vertex tractions and pressures); None where it records nothing
    fields: dict | None = field(default=None, repr=False)

    def then(self, later: "History") -> "History":
        """This history followed by ``later`` (a run from this one's final state): the arrays joined
        along time, the recorded window and fields too; the final state ``later``'s."""
        def join(a, b, axis):
            return None if a is None or b is None else np.concatenate([a, b], axis=axis)

        fields = None
        if self.fields is not None and later.fields is not None:
            fields = {k: tuple(self.fields[k]) + tuple(later.fields[k]) for k in self.fields}
        return type(later)(state=later.state, **{f: np.concatenate([getattr(self, f), getattr(later, f)], axis=-1)
                                                 for f in ("u", "Fx", "FN", "d", "a", "c", "work")},
                           slack=join(self.slack, later.slack, -2), slipping=join(self.slipping, later.slipping, -2),
                           fields=fields)

    def window_stick_radius(self, law):
        """Stick radius (``mdr.stick``) over the recorded steps (``run(record_from=...)``)."""
        if self.slack is None:
            raise InputError("the history has no recorded slip state: run it with record_from=<first step>")
        T = self.slack.shape[-2]
        return stick_radius(law.stick_nodes, self.slack, self.slipping, self.a[..., -T:], law.stick_onset)


class MDRContact:
    """MDR contact law of one profile (or a batch of profiles) and two materials.

    Parameters
    ----------
    profile : Profile (parameters may be batch arrays)
    materials : Materials
    mu : coefficient of friction (>= 0; scalar or batch array)
    F_max : largest normal force the law will see (sizes the spring grid), or
    a_max : largest contact radius directly. One of the two is required unless
            ``grid`` is given. The flat punch needs neither.
    n : number of spring cells (default gives 1e-4 relative dissipation error).
    F_min : optional smallest normal force of the history; adds a grid node at
            the smallest contact radius.
    """

    def __init__(self, profile: Profile, materials: Materials | None = None, mu=0.2, *,
                 F_max=None, a_max=None, n: int = DEFAULT_CELLS, F_min=None, grid: SpringGrid | None = None,
                 refine: float = 0.0):
        if not isinstance(profile, Profile):
            raise InputError(f"profile must be a Profile (Sphere, TruncatedSphere, FlatPunch, GeneralProfile), got {profile!r}")
        self.profile = profile
        self.materials = materials if materials is not None else Materials()
        self.mu = nonnegative("mu", mu)
        self.E_star = self.materials.E_star
        self.G_star = self.materials.G_star
        if grid is None:
            if isinstance(profile, FlatPunch):
                a_max = profile.b
            elif a_max is None:
                if F_max is None:
                    raise InputError("MDRContact needs F_max (> 0, the largest normal force) or a_max to size its spring grid")
                F_max = positive("F_max", F_max)
                a_max = profile.g_inv(approach_from_force(profile, self.materials, F_max))
            a_min = None
            if F_min is not None:
                F_min = nonnegative("F_min", F_min)
            if F_min is not None and not isinstance(profile, FlatPunch) and np.all(np.asarray(F_min) > 0):
                a_min = profile.g_inv(approach_from_force(profile, self.materials, F_min))
            grid = make_grid(profile, a_max, n=n, a_min=a_min, refine=refine)
        self.grid = grid
        self.batch = grid.width.shape[:-1]

    def describe(self) -> dict:
        return {"law": "mdr", "cells": self.grid.n}

    # ------------------------------------------------------------------ state
    def rest_state(self) -> LawState:
        """Bodies apart, no tangential displacement."""
        z = np.zeros(self.grid.width.shape)
        zb = np.zeros(self.batch)
        return LawState(v=z, ell=z.copy(), u=zb, d=zb.copy())

    def approach(self, F_N):
        """Approach d for normal force F_N >= 0 (0 means contact lost)."""
        F_N = nonnegative("F_N (normal force; no adhesion, so >= 0)", F_N)
        return approach_from_force(self.profile, self.materials, F_N)

    def contact_at(self, F_N) -> dict:
        """``mdr.protocol.ContactLaw.contact_at``: the half-space's closed form (MDR is exact for the
        normal contact of an axisymmetric profile)."""
        d = float(self.approach(F_N))
        return {"contact_radius": float(self.profile.g_inv(d)), "indentation": d}

    def normal_load(self, F_N) -> dict:
        """Normal forces as the approaches of ``prepare``/``step`` (``mdr.protocol``), at once."""
        return {"d": self.approach(F_N)}

    # --------------------------------------------------------------- normal
    def normal_phase(self, d) -> NormalPhase:
        """Normal contact for approach ``d`` of shape batch or batch + (T,)."""
        d = np.asarray(d, dtype=float)
        nb = len(self.batch)
        extra = d.ndim - nb
        if extra not in (0, 1) or d.shape[:nb] != self.batch:
            raise InputError(f"approach d must have shape {self.batch} or {self.batch} + (T,), got {d.shape}")
        g = self.grid

        def cells(arr):  # batch + (n,) -> batch + (1,)*extra + (n,)
            return arr.reshape(self.batch + (1,) * extra + (arr.shape[-1],))

        lo, width, int_g = cells(g.lo), cells(g.width), cells(g.int_g)
        dp = np.maximum(d, 0.0)
        touching = d > 0
        a = np.where(touching, self.profile.g_inv(dp), 0.0)
        x_max = g.x_max.reshape(self.batch + (1,) * extra)
        if np.any(a > x_max * (1 + 1e-9)):
            raise InputError("the contact radius exceeds the spring grid: build the law with a larger F_max (or a_max)")
        a = np.minimum(a, x_max)
        ell = np.clip(a[..., None] - lo, 0.0, width)
        full = ell >= width
        ig = np.where(full, int_g, 0.0)
        # the one partly covered cell: exact integral of g over [lo_k, a]
        k = np.sum(full, axis=-1, keepdims=True)
        has_partial = (k < width.shape[-1]) & (a[..., None] > 0)
        kk = np.minimum(k, width.shape[-1] - 1)
        lo_k = np.take_along_axis(np.broadcast_to(lo, ell.shape), kk, axis=-1)[..., 0]
        part = np.where(has_partial[..., 0] & (a > lo_k), self.profile.cell_integral(lo_k, np.maximum(a, lo_k)), 0.0)
        np.put_along_axis(ig, kk, np.where(has_partial, part[..., None], np.take_along_axis(ig, kk, axis=-1)), axis=-1)
        N = self.E_star * np.maximum(dp[..., None] * ell - ig, 0.0)
        mu = np.asarray(self.mu, dtype=float).reshape(self.batch + (1,) * (extra + 1)) if np.ndim(self.mu) else self.mu
        with np.errstate(divide="ignore", invalid="ignore"):
            vmax = np.where(ell > 0, mu * N / (self.G_star * ell), 0.0)
        return NormalPhase(d=dp, a=a, ell=ell, N=N, vmax=vmax, FN=2.0 * np.sum(N, axis=-1))

    # ----------------------------------------------------------- tangential
    @staticmethod
    def _carry(v, ell_old, ell_new):
        """Tangential displacement after the contact length of each cell changed."""
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(ell_new > 0, np.minimum(1.0, ell_old / ell_new), 0.0)
        return v * ratio

    def _tangential_force(self, ell, v):
        return 2.0 * self.G_star * np.sum(ell * v, axis=-1)

    #: slack of a spring cell falls linearly towards the stick edge (``mdr.stick``)
    stick_onset = 1.0

    @property
    def stick_nodes(self):
        """Radii of the nodes the stick radius is resolved on (batch + (n,)): the cell midpoints,
        and the outer edge of a cell of a flat face (its springs are identical: where one
        sticks, the whole cell sticks)."""
        nodes = getattr(self, "_stick_nodes", None)
        if nodes is None:
            g = self.grid
            b = self._flat_radius()
            nodes = g.mid if b is None else np.where(g.edges[..., 1:] <= b[..., None] * (1 + 1e-12), g.edges[..., 1:], g.mid)
            self._stick_nodes = nodes
        return nodes

    def _flat_radius(self):
        """Radius b of the flat face (batch array), or None for a profile without one."""
        if not isinstance(self.profile, (FlatPunch, TruncatedSphere)):
            return None
        b = np.asarray(getattr(self.profile, "b", 0.0), dtype=float)
        return None if not np.any(b > 0) else np.broadcast_to(b, self.batch)

    @staticmethod
    def _slack(phase: NormalPhase, trial, carried):
        """Per cell: slack vmax - |trial| to the slip limit, and slipping (at the limit, clipped
        in the normal update, or out of contact); the input of ``mdr.stick``."""
        slack = phase.vmax - np.abs(trial)
        return slack, at_limit(slack, phase.vmax) | (np.abs(carried) > phase.vmax) | (phase.ell <= 0)

    def step(self, state: LawState, u=None, *, d=None, F_N=None, Fx=None):
        """Advance the contact by one step; pure (``state`` is not modified).

        Give the normal load as approach ``d`` or force ``F_N`` (>= 0; zero means
        the contact is lost and all tangential history is released), and the
        tangential load as total relative displacement ``u`` or force ``Fx``
        (|Fx| < mu F_N). Returns (StepResult, new LawState).
        """
        if (d is None) == (F_N is None):
            raise InputError("step needs exactly one of d (approach) or F_N (normal force)")
        if (u is None) == (Fx is None):
            raise InputError("step needs exactly one of u (tangential displacement) or Fx (tangential force)")
        if u is not None:
            u = finite("u (tangential displacement)", u)
        else:
            Fx = finite("Fx (tangential force)", Fx)
        tr = self.prepare(state, d=d, F_N=F_N)
        if Fx is not None:
            u = state.u + self._solve_du(tr.phase, tr.v1, np.broadcast_to(np.asarray(Fx, dtype=float), self.batch))
        return tr.commit(u)

    def prepare(self, state: LawState, *, d=None, F_N=None) -> "Trial":
        """Normal update of a step, for many trial tangential displacements.

        Returns a Trial whose ``force(u)`` gives (F_x, dF_x/du) at total
        displacement u without committing, and ``commit(u)`` the step result and
        new state, identical to ``step(state, u, d=...)``.
        """
        if (d is None) == (F_N is None):
            raise InputError("prepare needs exactly one of d (approach) or F_N (normal force)")
        if d is None:
            d = self.approach(np.broadcast_to(F_N, self.batch))
        else:
            d = finite("d (approach)", d)
        phase = self.normal_phase(np.broadcast_to(np.asarray(d, dtype=float), self.batch))
        v = self._carry(state.v, state.ell, phase.ell)
        return Trial(self, state, phase, v, np.clip(v, -phase.vmax, phase.vmax))

    def _solve_du(self, phase: NormalPhase, v1, target):
        mu_FN = np.asarray(self.mu) * phase.FN
        if np.any(np.abs(target) >= mu_FN * (1 - 1e-12)) and np.any(np.abs(target) > 0):
            bad = np.abs(target) >= mu_FN * (1 - 1e-12)
            raise InputError(f"tangential force Fx={float(np.max(np.abs(target[bad]) if np.ndim(target) else abs(target))):.4g} N "
                             f"must stay below the friction limit mu*F_N={float(np.min(mu_FN[bad]) if np.ndim(mu_FN) else mu_FN):.4g} N "
                             f"under force control (beyond it the contact slides without equilibrium)")
        lo = np.min(np.where(phase.ell > 0, -phase.vmax - v1, 0.0), axis=-1)
        hi = np.max(np.where(phase.ell > 0, phase.vmax - v1, 0.0), axis=-1)
        k = 2.0 * self.G_star * phase.ell

        def fun(du):
            t = v1 + du[..., None]
            stick = np.abs(t) < phase.vmax
            return np.sum(k * np.clip(t, -phase.vmax, phase.vmax), axis=-1), np.sum(k * stick, axis=-1)

        scale = np.maximum(mu_FN, 1e-300)
        return solve_increasing(fun, target, lo, hi, x0=np.zeros_like(target), atol=1e-12 * scale,
                                what="MDR tangential force control")

    # ---------------------------------------------------------------- runs
    def run(self, u=None, *, F_N=None, d=None, Fx=None, state: LawState | None = None, block: int | None = None,
            record_from: int | None = None) -> History:
        """Run a whole load history (arrays of shape (T,) or batch + (T,)).

        Starts from ``state`` (default: at rest, bodies apart). With numba the
        whole history runs in the compiled loop of ``mdr.kernels`` (displacement and
        force control; the same arithmetic as ``step``, equal to round-off); without
        it, displacement control computes the normal phases of a block of time steps
        at once and loops over time only for the tangential update, and force control
        takes one ``step`` (a safeguarded Newton solve) per time step.
        ``record_from`` (a step index): keep the per-cell slack and slip flags of
        the steps from there on (``History.window_stick_radius``).
        """
        if (d is None) == (F_N is None):
            raise InputError("run needs exactly one of d (approach history) or F_N (normal force history)")
        if (u is None) == (Fx is None):
            raise InputError("run needs exactly one of u (displacement history) or Fx (force history)")
        drive = np.asarray(finite("u (tangential displacement)" if u is not None else "Fx (tangential force)",
                                  u if u is not None else Fx), dtype=float)
        T = drive.shape[-1]
        shape = self.batch + (T,)
        if d is None:
            F_N = np.broadcast_to(np.asarray(F_N, dtype=float), shape)
            d = self.approach(F_N)
        else:
            d = finite("d (approach)", d)
        d = np.broadcast_to(np.asarray(d, dtype=float), shape)
        drive = np.broadcast_to(drive, shape)
        if state is None:
            state = self.rest_state()
        out = {k: np.empty(shape) for k in ("u", "Fx", "FN", "d", "a", "c", "work")}
        rec0 = T if record_from is None else int(record_from)
        if not 0 <= rec0 <= T:
            raise InputError(f"record_from must be a step index in [0, {T}], got {record_from!r}")
        if T and kernels.enabled() and type(self) is MDRContact:
            return self._run_compiled(drive, d, state, Fx is not None, rec0, record_from is not None)
        rec = {k: np.empty(self.grid.width.shape[:-1] + (T - rec0,) + self.grid.width.shape[-1:], dtype=dt)
               for k, dt in (("slack", float), ("slipping", bool))}
        if Fx is not None:
            for t in range(T):
                res, state = self.step(state, d=d[..., t], Fx=drive[..., t])
                for key in out:
                    out[key][..., t] = getattr(res, key)
                if t >= rec0:
                    rec["slack"][..., t - rec0, :] = res.slack
                    rec["slipping"][..., t - rec0, :] = res.slipping
            return History(state=state, **out, **(rec if record_from is not None else {}))
        v, ell, u_prev = state.v.copy(), state.ell, state.u
        if block is None:  # bound the block arrays (batch x block x cells) to ~1e6 numbers
            block = int(np.clip(1_000_000 // max(v.size, 1), 1, 256))
        for t0 in range(0, T, block):
            t1 = min(T, t0 + block)
            db = d[..., t0:t1]
            if np.all(db == db[..., :1]):
                # constant normal load over the block: one normal phase, broadcast
                ph1 = self.normal_phase(db[..., 0])
                ph = NormalPhase(*(np.broadcast_to(np.expand_dims(x, -2 if x.ndim > len(self.batch) else -1),
                                                   x.shape[:len(self.batch)] + (t1 - t0,) + x.shape[len(self.batch):])
                                   for x in (ph1.d, ph1.a, ph1.ell, ph1.N, ph1.vmax, ph1.FN)))
            else:
                ph = self.normal_phase(db)
            ells = np.concatenate([ell[..., None, :], ph.ell], axis=-2)
            same = np.array_equal(ells[..., 1:, :], ells[..., :-1, :])
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = None if same else np.where(ells[..., 1:, :] > 0,
                                                   np.minimum(1.0, ells[..., :-1, :] / ells[..., 1:, :]), 0.0)
            du = np.diff(np.concatenate([u_prev[..., None], drive[..., t0:t1]], axis=-1), axis=-1)
            # time-major, contiguous copies for the sequential loop
            tm = lambda x: np.ascontiguousarray(np.moveaxis(x, -2, 0))
            vmax_t, du_t = tm(ph.vmax), np.ascontiguousarray(np.moveaxis(du, -1, 0))[..., None]
            ratio_t = None if ratio is None else tm(ratio)
            trial_t = np.empty(vmax_t.shape)
            v2_t = np.empty(vmax_t.shape)
            carried_t = np.empty(vmax_t.shape)
            for j in range(t1 - t0):
                vmax, cj, tj, vj = vmax_t[j], carried_t[j], trial_t[j], v2_t[j]
                if ratio_t is None:
                    cj[...] = v
                else:
                    np.multiply(v, ratio_t[j], out=cj)
                np.minimum(cj, vmax, out=tj)
                np.maximum(tj, -vmax, out=tj)
                tj += du_t[j]
                np.minimum(tj, vmax, out=vj)
                np.maximum(vj, -vmax, out=vj)
                v = vj
            back = lambda x: np.moveaxis(x, 0, -2)
            trial, v2s, carried = back(trial_t), back(v2_t), back(carried_t)
            # slip in the normal update (carried -> clipped) and in the tangential one
            slip = np.abs(carried - (trial - du[..., None])) + np.abs(trial - v2s)
            sl = slice(t0, t1)
            out["Fx"][..., sl] = self._tangential_force(ph.ell, v2s)
            out["FN"][..., sl] = ph.FN
            out["d"][..., sl] = ph.d
            out["a"][..., sl] = ph.a
            slack, slipping = self._slack(ph, trial, carried)
            out["c"][..., sl] = per_step(self.stick_nodes[..., None, :], slack, slipping, ph.a, self.stick_onset)
            if t1 > rec0:
                k0 = max(rec0, t0)
                rec["slack"][..., k0 - rec0:t1 - rec0, :] = slack[..., k0 - t0:, :]
                rec["slipping"][..., k0 - rec0:t1 - rec0, :] = slipping[..., k0 - t0:, :]
            out["work"][..., sl] = 2.0 * self.G_star * np.sum(ph.ell * ph.vmax * slip, axis=-1)
            ell = ph.ell[..., -1, :]
            v = v.copy()
            u_prev = drive[..., t1 - 1]
        out["u"][...] = drive
        return History(state=LawState(v=v, ell=ell, u=np.array(u_prev, dtype=float), d=np.array(d[..., -1])), **out,
                       **(rec if record_from is not None else {}))

    def _run_compiled(self, drive, d, state, force, rec0, record):
        """``run`` through the compiled loop of ``mdr.kernels`` (same results to round-off)."""
        h = kernels.law_history(self, drive, d, state, force, rec0)
        v, ell, u = h.pop("state")
        # the state's approach as the step API leaves it: as given (displacement control), d_+ (force control)
        last = h["d"][..., -1] if force else d[..., -1]
        rec = {k: h.pop(k) for k in ("slack", "slipping")}
        return History(state=LawState(v=v, ell=ell, u=u, d=np.array(last)), **h, **(rec if record else {}))

    # ------------------------------------------------------------ tractions
    def line_loads(self, state: LawState):
        """MDR line loads at the cell midpoints: x, q_z = E*(d-g) (exact cell mean), q_x = G* v."""
        ph = self.normal_phase(state.d)
        with np.errstate(divide="ignore", invalid="ignore"):
            qz = np.where(ph.ell > 0, ph.N / ph.ell, 0.0)
        return self.grid.mid, qz, np.where(ph.ell > 0, self.G_star * state.v, 0.0), ph.a

    def traction(self, state: LawState, r):
        """Tangential traction tau(r) (along x) of a single-scene state.

        MDR inverse transform tau(r) = -(1/pi) int_r^a q_x'(x)/sqrt(x^2-r^2) dx
        + q_x(a)/(pi sqrt(a^2 - r^2)), with q_x interpolated linearly between
        cell midpoints (constant towards the centre and over the cells of a flat
        face, whose springs are identical), extrapolated to a and limited there by
        Coulomb's |q_x| <= mu E* (d - g(a)); the segment integrals are exact (arccosh).
        """
        if self.batch:
            raise InputError("traction() works on a single scene; build the law without batch parameters")
        x, _, qx, a = self.line_loads(state)
        a = float(a)
        r = np.atleast_1d(np.asarray(r, dtype=float))
        inside = self.grid.lo < a
        xs, qs = x[inside], qx[inside]
        if xs.size == 0 or a <= 0:
            return np.zeros_like(r)
        full = self.grid.edges[1:][inside] <= a
        xf, qf = xs[full], qs[full]
        # the springs of a flat face (g = 0 for x < b) are identical: q_x is constant over each
        # such cell, so it holds up to the cell's edges instead of meeting the next cell halfway
        b_flat = self._flat_radius()
        b_flat = 0.0 if b_flat is None else float(b_flat)
        if b_flat > 0 and xf.size:
            lo, hi = self.grid.lo[inside][full], self.grid.edges[1:][inside][full]
            flat = hi <= b_flat * (1 + 1e-12)
            xf = np.concatenate([np.ravel(np.column_stack([lo[flat], hi[flat]])), xf[~flat]])
            qf = np.concatenate([np.repeat(qf[flat], 2), qf[~flat]])
            xf, keep = np.unique(xf, return_index=True)
            qf = qf[keep]
            inner = (xf > 0) & (xf < a)  # q is constant towards the centre; a is added below
            xf, qf = xf[inner], qf[inner]
        if xf.size >= 2:
            q_a = qf[-1] + (qf[-1] - qf[-2]) * (a - xf[-1]) / (xf[-1] - xf[-2])
        else:
            q_a = qs[-1]
        # Coulomb at the edge spring: |q_x(a)| <= mu E* (d - g(a)), zero where the profile meets
        # the surface smoothly (the extrapolation overshoots where q_x drops steeply in slip)
        q_lim = float(np.asarray(self.mu)) * self.E_star * max(float(state.d) - float(self.profile.g(a)), 0.0)
        q_a = float(np.clip(q_a, -q_lim, q_lim))
        nodes = np.concatenate([xf, [a]])
        vals = np.concatenate([qf, [q_a]])
        slopes = np.diff(vals) / np.diff(nodes)
        tau = np.zeros_like(r)
        for i, ri in enumerate(r):
            if ri >= a:
                continue
            x0 = np.maximum(nodes[:-1], ri)
            x1 = np.maximum(nodes[1:], ri)
            L = lambda z: np.log(z + np.sqrt(np.maximum(z**2 - ri**2, 0.0)))
            tau[i] = (-np.sum(slopes * (L(x1) - L(x0))) + q_a / np.sqrt(a**2 - ri**2)) / np.pi
        return tau
