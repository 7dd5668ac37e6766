"""Distances between two results of the same scene (plain arrays in, plain numbers out).

Conventions: a *relative difference* is (test - ref) / |ref| (signed); a
profile error is the relative L2 norm of the difference over the disk
r <= r_max; loop distances
compare two loops sampled at the same phases (the same time steps).
"""
from __future__ import annotations

import numpy as np

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


#: safety factor of the grid convergence index for a three-level study (Roache 1998,
#: Verification and Validation in Computational Science and Engineering, Hermosa)
GCI_SAFETY = 1.25
#: observed orders outside this range are not taken as asymptotic
ORDER_RANGE = (0.5, 4.0)


def ladder_error(sizes, values, *, floor=0.0) -> dict:
    """Error bar of the finest value of a refinement ladder (coarse to fine).

    ``sizes``: the resolution parameter of each level, decreasing (element size, or
    1/cells); ``values``: the quantity at each level (None or non-finite: dropped).
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
    - ``one level`` / ``no value``: error None (undetermined).

    Returns {value, extrapolated, error, order, status, levels}.
    """
    pts = [(float(h), float(v)) for h, v in zip(sizes, values)
           if v is not None and np.isfinite(float(v)) and h is not None]
    out = {"value": pts[-1][1] if pts else None, "extrapolated": None, "error": None, "order": None,
           "status": "no value" if not pts else "one level", "levels": len(pts)}
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
        out.update(error=max(abs(e21), abs(e10)), extrapolated=q2, status="converged")
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
    out.update(extrapolated=float(q2 + e21 / g), error=float(GCI_SAFETY * abs(e21) / g), status="asymptotic")
    return out


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
    """Dissipation error: relative to ref, or, when ref is below 1 % of the gross-slip
    scale 4 mu F0 u_A (a loop that hardly dissipates), as a slip-index difference."""
    scale = 4.0 * mu * F0 * u_A
    if ref is None or test is None:
        return None
    if abs(ref) >= 0.01 * scale or scale == 0:
        return rel(test, ref)
    return (float(test) - float(ref)) / scale


def _finite(*xs):
    return all(x is not None and np.isfinite(float(x)) for x in xs)


def verdict(mdr, fem, fem_ladder: dict, mdr_ladder: dict, tolerance, *, signed=True, unit="") -> dict:
    """One metric's verdict: ``holds`` is |MDR - FE| <= FE error + MDR error + tolerance.

    ``mdr``, ``fem``: the finest values (for a distance metric ``signed=False``: ``mdr`` is
    the distance between the finest results and ``fem`` None); ``fem_ladder`` and
    ``mdr_ladder``: ``ladder_error`` dicts of each side (the error bars); ``tolerance``:
    absolute, in the metric's unit. Any non-finite input makes ``holds`` None
    (undetermined), never True.
    """
    diff = (None if not _finite(mdr, fem) else float(mdr) - float(fem)) if signed else \
        (None if not _finite(mdr) else float(mdr))
    fe_err, mdr_err = fem_ladder.get("error"), mdr_ladder.get("error")
    holds = None
    if _finite(diff, fe_err, mdr_err, tolerance):
        holds = bool(abs(diff) <= fe_err + mdr_err + tolerance)
    return {"mdr": None if mdr is None or not signed else float(mdr), "fem": None if fem is None else float(fem),
            "difference": diff, "fem_error": fe_err, "mdr_error": mdr_err,
            "tolerance": None if tolerance is None else float(tolerance), "holds": holds, "unit": unit,
            "fem_ladder": fem_ladder, "mdr_ladder": mdr_ladder}


def conjunction(verdicts: dict):
    """Scene verdict: False if any metric fails, None (undetermined) if any is undetermined, else True."""
    hs = [v["holds"] for v in verdicts.values()]
    if any(h is False for h in hs):
        return False
    if not hs or any(h is None for h in hs):
        return None
    return True
