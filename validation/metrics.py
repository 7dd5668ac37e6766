"""Distances between two results of the same scene (plain arrays in, plain numbers out).

Conventions: a *relative difference* is (test - ref) / |ref| (signed); a
profile error is the area-weighted L2 norm of the difference over the disk
r <= r_max, divided by the reference's peak on that disk; loop distances
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


def own_error(values):
    """Error estimate of the finest of a refinement ladder: |Q_finest - Q_next| / |Q_finest|.

    Assumes the ladder converges monotonically, so the difference to the next
    coarser level bounds the finest level's error (it overestimates it by the
    factor 2^p - 1 for a halved mesh size and order p). None for fewer than two levels.
    """
    vals = [v for v in values if v is not None]
    if len(vals) < 2:
        return None
    q1, q0 = float(vals[-1]), float(vals[-2])
    if q1 == 0.0:
        return None if q0 == 0.0 else float("inf")
    return abs(q1 - q0) / abs(q1)


def profile_error(r_test, f_test, r_ref, f_ref, r_max, n=400):
    """Area-weighted L2 error of profile f(r) on the disk r <= r_max, over the reference peak.

    sqrt(int (f_t - f_r)^2 r dr / int r dr) / max|f_r|; both profiles are
    interpolated linearly on n points (zero beyond their last sample).
    """
    r = np.linspace(0.0, float(r_max), n)
    ft = np.interp(r, np.asarray(r_test, float), np.asarray(f_test, float), right=0.0)
    fr = np.interp(r, np.asarray(r_ref, float), np.asarray(f_ref, float), right=0.0)
    peak = float(np.max(np.abs(fr)))
    if peak == 0.0:
        return None
    l2 = np.sqrt(_trapz((ft - fr) ** 2 * r, r) / _trapz(r, r))
    return float(l2 / peak)


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
