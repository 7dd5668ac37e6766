"""The slip-index studies of Figs. 8 and 9 with a plugin contact law beside MDR.

``python -m mdr study fig8|fig9 --law NAME [--points N] [--levels L] [law flags]``
(e.g. ``--law fem --h-contact 0.1``: the FE law of ``python -m mdr apparatus --law
fem``, found through ``common.plugins``). The MDR curves are the full studies of
``studies.study``; the plugin law runs at a subset of their points, ``N`` values per curve
evenly spread over the curve's grid (both ends included; fig8: N flat-face radii b, each
with the four k_x; fig9: N stiffnesses k_x for each of the three b), at the study
resolution (3 cycles x 120 steps) and Table 2 load (``studies.study`` passes them). Fig. 8's flat punch
stays MDR only.

Cost: the law depends on the geometry (b), the materials, mu1 and F_max, not on k_x, mu2
or the drive, so one law per geometry and mesh level serves every apparatus point of that
geometry (a law is pure: each run starts from its ``rest_state``). The (geometry, level)
tasks spread over ``--jobs`` processes or the workers of ``--scheduler``.

Own error of the plugin law: each geometry runs at ``L`` levels of its discretisation,
coarsened by 2^(L-1) .. 2, 1 (``LawPlugin.make_law(coarsen=...)``; for the FE law the
element size), and the error bar of the finest value is ``common.ladder.ladder_error`` over
them (two levels: the last difference; three: Richardson where the order is observed).
Rows: b, kx, slip_index_mdr, slip_index_<law> (finest level), <law>_error, difference (law - MDR),
<law>_status (the ladder status) and slip_index_<law>_c<k> at each coarsening k.
"""
from __future__ import annotations

import argparse
import contextlib
import time

import numpy as np

from mdr.apparatus import Apparatus, run_apparatus
from common.errors import InputError
from common.ladder import ladder_error
from mdr.materials import Materials
from mdr.profiles import TruncatedSphere
from mdr.loading import Loading
from mdr.paper import R_INDENTER as R_IND, TABLE2

LAW_STUDIES = ("fig8", "fig9")
#: points per curve and mesh levels when not given
DEFAULT_POINTS, DEFAULT_LEVELS = 5, 2


def pick(values, n: int) -> list:
    """``n`` of the sorted distinct ``values``, evenly spread over their index range, ends included."""
    v = sorted(set(values))
    if n >= len(v):
        return v
    return [v[i] for i in sorted(set(np.round(np.linspace(0, len(v) - 1, n)).astype(int).tolist()))]


def study_points(name: str, rows: list, points: int) -> dict:
    """{b: [kx, ...]} of the plugin-law points of study ``name`` from its MDR rows."""
    if name == "fig8":
        bs = pick([r["b"] for r in rows], points)
        return {b: sorted({r["kx"] for r in rows if r["b"] == b}) for b in bs}
    if name == "fig9":
        ks = pick([r["kx"] for r in rows], points)
        return {b: list(ks) for b in sorted({r["b"] for r in rows})}
    raise InputError(f"study with --law must be one of {', '.join(LAW_STUDIES)}; got {name!r}")


def check_law_study(law_name: str, plugin, points, levels) -> tuple[int, int]:
    """Validated (points, levels); InputError naming the bad one (before any costly run)."""
    from common.errors import positive_int

    points = positive_int("points", points)
    levels = positive_int("levels", levels)
    if points < 2:
        raise InputError(f"points must be >= 2 (both ends of each curve), got {points}")
    if not hasattr(plugin, "make_law"):
        raise InputError(f"the contact law {law_name!r} offers no make_law (mdr.protocol.LawPlugin): "
                         "it cannot run the studies")
    return points, levels


def geometry_task(plugin, args, b: float, kxs, coarsen: float, R: float, load: dict, res: dict) -> dict:
    """One geometry (truncated sphere of radius R and flat-face radius b) at one level: the
    law set up once, then every apparatus point k_x of ``kxs`` from its rest state (``load``:
    F0, dF, mu1, mu2, ua; ``res``: cycles, steps; top level: picklable for any executor).
    Returns {b, coarsen, kx, slip_index, setup_s, runtime_s, worker}."""
    from common.executors import worker_id

    t0 = time.perf_counter()
    F0, dF, mu1 = load["F0"], load["dF"], load["mu1"]
    session = getattr(plugin, "session", None)
    with session() if session is not None else contextlib.nullcontext():
        law = plugin.make_law(TruncatedSphere(R, b), Materials(), mu1, F0 + dF, args, coarsen=coarsen)
        t1 = time.perf_counter()
        loading = Loading.apparatus(F0, dF, 0.0, load["ua"], cycles=res["cycles"], steps=res["steps"])
        slip_indices = [float(run_apparatus(law, Apparatus(kx=kx, mu2=load["mu2"]), loading)["slip_index"]) for kx in kxs]
    return {"b": b, "coarsen": coarsen, "kx": list(kxs), "slip_index": slip_indices, "setup_s": t1 - t0,
            "runtime_s": time.perf_counter() - t0, "worker": worker_id()}


def _lean(args):
    """The parsed flags without the command's function and plugin table (sent to workers)."""
    if args is None:
        return argparse.Namespace()
    return argparse.Namespace(**{k: v for k, v in vars(args).items() if k not in ("func", "law_plugins")})


def law_study(name: str, mdr_rows: list, law_name: str, plugin, args, *, R: float, load: dict, res: dict,
              points=DEFAULT_POINTS, levels=DEFAULT_LEVELS, executor=None, log=None) -> tuple[list, list]:
    """Study ``name`` (fig8, fig9) with the plugin law at the points of ``study_points``
    beside the MDR rows of the same study (``R``, ``load``, ``res``: those of the MDR study,
    see :func:`geometry_task`). Returns (rows, tasks): one row per point and the records of
    the (geometry, level) tasks (worker, set-up and run times)."""
    points, levels = check_law_study(law_name, plugin, points, levels)
    pts = study_points(name, mdr_rows, points)
    coarsen = [float(2 ** k) for k in range(levels - 1, -1, -1)]
    largs = _lean(args)
    jobs = [(b, kxs, c) for c in sorted(coarsen) for b, kxs in pts.items()]  # finest (costliest) first
    say = log or (lambda m: None)
    if executor is None:
        done = []
        for i, (b, kxs, c) in enumerate(jobs, 1):
            done.append(geometry_task(plugin, largs, b, kxs, c, R, load, res))
            say(f"[{name} {law_name} {i}/{len(jobs)}] b = {b * 1e6:g} um, coarsening {c:g}: "
                f"{len(kxs)} points in {done[-1]['runtime_s']:.1f} s")
    else:
        import concurrent.futures as futures

        futs = [executor.submit(geometry_task, plugin, largs, b, kxs, c, R, load, res) for b, kxs, c in jobs]
        done = []
        for i, f in enumerate(futures.as_completed(futs), 1):
            done.append(f.result())
            say(f"[{name} {law_name} {i}/{len(jobs)}] b = {done[-1]['b'] * 1e6:g} um, coarsening "
                f"{done[-1]['coarsen']:g}: {len(done[-1]['kx'])} points in {done[-1]['runtime_s']:.1f} s "
                f"on {done[-1]['worker']}")
    at = {(t["b"], t["coarsen"], k): d for t in done for k, d in zip(t["kx"], t["slip_index"])}
    mdr = {(r["b"], r["kx"]): r["slip_index_truncated"] for r in mdr_rows}
    rows = []
    for b, kxs in pts.items():
        for k in kxs:
            ladder = [at[(b, c, k)] for c in coarsen]
            err = ladder_error(coarsen, ladder)
            row = {"b": b, "kx": k, "slip_index_mdr": mdr[(b, k)], f"slip_index_{law_name}": ladder[-1],
                   f"{law_name}_error": err["error"], "difference": ladder[-1] - mdr[(b, k)],
                   f"{law_name}_status": err["status"]}
            row.update({f"slip_index_{law_name}_c{c:g}": v for c, v in zip(coarsen, ladder)})
            rows.append(row)
    tasks = [{k: v for k, v in t.items() if k not in ("kx", "slip_index")} | {"points": len(t["kx"])} for t in done]
    return rows, tasks


def law_figure(name: str, mdr_rows: list, rows: list, law_name: str):
    """MDR curves (lines) with the plugin law's points (markers, error bars = its own error)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.5, 4.2))
    curve, x, scale, xlabel = (("kx", "b", 1e6, "flat-face radius b (um)") if name == "fig8"
                               else ("b", "kx", 1e-6, "apparatus stiffness k_x (N/um)"))
    for c in sorted({r[curve] for r in mdr_rows}):
        sel = [r for r in mdr_rows if r[curve] == c]
        label = f"k_x = {c / 1e6:g} N/um" if curve == "kx" else f"b = {c * 1e6:g} um"
        line, = ax.semilogx([r[x] * scale for r in sel], [r["slip_index_truncated"] for r in sel], lw=1.5,
                            label=f"MDR, {label}")
        pts = [r for r in rows if r[curve] == c]
        if pts:
            ax.errorbar([r[x] * scale for r in pts], [r[f"slip_index_{law_name}"] for r in pts],
                        yerr=[r[f"{law_name}_error"] or 0.0 for r in pts], fmt="o", ms=5, mfc="none",
                        color=line.get_color(), capsize=3, label=f"{law_name.upper()}, {label}")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("slip index delta")
    ax.set_title(f"{name}: MDR (lines) and {law_name.upper()} (markers, own error bars), truncated sphere "
                 f"R = {R_IND * 1e3:g} mm in the apparatus\nTable 2: F0 = {TABLE2['F0']:g} N, dF = {TABLE2['dF']:g} N, "
                 f"mu1 = {TABLE2['mu1']:g}, mu2 = {TABLE2['mu2']:g}, u_A = {TABLE2['ua'] * 1e9:g} nm", fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    return fig
