"""The budget's cell of the brass plates' reading (``validation.budget``, column *plates*): the slip index
over the readings of the plates (``studies.plates.PLATE_READINGS``: how the paper's brass plates and
bedding may act) that the measured loops admit (``consistency``; a rig that states no loops or plates: every
reading) against the project's reference reading, itself one of them (so the range holds 0).
"""
from __future__ import annotations

import numpy as np

from .budget_readings import range_cell
from .paper_points import PAPER, Point, Setup

#: the readings of the brass plates the budget spans: all of ``studies.plates.PLATE_READINGS``; the paper's
#: loops then admit or exclude each (``plates_consistency``)
REFERENCE_READING = ("axial", 5e-3)


def readings() -> list:
    """The readings of the brass plates, the project's reference first (each once)."""
    from studies.plates import PLATE_READINGS

    return [REFERENCE_READING] + [r for r in PLATE_READINGS if tuple(r) != REFERENCE_READING]


def reading_name(r) -> str:
    m, rb = r
    return f"{m}{f' R_bed {rb * 1e3:g} mm' if m in ('tilt', 'parallel') else ''}"


def consistency(log=None, loops=None, setup: Setup = PAPER) -> list:
    """The measured loops (``validation.consistency.check``; default the paper's, Figs. 4-7) against every
    reading of the brass plates, the smooth indenters of ``setup``: [{reading, checks: {loop: check},
    admitted}]."""
    from mdr.profiles import TruncatedSphere

    from .consistency import check, paper_loops

    loops = paper_loops() if loops is None else loops
    (log or (lambda m: None))("budget: the measured loops against the readings of the brass plates")
    rows = []
    for m, rb in readings():
        kw = {**setup.app_kw, "plate_model": m, "R_bed": rb}
        checks = {lp.key: check(TruncatedSphere(setup.R, lp.point.b), lp, kw, setup.materials) for lp in loops}
        rows.append({"reading": reading_name((m, rb)), "checks": checks,
                     "admitted": all(c["consistent"] for c in checks.values())})
    return rows


def cell(p: Point, admitted: set | None, setup: Setup = PAPER, what: str = "plates") -> dict:
    """The slip index over the readings of the brass plates the measured loops admit (None, a rig of one's
    own without loops: every reading) against this project's reference reading (axial, R_bed 5 mm;
    itself a reading, so the range holds 0): MDR in the setup's apparatus, all readings in one batch;
    each reading's error the change from 100 to 400 spring cells."""
    from mdr.profiles import TruncatedSphere
    from studies.paper import RES, _slip_index

    rs = readings()
    k = len(rs)
    kw = {**setup.app_kw, "plate_model": np.array([m for m, _ in rs]), "R_bed": np.array([rb for _, rb in rs])}

    def each(n):
        prof = TruncatedSphere(np.full(k, setup.R), np.full(k, p.b))
        si, _ = _slip_index(prof, np.full(k, p.kx), mu1=p.mu1, mu2=p.mu2, F0=p.F0, dF=p.dF, ua=p.ua,
                            res={**RES, "n": n}, app_kw=kw, materials=setup.materials)
        return np.asarray(si, dtype=float)

    coarse, fine = each(100), each(400)
    per = {reading_name(r): {"effect": float(fine[j] - fine[0]), "slip_index": float(fine[j]),
                             "error": float(abs(fine[j] - fine[0] - coarse[j] + coarse[0])), "surfaces_sd": 0.0,
                             "sem": 0.0, "form_curvature": 0.0} for j, r in enumerate(rs)}
    return range_cell(per, admitted, "MDR apparatus", what)


