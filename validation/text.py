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
