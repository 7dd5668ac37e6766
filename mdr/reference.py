"""Closed-form reference solutions (half-space, Hertz-Mindlin assumptions).

These are the independent truths the tests and the validation report hold the
numerical models against. Nothing here calls a solver. Sources:

- Hertz, J. reine angew. Math. 92 (1882) 156: sphere normal contact.
- Truncated sphere (parabolic cap with flat face of radius b): Ciavarella,
  Hills & Monno, Proc. IMechE C 212 (1998) 319; in MDR form in Popov & Hess,
  *Method of Dimensionality Reduction in Contact Mechanics and Friction*,
  Springer 2015.
- Flat punch: Boussinesq (1885); Sneddon, Int. J. Eng. Sci. 3 (1965) 47.
- Cattaneo, Rend. Accad. Naz. Lincei 27 (1938); Mindlin, J. Appl. Mech. 16
  (1949) 259; Mindlin & Deresiewicz, J. Appl. Mech. 20 (1953) 327: tangential
  loading, unloading (Masing rule) and dissipation of the sphere at constant
  normal force.

All quantities SI. E* and G* are the two-body effective moduli of
``mdr.materials``. u* = mu E* d / G* is the gross-slip displacement of the
sphere (displacement at which the stick zone vanishes).
"""
from __future__ import annotations

import numpy as np

# --------------------------------------------------------------------------- normal


def hertz(F, R, E_star):
    """Sphere (parabolic) under normal force F: contact radius a, approach d, peak pressure p0."""
    a = (3.0 * F * R / (4.0 * E_star)) ** (1.0 / 3.0)
    return {"a": a, "d": a**2 / R, "p0": 3.0 * F / (2.0 * np.pi * a**2)}


def hertz_pressure(r, F, R, E_star):
    """Hertz pressure p(r) = p0 sqrt(1 - r^2/a^2) (zero outside)."""
    h = hertz(F, R, E_star)
    r = np.asarray(r, dtype=float)
    return h["p0"] * np.sqrt(np.maximum(1.0 - (r / h["a"]) ** 2, 0.0))


def hertz_energy(F, R, E_star):
    """Elastic energy stored by the normal Hertz contact: U = (2/5) F d."""
    return 0.4 * F * hertz(F, R, E_star)["d"]


def truncated_approach(a, R, b):
    """Approach of a parabolic truncated sphere with contact radius a >= b: d = a sqrt(a^2-b^2)/R."""
    return a * np.sqrt(np.maximum(a**2 - b**2, 0.0)) / R


def truncated_force(a, R, b, E_star):
    """Normal force of a parabolic truncated sphere: F = 2E*/(3R) sqrt(a^2-b^2) (2a^2+b^2)."""
    return 2.0 * E_star / (3.0 * R) * np.sqrt(np.maximum(a**2 - b**2, 0.0)) * (2.0 * a**2 + b**2)


def truncated_energy(a, R, b, E_star):
    """Normal elastic energy U = E* int_0^a (d - g)^2 dx of the parabolic truncated sphere."""
    d = truncated_approach(a, R, b)
    s3 = np.maximum(a**2 - b**2, 0.0) ** 1.5
    poly = (a**5 - b**5) / 5.0 - b**2 * (a**3 - b**3) / 3.0
    return E_star * (d**2 * a - 2.0 * d * s3 / (3.0 * R) + poly / R**2)


def truncated_contact_radius(F, R, b, E_star):
    """Invert truncated_force for a (Newton on a monotone function, to roundoff)."""
    a = max(hertz(F, R, E_star)["a"], b * (1 + 1e-9))
    for _ in range(100):
        s = np.sqrt(a**2 - b**2)
        res = truncated_force(a, R, b, E_star) - F
        # dF/da = 2 E* a g'(a) with g'(a) = (2a^2 - b^2) / (R s)
        slope = 2.0 * E_star * a * (2.0 * a**2 - b**2) / (R * s)
        a_new = a - res / slope
        a_new = max(a_new, b + 0.5 * (a - b))
        if abs(a_new - a) <= 1e-15 * a:
            a = a_new
            break
        a = a_new
    return a


def flat_punch_approach(F, b, E_star):
    """Flat punch of radius b: d = F / (2 E* b)."""
    return F / (2.0 * E_star * b)


def flat_punch_pressure(r, F, b):
    """Boussinesq flat-punch pressure p(r) = F / (2 pi b sqrt(b^2 - r^2)) for r < b."""
    r = np.asarray(r, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(r < b, F / (2.0 * np.pi * b * np.sqrt(b**2 - r**2)), 0.0)


def flat_punch_energy(F, b, E_star):
    """Normal elastic energy of the flat punch: U = E* b d^2 = F d / 2."""
    return 0.5 * F * flat_punch_approach(F, b, E_star)


# ------------------------------------------------------------------- tangential (sphere)


def gross_slip_displacement(d, mu, E_star, G_star):
    """u* = mu E* d / G*: tangential displacement at which the stick zone of a sphere vanishes."""
    return mu * E_star * d / G_star


def cattaneo_mindlin_force(u, FN, mu, u_star):
    """Monotonic loading from rest at constant F_N: F_x = mu F_N [1 - (1 - u/u*)^(3/2)], |u| <= u*."""
    u = np.asarray(u, dtype=float)
    s = np.clip(np.abs(u) / u_star, 0.0, 1.0)
    return np.sign(u) * mu * FN * (1.0 - (1.0 - s) ** 1.5)


def cattaneo_mindlin_displacement(Fx, FN, mu, u_star):
    """Inverse of cattaneo_mindlin_force: u = u* [1 - (1 - F_x/(mu F_N))^(2/3)]."""
    q = np.clip(np.abs(np.asarray(Fx, dtype=float)) / (mu * FN), 0.0, 1.0)
    return np.sign(Fx) * u_star * (1.0 - (1.0 - q) ** (2.0 / 3.0))


def cattaneo_mindlin_stick_radius(Fx, FN, mu, a):
    """Stick radius c = a (1 - |F_x|/(mu F_N))^(1/3)."""
    q = np.clip(np.abs(np.asarray(Fx, dtype=float)) / (mu * FN), 0.0, 1.0)
    return a * (1.0 - q) ** (1.0 / 3.0)


def cattaneo_mindlin_traction(r, Fx, FN, mu, a):
    """Tangential traction of the sphere under monotonic loading F_x (Cattaneo-Mindlin):
    tau = (3 mu F_N / (2 pi a^3)) [sqrt(a^2 - r^2) - sqrt(c^2 - r^2) for r < c]."""
    r = np.asarray(r, dtype=float)
    c = cattaneo_mindlin_stick_radius(Fx, FN, mu, a)
    pre = 3.0 * mu * FN / (2.0 * np.pi * a**3) * np.sign(Fx)
    return pre * (np.sqrt(np.maximum(a**2 - r**2, 0.0)) - np.sqrt(np.maximum(c**2 - r**2, 0.0)))


def mindlin_deresiewicz_loop(u, u_A, FN, mu, u_star, branch):
    """Stationary loop at constant F_N (Masing rule): force on the branch through u.

    ``branch='unloading'`` runs from +u_A to -u_A:  F = F_A - 2 F_CM((u_A - u)/2),
    ``branch='loading'``   runs from -u_A to +u_A:  F = -F_A + 2 F_CM((u_A + u)/2),
    with F_CM the Cattaneo-Mindlin loading curve and F_A = F_CM(u_A).
    """
    FA = cattaneo_mindlin_force(u_A, FN, mu, u_star)
    u = np.asarray(u, dtype=float)
    if branch == "unloading":
        return FA - 2.0 * cattaneo_mindlin_force((u_A - u) / 2.0, FN, mu, u_star)
    if branch == "loading":
        return -FA + 2.0 * cattaneo_mindlin_force((u_A + u) / 2.0, FN, mu, u_star)
    raise ValueError("branch must be 'loading' or 'unloading'")


def mindlin_deresiewicz_dissipation(u_A, FN, mu, u_star):
    """Energy dissipated per stationary cycle of amplitude u_A at constant F_N (sphere).

    dW = 8 mu F_N [u_A - (2 u*/5)(1 - (1 - u_A/u*)^(5/2))] - 4 u_A F_A   (u_A <= u*),
    dW = 4 mu F_N u_A - (16/5) mu F_N u*                                  (u_A >= u*).
    """
    s = min(float(u_A) / u_star, 1.0)
    FA = mu * FN * (1.0 - (1.0 - s) ** 1.5)
    if u_A >= u_star:
        return 4.0 * mu * FN * u_A - 3.2 * mu * FN * u_star
    return 8.0 * mu * FN * (u_A - 0.4 * u_star * (1.0 - (1.0 - s) ** 2.5)) - 4.0 * u_A * FA


def mindlin_deresiewicz_dissipation_force(F_A, FN, mu, u_star):
    """Force-controlled form: dissipation per stationary cycle of tangential force amplitude F_A < mu F_N."""
    u_A = cattaneo_mindlin_displacement(F_A, FN, mu, u_star)
    return mindlin_deresiewicz_dissipation(float(u_A), FN, mu, u_star)


def gross_slip_dissipation(u_A, FN, mu, U, E_star, G_star):
    """Any profile in gross slip at constant F_N (MDR): dW = 4 mu F_N u_A - 8 mu^2 (E*/G*) U.

    U is the normal elastic energy E* int_0^a (d - g)^2 dx. (Each MDR spring i of
    normal force N_i and stiffness k_i = N_i G*/(E* w_i) traces a rectangle of
    height 2 mu N_i and width 2 (u_A - mu N_i / k_i); summing gives the formula.)
    """
    return 4.0 * mu * FN * u_A - 8.0 * mu**2 * (E_star / G_star) * U
