"""One step of one scene of the MDR law, compiled (numba): the pieces the compiled time loops
(``mdr.kernels_loops``) are built from.

Each function repeats, over the n spring cells of one scene, what the step API of ``mdr.law``
computes with numpy: the number of fully covered cells, the normal update of a step, the
tangential force and its slope, the commit of a tangential increment with the instantaneous
stick radius, and one step of the safeguarded Newton iteration of ``mdr.solve``. Elementwise
operations are in numpy's order; only the sums (``_jit_sum``) may be reassociated, a round-off.

Assumptions: arrays of one scene, float64 (bool for the slip flags), the cells of ``mdr.grid``
in increasing radius; the caller owns every buffer and these functions write into it. Without
numba the decorators are the identity (the functions stay Python; the law then runs through
its step API, ``mdr.kernels.enabled``). Disk cache (``cache=True``): numba checks only the file
of each compiled function, not the files of the functions it calls, so a cached loop of
``mdr.kernels_loops`` older than this file (or ``mdr.solve``, whose
constants are compiled in) is removed when this module is imported (``drop_stale_caches``) and
compiles afresh.
"""
from __future__ import annotations

import math

import numpy as np

try:  # optional dependency
    import numba
except ImportError:  # pragma: no cover - exercised by the fallback test through ENABLED
    numba = None

#: the files whose code the compiled functions of ``DEPENDENTS`` take in at compile time
SOURCES = ("kernels_step.py", "solve.py")
#: the modules whose compiled functions call into ``SOURCES``
DEPENDENTS = ("kernels_loops",)


def drop_stale_caches(directory) -> list:
    """Remove the numba cache files (``__pycache__/<module>.*.nbi`` and ``.nbc``) of ``DEPENDENTS`` in
    ``directory`` that are older than any of ``SOURCES`` there: numba would load them although the
    code they were built from changed. Returns the removed paths; a file that cannot be removed is
    left (numba then reads it as before)."""
    from pathlib import Path

    directory = Path(directory)
    try:
        newest = max((directory / f).stat().st_mtime for f in SOURCES)
    except OSError:
        return []
    removed = []
    for mod in DEPENDENTS:
        for f in (directory / "__pycache__").glob(f"{mod}.*.nb[ic]"):
            try:
                if f.stat().st_mtime < newest:
                    f.unlink()
                    removed.append(f)
            except OSError:
                pass
    return removed


drop_stale_caches(__import__("pathlib").Path(__file__).resolve().parent)

# status codes of a scene (the loop stops that scene at the first failing step)
OK, BEYOND_FRICTION, NO_CONVERGENCE, LIFT_OFF, BEYOND_GRID = 0, 1, 2, 3, 4

if numba is not None:
    _jit = numba.njit(cache=True, error_model="numpy", nogil=True)
    # sums in any order (vectorised): only for sums, whose order is a round-off
    _jit_sum = numba.njit(cache=True, error_model="numpy", nogil=True, fastmath={"reassoc", "nsz"})
else:  # pragma: no cover
    def _jit(f):
        return f
    _jit_sum = _jit


# ------------------------------------------------------------------ one step, one scene
@_jit
def _count_full(a, lo, width):
    """Number of cells fully in contact at contact radius a (a prefix of the cells:
    a - lo_j >= width_j, the test of ``MDRContact.normal_phase``)."""
    i0, i1 = 0, lo.shape[0]
    while i0 < i1:
        m = (i0 + i1) // 2
        if a - lo[m] >= width[m]:
            i0 = m + 1
        else:
            i1 = m
    return i0


@_jit
def full_cells(a, lo, width, out):
    """``_count_full`` for every scene s and step t: a (S, T), lo/width (S, n) -> out (S, T)."""
    for s in range(a.shape[0]):
        for t in range(a.shape[1]):
            out[s, t] = _count_full(a[s, t], lo[s], width[s])


@_jit_sum
def _sum(x):
    """Sum of the elements (in any order: vectorised; the order is the only difference
    from numpy's pairwise sum, a round-off)."""
    s = 0.0
    for j in range(x.shape[0]):
        s += x[j]
    return s


@_jit
def _phase(dp, a, kk, part, lo, width, int_g, E, G, mu, ell_old, v, ell, N, vmax, carried, v1):
    """Normal update of one step (``normal_phase``, ``_carry`` and the clip of ``prepare``):
    fills ell, N, vmax, carried, v1 (n,); returns F_N. kk: the partly covered cell
    (-1: none), part: its integral of g. Elementwise, as numpy computes it."""
    for j in range(lo.shape[0]):
        e = min(max(a - lo[j], 0.0), width[j])
        ig = int_g[j] if e >= width[j] else 0.0
        ig = part if j == kk else ig
        Nj = E * max(dp * e - ig, 0.0)
        pos = e > 0.0
        vm = mu * Nj / (G * e) if pos else 0.0
        c = v[j] * (min(1.0, ell_old[j] / e) if pos else 0.0)
        ell[j] = e
        N[j] = Nj
        vmax[j] = vm
        carried[j] = c
        v1[j] = min(max(c, -vm), vm)
    return 2.0 * _sum(N)


@_jit_sum
def _force(v1, vmax, ell, G2, x):
    """Tangential force sum 2 G* ell clip(v1 + x) and its slope in x (``Trial.force``; summed
    in any order)."""
    f = 0.0
    s = 0.0
    for j in range(v1.shape[0]):
        k = G2 * ell[j]
        t = v1[j] + x
        m = vmax[j]
        f += k * min(max(t, -m), m)
        s += k if abs(t) < m else 0.0
    return f, s


@_jit
def _stick_one(r, slack, j, a, p):
    """Instantaneous stick radius (``mdr.stick._one_instant``; j: first slipping node, -1: none)."""
    if j < 0:
        return a
    if j == 0:
        return 0.0
    if p == 1.0:
        w1, w0 = slack[j - 1], slack[j]
    else:
        w1 = math.copysign(abs(slack[j - 1]) ** p, slack[j - 1])
        w0 = math.copysign(abs(slack[j]) ** p, slack[j])
    r1, r0 = r[j - 1], r[j]
    root = np.inf
    w2 = -np.inf
    if j >= 2:
        w2 = slack[j - 2] if p == 1.0 else math.copysign(abs(slack[j - 2]) ** p, slack[j - 2])
    if j >= 2 and w2 > w1 and w1 > 0.0:
        root = r1 + w1 * (r1 - r[j - 2]) / (w2 - w1)
    if w1 > 0.0 and w0 < w1:
        root = min(root, r1 + w1 * (r0 - r1) / (w1 - w0))
    if not math.isfinite(root):
        root = r0
    return min(max(min(root, a), r1), r0, a)


@_jit
def _commit(du, v1, vmax, ell, carried, nodes, a, p, at_lim, v, slack, slip, tmp1, tmp2):
    """Tangential update of one step by du (``Trial.commit``): writes the new v, the slack
    and slip flags; returns (sum ell v, sum ell vmax slip, stick radius). tmp1, tmp2: scratch."""
    n = v1.shape[0]
    for j in range(n):
        vm = vmax[j]
        tr = v1[j] + du
        v2 = min(max(tr, -vm), vm)
        tmp1[j] = ell[j] * v2
        tmp2[j] = ell[j] * vm * (abs(carried[j] - v1[j]) + abs(tr - v2))
        sk = vm - abs(tr)
        slack[j] = sk
        slip[j] = sk <= at_lim * vm or abs(carried[j]) > vm or ell[j] <= 0.0
        v[j] = v2
    first = -1
    for j in range(n):
        if slip[j]:
            first = j
            break
    return _sum(tmp1), _sum(tmp2), _stick_one(nodes, slack, first, a, p)


@_jit
def _newton_step(x, r, slope, lo, hi):
    """One step of the safeguarded Newton iteration of ``mdr.solve.solve_increasing`` (the one
    home of its update in the compiled loops) for a nondecreasing function whose residual at x
    is r with slope ``slope``, on the bracket [lo, hi]: the bracket shrinks to the root's side
    (r < 0: lo = x; r > 0: hi = x), then the Newton step, or the bisection of the bracket when
    that step is not finite or leaves the open bracket. Returns (x, lo, hi). The callers keep
    their own loops around it: each residual reads its own arrays (one law's cells; the law,
    the compliances and the bedding spheres; a batch of profiles) and stops on its own test,
    and one shared loop would take the residual as a closure over those arrays, which numba
    does not compile as an argument."""
    if r < 0:
        lo = x
    if r > 0:
        hi = x
    xn = x - r / slope
    if not np.isfinite(xn) or xn <= lo or xn >= hi:
        xn = 0.5 * (lo + hi)
    return xn, lo, hi
