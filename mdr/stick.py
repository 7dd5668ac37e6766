"""The stick radius: one definition and one estimator for every contact law.

Definition. Over a window of instants (one step, or the last stationary cycle),
the stick radius ``c`` is the radius of the central zone in which no point slips
at any instant of the window. Points out of contact at some instant do not belong
to it, so ``c`` never exceeds the smallest contact radius of the window; ``c = 0``
when the centre slips (gross slip). For one step this is the instantaneous stick
radius; for a stationary cycle, the permanent stick core, i.e. the smallest
instantaneous stick radius of the cycle (the slip zone of a half cycle grows
monotonically in partial slip, Mindlin & Deresiewicz 1953, J. Appl. Mech.).

Estimator. A law samples its contact at radial nodes ``r`` (MDR: the cells'
midpoints, where the 1D coordinate of a spring equals the 3D radius of the stick
edge; FE: the contact pairs) and reports, per instant and node, whether the node
slips (or is out of contact) and its *slack*, the distance to the slip limit
(> 0 in stick); a node at its slip limit (within ``AT_LIMIT``) slips: the
classical stick zone |tau| < mu p (Cattaneo 1938; Mindlin 1949, J. Appl. Mech.).
The first node ``j`` that slips at some instant brackets the edge
in ``[r[j-1], r[j]]``. Inside the bracket, the edge is the zero of the slack of the
last two sticking nodes, extrapolated outwards, or of the slack interpolated between the
last sticking and the first slipping node, whichever is smaller, at the instant that puts
it innermost. Taking the smaller zero (not one branch by a test on the slacks) keeps the
estimate continuous in its inputs: where two slacks tie, the extrapolated zero runs off to
infinity and the interpolated one takes over without a jump, so a perturbation at
round-off level moves the stick radius at round-off level, on any CPU. Near a stick edge the slack falls as ``(c - r)**onset``: ``onset = 1``
for the MDR springs (slack = mu E* (d - g(x)) / G* - |v|, smooth in x),
``onset = 1/2`` for a 3D traction (mu p - |tau| ~ sqrt(c - r), as in Cattaneo's
solution), so ``slack**(1/onset)`` is extrapolated linearly: second-order accurate
where the slack is smooth. Where it does not fall towards the edge (a flat face:
equal slack), the zero is interpolated towards the first slipping node.
"""
from __future__ import annotations

import math

import numpy as np

#: a node whose slack is below this fraction of its slip limit is at the limit (slips): a
#: stationary cycle brings the points of its slip annulus back to the limit exactly, which
#: round-off (and a solver's tolerance) leaves a hair above or below
AT_LIMIT = 1e-6


def at_limit(slack, limit):
    """Nodes at the slip limit: slack <= AT_LIMIT * limit (elementwise)."""
    return np.asarray(slack) <= AT_LIMIT * np.asarray(limit)


def stick_radius(r, slack, slipping, a, onset=1.0):
    """Stick radius over a window (see the module docstring).

    r : (n,) node radii, increasing (m).
    slack : (..., T, n) distance to the slip limit of each node at each of the T
        instants of the window (> 0 sticking; any unit, one per law).
    slipping : (..., T, n) bool, node slips or is out of contact at that instant.
    a : (..., T) contact radius at each instant (m).
    onset : exponent of the slack near the edge, slack ~ (c - r)**onset.
    Returns c of shape (...). Assumes the stick zone is a central disk.
    """
    r = np.asarray(r, dtype=float)
    slack = np.asarray(slack, dtype=float)
    slipping = np.asarray(slipping, dtype=bool)
    a = np.asarray(a, dtype=float)
    n = slack.shape[-1]
    ever = np.any(slipping, axis=-2)                       # (..., n)
    j = np.argmax(ever, axis=-1)                           # first node that slips
    rb = np.broadcast_to(r, ever.shape)

    def node(arr, idx):                                     # arr (..., n) -> (...)
        return np.take_along_axis(arr, np.clip(idx, 0, n - 1)[..., None], axis=-1)[..., 0]

    def series(arr, idx):                                   # arr (..., T, n) -> (..., T)
        ii = np.broadcast_to(np.clip(idx, 0, n - 1)[..., None, None], arr.shape[:-1] + (1,))
        return np.take_along_axis(arr, ii, axis=-1)[..., 0]

    p = 1.0 / float(onset)
    w = lambda s: np.sign(s) * np.abs(s) ** p               # noqa: E731  linear in r near the edge
    w2, w1, w0 = w(series(slack, j - 2)), w(series(slack, j - 1)), w(series(slack, j))
    r2, r1, r0 = (node(rb, j - k)[..., None] for k in (2, 1, 0))
    with np.errstate(divide="ignore", invalid="ignore"):
        extrap = r1 + w1 * (r1 - r2) / (w2 - w1)
        interp = r1 + w1 * (r0 - r1) / (w1 - w0)
    ext_ok = (j >= 2)[..., None] & (w2 > w1) & (w1 > 0) & np.isfinite(extrap)
    int_ok = (w1 > 0) & (w0 < w1) & np.isfinite(interp)
    # the smaller of the two zeros: continuous where either branch opens (at a tie w2 = w1 the
    # extrapolation runs off to infinity and the interpolation takes over smoothly)
    root = np.minimum(np.where(ext_ok, extrap, np.inf), np.where(int_ok, interp, np.inf))
    root = np.where(np.isfinite(root), root, r0)
    root = np.where(series(slipping, j), root, np.inf)      # only instants at which node j slips
    c = np.min(np.minimum(root, a), axis=-1)
    c = np.clip(c, node(rb, j - 1), node(rb, j))
    c = np.where(j == 0, 0.0, c)
    c = np.where(np.any(ever, axis=-1), c, np.min(a, axis=-1))
    return np.minimum(c, np.min(a, axis=-1))


#: a batch of at most this many scenes at one instant takes the scalar path of ``per_step``, scene by scene
SCALAR_BATCH = 16


def per_step(r, slack, slipping, a, onset=1.0):
    """Instantaneous stick radius of every step: arrays (..., T, n) and (..., T) -> (..., T).

    One instant of one scene, or of a small batch (up to ``SCALAR_BATCH`` scenes, arrays
    batch + (n,) and batch, e.g. the bedding spheres of the apparatus), goes through the same
    rule in scalars (equal to round-off), which is much cheaper than the vectorised rule there."""
    if np.ndim(slack) == 1 and np.ndim(r) == 1:  # one instant of one scene: the same rule, in scalars
        return _one_instant(r, slack, slipping, float(a), 1.0 / float(onset))
    if np.ndim(slack) == np.ndim(r) == np.ndim(a) + 1 and 0 < np.size(a) <= SCALAR_BATCH:
        p = 1.0 / float(onset)
        a = np.asarray(a, dtype=float)
        rb = np.broadcast_to(r, np.shape(slack))
        out = np.empty(a.shape)
        for i in np.ndindex(a.shape):
            out[i] = _one_instant(rb[i], slack[i], slipping[i], float(a[i]), p)
        return out
    return stick_radius(r, np.expand_dims(slack, -2), np.expand_dims(slipping, -2), np.asarray(a)[..., None], onset)


def _one_instant(r, slack, slipping, a, p):
    """``stick_radius`` for a single instant and scene (the FE and apparatus step path)."""
    idx = np.flatnonzero(slipping)
    if idx.size == 0:
        return a
    j = int(idx[0])
    if j == 0:
        return 0.0
    w = lambda s: math.copysign(abs(s) ** p, s)  # noqa: E731
    w1, w0 = w(float(slack[j - 1])), w(float(slack[j]))
    r1, r0 = float(r[j - 1]), float(r[j])
    root = math.inf
    if j >= 2 and w(float(slack[j - 2])) > w1 > 0:
        w2, r2 = w(float(slack[j - 2])), float(r[j - 2])
        root = r1 + w1 * (r1 - r2) / (w2 - w1)
    if w1 > 0 and w0 < w1:
        root = min(root, r1 + w1 * (r0 - r1) / (w1 - w0))
    if not math.isfinite(root):
        root = r0
    return min(max(min(root, a), r1), r0, a)
