"""Parameter studies of Willert, Machines 11 (2023) 484 (Figs. 4-9) with the apparatus model.

``python -m mdr study fig8 --out DIR``: slip index against the flat-face radius b
(1 um - 1 mm, log scale) for k_x = 1, 2, 10, 20 N/um, with the flat punch of
radius b beside it. ``fig9``: slip index against k_x for b = 10, 50, 100 um.
``loops``: the four experiment cases of Figs. 4-7 (loop plots F_x-F_N, F_x-du).
``sensitivity``: slip index at the Table 2 point as each reconstructed quantity
(bedding radius, mu2, plate model, bedding on/off, dF, alpha) varies one at a
time (CSV + markdown table). ``plates``: every reading of the brass plates
(``mdr.apparatus``, A3) against the paper's points of Figs. 4-9 (CSV + markdown
table). fig8, fig9 and loops take ``--plate-model`` and ``--R-bed``.
Table 2 values: F0 = 0.5 N, dF = 0.1 N, mu1 = 0.2, mu2 = 0.1, u_A = 150 nm.
All points of a study run as one batch (one pass of the vectorised laws).
Study resolution: 100 spring cells, 120 steps per cycle, 3 cycles (the slip
index changes by < 1e-3 against 400 cells / 400 steps).
"""
from __future__ import annotations

import csv
import io
import time
from pathlib import Path

import numpy as np

from mdr.apparatus import Apparatus, run_apparatus
from common.errors import InputError
from common.io import dumps_json, write_bytes_atomic
from mdr.law import MDRContact
from mdr.materials import Materials
from mdr.profiles import FlatPunch, Sphere, TruncatedSphere
from mdr.loading import Loading

TABLE2 = dict(F0=0.5, dF=0.1, mu1=0.2, mu2=0.1, ua=150e-9)
R_IND = 6e-3
TABLE1_B, TABLE1_KX = 0.6e-3, 1.9e6   # Table 1: flat-face radius of the truncated indenter, axis stiffness
RES = dict(cycles=3, steps=120, n=100)


def _slip_index(profile, kx, mu1=0.2, mu2=0.1, F0=0.5, dF=0.1, ua=150e-9, alpha=0.0, res=RES, app_kw=None):
    """Slip index of ``profile`` in the apparatus (``app_kw``: further Apparatus fields,
    e.g. plate_model and R_bed, scalars or arrays of the batch shape)."""
    law = MDRContact(profile, Materials(), mu1, F_max=F0 + dF, F_min=F0 - dF if dF < F0 else None,
                     n=res["n"]) if not isinstance(profile, FlatPunch) else MDRContact(profile, Materials(), mu1, n=8)
    loading = Loading.apparatus(F0, dF, alpha, ua, cycles=res["cycles"], steps=res["steps"])
    out = run_apparatus(law, Apparatus(kx=kx, mu2=mu2, **(app_kw or {})), loading)
    return out["slip_index"], out


def fig8(nb=25, app_kw=None, kx=(1e6, 2e6, 10e6, 20e6), b_range=(1e-6, 1e-3), res=RES):
    kx = np.asarray(kx, dtype=float)
    b = np.geomspace(*b_range, nb)
    B = np.broadcast_to(b, (kx.size, nb))
    K = np.broadcast_to(kx[:, None], B.shape)
    d_tr, _ = _slip_index(TruncatedSphere(np.full(B.shape, R_IND), B.copy()), K, res=res, app_kw=app_kw)
    d_fl, _ = _slip_index(FlatPunch(B.copy()), K, res=res, app_kw=app_kw)
    rows = [{"kx": float(K[i, j]), "b": float(B[i, j]), "delta_truncated": float(d_tr[i, j]),
             "delta_flat": float(d_fl[i, j])} for i in range(kx.size) for j in range(nb)]
    return rows


def fig9(nk=30, app_kw=None, res=RES):
    b = np.array([10e-6, 50e-6, 100e-6])
    kx = np.geomspace(0.3e6, 30e6, nk)
    K = np.broadcast_to(kx, (b.size, nk))
    B = np.broadcast_to(b[:, None], K.shape)
    d_tr, _ = _slip_index(TruncatedSphere(np.full(B.shape, R_IND), B.copy()), K.copy(), res=res, app_kw=app_kw)
    return [{"b": float(B[i, j]), "kx": float(K[i, j]), "delta_truncated": float(d_tr[i, j])}
            for i in range(b.size) for j in range(nk)]


# Sensitivity study. The Table 2 point needs b and k_x, which Table 2 does not give:
# the reference column uses Table 1's (b = 0.6 mm, k_x = 1.9 N/um, the apparatus
# of the experiments), the second column the sphere limit b = 10 um at the same k_x.
SENS_POINTS = {"b600um": (TABLE1_B, TABLE1_KX), "b10um": (10e-6, TABLE1_KX)}
SENS_BASE = dict(R_bed=5e-3, mu2=0.1, plate_model="axial", bedding=True, dF=0.1, alpha=0.0)
SENS_VARY = (("R_bed", (1e-3, 2.5e-3, 5e-3, 10e-3)), ("mu2", (0.05, 0.1, 0.2)),
             ("plate_model", ("axial", "bending", "rigid")), ("bedding", (True, False)),
             ("dF", (0.0, 0.05, 0.1, 0.2)), ("alpha", (0.0, np.pi / 2, np.pi)))


def sensitivity(points=SENS_POINTS, vary=SENS_VARY, res=RES):
    """Slip index at the Table 2 point (F0 = 0.5 N, mu1 = 0.2, u_A = 150 nm) as each
    reconstructed quantity of ``vary`` moves away from ``SENS_BASE`` one at a time.

    All scenes (every value at every (b, k_x) point of ``points``) run as one batch:
    the apparatus fields, dF and alpha are per-scene arrays. "bedding off" is run as
    mu2 = 0 (a frictionless bedding carries no tangential force; identical to
    ``Apparatus(bedding=False)``). Returns rows {quantity, value, point, b, kx, delta,
    change (delta minus the reference delta of the same point), stationary}.
    """
    scenes = [(q, v) for q, values in vary for v in values]
    cols = {k: [] for k in SENS_BASE}
    for q, v in scenes:
        for k in SENS_BASE:
            cols[k].append(v if k == q else SENS_BASE[k])
    mu2 = np.where(cols["bedding"], cols["mu2"], 0.0)
    names = list(points)
    nb = len(names)
    shape = (nb, len(scenes))
    per_scene = lambda v: np.array(np.broadcast_to(np.asarray(v), shape))  # noqa: E731
    B = np.broadcast_to(np.array([points[p][0] for p in names])[:, None], shape)
    K = np.broadcast_to(np.array([points[p][1] for p in names])[:, None], shape)
    F0, mu1, ua = TABLE2["F0"], TABLE2["mu1"], TABLE2["ua"]
    dF = per_scene(cols["dF"])
    law = MDRContact(TruncatedSphere(np.full(shape, R_IND), B.copy()), Materials(), mu1, F_max=F0 + dF,
                     F_min=F0 - np.maximum(dF, 0.05), n=res["n"])
    app = Apparatus(kx=K.copy(), mu2=per_scene(mu2), R_bed=per_scene(cols["R_bed"]),
                    plate_model=per_scene(np.array(cols["plate_model"])))
    loading = Loading.apparatus(F0, dF, per_scene(cols["alpha"]), ua, cycles=res["cycles"], steps=res["steps"])
    out = run_apparatus(law, app, loading)
    delta = out["slip_index"]
    # stationary: the last loop repeats the previous one (the dissipation test of
    # analyse_cycles is void for a sticking contact whose dW is ~0)
    stat = out["cycles"].loop_change[..., -1] <= 1e-3
    rows = []
    for j, (q, v) in enumerate(scenes):
        base_j = scenes.index((q, SENS_BASE[q]))
        value = ("on" if v else "off") if isinstance(v, bool) else v if isinstance(v, str) else float(v)
        for i, p in enumerate(names):
            rows.append({"quantity": q, "value": value, "reference": j == base_j, "point": p, "b": float(B[i, j]),
                         "kx": float(K[i, j]), "delta": float(delta[i, j]),
                         "change": float(delta[i, j] - delta[i, base_j]), "stationary": bool(stat[i, j])})
    return rows


def sensitivity_markdown(rows, points=SENS_POINTS):
    """The sensitivity rows as a markdown table (one column pair per (b, k_x) point)."""
    names = list(points)
    head = "| quantity | value | " + " | ".join(
        f"delta (b = {points[p][0] * 1e6:g} um, k_x = {points[p][1] / 1e6:g} N/um) | change" for p in names) + " |"
    lines = [head, "|---|---|" + "---|---|" * len(names)]
    keyed = {}
    for r in rows:
        keyed.setdefault((r["quantity"], r["value"]), {})[r["point"]] = r
    fmt = {"R_bed": lambda v: f"{v * 1e3:g} mm", "alpha": lambda v: f"{v / np.pi:g} pi", "dF": lambda v: f"{v:g} N"}
    for (q, v), by_point in keyed.items():
        val = fmt.get(q, str)(v) + (" (ref.)" if by_point[names[0]]["reference"] else "")
        cells = " | ".join(f"{by_point[p]['delta']:.4f} | {by_point[p]['change']:+.4f}" for p in names)
        lines.append(f"| {q} | {val} | {cells} |")
    return "\n".join(lines) + "\n"


LOOP_CASES = {  # Figs. 4-7: profile, F0, u_A, mu1, mu2; b and k_x from Table 1
    "fig4": ("sphere", 0.35, 90e-9, 0.24, 0.06),
    "fig5": ("sphere", 0.61, 220e-9, 0.26, 0.10),
    "fig6": ("truncated", 0.31, 90e-9, 0.20, 0.10),
    "fig7": ("truncated", 0.61, 220e-9, 0.16, 0.10),
}


LOOP_RES = dict(cycles=4, steps=400, n=400)


def loops(res=LOOP_RES, cases=None, app_kw=None, kx=TABLE1_KX):
    """The four experiment cases of Figs. 4-7 (``LOOP_CASES``; dF = 0.2 F0, alpha = 0,
    b = 0.6 mm and k_x = 1.9 N/um from Table 1). Per case: the stationary last
    cycle (Fx, FN, du), the slip index, ``friction_ratio_max`` = max |F_x| / (mu1 F_N)
    and ``on_limit`` = the fraction of the cycle's steps with F_x on the friction
    limit (|F_x| >= (1 - 1e-9) mu1 F_N): 0 in partial slip, finite in gross slip.
    ``app_kw`` (Apparatus fields) may hold arrays of one batch shape: then every
    value of a case is an array of that shape (one pass per case)."""
    out = {}
    cycles, steps = res["cycles"], res["steps"]
    shape = np.broadcast_shapes(np.shape(kx), *(np.shape(v) for v in (app_kw or {}).values()))
    for name in cases or LOOP_CASES:
        kind, F0, ua, mu1, mu2 = LOOP_CASES[name]
        R = np.full(shape, R_IND) if shape else R_IND
        prof = Sphere(R) if kind == "sphere" else TruncatedSphere(R, np.full(shape, TABLE1_B) if shape else TABLE1_B)
        delta, o = _slip_index(prof, kx, mu1=mu1, mu2=mu2, F0=F0, dF=0.2 * F0, ua=ua, res=res, app_kw=app_kw)
        last = slice((cycles - 1) * steps, cycles * steps + 1)
        ratio = np.abs(o["Fx"][..., last]) / (mu1 * o["FN"][..., last])
        stat = o["cycles"].last_is_stationary
        out[name] = {"profile": kind, "F0": F0, "ua": ua, "mu1": mu1, "mu2": mu2,
                     "slip_index": float(delta) if not shape else np.asarray(delta),
                     "friction_ratio_max": _scalar_or(np.max(ratio, axis=-1)),
                     "on_limit": _scalar_or(np.mean(ratio[..., 1:] >= 1 - 1e-9, axis=-1)),
                     "stationary": bool(stat) if not shape else np.asarray(stat),
                     "Fx": o["Fx"][..., last], "FN": o["FN"][..., last], "du": o["du"][..., last]}
    return out


def _scalar_or(a):
    a = np.asarray(a, dtype=float)
    return float(a) if a.ndim == 0 else a


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


def _crossing(kx, delta, level):
    """k_x (log-interpolated) where delta first rises through ``level``; nan if never, 0 if from the start."""
    above = np.nonzero(delta >= level)[0]
    if above.size == 0:
        return float("nan")
    j = above[0]
    if j == 0:
        return 0.0
    f = (level - delta[j - 1]) / (delta[j] - delta[j - 1])
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
            row[f"{name}_delta"] = float(lp[name]["slip_index"][i])
            row[f"{name}_on_limit"] = float(lp[name]["on_limit"][i])
            row[f"{name}_ratio_max"] = float(lp[name]["friction_ratio_max"][i])
            row[f"{name}_stationary"] = bool(lp[name]["stationary"][i])
        for j, b in enumerate(b9):
            row[f"fig9_k001_b{b * 1e6:g}um"] = _crossing(k9, d9[i, j], 0.01)
            row[f"fig9_k01_b{b * 1e6:g}um"] = _crossing(k9, d9[i, j], 0.1)
        row["fig8_kx1_max_delta"] = float(np.max(d8[i, 0]))
        row["fig8_kx2_delta_b10um"] = float(np.interp(np.log(10e-6), np.log(b8), d8[i, 1]))
        stiff = d8[i, 1:]  # k_x = 2, 10, 20 N/um
        row["fig8_stiff_max_delta"] = float(np.max(stiff))
        row["fig8_sphere_dev"] = float(np.max(np.abs(stiff[:, sph] - stiff[:, :1])))  # b = 1 um: the sphere
        row["fig8_flat_dev"] = float(np.max(np.abs(stiff[:, flat] - f8[i, 1:][:, flat])))
        ok = {"fig4": row["fig4_on_limit"] == 0.0 and row["fig4_delta"] > 1e-3,
              "fig5": row["fig5_on_limit"] == 0.0 and row["fig5_delta"] > 1e-3,
              "fig6": row["fig6_on_limit"] > 0.0, "fig7": row["fig7_on_limit"] > 0.0,
              "fig8_kx1": row["fig8_kx1_max_delta"] < 0.05,
              "fig8_profile": row["fig8_stiff_max_delta"] > 0.1 and row["fig8_sphere_dev"] < 0.01
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
            cells.append(f"{r[f'{name}_delta']:.3f} ({100 * r[f'{name}_on_limit']:.0f} %){mark(r[f'ok_{name}'])}")
        cells.append(f"{r['fig8_kx1_max_delta']:.3f}{mark(r['ok_fig8_kx1'])}")
        cells.append(f"{r['fig8_sphere_dev']:.4f} / {r['fig8_flat_dev']:.4f}"
                     + (" (delta 0)" if r["fig8_stiff_max_delta"] <= 0.1 else "") + mark(r["ok_fig8_profile"]))
        cells.append(" / ".join(f"{k(r[f'fig9_k001_b{b}um'])}-{k(r[f'fig9_k01_b{b}um'])}" for b in (10, 50, 100))
                     + mark(r["ok_fig9"]))
        cells.append(f"{r['score']} of {len(PAPER_POINTS)}")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n\n" + "x: the paper's point is not reproduced. Points: " + "; ".join(
        PAPER_POINTS.values()) + ".\n"


#: the units of the study rows' dimensional columns, written into the CSV headers (SI)
CSV_UNITS = {"kx": "N/m", "b": "m"}


def _csv(rows):
    """The rows as CSV, a dimensional column's header carrying its unit (``CSV_UNITS``): ``kx (N/m)``."""
    buf = io.StringIO()
    keys = list(rows[0])
    buf.write(",".join(f"{k} ({CSV_UNITS[k]})" if k in CSV_UNITS else k for k in keys) + "\r\n")
    w = csv.DictWriter(buf, fieldnames=keys)
    w.writerows(rows)
    return buf.getvalue().encode()


def _png(fig) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=120)
    return buf.getvalue()


STUDIES = ("fig8", "fig9", "loops", "sensitivity", "plates")
APP_KW_STUDIES = ("fig8", "fig9", "loops")  # the studies that take one apparatus (app_kw)


def run_study(name: str, out_dir, app_kw=None) -> dict:
    """Run study ``name`` (fig8, fig9, loops, sensitivity, plates) and write CSV/JSON + PNG
    (sensitivity, plates: CSV + markdown table) into out_dir. ``app_kw``: Apparatus fields
    (plate_model, R_bed) for fig8, fig9 and loops (the other two vary them themselves)."""
    res, files = study_outputs(name, app_kw)
    _write_files(out_dir, files)
    return res


def _write_files(out_dir, files: dict) -> None:
    for fname, data in files.items():
        write_bytes_atomic(Path(out_dir) / fname, data)


def study_outputs(name: str, app_kw=None) -> tuple[dict, dict]:
    """Run study ``name`` (``app_kw`` as :func:`run_study`); returns its result {study, rows,
    runtime_s, worker} and its files {file name: bytes} (written by the caller: a remote
    worker needs no shared disk)."""
    if app_kw and name not in APP_KW_STUDIES:
        raise InputError(f"plate_model/R_bed apply to the studies {', '.join(APP_KW_STUDIES)}, not to {name}")
    if app_kw:
        Apparatus(**app_kw)  # checked before the work
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from common.executors import worker_id

    files, fig = {}, None
    t0 = time.perf_counter()
    if name == "fig8":
        rows = fig8(app_kw=app_kw)
        files["fig8.csv"] = _csv(rows)
        fig, ax = plt.subplots(figsize=(6, 4))
        for kx in sorted({r["kx"] for r in rows}):
            sel = [r for r in rows if r["kx"] == kx]
            line, = ax.semilogx([r["b"] * 1e6 for r in sel], [r["delta_truncated"] for r in sel], lw=2,
                                label=f"k_x = {kx / 1e6:g} N/um")
            ax.semilogx([r["b"] * 1e6 for r in sel], [r["delta_flat"] for r in sel], lw=0.8, color=line.get_color())
        ax.set_xlabel("flat-face radius b (um)")
        ax.set_ylabel("slip index delta = dW / (4 mu1 u_A F0)")
        ax.set_title("Fig. 8: truncated sphere R = 6 mm (thick) and flat punch of radius b (thin)\n"
                     "F0 = 0.5 N, dF = 0.1 N, u_A = 150 nm, mu1 = 0.2, mu2 = 0.1", fontsize=9)
        ax.legend()
        fig.tight_layout()
        files["fig8.png"] = _png(fig)
    elif name == "fig9":
        rows = fig9(app_kw=app_kw)
        files["fig9.csv"] = _csv(rows)
        fig, ax = plt.subplots(figsize=(6, 4))
        for b in sorted({r["b"] for r in rows}):
            sel = [r for r in rows if r["b"] == b]
            ax.semilogx([r["kx"] / 1e6 for r in sel], [r["delta_truncated"] for r in sel], label=f"b = {b * 1e6:g} um")
        ax.axvline(0.2 * 0.5 / 150e-9 / 1e6, color="k", ls=":", label="mu1 F0 / u_A")
        ax.set_xlabel("apparatus stiffness k_x (N/um)")
        ax.set_ylabel("slip index delta = dW / (4 mu1 u_A F0)")
        ax.set_title("Fig. 9: truncated spheres R = 6 mm in the apparatus\n"
                     "F0 = 0.5 N, dF = 0.1 N, u_A = 150 nm, mu1 = 0.2, mu2 = 0.1", fontsize=9)
        ax.legend()
        fig.tight_layout()
        files["fig9.png"] = _png(fig)
    elif name == "loops":
        data = loops(app_kw=app_kw)
        files["loops.json"] = dumps_json(data).encode()
        fig, axes = plt.subplots(len(data), 2, figsize=(8, 2.6 * len(data)))
        for row, (key, d) in zip(axes, data.items()):
            row[0].plot(np.asarray(d["FN"]), np.asarray(d["Fx"]) * 1e3, "r")
            row[0].set_xlabel("F_N (N)")
            row[0].set_ylabel("F_x (mN)")
            row[1].plot(np.asarray(d["du"]) * 1e9, np.asarray(d["Fx"]) * 1e3, "r")
            row[1].set_xlabel("du (nm)")
            row[0].set_title(f"{key}: {d['profile']} F0 = {d['F0']} N, u_A = {d['ua'] * 1e9:g} nm, "
                             f"delta = {d['slip_index']:.2f}, on limit {100 * d['on_limit']:.0f} %",
                             fontsize=8, loc="left")
        fig.tight_layout()
        files["loops.png"] = _png(fig)
        rows = [{k: v for k, v in d.items() if k not in ("Fx", "FN", "du")} | {"case": k} for k, d in data.items()]
    elif name == "sensitivity":
        rows = sensitivity()
        files["sensitivity.csv"] = _csv(rows)
        files["sensitivity.md"] = sensitivity_markdown(rows).encode()
    elif name == "plates":
        rows = plate_readings()
        files["plates.csv"] = _csv(rows)
        files["plates.md"] = plates_markdown(rows).encode()
    else:
        raise InputError(f"study must be one of {', '.join(STUDIES)}; got {name!r}")
    if fig is not None:
        plt.close(fig)
    return {"study": name, "rows": rows, "runtime_s": time.perf_counter() - t0, "worker": worker_id()}, files


def study_names(names) -> list:
    """Validated list of study names from a comma list (or iterable); 'all' = every study."""
    if isinstance(names, str):
        names = [n.strip() for n in names.split(",") if n.strip()]
    names = list(dict.fromkeys(STUDIES if list(names) == ["all"] else names))
    bad = [n for n in names if n not in STUDIES]
    if bad or not names:
        raise InputError(f"study must be one of {', '.join(STUDIES)} (or a comma list, or all); got {', '.join(bad) or 'nothing'}")
    return names


def run_studies(names, out_dir, jobs: int = 1, app_kw=None, scheduler: str | None = None, *, law: str = "mdr",
                plugin=None, law_args=None, points=None, levels=None, log=None) -> list:
    """Run several studies, each one batch pass, in up to ``jobs`` spawned processes or on
    the workers of the Dask scheduler at ``scheduler`` (``common.executors``).

    The studies are independent and each is already one batch pass over its points,
    so the second core is used by running two studies at once. With the compiled loops
    (``mdr.kernels``) a study takes about a second and starting a worker (imports,
    loading the compiled code) costs more: ``jobs`` pays only without numba. The files
    are written here as each study comes back. Each result names its ``worker`` and the
    ``executor`` of the run. ``app_kw``: Apparatus fields for fig8, fig9, loops.

    ``law`` other than "mdr": fig8/fig9 with that plugin law (``plugin``, its parsed flags
    ``law_args``) beside MDR at ``points`` points per curve on ``levels`` mesh levels
    (``studies.law_study``); its (geometry, level) tasks are what the processes or workers share.
    """
    from common.executors import check_choice, executor_for

    names = study_names(names)
    jobs = check_choice(jobs, scheduler)
    bad = [n for n in names if app_kw and n not in APP_KW_STUDIES]
    if bad:
        raise InputError(f"--plate-model/--R-bed apply to the studies {', '.join(APP_KW_STUDIES)}, not to {', '.join(bad)}")
    if law != "mdr":
        if app_kw:
            raise InputError("--plate-model/--R-bed do not apply with --law (the FE-backed studies use the default apparatus)")
        return _run_law_studies(names, out_dir, jobs, scheduler, law, plugin, law_args, points, levels, log)
    if scheduler is None and (jobs == 1 or len(names) == 1):
        jobs = 1
    res = {}
    with executor_for(min(jobs, len(names)), scheduler) as (ex, label):
        if ex is None:
            for n in names:
                res[n], files = study_outputs(n, app_kw)
                _write_files(out_dir, files)
        else:
            # longest first, so that the pool balances (fig8 holds two batches)
            futs = {n: ex.submit(study_outputs, n, app_kw) for n in sorted(names, key=STUDIES.index)}
            for n, f in futs.items():
                res[n], files = f.result()
                _write_files(out_dir, files)
    return [dict(res[n], executor=label) for n in names]


def _run_law_studies(names, out_dir, jobs, scheduler, law, plugin, law_args, points, levels, log) -> list:
    """fig8/fig9 with a plugin law beside MDR (``studies.law_study``): CSV + PNG ``NAME_LAW.*``."""
    from common.executors import executor_for
    from .law_study import DEFAULT_LEVELS, DEFAULT_POINTS, LAW_STUDIES, check_law_study, law_figure, law_study

    bad = [n for n in names if n not in LAW_STUDIES]
    if bad:
        raise InputError(f"study with --law {law} must be one of {', '.join(LAW_STUDIES)}; got {', '.join(bad)}")
    if plugin is None:
        raise InputError(f"law must be mdr or an installed contact-law plugin; got {law!r}")
    points, levels = check_law_study(law, plugin, DEFAULT_POINTS if points is None else points,
                                     DEFAULT_LEVELS if levels is None else levels)
    out = []
    with executor_for(jobs, scheduler) as (ex, label):
        for n in names:
            t0 = time.perf_counter()
            mdr_rows = fig8() if n == "fig8" else fig9()
            rows, tasks = law_study(n, mdr_rows, law, plugin, law_args, R=R_IND, load=TABLE2, res=RES,
                                    points=points, levels=levels, executor=ex, log=log)
            fig = law_figure(n, mdr_rows, rows, law)
            _write_files(out_dir, {f"{n}_{law}.csv": _csv(rows), f"{n}_{law}.png": _png(fig)})
            import matplotlib.pyplot as plt

            plt.close(fig)
            out.append({"study": n, "law": law, "rows": rows, "tasks": tasks, "runtime_s": time.perf_counter() - t0,
                        "worker": ", ".join(sorted({t["worker"] for t in tasks})), "executor": label})
    return out
