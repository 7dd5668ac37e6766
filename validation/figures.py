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

from mdr.io import write_bytes_atomic  # noqa: E402
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

    files["speed_error"] = save(pareto_figure({s["name"]: result["speed_error"]}), out_dir / "speed_error.png")
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


def pareto_figure(rows_by_scene: dict):
    """Dissipation error against runtime: MDR grids and FE meshes of each scene (log-log)."""
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    markers = "osD^v<>ph*"
    for i, (name, rows) in enumerate(rows_by_scene.items()):
        for side, color in (("mdr", C_MDR), ("fem", C_FE)):
            pts = [(r["runtime_s"], r["error_vs_closed_form"] if r["error_vs_closed_form"] is not None
                    else r["error_vs_fe"]) for r in rows if r["side"] == side]
            pts = [(t, abs(e)) for t, e in pts if t is not None and e is not None and np.isfinite(e) and e != 0
                   and np.isfinite(t) and t > 0]
            if not pts:
                continue
            t, e = zip(*sorted(pts))
            ax.loglog(t, e, marker=markers[i % len(markers)], color=color, lw=1, ms=5,
                      label=f"{name} {side.upper()}")
    _plain_log_ticks(ax)
    ax.set_xlabel("runtime (s)")
    ax.set_ylabel("|relative dissipation error|")
    ax.set_title("speed against error (closed form where one exists, else finest FE)", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=6, ncol=2)
    else:
        ax.text(0.5, 0.5, "no finite, nonzero dissipation error to plot", transform=ax.transAxes, ha="center")
    fig.tight_layout()
    return fig


def validity_figure(result: dict, out_dir) -> dict:
    """Size effect: change of the FE answer (contact radius, stick radius, dissipation) when the
    block or the cap shrinks, against size / a, relative to the default 200 a bodies at the same
    mesh (which removes the mesh error common to all variants; the default is a half-space
    within that error, so this is the error a half-space model makes for the small body)."""
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    rows = result["validity"]
    big = max(max(r["block_over_a"], r["cap_over_a"]) for r in rows)  # the default bodies' size
    kinds = {"block": lambda r: r["block_over_a"] < big <= r["cap_over_a"],
             "cap": lambda r: r["cap_over_a"] < big <= r["block_over_a"],
             "both": lambda r: max(r["block_over_a"], r["cap_over_a"]) < big}
    for (kind, pick), mk, ls in zip(kinds.items(), ("o", "s", "^"), ("-", "--", ":")):
        sel = sorted([r for r in rows if pick(r)], key=lambda r: min(r["block_over_a"], r["cap_over_a"]))
        if not sel:
            continue
        x = [min(r["block_over_a"], r["cap_over_a"]) for r in sel]
        for q, c in (("contact_radius", "tab:blue"), ("stick_radius", "tab:green"), ("dissipation", "tab:red")):
            y = [max(abs(r[f"{q}_vs_default"] or 0.0), 1e-7) * 100 for r in sel]
            ax.semilogy(x, y, marker=mk, color=c, ls=ls,
                        label=f"{q.replace('_', ' ')}, {'block and cap' if kind == 'both' else kind + ' alone'} shrunk")
    ax.set_xscale("log")
    ax.set_xlabel("block or cap size / contact radius")
    ax.set_ylabel("|FE(size) - FE(200 a)| (%)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title("Where the half-space assumption breaks", fontsize=10)
    fig.tight_layout()
    return {"validity": save(fig, Path(out_dir) / "validity.png")}


def curvature_figure(result: dict, out_dir) -> dict:
    """Curvature effect (FE extrapolated - MDR, with its error bar) against a/R, one line per nu,
    for the dissipation and the radii, with the tolerances of the verdicts."""
    rows = result["curvature"]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, qs in zip(axes, (("dissipation",), ("contact_radius", "stick_radius"))):
        for q in qs:
            for nu, mk in ((0.1, "^"), (0.29, "o"), (0.45, "s")):
                sel = sorted([r for r in rows if abs(r["nu"] - nu) < 1e-9 and r.get(f"{q}_effect") is not None],
                             key=lambda r: r["a_over_R"])
                if not sel:
                    continue
                x = [100 * r["a_over_R"] for r in sel]
                y = [100 * r[f"{q}_effect"] for r in sel]
                e = [100 * (r[f"{q}_effect_error"] or 0.0) for r in sel]
                ax.errorbar(x, y, yerr=e, marker=mk, capsize=3, ls="-" if q != "stick_radius" else "--",
                            label=f"{q.replace('_', ' ')}, nu = {nu:g}")
            tol = rows[0]["verdicts"][q]["tolerance"]
            ref_q = abs(rows[0]["verdicts"][q]["fem"]) if q == "dissipation" else None
            if ref_q:
                ax.axhspan(-100 * tol / ref_q, 100 * tol / ref_q, color="0.9", zorder=0)
        ax.set_xscale("log")
        ax.set_xlabel("a / R (%)")
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.grid(alpha=0.3, which="both")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    axes[0].set_ylabel("FE - MDR, dissipation (% of the FE dissipation)")
    axes[1].set_ylabel("FE - MDR, radius (% of the contact radius)")
    axes[0].set_title("Dissipation (grey: tolerance)", fontsize=10)
    axes[1].set_title("Contact and stick radius", fontsize=10)
    fig.tight_layout()
    return {"curvature": save(fig, Path(out_dir) / "curvature.png")}


def assumptions3d_figure(result: dict, out_dir) -> dict:
    """The effect of each relaxed assumption (on minus off, same mesh) against the 3D element size,
    the finest level with its error bar; grey: the catalogue's tolerance."""
    rows = result["assumptions3d"]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, q, unit in ((axes[0], "dissipation", "% of the dissipation with the assumption"),
                        (axes[1], "stick_axis_x", "% of the contact radius")):
        for r, mk in zip(rows, "osd^v"):
            hs = [x["h"] for x in r["levels"] if x["effects"][q] is not None]
            ys = [100 * x["effects"][q] for x in r["levels"] if x["effects"][q] is not None]
            if not ys:
                continue
            line, = ax.plot(hs, ys, marker=mk, label=r["variant"].split("[", 1)[-1].rstrip("]"))
            err = r["verdicts"][q]["error"]
            if err is not None and np.isfinite(err):
                ax.errorbar([hs[-1]], [ys[-1]], yerr=[100 * err], color=line.get_color(), capsize=4)
        tol = rows[0]["verdicts"][q]["tolerance"] if rows else None
        if tol:
            ax.axhspan(-100 * tol, 100 * tol, color="0.9", zorder=0)
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.set_xscale("log")
        ax.invert_xaxis()
        ax.set_xlabel("element size on the contact / a_ref")
        ax.set_ylabel(f"relaxed - imposed ({unit})", fontsize=8)
        ax.set_title(q.replace("_", " "), fontsize=10)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.tight_layout()
    return {"assumptions3d": save(fig, Path(out_dir) / "assumptions3d.png")}


def tilt_figure(result: dict, out_dir) -> dict:
    """The effect of a tilt of the flat face against theta / theta_c (log x), one line per profile,
    each point the finest 3D level against the aligned face on the same mesh with the error bar of
    the effect's ladder: the dissipation (relative, or in units of 4 mu F0 u_A where the aligned
    face hardly dissipates; dashed: the catalogue's tolerance in that unit) and the contact area
    fraction at F0. Open markers: contacts too small to resolve (undetermined)."""
    rows = result["tilt"]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, q in ((axes[0], "dissipation"), (axes[1], "contact_area")):
        for r, mk in zip(rows, "osd^v"):
            pts = [p for p in r["points"] if p["aligned"][q]["effect"] is not None]
            if not pts:
                continue
            unit = f" ({r['dissipation_unit']})" if q == "dissipation" else ""
            label = f"{r['profile']} b = {r['b'] * 1e6:g} um{', banded edge' if r.get('banded') else ''}{unit}"
            ok = [p for p in pts if p.get("resolved", True)]
            x = np.array([p["ratio"] for p in ok])
            y = np.array([100 * p["aligned"][q]["effect"] for p in ok])
            e = np.array([100 * (p["aligned"][q]["error"] or 0.0) for p in ok])
            line = ax.errorbar(x, y, yerr=e, marker=mk, capsize=3, label=label)
            color = line.lines[0].get_color()
            bad = [p for p in pts if not p.get("resolved", True)]
            if bad:
                ax.plot([p["ratio"] for p in bad], [100 * p["aligned"][q]["effect"] for p in bad], marker=mk, ls="none",
                        mfc="none", color=color)
            tol = pts[0]["aligned"][q]["tolerance"]
            if tol:
                for sgn in (1, -1):
                    ax.axhline(sgn * 100 * tol, color=color, lw=0.8, ls="--")
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.axvline(1.0, color="0.6", lw=0.8, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("symlog", linthresh=0.01)
        ax.set_xlabel("tilt / theta_c  (theta_c = F0 / (4 E* b^2))")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("dissipation: tilted - aligned (%)", fontsize=8)
    axes[1].set_ylabel("contact area at F0: tilted / aligned - 1 (%)", fontsize=8)
    axes[0].set_title("Dissipation (dashed: tolerance; open: unresolved)", fontsize=10)
    axes[1].set_title("Contact area", fontsize=10)
    fig.tight_layout()
    return {"tilt": save(fig, Path(out_dir) / "tilt.png")}


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
