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

Layout: this module holds the law (``MDRContact``, its protocol methods) and its prepared step
(``Trial``); the values it hands around are in ``mdr.law_types`` (importable from here), the
arithmetic of the spring cells in ``mdr.law_cells``, the runs of whole histories in
``mdr.law_run`` and the traction's inverse transform in ``mdr.law_traction``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import kernels
from common.errors import InputError, finite, nonnegative
from .grid import DEFAULT_CELLS, SpringGrid
from .law_cells import (carry, cell_slack, flat_radius, law_grid, normal_phase, solve_du, stick_nodes,
                        tangential_force)
from .law_run import run_blocks, run_compiled, run_force_steps
from .law_traction import traction_from_line_loads
from .protocol import check_loads
from .law_types import History, LawState, NormalPhase, StepResult
from .materials import Materials
from .normal import approach_from_force
from .profiles import Profile
from .stick import per_step

__all__ = ["History", "LawState", "MDRContact", "NormalPhase", "StepResult", "Trial"]


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
            grid = law_grid(profile, self.materials, F_max=F_max, a_max=a_max, n=n, F_min=F_min, refine=refine)
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
        """Normal contact for approach ``d`` of shape batch or batch + (T,) (``mdr.law_cells``)."""
        return normal_phase(self.profile, self.grid, self.batch, self.E_star, self.G_star, self.mu, d)

    # ----------------------------------------------------------- tangential
    #: tangential displacement after the contact length of each cell changed (``mdr.law_cells``)
    _carry = staticmethod(carry)
    #: per cell: slack to the slip limit and the slip flags (``mdr.law_cells``)
    _slack = staticmethod(cell_slack)

    def _tangential_force(self, ell, v):
        return tangential_force(self.G_star, ell, v)

    #: slack of a spring cell falls linearly towards the stick edge (``mdr.stick``)
    stick_onset = 1.0

    @property
    def stick_nodes(self):
        """Radii of the nodes the stick radius is resolved on (batch + (n,)): the cell midpoints,
        and the outer edge of a cell of a flat face (its springs are identical: where one
        sticks, the whole cell sticks)."""
        nodes = getattr(self, "_stick_nodes", None)
        if nodes is None:
            nodes = stick_nodes(self.grid, self._flat_radius())
            self._stick_nodes = nodes
        return nodes

    def _flat_radius(self):
        """Radius b of the flat face (batch array), or None for a profile without one."""
        return flat_radius(self.profile, self.batch)

    def step(self, state: LawState, u=None, *, d=None, F_N=None, Fx=None):
        """Advance the contact by one step; pure (``state`` is not modified).

        Give the normal load as approach ``d`` or force ``F_N`` (>= 0; zero means
        the contact is lost and all tangential history is released), and the
        tangential load as total relative displacement ``u`` or force ``Fx``
        (|Fx| < mu F_N). Returns (StepResult, new LawState).
        """
        check_loads("step", d=d, F_N=F_N, u=u, Fx=Fx)
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
        check_loads("prepare", d=d, F_N=F_N)
        if d is None:
            d = self.approach(np.broadcast_to(F_N, self.batch))
        else:
            d = finite("d (approach)", d)
        phase = self.normal_phase(np.broadcast_to(np.asarray(d, dtype=float), self.batch))
        v = self._carry(state.v, state.ell, phase.ell)
        return Trial(self, state, phase, v, np.clip(v, -phase.vmax, phase.vmax))

    def _solve_du(self, phase: NormalPhase, v1, target):
        return solve_du(phase, v1, target, self.mu, self.G_star)

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
        check_loads("run", d=d, F_N=F_N, u=u, Fx=Fx, history=True)
        load = np.asarray(finite("u (tangential displacement)" if u is not None else "Fx (tangential force)",
                                  u if u is not None else Fx), dtype=float)
        T = load.shape[-1]
        shape = self.batch + (T,)
        if d is None:
            F_N = np.broadcast_to(np.asarray(F_N, dtype=float), shape)
            d = self.approach(F_N)
        else:
            d = finite("d (approach)", d)
        d = np.broadcast_to(np.asarray(d, dtype=float), shape)
        load = np.broadcast_to(load, shape)
        if state is None:
            state = self.rest_state()
        rec0 = T if record_from is None else int(record_from)
        if not 0 <= rec0 <= T:
            raise InputError(f"record_from must be a step index in [0, {T}], got {record_from!r}")
        if T and kernels.enabled() and type(self) is MDRContact:
            return run_compiled(self, load, d, state, Fx is not None, rec0, record_from is not None)
        if Fx is not None:
            return run_force_steps(self, load, d, state, rec0, record_from is not None)
        return run_blocks(self, load, d, state, block, rec0, record_from is not None)

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
        return traction_from_line_loads(self.grid, self.profile, self.mu, self.E_star, self._flat_radius(), x, qx, a,
                                        state.d, r)
