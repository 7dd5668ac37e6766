"""Compiled time loops of the MDR contact law (numba): whole histories at compiled speed.

The step API of ``mdr.law`` (``step``, ``prepare``/``force``/``commit``) stays the
reference; these loops run the same arithmetic, spring cell by spring cell, for a
whole history and for every scene of a batch (scene by scene):

- ``law_history``: ``MDRContact.run`` under displacement control (u given) and under
  force control (F_x given). Within a step the tangential force of the cells is
  piecewise linear and nondecreasing in the step's displacement, so force control
  solves for it in the loop with the safeguarded Newton iteration of
  ``mdr.solve.solve_increasing`` (same bracket, start and tolerance), which ends
  exactly once it lands on the right linear piece.
- ``apparatus_loop``: the step loop of ``mdr.apparatus.run_apparatus`` with the MDR
  law and its MDR bedding spheres (one front, two equal rear ones) (Hertz approach, sphere normal phase and the
  moment coupling of the bedding loads in the loop), the same Newton iteration per step.
- ``CompiledBedding``: those bedding spheres alone, stepped compiled within the step loop of
  ``run_apparatus`` around any other contact law (the FE models, the rough half-space).

What stays in numpy, vectorised over all steps: the contact radius of each step and
the integral of g over its one partly covered cell (``normal_inputs``; any profile),
and the stick radius over a window (``mdr.stick.stick_radius``). Results equal those
of the step API to round-off (sums in another order; tests/test_mdr_kernels.py).

numba is optional (``pip install .[fast]``): without it, or with the environment
variable ``MDR_PURE_PYTHON=1``, or with ``ENABLED = False``, every history runs
through the step API. Compiled code is cached on disk (``cache=True``), so only the
first call after installation pays the compilation (after an edit of the compiled code,
see ``mdr.kernels_step`` on that cache).

Layout: this module is the switch (``ENABLED``, ``enabled``) and the numpy side that prepares
the inputs of the compiled code and reads its outputs; the compiled code itself is in
``mdr.kernels_step`` (one step of one scene) and ``mdr.kernels_loops`` (the time loops), whose
public names are importable from here too.
"""
from __future__ import annotations

import dataclasses
import os

import numpy as np

from common.errors import ConvergenceError, InputError
from .kernels_loops import bedding_commit, bedding_force, bedding_normal, run_apparatus_loop, run_law
from .kernels_step import BEYOND_FRICTION, BEYOND_GRID, LIFT_OFF, NO_CONVERGENCE, OK, full_cells, numba
from .profiles import TruncatedSphere
from .solve import MAX_ITER
from .stick import AT_LIMIT

__all__ = ["BEYOND_FRICTION", "BEYOND_GRID", "CompiledBedding", "ENABLED", "LIFT_OFF", "NO_CONVERGENCE", "OK",
           "apparatus_loop", "parabolic_spheres",
           "enabled", "full_cells", "law_history", "normal_inputs", "run_apparatus_loop",
           "run_law"]

#: run histories through the compiled loops (False: the step API of mdr.law everywhere)
ENABLED = numba is not None and os.environ.get("MDR_PURE_PYTHON", "").strip() in ("", "0")


def enabled() -> bool:
    """True when the compiled loops are used (numba importable and not switched off)."""
    return bool(ENABLED) and numba is not None


# ------------------------------------------------------------------ glue (numpy side)
def normal_inputs(law, d):
    """Per step of the approaches d (shape batch + (T,)): (d_+, contact radius a, index of the
    one partly covered cell or -1, integral of g over its part in contact), exactly as
    ``MDRContact.normal_phase`` computes them (same calls of the profile)."""
    grid = law.grid
    batch = law.batch
    n = grid.n
    dp = np.maximum(d, 0.0)
    a = np.where(d > 0, law.profile.g_inv(dp), 0.0)
    x_max = grid.x_max.reshape(batch + (1,))
    if np.any(a > x_max * (1 + 1e-9)):
        raise InputError("the contact radius exceeds the spring grid: build the law with a larger F_max (or a_max)")
    a = np.minimum(a, x_max)
    S, T = int(np.prod(batch, dtype=int)), d.shape[-1]
    k = np.empty((S, T), dtype=np.int64)
    full_cells(_flat(a, batch, (T,)), _flat(grid.lo, batch, (n,)), _flat(grid.width, batch, (n,)), k)
    k = k.reshape(batch + (T,))
    has = (k < n) & (a > 0)
    kk = np.minimum(k, n - 1)
    lo_k = np.take_along_axis(np.broadcast_to(grid.lo, batch + (n,)), kk, axis=-1)
    part = np.where(has & (a > lo_k), law.profile.cell_integral(lo_k, np.maximum(a, lo_k)), 0.0)
    return dp, a, np.where(has, kk, -1), part


def _flat(x, batch, tail=()):
    """x broadcast to batch + tail, as a new writable C array of shape (S,) + tail (one
    type for every call: the compiled loops are specialised once)."""
    return np.array(np.broadcast_to(np.asarray(x, dtype=float), tuple(batch) + tuple(tail)), dtype=float,
                    order="C").reshape((-1,) + tuple(tail))


def law_history(law, load, d, state, force, rec0):
    """``MDRContact.run`` through the compiled loop. load, d: batch + (T,) arrays; state: the
    LawState to start from; rec0: first recorded step (T: none). Returns a dict of the
    History's fields (arrays batch + (T,)), the recorded slack/slipping and the final
    (v, ell, u) of the state; raises as the step API does."""
    batch = law.batch
    T = load.shape[-1]
    n = law.grid.n
    S = int(np.prod(batch, dtype=int))
    dp, a, kk, part = normal_inputs(law, d)
    grid = law.grid
    cells = lambda x: _flat(x, batch, (n,))  # noqa: E731
    steps = lambda x: _flat(x, batch, (T,))  # noqa: E731
    v, ell, u = cells(state.v), cells(state.ell), _flat(state.u, batch)
    out = {key: np.zeros((S, T)) for key in ("u", "Fx", "FN", "c", "work")}
    r_slack = np.zeros((S, T - rec0, n))
    r_slip = np.zeros((S, T - rec0, n), dtype=bool)
    bad = np.zeros((S, T), dtype=bool)
    status = np.zeros(S, dtype=np.int64)
    info = np.zeros((S, 3))
    run_law(bool(force), steps(dp), steps(a), np.array(np.broadcast_to(kk, batch + (T,)), dtype=np.int64, order="C").reshape(S, T),
            steps(part), steps(load), cells(grid.lo), cells(grid.width), cells(grid.int_g), cells(law.stick_nodes),
            float(law.E_star), float(law.G_star), _flat(law.mu, batch), 1.0 / float(law.stick_onset), AT_LIMIT,
            v, ell, u, int(rec0), out["u"], out["Fx"], out["FN"], out["c"], out["work"], r_slack, r_slip,
            bad, status, info)
    if force:
        _raise_force_control(law, load.reshape(S, T), out["FN"], bad, status, info)
    shape = batch + (T,)
    res = {key: val.reshape(shape) for key, val in out.items()}
    res["d"], res["a"] = dp, a
    res["slack"] = r_slack.reshape(batch + (T - rec0, n))
    res["slipping"] = r_slip.reshape(batch + (T - rec0, n))
    res["state"] = (v.reshape(batch + (n,)), ell.reshape(batch + (n,)), u.reshape(batch))
    return res


def _raise_force_control(law, target, FN, bad, status, info):
    """The errors of ``MDRContact.step`` under force control, at the first failing step."""
    T = target.shape[1]
    beyond = np.any(bad, axis=0) & np.any(np.abs(target) > 0, axis=0)
    t_in = int(np.argmax(beyond)) if np.any(beyond) else T
    failed = status == NO_CONVERGENCE
    t_nc = int(np.min(info[failed, 0])) if np.any(failed) else T
    if t_in < T and t_in <= t_nc:
        sel = bad[:, t_in]
        mu_FN = _flat(law.mu, law.batch)[sel] * FN[sel, t_in]
        raise InputError(f"tangential force Fx={float(np.max(np.abs(target[sel, t_in]))):.4g} N "
                         f"must stay below the friction limit mu*F_N={float(np.min(mu_FN)):.4g} N "
                         f"under force control (beyond it the contact slides without equilibrium)")
    if t_nc < T:
        sel = failed & (info[:, 0] == t_nc)
        raise ConvergenceError(f"MDR tangential force control: safeguarded Newton did not converge in {MAX_ITER} "
                               f"iterations (worst residual {float(np.max(info[sel, 1])):.3e}, tolerance "
                               f"{float(np.max(info[sel, 2])):.3e})")


def parabolic_spheres(bed, batch) -> bool:
    """True if the bedding law's profile is the parabolic sphere (b = 0) and its batch is batch + (2,)
    (the front sphere and one rear sphere of each scene): the bedding the compiled code steps."""
    prof = getattr(bed, "profile", None)
    return (isinstance(prof, TruncatedSphere) and not prof.exact and not np.any(np.asarray(prof.b) > 0)
            and tuple(getattr(bed, "batch", ())) == tuple(batch) + (2,))


def _plain_sphere_bedding(law, bed, batch):
    """True if the bedding law is an MDR law (the law's type) of parabolic spheres (``parabolic_spheres``)."""
    return type(bed) is type(law) and parabolic_spheres(bed, batch)


class CompiledBedding:
    """The MDR bedding of ``mdr.apparatus`` (an ``MDRContact`` of parabolic spheres, batch + (2,): the
    front sphere and one rear sphere; the second rear sphere is the first's twin) stepped by the
    compiled ``bedding_normal``/``bedding_force``/``bedding_commit``, for the step loop of
    ``run_apparatus`` around a contact law that has no compiled loop (the FE models, the rough
    half-space). The interface of ``mdr.apparatus.StepBedding``, which steps any bedding law through
    the step API: the same arithmetic as that API and as the bedding of ``run_apparatus_loop`` (sums
    in another order: a round-off; tests/test_mdr_kernels.py). The state is held here, updated by
    ``commit``. Assumes ``parabolic_spheres(bed, batch)`` and a law of the ``MDRContact`` step API."""

    def __init__(self, bed, batch):
        self.batch = tuple(batch)
        S = int(np.prod(self.batch, dtype=int))
        nb = bed.grid.n
        cells = lambda x: _flat(x, self.batch, (2, nb))  # noqa: E731
        sph = lambda x: _flat(x, self.batch, (2,))  # noqa: E731
        self.cells = (sph(bed.profile.R), float(bed.E_star), float(bed.G_star), sph(bed.mu), sph(bed.grid.x_max),
                      cells(bed.grid.lo), cells(bed.grid.width), cells(bed.grid.int_g))
        self.Gb2 = 2.0 * float(bed.G_star)
        self.ell, self.v, self.ub = np.zeros((S, 2, nb)), np.zeros((S, 2, nb)), np.zeros((S, 2))
        self.step = tuple(np.empty((S, 2, nb)) for _ in range(5))  # ellN, N, vmax, carried, v1
        self.F, self.k, self.tmp = np.empty(S), np.empty(S), np.empty(nb)

    def _x(self, ub):
        """A per-scene value (batch) as the compiled code's (S,) array."""
        x = np.asarray(ub, dtype=float)
        return x.reshape(-1) if x.shape == self.batch and x.flags.c_contiguous else _flat(x, self.batch)

    def normal(self, N_b):
        """The normal update at the sphere loads ``N_b`` (batch + (2,), > 0: the caller checks lift-off)."""
        N_b = np.asarray(N_b, dtype=float)
        if not bedding_normal(self._x(N_b[..., 0]), self._x(N_b[..., 1]), *self.cells, self.ell, self.v, *self.step):
            raise InputError("the contact radius exceeds the spring grid: build the law with a larger F_max (or a_max)")

    def force(self, ub):
        """(F_bed, dF_bed/du_b) of the prepared step at the bedding-plane displacement ``ub`` (batch)."""
        ellN, _, vmax, _, v1 = self.step
        bedding_force(v1, vmax, ellN, self.Gb2, self._x(ub), self.ub, self.F, self.k)
        return self.F.reshape(self.batch).copy(), self.k.reshape(self.batch).copy()

    def commit(self, ub):
        """Commit the prepared step at ``ub``: the bedding's tangential force F_bed (batch)."""
        ellN, _, vmax, _, v1 = self.step
        bedding_commit(v1, vmax, ellN, self.Gb2, self._x(ub), self.ub, self.ell, self.v, self.F, self.tmp)
        return self.F.reshape(self.batch).copy()


def apparatus_loop(law, bed, app, mu, FN, d, u3, cx, cp, first, state_at, g_acc, xtol):
    """The step loop of ``run_apparatus`` compiled, for an MDR law and (``bed``, or None
    without bedding) the MDR bedding of parabolic spheres; None when not applicable (the
    caller then runs its step loop). Returns (out, window, evaluations) as that loop
    leaves them."""
    batch = tuple(law.batch)
    if not enabled() or (bed is not None and not _plain_sphere_bedding(law, bed, batch)):
        return None
    T = u3.size
    n = law.grid.n
    S = int(np.prod(batch, dtype=int))
    shape = batch + (T,)
    FN = np.broadcast_to(np.asarray(FN, dtype=float), shape)
    d = np.broadcast_to(np.asarray(d, dtype=float), shape)
    dp, a, kk, part = normal_inputs(law, d)
    grid = law.grid
    cells = lambda x: _flat(x, batch, (n,))  # noqa: E731
    steps = lambda x: _flat(x, batch, (T,))  # noqa: E731
    per = lambda x: _flat(x, batch)  # noqa: E731
    use_bed = bed is not None
    if use_bed:
        nb = bed.grid.n
        bcells = lambda x: _flat(x, batch, (2, nb))  # noqa: E731
        bsph = lambda x: _flat(x, batch, (2,))  # noqa: E731
        bargs = (bcells(bed.grid.lo), bcells(bed.grid.width), bcells(bed.grid.int_g), bsph(bed.grid.x_max),
                 bsph(bed.profile.R), bsph(bed.mu), float(bed.E_star), float(bed.G_star))
    else:
        z2 = np.zeros((S, 2, 1))
        bargs = (z2, z2 + 1.0, z2, np.ones((S, 2)), np.ones((S, 2)), np.zeros((S, 2)), 1.0, 1.0)
    names = ("Fx", "FN", "u1", "u2", "du", "Fbed", "c")
    o = {key: np.zeros((S, T)) for key in names}
    evals = np.zeros((S, T), dtype=np.int64)
    W = T - first
    r_slack = np.zeros((S, W, n))
    r_slip = np.zeros((S, W, n), dtype=bool)
    sa_v, sa_ell, sa_u = np.zeros((S, n)), np.zeros((S, n)), np.zeros(S)
    status = np.zeros(S, dtype=np.int64)
    info = np.zeros((S, 3))
    sa = -1 if state_at is None else int(state_at)
    run_apparatus_loop(steps(dp), steps(a), np.array(kk.reshape(S, T), dtype=np.int64, order="C"), steps(part), steps(FN),
                       np.array(u3, dtype=float, order="C"), cells(grid.lo), cells(grid.width), cells(grid.int_g),
                       cells(law.stick_nodes), float(law.E_star), float(law.G_star), per(law.mu),
                       1.0 / float(law.stick_onset), AT_LIMIT, use_bed, *bargs,
                       per(cx), per(cp), per(app.m1 * g_acc), per(app.l1), per(app.l2), per(app.h), per(app.h2),
                       per(app.mu2 if use_bed else 0.0), float(xtol), int(first), sa,
                       o["Fx"], o["FN"], o["u1"], o["u2"], o["du"], o["Fbed"], o["c"], evals, r_slack, r_slip,
                       sa_v, sa_ell, sa_u, status, info)
    if np.any(status != OK):
        k = int(np.min(info[status != OK, 0]))
        code = int(np.min(status[(status != OK) & (info[:, 0] == k)]))
        if code == LIFT_OFF:
            raise InputError("the block lifts off a bedding sphere: tangential moment too large for the bedding geometry")
        if code == BEYOND_GRID:
            raise InputError("the contact radius exceeds the spring grid: build the law with a larger F_max (or a_max)")
        sel = (status == NO_CONVERGENCE) & (info[:, 0] == k)
        raise ConvergenceError(f"apparatus equilibrium: safeguarded Newton did not converge in {MAX_ITER} iterations "
                               f"(worst residual {float(np.max(info[sel, 1])):.3e}, tolerance {float(xtol):.3e})")
    out = {key: o[key].reshape(shape) for key in names}
    out["a"] = a
    if state_at is not None:
        out["state_at"] = dataclasses.replace(law.rest_state(), v=sa_v.reshape(batch + (n,)),
                                              ell=sa_ell.reshape(batch + (n,)), u=sa_u.reshape(batch),
                                              d=np.array(dp[..., sa]))
    slack = r_slack.reshape(batch + (W, n))
    slipping = r_slip.reshape(batch + (W, n))
    window = [(slack[..., i, :], slipping[..., i, :]) for i in range(W)]
    # the step loop counts the evaluations of the whole batch: the slowest scene of each step
    evaluations = int(np.sum(np.max(evals, axis=0))) if S else 0
    return out, window, evaluations
