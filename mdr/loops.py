"""Fretting-loop analysis: cycles, stationarity, dissipation, slip index.

A history sampled with ``steps`` samples per cycle and T = cycles*steps + 1
samples (t = 0 included) is cut into cycles k = 0..cycles-1, cycle k holding
samples k*steps .. (k+1)*steps. The first cycle starts from rest and is not
stationary; a cycle counts as stationary when its loop matches the previous
one in the free variable of the drive and in dissipation (relative change <= tol).
The free variable is F_x under displacement control (max |F_x difference| <= tol * mu F0)
and du under force control, where F_x repeats by construction (max |du difference| <=
tol * the cycle's du amplitude, half its du range: a ratcheting loop drifts in du).
Dissipation per cycle dW = |closed integral F_x d(du)| (trapezoidal rule on the
samples; below ``ZERO_FRACTION`` of the loop's box it is round-off and exactly 0); slip index delta = dW / (4 mu u_A F0) (Willert, Machines 11 (2023)
484, Eq. 4, after Varenberg, Etsion & Halperin, Tribol. Lett. 17 (2004) 569).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from common.errors import InputError, positive_int
from .loading import gross_slip_work


#: a loop integral below this fraction of its loop's box (max |F_x| x the du range) is round-off,
#: and is 0: the trapezoidal sum of ~1e3 terms of size F_x d(du) carries ~1e-13 of the box in
#: round-off, which differs between CPUs (numpy's SIMD kernels), so a loop that closes exactly
#: (full stick) must give 0 on every machine, not 1e-26 J on one and 0 on another
ZERO_FRACTION = 1e-10


def path_integral(du, Fx):
    """integral F_x d(du) along the path (the last axis), by the trapezoid rule, signed and open: the
    tangential force's work over it."""
    du, Fx = np.asarray(du, dtype=float), np.asarray(Fx, dtype=float)
    return np.sum(0.5 * (Fx[..., 1:] + Fx[..., :-1]) * np.diff(du, axis=-1), axis=-1)


def _trapezoid_area(du, Fx):
    """|closed integral F_x d(du)| along the last axis, 0 below ``ZERO_FRACTION`` of the loop's box."""
    W = np.abs(path_integral(du, Fx))
    box = np.max(np.abs(Fx), axis=-1) * np.ptp(du, axis=-1)
    return np.where(W <= ZERO_FRACTION * box, 0.0, W)


def loop_integral(du, Fx):
    """|closed integral F_x d(du)| over one closed loop (closes it if needed); 0 below
    ``ZERO_FRACTION`` of the loop's box (round-off)."""
    du = np.asarray(du, dtype=float)
    Fx = np.asarray(Fx, dtype=float)
    if du[..., 0].shape == () and (du[0] != du[-1] or Fx[0] != Fx[-1]):
        du = np.append(du, du[0])
        Fx = np.append(Fx, Fx[0])
    return _trapezoid_area(du, Fx)


@dataclass
class CycleAnalysis:
    dissipation: np.ndarray       # dW of every cycle (batch + (cycles,))
    loop_change: np.ndarray       # change of the free variable from cycle k-1 (analyse_cycles), cycle 0: inf
    dissipation_change: np.ndarray  # |dW_k - dW_k-1| / dW_k (0 where dW_k is zero), cycle 0: inf
    stationary: np.ndarray        # bool (batch + (cycles,)): cycle k is stationary
    first_stationary: np.ndarray  # index of the first stationary cycle, -1 if none

    @property
    def last_is_stationary(self):
        return self.stationary[..., -1]

    def last_change(self) -> dict:
        """The last cycle's change from the one before (one scene): ``loop`` (the free variable's,
        see ``analyse_cycles``) and ``dissipation`` (relative); None where there is no earlier cycle.
        Only cycles after the first can be stationary: the first starts from rest."""
        def last(x):
            v = float(np.asarray(x)[..., -1])
            return v if np.isfinite(v) else None
        return {"loop": last(self.loop_change), "dissipation": last(self.dissipation_change)}


#: a cycle is stationary when it repeats the one before within this fraction (``analyse_cycles``)
STATIONARY_TOL = 1e-3

#: what a history's drive prescribes: ``analyse_cycles(driven=...)``
DRIVEN = ("displacement", "force")


def analyse_cycles(du, Fx, steps: int, mu, F0, tol: float = STATIONARY_TOL, *, driven: str) -> CycleAnalysis:
    """Cut a history (batch + (T,)) into cycles and test them for stationarity.

    ``driven``: ``"displacement"`` when the history prescribes a displacement (du itself, or a
    machine stroke in series with compliances: F_x is free), its loop change max |F_x,k -
    F_x,k-1| / (mu F0); ``"force"`` when it prescribes F_x, whose repetition says nothing, so the
    loop change is max |du_k - du_k-1| / u_k with u_k = ptp(du_k) / 2 the du amplitude of cycle k.
    """
    steps = positive_int("steps", steps, minimum=4)
    if driven not in DRIVEN:
        raise InputError(f"driven must be one of {DRIVEN} (what the history prescribes), got {driven!r}")
    du = np.asarray(du, dtype=float)
    Fx = np.asarray(Fx, dtype=float)
    T = du.shape[-1]
    cycles = (T - 1) // steps
    if cycles < 1:
        raise ValueError(f"history of {T} samples holds no full cycle of {steps} steps")
    idx = np.arange(cycles)[:, None] * steps + np.arange(steps + 1)[None, :]
    U = du[..., idx]
    F = Fx[..., idx]
    W = _trapezoid_area(U, F)
    scale = np.maximum(np.asarray(mu, dtype=float) * np.asarray(F0, dtype=float), 1e-300)
    scale = np.reshape(scale, np.shape(scale) + (1,)) if np.ndim(scale) else scale
    change = np.full(W.shape, np.inf)
    if driven == "displacement":
        change[..., 1:] = np.max(np.abs(F[..., 1:, :] - F[..., :-1, :]), axis=-1) / scale
    else:
        u_amp = np.maximum(0.5 * np.ptp(U[..., 1:, :], axis=-1), 1e-300)
        change[..., 1:] = np.max(np.abs(U[..., 1:, :] - U[..., :-1, :]), axis=-1) / u_amp
    dW_change = np.full(W.shape, np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):
        dW_change[..., 1:] = np.abs(W[..., 1:] - W[..., :-1]) / np.maximum(W[..., 1:], 1e-300)
    dW_change[..., 1:] = np.where(W[..., 1:] <= 1e-12 * scale * np.max(np.abs(U), axis=-1)[..., 1:], 0.0,
                                  dW_change[..., 1:])
    stat = (change <= tol) & (dW_change <= tol)
    first = np.where(np.any(stat, axis=-1), np.argmax(stat, axis=-1), -1)
    return CycleAnalysis(dissipation=W, loop_change=change, dissipation_change=dW_change, stationary=stat,
                         first_stationary=first)


def slip_index(dW, mu, u_A, F0):
    """delta = dW / (4 mu u_A F0) (``mdr.loading.gross_slip_work``); NaN where mu u_A F0 = 0 (undefined)."""
    den = gross_slip_work(mu, F0, u_A)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(den > 0, np.asarray(dW, dtype=float) / np.where(den > 0, den, 1.0), np.nan)
