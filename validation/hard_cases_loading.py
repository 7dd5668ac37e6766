"""Hard cases of extreme loading of the sphere (``validation.hard_cases``): gross slip at ten
times the gross-slip displacement over many cycles, a normal force down to 1 % of its mean and
to zero (contact lost), friction coefficients from 0 to 1, and the apparatus from a soft to a
stiff tangential drive.

Assumptions: the scene of ``validation.hard_cases_base``. The truths are Mindlin-Deresiewicz
(dissipation at a displacement or force amplitude under constant F_N), Cattaneo-Mindlin (stick
radius), energy (loop area = friction work) and Coulomb |F_x| <= mu F_N; under a varying normal
force only the energy balance and Coulomb are asserted, there being no closed form.
"""
from __future__ import annotations

import time

import numpy as np

from mdr import MDRContact, Sphere
from mdr import reference as ref
from mdr.drive import run_mdr_contact
from mdr.loading import Loading, gross_slip_work
from mdr.loops import loop_integral

from .hard_cases_base import (F, MU, R, ROUNDOFF, STEEL, TOL_MD_FORCE, TRUTH_MD_FORCE, _energy_rows, _fe,
                              _harmonic, _md_force, _newton_per_step, _row, _u_star)

# -------------------------------------------------------------- gross slip, many cycles


def case_gross_slip_many_cycles(quick=True, cache_dir=None):
    """u_A = 10 u* for 50 cycles (MDR; FE fewer): every stationary cycle dissipates the
    gross-slip value, the loop does not drift or ratchet."""
    rows = []
    us = _u_star()
    ua = 10 * us
    truth = ref.mindlin_deresiewicz_dissipation(ua, F, MU, us)
    t0 = time.perf_counter()
    cycles, steps = 50, 200
    res = run_mdr_contact(Sphere(R), STEEL, MU, Loading.of(F, ua=ua, cycles=cycles, steps=steps))
    t, s = _harmonic(cycles, steps)
    H = MDRContact(Sphere(R), STEEL, MU, F_max=F).run(u=ua * s, F_N=np.full(t.size, F))
    W = np.array([np.sum(H.work[k * steps + 1:(k + 1) * steps + 1]) for k in range(cycles)])
    err = np.max(np.abs(W[1:] / truth - 1))
    loops = H.Fx[:-1].reshape(cycles, steps)
    drift = float(np.max(np.abs(loops[2:] - loops[1])) / (MU * F))
    rows.append(_row("gross slip u_A = 10 u*, 50 cycles", "mdr", max(err, drift), 3e-7,
                     "dW = 4 mu F u_A - 3.2 mu F u* every cycle (Mindlin-Deresiewicz), no drift", t0,
                     note=f"loop area {res['dissipation'] / truth - 1:+.1e} (trapezoid over {steps} steps); "
                          f"loop drift {drift:.1e} mu F", drift=drift))
    t0 = time.perf_counter()
    cycles, steps = (10, 40) if quick else (50, 80)
    law = _fe(Sphere(R), h=0.1 if quick else 1 / 40, cache_dir=cache_dir, displacement="contact")
    t, s = _harmonic(cycles, steps)
    H = law.run(u=ua * s, F_N=np.full(t.size, F))
    W = np.array([np.sum(H.work[k * steps + 1:(k + 1) * steps + 1]) for k in range(cycles)])
    A = np.array([abs(loop_integral(H.u[k * steps:(k + 1) * steps + 1], H.Fx[k * steps:(k + 1) * steps + 1]))
                  for k in range(cycles)])
    loops = H.Fx[:-1].reshape(cycles, steps)
    drift = float(np.max(np.abs(loops[2:] - loops[1])) / (MU * F))
    err = np.max(np.abs(W[1:] / truth - 1))
    rows.append(_row(f"gross slip u_A = 10 u*, {cycles} cycles", "fem", max(err, drift), 6e-4 if quick else 3e-4,
                     "dW = 4 mu F u_A - 3.2 mu F u* every cycle (u_A: contact displacement), no drift", t0, iterations=_newton_per_step(law),
                     note=f"friction work {err:.1e}, loop area {np.max(np.abs(A[1:] / truth - 1)):.1e} "
                          f"({steps} steps); drift {drift:.1e} mu F", drift=drift))
    return rows


# ------------------------------------------------------------------ vanishing contact


def case_vanishing_contact(quick=True, cache_dir=None):
    """F_N = F (1 + 0.99 sin(2 pi t + pi/2)) down to 1 % of its mean while u runs; and F_N = 0
    (contact lost): a defined answer (F_x = 0, a = c = 0, history released), never NaN."""
    rows = []
    ua, q = 0.5 * _u_star(), 0.99
    cycles, steps = 3, 800
    t, s = _harmonic(cycles, steps)
    FN = F * (1 + q * np.sin(2 * np.pi * t + np.pi / 2))
    t0 = time.perf_counter()
    H = MDRContact(Sphere(R), STEEL, MU, F_max=FN.max(), n=400).run(u=ua * s, F_N=FN)
    rows.append(_energy_rows("normal force down to 1 % of its mean", "mdr", H, steps, cycles, MU, t0, tol=0.01))
    t0 = time.perf_counter()
    law = _fe(Sphere(R), F_max=FN.max(), h=0.05 if quick else 1 / 80, cache_dir=cache_dir, displacement="contact")
    fe_steps = 200 if quick else 800
    t2, s2 = _harmonic(cycles, fe_steps)
    FN2 = F * (1 + q * np.sin(2 * np.pi * t2 + np.pi / 2))
    H2 = law.run(u=ua * s2, F_N=FN2)
    rows.append(_energy_rows("normal force down to 1 % of its mean", "fem", H2, fe_steps, cycles, MU, t0,
                             iterations=_newton_per_step(law), tol=0.05 if quick else 0.015))
    # contact lost: F_N reaches 0 (dF = F0) and a step at F_N = 0
    for model in ("mdr", "fem"):
        t0 = time.perf_counter()
        lw = MDRContact(Sphere(R), STEEL, MU, F_max=2 * F) if model == "mdr" else \
            _fe(Sphere(R), F_max=2 * F, h=0.1, cache_dir=cache_dir, displacement="contact")
        st = lw.rest_state()
        r1, st = lw.step(st, ua, F_N=F)
        r0, st0 = lw.step(st, ua, F_N=0.0)
        r2, _ = lw.step(st0, ua, F_N=F)
        vals = [r0.Fx, r0.FN, r0.a, r0.c, r0.work, r2.Fx]
        finite = all(np.isfinite(v) for v in vals)
        # measured: F_x at F_N = 0 and on re-contact at the same u (both must vanish: the history
        # is released) against mu F, and the radii at F_N = 0 against the Hertz radius at F
        a_h = ref.hertz(F, R, STEEL.E_star)["a"]
        err = max(abs(float(r0.Fx)) / (MU * F), abs(float(r2.Fx)) / (MU * F), abs(float(r0.FN)) / F,
                  abs(float(r0.a)) / a_h, abs(float(r0.c)) / a_h) if finite else None
        rows.append(_row("F_N = 0: contact lost", model, err, ROUNDOFF,
                         "F_x = 0, F_N = 0, a = c = 0 at F_N = 0; re-contact at the same u starts unstrained "
                         "(F_x = 0); error: max of |F_x|/(mu F), F_N/F, a/a_Hertz, c/a_Hertz", t0,
                         note=f"before: F_x = {float(r1.Fx):.3g} N; at F_N = 0: F_x = {float(r0.Fx):g}, "
                              f"a = {float(r0.a):g}; re-contact F_x = {float(r2.Fx):.1e} N"
                              + ("" if finite else "; NaN/inf in the result"), flagged=not finite))
    return rows


# -------------------------------------------------------------------- friction extremes


def case_friction_extremes(quick=True, cache_dir=None):
    """mu = 0.01 and 1.0: Mindlin-Deresiewicz dissipation at u_A = u*/2 (MDR, displacement
    control; u* scales with mu) and at the force amplitude F_CM(u*/2) (FE, force control);
    mu = 0: no tangential force, no dissipation, slip index undefined (None)."""
    rows = []
    for mu in (0.01, 1.0):
        us = _u_star(mu=mu)
        truth = ref.mindlin_deresiewicz_dissipation(0.5 * us, F, mu, us)
        t0 = time.perf_counter()
        res = run_mdr_contact(Sphere(R), STEEL, mu, Loading.of(F, ua=0.5 * us, cycles=3, steps=400))
        rows.append(_row(f"mu = {mu:g}", "mdr", res["dissipation"] / truth - 1, 2.5e-5,
                         "Mindlin-Deresiewicz dW at u_A = u*/2", t0))
        t0 = time.perf_counter()
        law = _fe(Sphere(R), mu, h=0.05 if quick else 1 / 80, cache_dir=cache_dir)
        steps = 100 if quick else 200
        e_w, e_area, e_c, _ = _md_force(law, mu=mu, steps=steps)
        rows.append(_row(f"mu = {mu:g}", "fem", max(abs(e_w), e_c), TOL_MD_FORCE[quick], TRUTH_MD_FORCE, t0,
                         iterations=_newton_per_step(law),
                         note=f"friction work {e_w:+.1e}, loop area {e_area:+.1e} ({steps} steps per cycle); "
                              f"stick radius {e_c:.1e} of a (Cattaneo-Mindlin)", stick_radius_error=e_c))
    t0 = time.perf_counter()
    ua0 = 50e-9
    res = run_mdr_contact(Sphere(R), STEEL, 0.0, Loading.of(F, ua=ua0, cycles=2, steps=40))
    fx = max(abs(x) for x in res["loop"]["Fx"]) / F
    dw = abs(res["dissipation"]) / (4 * F * ua0)
    rows.append(_row("mu = 0 (frictionless)", "mdr", max(fx, dw), ROUNDOFF,
                     "F_x = 0, dW = 0, slip index undefined; error: max of max|F_x|/F_N, dW/(4 F_N u_A)", t0,
                     note=f"max|F_x|/F_N = {fx:.1e}, dW/(4 F_N u_A) = {dw:.1e}, slip index "
                          + ("undefined" if res["slip_index"] is None else f"{res['slip_index']:.3g} (should be undefined)"),
                     flagged=res["slip_index"] is not None))
    t0 = time.perf_counter()
    law = _fe(Sphere(R), 0.0, h=0.1, cache_dir=cache_dir)
    t, s = _harmonic(2, 16)
    H = law.run(u=ua0 * s, F_N=np.full(t.size, F))
    fx, dw = float(np.max(np.abs(H.Fx))) / F, float(np.sum(np.abs(H.work))) / (4 * F * ua0)
    rows.append(_row("mu = 0 (frictionless)", "fem", max(fx, dw), ROUNDOFF,
                     "F_x = 0, dW = 0; error: max of max|F_x|/F_N, total work/(4 F_N u_A)", t0,
                     note=f"max|F_x|/F_N = {fx:.1e}, work/(4 F_N u_A) = {dw:.1e}",
                     flagged=not np.all(np.isfinite(H.c))))
    return rows


# ------------------------------------------------------------------------- apparatus


def _contact_truth(out, mu, F0, steps, cycles, mat=STEEL):
    """Independent truth for the contact loop inside the apparatus (sphere, constant F_N):
    Mindlin-Deresiewicz at the measured force amplitude (partial slip) or at the measured
    contact displacement amplitude (gross slip)."""
    sl = slice((cycles - 1) * steps, cycles * steps + 1)
    Fx, du = out["Fx"][..., sl], out["du"][..., sl]
    FA = 0.5 * np.ptp(Fx, axis=-1)
    uA = 0.5 * np.ptp(du, axis=-1)
    us = _u_star(F0, mu, mat)
    truth = np.array([ref.mindlin_deresiewicz_dissipation_force(fa, F0, mu, us) if fa < mu * F0 * (1 - 1e-6)
                      else ref.mindlin_deresiewicz_dissipation(ua, F0, mu, us)
                      for fa, ua in zip(np.atleast_1d(FA), np.atleast_1d(uA))])
    return truth, FA


def case_apparatus_stiffness(quick=True, cache_dir=None):
    """Sphere in the apparatus with k_x = 0.1 .. 100 N/um (dF = 0): the contact's loop
    dissipates the Mindlin-Deresiewicz energy of its own force (or displacement) amplitude;
    at 0.1 N/um the contact sticks (slip index ~ 0, F_x far below mu F_N)."""
    from mdr.apparatus import Apparatus, run_apparatus

    rows = []
    kx = np.array([0.1, 0.3, 1.0, 3.0, 10.0, 30.0, 100.0]) * 1e6
    cycles, steps = 3, 200
    t0 = time.perf_counter()
    law = MDRContact(Sphere(np.full(kx.size, R)), STEEL, MU, F_max=F, n=400)
    out = run_apparatus(law, Apparatus(kx=kx), Loading.apparatus(F, dF=0.0, ua=150e-9, cycles=cycles, steps=steps))
    truth, FA = _contact_truth(out, MU, F, steps, cycles)
    dW = out["dissipation"]
    err = np.abs(dW - truth) / gross_slip_work(MU, F, 150e-9)  # as a slip-index difference (dW -> 0 when sticking)
    delta = np.asarray(out["slip_index"])
    mono = bool(np.all(np.diff(delta) > 0))
    sticking = bool(delta[0] < 0.01 and FA[0] < 0.2 * MU * F)
    rows.append(_row("apparatus k_x = 0.1 .. 100 N/um", "mdr", float(np.max(err)), 4e-4,
                     "Mindlin-Deresiewicz dW at the contact's own amplitude (slip-index difference)", t0,
                     iterations=out["evaluations_per_step"],
                     note="slip index " + ", ".join(f"{d:.3f}" for d in delta) + " (k_x = 0.1 .. 100 N/um); "
                          + ("sticks at 0.1 N/um" if sticking else "does NOT stick at 0.1 N/um"),
                     flagged=not (mono and sticking), slip_index=delta.tolist()))
    # FE law (contact displacement measure) in the same apparatus, at the two extremes
    t0 = time.perf_counter()
    ks = (0.1e6, 100e6)
    fe_steps = 40 if quick else 100
    errs, deltas, its = [], [], []
    for k in ks:
        fe = _fe(Sphere(R), h=0.05 if quick else 1 / 40, cache_dir=cache_dir, displacement="contact")
        o = run_apparatus(fe, Apparatus(kx=k), Loading.apparatus(F, dF=0.0, ua=150e-9, cycles=cycles, steps=fe_steps))
        tr, _ = _contact_truth(o, MU, F, fe_steps, cycles)
        errs.append(abs(float(o["dissipation"]) - float(tr[0])) / float(gross_slip_work(MU, F, 150e-9)))
        deltas.append(float(o["slip_index"]))
        its.append(_newton_per_step(fe))
    rows.append(_row("apparatus k_x = 0.1 and 100 N/um", "fem", max(errs), 8e-3 if quick else 1.9e-3,
                     "Mindlin-Deresiewicz dW at the contact's own amplitude (slip-index difference)", t0, iterations=float(np.mean(its)),
                     note=f"slip index {deltas[0]:.3f} (0.1 N/um, sticks), {deltas[1]:.3f} (100 N/um); "
                          f"errors {errs[0]:.1e}, {errs[1]:.1e}", flagged=not deltas[0] < 0.01,
                     slip_index=deltas))
    return rows
