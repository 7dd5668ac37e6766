"""Distances between two results of the same scene (plain arrays in, plain numbers out).

Conventions: a *relative difference* is (test - ref) / |ref| (signed); a
profile error is the relative L2 norm of the difference over the disk
r <= r_max; loop distances
compare two loops sampled at the same phases (the same time steps).
"""
from __future__ import annotations

import numpy as np

# the error bar of a refinement ladder lives in common.ladder (python -m mdr study --law uses it too)
from common.ladder import BOUNDED, GCI_SAFETY, ORDER_RANGE, ladder_error  # noqa: F401
from mdr.loading import HARDLY_DISSIPATES, gross_slip_work
from mdr.loops import loop_integral

_trapz = getattr(np, "trapezoid", None) or np.trapz  # numpy < 2 has only trapz


def rel(test, ref):
    """Signed relative difference (test - ref)/|ref|; None if either is missing or ref == 0."""
    if test is None or ref is None:
        return None
    test, ref = float(test), float(ref)
    if ref == 0.0 or not (np.isfinite(test) and np.isfinite(ref)):
        return None
    return (test - ref) / abs(ref)


def profile_error(r_test, f_test, r_ref, f_ref, r_max, n=400, exclude=None):
    """Relative L2 error of a profile f(r) on the disk r <= r_max: ||f_t - f_r|| / ||f_r||.

    ||f||^2 = int f^2 r dr. Both profiles are linear between their samples (zero beyond
    the last) and integrated exactly on the union of both sample sets and n uniform
    points. ``exclude = (lo, hi)``: leave out that ring, e.g. around the kink r = b of a
    truncated sphere, where the pressure is log-singular and any sampled profile (the
    closed form on its grid, the FE at its pairs) shows a finite peak that depends on
    where its samples fall, not on the physics. None when the reference is zero.
    """
    r_max = float(r_max)
    rt, rr = np.asarray(r_test, float), np.asarray(r_ref, float)
    r = np.unique(np.concatenate([np.linspace(0.0, r_max, n), rt[rt < r_max], rr[rr < r_max]]))
    pieces = [(0.0, r_max)] if exclude is None else [(0.0, min(exclude[0], r_max)), (max(exclude[1], 0.0), r_max)]
    num = den = 0.0
    for lo, hi in pieces:
        if hi <= lo:
            continue
        rp = np.unique(np.concatenate([[lo, hi], r[(r > lo) & (r < hi)]]))
        ft = np.interp(rp, rt, np.asarray(f_test, float), right=0.0)
        fr = np.interp(rp, rr, np.asarray(f_ref, float), right=0.0)
        num += _l2_disk(rp, ft - fr) ** 2
        den += _l2_disk(rp, fr) ** 2
    if den == 0.0:
        return None
    return float(np.sqrt(num / den))


def _l2_disk(r, f):
    """sqrt(int f^2 r dr) of a piecewise-linear f on nodes r (exact per segment)."""
    r0, r1, f0, f1 = r[:-1], r[1:], f[:-1], f[1:]
    # int_{r0}^{r1} (f0 + (f1 - f0) t)^2 (r0 + (r1 - r0) t) (r1 - r0) dt, t in [0, 1]
    h, df, dr = r1 - r0, f1 - f0, r1 - r0
    val = h * (r0 * (f0 * f0 + f0 * df + df * df / 3.0)
               + dr * (f0 * f0 / 2.0 + 2.0 * f0 * df / 3.0 + df * df / 4.0))
    return float(np.sqrt(max(np.sum(val), 0.0)))


def loop_distance(test: dict, ref: dict, mu, F0) -> dict:
    """Shape distance of two stationary loops ``{"du", "Fx"}`` sampled at the same phases.

    ``Fx``: max |Fx_test - Fx_ref| / (mu F0); ``du``: max |du_test - du_ref| /
    max |du_ref| (under force control Fx is prescribed and du carries the
    difference; under displacement control the other way round); ``area``:
    relative difference of the enclosed areas (the dissipation).
    """
    du_t, fx_t = np.asarray(test["du"], float), np.asarray(test["Fx"], float)
    du_r, fx_r = np.asarray(ref["du"], float), np.asarray(ref["Fx"], float)
    if du_t.shape != du_r.shape:
        # resample the test loop on the reference's phases
        ph_t = np.linspace(0.0, 1.0, du_t.size)
        ph_r = np.linspace(0.0, 1.0, du_r.size)
        du_t, fx_t = np.interp(ph_r, ph_t, du_t), np.interp(ph_r, ph_t, fx_t)
    scale_u = float(np.max(np.abs(du_r)))
    return {
        "Fx": float(np.max(np.abs(fx_t - fx_r)) / (mu * F0)) if mu > 0 else None,
        "du": float(np.max(np.abs(du_t - du_r)) / scale_u) if scale_u > 0 else None,
        "area": rel(loop_integral(du_t, fx_t), loop_integral(du_r, fx_r)),
    }


def dissipation_error(test, ref, mu, F0, u_A):
    """Dissipation error: relative to ref, or, when ref is below ``HARDLY_DISSIPATES`` (1 %) of the
    gross-slip scale 4 mu F0 u_A (a loop that hardly dissipates), as a slip-index difference."""
    scale = float(gross_slip_work(mu, F0, u_A))
    if ref is None or test is None:
        return None
    if abs(ref) >= HARDLY_DISSIPATES * scale or scale == 0:
        return rel(test, ref)
    return (float(test) - float(ref)) / scale


def _finite(*xs):
    return all(x is not None and np.isfinite(float(x)) for x in xs)


#: the grades of a verdict, from the strongest claim to none; a scene takes its weakest metric's
#: (``conjunction``)
GRADES = ("holds", "below resolution", "consistent within its spread", "undetermined", "fails")


def grade(difference, error, tolerance, *, bounded: bool, floor: float | None = None) -> tuple:
    """The verdict rule, once for every family: ``(holds, grade)`` of |difference| against
    ``error`` (all error bars summed) + the tolerance, the physics' ``tolerance`` raised to the
    resolution ``floor`` where one is given. ``undetermined`` (None) where a number is missing or not
    finite; ``fails`` (False) beyond the sum; within it ``below resolution`` (None) where the physics'
    tolerance alone would fail and only the floor lets it pass (whether or not the bars bound);
    ``consistent within its spread`` (None) unless ``bounded`` (every error bar an upper bound); else
    ``holds`` (True)."""
    if not _finite(difference, error, tolerance):
        return None, "undetermined"
    allowed = tolerance if floor is None else max(tolerance, floor)
    if abs(difference) > error + allowed:
        return False, "fails"
    if abs(difference) > error + tolerance:
        return None, "below resolution"
    if not bounded:
        return None, "consistent within its spread"
    return True, "holds"


_LADDERS = object()  # effect_verdict's default: the error of the effect's own ladder


def effect_verdict(effect, ladder: dict, tolerance, *, error=_LADDERS, bounded=None) -> dict:
    """The graded verdict of an effect measured by its own ladder (a 3D effect, a tilt, the 3D pressure
    against MDR's): |effect| <= its error + tolerance (``grade``); ``error`` overrides the ladder's
    (e.g. raised to an estimator's resolution; None: unknown, so undetermined), ``bounded`` its
    boundedness."""
    err = ladder.get("error") if error is _LADDERS else error
    b = ladder.get("bounded", False) if bounded is None else bounded
    holds, g = (None, "undetermined") if tolerance is None else grade(effect, err, tolerance, bounded=b)
    return {"effect": effect, "error": err, "status": ladder.get("status"), "tolerance": tolerance,
            "holds": holds, "grade": g, "bounded": b}


def with_settling(v: dict, settle: dict | None) -> dict:
    """An effect verdict (``effect_verdict``) with the settling of its quantity towards the stationary
    cycle (``common.ladder.settling_error``; None: no quantity of the cycles) added to its error bar:
    errors summed, boundedness of both, regraded; the settling kept under ``settling``."""
    if settle is None:
        return {**v, "settling": None}
    err = None if v["error"] is None or settle["error"] is None else v["error"] + settle["error"]
    out = effect_verdict(v["effect"], {"status": v["status"]}, v["tolerance"], error=err,
                         bounded=v["bounded"] and settle["bounded"])
    return {**out, "settling": settle}


def verdict(mdr, fem, fem_ladder: dict, mdr_ladder: dict, tolerance, *, signed=True, unit="",
            extra: dict | None = None, floor: float | None = None) -> dict:
    """One metric's verdict: |MDR - FE| against FE error + MDR error + tolerance, graded.

    ``mdr``, ``fem``: the finest values (for a distance metric ``signed=False``: ``mdr`` is
    the distance between the finest results and ``fem`` None); ``fem_ladder`` and
    ``mdr_ladder``: ``ladder_error`` dicts of each side (the error bars); ``extra``: further
    error bars ``{"fem" | "mdr": {name: ladder dict}}`` in the metric's unit added to that side's
    (the time step's); ``tolerance``: the physics' tolerance, absolute, in the metric's unit; ``floor``:
    the resolution floor it is raised to, if any (the verdict's ``tolerance`` is the larger of the
    two, ``tolerance_physics`` the first).

    ``grade`` (``GRADES``): ``undetermined`` where any number or error bar is not finite or
    missing; ``fails`` where |MDR - FE| exceeds the sum; otherwise ``holds`` only if every error bar
    is an upper bound (``bounded``: an asymptotic or converged ladder), else ``consistent within
    its spread`` (a non-monotone ladder's spread is no bound: an error injected into one level
    can hide in it); ``below resolution`` where it is within the sum only thanks to the floor.
    ``holds`` is True, False or None: True only for the grade ``holds``.
    """
    diff = (None if not _finite(mdr, fem) else float(mdr) - float(fem)) if signed else \
        (None if not _finite(mdr) else float(mdr))
    parts = {"fem": {"mesh": fem_ladder}, "mdr": {"grid": mdr_ladder}}
    for side, bars in (extra or {}).items():  # a bar given as None is unknown: undetermined, never dropped
        parts[side].update({k: ({"error": None, "bounded": False} if v is None else v) for k, v in bars.items()})
    errs = {side: [b.get("error") for b in bars.values()] for side, bars in parts.items()}
    fe_err = float(sum(errs["fem"])) if _finite(*errs["fem"]) else None
    mdr_err = float(sum(errs["mdr"])) if _finite(*errs["mdr"]) else None
    bounded = all(b.get("bounded", b.get("status") in BOUNDED) for bars in parts.values() for b in bars.values())
    holds, g = grade(diff, None if not _finite(fe_err, mdr_err) else fe_err + mdr_err, tolerance,
                     bounded=bounded, floor=floor)
    allowed = None if tolerance is None else float(tolerance if floor is None else max(tolerance, floor))
    return {"mdr": None if mdr is None or not signed else float(mdr), "fem": None if fem is None else float(fem),
            "difference": diff, "fem_error": fe_err, "mdr_error": mdr_err,
            "tolerance": allowed, "tolerance_physics": None if tolerance is None else float(tolerance),
            "floor": floor, "holds": holds,
            "grade": g, "bounded": bounded, "unit": unit, "fem_ladder": fem_ladder, "mdr_ladder": mdr_ladder,
            "error_parts": {side: {k: b.get("error") for k, b in bars.items()} for side, bars in parts.items()}}


def judged(verdicts: dict) -> dict:
    """The verdicts that carry a tolerance: those a scene's or a point's grade is made of."""
    return {q: x for q, x in verdicts.items() if x.get("tolerance") is not None}


def judged_grade(verdicts: dict) -> tuple:
    """(``family_holds``, ``scene_grade``) of the judged verdicts (``judged``): the one rule of a row
    of effects (the assumptions-3d and tilt families)."""
    return family_holds(verdicts.values()), scene_grade(judged(verdicts))


def family_holds(verdicts) -> bool | None:
    """``holds`` of several judged verdicts (those with a tolerance): False if any fails, None if any
    is not graded ``holds`` (or there is none), else True."""
    judged = [x["holds"] for x in verdicts if x.get("tolerance") is not None]
    return False if False in judged else (None if None in judged or not judged else True)


def conjunction(verdicts: dict):
    """Scene verdict, ``family_holds`` of its metrics (``scene_grade`` says which weaker grade)."""
    return family_holds(verdicts.values())


def grade_of(v: dict) -> str:
    """A verdict's grade (a stored result of an older release has only ``holds``)."""
    return v.get("grade") or {True: "holds", False: "fails"}.get(v.get("holds"), "undetermined")


def scene_grade(verdicts: dict) -> str:
    """The weakest grade of a scene's metrics (``GRADES`` order); ``undetermined`` without metrics."""
    grades = [grade_of(v) for v in verdicts.values()]
    return max(grades, key=GRADES.index) if grades else "undetermined"