"""Normal contact of the parabolic truncated sphere, compiled (numba).

``approach_truncated_sphere`` is ``mdr.normal.approach_from_force`` for that profile: the same
iteration over all elements of a batch at once (bracket from the flat-face radius, doubled
until it holds the force, then the safeguarded Newton iteration of ``mdr.kernels_step`` on the
contact radius), identical to the last bit. Assumptions: the parabolic cap (not the exact
spherical one) of radius R with a flat face of radius b >= 0 (b = 0: the sphere), F, R, b flat
float64 arrays of one length, one E*; the caller (``mdr.normal``) checks the returned status.
Disk cache: see ``mdr.kernels_step``.
"""
from __future__ import annotations

import math

import numpy as np

from .kernels_step import _jit, _newton_step


# ------------------------------------------------------------------ normal contact
@_jit
def _truncated_force(a, R, b, Es):
    """F_N(a) = 2 E* (a g(a) - G(a)) of the parabolic truncated sphere (``mdr.normal``)."""
    s2 = max(a**2 - b**2, 0.0)
    return 2.0 * Es * (a * (a * math.sqrt(s2) / R) - s2**1.5 / (3.0 * R))


@_jit
def approach_truncated_sphere(F, R, b, Es, rtol, d):
    """``mdr.normal.approach_from_force`` for the parabolic truncated sphere, the same
    iteration over all elements at once: the bracket from the flat-face radius, doubled
    until F(hi) >= F, then the safeguarded Newton iteration on the contact radius, which
    freezes converged elements and stops when every element is converged or took a step
    below rtol (a step criterion shared by the batch, as numpy's loop has it).
    Returns 0, or 1 (bracket failed), 2 (no convergence; residuals in d)."""
    m = F.shape[0]
    Fp = np.maximum(F, 0.0)
    lo = np.maximum(np.zeros(m), b)
    hi = np.maximum(lo * 2.0, 1e-9)
    ok = False
    for _ in range(200):
        need = False
        for i in range(m):
            if _truncated_force(hi[i], R[i], b[i], Es) < Fp[i]:
                hi[i] = hi[i] * 2.0
                need = True
        if not need:
            ok = True
            break
    if not ok:
        return 1
    a = 0.5 * (lo + hi)
    res = np.empty(m)
    a_new = np.empty(m)
    frozen = np.zeros(m, dtype=np.bool_)  # converged: a, and so res, stay as they are
    ok = False
    for it in range(200):
        all_done = True
        for i in range(m):
            if frozen[i]:
                continue
            res[i] = _truncated_force(a[i], R[i], b[i], Es) - Fp[i]
            if not (abs(res[i]) <= 1e-14 * Fp[i] or Fp[i] == 0):
                all_done = False
        if all_done:
            ok = True
            break
        small = True
        for i in range(m):
            if frozen[i]:
                a_new[i] = a[i]
                continue
            ai, bi = a[i], b[i]
            dg = (2.0 * ai**2 - bi**2) / (R[i] * math.sqrt(ai**2 - bi**2)) if ai > bi else 0.0
            # (res = 0 is converged and frozen below, so its bracket no longer matters)
            an, lo[i], hi[i] = _newton_step(ai, res[i], 2.0 * Es * ai * dg, lo[i], hi[i])
            done = abs(res[i]) <= 1e-14 * Fp[i] or Fp[i] == 0
            if done:
                an = ai
                frozen[i] = True
            a_new[i] = an
            if not (done or abs(an - ai) <= rtol * max(ai, 1e-300)):
                small = False
        if small:
            a[:] = a_new
            ok = True
            break
        a[:] = a_new
    if not ok:
        d[:] = res
        return 2
    for i in range(m):
        d[i] = a[i] * math.sqrt(max(a[i]**2 - b[i]**2, 0.0)) / R[i] if F[i] > 0 else 0.0
    return 0
