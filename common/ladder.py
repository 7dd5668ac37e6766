"""Error bars of a discretisation: a refinement ladder (``ladder_error``, one home:
``validation.metrics`` and the studies of ``python -m mdr study --law NAME`` use it), and the
settling of a quantity over load cycles towards its stationary cycle (``settling_error``).
"""
from __future__ import annotations

import numpy as np


#: safety factor of the grid convergence index for a three-level study (Roache 1998,
#: Verification and Validation in Computational Science and Engineering, Hermosa)
GCI_SAFETY = 1.25
#: observed orders outside this range are not taken as asymptotic
ORDER_RANGE = (0.5, 4.0)
#: the statuses whose error is an upper bound (``ladder_error``'s and ``modelled_error``'s ``bounded``)
BOUNDED = ("asymptotic", "converged", "calibrated")
#: ``settling_error``: the slowest contraction assumed of the cycles, the ratio of successive
#: changes (measured on the 3D model at Table 2's loading: 0.16-0.6 for the traction's direction; the
#: coupled steel/aluminium pair settles in modes, its slowest tail at 0.86-0.93 on the a/5-a/7 meshes
#: over cycles 8-30); the remainder after a last change d is at most d r / (1 - r) = 19 d
SETTLING_RATIO_MAX = 0.95
#: a change below this fraction of the floor counts as settled whether or not it still contracts
#: (round-off level changes do not: 1e-20 after 1e-21 J on a sticking punch)
NEGLIGIBLE = 1e-3
#: the statuses of ``settling_error`` whose error is an upper bound
SETTLED = ("stationary",)


def ladder_error(sizes, values, *, floor=0.0) -> dict:
    """Error bar of the finest value of a refinement ladder (coarse to fine).

    ``sizes``: the resolution parameter of each level, decreasing (element size, or
    1/cells); ``values``: the quantity at each level. A level without a finite value (None,
    NaN, inf) makes the whole ladder undetermined (``non-finite level``, error None): a
    failed level is not dropped, since the levels left could then vouch for a wrong answer.
    Over the three finest levels q0, q1, q2 (refinement ratios r10 = h0/h1, r21 =
    h1/h2) with e10 = q1 - q0, e21 = q2 - q1:

    - ``converged``: |e21|, |e10| <= ``floor`` (round-off or an exact answer on both
      levels): error = max(|e21|, |e10|);
    - ``asymptotic``: e10, e21 of one sign and an observed order p (Celik et al.
      2008, J. Fluids Eng. 130, 078001: fixed point of p = ln|e10/e21 (r21^p - 1)/
      (r10^p - 1)| / ln r21) inside ``ORDER_RANGE``: Richardson extrapolation
      q2 + e21/(r21^p - 1), error = GCI_SAFETY |e21| / (r21^p - 1) (Roache's grid
      convergence index);
    - ``non-monotone`` (e10, e21 of opposite signs) or ``order p outside ...``: the
      ladder is not in its asymptotic range; error = the spread max - min of the
      three levels (never the last difference alone);
    - ``two levels``: error = |e21| (no order can be observed; flagged);
    - ``one level`` / ``no value`` / ``non-finite level``: error None (undetermined).

    ``bounded``: whether the error is an upper bound of the finest level's error for a stated
    reason (``asymptotic``: Richardson with the GCI's safety factor; ``converged``: round-off),
    as a verdict "holds" needs; a spread or a last difference is not.

    Returns {value, extrapolated, error, order, status, levels, bounded}.
    """
    pairs = list(zip(sizes, values))
    finite = [v is not None and h is not None and np.isfinite(float(v)) for h, v in pairs]
    pts = [(float(h), float(v)) for (h, v), ok in zip(pairs, finite) if ok]
    out = {"value": pts[-1][1] if pts else None, "extrapolated": None, "error": None, "order": None,
           "status": "no value" if not pts else "one level", "levels": len(pts), "bounded": False}
    if pts and not all(finite):
        out.update(status="non-finite level", value=pts[-1][1] if finite[-1] else None)
        return out
    if len(pts) < 2:
        return out
    (h1, q1), (h2, q2) = pts[-2], pts[-1]
    e21 = q2 - q1
    if len(pts) == 2:
        out.update(error=abs(e21), status="two levels")
        return out
    h0, q0 = pts[-3]
    e10 = q1 - q0
    if abs(e21) <= floor and abs(e10) <= floor:
        out.update(error=max(abs(e21), abs(e10)), extrapolated=q2, status="converged", bounded=True)
        return out
    spread = max(q0, q1, q2) - min(q0, q1, q2)
    if e21 == 0.0 or e10 == 0.0 or np.sign(e21) != np.sign(e10):
        out.update(error=float(spread), status="non-monotone")
        return out
    r21, r10 = h1 / h2, h0 / h1
    ratio = abs(e10 / e21)
    p = _observed_order(ratio, r21, r10)
    out["order"] = float(p) if np.isfinite(p) else None
    if not (np.isfinite(p) and ORDER_RANGE[0] <= p <= ORDER_RANGE[1]):
        out.update(error=float(spread), status=f"order {p:.2g} outside {ORDER_RANGE[0]:g}-{ORDER_RANGE[1]:g}")
        return out
    g = r21 ** p - 1.0
    out.update(extrapolated=float(q2 + e21 / g), error=float(GCI_SAFETY * abs(e21) / g), status="asymptotic",
               bounded=True)
    return out


def modelled_error(sizes, values, bound, *, floor=0.0) -> dict:
    """Error bar of the finest value of a ladder whose error obeys a calibrated bound |q(h) - q(0)| <=
    ``bound(h)`` (a callable, in the quantity's unit), where the ladder alone need not be asymptotic (the
    quantity jumps with the mesh: an edge that falls at a different place in an element on each level).

    ``ladder_error``'s statuses stand where they decide alone (``converged``; a missing or non-finite
    level). Otherwise the ladder tests the bound: if every two levels lie within the sum of their bounds,
    |q_i - q_j| <= bound(h_i) + bound(h_j) + ``floor`` (what the bound implies, so a level that breaks it
    refutes it for this ladder; the three finest levels, as ``ladder_error``'s), the status is
    ``calibrated`` and the error the larger of bound(h_finest) and the ladder's own bounded error
    (Richardson's, where asymptotic): bounded. A ladder that breaks it
    is ``outside its calibrated bound``: error the larger of the spread and the bound, not bounded.
    Returns ``ladder_error``'s dict with ``bound`` (bound(h_finest)) added."""
    lad = ladder_error(sizes, values, floor=floor)
    if lad["error"] is None or lad["status"] == "converged":
        return {**lad, "bound": None}
    hs = [float(h) for h in sizes][-3:]
    qs = [float(v) for v in values][-3:]
    E = [float(bound(h)) for h in hs]
    consistent = all(abs(qs[i] - qs[j]) <= E[i] + E[j] + floor for i in range(len(qs)) for j in range(i))
    if consistent:
        own = lad["error"] if lad["bounded"] else 0.0
        return {**lad, "error": max(E[-1], own), "status": "calibrated", "bounded": True, "bound": E[-1]}
    spread = max(qs) - min(qs)
    return {**lad, "error": max(spread, E[-1]), "status": "outside its calibrated bound", "bounded": False,
            "bound": E[-1]}


def ensemble_ladder(values_by_level, sizes) -> tuple:
    """An ensemble on a refinement ladder (``values_by_level``: per level, coarse to fine, the members'
    values; ``sizes`` as ``ladder_error``'s): (the members' mean at the finest level, its standard error
    there, the grid error of the mean over the levels, ``ladder_error``'s: None where undetermined)."""
    means = [float(np.mean(v)) for v in values_by_level]
    fine = np.asarray(values_by_level[-1], dtype=float)
    sem = float(fine.std(ddof=1) / np.sqrt(fine.size)) if fine.size > 1 else 0.0
    return means[-1], sem, ladder_error(sizes, means)["error"]


def _observed_order(ratio, r21, r10) -> float:
    """Order p of Q = Q* + C h^p from e10/e21 = r21^p (r10^p - 1)/(r21^p - 1) (Celik et al. 2008);
    NaN where no p in (0.01, 30) fits."""
    from scipy.optimize import brentq

    if abs(r21 - r10) < 1e-12 * r21:
        return float(np.log(ratio) / np.log(r21))
    f = lambda p: np.log(ratio) - p * np.log(r21) - np.log((r10 ** p - 1.0) / (r21 ** p - 1.0))  # noqa: E731
    lo, hi = 0.01, 30.0
    if not (np.isfinite(f(lo)) and np.isfinite(f(hi))) or f(lo) * f(hi) > 0:
        return float("nan")
    return float(brentq(f, lo, hi, xtol=1e-12))


def contracting(values) -> bool:
    """Whether the last change of a sequence of cycles is 0 or at most ``SETTLING_RATIO_MAX`` of the
    one before (False with fewer than three values and a non-zero change), up to the round-off of the
    two changes: each difference of two doubles is off by up to an ulp of the larger, so a tie within
    4 eps max |x| counts as contracting on every rounding path (a ratio at exactly the bound, read from
    changes of 1e-8 of the values, is otherwise decided by the last bits: 2e-9 of the ratio)."""
    x = np.array([float(v) for v in values])
    d = np.diff(x)
    if d.size and d[-1] == 0.0:
        return True
    if d.size < 2:
        return False
    roundoff = 4.0 * np.finfo(float).eps * float(np.max(np.abs(x[-3:])))
    return abs(d[-1]) <= SETTLING_RATIO_MAX * abs(d[-2]) * (1.0 + 1e-12) + roundoff


def settling_error(values, *, floor=0.0) -> dict:
    """Error bar of a quantity's last cycle against its stationary cycle, from its values over the
    closed cycles of a run (in order, the cycle from rest left out).

    Assumes the cycles contract: each repeats at most ``SETTLING_RATIO_MAX`` = r of the last one's
    change (geometric settling, the slowest mode dominating), so that after a last change d_n =
    x_n - x_n-1 the stationary cycle is at most |d_n| r / (1 - r) away. Early cycles mix faster
    modes (the coupled dissimilar pair on one mesh: ratios 0.26, 0.56, 0.72, 0.86, 0.86 ... 0.9;
    on another a fast mode dies by cycle 9 and a slow one of ~5e-5 per cycle at ratio ~0.93 remains),
    so an extrapolation from the ratios observed so far is no bound (it fell short on that pair after
    4, 5 and 7 cycles), nor is a bound from the slowest ratio before the run has settled.

    - ``stationary``: |d_n| <= ``floor`` (the run has settled to that level; 0: the last two cycles
      repeat, in a rate-independent model a fixed point) and still contracting (``contracting``: a
      change no smaller than r times the one before is no settling, unless below ``NEGLIGIBLE``
      of the floor): error |d_n| r / (1 - r), bounded;
    - ``settling``: a larger change with a contracting latest ratio rho = d_n / d_n-1 (|rho| < 1):
      error |d_n| s / (1 - s) with s the larger of |rho| and r, and Aitken's x_n + d_n rho / (1 - rho)
      as ``extrapolated``; no bound;
    - ``not contracting`` (|rho| >= 1) or ``two cycles``: the spread of the last three values (two);
      no bound;
    - ``one cycle`` / ``no value`` / ``non-finite cycle``: error None (undetermined).

    ``bounded`` as in ``ladder_error``: True for the statuses in ``SETTLED``.
    Returns {value, extrapolated, error, ratio, status, cycles, bounded}.
    """
    xs = [None if v is None else float(v) for v in values]
    out = {"value": xs[-1] if xs else None, "extrapolated": None, "error": None, "ratio": None,
           "status": "no value" if not xs else "one cycle", "cycles": len(xs), "bounded": False}
    if any(x is None or not np.isfinite(x) for x in xs):
        out.update(status="non-finite cycle", value=None)
        return out
    if len(xs) < 2:
        return out
    r = SETTLING_RATIO_MAX
    d = np.diff(xs)
    dn = float(d[-1])
    if abs(dn) <= floor and (contracting(xs) or abs(dn) <= NEGLIGIBLE * floor):
        out.update(error=abs(dn) * r / (1.0 - r), extrapolated=xs[-1], status="stationary", bounded=True)
        return out
    spread = float(max(xs[-3:]) - min(xs[-3:]))
    if len(xs) == 2:
        out.update(error=spread, status="two cycles")
        return out
    rho = dn / float(d[-2]) if d[-2] != 0.0 else float("inf")
    if abs(rho) < 1.0:
        s = max(abs(rho), r)
        out.update(error=abs(dn) * s / (1.0 - s), extrapolated=xs[-1] + dn * rho / (1.0 - rho), ratio=rho,
                   status="settling")
    else:
        out.update(error=spread, ratio=rho if np.isfinite(rho) else None, status="not contracting")
    return out
