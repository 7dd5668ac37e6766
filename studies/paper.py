"""The apparatus studies of Willert, Machines 11 (2023) 484, as functions that return rows.

- ``fig8``: slip index against the flat-face radius b for k_x = 1, 2, 10, 20 N/um, the flat punch
  of radius b beside the truncated sphere; ``fig9``: slip index against k_x for b = 10, 50,
  100 um; ``loops``: the four experiment cases of Figs. 4-7 (``LOOP_CASES``), their last cycle.
- ``sensitivity`` (and ``sensitivity_markdown``): the slip index at the Table 2 point as each
  reconstructed quantity of the apparatus varies one at a time.

Assumptions: the MDR law in the apparatus model of ``mdr.apparatus`` with the Table 2 load
(``TABLE2``: F0 = 0.5 N, dF = 0.1 N, mu1 = 0.2, mu2 = 0.1, u_A = 150 nm), the indenter radius
R = 6 mm and Table 1's b and k_x where the paper gives no other; all points of a study run as
one batch. Study resolution ``RES``: 100 spring cells, 120 steps per cycle, 3 cycles (the slip
index changes by < 1e-3 against 400 cells / 400 steps). Writing files is ``studies.study``'s.
"""
from __future__ import annotations

import numpy as np

from mdr.apparatus import Apparatus, run_apparatus
from mdr.law import MDRContact
from mdr.loading import Loading
from mdr.materials import Materials
from mdr.paper import DF_OVER_F0
from mdr.paper import B_TABLE1 as TABLE1_B, KX_TABLE1 as TABLE1_KX, R_INDENTER as R_IND, TABLE2  # noqa: F401
from mdr.profiles import FlatPunch, Sphere, TruncatedSphere

RES = dict(cycles=3, steps=120, n=100)


def _slip_index(profile, kx, mu1=0.2, mu2=0.1, F0=0.5, dF=0.1, ua=150e-9, alpha=0.0, res=RES, app_kw=None,
                materials=None):
    """Slip index of ``profile`` in the apparatus (``app_kw``: further Apparatus fields,
    e.g. plate_model and R_bed, scalars or arrays of the batch shape; ``materials``: the pair's,
    default the paper's steel on steel)."""
    mat = materials or Materials()
    law = MDRContact(profile, mat, mu1, F_max=F0 + dF, F_min=F0 - dF if dF < F0 else None,
                     n=res["n"]) if not isinstance(profile, FlatPunch) else MDRContact(profile, mat, mu1, n=8)
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
    rows = [{"kx": float(K[i, j]), "b": float(B[i, j]), "slip_index_truncated": float(d_tr[i, j]),
             "slip_index_flat": float(d_fl[i, j])} for i in range(kx.size) for j in range(nb)]
    return rows


def fig9(nk=30, app_kw=None, res=RES):
    b = np.array([10e-6, 50e-6, 100e-6])
    kx = np.geomspace(0.3e6, 30e6, nk)
    K = np.broadcast_to(kx, (b.size, nk))
    B = np.broadcast_to(b[:, None], K.shape)
    d_tr, _ = _slip_index(TruncatedSphere(np.full(B.shape, R_IND), B.copy()), K.copy(), res=res, app_kw=app_kw)
    return [{"b": float(B[i, j]), "kx": float(K[i, j]), "slip_index_truncated": float(d_tr[i, j])}
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
    ``Apparatus(bedding=False)``). Returns rows {quantity, value, point, b, kx, slip_index,
    change (slip_index minus the reference slip_index of the same point), stationary}.
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
    slip_index = out["slip_index"]
    # stationary: the last loop repeats the previous one (the dissipation test of
    # analyse_cycles is void for a sticking contact whose dW is ~0)
    stat = out["cycles"].loop_change[..., -1] <= 1e-3
    rows = []
    for j, (q, v) in enumerate(scenes):
        base_j = scenes.index((q, SENS_BASE[q]))
        value = ("on" if v else "off") if isinstance(v, bool) else v if isinstance(v, str) else float(v)
        for i, p in enumerate(names):
            rows.append({"quantity": q, "value": value, "reference": j == base_j, "point": p, "b": float(B[i, j]),
                         "kx": float(K[i, j]), "slip_index": float(slip_index[i, j]),
                         "change": float(slip_index[i, j] - slip_index[i, base_j]), "stationary": bool(stat[i, j])})
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
        cells = " | ".join(f"{by_point[p]['slip_index']:.4f} | {by_point[p]['change']:+.4f}" for p in names)
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
    """The four experiment cases of Figs. 4-7 (``LOOP_CASES``; dF = DF_OVER_F0 F0 = 0.2 F0, alpha = 0,
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
        slip_index, o = _slip_index(prof, kx, mu1=mu1, mu2=mu2, F0=F0, dF=DF_OVER_F0 * F0, ua=ua, res=res, app_kw=app_kw)
        last = slice((cycles - 1) * steps, cycles * steps + 1)
        ratio = np.abs(o["Fx"][..., last]) / (mu1 * o["FN"][..., last])
        stat = o["cycles"].last_is_stationary
        out[name] = {"profile": kind, "F0": F0, "ua": ua, "mu1": mu1, "mu2": mu2,
                     "slip_index": float(slip_index) if not shape else np.asarray(slip_index),
                     "friction_ratio_max": _scalar_or(np.max(ratio, axis=-1)),
                     "on_limit": _scalar_or(np.mean(ratio[..., 1:] >= 1 - 1e-9, axis=-1)),
                     "stationary": bool(stat) if not shape else np.asarray(stat),
                     "Fx": o["Fx"][..., last], "FN": o["FN"][..., last], "du": o["du"][..., last]}
    return out


def _scalar_or(a):
    a = np.asarray(a, dtype=float)
    return float(a) if a.ndim == 0 else a
