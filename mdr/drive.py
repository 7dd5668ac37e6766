"""Drive a contact law directly with a harmonic fretting load (``mdr.loading.Loading``): the normal
force F_N(t) and either the tangential force (force control) or the relative displacement
(displacement control), from rest (the normal load applied at zero tangential load in the first
step). The result is a plain dict with the project's JSON keys (SI units); only the last cycle is
reported as the loop, and it is checked for stationarity. Under force control the slip index uses
the measured displacement amplitude u_A = (max du - min du)/2 of the last cycle.
"""
from __future__ import annotations

import time

import numpy as np

from common.errors import InputError
from .grid import DEFAULT_CELLS
from .law import MDRContact
from .loading import Loading
from .loops import analyse_cycles, path_integral, slip_index
from .materials import Materials
from .profiles import Profile
from .protocol import ContactLaw


def mdr_law(profile: Profile, materials: Materials, mu, loading: Loading, n: int = DEFAULT_CELLS) -> MDRContact:
    """The MDR law of ``n`` cells whose grid is sized for the load's normal-force range."""
    return MDRContact(profile, materials, mu, F_max=loading.F_max, F_min=loading.F_min, n=n)


def run_mdr_contact(profile: Profile, materials: Materials, mu, loading: Loading, n: int = DEFAULT_CELLS, **kw):
    """``run_contact`` of the MDR law of ``n`` cells sized for the load (``python -m mdr contact``)."""
    return run_contact(mdr_law(profile, materials, mu, loading, n), loading, **kw)


def normal_loading(law: ContactLaw, loading: Loading):
    """The law's state after the loading's normal loading (``Loading.normal_steps``): F_N from rest up to
    F_N(0) in equal steps with friction active and F_x = 0 (the rest state where the loading has none).
    The same for every law (``mdr.protocol.ContactLaw.step``)."""
    st, n, F = law.rest_state(), loading.normal_steps, float(np.ravel(loading.normal_force(0.0))[0])
    for k in range(1, n + 1):
        _, st = law.step(st, Fx=0.0, F_N=k / n * F)
    return st


def run_contact(law: ContactLaw, loading: Loading, *, state_at=None, state0=None, return_state: bool = False,
                on_history=None):
    """Drive a contact law directly with ``loading`` (drive ``"force"`` or ``"displacement"``); returns
    the result dict (JSON keys).

    ``law`` is any ``mdr.protocol.ContactLaw`` (its ``run``; ``mdr_law`` for MDR's); its ``mu`` is the
    friction of the slip index too. ``state_at`` (a step index): also return the law's state
    after that step, as ``(result, state)`` (the history is run in two pieces,
    which gives the same result). ``state0``: the law's state to start from (a continued history);
    default: its rest state after the loading's normal loading (``normal_loading``; the result's
    ``normal_loading`` says which preceded the cycles). ``return_state``: also return the
    law's state at the end, as ``(result, state)``, to continue the history (a run of k cycles
    from it continues this one: every cycle starts at the same phase); not with ``state_at``.
    ``on_history``: called with the run's whole ``mdr.law.History`` (one history also where it ran in
    two pieces), e.g. to read a law's recorded ``fields``.
    """
    if return_state and state_at is not None:
        raise InputError("give at most one of state_at and return_state")
    if loading.drive not in ("force", "displacement"):
        raise InputError(f"run_contact drives the contact directly (drive 'force' or 'displacement'), got drive "
                         f"{loading.drive!r}: the apparatus is mdr.apparatus.apparatus_result")
    mu = loading.check_friction(law.mu)
    F0, steps = loading.F0, loading.steps
    t_start = time.perf_counter()
    t, FN, load = loading.times(), loading.normal_force(), loading.tangential()
    key = "u" if loading.drive == "displacement" else "Fx"
    kept = None
    ramp = loading.normal_loading_record() if state0 is None else None
    if state0 is None and loading.normal_steps:
        state0 = normal_loading(law, loading)
    first = loading.last_cycle.start  # the last (stationary) cycle: steps first .. first + steps
    if state_at is None:
        H = law.run(**{key: load}, F_N=FN, record_from=first, state=state0)
    else:
        k = int(state_at)
        if not 0 <= k < t.size - 1:
            raise InputError(f"state_at must be a step index in [0, {t.size - 2}], got {state_at!r}")
        H1 = law.run(**{key: load[:k + 1]}, F_N=FN[:k + 1], record_from=min(first, k + 1), state=state0)
        H2 = law.run(**{key: load[k + 1:]}, F_N=FN[k + 1:], state=H1.state, record_from=max(first - k - 1, 0))
        kept = H1.state
        H = H1.then(H2)
    if on_history is not None:
        on_history(H)
    cyc = analyse_cycles(H.u, H.Fx, steps, mu, F0, driven=loading.drive)
    last = loading.last_cycle
    dW = float(cyc.dissipation[-1])
    u_amp = loading.ua if loading.ua is not None else 0.5 * float(np.ptp(H.u[last]))
    stationary = bool(cyc.last_is_stationary) or mu == 0
    # the first cycle after the normal loading, +Q -> -Q -> +Q (from the drive's first peak, a quarter
    # cycle in; a Loading has steps a multiple of 4 and cycles >= 2): the friction work of its steps, what
    # it dissipates whether or not its loop closes (under coupling the displacement drifts over it, and
    # closing the loop by a segment would add Q times the drift); the open path from rest
    # 0 -> +Q -> -Q -> 0 is cycle 0 (without coupling, at a constant normal force, the first cycle is
    # already the stationary one: Masing's rule)
    q = steps // 4
    first_loop = float(np.sum(H.work[q + 1:q + steps + 1]))
    first_path = float(path_integral(H.u[q:q + steps + 1], H.Fx[q:q + steps + 1]))  # the loop left open
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
        "tangential_work_first_cycle": first_path,
        "dissipation_open_path": float(cyc.dissipation[0]),
        "stationary": stationary,
        "normal_loading": ramp,  # None: a continued history (its first run's holds it)
        "cycle_change": cyc.last_change(),
        "first_stationary_cycle": int(cyc.first_stationary),
        "runtime_s": runtime,
        "loop": {"t": t[last].tolist(), "du": H.u[last].tolist(), "Fx": H.Fx[last].tolist(), "FN": H.FN[last].tolist()},
        "inputs": {**law.profile.describe(), **law.materials.as_dict(), "mu": mu, **loading.as_inputs(),
                   "law": law.describe()},
    }
    if return_state:
        return out, H.state
    return out if state_at is None else (out, kept)
