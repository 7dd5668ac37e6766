"""Frictionless normal contact of an axisymmetric profile by the MDR.

Assumptions: half-space approximation (contact radius small against the
bodies, small surface slopes), linear elasticity, no adhesion, g(x)
nondecreasing (the contact area is a disk of radius a). With the plane
profile g of ``mdr.profiles`` (Popov & Hess, Springer 2015):

    g(a) = d                               (contact radius; a = b for a flat punch)
    F_N  = 2 E* int_0^a (d - g(x)) dx = 2 E* (a d - G(a))
    p(r) = (E*/pi) [ int_r^a g'(x) / sqrt(x^2 - r^2) dx + (d - g(a)) / sqrt(a^2 - r^2) ]

The last term is the edge load of profiles with a sharp edge (flat punch);
it vanishes for smooth profiles. All functions are vectorised over d or F.
"""
from __future__ import annotations

import numpy as np

from common.errors import ConvergenceError, finite, nonnegative
from .materials import Materials
from .profiles import FlatPunch, Profile, TruncatedSphere, _bcast

_GL32_T, _GL32_W = np.polynomial.legendre.leggauss(32)
_GL32_T = 0.5 * (_GL32_T + 1.0)
_GL32_W = 0.5 * _GL32_W


def contact_radius(profile: Profile, d):
    """Contact radius a(d) from g(a) = d."""
    return profile.g_inv(np.asarray(d, dtype=float))


def force_from_approach(profile: Profile, materials: Materials, d):
    """Normal force F_N(d) = 2 E* (a d - G(a)); zero for d <= 0."""
    d = np.asarray(d, dtype=float)
    dp = np.maximum(d, 0.0)
    a = contact_radius(profile, dp)
    F = 2.0 * materials.E_star * (a * dp - profile.G(a))
    return np.where(d > 0, np.maximum(F, 0.0), 0.0)


def approach_from_force(profile: Profile, materials: Materials, F, rtol=1e-14):
    """Approach d(F_N) (inverse of ``force_from_approach``), F_N >= 0.

    Closed forms for the flat punch (d = F/(2E* b)), the parabolic sphere and the parabolic
    truncated sphere (``_approach_truncated``: a cubic in sqrt(a^2 - b^2)); otherwise a
    safeguarded Newton iteration on the contact radius a, using dF/da = 2 E* a g'(a)
    (monotone for nondecreasing g).
    """
    F = np.asarray(nonnegative("F_N (normal force; no adhesion, so >= 0)", F), dtype=float)
    if F.ndim < len(profile.batch_shape):
        F = np.broadcast_to(F, profile.batch_shape)
    Es = materials.E_star
    if isinstance(profile, FlatPunch):
        return F / (2.0 * Es * _bcast(profile.b, F))
    if isinstance(profile, TruncatedSphere) and not profile.exact and not np.any(np.asarray(profile.b) > 0):
        R = _bcast(profile.R, F)
        a = (3.0 * F * R / (4.0 * Es)) ** (1.0 / 3.0)
        return a**2 / R
    if isinstance(profile, TruncatedSphere) and not profile.exact:
        return _approach_truncated(profile, Es, F)
    Fp = np.maximum(F, 0.0)
    lo = np.zeros(Fp.shape)
    for k in profile.kinks:  # a kink below which g vanishes (a flat face) lies inside every contact
        kb = np.broadcast_to(_bcast(k, Fp), Fp.shape)
        lo = np.where(np.asarray(profile.g(kb)) == 0.0, np.maximum(lo, kb), lo)

    def F_of_a(a):
        return 2.0 * Es * (a * profile.g(a) - profile.G(a))

    # bracket: grow hi until F(hi) >= F
    hi = np.maximum(lo * 2.0, 1e-9)
    xlim = profile.x_limit
    for _ in range(200):
        Fh = F_of_a(np.minimum(hi, _bcast(xlim, hi) * (1 - 1e-12) if np.isfinite(np.max(xlim)) else hi))
        need = Fh < Fp
        if not np.any(need):
            break
        hi = np.where(need, hi * 2.0, hi)
    else:
        raise ConvergenceError("could not bracket the contact radius for the requested normal force")
    if np.all(np.isfinite(np.asarray(xlim))):
        hi = np.minimum(hi, _bcast(xlim, hi) * (1 - 1e-12))
    a = 0.5 * (lo + hi)
    step_before = hi - lo
    for it in range(200):
        res = F_of_a(a) - Fp
        if np.all((np.abs(res) <= 1e-14 * Fp) | (Fp == 0)):
            break
        lo = np.where(res < 0, a, lo)
        hi = np.where(res >= 0, a, hi)
        slope = 2.0 * Es * a * profile.dg(a)
        with np.errstate(divide="ignore", invalid="ignore"):
            a_new = a - res / slope
        # bisect where Newton leaves the bracket or does not halve the step before last (a tabulated
        # profile's slope between its samples can stall it inside the bracket)
        slow = np.abs(2.0 * res) > np.abs(step_before * slope)
        bad = ~np.isfinite(a_new) | (a_new <= lo) | (a_new >= hi) | slow
        a_new = np.where(bad, 0.5 * (lo + hi), a_new)
        step_before = np.abs(a_new - a)
        done = (np.abs(res) <= 1e-14 * Fp) | (Fp == 0)
        a_new = np.where(done, a, a_new)
        if np.all(done | (np.abs(a_new - a) <= rtol * np.maximum(a, 1e-300))):
            a = a_new
            break
        a = a_new
    else:
        raise ConvergenceError(f"approach_from_force: Newton on the contact radius did not converge "
                               f"(max residual {float(np.max(np.abs(res))):.3g} N)")
    return np.where(F > 0, profile.g(a), 0.0)


def _approach_truncated(profile: TruncatedSphere, Es, F):
    """``approach_from_force`` of the parabolic truncated sphere in closed form. With t = sqrt(a^2 - b^2),
    g(a) = a t / R and G(a) = t^3 / (3 R), so F = 2 E* (a g - G) = (2 E* / R) (b^2 t + 2 t^3 / 3): a cubic
    in t, increasing and convex for t >= 0, solved by Newton's method from above (from
    min(c / b^2, (3 c / 2)^(1/3)), c = F R / (2 E*), each an upper bound of t), which converges
    monotonically; d = sqrt(t^2 + b^2) t / R. Well conditioned where the contact barely passes the face
    (a - b down to 1e-16 b: a wide face at a light load), where a Newton iteration on a itself cannot
    resolve a - b in floating point (its approach 1 % off at b = 0.6 mm, 5 mN)."""
    R, b = _bcast(profile.R, F), _bcast(profile.b, F)
    c = np.maximum(F, 0.0) * R / (2.0 * Es)
    b2 = b * b
    with np.errstate(divide="ignore"):
        t = np.minimum(np.where(b2 > 0, c / np.where(b2 > 0, b2, 1.0), np.inf), np.cbrt(1.5 * c))
    for _ in range(100):
        with np.errstate(divide="ignore", invalid="ignore"):  # t = 0 at F = 0: no step
            step = (b2 * t + (2.0 / 3.0) * t**3 - c) / (b2 + 2.0 * t * t)
        step = np.where(np.isfinite(step), step, 0.0)
        t_new = np.maximum(t - step, 0.0)
        if np.all(np.abs(t_new - t) <= 4.0 * np.finfo(float).eps * np.abs(t_new)):
            t = t_new
            break
        t = t_new
    else:
        raise ConvergenceError("approach_from_force: Newton on the truncated sphere's cubic did not converge")
    return np.where(F > 0, np.sqrt(t * t + b2) * t / R, 0.0)


def pressure(profile: Profile, materials: Materials, d, r):
    """MDR pressure p(r) at approach ``d`` (scalar) and radii ``r`` (array).

    The integral is evaluated with x = sqrt(r^2 + s^2), split at the kinks of
    g and with a t^2 substitution at each segment's lower end, which absorbs
    the inverse-square-root slope of g just above a kink.
    """
    d = float(nonnegative("d (approach)", d))
    r = np.atleast_1d(np.asarray(finite("r", r), dtype=float))
    a = float(contact_radius(profile, d))
    Es = materials.E_star
    p = np.zeros_like(r)
    inside = r < a
    ri = r[inside]
    S = np.sqrt(a**2 - ri**2)
    breaks = [np.zeros_like(ri)]
    for k in sorted(float(np.max(k)) for k in profile.kinks):
        breaks.append(np.clip(np.sqrt(np.maximum(k**2 - ri**2, 0.0)), 0.0, S))
    breaks.append(S)
    integral = np.zeros_like(ri)
    for s0, s1 in zip(breaks[:-1], breaks[1:]):
        span = (s1 - s0)[:, None]
        s = s0[:, None] + span * _GL32_T**2
        x = np.sqrt(ri[:, None] ** 2 + s**2)
        with np.errstate(divide="ignore", invalid="ignore"):
            integrand = np.where(x > 0, profile.dg(x) / x, 0.0)
        integrand = np.nan_to_num(integrand, nan=0.0, posinf=0.0)
        integral += np.sum(_GL32_W * integrand * 2.0 * span * _GL32_T, axis=1)
    edge = d - float(profile.g(a))
    p[inside] = Es / np.pi * (integral + edge / S)
    return p


def normal_energy(profile: Profile, materials: Materials, d):
    """Elastic energy of the normal contact U = E* int_0^a (d - g)^2 dx = int_0^d F dd'."""
    d = float(nonnegative("d (approach)", d))
    a = float(contact_radius(profile, d))
    return materials.E_star * _contact_integral(profile, a, lambda x: (d - profile.g(x)) ** 2)


def _contact_integral(profile: Profile, a, f) -> float:
    """int_0^a f(x) dx for an integrand built on g: 48-point Gauss-Legendre on each piece between the
    kinks of g, with x = lo + (hi - lo) t^2, which absorbs the sqrt(x - b) behaviour of g just
    above a kink."""
    edges = [0.0] + sorted(float(np.max(k)) for k in profile.kinks if float(np.max(k)) < a) + [a]
    total = 0.0
    t, w = np.polynomial.legendre.leggauss(48)
    t, w = 0.5 * (t + 1.0), 0.5 * w
    for lo, hi in zip(edges[:-1], edges[1:]):
        x = lo + (hi - lo) * t**2
        total += np.sum(w * f(x) * 2.0 * (hi - lo) * t)
    return float(total)


def moment_radius(force, second_moment):
    """The pressure's second-moment radius sqrt(5 M2 / (2 F_N)) (m), from the force F_N = int p dA (N)
    and the second moment M2 = int p r^2 dA (N m^2) about the load axis: the radius of the Hertz
    pressure p0 sqrt(1 - r^2/a^2) of that force and moment (M2 / F_N = 2 a^2 / 5), so for a sphere the
    contact radius. An integral of the pressure, it needs no edge to be located: the one definition
    of ``pressure_radius`` for MDR (:func:`pressure_radius`) and the FE models. NaN for F_N <= 0."""
    force, second_moment = float(force), float(second_moment)
    return float(np.sqrt(2.5 * second_moment / force)) if force > 0 else float("nan")


def pressure_radius(profile: Profile, materials: Materials, d):
    """:func:`moment_radius` of the MDR pressure at approach ``d`` (scalar, m); NaN without contact.

    The MDR line load E* (d - g(x)) is the pressure integrated across the contact (its Abel
    transform), so int p r^2 dA = 2 int q x^2 dx = 4 E* int_0^a (d - g(x)) x^2 dx exactly (the
    same assumptions as :func:`force_from_approach`; the quadrature of :func:`_contact_integral`).
    Hertz: the contact radius; flat punch: sqrt(5/3) b."""
    d = float(nonnegative("d (approach)", d))
    if d == 0.0:
        return float("nan")
    a = float(contact_radius(profile, d))
    M2 = _contact_integral(profile, a, lambda x: (d - profile.g(x)) * x**2)
    return moment_radius(force_from_approach(profile, materials, d), 4.0 * materials.E_star * M2)
