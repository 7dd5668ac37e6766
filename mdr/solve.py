"""Root finding for monotone scalar equations, vectorised (the one home of the project's
root finders).

- :func:`solve_increasing`: safeguarded Newton, for a function with a slope. Used
  wherever an equilibrium reduces to one monotone equation per scene: a tangential
  force prescribed on a contact law, or the apparatus equilibrium. The functions
  involved are piecewise linear (spring cells sticking or slipping), for which Newton
  terminates exactly once it lands on the right piece; a bracket that shrinks every
  iteration makes it robust.
- :func:`bisect_increasing`: bisection, for a function without a slope (a profile's
  contact radius from its approach, ``mdr.profiles``).
- :func:`regula_falsi_increasing`: one scalar, values only, each evaluation an expensive
  solve (the FE contact laws' force-control fallbacks, ``fem.axisym.friction`` and
  ``fem.solid3d.contact``: a total force against the displacement that produced it): bracket
  expansion and the Illinois variant of regula falsi.

Solvers tied to one problem stay with it: the semi-smooth Newton methods of the FE
contact problems (``fem.axisym.normal``, ``fem.axisym.friction``, ``fem.solid3d.contact``).
"""
from __future__ import annotations

import numpy as np

from common.errors import ConvergenceError


#: iteration limit of ``solve_increasing`` (also of its compiled copies in ``mdr.kernels``)
MAX_ITER = 200
#: bracket doublings of ``regula_falsi_increasing`` before it gives up (2^60 the first bracket)
MAX_DOUBLINGS = 60


def solve_increasing(fun, target, lo, hi, x0=None, atol=0.0, xtol=0.0, max_iter=MAX_ITER, what="equation"):
    """Solve fun(x) = target for nondecreasing ``fun`` on the bracket [lo, hi].

    ``fun(x)`` returns (value, slope) elementwise. Requires
    fun(lo) <= target <= fun(hi) (not checked for speed; a violated bracket ends
    at the bracket end and is caught by the residual check). Returns x.
    Raises ConvergenceError with the worst residual if ``max_iter`` is reached.
    """
    target = np.asarray(target, dtype=float)
    lo = np.array(np.broadcast_to(lo, target.shape), dtype=float)
    hi = np.array(np.broadcast_to(hi, target.shape), dtype=float)
    x = 0.5 * (lo + hi) if x0 is None else np.clip(np.broadcast_to(x0, target.shape), lo, hi)
    atol = np.broadcast_to(atol, target.shape)
    for it in range(max_iter):
        f, s = fun(x)
        r = f - target
        if np.all((np.abs(r) <= atol) | (hi - lo <= xtol)):
            return x
        lo = np.where(r < 0, x, lo)
        hi = np.where(r > 0, x, hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = x - r / s
        bad = ~np.isfinite(xn) | (xn <= lo) | (xn >= hi)
        xn = np.where(bad, 0.5 * (lo + hi), xn)
        x = np.where(np.abs(r) <= atol, x, xn)
    f, _ = fun(x)
    worst = float(np.max(np.abs(f - target)))
    raise ConvergenceError(f"{what}: safeguarded Newton did not converge in {max_iter} iterations "
                           f"(worst residual {worst:.3e}, tolerance {float(np.max(atol)):.3e})")


def bisect_increasing(fun, target, lo, hi, rtol=0.0, max_iter=200):
    """Solve fun(x) = target for nondecreasing ``fun`` (values only) by bisection on [lo, hi],
    elementwise. Stops when every bracket is below ``rtol`` times its upper end (floored at
    1e-30; ``rtol=0``: until the brackets collapse to round-off) or after ``max_iter``
    halvings, and returns the brackets' midpoints (no error: the caller's bracket decides)."""
    for _ in range(max_iter):
        mid = 0.5 * (lo + hi)
        below = fun(mid) < target
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
        if np.all(hi - lo <= rtol * np.maximum(hi, 1e-30)):
            break
    return 0.5 * (lo + hi)


def regula_falsi_increasing(fun, lo, hi, tol, xtol=0.0, max_iter=200, what="equation"):
    """Zero of a continuous nondecreasing scalar ``fun`` by regula falsi, Illinois variant
    (Dowell & Jarratt, BIT 11 (1971) 168). ``fun(x)`` returns (value, payload); the bracket
    [lo, hi] (lo < 0 < hi) is doubled outwards until it holds a sign change (at most
    ``MAX_DOUBLINGS`` times, then ConvergenceError: an unreachable target). Stops when
    |value| <= ``tol`` or the bracket is below ``xtol``; returns (x, payload). Raises
    ConvergenceError after ``max_iter`` iterations."""
    flo, _ = fun(lo)
    fhi, out = fun(hi)
    for _ in range(MAX_DOUBLINGS):
        if fhi >= 0 and flo <= 0:
            break
        if fhi < 0:
            hi *= 2
            fhi, out = fun(hi)
        if flo > 0:
            lo *= 2
            flo, out = fun(lo)
    else:
        raise ConvergenceError(f"{what}: no sign change in [{lo:.3g}, {hi:.3g}] after {MAX_DOUBLINGS} doublings "
                               "(is the target reachable?)")
    side = 0
    for _ in range(max_iter):
        x = hi - fhi * (hi - lo) / (fhi - flo) if fhi != flo else 0.5 * (lo + hi)
        fx, out = fun(x)
        if abs(fx) <= tol or hi - lo <= xtol:
            return x, out
        if fx < 0:
            lo, flo = x, fx
            if side == -1:
                fhi *= 0.5
            side = -1
        else:
            hi, fhi = x, fx
            if side == 1:
                flo *= 0.5
            side = 1
    raise ConvergenceError(f"{what}: regula falsi did not converge in {max_iter} iterations")
