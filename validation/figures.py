"""Matplotlib figures of scene results (they read result dicts, never call a solver).

Every figure is written atomically as PNG; functions return ``{key: file name}``
relative to the directory they write into.
"""
from __future__ import annotations

import io
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from common.io import write_bytes_atomic  # noqa: E402
from mdr.reference import flat_punch_pressure  # noqa: E402

C_MDR, C_FE, C_CF = "tab:blue", "tab:red", "k"
#: smallest y span of a slip-index plot (the slip index lies in [0, 1])
MIN_DELTA_SPAN = 0.05


def save(fig, path) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    plt.close(fig)
    write_bytes_atomic(path, buf.getvalue())
    return Path(path).name


def _loop_axes(ax_du, ax_fn, res, label, color, ls="-"):
    lp = res["loop"]
    du, fx, fn = (np.asarray(lp[k], float) for k in ("du", "Fx", "FN"))
    ax_du.plot(du * 1e9, fx, ls, color=color, label=label, lw=1.4)
    ax_fn.plot(fn, fx, ls, color=color, label=label, lw=1.4)


def scene_figures(result: dict, out_dir) -> dict:
    """loops.png (F_x-du, F_x-F_N), profiles.png (p, tau), speed_error.png for one scene."""
    out_dir = Path(out_dir)
    s = result["scene"]
    files = {}
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    _loop_axes(a1, a2, result["mdr"], f"MDR (n={result['mdr']['cells']})", C_MDR)
    _loop_axes(a1, a2, result["fem"], f"FE (a/{1 / result['fem']['h_contact']:.0f})", C_FE, "--")
    a1.set_xlabel("du = u2 - u1 (nm): block minus indenter, as the paper measures it" if s.get("drive") == "apparatus"
                  else "du (nm): the contact's tangential displacement, without the bodies' bulk compliance")
    a1.set_ylabel("F_x (N)")
    fn = np.concatenate([np.asarray(result[k]["loop"]["FN"], float) for k in ("mdr", "fem")])
    fn_span = float(np.ptp(fn)) if fn.size else 0.0
    if fn.size and fn_span <= 1e-6 * max(float(np.max(np.abs(fn))), 1e-30):
        # constant normal force: F_x against F_N would be a vertical line on an offset axis;
        # show F_x over the cycle instead and say that F_N is constant
        a2.cla()
        for k, label, color, ls in (("mdr", "MDR", C_MDR, "-"), ("fem", "FE", C_FE, "--")):
            lp = result[k]["loop"]
            t = np.asarray(lp["t"], float)
            a2.plot(t - t[0], np.asarray(lp["Fx"], float), ls, color=color, label=label, lw=1.4)
        a2.set_xlabel("time in the last cycle (cycles)")
        a2.set_ylabel("F_x (N)")
        a2.text(0.03, 0.04, f"F_N constant = {float(np.mean(fn)):.4g} N", transform=a2.transAxes, fontsize=9)
    else:
        a2.set_xlabel("F_N (N)")
        a2.set_ylabel("F_x (N)")
        a2.ticklabel_format(axis="x", useOffset=False)
    for a in (a1, a2):
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.suptitle(f"{s['name']}: stationary loop")
    fig.tight_layout()
    files["loops"] = save(fig, out_dir / "loops.png")

    cf = result.get("closed_form")
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    pm, pf = result["mdr"]["profiles"], result["fem"]["profiles"]
    a1.plot(np.asarray(pm["r"]) * 1e6, np.asarray(pm["pressure"]) / 1e6, color=C_MDR, label="MDR")
    a1.plot(np.asarray(pf["r"]) * 1e6, np.asarray(pf["pressure"]) / 1e6, ".", ms=3, color=C_FE, label="FE")
    if pm.get("traction") is not None:
        a2.plot(np.asarray(pm["r"]) * 1e6, np.asarray(pm["traction"]) / 1e6, color=C_MDR, label="MDR")
    if pf.get("traction") is not None:
        a2.plot(np.asarray(pf["r_pairs"]) * 1e6, np.asarray(pf["traction"]) / 1e6, ".", ms=3, color=C_FE, label="FE")
    if cf is not None:
        pc = cf["profiles"]
        a1.plot(np.asarray(pc["r"]) * 1e6, np.asarray(pc["pressure"]) / 1e6, ":", color=C_CF, label="closed form")
        a2.plot(np.asarray(pc["r"]) * 1e6, np.asarray(pc["traction"]) / 1e6, ":", color=C_CF, label="closed form")
    elif s.get("profile") == "flat":  # Boussinesq's rigid flat punch (1885): the pressure's closed form at F0
        rr = np.linspace(0.0, 0.999, 400) * s["b"]
        a1.plot(rr * 1e6, flat_punch_pressure(rr, s["F0"], s["b"]) / 1e6, ":", color=C_CF,
                label="closed form (Boussinesq)")
    # the axes end a little above the profiles' largest value inside r <= 0.99 a: a flat edge's
    # singular pressure and traction would otherwise flatten the whole profile into the axis
    a_c = float(result["fem"].get("contact_radius") or result["mdr"].get("contact_radius") or 0.0)

    def top(r, v):
        r, v = np.asarray(r, float), np.abs(np.asarray(v, float))
        inside = np.isfinite(v) & (r <= 0.99 * a_c) if a_c > 0 else np.isfinite(v)
        return 1.15 * float(np.max(v[inside])) / 1e6 if np.any(inside) and np.max(v[inside]) > 0 else None

    pt = top(pm["r"], pm["pressure"])
    if pt:
        a1.set_ylim(0, pt)
    if pm.get("traction") is not None:
        tt = top(pm["r"], pm["traction"])
        if tt:
            a2.set_ylim(-0.1 * tt, tt)
    a1.set_xlabel("r (um)")
    a1.set_ylabel("p (MPa) at F_N = F0")
    a2.set_xlabel("r (um)")
    a2.set_ylabel("tau (MPa) at the peak of the last cycle")
    if s.get("profile", "sphere") != "sphere":
        why = "the punch's edge is singular" if s.get("profile") == "flat" else "the kink at r = b is log-singular"
        a1.text(0.02, 0.95, f"axes end at 1.15x the largest value inside 0.99 a ({why})",
                transform=a1.transAxes, fontsize=7, va="top")
    for a in (a1, a2):
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.suptitle(f"{s['name']}: pressure and traction")
    fig.tight_layout()
    files["profiles"] = save(fig, out_dir / "profiles.png")

    files["speed_error"] = save(speed_error_figure(speed_error_points(result),
                                                   f"{s['name']}: each ladder level against the closed form, or "
                                                   "its own extrapolated answer"), out_dir / "speed_error.png")
    return files


def _plain_log_ticks(ax):
    """Log axes without overlapping labels: matplotlib labels every minor tick of an axis
    spanning less than a decade (3 x 10^-1, 4 x 10^-1, ... run into each other). An axis
    of up to 2.5 decades is labelled at 1, 2, 5 x 10^k in plain numbers, a longer one at its
    decades only."""
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    for axis, lim in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
        lo, hi = sorted(lim)
        axis.set_minor_formatter(NullFormatter())
        if lo > 0 and np.log10(hi / lo) < 2.5:
            axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
            axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:.3g}"))


def speed_error_points(result: dict) -> list:
    """The speed-against-error points of a pair scene: every level of each side's ladder with its run
    time and its dissipation error against the answer that level approximates: the closed form where
    one exists, else that side's own answer extrapolated over its ladder (``metrics.ladder_error``;
    none where the ladder gives no extrapolation: no point rather than a distance to the finest
    level, which would vanish there by construction). Each point: model ("MDR", "FE"), the scene's
    group and name, level index, runtime (s), |relative error|."""
    closed = (result.get("closed_form") or {}).get("dissipation")
    v = (result.get("verdicts") or {}).get("dissipation") or {}
    out = []
    for side, model in (("mdr", "MDR"), ("fem", "FE")):
        ref = closed if closed else (v.get(f"{side}_ladder") or {}).get("extrapolated")
        rows = [r for r in result.get("speed_error") or [] if r.get("side") == side]
        for k, r in enumerate(rows):
            t, W = r.get("runtime_s"), r.get("dissipation")
            ok = all(x is not None and np.isfinite(x) for x in (t, W, ref)) and ref != 0 and t > 0
            if ok and W != ref:
                out.append({"model": model, "group": result["scene"].get("group", ""),
                            "scene": result["scene"].get("name", ""), "level": k, "runtime_s": t,
                            "error": abs(W / ref - 1), "against": "closed form" if closed else "own extrapolation"})
    return out


def speed_error_figure(points: list, title: str):
    """Dissipation error against run time, one curve per model, scene group and reference: at each ladder
    level the median run time and the median error over the group's scenes (log-log;
    ``speed_error_points``). Errors against a closed form (solid) and against a ladder's own extrapolated
    answer (dashed: its convergence, no distance to a truth) are never pooled."""
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    markers = dict(zip(sorted({p["group"] for p in points}), "osD^v<>ph*"))
    kinds = [(model, color, against, ls) for model, color in (("MDR", C_MDR), ("FE", C_FE))
             for against, ls in (("closed form", "-"), ("own extrapolation", "--"))]
    for model, color, against, ls in kinds:
        for group, mk in markers.items():
            sel = [p for p in points if p["model"] == model and p["group"] == group
                   and p["against"] == against]
            levels = sorted({p["level"] for p in sel})
            pts = [(float(np.median([p["runtime_s"] for p in sel if p["level"] == k])),
                    float(np.median([p["error"] for p in sel if p["level"] == k]))) for k in levels]
            pts = [(t, e) for t, e in pts if t > 0 and e > 0 and np.isfinite(t) and np.isfinite(e)]
            if pts:
                t, e = zip(*pts)
                n = len({p["scene"] for p in sel})
                ax.loglog(t, e, marker=mk, color=color, lw=1.2, ms=6, ls=ls,
                          label=f"{model}, {group} ({n} scene{'s' if n > 1 else ''}): against {against}")
    _plain_log_ticks(ax)
    ax.set_xlabel("run time of one ladder level (s)")
    ax.set_ylabel("|dissipation / reference - 1|")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3, which="both")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=7)
    else:
        ax.text(0.5, 0.5, "no finite, nonzero dissipation error to plot:\nthe scene hardly dissipates, or no ladder "
                          "extrapolates", transform=ax.transAxes, ha="center")
    fig.tight_layout()
    return fig


def series_figure(points: dict, xlabel: str, path, logx=True) -> str:
    """Slip index against a scene parameter: ``points = {"mdr": [(x, delta)], "fem": [...]}``."""
    fig, ax = plt.subplots(figsize=(6, 4))
    # MDR as large open circles, FE as small filled squares: where the two agree both stay visible
    for side, color, mk, kw in (("mdr", C_MDR, "o-", {"ms": 9, "mfc": "none", "mew": 1.5}),
                                ("fem", C_FE, "s--", {"ms": 4})):
        pts = sorted(p for p in points.get(side, []) if _finite(p[0]) and _finite(p[1]))
        if pts:
            x, y = zip(*pts)
            ax.plot(x, y, mk, color=color, label=side.upper(), **kw)
    if logx:
        ax.set_xscale("log")
    # a y axis at least MIN_DELTA_SPAN tall: two nearly equal slip indices (quick mode: one
    # scene) would otherwise fill a 4e-5 span and look like a large disagreement
    lo, hi = ax.get_ylim()
    if hi - lo < MIN_DELTA_SPAN:
        mid = 0.5 * (lo + hi)
        lo, hi = mid - 0.5 * MIN_DELTA_SPAN, mid + 0.5 * MIN_DELTA_SPAN
        if lo < 0.0 <= mid:
            lo, hi = 0.0, MIN_DELTA_SPAN
        ax.set_ylim(lo, hi)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("slip index delta = dW / (4 mu F0 u_A)")
    ax.grid(alpha=0.3, which="both")
    if ax.get_legend_handles_labels()[0]:
        ax.legend()
    else:
        ax.text(0.5, 0.5, "no finite slip index to plot", transform=ax.transAxes, ha="center")
    fig.tight_layout()
    return save(fig, path)


def _finite(x) -> bool:
    """A number that can be plotted (None, NaN and inf cannot)."""
    try:
        return x is not None and bool(np.isfinite(float(x)))
    except (TypeError, ValueError):
        return False
