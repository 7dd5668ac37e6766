"""Hard cases of indenter profiles other than the smooth sphere (``validation.hard_cases``): the
flat punch, whose pressure is singular at its edge and whose contact radius is fixed, and the
truncated sphere with its flat face's edge inside, at and beyond the sphere's contact edge.

Assumptions: the scene of ``validation.hard_cases_base`` (steel, F = 0.5 N, mu = 0.2); the truths
are the closed forms of ``mdr.reference`` (Boussinesq flat punch, the truncated-sphere contact
radius, approach and energy) and the gross-slip dissipation of any profile. The FE tangential
flat-punch row uses the plate displacement (no compliance calibration), since the full-stick
stiffness it would be checked against is the calibration itself.
"""
from __future__ import annotations

import time

import numpy as np

from mdr import FlatPunch, MDRContact, TruncatedSphere
from mdr import reference as ref
from mdr.drive import run_mdr_contact
from mdr.loading import Loading
from mdr.normal import approach_from_force, pressure

from .hard_cases_base import F, MU, R, ROUNDOFF, STEEL, _fe, _harmonic, _newton_per_step, _row, _work

# ---------------------------------------------------------------------- flat punch


def case_flat_punch(quick=True, cache_dir=None):
    """Flat punch b = 30 um: Boussinesq pressure with its edge singularity, the contact radius
    fixed at b (approach linear in F), full stick then sudden gross slip at u* = mu E* d/G*."""
    rows = []
    b = 30e-6
    prof = FlatPunch(b)
    t0 = time.perf_counter()
    d = float(approach_from_force(prof, STEEL, F))
    r = np.linspace(0, 0.99, 100) * b
    p = pressure(prof, STEEL, d, r)
    err = np.max(np.abs(p / ref.flat_punch_pressure(r, F, b) - 1))
    err = max(err, abs(d / ref.flat_punch_approach(F, b, STEEL.E_star) - 1))
    rows.append(_row("flat punch: pressure with edge singularity", "mdr", err, ROUNDOFF,
                     "Boussinesq p = F/(2 pi b sqrt(b^2-r^2)), d = F/(2 E* b)", t0))
    # MDR: full stick then gross slip, exact
    t0 = time.perf_counter()
    law = MDRContact(prof, STEEL, MU, n=50)
    us = MU * STEEL.E_star * d / STEEL.G_star
    u = np.linspace(0, 2 * us, 101)
    H = law.run(u=u, F_N=np.full(u.size, F))
    truth = np.minimum(2 * STEEL.G_star * b * u, MU * F)
    err = np.max(np.abs(H.Fx - truth)) / (MU * F)
    rows.append(_row("flat punch: full stick then sudden gross slip", "mdr", err, ROUNDOFF,
                     "F_x = min(2 G* b u, mu F_N)", t0, stick_radius_before=float(H.c[40]),
                     stick_radius_after=float(H.c[-1])))
    # FE: normal stiffness at two forces (radius fixed), pressure inside, edge growth under refinement
    from fem.axisym.normal_run import run_normal

    t0 = time.perf_counter()
    hs = (1 / 20, 1 / 40) if quick else (1 / 20, 1 / 40, 1 / 80)
    p_edge, errs, its = [], [], []
    for h in hs:
        outs = [run_normal("flat", b=b, F=f, h_contact=h, cache_dir=cache_dir) for f in (0.05 * F, F)]
        o = outs[1]
        rr, pp = np.asarray(o["pressure"]["r"]), np.asarray(o["pressure"]["p"])
        inner = rr <= 0.8 * b
        e_p = np.max(np.abs(pp[inner] / ref.flat_punch_pressure(rr[inner], F, b) - 1))
        e_d = abs(o["indentation"] / ref.flat_punch_approach(F, b, STEEL.E_star) - 1)
        e_lin = abs(outs[1]["approach"] / outs[0]["approach"] / 20.0 - 1)  # fixed radius: d proportional to F
        errs.append((e_d, e_p, e_lin))
        p_edge.append(float(pp[rr < b][-1]) / (F / (np.pi * b**2)))
        its.append(o["solver"]["newton_iterations"] / o["solver"]["al_iterations"])
    e_d, e_p, e_lin = errs[-1]
    grows = all(p_edge[i + 1] > 1.2 * p_edge[i] for i in range(len(p_edge) - 1))
    rows.append(_row("flat punch: normal stiffness, pressure, fixed radius", "fem", max(e_d, e_lin),
                     5e-3 if quick else 3e-3,
                     "d = F/(2 E* b); d proportional to F (radius fixed at b)", t0, iterations=its[-1],
                     note=f"h = b/{1 / hs[-1]:.0f}: p(r <= 0.8 b) within {e_p:.1%} of Boussinesq; edge pressure / "
                          f"mean {', '.join(f'{x:.2f}' for x in p_edge)} grows with refinement (singular)",
                     flagged=not grows, pressure_error=e_p, edge_pressure=p_edge))
    # FE tangential (plate displacement, no compliance calibration: with displacement="contact"
    # the full-stick stiffness 2 G* b would be the calibration itself). Full stick: a force
    # cycle at F_A = 0.95 mu F_N must neither slip nor dissipate (Mindlin 1949, J. Appl. Mech.:
    # traction and pressure share the edge singularity, tau/p = F_x/F_N < mu everywhere); the FE
    # edge pairs slip a little, which refines away (h). Gross slip: beyond the sliding point
    # F_x = mu F_N exactly and nothing sticks.
    t0 = time.perf_counter()
    h = 1 / 20 if quick else 1 / 40
    law = _fe(prof, h=h, cache_dir=cache_dir)
    n0 = dict(law.stats)
    q, steps = 0.95, 40
    t, s = _harmonic(2, steps)
    H = law.run(Fx=q * MU * F * s, F_N=np.full(t.size, F))
    c_min = float(np.min(H.c[1:]))
    uA = 0.5 * float(np.ptp(H.u[steps:]))
    slip_index = _work(H, 2, steps) / (4 * q * MU * F * uA)
    u_hs = MU * F / (2 * STEEL.G_star * b)  # half-space sliding displacement; the plate's is larger
    u = np.linspace(0, 4 * u_hs, 41)
    H = law.run(u=u, F_N=np.full(u.size, F))
    sliding = u > 2.5 * u_hs
    e_gross = float(np.max(np.abs(H.Fx[sliding] - MU * F))) / (MU * F)
    err = max(1 - c_min / b, slip_index, e_gross)
    rows.append(_row("flat punch: full stick then sudden gross slip", "fem", err, 1e-3 if quick else 5e-4,
                     "full stick (c = b, dW = 0) at F_x = 0.95 mu F_N; F_x = mu F_N, c = 0 when sliding; "
                     "error: max of 1 - c_min/b, slip index, |F_x - mu F_N|/(mu F_N)", t0,
                     iterations=_newton_per_step(law, n0),
                     note=f"h = b/{1 / h:.0f}: at 0.95 mu F_N stick radius {c_min / b:.3f} b, slip index "
                          f"{slip_index:.1e} (the edge pairs; both refine towards full stick); sliding: "
                          f"F_x - mu F_N = {e_gross:.1e} mu F_N, c = {float(np.max(H.c[sliding])):g}",
                     flagged=bool(np.any(H.c[sliding] > 0)), stick_radius_min=c_min, slip_index=slip_index))
    return rows


# ------------------------------------------------------------------ truncated sphere


def case_truncated_edge(quick=True, cache_dir=None):
    """Truncated sphere with the flat face edge inside, at and beyond the sphere's contact
    edge (b = 0.9 a, a, 1.05 a, a the Hertz radius at F): contact radius and approach against
    the closed forms (the kink at r = b gives a weak pressure singularity)."""
    from fem.axisym.normal_run import run_normal

    rows = []
    a_h = ref.hertz(F, R, STEEL.E_star)["a"]
    for q in (0.9, 1.0, 1.05):
        b = q * a_h
        prof = TruncatedSphere(R, b)
        a_t = ref.truncated_contact_radius(F, R, b, STEEL.E_star)
        d_t = ref.truncated_approach(a_t, R, b)
        t0 = time.perf_counter()
        d = float(approach_from_force(prof, STEEL, F))
        err = max(abs(float(prof.g_inv(d)) / a_t - 1), abs(d / d_t - 1))
        # gross slip at 3 u*: dW = 4 mu F u_A - 8 mu^2 (E*/G*) U (any profile)
        ua = 3 * MU * STEEL.E_star * d / STEEL.G_star
        res = run_mdr_contact(prof, STEEL, MU, Loading.of(F, ua=ua, cycles=3, steps=400))
        U = ref.truncated_energy(a_t, R, b, STEEL.E_star)
        e_w = abs(res["friction_work"] / ref.gross_slip_dissipation(ua, F, MU, U, STEEL.E_star, STEEL.G_star) - 1)
        rows.append(_row(f"truncated b = {q:g} a: contact radius, approach, gross slip", "mdr", max(err, e_w),
                         {0.9: 3e-7, 1.0: 2.4e-7, 1.05: 2e-7}[q],
                         "a, d of the truncated sphere (closed form); dW = 4 mu F u_A - 8 mu^2 E*/G* U", t0,
                         note=f"a/b = {a_t / b:.4f}"))
        t0 = time.perf_counter()
        h = 1 / 40 if quick else 1 / 160
        o = run_normal("truncated", R=R, b=b, F=F, h_contact=h, cache_dir=cache_dir)
        e_a = o["contact_radius"] / a_t - 1
        e_d = o["indentation"] / d_t - 1
        rr, pp = np.asarray(o["pressure"]["r"]), np.asarray(o["pressure"]["p"])
        ok = bool(np.all(np.isfinite(pp)) and np.all(pp >= 0))
        # pressure against the MDR (exact half-space) pressure away from the kink and the edge
        sel = (np.abs(rr - b) > 0.1 * a_t) & (rr < 0.9 * a_t)
        pm = pressure(prof, STEEL, d_t, rr[sel])
        e_p = float(np.max(np.abs(pp[sel] - pm)) / np.max(pm))
        tol = {0.9: 2.5e-3, 1.0: 8e-4, 1.05: 5e-3}[q] if quick else {0.9: 8e-4, 1.0: 1.5e-3, 1.05: 1e-3}[q]
        rows.append(_row(f"truncated b = {q:g} a: contact radius, approach", "fem", max(abs(e_a), abs(e_d)), tol,
                         "truncated-sphere closed forms a(F), d(a)", t0,
                         iterations=o["solver"]["newton_iterations"] / o["solver"]["al_iterations"],
                         note=f"h = a/{1 / h:.0f}: a {e_a:+.2e}, d {e_d:+.2e}, p off the kink within {e_p:.1%} of MDR",
                         flagged=not ok, pressure_error=e_p))
    return rows
