"""Drive a contact law directly with harmonic fretting loads.

Loading (time in cycles, t = k/steps):

    F_N(t) = F0 + dF sin(2 pi t + alpha)
    u(t)   = u_A sin(2 pi t)      (displacement control, ``ua``)  or
    F_x(t) = f_A sin(2 pi t)      (force control, ``fa``)

starting from rest (normal load applied at u = 0 in the first step). The
result is a plain dict with the project's JSON keys (SI units); only the last
cycle is reported as the loop, and it is checked for stationarity.
Under force control the slip index uses the measured displacement amplitude
u_A = (max du - min du)/2 of the last cycle.
"""
from __future__ import annotations

import time

import numpy as np

from common.errors import InputError, finite, nonnegative, positive, positive_int
from .grid import DEFAULT_CELLS
from .law import MDRContact
from .loops import analyse_cycles, loop_integral, slip_index
from .materials import Materials
from .profiles import Profile
from .protocol import ContactLaw


def harmonic_history(F0, dF, alpha, cycles, steps):
    """Sample times t (in cycles) and normal forces F_N(t)."""
    t = np.arange(cycles * steps + 1) / steps
    return t, F0 + dF * np.sin(2.0 * np.pi * t + alpha)


def last_peak(F0, dF, alpha, cycles, steps) -> tuple[int, float]:
    """The step of the drive's peak in the last cycle (a quarter cycle into it, sin(2 pi t) = 1;
    ``steps`` a multiple of 4) and the normal force F_N there (N): where the fields are read."""
    k = (cycles - 1) * steps + steps // 4
    return k, float(F0 + dF * np.sin(2.0 * np.pi * k / steps + alpha))


def check_harmonic_load(F0, dF, alpha, cycles, steps):
    """Validate the normal force F0 + dF sin(2 pi t + alpha) and the time sampling (``dF`` and
    ``alpha`` may be batch arrays), for every driver: ``check_loading`` here and the apparatus.
    Returns them normalised."""
    F0 = positive("F0", F0)
    dF = nonnegative("dF", dF)
    if np.any(np.asarray(dF) > F0):
        raise InputError(f"dF must be in [0, F0] (the normal force may not become tensile), got dF={dF!r}, F0={F0!r}")
    alpha = finite("alpha", alpha)
    cycles = positive_int("cycles", cycles, minimum=2)
    steps = positive_int("steps", steps, minimum=8)
    if steps % 4:
        raise InputError(f"steps must be a multiple of 4 (so the load reversals are sampled), got {steps}")
    return F0, dF, alpha, cycles, steps


def check_loading(F0, dF, alpha, mu, ua, fa, cycles, steps):
    """Validate the harmonic loading parameters of ``run_contact``; returns them normalised."""
    F0, dF, alpha, cycles, steps = check_harmonic_load(F0, dF, alpha, cycles, steps)
    mu = nonnegative("mu", mu)
    if (ua is None) == (fa is None):
        raise InputError("give exactly one of ua (displacement amplitude) or fa (force amplitude)")
    if ua is not None:
        ua = positive("ua", ua)
    if fa is not None:
        fa = positive("fa", fa)
        if mu == 0:
            raise InputError("fa (force control) needs mu > 0: a frictionless contact carries no tangential "
                             "force; use ua (displacement control) with mu = 0")
    if fa is not None:
        t, FN = harmonic_history(F0, dF, alpha, cycles, steps)
        need = np.abs(fa * np.sin(2.0 * np.pi * t))
        if np.any(need >= mu * FN * (1 - 1e-9)):
            ratio = np.max(need / np.maximum(mu * FN, 1e-300))
            raise InputError(f"fa must stay below the friction limit mu*F_N(t) at every instant "
                             f"(force control has no equilibrium in gross sliding); fa={fa:g} N is "
                             f"{ratio:.3g} times the limit, so use fa < {fa / ratio:.4g} N")
    return F0, dF, alpha, mu, ua, fa, cycles, steps


def run_contact(profile: Profile, materials: Materials, mu, F0, dF=0.0, alpha=0.0, ua=None, fa=None,
                cycles: int = 3, steps: int = 400, n: int = DEFAULT_CELLS, law: ContactLaw | None = None,
                state_at=None, state0=None, return_state: bool = False):
    """Drive a contact law directly; returns the result dict (JSON keys).

    ``law`` is any ``mdr.protocol.ContactLaw`` (its ``run``); default: an MDRContact with ``n`` cells sized for
    the load history. ``state_at`` (a step index): also return the law's state
    after that step, as ``(result, state)`` (the history is run in two pieces,
    which gives the same result). ``state0``: the law's state to start from (default its rest
    state), e.g. after a normal loading with friction active. ``return_state``: also return the
    law's state at the end, as ``(result, state)``, to continue the history (a run of k cycles
    from it continues this one: every cycle starts at the same phase); not with ``state_at``.
    """
    if return_state and state_at is not None:
        raise InputError("give at most one of state_at and return_state")
    F0, dF, alpha, mu, ua, fa, cycles, steps = check_loading(F0, dF, alpha, mu, ua, fa, cycles, steps)
    t_start = time.perf_counter()
    if law is None:
        law = MDRContact(profile, materials, mu, F_max=F0 + dF, F_min=F0 - dF if dF < F0 else None, n=n)
    elif np.ndim(law.mu) == 0 and float(law.mu) != mu:
        # the law's own mu sets the physics, mu the slip index: they must agree
        raise InputError(f"mu={mu!r} conflicts with the contact law's mu={float(law.mu)!r}; give the same value")
    t, FN = harmonic_history(F0, dF, alpha, cycles, steps)
    s = np.sin(2.0 * np.pi * t)
    drive = ua * s if ua is not None else fa * s
    key = "u" if ua is not None else "Fx"
    kept = None
    first = cycles * steps - steps  # the last (stationary) cycle: steps first .. first + steps
    if state_at is None:
        H = law.run(**{key: drive}, F_N=FN, record_from=first, state=state0)
    else:
        k = int(state_at)
        if not 0 <= k < t.size - 1:
            raise InputError(f"state_at must be a step index in [0, {t.size - 2}], got {state_at!r}")
        H1 = law.run(**{key: drive[:k + 1]}, F_N=FN[:k + 1], record_from=min(first, k + 1), state=state0)
        H2 = law.run(**{key: drive[k + 1:]}, F_N=FN[k + 1:], state=H1.state, record_from=max(first - k - 1, 0))
        kept = H1.state
        H = type(H2)(state=H2.state, **{f: np.concatenate([getattr(H1, f), getattr(H2, f)], axis=-1)
                                        for f in ("u", "Fx", "FN", "d", "a", "c", "work")},
                     **{f: np.concatenate([getattr(H1, f), getattr(H2, f)], axis=-2) for f in ("slack", "slipping")})
    driven = "displacement" if ua is not None else "force"
    cyc = analyse_cycles(H.u, H.Fx, steps, mu, F0, driven=driven)
    last = slice(first, cycles * steps + 1)
    dW = float(cyc.dissipation[-1])
    u_amp = ua if ua is not None else 0.5 * float(np.ptp(H.u[last]))
    stationary = bool(cyc.last_is_stationary) or mu == 0
    # the first closed loop after the normal loading, +Q -> -Q -> +Q (from the drive's first peak, a
    # quarter cycle in; check_loading makes steps a multiple of 4 and cycles >= 2); the open path from
    # rest 0 -> +Q -> -Q -> 0 is cycle 0 (without coupling, at a constant normal force, the first closed
    # loop is already the stationary one: Masing's rule)
    q = steps // 4
    first_loop = float(loop_integral(H.u[q:q + steps + 1], H.Fx[q:q + steps + 1]))
    delta = float(slip_index(dW, mu, u_amp, F0))
    runtime = time.perf_counter() - t_start
    out = {
        **law.contact_at(F0),  # the law's own (an FE law's: the FE's), never another model's
        "normal_force": F0,
        "stick_radius": float(H.window_stick_radius(law)),
        "dissipation": dW,
        "friction_work": float(np.sum(H.work[last][1:])),
        "slip_index": None if not np.isfinite(delta) else delta,
        "displacement_amplitude": u_amp,
        "tangential_force_amplitude": 0.5 * float(np.ptp(H.Fx[last])),
        "dissipation_per_cycle": cyc.dissipation.tolist(),
        "dissipation_first_cycle": first_loop,
        "dissipation_open_path": float(cyc.dissipation[0]),
        "stationary": stationary,
        "cycle_change": cyc.last_change(),
        "first_stationary_cycle": int(cyc.first_stationary),
        "runtime_s": runtime,
        "loop": {"t": t[last].tolist(), "du": H.u[last].tolist(), "Fx": H.Fx[last].tolist(), "FN": H.FN[last].tolist()},
        "inputs": {**profile.describe(), **materials.as_dict(), "mu": mu, "F0": F0, "dF": dF, "alpha": alpha,
                   "ua": ua, "fa": fa, "cycles": cycles, "steps": steps,
                   "law": law.describe()},
    }
    if return_state:
        return out, H.state
    return out if state_at is None else (out, kept)
