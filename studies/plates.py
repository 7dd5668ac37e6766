"""Every reading of the apparatus's brass plates (``mdr.apparatus``, A3) against the paper's points
(Willert, Machines 11 (2023) 484, Figs. 4-9): ``plate_readings`` (one row per reading, a check
per paper point and a score) and ``plates_markdown`` (the rows as a table).

Assumptions: the studies of ``studies.paper`` (same load, indenter and resolution), each run as
one batch over all readings; a reading is a plate model with the bedding radius R_bed, the one
quantity of the apparatus the paper leaves open, optionally with a compliance c carrying F_x
alone in series with the axis (``FX_COMPLIANCE_ROWS``: not readings of Table 1; they show what
the readings lack).
"""
from __future__ import annotations

import numpy as np

from mdr.apparatus import Apparatus
from mdr.profiles import FlatPunch, TruncatedSphere

from .paper import LOOP_CASES, LOOP_RES, R_IND, RES, TABLE1_KX, TABLE2, _slip_index, loops

# ------------------------------------------------------------------ plate readings
# Each reading of the brass plates (mdr.apparatus, A3) with the bedding radius R_bed,
# the one quantity of the apparatus the paper leaves open (1-10 mm; it sets the
# rocking stiffness of the tilting readings). The other readings do not depend on
# R_bed beyond 1e-4 in delta (sensitivity study), so they run at 5 mm.
PLATE_READINGS = (("axial", 5e-3), ("bending", 5e-3), ("inplane", 5e-3), ("rigid", 5e-3),
                  ("tilt", 1e-3), ("tilt", 5e-3), ("tilt", 10e-3),
                  ("parallel", 1e-3), ("parallel", 5e-3), ("parallel", 10e-3))
# Not readings of Table 1: today's reading plus a compliance c (m/N) carrying the
# contact force F_x alone (in series with the axis, 1/k_x -> 1/k_x + c), the kind
# of compliance no plate reading has; the rows show what the readings lack.
FX_COMPLIANCE_ROWS = (("axial", 5e-3, 0.25e-6), ("axial", 5e-3, 0.5e-6), ("axial", 5e-3, 0.75e-6))
# the paper's statements, one check each (Willert 2023, Sections 4-5)
PAPER_POINTS = {
    "fig4": "Fig. 4 sphere: partial slip (F_x below mu1 F_N all cycle, a loop: delta > 1e-3)",
    "fig5": "Fig. 5 sphere: partial slip (as Fig. 4; the truncation pushes towards sliding)",
    "fig6": "Fig. 6 truncated: gross slip (F_x on mu1 F_N part of the cycle)",
    "fig7": "Fig. 7 truncated: sliding (F_x on mu1 F_N part of the cycle)",
    "fig8_kx1": "Fig. 8: at k_x = 1 N/um delta close to zero for all b (max_b delta < 0.05)",
    "fig8_profile": "Fig. 8: at k_x = 2, 10, 20 N/um (curves well above zero, max delta > 0.1) b <= 10 um "
                    "acts as the sphere, b >= 30 um as the flat punch (|delta difference| < 0.01)",
    "fig9": "Fig. 9: the transition (delta = 0.1) lies between 1 and 2 N/um for b = 10, 50, 100 um",
}
PLATES_RES = dict(fig9_nk=31, fig8_nb=7)


def _crossing(kx, slip_index, level):
    """k_x (log-interpolated) where ``slip_index`` first rises through ``level``; nan if never, 0 if from the start."""
    above = np.nonzero(slip_index >= level)[0]
    if above.size == 0:
        return float("nan")
    j = above[0]
    if j == 0:
        return 0.0
    f = (level - slip_index[j - 1]) / (slip_index[j] - slip_index[j - 1])
    return float(np.exp(np.log(kx[j - 1]) + f * (np.log(kx[j]) - np.log(kx[j - 1]))))


def plate_readings(readings=PLATE_READINGS + FX_COMPLIANCE_ROWS, res=RES, loop_res=LOOP_RES, nk=PLATES_RES["fig9_nk"],
                   nb=PLATES_RES["fig8_nb"]):
    """Every plate reading against the paper's points (``PAPER_POINTS``): Figs. 4-7 at the
    loops' resolution, the Fig. 9 transition (k_x where delta passes 0.01 and 0.1, on
    ``nk`` log-spaced k_x in 0.3-30 N/um) and Fig. 8 (``nb`` log-spaced b in 1 um - 1 mm at
    k_x = 1, 2, 10, 20 N/um, flat punches beside), each study one batch over the readings.
    Returns one row per reading with the measured numbers, ``ok_<point>`` per paper
    point and ``score`` = the number of points reproduced. A reading is (plate_model,
    R_bed) or (plate_model, R_bed, c): c (m/N) a compliance carrying F_x alone, added in
    series with the axis (``FX_COMPLIANCE_ROWS``)."""
    readings = [tuple(r) + (0.0,) * (3 - len(r)) for r in readings]
    pm = np.array([r[0] for r in readings])
    Rb = np.array([r[1] for r in readings], dtype=float)
    cf = np.array([r[2] for r in readings], dtype=float)
    nr = len(readings)

    def soft(kx, c):  # the axis with the extra compliance in series
        return 1.0 / (1.0 / kx + c)

    # Figs. 4-7: one batch of the readings per case
    lp = loops(res=loop_res, app_kw=dict(plate_model=pm, R_bed=Rb), kx=soft(TABLE1_KX, cf))
    # Fig. 9: readings x b x k_x in one batch
    b9 = np.array([10e-6, 50e-6, 100e-6])
    k9 = np.geomspace(0.3e6, 30e6, nk)
    shape9 = (nr, b9.size, nk)
    d9, _ = _slip_index(TruncatedSphere(np.full(shape9, R_IND), np.array(np.broadcast_to(b9[:, None], shape9))),
                        soft(k9, cf[:, None, None]) * np.ones(shape9), res=res,
                        app_kw=dict(plate_model=np.array(np.broadcast_to(pm[:, None, None], shape9)),
                                    R_bed=np.array(np.broadcast_to(Rb[:, None, None], shape9))))
    # Fig. 8: readings x k_x x b, truncated spheres and flat punches
    k8 = np.array([1e6, 2e6, 10e6, 20e6])
    b8 = np.geomspace(1e-6, 1e-3, nb)
    shape8 = (nr, k8.size, nb)
    B8 = np.array(np.broadcast_to(b8, shape8))
    kw8 = dict(plate_model=np.array(np.broadcast_to(pm[:, None, None], shape8)),
               R_bed=np.array(np.broadcast_to(Rb[:, None, None], shape8)))
    K8 = soft(k8[:, None], cf[:, None, None]) * np.ones(shape8)
    d8, _ = _slip_index(TruncatedSphere(np.full(shape8, R_IND), B8.copy()), K8, res=res, app_kw=kw8)
    f8, _ = _slip_index(FlatPunch(B8.copy()), K8.copy(), res=res, app_kw=kw8)
    sph = b8 <= 10e-6
    flat = b8 >= 30e-6
    rows = []
    for i, (model, R_bed, c) in enumerate(readings):
        app = Apparatus(plate_model=model, R_bed=R_bed)
        A, Bc = app.stroke_loss(TABLE2["F0"])
        row = {"plate_model": model, "R_bed": R_bed, "fx_compliance": c, "k_plates": float(app.k_plates),
               "loss_contact": float(A + c), "loss_bedding": float(Bc)}
        for name in LOOP_CASES:
            row[f"{name}_slip_index"] = float(lp[name]["slip_index"][i])
            row[f"{name}_on_limit"] = float(lp[name]["on_limit"][i])
            row[f"{name}_ratio_max"] = float(lp[name]["friction_ratio_max"][i])
            row[f"{name}_stationary"] = bool(lp[name]["stationary"][i])
        for j, b in enumerate(b9):
            row[f"fig9_k001_b{b * 1e6:g}um"] = _crossing(k9, d9[i, j], 0.01)
            row[f"fig9_k01_b{b * 1e6:g}um"] = _crossing(k9, d9[i, j], 0.1)
        row["fig8_kx1_max_slip_index"] = float(np.max(d8[i, 0]))
        row["fig8_kx2_slip_index_b10um"] = float(np.interp(np.log(10e-6), np.log(b8), d8[i, 1]))
        stiff = d8[i, 1:]  # k_x = 2, 10, 20 N/um
        row["fig8_stiff_max_slip_index"] = float(np.max(stiff))
        row["fig8_sphere_dev"] = float(np.max(np.abs(stiff[:, sph] - stiff[:, :1])))  # b = 1 um: the sphere
        row["fig8_flat_dev"] = float(np.max(np.abs(stiff[:, flat] - f8[i, 1:][:, flat])))
        ok = {"fig4": row["fig4_on_limit"] == 0.0 and row["fig4_slip_index"] > 1e-3,
              "fig5": row["fig5_on_limit"] == 0.0 and row["fig5_slip_index"] > 1e-3,
              "fig6": row["fig6_on_limit"] > 0.0, "fig7": row["fig7_on_limit"] > 0.0,
              "fig8_kx1": row["fig8_kx1_max_slip_index"] < 0.05,
              "fig8_profile": row["fig8_stiff_max_slip_index"] > 0.1 and row["fig8_sphere_dev"] < 0.01
              and row["fig8_flat_dev"] < 0.01,
              "fig9": all(1e6 <= row[f"fig9_k01_b{b * 1e6:g}um"] <= 2e6 for b in b9)}
        row.update({f"ok_{k}": bool(v) for k, v in ok.items()})
        row["score"] = int(sum(ok.values()))
        rows.append(row)
    return rows


def plates_markdown(rows):
    """The plate readings against the paper's points as a markdown table."""
    head = ["reading", "R_bed", "k_p (N/um)", "loss A (F_x), Bc (F_bed) (um/N)", "Fig. 4 delta (on limit)", "Fig. 5", "Fig. 6",
            "Fig. 7", "Fig. 8: max delta at 1 N/um", "Fig. 8 (2-20 N/um): max. deviation from sphere / flat punch",
            "Fig. 9: k_x at delta 0.01 / 0.1 (b = 10, 50, 100 um)", "paper points"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    mark = lambda ok: "" if ok else " x"  # noqa: E731

    def k(v):
        return "never" if not np.isfinite(v) else f"{v / 1e6:.2f}"

    for r in rows:
        name = r["plate_model"] + (f" + c = {r['fx_compliance'] * 1e6:g} um/N on F_x (not a reading)"
                                   if r["fx_compliance"] else "")
        cells = [name, f"{r['R_bed'] * 1e3:g} mm", f"{r['k_plates'] / 1e6:.3g}",
                 f"{r['loss_contact'] * 1e6:.3g}, {r['loss_bedding'] * 1e6:.3g}"]
        for name in LOOP_CASES:
            cells.append(f"{r[f'{name}_slip_index']:.3f} ({100 * r[f'{name}_on_limit']:.0f} %){mark(r[f'ok_{name}'])}")
        cells.append(f"{r['fig8_kx1_max_slip_index']:.3f}{mark(r['ok_fig8_kx1'])}")
        cells.append(f"{r['fig8_sphere_dev']:.4f} / {r['fig8_flat_dev']:.4f}"
                     + (" (delta 0)" if r["fig8_stiff_max_slip_index"] <= 0.1 else "") + mark(r["ok_fig8_profile"]))
        cells.append(" / ".join(f"{k(r[f'fig9_k001_b{b}um'])}-{k(r[f'fig9_k01_b{b}um'])}" for b in (10, 50, 100))
                     + mark(r["ok_fig9"]))
        cells.append(f"{r['score']} of {len(PAPER_POINTS)}")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n\n" + "x: the paper's point is not reproduced. Points: " + "; ".join(
        PAPER_POINTS.values()) + ".\n"

