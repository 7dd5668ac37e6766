"""Axisymmetric indenter profiles and their MDR transforms.

A profile is the gap ``f(r)`` between the bodies at first contact (r >= 0,
f(0) = 0, f nondecreasing). The Method of Dimensionality Reduction (Popov &
Hess, *Method of Dimensionality Reduction in Contact Mechanics and Friction*,
Springer 2015) replaces it by the plane profile

    g(x) = |x| * integral_0^|x| f'(r) / sqrt(x^2 - r^2) dr,

so that a row of independent springs indented by ``d - g(x)`` reproduces the
normal and (Hertz-Mindlin) tangential behaviour of the axisymmetric contact
exactly, within the half-space approximation.

Every profile offers, vectorised over numpy arrays:

- ``f(r)``, ``g(x)``, ``dg(x)`` (= g'(x)),
- ``G(x)`` = integral_0^x g, used for exact normal forces of spring cells,
- ``g_inv(d)``: the contact radius ``a`` that solves ``g(a) = d``,
- ``kinks``: radii where g is not smooth (spring grids put a node there).

Profile parameters may be numpy arrays (a batch of scenes); they broadcast
against the leading axes of ``x`` (shape ``batch + (n,)`` or ``batch``).
Assumption everywhere: g is nondecreasing, so the contact area is a disk.
"""
from __future__ import annotations

import numpy as np
from scipy.interpolate import PchipInterpolator

from common.errors import InputError, nonnegative, positive, positive_int
from .solve import bisect_increasing

# 8-point Gauss-Legendre rule on [0, 1]
_GL_T, _GL_W = np.polynomial.legendre.leggauss(8)
_GL_T = 0.5 * (_GL_T + 1.0)
_GL_W = 0.5 * _GL_W


def _bcast(p, x):
    """Reshape parameter ``p`` (scalar or batch array) to broadcast with ``x``."""
    p = np.asarray(p, dtype=float)
    x = np.asarray(x)
    if p.ndim == 0 or x.ndim <= p.ndim:
        return p
    return p.reshape(p.shape + (1,) * (x.ndim - p.ndim))


class Profile:
    """Base class. Subclasses define ``f``, ``g`` and ideally ``G``, ``g_inv``."""

    name = "profile"
    #: True where the contact radius does not depend on the approach (flat punch)
    edge_fixed = False

    # -- required -----------------------------------------------------------
    def f(self, r):
        raise NotImplementedError

    def g(self, x):
        raise NotImplementedError

    # -- generic numerics (overridden by closed forms) ------------------------
    @property
    def kinks(self):
        """Radii (scalars or batch arrays) where g(x) has a kink or singular slope."""
        return ()

    def dg(self, x, eps=1e-7):
        x = np.asarray(x, dtype=float)
        h = eps * np.maximum(np.abs(x), 1e-9)
        return (self.g(x + h) - self.g(np.maximum(x - h, 0.0))) / (x + h - np.maximum(x - h, 0.0))

    def cell_integral(self, lo, hi):
        """integral_lo^hi g(x) dx for lo <= hi (elementwise).

        Gauss-Legendre with the substitution x = lo + (hi - lo) t^2, which keeps
        the rule exact-to-roundoff for the sqrt(x - b) behaviour of g just above
        a kink at ``lo`` (spring grids place cell boundaries at kinks).
        """
        lo = np.asarray(lo, dtype=float)
        hi = np.asarray(hi, dtype=float)
        span = (hi - lo)[..., None]
        x = lo[..., None] + span * _GL_T**2
        return np.sum(_GL_W * self.g(x) * 2.0 * span * _GL_T, axis=-1)

    def G(self, x):
        """integral_0^x g, piecewise over kinks (exact for the closed-form profiles)."""
        x = np.asarray(x, dtype=float)
        total = np.zeros(np.broadcast_shapes(x.shape, *[np.shape(k) for k in self.kinks]) if self.kinks else x.shape)
        lo = np.zeros_like(total)
        for k in sorted(self.kinks, key=lambda v: float(np.max(v))):
            kk = _bcast(k, x)
            seg_hi = np.minimum(x, kk)
            total = total + np.where(seg_hi > lo, self.cell_integral(lo, np.maximum(seg_hi, lo)), 0.0)
            lo = np.maximum(lo, kk)
        return total + np.where(x > lo, self.cell_integral(lo, np.maximum(x, lo)), 0.0)

    def g_inv(self, d, hi=None):
        """Contact radius ``a`` with g(a) = d (bisection, ``mdr.solve.bisect_increasing``; vectorised)."""
        d = np.asarray(d, dtype=float)
        if hi is None:
            hi = self.x_limit
        lo = np.zeros(np.broadcast_shapes(d.shape, np.shape(hi)))
        hi = np.broadcast_to(np.asarray(hi, dtype=float), lo.shape).copy()
        return bisect_increasing(self.g, d, lo, hi, rtol=1e-15, max_iter=200)

    @property
    def batch_shape(self) -> tuple:
        """Shape of the batch of scenes described by array parameters (() for one)."""
        return np.broadcast_shapes(*[np.shape(getattr(self, k)) for k in ("R", "b") if hasattr(self, k)])

    @property
    def x_limit(self):
        """Largest radius at which g is defined (contact radius must stay below)."""
        return np.inf

    def describe(self) -> dict:
        raise NotImplementedError


class TruncatedSphere(Profile):
    """Sphere of radius ``R`` with a flat face of radius ``b`` (b = 0: sphere).

    Parabolic (default): f = 0 for r <= b, (r^2 - b^2)/(2R) beyond, with the
    closed form g(x) = x sqrt(x^2 - b^2)/R for x > b.
    ``exact=True`` uses the exact spherical cap f = sqrt(R^2-b^2) - sqrt(R^2-r^2),
    for which g(x) = x ln[(sqrt(R^2-b^2) + sqrt(x^2-b^2)) / sqrt(R^2-x^2)]
    (valid for x < R; the contact must stay inside the cap).
    """

    name = "truncated"

    def __init__(self, R, b, exact: bool = False):
        self.R = positive("R", R)
        self.b = nonnegative("b", b)
        if np.any(np.asarray(self.b) >= np.asarray(self.R)):
            raise InputError(f"b must be in [0, R) (flat face inside the sphere), got b={b!r}, R={R!r}")
        self.exact = bool(exact)

    @property
    def kinks(self):
        return (self.b,) if np.any(np.asarray(self.b) > 0) else ()

    @property
    def x_limit(self):
        return self.R if self.exact else np.inf

    def f(self, r):
        r = np.asarray(r, dtype=float)
        R, b = _bcast(self.R, r), _bcast(self.b, r)
        if self.exact:
            rr = np.minimum(np.maximum(r, b), R)
            return np.sqrt(R**2 - b**2) - np.sqrt(R**2 - rr**2)
        return np.where(r > b, (r**2 - b**2) / (2.0 * R), 0.0)

    def g(self, x):
        x = np.abs(np.asarray(x, dtype=float))
        R, b = _bcast(self.R, x), _bcast(self.b, x)
        s = np.sqrt(np.maximum(x**2 - b**2, 0.0))
        if self.exact:
            with np.errstate(divide="ignore", invalid="ignore"):
                val = x * np.log((np.sqrt(R**2 - b**2) + s) / np.sqrt(np.maximum(R**2 - x**2, 0.0)))
            return np.where(x >= R, np.inf, np.where(x > b, val, 0.0))
        return x * s / R

    def dg(self, x):
        x = np.abs(np.asarray(x, dtype=float))
        R, b = _bcast(self.R, x), _bcast(self.b, x)
        s2 = x**2 - b**2
        with np.errstate(divide="ignore", invalid="ignore"):
            if self.exact:
                s = np.sqrt(np.maximum(s2, 0.0))
                c = np.sqrt(R**2 - b**2)
                val = np.log((c + s) / np.sqrt(R**2 - x**2)) + x * (x / (s * (c + s)) + x / (R**2 - x**2))
            else:
                val = (2.0 * x**2 - b**2) / (R * np.sqrt(s2))
        return np.where(x > b, val, 0.0)

    def G(self, x):
        if self.exact:
            return super().G(x)
        x = np.asarray(x, dtype=float)
        R, b = _bcast(self.R, x), _bcast(self.b, x)
        return np.maximum(x**2 - b**2, 0.0) ** 1.5 / (3.0 * R)

    def cell_integral(self, lo, hi):
        if self.exact:
            return super().cell_integral(lo, hi)
        return self.G(hi) - self.G(lo)

    def g_inv(self, d, hi=None):
        if self.exact:
            return super().g_inv(d, hi=np.asarray(self.R) * (1 - 1e-12) if hi is None else hi)
        d = np.asarray(d, dtype=float)
        R, b = _bcast(self.R, d), _bcast(self.b, d)
        # x^2 (x^2 - b^2) = R^2 d^2  ->  x^2 = (b^2 + sqrt(b^4 + 4 R^2 d^2)) / 2
        x2 = 0.5 * (b**2 + np.sqrt(b**4 + 4.0 * R**2 * d**2))
        return np.sqrt(x2)

    def describe(self):
        return {"profile": "sphere" if not np.any(np.asarray(self.b) > 0) else "truncated",
                "R": self.R, "b": self.b, "exact_cap": self.exact}


class RoundedTruncatedSphere(Profile):
    """Truncated sphere whose kink at r = b is rounded by a circular fillet of radial width ``w``
    (parabolic approximation, like ``TruncatedSphere``): the flat face f = 0 for r <= r1, the fillet
    f = (r - r1)^2 / (2 rho) for r1 < r < r2, the sphere f = (r^2 - b^2) / (2R) beyond r2.

    The fillet is tangent to the flat face at r1 and to the sphere at r2 = r1 + w, and lies between
    the face's plane and the sphere (rounding an edge removes material: f >= the sharp profile's),
    which fixes r2 = (w + sqrt(w^2 + 4 b^2)) / 2 and rho = w R / r2. w -> 0 is the sharp kink. With
    f' = 0, (r - r1)/rho and r/R on the three pieces, the MDR transform is closed:

        g(x) = (x / rho) [s(r1) - s(m) - r1 (asin(m/x) - asin(r1/x))] + (x / R) s(r2) [x > r2],

    s(r) = sqrt(x^2 - r^2), m = min(x, r2). The sharp kink's pressure is log-singular at r = b;
    the fillet bounds it. One scene (no batch arrays).
    """

    name = "rounded"

    def __init__(self, R, b, w):
        self.R = float(positive("R", R))
        self.b = float(positive("b", b))
        self.w = float(positive("fillet", w))
        if np.ndim(R) or np.ndim(b) or np.ndim(w):
            raise InputError("a rounded truncated sphere is one scene: R, b and fillet must be numbers")
        self.r2 = 0.5 * (self.w + np.sqrt(self.w**2 + 4.0 * self.b**2))
        self.r1 = self.r2 - self.w
        self.rho = self.w * self.R / self.r2
        if self.r2 >= self.R:
            raise InputError(f"b + fillet must stay well inside the sphere (r2 < R), got b={b!r}, fillet={w!r}, R={R!r}")

    @property
    def kinks(self):
        return (self.r1, self.r2)

    def f(self, r):
        r = np.asarray(r, dtype=float)
        fil = (r - self.r1) ** 2 / (2.0 * self.rho)
        sph = (r**2 - self.b**2) / (2.0 * self.R)
        return np.where(r <= self.r1, 0.0, np.where(r < self.r2, fil, sph))

    def _parts(self, x):
        x = np.abs(np.asarray(x, dtype=float))
        r1, r2 = self.r1, self.r2
        xs = np.maximum(x, 1e-300)
        s1 = np.sqrt(np.maximum(x**2 - r1**2, 0.0))
        s2 = np.sqrt(np.maximum(x**2 - r2**2, 0.0))
        m = np.minimum(x, r2)
        with np.errstate(invalid="ignore"):
            asin = lambda v: np.arcsin(np.clip(v / xs, -1.0, 1.0))  # noqa: E731
            sm = np.sqrt(np.maximum(x**2 - m**2, 0.0))
            I = (s1 - sm - r1 * (asin(m) - asin(r1))) / self.rho + np.where(x > r2, s2 / self.R, 0.0)
        return x, s1, s2, np.where(x > r1, I, 0.0)

    def g(self, x):
        x, _, _, I = self._parts(x)
        return x * I

    def dg(self, x):
        # g = x I(x): I' = s1 / (rho x) on the fillet, s1 / (rho x) - r1 s2 / (w R x) beyond (the 1/s2 terms
        # of the two pieces cancel: f' is continuous at r2)
        x, s1, s2, I = self._parts(x)
        val = I + s1 / self.rho - np.where(x > self.r2, self.r1 * s2 / (self.w * self.R), 0.0)
        return np.where(x > self.r1, val, 0.0)

    def g_inv(self, d, hi=None):
        d = np.asarray(d, dtype=float)
        if hi is None:  # beyond the root: the sphere's g from r2 on alone, x s(r2) / R, reaches d there
            hi = np.sqrt(0.5 * (self.r2**2 + np.sqrt(self.r2**4 + 4.0 * self.R**2 * d**2))) * (1 + 1e-12) + 1e-300
        return super().g_inv(d, hi=hi)

    def describe(self):
        return {"profile": "rounded", "R": self.R, "b": self.b, "fillet": self.w}


class Sphere(TruncatedSphere):
    """Parabolic sphere f = r^2/(2R): g(x) = x^2/R (Hertz)."""

    name = "sphere"

    def __init__(self, R, exact: bool = False):
        super().__init__(R, 0.0, exact=exact)


class FlatPunch(Profile):
    """Rigid-edged flat cylindrical punch of radius ``b``: g = 0 for x <= b, inf beyond.

    The contact radius is ``b`` for any approach d > 0.
    """

    name = "flat"
    edge_fixed = True

    def __init__(self, b):
        self.b = positive("b", b)

    @property
    def kinks(self):
        return (self.b,)

    @property
    def x_limit(self):
        return self.b

    def f(self, r):
        r = np.asarray(r, dtype=float)
        return np.where(r <= _bcast(self.b, r), 0.0, np.inf)

    def g(self, x):
        x = np.abs(np.asarray(x, dtype=float))
        return np.where(x <= _bcast(self.b, x) * (1 + 1e-12), 0.0, np.inf)

    def dg(self, x):
        return np.zeros_like(np.asarray(x, dtype=float))

    def G(self, x):
        x = np.asarray(x, dtype=float)
        return np.where(x <= _bcast(self.b, x) * (1 + 1e-12), 0.0, np.inf)

    def cell_integral(self, lo, hi):
        return np.zeros(np.broadcast_shapes(np.shape(lo), np.shape(hi)))

    def g_inv(self, d, hi=None):
        d = np.asarray(d, dtype=float)
        return np.broadcast_to(_bcast(self.b, d), d.shape).astype(float) * np.ones_like(d)

    def describe(self):
        return {"profile": "flat", "b": self.b}


class TabulatedProfile(Profile):
    """A profile whose plane profile g is one monotone cubic (PCHIP) over a table (x, g) from x = 0 to
    ``x_limit``: g, g', G and the cells' integrals all from that interpolant, g = inf beyond the table
    (``GeneralProfile``, ``mdr.equivalent.EquivalentProfile``). Assumes the table nondecreasing."""

    def _tabulate(self, x, gtab):
        self._xg = np.asarray(x, dtype=float)
        self._interp = PchipInterpolator(self._xg, gtab, extrapolate=False)
        self._dinterp = self._interp.derivative()
        self._Ginterp = self._interp.antiderivative()

    @property
    def x_limit(self):
        return self._xg[-1]

    def g(self, x):
        x = np.abs(np.asarray(x, dtype=float))
        val = self._interp(np.minimum(x, self._xg[-1]))
        return np.where(x > self._xg[-1], np.inf, val)

    def dg(self, x):
        x = np.abs(np.asarray(x, dtype=float))
        return self._dinterp(np.minimum(x, self._xg[-1]))

    def G(self, x):
        x = np.asarray(x, dtype=float)
        return self._Ginterp(np.minimum(x, self._xg[-1])) - self._Ginterp(0.0)

    def cell_integral(self, lo, hi):
        return self.G(hi) - self.G(lo)


class GeneralProfile(TabulatedProfile):
    """Any axisymmetric profile from a callable ``f(r)`` or samples ``(r, f)``.

    The gap is interpolated piecewise linearly between samples (the callable is
    sampled at ``n`` points on [0, r_max]), for which the MDR transform is exact:

        g(x) = x * sum_j s_j [asin(min(r_{j+1}, x)/x) - asin(min(r_j, x)/x)],

    with s_j the slope of segment j. g is tabulated on the sample radii and
    interpolated with a monotone cubic (PCHIP); G and g' follow from the same
    interpolant. Kinks of f (``kinks=[...]``) are added to the samples so the
    interpolation honours them. Assumes f(0) = 0 and g nondecreasing.
    """

    name = "general"

    def __init__(self, f=None, *, r=None, samples=None, r_max=None, n=4001, kinks=()):
        if (f is None) == (samples is None):
            raise InputError("GeneralProfile needs exactly one of f (callable) or samples (array of f(r))")
        if f is not None:
            r_max = positive("r_max", r_max) if r_max is not None else None
            if r_max is None:
                raise InputError("r_max must be given (> 0) with a callable profile f")
            n = positive_int("n", n, minimum=16)
            rr = np.linspace(0.0, r_max, n)
            extra = [float(k) for k in np.atleast_1d(kinks) if 0 < float(k) < r_max]
            rr = np.unique(np.concatenate([rr, extra]))
            ff = np.asarray(f(rr), dtype=float)
        else:
            if r is None:
                raise InputError("samples need their radii r")
            rr = np.asarray(r, dtype=float)
            ff = np.asarray(samples, dtype=float)
            if rr.shape != ff.shape or rr.ndim != 1 or rr.size < 3:
                raise InputError("r and samples must be 1D arrays of equal length >= 3")
            order = np.argsort(rr)
            rr, ff = rr[order], ff[order]
        if not (np.all(np.isfinite(rr)) and np.all(np.isfinite(ff))):
            raise InputError("profile samples must be finite")
        if rr[0] < 0 or np.any(np.diff(rr) <= 0):
            raise InputError("profile radii r must be >= 0 and strictly increasing")
        if rr[0] > 0:
            rr = np.concatenate([[0.0], rr])
            ff = np.concatenate([[ff[0]], ff])
        ff = ff - ff[0]
        if np.any(np.diff(ff) < -1e-15 * max(np.max(np.abs(ff)), 1e-300)):
            raise InputError("profile f(r) must be nondecreasing in r")
        self._r, self._f = rr, ff
        self._kinks = tuple(float(k) for k in np.atleast_1d(kinks) if float(k) > 0)
        slopes = np.diff(ff) / np.diff(rr)
        x = rr[1:]
        gtab = np.empty(x.size)
        chunk = max(1, 2_000_000 // rr.size)  # bound the memory of the O(n^2) transform
        for i in range(0, x.size, chunk):
            xc = x[i:i + chunk, None]
            m = min(rr.size - 1, i + chunk)  # segments beyond the largest x of the chunk add nothing
            lo = np.minimum(rr[None, :m], xc) / xc
            hi = np.minimum(rr[None, 1:m + 1], xc) / xc
            gtab[i:i + chunk] = xc[:, 0] * np.sum(slopes[None, :m] * (np.arcsin(hi) - np.arcsin(lo)), axis=1)
        gtab = np.concatenate([[0.0], gtab])
        if np.any(np.diff(gtab) < -1e-12 * max(gtab.max(), 1e-300)):
            raise InputError("the profile's MDR transform g(x) is not monotone: the contact would not be "
                             "a disk, which the MDR contact law does not cover")
        self._gtab = np.maximum.accumulate(gtab)
        self._tabulate(rr, self._gtab)

    @property
    def kinks(self):
        return self._kinks

    def f(self, r):
        return np.interp(np.asarray(r, dtype=float), self._r, self._f, right=np.inf)

    def g_inv(self, d, hi=None):
        d = np.asarray(d, dtype=float)
        if np.any(d > self._gtab[-1]):
            raise InputError(f"approach d={float(np.max(d)):.4g} m puts the contact edge beyond the "
                             f"profile's sampled radius r_max={self._r[-1]:.4g} m; give a larger r_max")
        j = np.clip(np.searchsorted(self._gtab, d), 1, len(self._r) - 1)
        lo, hi_ = self._r[j - 1], self._r[j]
        # bisection on the bracketing interval of the table, exact to roundoff
        return bisect_increasing(self._interp, d, lo, hi_, rtol=0.0, max_iter=60)

    def describe(self):
        return {"profile": "general", "r_max": float(self._r[-1]), "samples": int(self._r.size)}


def make_profile(kind: str, R=None, b=None, exact: bool = False, fillet=None) -> Profile:
    """Build a profile from a command-line style name: sphere, truncated or flat; ``fillet`` (m, > 0,
    truncated only): the kink rounded by a circular fillet of that radial width
    (``RoundedTruncatedSphere``; 0 or None: the sharp kink).

    Parameters that the named profile does not use are conflicting input and
    rejected (b for the sphere unless 0, R and the exact cap for the flat punch),
    never silently ignored.
    """
    if kind not in ("sphere", "truncated", "flat"):
        raise InputError(f"profile must be one of sphere, truncated, flat; got {kind!r}")
    if kind == "sphere" and b is not None and b != 0:
        raise InputError(f"b is not a parameter of profile 'sphere' (got b={b!r}); use profile 'truncated' "
                         f"for a flat face of radius b")
    if kind == "flat" and R is not None:
        raise InputError(f"R is not a parameter of profile 'flat' (got R={R!r}); the flat punch has radius b only")
    if kind == "flat" and exact:
        raise InputError("exact (the exact spherical cap) does not apply to profile 'flat'")
    if fillet is not None and fillet != 0:
        if kind != "truncated":
            raise InputError(f"fillet (the rounded kink) applies to profile 'truncated' only, got profile {kind!r}")
        if exact:
            raise InputError("fillet (the rounded kink) is parabolic: not with exact (the exact spherical cap)")
        if R is None or b is None:
            raise InputError("R and b must be given for profile 'truncated' (R > 0, 0 < b < R)")
        return RoundedTruncatedSphere(R, b, fillet)
    if kind == "sphere":
        if R is None:
            raise InputError("R must be given (> 0) for profile 'sphere'")
        return Sphere(R, exact=exact)
    if kind == "truncated":
        if R is None or b is None:
            raise InputError("R and b must be given for profile 'truncated' (R > 0, 0 <= b < R)")
        return TruncatedSphere(R, b, exact=exact)
    if kind == "flat":
        if b is None:
            raise InputError("b must be given (> 0) for profile 'flat'")
        return FlatPunch(b)
    raise InputError(f"profile must be one of sphere, truncated, flat; got {kind!r}")
