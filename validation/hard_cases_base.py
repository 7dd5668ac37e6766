"""What every hard case (``validation.hard_cases``) shares: the scene, the row of the table, the FE
law as the cases build it, and the loop measures and truths several cases use.

Assumptions: steel on steel (E = 200 GPa, nu = 0.29, ``STEEL``) unless a case says otherwise,
sphere R = 6 mm, F = 0.5 N, mu = 0.2 (Table 2 of Willert, Machines 11 (2023) 484), constant normal
force where a closed form is used (Cattaneo-Mindlin and Mindlin-Deresiewicz hold for any nu with the
two-body E*, G*, and for equal materials there is no normal-tangential coupling). Partial-slip FE
cases are force controlled (``F_x`` history): the dissipation at a force amplitude and the stick
radius do not depend on the finite bodies' series compliance, so no calibration of the FE law
enters the comparison (``_md_force``). Gross slip cannot be force controlled; those cases use
``displacement="contact"`` (the series compliance removed with the calibration of
``fem.axisym.law``), and say so in their truth. A harmonic history has ``steps`` steps per cycle
and starts at rest (``_harmonic``); the last cycle is the stationary one (``_last``, ``_work``).
"""
from __future__ import annotations

import time
import warnings

import numpy as np

from mdr import Materials
from mdr import reference as ref
from mdr.loops import loop_integral
from mdr.paper import R_INDENTER, TABLE2

R, F, MU = R_INDENTER, TABLE2["F0"], TABLE2["mu1"]
ROUNDOFF = 1.3e-15  # tolerance of the rows that are exact up to rounding (measured 2.8e-16, 4.4e-16)
# FE sphere under force control at F_A = F_CM(u*/2): error = max(|dW error|, stick radius error
# / a); tolerances at h = a/20 (quick: measured 1.7e-2 .. 2.3e-2, the stick radius at the mesh's
# resolution) and h = a/80 (full)
TRUTH_MD_FORCE = ("Mindlin-Deresiewicz dW at F_A = F_CM(u*/2), Cattaneo-Mindlin stick radius (of a) on the "
                  "first loading; force control; error = max of the two")
TOL_MD_FORCE = {True: 0.018, False: 0.004}
TOL_INCOMPRESSIBLE = {True: 0.016, False: 0.005}
STEEL = Materials()


# ------------------------------------------------------------------------- helpers


def _row(name, model, error, tol, truth, t0, iterations=None, note="", flagged=False, **extra):
    """One table row; ``error`` is the measured error against ``truth`` (None only when the
    case produced no number, then ``note`` must say why)."""
    err = None if error is None else float(abs(error))
    if err is None and not note:
        raise ValueError(f"row {name!r} ({model}) has no error and no note")
    ok = err is not None and np.isfinite(err) and err <= tol and not flagged
    return {"name": name, "model": model, "status": "ok" if ok else "flagged",
            "iterations": None if iterations is None else float(iterations), "error": err, "tol": float(tol),
            "truth": truth, "time_s": time.perf_counter() - t0, "note": note, **extra}


def _fe(profile, mu=MU, *, F_max=F, h=0.1, cache_dir=None, mat=STEEL, **kw):
    from fem.axisym.law import FEContact

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the coarse-mesh warning is the point of some cases
        return FEContact(profile, mat, mu, F_max=F_max, h_contact=h, cache_dir=cache_dir, **kw)


def _newton_per_step(law, before=None):
    st = law.stats
    steps = st["steps"] - (before or {}).get("steps", 0)
    return (st["newton"] - (before or {}).get("newton", 0)) / max(steps, 1)


def _u_star(F_N=F, mu=MU, mat=STEEL):
    return ref.gross_slip_displacement(ref.hertz(F_N, R, mat.E_star)["d"], mu, mat.E_star, mat.G_star)


def _harmonic(cycles, steps):
    t = np.arange(cycles * steps + 1) / steps
    return t, np.sin(2 * np.pi * t)


def _last(H, cycles, steps):
    sl = slice((cycles - 1) * steps, cycles * steps + 1)
    return H.u[sl], H.Fx[sl]


def _work(H, cycles, steps):
    """Friction work of the last cycle (summed over the springs/pairs: exact in time for a
    constant normal force, unlike the trapezoidal loop area)."""
    return float(np.sum(H.work[(cycles - 1) * steps + 1:cycles * steps + 1]))


def _md_force(law, mu=MU, mat=STEEL, steps=100, cycles=2):
    """Force-controlled stationary loop of the sphere at F_A = F_CM(u*/2) (Cattaneo-Mindlin
    force at half the gross-slip displacement) and constant F_N = F. Returns the relative
    errors of the friction work and of the loop area of the last cycle against
    Mindlin-Deresiewicz at F_A, the stick-radius error (of a) over the first loading from
    rest against Cattaneo-Mindlin, and the history. No series compliance enters: under force
    control the bodies' bulk compliance shears the loop without changing its area."""
    us = _u_star(mu=mu, mat=mat)
    FA = float(ref.cattaneo_mindlin_force(0.5 * us, F, mu, us))
    truth = ref.mindlin_deresiewicz_dissipation_force(FA, F, mu, us)
    t, s = _harmonic(cycles, steps)
    H = law.run(Fx=FA * s, F_N=np.full(t.size, F))
    e_w = _work(H, cycles, steps) / truth - 1
    e_area = abs(loop_integral(*_last(H, cycles, steps))) / truth - 1
    a = ref.hertz(F, R, mat.E_star)["a"]
    up = slice(1, steps // 4 + 1)  # first loading, 0 -> F_A
    e_c = float(np.max(np.abs(H.c[up] - ref.cattaneo_mindlin_stick_radius(H.Fx[up], F, mu, a))) / a)
    return float(e_w), float(e_area), e_c, H


def _energy_rows(name, model, H, steps, cycles, mu, t0, iterations=None, tol=0.05, note=""):
    u, Fx = _last(H, cycles, steps)
    FN = H.FN[(cycles - 1) * steps:]
    finite = all(np.all(np.isfinite(getattr(H, k))) for k in ("Fx", "FN", "c", "a", "work"))
    coulomb = float(np.max(np.abs(H.Fx) - mu * H.FN))
    area = abs(loop_integral(u, Fx))
    work = float(np.sum(H.work[(cycles - 1) * steps + 1:]))
    err = abs(area / work - 1) if work > 0 else np.inf
    return _row(name, model, err, tol, "loop area = friction work; |F_x| <= mu F_N; no NaN", t0,
                iterations=iterations, flagged=not finite or coulomb > 1e-9 * mu * np.max(FN),
                note=note or f"min F_N {np.min(FN):.3g} N, max |F_x| - mu F_N = {coulomb:.1e} N")
