"""One step of the FE contact law (``fem.axisym.law.FEContact``) as functions of the law and an
explicit state: the state (``FEState``), the normal part of a step, the tangential return map,
the step's result, and a prepared step (``FETrial``).

- ``normal_part``: mode 0 at the step's normal force or plate approach (``FEContact.normal``,
  cached per load value), the slip limits g_i = mu lam_i of the pairs and the previous plastic
  slip (a pair out of contact follows the relative displacement).
- ``tangential``: the Coulomb return map on the condensed interface (``fem.axisym.friction``)
  with the augmented Lagrangian of ``friction_al_tol``, at plate displacement u or force F_x.
- ``finish``: the slip update, the slack to the slip limit, the slip flags and the stick
  radius: the ``mdr.law.StepResult`` and the new ``FEState``.

Assumptions: one scene (scalars per step, arrays over the n contact pairs); the law is set up
(``Ct``, ``M``, penalty ``k`` and their factorisations) and keeps only caches and counters
(``stats``), so a step is a pure function of the state: nothing here changes a state.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from common.errors import ConvergenceError, InputError, nonnegative
from mdr.law import StepResult
from mdr.stick import at_limit, per_step

from fem.axisym.friction import slip_update, solve_increment
from fem.solvers import blas_threads
from fem.stepping import frozen


@dataclass(frozen=True)
class FEState:
    """History of the FE contact (read-only arrays over the n pairs): tangential pair forces
    ``T`` (N), plastic slip ``slip`` (m), normal pair forces ``lam`` (N), last sliding sets
    ``sgn`` (warm start), plate displacement ``u`` and approach ``d`` (m)."""

    T: np.ndarray
    slip: np.ndarray
    lam: np.ndarray
    sgn: np.ndarray
    u: float
    d: float


def normal_part(law, state, d, F_N) -> dict:
    """The normal part of a step from ``state`` at normal force ``F_N`` or plate approach ``d``: the
    dict (ctx) that ``tangential`` and ``finish`` read (a force of 0 or an approach <= 0: contact
    lost, no pair carries a force)."""
    n = law.n_pairs
    if F_N is not None:
        F_N = float(nonnegative("F_N (normal force; no adhesion, so >= 0)", F_N))
        lost = F_N == 0.0
    else:
        d = float(d)
        if not np.isfinite(d):
            raise InputError(f"d must be finite, got {d!r}")
        lost = d <= 0.0
    if lost:
        lam = np.zeros(n)
        FN, dd, a = 0.0, (0.0 if d is None else d), 0.0
    else:
        res = law.normal(F_N=F_N, d=d)
        lam, FN, dd, a = res.lam, res.force, res.approach, res.contact_radius
    T_old = np.asarray(state.T)
    s_old = state.u - law.Ct @ T_old
    g = law.mu * lam
    contact = g > 0
    any_contact = bool(contact.any())
    return {"state": state, "lam": lam, "FN": FN, "d": dd, "a": a, "g": g, "T_old": T_old,
            "slip_old": np.where(np.asarray(state.lam) > 0, state.slip, s_old), "contact": contact,
            "any_contact": any_contact, "gmax": float(g.max()) if any_contact else 0.0,
            "sgn_old": np.asarray(state.sgn), "u": None}


def tangential(law, ctx, u, Fx):
    """Tangential return map of a step at plate displacement ``u`` or force ``Fx``: the
    solve only, returns the dict of ``finish`` (no contact: None) with the forces
    ``T``, displacement ``u``, sets ``sgn``, last multipliers ``lbar`` and the tangent
    ``slope`` dFx/du of the stick set.

    Augmented Lagrangian (``fem.axisym.friction``): passes lbar <- T until the largest change is
    below ``friction_al_tol`` of the largest slip limit. Its limit lbar = T is the exact
    Coulomb return map: the box QP of ``fem.axisym.friction`` with M = Ct (no penalty) and
    b = -slip_old, whose active-set iteration has the same set test as an AL pass at that
    limit. With ``friction_exact_start`` that problem is solved first and its forces
    start the AL, so the first pass normally meets the tolerance (it then checks the
    solution, and carries on from it if not; should that solve fail, the classical start
    is taken); otherwise the passes start from the
    previous forces clipped to the new limits (about four passes at the default
    tolerance). The tangent is that of the map the passes converge to: sum Ct_ff^-1 1
    over the sticking pairs f with the exact start (the AL limit), sum M_ff^-1 1 without
    (one pass, the classical path), and with the pure penalty."""
    n = law.n_pairs
    FN, g = ctx["FN"], ctx["g"]
    T_old, slip_old = ctx["T_old"], ctx["slip_old"]
    if Fx is not None and abs(Fx) >= law.mu * FN * (1 - 1e-12) and Fx != 0.0:
        raise InputError(f"tangential force Fx={Fx:.4g} N must stay below the friction limit "
                         f"mu*F_N={law.mu * FN:.4g} N under force control")
    contact = ctx["contact"]
    if not ctx["any_contact"]:
        return None
    k = law.k
    sgn = ctx["sgn_old"]
    newton = 0
    exact = law.friction_al_tol > 0 and law.friction_exact_start
    with blas_threads(1):
        if exact:
            try:
                lbar, _, sgn, nit, _ = solve_increment(law.Ct, law._fac_exact, -slip_old, g, k, sgn, u=u, F=Fx)
                newton += nit
            except (ConvergenceError, np.linalg.LinAlgError):  # the classical start below instead
                exact = False
        if not exact:
            lbar = np.clip(T_old, -g, g) if law.friction_al_tol > 0 else np.zeros(n)
        for n_al in range(1, law.max_al + 1):
            b = lbar / k - slip_old
            T, uu, sgn, nit, trial = solve_increment(law.M, law._fac, b, g, k, sgn, u=u, F=Fx)
            newton += nit
            change = float(np.max(np.abs(T - lbar)) / ctx["gmax"])
            if law.friction_al_tol == 0 or change <= law.friction_al_tol:
                break
            lbar = T
        else:
            raise ConvergenceError(f"friction augmented Lagrangian: multiplier change {change:.3g} of "
                                   f"mu max(lam) after {law.max_al} passes (friction_al_tol="
                                   f"{law.friction_al_tol:g})")
        free = (sgn == 0) & contact
        slope = ((law._fac_exact if exact else law._fac).get(free).ysum if free.any() else 0.0)
    law.stats["trial_solves"] += 1
    law.stats["newton"] += newton
    law.stats["al"] += n_al
    law.stats["al_change_max"] = max(law.stats.get("al_change_max", 0.0), change)
    return {"T": T, "u": float(uu), "sgn": sgn, "lbar": lbar, "slope": float(slope), "Fx": float(T.sum())}


def finish(law, ctx, sol):
    """(StepResult, FEState) of a solved step (``sol`` from ``tangential``): the slip
    update, the slack to the slip limit, the slip flags and the stick radius of the step."""
    n = law.n_pairs
    state, lam, FN, dd, a, g = ctx["state"], ctx["lam"], ctx["FN"], ctx["d"], ctx["a"], ctx["g"]
    if sol is None:  # no pair in contact: no force, the plastic slip follows the plate
        uu = state.u if ctx["u"] is None else ctx["u"]
        z = np.zeros(n)
        new = FEState(T=frozen(z), slip=frozen(np.full(n, uu)), lam=frozen(z),
                      sgn=frozen(np.zeros(n, dtype=np.int8)), u=float(uu), d=float(dd))
        return StepResult(Fx=0.0, FN=FN, d=dd, a=a, c=0.0, u=float(uu), work=0.0, slack=z,
                          slipping=np.ones(n, dtype=bool)), new
    T, uu, sgn = sol["T"], sol["u"], sol["sgn"]
    contact = ctx["contact"]
    s = uu - law.Ct @ T
    slip_new, work = slip_update(s, T, sol["lbar"], law.k, contact, ctx["slip_old"])
    w = law.model.interface.w
    slack = np.where(contact, (g - np.abs(T)) / w, 0.0)  # mu p - |tau| at the pairs
    slipping = (sgn != 0) | ~contact | at_limit(slack, g / w)
    c = float(per_step(law.stick_nodes, slack, slipping, a, law.stick_onset))
    new = FEState(T=frozen(T), slip=frozen(slip_new), lam=frozen(lam), sgn=frozen(sgn),
                  u=float(uu), d=float(dd))
    return StepResult(Fx=sol["Fx"], FN=float(FN), d=float(dd), a=float(a), c=c, u=float(uu),
                      work=work, slack=slack, slipping=slipping), new


class FETrial:
    """A prepared step of an FEContact (see :meth:`FEContact.prepare`); pure like ``step``."""

    def __init__(self, law: FEContact, ctx: dict):  # noqa: F821 (fem.axisym.law imports this module)
        self.law, self.ctx = law, ctx
        self._last = None

    def _at(self, u):
        u = float(u)
        if not np.isfinite(u):
            raise InputError(f"u must be finite, got {u!r}")
        if self._last is None or self._last[0] != u:
            self._last = (u, self.law._tangential(self.ctx, u, None))
        return self._last[1]

    def force(self, u):
        """(Fx, dFx/du) at plate (or contact) displacement u; dFx/du is the stick-set tangent."""
        sol = self._at(u)
        return (0.0, 0.0) if sol is None else (sol["Fx"], sol["slope"])

    def commit(self, u):
        """(StepResult, FEState) of the step to displacement u (counted as a committed step);
        the slip update and the step's stick radius are worked out here, not for every trial."""
        sol = self._at(u)
        res, new = self.law._finish(dict(self.ctx, u=float(u)), sol)
        self.law.stats["steps"] += 1
        return res, new
