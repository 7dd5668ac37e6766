"""report.md and results.json from the stored scene results (no solver calls).

The verdict of a scene compares each MDR-FE difference with the FE's own error
estimate (finest mesh against the next coarser one): a difference inside
``FE error + tolerance`` is not evidence against MDR; one beyond it is a real
departure from the half-space model (or an FE model that is not converged,
which the FE error column shows).
"""
from __future__ import annotations

import json
import os
import platform
import time
from pathlib import Path

from mdr.io import write_bytes_atomic, write_json

from . import figures
from .runner import load_scene
from .scenes import code_version

DEFAULT_TOL = 0.02


def _pct(x, digits=2):
    return "-" if x is None else f"{100 * x:+.{digits}f} %"


def _apct(x, digits=2):
    return "-" if x is None else f"{100 * abs(x):.{digits}f} %"


def _num(x, fmt=".4g"):
    return "-" if x is None else format(x, fmt)


def verdict(res: dict) -> tuple[bool | None, str]:
    """Does MDR agree with FE within the FE error plus the scene's tolerance? (holds, reason)."""
    e = res.get("errors", {})
    expect = res["scene"].get("expect") or {}
    if "validity" in res:
        return None, "see the size table"
    checks = []
    d = e.get("dissipation", {})
    if "slip_index_abs" in expect:
        si = e.get("slip_index", {})
        if si.get("mdr_minus_fe") is not None:
            tol = expect["slip_index_abs"] + (si.get("fe_error") or 0.0)
            checks.append(("slip index", abs(si["mdr_minus_fe"]), tol, False))
    else:
        tol = expect.get("dissipation", DEFAULT_TOL)
        if d.get("mdr_minus_fe") is not None:
            checks.append(("dissipation", abs(d["mdr_minus_fe"]), tol + (d.get("fe_error") or 0.0), True))
    for q in ("contact_radius", "stick_radius"):
        if q in expect and e.get(q, {}).get("mdr_minus_fe") is not None:
            checks.append((q.replace("_", " "), abs(e[q]["mdr_minus_fe"]), expect[q] + (e[q].get("fe_error") or 0), True))
    if not checks:
        return None, "no comparable quantity"
    bad = [c for c in checks if c[1] > c[2]]
    if bad:
        return False, "; ".join(f"{n} differs by {v:.2%} > {t:.2%}" if rel else f"{n} differs by {v:.3g} > {t:.3g}"
                                for n, v, t, rel in bad)
    return True, "within FE error + tolerance"


def hard_cases_cached(out, quick: bool, log=print):
    """Rows of ``validation.hard_cases.hard_cases`` (stored per code version), or None if unavailable."""
    try:
        from .hard_cases import hard_cases
    except ImportError:
        return None
    out = Path(out)
    path = out / ("hard_cases_quick.json" if quick else "hard_cases.json")
    version = code_version()
    try:
        stored = json.loads(path.read_text())
        if stored.get("code") == version:
            log("[skip] hard cases: unchanged since the last run")
            return stored["rows"]
    except (OSError, ValueError, KeyError):
        pass
    log(f"hard cases ({'quick' if quick else 'full'}) ...")
    t0 = time.perf_counter()
    rows = hard_cases(quick=quick)
    log(f"hard cases done in {time.perf_counter() - t0:.0f} s")
    write_json(path, {"code": version, "rows": rows})
    return rows


def _scene_table(res):
    m, f, cfm = res["mdr"], res["fem"], res.get("closed_form")
    e = res["errors"]
    lines = ["| quantity | MDR | FE | closed form | MDR - FE | FE own error | MDR own error |",
             "|---|---|---|---|---|---|---|"]
    units = {"contact_radius": ("um", 1e6), "stick_radius": ("um", 1e6), "dissipation": ("pJ", 1e12),
             "slip_index": ("", 1.0)}
    for q, (u, k) in units.items():
        ee = e.get(q, {})
        fmt = _pct if ee.get("kind") == "relative" else (lambda x: _num(x, "+.2e"))
        afmt = _apct if ee.get("kind") == "relative" else (lambda x: _num(None if x is None else abs(x), ".2e"))
        val = lambda r: None if r is None or r.get(q) is None else r[q] * k  # noqa: E731
        lines.append(f"| {q.replace('_', ' ')}{f' ({u})' if u else ''} | {_num(val(m))} | {_num(val(f))} | "
                     f"{_num(val(cfm) if cfm else None)} | {fmt(ee.get('mdr_minus_fe'))} | {afmt(ee.get('fe_error'))} | "
                     f"{afmt(ee.get('mdr_error'))} |")
    for q, label in (("pressure_profile", "pressure profile (L2 / peak)"),
                     ("traction_profile", "traction profile at the peak (L2 / peak)")):
        if q in e:
            lines.append(f"| {label} | | | | {_apct(e[q].get('mdr_minus_fe'))} | {_apct(e[q].get('fe_error'))} | |")
    lp = e.get("loop", {})
    for k, label in (("Fx", "loop: max abs(F_x difference) / (mu F0)"), ("du", "loop: max abs(du difference) / u_A"), ("area", "loop area")):
        if k in lp:
            lines.append(f"| {label} | | | | {_apct(lp[k].get('mdr_minus_fe'))} | {_apct(lp[k].get('fe_error'))} | |")
    if cfm:
        c = e.get("closed_form", {})
        lines.append("")
        lines.append(f"Against the closed form ({cfm['source']}):")
        lines.append("")
        lines.append("| side | contact radius | stick radius | dissipation | pressure profile | traction profile |")
        lines.append("|---|---|---|---|---|---|")
        for side in ("mdr", "fem"):
            r = c.get(side, {})
            lines.append(f"| {side.upper()} | {_pct(r.get('contact_radius'), 3)} | {_pct(r.get('stick_radius'), 3)} | "
                         f"{_pct(r.get('dissipation'), 3)} | {_apct(r.get('pressure_profile'), 3)} | "
                         f"{_apct(r.get('traction_profile'), 3)} |")
    return lines


def _ladder_table(res):
    lines = ["| side | level | DOFs / cells | runtime (s) | dissipation error vs finest FE | vs closed form |",
             "|---|---|---|---|---|---|"]
    for r in res["speed_error"]:
        lines.append(f"| {r['side'].upper()} | {r['level']} | {r['size']} | {r['runtime_s']:.3g} | "
                     f"{_pct(r['error_vs_fe'], 3)} | {_pct(r['error_vs_closed_form'], 3)} |")
    return lines


def _validity_table(res):
    lines = ["Size effect = FE of the small body against the default 200 a bodies at the same mesh (the mesh "
             "error cancels; the default is a half-space within it): the error a half-space model makes.", "",
             "| variant | DOFs | a: size effect | c: size effect | dW: size effect | a: MDR - FE | c: MDR - FE "
             "| dW: MDR - FE | bulk compliance (m/N) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in res["validity"]:
        lines.append(f"| {r['variant']} | {r['dofs']} | {_pct(r['contact_radius_vs_default'], 3)} | "
                     f"{_pct(r['stick_radius_vs_default'], 3)} | {_pct(r['dissipation_vs_default'], 3)} | "
                     f"{_pct(r['contact_radius_mdr_minus_fe'])} | {_pct(r['stick_radius_mdr_minus_fe'])} | "
                     f"{_pct(r['dissipation_mdr_minus_fe'])} | {r['bulk_compliance']:.3g} |")
    return lines


def _hard_table(rows):
    lines = ["| case | model | status | iterations | error | truth | time (s) | note |", "|---|---|---|---|---|---|---|---|"]
    def cell(x):
        return str(x).replace("|", "\\|").replace("\n", " ")

    for r in rows:
        err = r.get("error")
        lines.append(f"| {cell(r.get('name'))} | {r.get('model')} | {r.get('status')} | {_num(r.get('iterations'), '.3g')} | "
                     f"{'-' if err is None else f'{err:.2e}'} | {cell(r.get('truth', ''))} | {_num(r.get('time_s'), '.3g')} | "
                     f"{cell(r.get('note', ''))} |")
    return lines


def write_report(out, names, status: dict, *, hard_cases=None, json_path=None, quick=False) -> Path:
    """Build report.md, results.json and the summary figures from the stored scenes."""
    out = Path(out)
    results = {}
    for n in names:
        r = load_scene(out, n)
        if r is not None:
            results[n] = r
    summary_figs = {}
    geo = [r for r in results.values() if r["scene"]["group"] == "geometry" and r["scene"]["profile"] != "flat"]
    if geo:
        pts = {side: [(max(r["scene"]["b"], 1e-6), r[side].get("slip_index")) for r in geo] for side in ("mdr", "fem")}
        summary_figs["delta_b"] = figures.series_figure(pts, "b (m; the sphere plotted at 1 um)",
                                                        out / "delta_vs_b.png")
    app = [r for r in results.values() if r["scene"]["group"] == "apparatus"]
    if app:
        pts = {side: [(r["scene"]["kx"] / 1e6, r[side].get("slip_index")) for r in app] for side in ("mdr", "fem")}
        summary_figs["delta_kx"] = figures.series_figure(pts, "k_x (N/um)", out / "delta_vs_kx.png")
    # scenes that dissipate (slip index >= 0.01): a near-zero reference makes any error look tiny
    se = {n: r["speed_error"] for n, r in results.items()
          if "speed_error" in r and (r["fem"].get("slip_index") or 0.0) >= 0.01}
    if se:
        summary_figs["pareto"] = figures.save(figures.pareto_figure(se), out / "speed_error.png")

    L = ["# MDR against FE: where the half-space model holds", ""]
    L.append(f"Code version `{code_version()}`, {'quick ladders' if quick else 'full ladders'}, "
             f"{os.cpu_count()} cores, Python {platform.python_version()}. "
             "Differences are MDR minus FE at the finest level of each; *FE own error* is the finest mesh against "
             "the next coarser one (an upper estimate of the FE error), so a difference inside it is not "
             "evidence against MDR. The FE displacement is measured without the finite bodies' series "
             "compliance (`fem.law`, `displacement=\"contact\"`).")
    L.append("")
    L.append("## Summary")
    L.append("")
    L.append("| scene | FE DOFs | dissipation MDR - FE | FE own error | contact radius MDR - FE | stick radius MDR - FE "
             "| slip index MDR / FE | runtime MDR / FE (s) | MDR holds? |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    for n in names:
        st = status.get(n, "stored")
        r = results.get(n)
        if r is None:
            L.append(f"| {n} | | | | | | | | failed: {st} |")
            continue
        if "validity" in r:
            L.append(f"| [{n}](#{n}) | | | | | | | | see the size table |")
            continue
        e = r["errors"]
        ok, why = verdict(r)
        if st not in ("ok", "skipped", "stored"):
            why, ok = f"this run failed ({st}); the row shows the previous result", None
        mr = r["mdr"]["runtime_s"]
        fr = r["fem"]["runtime_s"]["total"]
        L.append(f"| [{n}](#{n}) | {r['fem']['dofs']} | {_pct(e['dissipation']['mdr_minus_fe'])} | "
                 f"{_apct(e['dissipation']['fe_error'])} | {_pct(e['contact_radius']['mdr_minus_fe'], 3)} | "
                 f"{_pct(e['stick_radius']['mdr_minus_fe'])} | {_num(r['mdr'].get('slip_index'), '.3f')} / "
                 f"{_num(r['fem'].get('slip_index'), '.3f')} | {mr:.3g} / {fr:.3g} | "
                 f"{'yes' if ok else ('no: ' + why if ok is False else why)} |")
    L.append("")
    for key, title in (("delta_b", "Slip index against b (geometry series)"),
                       ("delta_kx", "Slip index against k_x (apparatus)"),
                       ("pareto", "Speed against error, all dissipating scenes (slip index >= 0.01)")):
        if key in summary_figs:
            L += [f"### {title}", "", f"![{title}]({summary_figs[key]})", ""]
    if hard_cases:
        L += ["## Hard cases", "", *_hard_table(hard_cases), ""]
    for n in names:
        r = results.get(n)
        if r is None:
            continue
        s = r["scene"]
        d = f"scenes/{n}"
        L += [f"## {n}", "", f"**{s['title']}.** profile {s['profile']}, b = {s['b'] * 1e6:g} um, R = {s['R'] * 1e3:g} mm, "
              f"mu = {s['mu']}, F0 = {s['F0']} N, dF = {s['dF']} N, alpha = {s['alpha']:g}, drive {s['drive']} "
              f"(amplitude {s['amplitude']:g} {'N' if s['drive'] == 'force' else 'm'}"
              + (f", k_x = {s['kx'] / 1e6:g} N/um, mu2 = {s['mu2']}" if s["drive"] == "apparatus" else "")
              + f"), {s['cycles']} cycles x {s['steps']} steps; FE model {s['fe_model']}.", ""]
        if s.get("notes"):
            L += [s["notes"], ""]
        if "validity" in r:
            L += _validity_table(r) + [""]
            if "validity" in r["files"]:
                L += [f"![validity]({d}/{r['files']['validity']})", ""]
            continue
        ok, why = verdict(r)
        L += [f"MDR holds: **{'yes' if ok else 'no' if ok is False else 'n/a'}** ({why}).", ""]
        L += _scene_table(r) + [""]
        L += ["Speed against error (ladders):", ""] + _ladder_table(r) + [""]
        files = r.get("files", {})
        for key in ("loops", "profiles", "fields", "speed_error"):
            if key in files:
                L += [f"![{key}]({d}/{files[key]})", ""]
        if "fields_error" in files:
            L += [f"Field plot not rendered: {files['fields_error']}", ""]
        if "vtu" in files:
            L += [f"FE fields for ParaView: [{d}/{files['vtu']}]({d}/{files['vtu']})", ""]
    path = out / "report.md"
    write_bytes_atomic(path, "\n".join(L).encode())
    payload = {"code_version": code_version(), "quick": quick, "status": status,
               "scenes": results,
               "hard_cases": hard_cases}
    write_json(out / "results.json", payload)
    if json_path:
        write_json(json_path, payload)
    return path

