"""The harmonic fretting load: one home of the load history, its time grid and its scales.

Time runs in cycles, sampled at ``t = k / steps``, k = 0 .. cycles * steps (from rest: the normal
load is applied at zero tangential load in the first step)::

    F_N(t) = F0 + dF sin(2 pi t + alpha)
    tangential: amplitude * sin(2 pi t)

where the tangential drive is, by ``drive``, the tangential force F_x (``"force"``, N), the
contact's relative displacement u (``"displacement"``, m) or the apparatus's piezo displacement u_3
(``"apparatus"``, m: ``mdr.apparatus``). Only the last cycle is reported (the stationary one, once
the history has settled); the slip index's gross-slip work 4 mu F0 u_A (Willert 2023, Machines 11,
484, Eq. 4) is :func:`gross_slip_work`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from common.errors import InputError, finite, nonnegative, positive, positive_int
from .paper import TABLE2

#: what the tangential amplitude drives, and its unit
DRIVES = {"force": "N", "displacement": "m", "apparatus": "m"}


def gross_slip_work(mu, F0, u_A):
    """4 mu F0 u_A (J): the work of one cycle of gross sliding at the friction limit mu F0 over a
    relative displacement amplitude u_A; the scale of the slip index and of a loop's dissipation."""
    return 4.0 * np.asarray(mu, dtype=float) * np.asarray(F0, dtype=float) * np.asarray(u_A, dtype=float)


#: a loop dissipating less than this fraction of 4 mu F0 u_A (``gross_slip_work``) hardly dissipates (a
#: sticking punch): its errors and its settling are measured in that unit, not relative to its own
#: dissipation (``fem.contact_run.settled``, ``validation.metrics.dissipation_error``,
#: ``validation.sides.time_step_error``)
HARDLY_DISSIPATES = 0.01


@dataclass(frozen=True)
class Loading:
    """A harmonic fretting load (SI; module docstring), checked once on construction: F0 > 0,
    0 <= dF <= F0 (the normal force never tensile), alpha finite, amplitude > 0 in the unit of its
    ``drive``, cycles >= 2, steps a multiple of 4 (the load reversals are sampled), >= 8.
    ``dF`` and ``alpha`` may be batch arrays (one value per scene of a batch law, the apparatus's
    studies); every other field is one number. ``normal_steps`` >= 0: the normal loading before the
    cycles, from rest to F_N(0) in that many steps with friction active and F_x = 0 (``mdr.drive.
    normal_loading``; with coupling, slip during it locks traction in, Spence 1975); 0: none, the cycles'
    first sample (t = 0, where the tangential load is zero) applies the normal force at once."""

    F0: float
    amplitude: float
    drive: str = "force"
    dF: float = 0.0
    alpha: float = 0.0
    cycles: int = 3
    steps: int = 400
    normal_steps: int = 0

    def __post_init__(self):
        if self.drive not in DRIVES:
            raise InputError(f"drive must be one of {', '.join(DRIVES)}, got {self.drive!r}")
        F0 = positive("F0", self.F0)
        dF = nonnegative("dF", self.dF)
        if np.any(np.asarray(dF) > F0):
            raise InputError(f"dF must be in [0, F0] (the normal force may not become tensile), got dF={dF!r}, "
                             f"F0={F0!r}")
        name = {"force": "fa", "displacement": "ua", "apparatus": "ua"}[self.drive]
        amplitude = positive(name, self.amplitude)
        alpha = finite("alpha", self.alpha)
        cycles = positive_int("cycles", self.cycles, minimum=2)
        steps = positive_int("steps", self.steps, minimum=8)
        if steps % 4:
            raise InputError(f"steps must be a multiple of 4 (so the load reversals are sampled), got {steps}")
        normal_steps = positive_int("normal_steps", self.normal_steps, minimum=0)
        for k, v in (("F0", F0), ("dF", dF), ("amplitude", amplitude), ("alpha", alpha), ("cycles", cycles),
                     ("steps", steps), ("normal_steps", normal_steps)):
            object.__setattr__(self, k, v)

    @classmethod
    def of(cls, F0, dF=0.0, alpha=0.0, *, ua=None, fa=None, cycles=3, steps=400) -> "Loading":
        """The load of a contact driven directly, from the command line's amplitudes: exactly one of
        ``ua`` (displacement control, m) and ``fa`` (force control, N)."""
        if (ua is None) == (fa is None):
            raise InputError("give exactly one of ua (displacement amplitude) or fa (force amplitude)")
        drive, amplitude = ("displacement", ua) if ua is not None else ("force", fa)
        return cls(F0, amplitude, drive, dF, alpha, cycles, steps)

    @classmethod
    def apparatus(cls, F0, dF=TABLE2["dF"], alpha=0.0, ua=TABLE2["ua"], *, cycles=4, steps=200) -> "Loading":
        """The load of the apparatus (``mdr.apparatus``): the normal force and the piezo amplitude ``ua`` (m);
        the defaults are the paper's Table 2 (dF = 0.1 N, u_A = 150 nm)."""
        return cls(F0, ua, "apparatus", dF, alpha, cycles, steps)

    @property
    def unit(self) -> str:
        """The unit of ``amplitude``: N under force control, m otherwise."""
        return DRIVES[self.drive]

    @property
    def ua(self):
        """The displacement amplitude (m), or None under force control."""
        return None if self.drive == "force" else self.amplitude

    @property
    def fa(self):
        """The force amplitude (N), or None under displacement control."""
        return self.amplitude if self.drive == "force" else None

    @property
    def F_max(self):
        """The largest normal force F0 + dF (N; an array for a batch)."""
        return self.F0 + self.dF  # dF a float or an array once checked

    @property
    def F_min(self):
        """The smallest normal force F0 - dF (N), or None where it is 0 (dF = F0: the contact opens)."""
        if np.ndim(self.dF):
            return self.F0 - self.dF
        return self.F0 - self.dF if self.dF < self.F0 else None

    @property
    def n_steps(self) -> int:
        """Steps of the whole history (its samples are one more)."""
        return self.cycles * self.steps

    def times(self) -> np.ndarray:
        """The sample times t = k / steps (in cycles), k = 0 .. cycles * steps."""
        return np.arange(self.n_steps + 1) / self.steps

    def normal_force(self, t=None) -> np.ndarray:
        """F_N(t) (N) at the times ``t`` (default the sample times); a batch's rows on the first axes."""
        t = self.times() if t is None else np.asarray(t, dtype=float)
        dF, alpha = np.asarray(self.dF, dtype=float), np.asarray(self.alpha, dtype=float)
        if dF.ndim or alpha.ndim:
            dF, alpha = dF[..., None], alpha[..., None]
        return self.F0 + dF * np.sin(2.0 * np.pi * t + alpha)

    def tangential(self, t=None) -> np.ndarray:
        """The tangential drive amplitude sin(2 pi t) (N or m, ``unit``) at the times ``t``."""
        t = self.times() if t is None else np.asarray(t, dtype=float)
        return self.amplitude * np.sin(2.0 * np.pi * t)

    @property
    def last_cycle(self) -> slice:
        """The samples of the last (reported) cycle, its closing sample included."""
        return slice(self.n_steps - self.steps, self.n_steps + 1)

    def last_peak(self) -> tuple[int, float]:
        """The step of the drive's peak in the last cycle (a quarter cycle into it, sin(2 pi t) = 1) and
        the normal force F_N there (N; a scalar load): where the fields are read."""
        k = self.n_steps - self.steps + self.steps // 4
        return k, float(self.F0 + self.dF * np.sin(2.0 * np.pi * k / self.steps + self.alpha))

    def check_friction(self, mu):
        """Force control needs a friction limit above the drive at every instant (no equilibrium in
        gross sliding): mu > 0 and |fa sin(2 pi t)| < mu F_N(t). A displacement drive needs mu >= 0."""
        mu = nonnegative("mu", mu)
        if self.drive != "force":
            return mu
        if np.all(np.asarray(mu) == 0):
            raise InputError("fa (force control) needs mu > 0: a frictionless contact carries no tangential "
                             "force; use ua (displacement control) with mu = 0")
        need = np.abs(self.tangential())
        limit = np.asarray(mu)[..., None] * self.normal_force() if np.ndim(mu) else mu * self.normal_force()
        if np.any(need >= limit * (1 - 1e-9)):
            ratio = np.max(need / np.maximum(limit, 1e-300))
            raise InputError(f"fa must stay below the friction limit mu*F_N(t) at every instant (force control has "
                             f"no equilibrium in gross sliding); fa={self.amplitude:g} N is {ratio:.3g} times the "
                             f"limit, so use fa < {self.amplitude / ratio:.4g} N")
        return mu

    def normal_loading_record(self) -> dict:
        """What a result states of the normal loading before its cycles (its key ``normal_loading``): the
        steps, with friction active and F_x = 0; ``{"steps": 0}`` where there is none (the cycles' first
        sample applies the normal force)."""
        if not self.normal_steps:
            return {"steps": 0}
        return {"steps": self.normal_steps, "friction": True, "F_x": 0.0}

    def as_inputs(self) -> dict:
        """The load's keys of a result's ``inputs`` (the JSON contract: F0, dF, alpha, ua, fa, cycles,
        steps)."""
        listed = lambda v: np.asarray(v).tolist() if np.ndim(v) else v  # noqa: E731
        out = {"F0": self.F0, "dF": listed(self.dF), "alpha": listed(self.alpha), "ua": self.ua, "fa": self.fa,
               "cycles": self.cycles, "steps": self.steps}
        if self.drive == "apparatus":
            del out["fa"]
        return out
