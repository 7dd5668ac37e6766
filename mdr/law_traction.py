"""The tangential traction of the MDR contact law from its line loads (the MDR inverse transform).

``traction_from_line_loads`` is the body of ``mdr.law.MDRContact.traction``: the traction
tau(r) along x of one scene, from the tangential line load q_x at the cell midpoints
(Popov & Hess, *Method of Dimensionality Reduction in Contact Mechanics and Friction*,
Springer 2015: tau(r) = -(1/pi) int_r^a q_x'(x)/sqrt(x^2-r^2) dx + q_x(a)/(pi sqrt(a^2 - r^2))).

Assumptions: one scene (no batch), q_x piecewise linear between the cell midpoints, constant
towards the centre and over the cells of a flat face of radius b (its springs are identical),
extrapolated to the contact radius a and limited there by Coulomb's |q_x| <= mu E* (d - g(a));
the segment integrals are exact (arccosh).
"""
from __future__ import annotations

import numpy as np


def traction_from_line_loads(grid, profile, mu, E_star, b_flat, x, qx, a, d, r):
    """tau(r) (along x) from the line loads x, q_x (``MDRContact.line_loads``) at contact radius
    a and approach d of a single scene; ``b_flat`` the flat face's radius (None: none)."""
    a = float(a)
    r = np.atleast_1d(np.asarray(r, dtype=float))
    inside = grid.lo < a
    xs, qs = x[inside], qx[inside]
    if xs.size == 0 or a <= 0:
        return np.zeros_like(r)
    full = grid.edges[1:][inside] <= a
    xf, qf = xs[full], qs[full]
    # the springs of a flat face (g = 0 for x < b) are identical: q_x is constant over each
    # such cell, so it holds up to the cell's edges instead of meeting the next cell halfway
    b_flat = 0.0 if b_flat is None else float(b_flat)
    if b_flat > 0 and xf.size:
        lo, hi = grid.lo[inside][full], grid.edges[1:][inside][full]
        flat = hi <= b_flat * (1 + 1e-12)
        xf = np.concatenate([np.ravel(np.column_stack([lo[flat], hi[flat]])), xf[~flat]])
        qf = np.concatenate([np.repeat(qf[flat], 2), qf[~flat]])
        xf, keep = np.unique(xf, return_index=True)
        qf = qf[keep]
        inner = (xf > 0) & (xf < a)  # q is constant towards the centre; a is added below
        xf, qf = xf[inner], qf[inner]
    if xf.size >= 2:
        q_a = qf[-1] + (qf[-1] - qf[-2]) * (a - xf[-1]) / (xf[-1] - xf[-2])
    else:
        q_a = qs[-1]
    # Coulomb at the edge spring: |q_x(a)| <= mu E* (d - g(a)), zero where the profile meets
    # the surface smoothly (the extrapolation overshoots where q_x drops steeply in slip)
    q_lim = float(np.asarray(mu)) * E_star * max(float(d) - float(profile.g(a)), 0.0)
    q_a = float(np.clip(q_a, -q_lim, q_lim))
    nodes = np.concatenate([xf, [a]])
    vals = np.concatenate([qf, [q_a]])
    slopes = np.diff(vals) / np.diff(nodes)
    tau = np.zeros_like(r)
    for i, ri in enumerate(r):
        if ri >= a:
            continue
        x0 = np.maximum(nodes[:-1], ri)
        x1 = np.maximum(nodes[1:], ri)
        L = lambda z: np.log(z + np.sqrt(np.maximum(z**2 - ri**2, 0.0)))
        tau[i] = (-np.sum(slopes * (L(x1) - L(x0))) + q_a / np.sqrt(a**2 - ri**2)) / np.pi
    return tau
