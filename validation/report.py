"""report.md and results.json from the stored scene results (no solver calls).

Every scene of the family ``pair`` carries a verdict per metric (``validation.families.pair.scene_verdicts``;
the other families' tables are their own, ``validation.families``):
MDR and FE at their finest levels, their difference, each side's error bar
extrapolated over its refinement ladder (``validation.metrics.ladder_error``) and
the scene's tolerance (``validation.scenes.TOLERANCES``). A metric holds exactly
when |MDR - FE| <= FE error + MDR error + tolerance; a metric whose numbers are
not finite is undetermined, never "holds". The scene verdict is the conjunction.
"""
from __future__ import annotations

import math
import os
import platform
import sys
from pathlib import Path

from common.io import json_bytes, write_files_atomic

from . import families, figures
from .metrics import scene_grade
from .store import load_scene
from .scenes import TOLERANCE_ORIGINS, TOLERANCES
from .sources import code_version
from .text import HOW_TO_READ, LABELS, grade_text, num, pct, sig

#: the report's summary figures (key: file name in the output folder)
SUMMARY_FIGURES = {"delta_b": "delta_vs_b.png", "delta_kx": "delta_vs_kx.png", "pareto": "speed_error.png"}
#: display units of the scalar metrics: (unit shown, factor from SI)
UNITS = {"contact_radius": ("um", 1e6), "stick_radius": ("um", 1e6), "dissipation": ("pJ", 1e12),
         "slip_index": ("", 1.0)}


def cycle_change(side: dict) -> str:
    """The last cycle's change from the one before (``mdr.loops.CycleAnalysis.last_change``): the larger
    of the loop's and the dissipation's, with '(not stationary)' above the stationarity tolerance."""
    ch = side.get("cycle_change") or {}
    vals = [v for v in (ch.get("loop"), ch.get("dissipation")) if v is not None]
    if not vals:
        return "-"
    x = max(vals)
    return num(x, ".1g") + ("" if side.get("stationary", True) else " (not stationary)")


def git_commit() -> str | None:
    """The git commit of the code ('+changes' if the tracked files differ), or None outside git."""
    import subprocess

    root = Path(__file__).resolve().parent.parent
    try:
        rev = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True,
                             timeout=10)
        if rev.returncode:
            return None
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"], cwd=root,
                               capture_output=True, text=True, timeout=10).stdout.strip()
        return rev.stdout.strip() + ("+changes" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        return None


def scene_outcome(res: dict) -> tuple[bool | None, str]:
    """The scene's verdict (the conjunction of its metrics) and the metrics that decide it: those
    that fail, else those that are undetermined, else those only consistent within a spread or
    below resolution (``validation.metrics.GRADES``)."""
    if families.of_result(res) != "pair":
        return None, "see its table"
    v = res.get("verdicts") or {}
    if not v:
        return None, "no comparable quantity"

    def named(grade):
        return [LABELS.get(q, q).split(" (")[0] for q, x in v.items() if grade_text(x) == grade_text({"grade": grade})]

    for grade, text in (("fails", "beyond error bars + tolerance"), ("undetermined", "undetermined"),
                        ("consistent within its spread", "consistent within a ladder's spread, which bounds nothing"),
                        ("below resolution", "within the resolution floor only")):
        if named(grade):
            return (False if grade == "fails" else None), f"{text}: " + ", ".join(named(grade))
    return True, f"all {len(v)} metrics within bounded error bars + tolerance"


def _reference(q, res):
    """Scale that makes a scalar metric relative in the summary (None: shown absolute)."""
    v = res["verdicts"][q]
    x = res["fem"].get("contact_radius") if q in ("contact_radius", "stick_radius") else \
        v.get("fem") if q == "dissipation" else None
    if x is None or not math.isfinite(float(x)) or float(x) == 0.0:
        return None
    return abs(float(x))


def bottom_line(res: dict) -> str:
    """A pair scene's plain bottom line: MDR - FE of each scalar metric (radii and dissipation relative to
    the FE values, the slip index absolute), how many of its verdicts are decided, and what both models
    assume."""
    v = res.get("verdicts") or {}
    parts = []
    for q in ("contact_radius", "stick_radius", "dissipation", "slip_index"):
        if q not in v or v[q].get("difference") is None or not math.isfinite(float(v[q]["difference"])):
            continue
        ref = _reference(q, res)
        d = float(v[q]["difference"])
        parts.append(f"{LABELS.get(q, q).split(' (')[0]} {num(d, '+.2g', 100.0 / ref)} %" if ref else
                     f"{LABELS.get(q, q).split(' (')[0]} {num(d, '+.2g')}")
    t = tally({"_": res}, ["_"])
    s = res.get("scene") or {}
    shared = "linear elasticity, small strains, Coulomb friction with one coefficient" + (
        ", the traction along x (Mindlin)" if s.get("fe_model", "axisym") == "axisym" else "")
    return (f"**Bottom line.** MDR - FE: {', '.join(parts) if parts else 'no scalar metric'}; {t['decided']} of "
            f"{t['total']} verdicts decided ({t['holds']} hold, {t['below resolution']} below resolution, "
            f"{t['fails']} fail). Both models assume {shared}.")


def materials_text(s: dict) -> str:
    """The scene's materials (a stored scene's fields E1, nu1, E2, nu2, the steel's where absent) and, for
    a dissimilar pair, the assumption MDR and the axisymmetric FE model share: no normal-tangential
    coupling (Dundurs' beta taken as 0; the 3D model has it)."""
    from mdr.materials import Materials

    m = Materials(*(float(s.get(k, d)) for k, d in zip(("E1", "nu1", "E2", "nu2"), Materials().as_dict().values())))
    text = f"Indenter E1 = {m.E1 / 1e9:g} GPa, nu1 = {m.nu1:g}; block E2 = {m.E2 / 1e9:g} GPa, nu2 = {m.nu2:g}."
    beta = m.dundurs_beta
    if abs(beta) > 1e-12:
        text += (f" A dissimilar pair (Dundurs' beta = {beta:+.3f}): MDR"
                 + (" and the axisymmetric FE model leave" if s.get("fe_model", "axisym") == "axisym" else " leaves")
                 + " out the normal-tangential coupling (docs/fem3d.md measures it with the 3D model).")
    return text


def tally(results: dict, names) -> dict:
    """The metric verdicts of the pair scenes among ``names``, counted by grade
    (``validation.metrics.GRADES``), with ``decided`` (holds, below resolution, fails) and ``total``."""
    from .metrics import GRADES

    out = dict.fromkeys(GRADES, 0)
    for n in names:
        r = results.get(n)
        if r is None or families.of_result(r) != "pair":
            continue
        for v in (r.get("verdicts") or {}).values():
            out[v.get("grade", "undetermined")] = out.get(v.get("grade", "undetermined"), 0) + 1
    out["decided"] = out["holds"] + out["below resolution"] + out["fails"]
    out["total"] = sum(out[g] for g in GRADES)
    return out


def tally_text(t: dict) -> str:
    """One sentence of ``tally``."""
    return (f"Decided: {t['decided']} of {t['total']} metric verdicts of the pair scenes ({t['holds']} hold, "
            f"{t['below resolution']} below resolution, {t['fails']} fail); {t['consistent within its spread']} "
            f"consistent within a spread, which bounds nothing; {t['undetermined']} undetermined.")


def summary_cell(q, res) -> str:
    """MDR - FE (FE error + MDR error + tolerance) and the metric's verdict, relative to the FE
    contact radius (radii) or the FE dissipation; the slip index absolute."""
    v = res.get("verdicts", {}).get(q)
    if v is None:
        return "-"
    ref = _reference(q, res)
    k, unit = (100.0 / ref, " %") if ref else (UNITS.get(q, ("", 1.0))[1], f" {UNITS.get(q, ('', 1.0))[0]}".rstrip())
    d = "0" if v.get("difference") == 0 else num(v.get("difference"), "+.2g", k)
    return (f"{d} ({sig(v['fem_error'], k, 2)} + {sig(v['mdr_error'], k, 2)} + {sig(v['tolerance'], k, 2)}){unit}: "
            f"{grade_text(v).replace('consistent within its spread', 'consistent (spread)')}")


def _scene_table(res):
    """Every metric with both values, the difference, both error bars (ladder status and observed
    order), the tolerance and the verdict, in one unit per row."""
    cfm = res.get("closed_form")
    lines = ["| metric | unit | MDR | FE | closed form | MDR - FE | FE error | MDR error | tolerance | holds |",
             "|---|---|---|---|---|---|---|---|---|---|"]

    def err(v, side, k):
        ld = v[f"{side}_ladder"]
        return "0" if ld.get("status") == "converged" else sig(v[f"{side}_error"], k, 2)

    def bar(ld):
        if ld.get("error") is None:
            return f" ({ld.get('status')})"
        o = ld.get("order")
        order = "" if o is None or ld.get("status") != "asymptotic" else ", p = " + num(o, ".2g")
        model = f": {ld['model']}" if ld.get("status") == "calibrated" and ld.get("model") else ""
        return f" ({ld.get('status')}{order}{model})"

    def tol_origin(v):
        fl, tl = v.get("floor"), v.get("tolerance")
        return " (floor)" if fl is not None and tl is not None and fl >= tl else ""

    for q, v in res.get("verdicts", {}).items():
        unit, k = UNITS.get(q, (v.get("unit", ""), 1.0))
        cf = None if not cfm or q not in UNITS or cfm.get(q) is None else cfm[q] * k
        lines.append(f"| {LABELS.get(q, q)} | {unit or v.get('unit', '')} | {sig(v['mdr'], k, 5)} | {sig(v['fem'], k, 5)} | "
                     f"{sig(cf, 1.0, 5)} | {sig(v['difference'], k)} | {err(v, 'fem', k)}{bar(v['fem_ladder'])} | "
                     f"{err(v, 'mdr', k)}{bar(v['mdr_ladder'])} | {sig(v['tolerance'], k, 2)}{tol_origin(v)} | {grade_text(v)} |")
    if cfm:
        c = res["errors"].get("closed_form", {})
        lines += ["", f"Against the closed form ({cfm['source']}):", "",
                  "| side | contact radius | stick radius | dissipation | pressure profile | traction profile |",
                  "|---|---|---|---|---|---|"]
        for side in ("mdr", "fem"):
            r = c.get(side, {})
            lines.append(f"| {side.upper()} | {pct(r.get('contact_radius'), 3)} | {pct(r.get('stick_radius'), 3)} | "
                         f"{pct(r.get('dissipation'), 3)} | {sig(r.get('pressure_profile'), 100, 2)} % | "
                         f"{sig(r.get('traction_profile'), 100, 2)} % |")
    return lines


def _error_parts_lines(res):
    """Where the time step joins an error bar: each side's share of the dissipation's."""
    v = (res.get("verdicts") or {}).get("dissipation") or {}
    parts = v.get("error_parts") or {}
    if not any("time step" in p for p in parts.values()):
        return []
    cells = []
    for side in ("mdr", "fem"):
        p = parts.get(side) or {}
        cells.append(("MDR " if side == "mdr" else "FE ") + " + ".join(f"{name} {sig(x, 1e12, 2)}" for name, x in p.items()) + " pJ")
    return ["Dissipation error bars by origin: " + "; ".join(cells) + ".", ""]


def _time_step_lines(res):
    """The time step's share of the dissipation error of each side (``validation.sides.time_step_error``),
    part of the error bars above; sentences generated from the numbers they describe."""
    ts = res.get("errors", {}).get("time_step")
    if not ts:
        return []

    def side(name, t):
        if not t:
            return f"{name}: not computed"
        if t.get("shift") is None:
            return f"{name}: no extrapolation ({t['status']})"
        x = abs(t["shift"])
        order = "" if t.get("order") is None else f", observed order {num(t.get('order'), '.2g')}"
        if x == 0:
            return f"{name}'s dissipation does not change with the step ({t.get('status')}{order})"
        size = f"{num(x, '.2g', 100)} %" if t.get("shift_unit", "relative") == "relative" else f"{num(x, '.2g')} of 4 mu F0 u_A"
        return (f"{name}'s dissipation at the scene's step is {size} {'below' if t['shift'] > 0 else 'above'} its "
                f"extrapolation ({t.get('status')}{order})")

    steps = ", ".join(str(k) for k in (ts.get("mdr") or {}).get("steps") or [])
    line = (f"Time step (the finest levels at {steps} steps per cycle): {side('MDR', ts.get('mdr'))}; "
            f"{side('FE', ts.get('fem'))}. Each side's time-step error bar (this ladder's) is part of its error "
            "bar on the dissipation and the slip index above.")
    sm, sf = ((ts.get(k) or {}).get("shift") for k in ("mdr", "fem"))
    units = {(ts.get(k) or {}).get("shift_unit", "relative") for k in ("mdr", "fem")}
    if sm is not None and sf is not None and units == {"relative"}:
        line += (f" Both extrapolated in time, MDR - FE would move by {pct(sm - sf, 3)} of the dissipation"
                 + (" (the two shifts agree within 1e-5)" if abs(sm - sf) < 1e-5 else "") + ".")
    Wc = (res.get("closed_form") or {}).get("dissipation")
    if ts["mdr"].get("extrapolated") is not None and Wc:
        line += (f" MDR's extrapolated dissipation against the closed form: "
                 f"{pct(ts['mdr']['extrapolated'] / Wc - 1, 3)}.")
    return [line, ""]


def _ladder_table(res):
    lines = ["| side | level | DOFs / cells | runtime (s) | dissipation error vs finest FE | vs closed form |",
             "|---|---|---|---|---|---|"]
    for r in res["speed_error"]:
        lines.append(f"| {r['side'].upper()} | {r['level']} | {r['size']} | {num(r.get('runtime_s'))} | "
                     f"{pct(r['error_vs_fe'], 3)} | {pct(r['error_vs_closed_form'], 3)} |")
    return lines


def _witness_lines(results) -> list:
    """The CalculiX witness (``validation.calculix``): per block/cap geometry both codes' relative
    difference at the fine level with each code's error bar, whether they agree within both, and the
    run times side by side."""
    from .calculix import agrees

    L = ["## Independent FE code: CalculiX", "",
         "The same finite bodies (frictionless normal contact of the sphere R = 6 mm at 0.5 N on blocks and "
         "caps of the sizes below, in contact radii) in CalculiX 2.20 (CAX8, surface-to-surface penalty "
         "contact; its own mesh and solver) and in the project's `fem normal`, each at two mesh levels "
         "(a/40 and a/80 with half the grading); *diff* = (CalculiX - project) / project at the fine level, "
         "*bars* = each code's change between the levels (CalculiX + project); it agrees where |diff| <= "
         "both bars + CalculiX's penalty error. p0 and a from the same fit of p^2 against r^2 "
         "(0.25-0.7 a) on both sides. Run time: one run at the fine level, serial.", "",
         "| block / cap | approach: diff (bars) | p0: diff (bars) | contact radius: diff (bars) | agree? "
         "| CalculiX (s) | project (s) | ratio |", "|---|---|---|---|---|---|---|---|"]

    def cell(c):
        return f"{num(c.get('diff'), '+.1e')} ({num(c.get('bar_calculix'), '.1e')} + {num(c.get('bar_fem'), '.1e')})"

    for res in results:
        g, cmp_ = res.get("geometry") or {}, res.get("compare") or {}
        fine = (res.get("runs") or [{}])[-1]
        ok = agrees(res)
        verdict_ = "yes" if all(ok.get(q) for q in ("approach", "p0", "contact_radius")) else \
            ("**no**" if any(ok.get(q) is False for q in ("approach", "p0", "contact_radius")) else "undetermined")
        tc = ((fine.get("calculix") or {}).get("runtime_s") or {}).get("total")
        tf = ((fine.get("fem") or {}).get("runtime_s") or {}).get("total")
        L.append(f"| {num(g.get('block'), 'g')} / {num(g.get('cap'), 'g')} | {cell(cmp_.get('approach') or {})} | "
                 f"{cell(cmp_.get('p0') or {})} | {cell(cmp_.get('contact_radius') or {})} | {verdict_} | "
                 f"{num(tc, '.1f')} | {num(tf, '.2f')} | {num(fine.get('runtime_ratio'), '.0f')} |")
    return L + [""]


def _hard_table(rows):
    lines = ["| case | model | status | iterations | error | tolerance | truth | time (s) | note |",
             "|---|---|---|---|---|---|---|---|---|"]
    def cell(x):
        return str(x).replace("|", "\\|").replace("\n", " ")

    for r in rows:
        err = r.get("error")
        lines.append(f"| {cell(r.get('name'))} | {r.get('model')} | {r.get('status')} | {num(r.get('iterations'), '.3g')} | "
                     f"{num(err, '.2e')} | {sig(r.get('tol'), 1.0, 2)} | {cell(r.get('truth', ''))} | "
                     f"{num(r.get('time_s'), '.3g')} | "
                     f"{cell(r.get('note', ''))} |")
    return lines


def write_report(out, names, status: dict, *, hard_cases=None, json_path=None, quick=False,
                 executor: str | None = None, hard_cases_note: str | None = None, witness=None) -> Path:
    """Build report.md, results.json and the summary figures from the stored scenes.

    ``executor``: where this run's scenes ran (``common.executors.executor_for`` label); each
    stored scene keeps the ``worker`` that computed it. The report is rendered in full before any
    file is written; then the summary figures, and report.md, results.json and ``json_path`` are
    staged and renamed into place together (``common.io.write_files_atomic``, report.md last): a failure
    while rendering leaves the previous report and its figures intact."""
    out = Path(out)
    results = {}
    for n in names:
        r = load_scene(out, n)
        if r is not None:
            results[n] = r
    # the summary figures: what each plots, decided first, drawn only once the report has rendered
    plots = {}
    geo = [r for r in results.values() if r["scene"]["group"] == "geometry" and r["scene"]["profile"] != "flat"]
    if geo:
        pts = {side: [(max(r["scene"]["b"], 1e-6), r[side].get("slip_index")) for r in geo] for side in ("mdr", "fem")}
        label = "b (m; the sphere plotted at 1 um)" if any(r["scene"]["b"] == 0 for r in geo) else "b (m)"
        plots["delta_b"] = lambda path, pts=pts, label=label: figures.series_figure(pts, label, path)
    app = [r for r in results.values() if r["scene"]["group"] == "apparatus"]
    if app:
        pts = {side: [(r["scene"]["kx"] / 1e6, r[side].get("slip_index")) for r in app] for side in ("mdr", "fem")}
        plots["delta_kx"] = lambda path, pts=pts: figures.series_figure(pts, "k_x (N/um)", path)
    # scenes that dissipate (slip index >= 0.01): a near-zero reference makes any error look tiny
    se = [p for r in results.values() if "speed_error" in r and (r["fem"].get("slip_index") or 0.0) >= 0.01
          for p in figures.speed_error_points(r)]
    if se:
        plots["pareto"] = lambda path: figures.save(figures.speed_error_figure(
            se, "ladders against the closed form (solid) or their own extrapolation (dashed)\n"
                "(median over the scenes of a group at each level)"), path)
    summary_figs = {key: SUMMARY_FIGURES[key] for key in plots}

    commit = git_commit()
    text = render_report(results, names, status, summary_figs=summary_figs, hard_cases=hard_cases, quick=quick,
                         executor=executor, commit=commit, hard_cases_note=hard_cases_note, witness=witness)
    payload = {"code_version": code_version(), "git_commit": commit, "quick": quick, "executor": executor,
               "status": status, "scenes": results,
               "hard_cases": hard_cases, "hard_cases_rerun": hard_cases_note is None, "witness_calculix": witness}
    path = out / "report.md"
    data = json_bytes(payload)
    files = {out / "results.json": data}
    if json_path and str(json_path) != "-":
        files[Path(json_path)] = data
    files[path] = text.encode()  # renamed last: a report.md on disk always has its results.json
    for key, draw in plots.items():  # each written atomically (figures.save)
        draw(out / SUMMARY_FIGURES[key])
    write_files_atomic(files)
    # a summary figure of an earlier run that this report does not show would be left unreferenced
    for key, fname in SUMMARY_FIGURES.items():
        if key not in summary_figs and (out / fname).exists():
            (out / fname).unlink()
    if str(json_path) == "-":
        sys.stdout.buffer.write(files[out / "results.json"])
        sys.stdout.flush()
    return path


def render_report(results: dict, names, status: dict, *, summary_figs=None, hard_cases=None, quick=False,
                  executor: str | None = None, commit: str | None = None, hard_cases_note: str | None = None,
                  witness=None) -> str:
    """report.md's text from the scene results (plain dicts, as stored): no file, no solver. Renders
    any value a result can hold (None, NaN, inf, 0, negative; a ladder of any status)."""
    summary_figs = summary_figs or {}
    L = ["# MDR against FE: where the half-space model holds", ""]
    L.append(f"Code {'commit `' + commit + '`, ' if commit else ''}sources `{code_version()}`, "
             f"{'quick ladders' if quick else 'full ladders'}, {os.cpu_count()} cores, "
             f"Python {platform.python_version()}"
             + (f"; scenes of this run on executor `{executor}`" if executor else "") + ".")
    L.append("")
    L.append(HOW_TO_READ)
    L.append("")
    L += ["Tolerances and their origin:", ""] + [f"- {LABELS.get(q, q)}: {TOLERANCES[q]:g}, {o}"
                                                for q, o in TOLERANCE_ORIGINS.items()]
    L.append("")
    L.append("## Summary")
    L.append("")
    L.append("| scene | FE DOFs | contact radius | stick radius | dissipation | slip index MDR / FE "
             "| last-cycle change MDR / FE | runtime MDR / FE (s) | grade |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    for n in names:
        st = status.get(n, "stored")
        r = results.get(n)
        if r is None:
            L.append(f"| {n} | | | | | | | | failed: {st} |")
            continue
        if families.of_result(r) != "pair":
            L.append(f"| [{n}](#{n}) | | | | | | | | see its table |")
            continue
        ok, why = scene_outcome(r)
        text = {True: "**holds**", False: f"**fails**: {why}", None: why}[ok]
        if st not in ("ok", "skipped", "stored"):
            text = f"this run failed ({st}); the row shows the previous result"
        mr = r["mdr"].get("runtime_s")
        fr = (r["fem"].get("runtime_s") or {}).get("total")
        L.append(f"| [{n}](#{n}) | {r['fem']['dofs']} | {summary_cell('contact_radius', r)} | "
                 f"{summary_cell('stick_radius', r)} | {summary_cell('dissipation', r)} | "
                 f"{num(r['mdr'].get('slip_index'), '.3f')} / {num(r['fem'].get('slip_index'), '.3f')} | "
                 f"{cycle_change(r['mdr'])} / {cycle_change(r['fem'])} | {num(mr, '.2g')} / {num(fr, '.2g')} | {text} |")
    L += ["", tally_text(tally(results, names)), ""]
    for key, title in (("delta_b", "Slip index against b (geometry series)"),
                       ("delta_kx", "Slip index against k_x (apparatus)"),
                       ("pareto", "Speed against error, the dissipating scenes (slip index >= 0.01) by group")):
        if key in summary_figs:
            L += [f"### {title}", "", f"![{title}]({summary_figs[key]})", ""]
    for n in names:
        r = results.get(n)
        if r is None:
            continue
        s = r["scene"]
        d = f"scenes/{n}"
        L += [f"## {n}", "", f"**{s['title']}.** profile {s['profile']}, b = {s['b'] * 1e6:g} um, R = {s['R'] * 1e3:g} mm, "
              f"mu = {s['mu']:g}, F0 = {s['F0']:.4g} N, dF = {s['dF']:.4g} N, alpha = {s['alpha']:g}, drive {s['drive']} "
              f"(amplitude {s['amplitude']:g} {'N' if s['drive'] == 'force' else 'm'}"
              + (f", k_x = {s['kx'] / 1e6:g} N/um, mu2 = {s['mu2']:g}" if s["drive"] == "apparatus" else "")
              + f"), {s['cycles']} cycles x {s['steps']} steps; FE model {s['fe_model']}"
              + (f"; computed on worker `{r['worker']}`" if r.get("worker") else "") + ". " + materials_text(s), ""]
        if s.get("notes"):
            L += [s["notes"], ""]
        fam = families.of_result(r)
        if fam != "pair":
            mod = families.module(fam)
            L += mod.table(r) + [""]
            if mod.KEY in r.get("files", {}):
                L += [f"![{mod.TITLE}]({d}/{r['files'][mod.KEY]})", ""]
            continue
        ok, why = scene_outcome(r)
        L += [bottom_line(r), ""]
        L += [f"Verdict: **{grade_text({'grade': scene_grade(r.get('verdicts') or {})}).strip('*')}** ({why}).", ""]
        L += _error_parts_lines(r)
        L += _scene_table(r) + [""]
        L += _time_step_lines(r)
        L += ["Speed against error (ladders):", ""] + _ladder_table(r) + [""]
        files = r.get("files", {})
        for key in ("loops", "profiles", "fields", "speed_error"):
            if key in files:
                L += [f"![{key}]({d}/{files[key]})", ""]
        if "fields_error" in files:
            L += [f"Field plot not rendered: {files['fields_error']}", ""]
        if "vtu" in files:
            L += [f"FE fields for ParaView: [{d}/{files['vtu']}]({d}/{files['vtu']})", ""]
    if witness:
        L += _witness_lines(witness)
    if hard_cases:
        L += ["## Hard cases", "",
              "Numerical stability, each case against an independent truth (closed forms, energy "
              "conservation, refinement; the *truth* column names it). *status*: ok (the error within the "
              "case's tolerance, 2-3x the error measured when it was set), flagged (the model itself warned or "
              "reported the case doubtful, e.g. a deliberately soft penalty or coarse mesh, or the error is "
              "above the tolerance: expected in the rows that test those warnings), error (an exception; the "
              "note holds it). *iterations*: the mean active-set (Newton) iterations per step of the FE solver; "
              "for an MDR row in the apparatus the mean evaluations per step of its equilibrium search (the "
              "MDR law itself is explicit). *error*: relative unless the truth says otherwise; none when the "
              "case produced no number (a detected non-convergence, in the note).", "",
              *([hard_cases_note, ""] if hard_cases_note else []),
              *_hard_table(hard_cases), ""]
    return "\n".join(L)
