"""The numbers and words of the report and the family tables: one formatter, one reading of a grade.

Pure functions of result values (no solver, no file): every value a result can hold renders.
"""
from __future__ import annotations

import math

from .metrics import grade_of

LABELS = {"contact_radius": "contact radius", "stick_radius": "stick radius", "dissipation": "dissipation",
          "slip_index": "slip index", "pressure_profile": "pressure profile at F0",
          "traction_profile": "traction profile at the peak",
          "loop_Fx": "loop: largest F_x difference", "loop_du": "loop: largest du difference"}


def num(x, spec=".3g", k=1.0) -> str:
    """``x * k`` formatted by ``spec``: the one number formatter of the report. Renders every value a
    result can hold: None (not computed) as '-', NaN and +-inf as such, anything not a number as
    its text, never raising."""
    if x is None:
        return "-"
    try:
        v = float(x) * k
    except (TypeError, ValueError):
        return str(x)
    return format(v, spec) if math.isfinite(v) else str(v)


def pct(x, digits=2):
    return "-" if x is None else num(x, f"+.{digits}f", 100.0) + " %"


def sig(x, k=1.0, digits=3):
    """A number with ``digits`` significant digits (0 stays 0; None is '-')."""
    if x is None:
        return "-"
    return "0" if x == 0 else num(x, f".{digits}g", k)


def grade_text(v: dict) -> str:
    """A metric's grade (``validation.metrics.GRADES``) as the report shows it."""
    g = grade_of(v)
    return {"holds": "**holds**", "fails": "**fails**"}.get(g, g)


#: the report's "How to read a verdict" paragraph
HOW_TO_READ = ("How to read a verdict: each metric compares MDR and FE at the finest level of their ladders. "
             "Each side's *error* is its error bar: extrapolated over its refinement ladder (Richardson with "
             "the observed order p and Roache's safety factor 1.25 where the three finest levels converge "
             "monotonically with 0.5 <= p <= 4: an upper bound; *calibrated* where a bound C h^p of the "
             "model's error, calibrated on the anchors and validated on held-out scenes "
             "(`validation.error_models`), contains every level of the ladder: the bound at the finest level, "
             "or Richardson's bar where larger; the spread of the levels where neither holds: "
             "no bound), plus, on the dissipation and the slip index, the time step's error bar (the finest "
             "level at 1, 2 and 4 times the steps) and the cycles' settling towards the stationary cycle "
             "(`common.ladder.settling_error`). The *tolerance* is what \"MDR holds\" claims beyond both "
             "error bars (`validation/scenes.py`, `TOLERANCES`; marked *floor* where the resolution floor "
             "of the dissipation, 1e-4 x 4 mu F0 u_A, exceeds it). Grades: **holds** when "
             "|MDR - FE| <= FE error + MDR error + tolerance and every error bar is an upper bound; "
             "*consistent within its spread* when the inequality holds but a ladder is neither in its asymptotic "
             "range (non-monotone, or an order outside 0.5-4) nor within a calibrated bound: an error injected into one level could hide "
             "in its spread, so this is no evidence that MDR holds; *below resolution* when it holds only "
             "thanks to the floor; **fails** when the inequality fails; *undetermined* when a number or a ladder "
             "level is not finite. The FE displacement is the half-space comparable one (`fem.axisym.law`, "
             "`displacement=\"contact\"`). Summary cells: MDR - FE (FE error + MDR error + tolerance), "
             "radii in % of the FE contact radius, dissipation in % of the FE dissipation, slip index absolute. "
             "*Last-cycle change*: how much the reported (last) cycle differs from the one before, the larger "
             "of the loop's change (F_x in mu F0, or du in its amplitude) and the dissipation's (relative); "
             "the cycle counts as stationary at or below 1e-3 (`mdr.loops.analyse_cycles`).")
