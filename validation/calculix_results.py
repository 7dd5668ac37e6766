"""Reading the CalculiX witness's output (``validation.calculix``): the ``.dat`` file of printed
values (``parse_dat``), the ASCII ``.frd`` result blocks (``parse_frd``), and the Hertz fit of a
nodal pressure both codes' pressures go through (``fit_hertz``).

Assumptions: the files are those of the deck of ``validation.calculix_deck.write_inp`` (its node
sets and print requests, CalculiX 2.20's text layout); the last increment is the converged end of
the force step. ``fit_hertz`` fits a line p^2 = c0 + c1 r^2 through the nodal pressures with
``FIT_WINDOW`` (0.25 a <= r <= 0.7 a) (Hertz: p^2 = p0^2 (1 - r^2/a^2), so p0 = sqrt(c0),
a = sqrt(-c0/c1); Hertz, J. reine angew. Math. 92 (1882) 156). The window keeps away from the axis,
where CalculiX's surface values are wrong (the first nodes read 0 or -0.6 p0 instead of p0), and
from the edge, where they oscillate.
"""
from __future__ import annotations

import math
import re

import numpy as np

from common.errors import ConvergenceError

#: r / a window of the p^2-linear-in-r^2 fit
FIT_WINDOW = (0.25, 0.7)


# --------------------------------------------------------------------------- output


def parse_dat(text: str) -> dict:
    """The last increment's values of the ``.dat`` file written by the deck of :func:`write_inp`:
    ``u_probe`` {node: u_z}, ``u_load`` (u_z of the plate), ``rf_bottom`` (total u_z reaction of
    the block bottom) and ``contact_normal_force`` (CalculiX's printed values, i.e. per 2-degree
    sector)."""
    out = {}
    probe, load, rf, cfn = None, None, None, None
    lines = text.splitlines()
    for i, ln in enumerate(lines):
        head = ln.strip()
        if not head or head[0].isdigit() or head[0] in "-+":
            continue
        data = []
        for nxt in lines[i + 1:]:
            if nxt.strip():
                if not re.match(r"^\s*[-+]?\d", nxt):
                    break
                data.append(nxt.split())
            elif data:
                break
        if head.startswith("displacements") and "NPROBE" in head:
            probe = {int(f[0]): float(f[2]) for f in data}
        elif head.startswith("displacements") and "NLOAD" in head:
            load = float(data[0][2])
        elif head.startswith("total force") and "NBOTTOM" in head:
            rf = float(data[0][1])
        elif head.startswith("area,") and "normal force" in head:
            cfn = float(data[0][1])
    if probe is None or load is None or rf is None:
        raise ConvergenceError("ccx wrote no displacement / reaction output (did the step converge?)")
    out.update(u_probe=probe, u_load=load, rf_bottom=rf, contact_normal_force=cfn)
    return out


def parse_frd(text: str, block: str) -> dict:
    """{node: [values]} of the last result block named ``block`` (``STRESS``, ``CONTACT``, ``DISP``)
    of an ASCII ``.frd`` file (fixed format: node in columns 4-13, values 12 characters each)."""
    start = text.rfind(f" -4  {block}")
    if start < 0:
        raise ConvergenceError(f"ccx wrote no {block} block to the .frd file")
    out = {}
    for ln in text[start:].splitlines()[1:]:
        if ln.startswith(" -3"):
            break
        if ln.startswith(" -1"):
            n = (len(ln.rstrip()) - 13) // 12
            out[int(ln[3:13])] = [float(ln[13 + 12 * k:25 + 12 * k]) for k in range(n)]
    return out


def fit_hertz(r, p, a_guess, window=FIT_WINDOW, iterations=4) -> dict:
    """p0 and contact radius a of a line p^2 = c0 + c1 r^2 fitted (least squares) to the nodal
    pressures with window[0] a <= r <= window[1] a; a starts at ``a_guess`` and is refined from the
    fit until the node set repeats. Returns ``p0``, ``a``, ``nodes`` (used) and ``rms`` (relative
    rms residual of p^2)."""
    r = np.asarray(r, dtype=float)
    p = np.asarray(p, dtype=float)
    a = float(a_guess)
    used = None
    for _ in range(iterations):
        sel = (r >= window[0] * a) & (r <= window[1] * a)
        if sel.sum() < 3:
            raise ConvergenceError(f"too few pressure nodes ({int(sel.sum())}) in {window[0]:g}..{window[1]:g} a "
                                   "for the p^2 fit: refine the mesh")
        c1, c0 = np.polyfit(r[sel] ** 2, p[sel] ** 2, 1)
        if c0 <= 0 or c1 >= 0:
            raise ConvergenceError(f"p^2 = {c0:.4g} + {c1:.4g} r^2 is no Hertz-like profile")
        a = math.sqrt(-c0 / c1)
        key = tuple(np.flatnonzero(sel))
        if key == used:
            break
        used = key
    res = p[sel] ** 2 - (c0 + c1 * r[sel] ** 2)
    return {"p0": math.sqrt(c0), "a": a, "nodes": int(sel.sum()), "rms": float(np.sqrt(np.mean(res**2)) / c0)}


def _ring_forces(r, p):
    """Ring forces (N) of nodal pressures p at radii r (trapezoidal rule of 2 pi r p dr)."""
    r = np.asarray(r, dtype=float)
    dr = np.gradient(r) if r.size > 1 else np.zeros(1)
    w = 2.0 * np.pi * r * dr
    w[0] = 2.0 * np.pi * r[0] * 0.5 * (r[1] - r[0]) if r.size > 1 else 0.0
    return p * w
