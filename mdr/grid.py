"""Spring grid of the MDR contact law.

The one-dimensional MDR model is a row of springs on x in [-a, a]; by symmetry
we keep x >= 0 and double every force. The springs are grouped in *cells*
[x_j, x_{j+1}]. A cell carries one tangential displacement, but its normal
force is the exact integral of E* (d - g(x)) over the part of the cell in
contact, so the normal force, the contact radius and the gross-slip force
mu F_N are exact on any grid; the grid only resolves the stick-slip boundary
inside the contact.

Nodes are placed at every kink of g (the flat-face edge r = b), at the
smallest contact radius of the history (if given) and the grid extends to the
largest contact radius a_max. Springs in a flat zone (g = 0 for x < b) are
identical in every load history, so that zone gets two cells and all other
cells go to the annulus b < x < a_max, where stick and slip alternate.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from common.errors import InputError, positive, positive_int
from .profiles import FlatPunch, Profile

#: default number of cells; gives < 1e-4 relative error in the dissipation (see
#: tests/test_mdr_tangential.py, the README table, and benchmarks/bench_mdr.py)
DEFAULT_CELLS = 400


@dataclass(frozen=True)
class SpringGrid:
    """Cell edges ``edges`` (shape batch + (n + 1,)) and derived cell data."""

    edges: np.ndarray
    lo: np.ndarray
    width: np.ndarray
    mid: np.ndarray
    int_g: np.ndarray  # integral of g over each (full) cell

    @property
    def n(self) -> int:
        return self.width.shape[-1]

    @property
    def x_max(self):
        return self.edges[..., -1]


def _edges_1d(x_max: float, kinks, n: int, edge_band, refine: float, flat_below=None) -> np.ndarray:
    """Edges on [0, x_max] with nodes at kinks; uniform in between, optionally
    compressed geometrically towards each kink and the contact-edge band."""
    pts = sorted({0.0, x_max, *[k for k in kinks if 0.0 < k < x_max]})
    if edge_band is not None:
        lo_b, hi_b = edge_band
        pts = sorted(set(pts) | {v for v in (lo_b, hi_b) if 0.0 < v < x_max})
    lengths = np.diff(pts)
    weight = lengths.copy()
    if flat_below is not None:
        # springs in the flat zone g = 0 (x < b) are identical in every history: two cells suffice
        weight[np.asarray(pts[1:]) <= flat_below * (1 + 1e-12)] = 0.0
    # allocate cells proportionally to the weighted segment length, at least 2 per segment
    counts = np.maximum(2, np.round((n - 2 * np.sum(weight == 0)) * weight / max(weight.sum(), 1e-300)).astype(int))
    while counts.sum() > n and counts.max() > 2:
        counts[np.argmax(counts)] -= 1
    while counts.sum() < n:
        counts[np.argmax(weight / counts)] += 1
    if np.sum(weight) == 0:
        raise InputError('spring grid has no cells outside the flat zone')
    out = [np.array([0.0])]
    for (x0, x1), m in zip(zip(pts[:-1], pts[1:]), counts):
        s = np.linspace(0.0, 1.0, m + 1)[1:]
        if refine > 0 and x0 in kinks:
            # cluster towards the kink at the segment start: x = x0 + L s^(1+refine)
            s = s ** (1.0 + refine)
        out.append(x0 + (x1 - x0) * s)
    e = np.concatenate(out)
    e[-1] = x_max
    return e


def make_grid(profile: Profile, a_max, n: int = DEFAULT_CELLS, margin: float = 0.02,
              a_min=None, refine: float = 0.0) -> SpringGrid:
    """Build the spring grid for contact radii up to ``a_max`` (scalar or batch array).

    ``margin`` extends the grid beyond a_max (relative), ``a_min`` (optional)
    adds a node at the smallest contact radius of the history so the band
    [a_min, a_max] swept by the contact edge gets its own cells, ``refine`` > 0
    clusters cells towards kinks. For a flat punch the grid ends at b exactly.
    """
    n = positive_int("n (spring cells)", n, minimum=8)
    a_max = positive("a_max", a_max)
    if not 0 <= margin < 1:
        raise InputError(f"margin must be in [0, 1), got {margin!r}")
    batch = np.shape(a_max)
    a_arr = np.broadcast_to(np.asarray(a_max, dtype=float), batch)
    amin_arr = None if a_min is None else np.broadcast_to(np.asarray(a_min, dtype=float), batch)
    kinks = [np.broadcast_to(np.asarray(k, dtype=float), batch) for k in profile.kinks]
    flat = isinstance(profile, FlatPunch)
    edges = np.empty(batch + (n + 1,))
    built = {}  # scenes of equal grid parameters share their edges (a batch of identical bedding spheres)
    for idx in np.ndindex(*batch) if batch else [()]:
        am = float(a_arr[idx])
        x_max = float(np.asarray(profile.b)[idx] if np.ndim(profile.b) else profile.b) if flat else am * (1.0 + margin)
        ks = [float(k[idx]) for k in kinks]
        band = None
        if amin_arr is not None and not flat:
            band = (float(amin_arr[idx]), am)
        flat_below = None
        if not flat and ks:
            kmax = max(ks)
            if float(np.asarray(profile.g(np.full(batch, min(kmax, x_max))))[idx]) == 0.0:
                flat_below = min(kmax, x_max)
        key = (x_max, tuple(ks), band, flat_below)
        if key not in built:
            built[key] = _edges_1d(x_max, ks, n, band, refine, flat_below)
        edges[idx] = built[key]
    lo = edges[..., :-1]
    width = np.diff(edges, axis=-1)
    int_g = profile.cell_integral(lo, edges[..., 1:]) if not flat else np.zeros_like(lo)
    return SpringGrid(edges=edges, lo=lo, width=width, mid=lo + 0.5 * width, int_g=int_g)
