"""The rough half-space as a contact law of the protocol (``mdr.protocol.ContactLaw``): the apparatus
(``mdr.apparatus.run_apparatus``) drives it as it drives MDR, so the slip index of a rough contact in
the apparatus is computed, not inferred from an equivalent profile.

Normal: at each step's normal force F_N the frictionless contact of the indenter plus the heights on
the periodic grid (``rough.normal.elastic_pressure``, each force warm-started from the nearest one
solved; the forces of a history are solved once each, a cycle's forces recur in the next). With a
``hardness`` the asperities are flattened first by ``preload`` and elastic after
(``rough.equivalent.flattened``), as in ``rough.equivalent.mdr_against_rough``.

Tangential, under the relative displacement u of the bodies far away (displacement control, as the
apparatus imposes it): Coulomb's law cell by cell with memory (``rough.tangential``'s, Mindlin's
assumptions: the traction along x, no normal-tangential coupling), the traction q minimising

    (1/2) q.K q + q.(s - u)   over |q| <= mu p cell by cell   (``rough.boxqp.solve_box_free``),

with s each cell's slip so far and K the x-x Cerruti kernel of the two half-spaces without periodic
images (``rough.tangential.cerruti_pixel_kernel``): it holds the rigid mode, so u is the same
displacement as MDR's and the apparatus's. K is a dense matrix over the cells that are ever in contact
(a rough contact touches a few hundred pixels; at most ``MAX_CELLS``): each solve is a small dense
problem, not an FFT over the grid. The force's slope dF/du, which the apparatus's Newton iteration
takes, is that of the step's stick set: dA 1.K_ss^-1 1 over the sticking cells s (exact on the
piecewise linear branch the solution lies on).

A cell that leaves the contact carries nothing and takes its current relative position as its slip, so
it re-enters sticking. The stick radius of a rough contact is no radius: ``c`` is that of the disk of
the stick cells' area, and the law reports no per-node slack (the apparatus then takes the cycle's
smallest c).
"""
from __future__ import annotations

import copy
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from common.errors import InputError, positive
from mdr.law_types import StepResult
from mdr.protocol import check_loads

from .boxqp import solve_box_free_dense
from .halfspace import among_cells
from .normal import Grid, _rigid_surface, contact_approach, dense_elastic_pressure, elastic_pressure
from .surfaces import HeightMap
from .tangential import TOLERANCE, cerruti_pixel_kernel

#: the largest number of cells the law holds (its compliance is dense, no grid path to fall back on: MAX_CELLS^2
#: doubles, 8000 cells are 512 MB)
MAX_CELLS = 8000
#: forces (N) closer than this relative amount share their normal solve (a cycle's F_N(t) recurs in the
#: next to round-off)
FORCE_KEY_DIGITS = 12


@dataclass(frozen=True)
class RoughState:
    """The memory of the contact: ``tracked``, the flat indices (increasing) of the grid's cells whose
    memory the state holds (the law's dense set when it was made), and on them each cell's slip ``s``
    (m) and traction ``q`` (Pa, along x); the relative displacement ``u`` (m) and the friction work (J).
    A cell outside ``tracked`` has never touched: its slip is its relative position, u minus the
    elastic displacement there. (Only the few hundred cells a rough contact ever touches are held, not
    the grid: a step copies the state.)"""

    s: np.ndarray
    q: np.ndarray
    u: float = 0.0
    work: float = 0.0
    tracked: np.ndarray = None


class RoughContact:
    """The indenter ``profile`` plus ``heights`` (``rough.surfaces.HeightMap`` on ``grid``; None: the smooth
    indenter) on the half-space of ``materials`` with friction ``mu`` (module docstring); ``hardness``
    (Pa) and ``preload`` (N): perfectly plastic asperities flattened once at ``preload``. ``start``: (F,
    pressure (n, n)) of a contact of this surface already solved (on the flattened surface where
    plastic), where the first normal solve starts (else on the grid from a uniform pressure)."""

    batch = ()
    #: Cattaneo-Mindlin's slack falls as sqrt towards a smooth stick edge (unused: no per-node slack)
    stick_onset = 0.5

    def __init__(self, profile, materials, mu, grid: Grid, heights: HeightMap | None = None, *,
                 hardness: float | None = None, preload: float | None = None, tol: float = TOLERANCE,
                 start: tuple | None = None):
        if not isinstance(grid, Grid):
            raise InputError(f"grid must be a rough.normal.Grid, got {grid!r}")
        self.profile, self.materials, self.grid = profile, materials, grid
        self.mu = float(positive("mu", mu))
        self.tol = float(positive("tol", tol))
        self.hardness = hardness
        if hardness is not None:
            from .equivalent import flattened

            heights, _ = flattened(profile, materials, grid, heights, hardness, preload)
        elif preload is not None:
            raise InputError("preload needs a hardness (the load that flattened the asperities)")
        self.heights = heights
        self.surface = _rigid_surface(profile, grid, heights)
        self.dA = grid.pixel ** 2
        self._kernel = cerruti_pixel_kernel(grid.n, grid.pixel, materials, "xx")
        # what does not depend on the friction, shared by ``with_friction``'s copies: the normal solves
        # (force key -> (flat indices of the contact, their pressures, approach)), the dense set's cells
        # (flat indices) and compliance, and the last slope computed ((stick set, dF/du): the next step's
        # often shares it)
        self._shared = SimpleNamespace(normal={}, cells=np.zeros(0, dtype=np.int64), K=np.zeros((0, 0)), slope=None)
        self.stats = {"normal_solves": 0, "grid_normal_solves": 0, "tangential_solves": 0}
        self._start = None
        if start is not None:
            F0, p0 = float(positive("start force", start[0])), np.asarray(start[1], dtype=float)
            if p0.shape != (grid.n, grid.n):
                raise InputError(f"the start pressure must lie on the grid, ({grid.n}, {grid.n}), got {p0.shape}")
            self._start = (F0, p0)

    def with_friction(self, mu) -> "RoughContact":
        """The same contact with the friction ``mu``, sharing this one's normal solves and dense compliance
        (they do not depend on it): the points of an apparatus study at several frictions solve each
        force once."""
        other = copy.copy(self)
        other.mu = float(positive("mu", mu))
        return other

    @property
    def _normal(self) -> dict:
        return self._shared.normal

    @property
    def _cells(self) -> np.ndarray:
        return self._shared.cells

    @property
    def _K(self) -> np.ndarray:
        return self._shared.K

    # ------------------------------------------------------------------ protocol
    def describe(self) -> dict:
        return {"law": "rough half-space", **self.profile.describe(), "period": self.grid.period, "n": self.grid.n,
                "rms": None if self.heights is None else self.heights.rms, "hardness": self.hardness}

    @property
    def stick_nodes(self) -> np.ndarray:
        return np.zeros(0)

    def rest_state(self) -> RoughState:
        return RoughState(s=np.zeros(0), q=np.zeros(0), tracked=np.zeros(0, dtype=np.int64))

    def normal_load(self, F_N) -> dict:
        """``{"F_N": F_N}``; every force of the history solved now (once each), so the dense set holds
        every cell the history brings into contact."""
        F = np.asarray(F_N, dtype=float)
        for f in sorted({self._key(x) for x in F[F > 0].ravel()}, reverse=True):  # the largest contact first
            self._normal_at(f)
        return {"F_N": F}

    def contact_at(self, F_N) -> dict:
        """The normal contact at ``F_N`` without tangential traction: the radius of the disk of its area
        (``contact_radius``) and the approach since first contact (``indentation``, m)."""
        idx, p, d = self._normal_at(float(positive("F_N", F_N)))
        return {"contact_radius": float(np.sqrt(idx.size * self.dA / np.pi)), "indentation": d}

    def prepare(self, state: RoughState, *, d=None, F_N=None) -> "RoughTrial":
        check_loads("prepare", d=d, F_N=F_N)
        if d is not None:
            raise InputError("the rough law takes the normal force F_N, not the approach d")
        F = float(F_N)
        if not np.isfinite(F) or F < 0:
            raise InputError(f"F_N must be finite and >= 0, got {F_N!r}")
        if F == 0.0:
            raise InputError("F_N = 0: the rough law has no contact to slide (lift-off is not modelled)")
        idx, p, d_app = self._normal_at(F)
        lim = np.zeros(self._cells.size)
        lim[np.searchsorted(self._cells, idx)] = self.mu * p
        return RoughTrial(self, state, F, d_app, lim)

    def step(self, state: RoughState, u=None, *, d=None, F_N=None, Fx=None):
        check_loads("step", d=d, F_N=F_N, u=u, Fx=Fx)
        if Fx is not None:
            raise InputError("the rough law is displacement-controlled: give u, not Fx")
        return self.prepare(state, d=d, F_N=F_N).commit(float(u))

    def run(self, u=None, *, F_N=None, d=None, Fx=None, state=None, record_from=None):
        raise InputError("the rough law runs in the apparatus (mdr.apparatus.run_apparatus) or step by step")

    # ------------------------------------------------------------------ internals
    def _key(self, F: float) -> float:
        return float(f"{F:.{FORCE_KEY_DIGITS}g}")

    def _normal_at(self, F: float):
        key = self._key(F)
        hit = self._normal.get(key)
        if hit is not None:
            return hit
        start = None
        if self._normal:  # warm start: the nearest force solved, scaled
            near = min(self._normal, key=lambda k: abs(k - key))
            idx, p, _ = self._normal[near]
            start = np.zeros(self.grid.n ** 2)
            start[idx] = p * (key / near)
            start = start.reshape(self.grid.n, self.grid.n)
        elif self._start is not None:  # the contact given, scaled
            start = self._start[1] * (key / self._start[0])
        E_star = float(self.materials.E_star)
        P = None if start is None else dense_elastic_pressure(self.surface, key, self.grid, E_star, start,
                                                              self._cells, MAX_CELLS)
        if P is None:  # the first force, or the dense solve found no answer: the grid's conjugate gradient
            P = elastic_pressure(self.surface, key, self.grid, E_star, start)
            self.stats["grid_normal_solves"] += 1
        flat = P.ravel()
        idx = np.flatnonzero(flat > 0)
        d = contact_approach(P, self.surface, self.grid.pixel, E_star)
        self._normal[key] = hit = (idx, flat[idx].copy(), d)
        self.stats["normal_solves"] += 1
        self._grow(idx)
        return hit

    def _grow(self, idx) -> None:
        """Extend the dense set by the cells of ``idx`` not yet in it (the compliance among them)."""
        cells = np.union1d(self._cells, idx)
        if cells.size == self._cells.size:
            return
        if cells.size > MAX_CELLS:
            raise InputError(f"the rough contact touches {cells.size} cells, more than the dense solve's "
                             f"{MAX_CELLS}: use a coarser grid (n = {self.grid.n} now)")
        self._shared.K = among_cells(self._kernel, cells, self.grid.n, periodic=False)
        self._shared.cells, self._shared.slope = cells, None


class RoughTrial:
    """One step's normal part done (``mdr.protocol.ContactTrial``): ``force(u)`` solves the tangential
    problem at the displacement u without committing it; ``commit(u)`` makes it the new state."""

    def __init__(self, law: RoughContact, state: RoughState, F_N: float, d: float, lim: np.ndarray):
        self.law, self.state, self.F_N, self.d, self.lim = law, state, F_N, d, lim
        # the dense set now (it only grows: the state's cells are among them)
        self.cells, self.K = law._cells, law._K
        m = self.cells.size
        self.s, self.q0, new = np.zeros(m), np.zeros(m), np.ones(m, dtype=bool)
        if state.tracked.size:
            at = np.searchsorted(self.cells, state.tracked)
            self.s[at], self.q0[at], new[at] = state.s, state.q, False
            if new.any():  # cells the set gained since the state: at their relative position
                self.s[new] = state.u - self.K[np.ix_(new, ~new)] @ self.q0[~new]
        self._last = None  # (u, q, F, slope): a commit after a force at the same u reuses it

    def _solve(self, u: float):
        if self._last is not None and self._last[0] == u:
            return self._last
        law = self.law
        K = self.K
        start = self.q0 if self._last is None else self._last[1]
        q = solve_box_free_dense(K, self.s - u, self.lim, start, law.tol, "rough tangential contact")
        law.stats["tangential_solves"] += 1
        F = float(q.sum()) * law.dA
        stick = (self.lim > 0) & (np.abs(q) < self.lim * (1 - 1e-9))
        if not stick.any():  # gross slip: the force is mu F_N whatever u
            slope = 0.0
        elif law._shared.slope is not None and np.array_equal(law._shared.slope[0], stick):  # the same stick set
            slope = law._shared.slope[1]
        else:
            import scipy.linalg as sla

            x = sla.solve(K[np.ix_(stick, stick)], np.ones(int(stick.sum())), assume_a="pos")
            slope = float(x.sum()) * law.dA
            law._shared.slope = (stick, slope)
        self._last = (u, q, F, slope, stick)
        return self._last

    def force(self, u):
        _, _, F, slope, _ = self._solve(float(u))
        return F, slope

    def commit(self, u):
        u = float(u)
        law = self.law
        _, q, F, _, stick = self._solve(u)
        g = self.K @ q + self.s
        inside = self.lim > 0
        ds = np.where(stick, 0.0, u - g)  # 0 sticking; the slip increment slipping; re-entry sticking outside
        work = float(np.sum(q * np.where(inside, ds, 0.0))) * law.dA
        new = RoughState(s=self.s + ds, q=q, u=u, work=self.state.work + work, tracked=self.cells)
        area = np.sqrt(np.count_nonzero(inside) * law.dA / np.pi)
        c = np.sqrt(np.count_nonzero(stick) * law.dA / np.pi)
        res = StepResult(Fx=np.asarray(F), FN=np.asarray(self.F_N), d=np.asarray(self.d), a=np.asarray(area),
                         c=np.asarray(c), u=np.asarray(u), work=np.asarray(work))
        return res, new
