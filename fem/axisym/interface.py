"""Contact pairs between the indenter and the block surface (small sliding, built once).

Assumption (small sliding): the tangential relative motion in fretting (tens of
nm) is far below the element size, so each indenter surface node keeps facing
the same block surface point for the whole history. The pairing is therefore
built once, on the undeformed configuration:

- every P2 node of the indenter's ``contact`` boundary with radius r_i (and
  r_i <= ``r_max``; the flat punch pairs only r <= b) is a *slave point*;
- its partner is the block surface point at the same radius r_i, whose
  displacement is interpolated from the block's P2 surface nodes with the
  quadratic shape functions of the surface segment that contains r_i
  (row i of the sparse matrix ``N``: block surface node values -> pair values);
- the initial gap is the profile, ``gap0_i = f(r_i)`` (parabolic by default; the
  mesh carries the exact cap, whose deviation from the parabola is r^4/(8R^3),
  below 1e-5 of f in the contact zone);
- each pair carries the area it stands for, the lumped (row-sum) weight
  ``w_i = integral N_i 2 pi r ds`` over the indenter contact segments, which is
  2 pi r_i times the Simpson weight of the node. A pair force lam_i (N) is a
  nodal pressure p_i = lam_i / w_i. The node on the axis has w = 0 and is no
  pair (no area); its pressure is extrapolated (see ``fem.axisym.normal``).

For the tangential work (Fourier mode 1) the same ``N`` and ``w`` apply to the
r and theta components.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from fem.axisym.mode0 import facet_nodes, node_coords

TWO_PI = 2.0 * np.pi


@dataclass
class ContactInterface:
    """Pairs of the indenter contact nodes with the block surface.

    Attributes (n = number of pairs, mb = number of block contact nodes):
    ``r`` (n,) pair radii; ``gap0`` (n,) initial gaps f(r); ``w`` (n,) areas (m^2);
    ``ind_nodes`` (n,) indenter P2 node numbers; ``blk_nodes`` (mb,) block P2
    node numbers; ``N`` (n, mb) CSR interpolation; ``h`` contact element size.
    """

    r: np.ndarray
    gap0: np.ndarray
    w: np.ndarray
    ind_nodes: np.ndarray
    blk_nodes: np.ndarray
    N: sp.csr_matrix
    h: float

    @property
    def n(self) -> int:
        return self.r.size


def _segment_elements(mesh, name):
    """(3, ne) P2 nodes (vertex0, vertex1, mid) of a boundary, and node coordinates."""
    F = mesh.boundaries[name]
    return facet_nodes(mesh, F), node_coords(mesh)


def build_interface(amesh, profile, r_max: float | None = None) -> ContactInterface:
    """Pair the indenter contact nodes with the block contact surface.

    ``profile``: an ``mdr.profiles`` profile (its ``f`` gives the initial gap);
    ``r_max``: largest pair radius (default: the whole contact segment; for a
    flat punch b, where f jumps to infinity).
    """
    ind, blk = amesh.indenter, amesh.block
    el_i, xy_i = _segment_elements(ind, "contact")
    el_b, xy_b = _segment_elements(blk, "contact")
    if r_max is None:
        r_max = float(getattr(profile, "b", 0.0)) if getattr(profile, "edge_fixed", False) else np.inf
    tol = 1e-9 * amesh.params.r_contact
    # indenter elements inside r <= r_max
    r0, r1 = xy_i[0, el_i[0]], xy_i[0, el_i[1]]
    keep = np.maximum(r0, r1) <= r_max + tol
    el_i = el_i[:, keep]
    r0, r1 = r0[keep], r1[keep]
    L = np.hypot(xy_i[0, el_i[1]] - xy_i[0, el_i[0]], xy_i[1, el_i[1]] - xy_i[1, el_i[0]])
    nodes = np.unique(el_i)
    w = np.zeros(nodes.size)
    pos = np.searchsorted(nodes, el_i)
    np.add.at(w, pos[0], TWO_PI * L * r0 / 6.0)
    np.add.at(w, pos[1], TWO_PI * L * r1 / 6.0)
    np.add.at(w, pos[2], TWO_PI * L * (r0 + r1) / 3.0)
    pair = w > 0.0
    nodes, w = nodes[pair], w[pair]
    r = xy_i[0, nodes]
    order = np.argsort(r)
    nodes, w, r = nodes[order], w[order], r[order]

    # block surface interpolation at the pair radii
    blk_nodes = np.unique(el_b)
    br0, br1 = xy_b[0, el_b[0]], xy_b[0, el_b[1]]
    lo, hi = np.minimum(br0, br1), np.maximum(br0, br1)
    rows, cols, vals = [], [], []
    srt = np.argsort(lo)
    lo_s = lo[srt]
    for i, ri in enumerate(r):
        k = srt[max(np.searchsorted(lo_s, ri + tol, side="right") - 1, 0)]
        if not (lo[k] - tol <= ri <= hi[k] + tol):
            raise ValueError(f"pair radius {ri:.6g} m is outside the block contact segment")
        t = (ri - br0[k]) / (br1[k] - br0[k])
        sh = ((1 - t) * (1 - 2 * t), t * (2 * t - 1), 4 * t * (1 - t))
        for j in range(3):
            rows.append(i)
            cols.append(np.searchsorted(blk_nodes, el_b[j, k]))
            vals.append(sh[j])
    N = sp.csr_matrix((vals, (rows, cols)), shape=(r.size, blk_nodes.size))
    N.eliminate_zeros()
    with np.errstate(invalid="ignore"):
        gap0 = np.asarray(profile.f(r), dtype=float)
    if not np.all(np.isfinite(gap0)):
        raise ValueError("profile gap is infinite at a pair radius: lower r_max")
    return ContactInterface(r=r, gap0=gap0, w=w, ind_nodes=nodes, blk_nodes=blk_nodes, N=N,
                            h=float(amesh.params.h_min))
