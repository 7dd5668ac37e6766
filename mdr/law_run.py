"""Whole load histories of the MDR contact law: the three paths of ``mdr.law.MDRContact.run``.

- ``run_compiled``: the compiled loop of ``mdr.kernels`` (displacement and force control), its
  outputs assembled into a ``History``.
- ``run_force_steps``: force control without it, one ``step`` (a safeguarded Newton solve) per
  time step.
- ``run_blocks``: displacement control without it: the normal phases of a block of time steps
  at once, then a time loop over the tangential update only.

Assumptions: the caller (``MDRContact.run``) has checked the tangential ``load`` (u or F_x, as the drive) and broadcast it
(u or F_x) and the approaches d to batch + (T,), and checked ``rec0`` (the first recorded step,
T: none). The law is read through its own methods (``step``, ``normal_phase``, ``_slack``,
``_tangential_force``, ``stick_nodes``), so the paths stay the ones of the law's step API.
"""
from __future__ import annotations

import numpy as np

from . import kernels
from .law_types import History, LawState, NormalPhase
from .stick import per_step

#: the time series of a History
SERIES = ("u", "Fx", "FN", "d", "a", "c", "work")


def _recorded(law, T, rec0):
    """Empty arrays for the slack and slip flags of the recorded steps rec0..T-1."""
    return {k: np.empty(law.grid.width.shape[:-1] + (T - rec0,) + law.grid.width.shape[-1:], dtype=dt)
            for k, dt in (("slack", float), ("slipping", bool))}


def run_compiled(law, load, d, state, force, rec0, record) -> History:
    """``run`` through the compiled loop of ``mdr.kernels`` (same results to round-off)."""
    hist = kernels.law_history(law, load, d, state, force, rec0)
    v, ell, u = hist.pop("state")
    # the state's approach as the step API leaves it: as given (displacement control), d_+ (force control)
    last = hist["d"][..., -1] if force else d[..., -1]
    rec = {k: hist.pop(k) for k in ("slack", "slipping")}
    return History(state=LawState(v=v, ell=ell, u=u, d=np.array(last)), **hist, **(rec if record else {}))


def run_force_steps(law, load, d, state, rec0, record) -> History:
    """Force control step by step: ``drive`` the tangential force, one ``law.step`` per time step."""
    T = load.shape[-1]
    out = {k: np.empty(law.batch + (T,)) for k in SERIES}
    rec = _recorded(law, T, rec0)
    for t in range(T):
        res, state = law.step(state, d=d[..., t], Fx=load[..., t])
        for key in out:
            out[key][..., t] = getattr(res, key)
        if t >= rec0:
            rec["slack"][..., t - rec0, :] = res.slack
            rec["slipping"][..., t - rec0, :] = res.slipping
    return History(state=state, **out, **(rec if record else {}))


def run_blocks(law, load, d, state, block, rec0, record) -> History:
    """Displacement control in blocks of time steps: ``drive`` the total tangential displacement;
    ``block`` steps per block (None: ~1e6 numbers per block array)."""
    T = load.shape[-1]
    out = {k: np.empty(law.batch + (T,)) for k in SERIES}
    rec = _recorded(law, T, rec0)
    v, ell, u_prev = state.v.copy(), state.ell, state.u
    if block is None:  # bound the block arrays (batch x block x cells) to ~1e6 numbers
        block = int(np.clip(1_000_000 // max(v.size, 1), 1, 256))
    for t0 in range(0, T, block):
        t1 = min(T, t0 + block)
        db = d[..., t0:t1]
        if np.all(db == db[..., :1]):
            # constant normal load over the block: one normal phase, broadcast
            ph1 = law.normal_phase(db[..., 0])
            ph = NormalPhase(*(np.broadcast_to(np.expand_dims(x, -2 if x.ndim > len(law.batch) else -1),
                                               x.shape[:len(law.batch)] + (t1 - t0,) + x.shape[len(law.batch):])
                               for x in (ph1.d, ph1.a, ph1.ell, ph1.N, ph1.vmax, ph1.FN)))
        else:
            ph = law.normal_phase(db)
        ells = np.concatenate([ell[..., None, :], ph.ell], axis=-2)
        same = np.array_equal(ells[..., 1:, :], ells[..., :-1, :])
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = None if same else np.where(ells[..., 1:, :] > 0,
                                               np.minimum(1.0, ells[..., :-1, :] / ells[..., 1:, :]), 0.0)
        du = np.diff(np.concatenate([u_prev[..., None], load[..., t0:t1]], axis=-1), axis=-1)
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
        out["Fx"][..., sl] = law._tangential_force(ph.ell, v2s)
        out["FN"][..., sl] = ph.FN
        out["d"][..., sl] = ph.d
        out["a"][..., sl] = ph.a
        slack, slipping = law._slack(ph, trial, carried)
        out["c"][..., sl] = per_step(law.stick_nodes[..., None, :], slack, slipping, ph.a, law.stick_onset)
        if t1 > rec0:
            k0 = max(rec0, t0)
            rec["slack"][..., k0 - rec0:t1 - rec0, :] = slack[..., k0 - t0:, :]
            rec["slipping"][..., k0 - rec0:t1 - rec0, :] = slipping[..., k0 - t0:, :]
        out["work"][..., sl] = 2.0 * law.G_star * np.sum(ph.ell * ph.vmax * slip, axis=-1)
        ell = ph.ell[..., -1, :]
        v = v.copy()
        u_prev = load[..., t1 - 1]
    out["u"][...] = load
    return History(state=LawState(v=v, ell=ell, u=np.array(u_prev, dtype=float), d=np.array(d[..., -1])), **out,
                   **(rec if record else {}))
