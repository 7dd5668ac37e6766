"""MDR's equivalent profile of a measured normal force-approach curve (``EquivalentProfile``).

The MDR law reproduces any axisymmetric contact from its plane profile g(x) (``mdr.profiles``). Read
backwards, a normal force-approach curve F(d) fixes g: the row of springs carries
F(d) = 2 E* int_0^a (d - g(x)) dx with g(a) = d, so dF/dd = 2 E* a(d) (Popov & Hess, *Method of
Dimensionality Reduction in Contact Mechanics and Friction*, Springer 2015, ch. 3): the contact
radius of the equivalent profile at approach d is a(d) = F'(d) / (2 E*), and g is the inverse of a,
g(a(d)) = d. Any contact whose F(d) is convex (a(d) nondecreasing) has one: a rough contact
(ensemble mean), a measured curve. Its tangential behaviour under MDR is then that of the
axisymmetric body with this F(d) under Mindlin's assumptions (Coulomb friction with the traction
along the drive, partial slip from the edge); how far a real rough contact is from that is what
the rough half-space model (``rough.tangential``) measures.

Assumptions: the curve starts at first contact (d = 0, F = 0; added when absent), F is
nondecreasing and, up to the noise of a measured mean, convex; a(d) is read from a monotone cubic
(PCHIP) of the samples, and where noise makes it decrease it is held at its running maximum
(``repair``: the largest such change over a_max). Materials: the E* of the pair the MDR law will
use (the profile is E*-specific).
"""
from __future__ import annotations

import numpy as np
from scipy.interpolate import PchipInterpolator

from common.errors import InputError
from .materials import Materials
from .profiles import TabulatedProfile
from .solve import bisect_increasing

# Gauss-Legendre rule on [0, pi/2] for the inverse transform f(r) = (2/pi) int_0^{pi/2} g(r sin t) dt
_T, _W = np.polynomial.legendre.leggauss(64)
_T, _W = 0.25 * np.pi * (_T + 1.0), 0.25 * np.pi * _W


#: the smallest growth of the contact radius a(d) from one sample to the next that counts (relative to the
#: largest): below it a(d) is a plateau, and where the curve ends on one (a flat face whose contact no
#: longer grows: the smooth face b = 0.6 mm, a - b < 1e-11 b to 0.75 N) g rises to the curve's largest
#: approach over a wall of this width, so that the profile carries the curve's whole force range (the
#: normal solve brackets a within 1e-12 of the table's end: the wall loses 1e-6 of its rise there)
WALL = 1e-6


class EquivalentProfile(TabulatedProfile):
    """The plane profile g of the MDR law whose normal force-approach curve is (``d``, ``F``) (m, N;
    1D samples, at least 4) on ``materials`` (module docstring). ``repair``: the largest change the
    running maximum made to the contact radius a(d), over a_max (0 for a convex curve)."""

    name = "equivalent"

    def __init__(self, d, F, materials: Materials):
        d, F = np.asarray(d, dtype=float), np.asarray(F, dtype=float)
        if d.ndim != 1 or d.shape != F.shape or d.size < 4:
            raise InputError(f"d and F must be 1D arrays of equal length >= 4 (the normal force-approach curve), "
                             f"got shapes {d.shape} and {F.shape}")
        if not (np.all(np.isfinite(d)) and np.all(np.isfinite(F))):
            raise InputError("d and F must be finite (the normal force-approach curve)")
        if d[0] < 0 or np.any(np.diff(d) <= 0):
            raise InputError("the approaches d must be >= 0 and strictly increasing")
        if F[0] < 0 or np.any(np.diff(F) < 0):
            raise InputError("the normal forces F must be >= 0 and nondecreasing in d (no adhesion)")
        if d[0] > 0:
            d, F = np.concatenate([[0.0], d]), np.concatenate([[0.0], F])
        if F[-1] <= 0:
            raise InputError("the normal force must become positive along the curve")
        E = float(materials.E_star)
        a = np.maximum(PchipInterpolator(d, F).derivative()(d), 0.0) / (2.0 * E)
        a_mono = np.maximum.accumulate(a)
        self.repair = float(np.max(a_mono - a) / a_mono[-1])
        keep = np.concatenate([[True], np.diff(a_mono) > WALL * a_mono[-1]])
        x, y = a_mono[keep], d[keep]
        if not keep[-1]:  # a(d) ends on a plateau (F linear in d: a flat punch's edge): g rises there as a wall
            x, y = np.append(x, x[-1] * (1.0 + WALL)), np.append(y, d[-1])
        if x[0] > 0:  # a finite contact radius at first touch: g is flat (zero) out to it
            x, y = np.concatenate([[0.0], x]), np.concatenate([[0.0], y])
        self._x, self._y, self.materials = x, y, materials
        self._tabulate(x, y)
        self._d, self._F = d, F

    def g_inv(self, d, hi=None):
        """The contact radius a with g(a) = d: bisection on the bracketing interval of the table (the
        exact inverse of the interpolant ``g`` uses)."""
        d = np.asarray(d, dtype=float)
        if np.any(d > self._y[-1]):
            raise InputError(f"approach d={float(np.max(d)):.4g} m is beyond the curve's largest approach "
                             f"{self._y[-1]:.4g} m: measure the curve to a larger load")
        j = np.clip(np.searchsorted(self._y, d), 1, self._x.size - 1)
        return np.where(d > 0, bisect_increasing(self._interp, d, self._x[j - 1], self._x[j], rtol=0.0, max_iter=80),
                        0.0)

    def f(self, r):
        """The axisymmetric profile of this g (MDR's inverse transform, f(r) = (2/pi) int_0^r
        g(x) / sqrt(r^2 - x^2) dx = (2/pi) int_0^{pi/2} g(r sin t) dt, 64-point Gauss-Legendre);
        inf beyond x_limit."""
        r = np.asarray(r, dtype=float)
        val = (2.0 / np.pi) * np.sum(_W * self.g(np.minimum(r, self._x[-1])[..., None] * np.sin(_T)), axis=-1)
        return np.where(r > self._x[-1], np.inf, val)

    def describe(self) -> dict:
        return {"profile": "equivalent", "samples": int(self._d.size), "d_max": float(self._d[-1]),
                "F_max": float(self._F[-1]), "a_max": float(self._x[-1]), "repair": self.repair}
