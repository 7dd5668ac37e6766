"""The paper's own loops as a check of a reading the paper leaves open (a roughness spectrum, the brass
plates' reading): a reading whose model cannot produce the measured loops is excluded by the data.

Willert, Machines 11 (2023) 484, Section 4, chose mu1 of each experiment from "the ratio of tangential
force oscillation amplitude and nominal normal force" (which varied by 0.01-0.02 between the three
experiments of one parameter set), so each loop's measured tangential force amplitude is about
mu1 F0: 0.084 N (Fig. 4), 0.159 N (Fig. 5), 0.062 N (Fig. 6), 0.098 N (Fig. 7). It reports Figs. 6-7 in
the gross slip (sliding) regime. A model reading is checked as the paper fitted its own (``check``):

- **amplitude**: the force amplitude of the last cycle, MDR in the apparatus at the figure's F0, dF,
  u_A, mu2 and k_x, grows with mu1 up to full stick (``MU_SWEEP``); the largest (``reachable``) must
  reach the measured amplitude within ``AMPLITUDE_TOLERANCE`` F0 (the paper's spread of mu1), and mu1
  is fitted to it (``mu_fit``, linear in log mu between the sweep's points);
- **regime**, Figs. 6-7: at the fitted mu1 the loop is in gross slip, as the paper reports: the friction
  force reaches the limit mu1 F_N in some step of the cycle (``on_limit`` > 0, as ``studies.paper.loops``
  reads the paper's regimes). Fouvry's energy ratio A = W / (4 delta* Q*) is reported beside it (W the
  loop's dissipation, delta* and Q* its relative displacement and force amplitudes; 0.2 at a sphere's
  onset of sliding: Fouvry, Kapsa & Vincent 1995, Wear 185, 35-46). Figs. 4-5's "partial slip" is not
  a check: the paper's own smooth model, which it reports as agreeing with those loops, reaches the
  friction limit over 25 % and 46 % of their cycles (A = 0.43, 0.69) under the varying normal force;
  the narrow loop the paper calls partial slip is not a stick zone that persists.

A reading is consistent on a figure where both hold. A rig of one's own states its measured loops the same
way (``Loop``: the point, the measured force amplitude, whether gross slip was seen; ``validation.rig``'s
``[[loop]]`` tables); the paper's are ``paper_loops``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .paper_points import Point, loop_point

#: the loop experiments, the contact each checks and the regime the paper reports
FIGURES = {"fig4": "sphere", "fig5": "sphere", "fig6": "face", "fig7": "face"}
GROSS = {"fig6", "fig7"}
#: the spread of the paper's mu1 between the experiments of one parameter set (Section 4), as a
#: fraction of F0: how well the measured amplitude mu1 F0 is known
AMPLITUDE_TOLERANCE = 0.02
#: the friction coefficients the amplitude is swept over (full stick at the top for every paper loop)
MU_SWEEP = tuple(np.geomspace(0.03, 3.0, 13))
#: the MDR resolution of the check: as the studies' (``studies.paper.RES``)
RES = dict(cycles=3, steps=120, n=100)


@dataclass(frozen=True)
class Loop:
    """A measured loop: its ``key``, the apparatus ``point`` it ran at (``validation.paper_points.Point``),
    its measured tangential force ``amplitude`` Q* (N) and whether gross slip was reported (``gross``: then
    the check asks for it)."""

    key: str
    point: Point
    amplitude: float
    gross: bool = False


def paper_loop(fig: str) -> Loop:
    """The paper's loop ``fig`` (``FIGURES``): its point, the amplitude mu1 F0 its mu1 was fitted to, gross
    slip where it reports it (``GROSS``, read at the call)."""
    p = loop_point(fig)
    return Loop(fig, p, p.mu1 * p.F0, fig in GROSS)


def paper_loops() -> tuple:
    return tuple(paper_loop(f) for f in FIGURES)


def loop(profile, lp, mu: float, app_kw=None, materials=None) -> dict:
    """The last cycle of the loop ``lp`` (a ``Loop``, or a figure of the paper), MDR in the apparatus
    (``app_kw``: its fields besides kx, mu2) at friction ``mu`` on ``materials`` (default the paper's
    steel): its force amplitude Q* (N), relative displacement amplitude delta* (m), dissipation W (J),
    the fraction of its steps on the friction limit, Fouvry's ratio and the slip index."""
    from mdr.apparatus import Apparatus, run_apparatus
    from mdr.law import MDRContact
    from mdr.loading import Loading
    from mdr.materials import Materials

    p = (paper_loop(lp) if isinstance(lp, str) else lp).point
    law = MDRContact(profile, materials or Materials(), float(mu), F_max=p.F0 + p.dF,
                     F_min=p.F0 - p.dF if p.dF < p.F0 else None, n=RES["n"])
    out = run_apparatus(law, Apparatus(kx=p.kx, mu2=p.mu2, **(app_kw or {})),
                        Loading.apparatus(p.F0, p.dF, 0.0, p.ua, cycles=RES["cycles"], steps=RES["steps"]))
    fx, du = np.asarray(out["Fx"])[..., -RES["steps"]:], np.asarray(out["du"])[..., -RES["steps"]:]
    fn = np.asarray(out["FN"])[..., -RES["steps"]:]
    q, d, w = 0.5 * float(np.ptp(fx)), 0.5 * float(np.ptp(du)), float(out["dissipation"])
    return {"amplitude": q, "displacement": d, "dissipation": w,
            "on_limit": float(np.mean(np.abs(fx) >= (1 - 1e-9) * mu * fn)),
            "ratio": w / (4 * d * q) if d > 0 and q > 0 else 0.0, "slip_index": float(out["slip_index"])}


def check(profile, lp, app_kw=None, materials=None) -> dict:
    """The loop's check of one model reading (``profile``; ``lp`` a ``Loop`` or a figure of the paper;
    ``app_kw``: the apparatus's reading; ``materials``: the pair's): target and reachable amplitude (N),
    the fitted mu1 (None where unreachable), the amplitude at the loop's mu1, the regime at the fitted mu1
    (Fouvry's ratio) and ``consistent``."""
    lp = paper_loop(lp) if isinstance(lp, str) else lp
    p, target = lp.point, lp.amplitude
    amps = np.array([loop(profile, lp, mu, app_kw, materials)["amplitude"] for mu in MU_SWEEP])
    reach = float(amps.max())
    out = {"figure": lp.key, "target": target, "reachable": reach, "mu_fit": None, "ratio": None, "regime": None,
           "amplitude_at_paper_mu": loop(profile, lp, p.mu1, app_kw, materials)["amplitude"]}
    if reach < target - AMPLITUDE_TOLERANCE * p.F0:
        return {**out, "consistent": False, "why": f"amplitude {reach:.3g} N at most, {target:.3g} N measured"}
    k = int(np.argmax(amps >= min(target, reach)))
    if k == 0:
        mu = MU_SWEEP[0]
    else:
        lo, hi = amps[k - 1], amps[k]
        t = (min(target, reach) - lo) / (hi - lo) if hi > lo else 1.0
        mu = float(np.exp(np.log(MU_SWEEP[k - 1]) + t * (np.log(MU_SWEEP[k]) - np.log(MU_SWEEP[k - 1]))))
    at = loop(profile, lp, mu, app_kw, materials)
    regime = "gross slip" if at["on_limit"] > 0 else "partial slip"
    ok = not lp.gross or regime == "gross slip"
    return {**out, "mu_fit": mu, "ratio": at["ratio"], "on_limit": at["on_limit"], "regime": regime,
            "consistent": ok, "why": "" if ok else f"{regime} at the fitted mu1 = {mu:.2g}, gross slip measured"}
