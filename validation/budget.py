"""The error budget of MDR in a fretting apparatus: what each of its assumptions costs each result.

``python -m validation.budget [--out DIR]`` prints (and writes to ``DIR/budget.md``) the budget of the
paper, Willert, Machines 11 (2023) 484: a row per result (the loops of Figs. 4-5 on the sphere and of
Figs. 6-7 on the truncated sphere b = 0.6 mm, the slip-index curves of Figs. 8 and 9, the Table 2
point), a column per assumption of the half-space MDR model in the apparatus, each cell the change of the
result's slip index (its dissipation per cycle over 4 mu F0 u_A, what Figs. 8-9 plot and the loops of
Figs. 4-7 enclose) when the assumption is dropped, with its error bar, where it was measured, and a
verdict against the resolution (``validation.budget_cells``: ``verdict``, ``grade``):

- ``negligible``: |effect| + error <= resolution;
- ``matters``: |effect| - error > resolution (a measured effect, not a bound); a *range* over readings
  of an input left open matters only where all of it, with its error, lies beyond the resolution on one
  side (``validation.budget_readings.grade_range``);
- ``undetermined``: in between, a bound above the resolution, a range that reaches across it, or not
  measured at the result's conditions (the cell says what would measure it).

``python -m validation.budget --scene-file RIG.toml`` does the same for a rig of one's own
(``validation.rig``): it runs the scenes that measure the rig's cells (``validation.rig_budget``; each
skipped while unchanged) into ``--out`` and writes ``budget-<rig name>.md`` there. Both read their cells
by one code path (``validation.budget_cells``, with the rig's ``Inputs``: the catalogue's scenes for the
paper, the generated ones for a rig).

Where the cells come from (``COLUMNS``; the paper's scenes named, a rig's are ``<name>-<kind>``):

- *half-space size*: the ``validity`` scene's rows (the block and the cap shrunk, against the FE model's
  default bodies on the same mesh); the effect falls with either body's size, so a row of bodies no
  larger than the point's is a *bound*. The cap is the whole sphere in the paper (and wherever it
  reaches the equator): the FE model's own, its effect in the curvature cell;
- *curvature*: measured at each point itself, the axisymmetric FE model (the cap's real sphere)
  against MDR in the apparatus there (``measured_in_apparatus``: the experiment scenes, the k_x
  series, ``halfspace-points``), a change of the slip index; where none is stored, bounded by the
  sphere's ``validity-curvature`` row at the next larger a/R;
- *traction direction*: the 3D model at each point in the apparatus (``direction-points``), else the
  force-control row of ``assumptions-3d``;
- *coupling*: exactly 0 for one material (Dundurs' beta = 0, the paper's steel on steel); a dissimilar
  pair's from the 3D model with and without the coupling (a rig's ``<name>-coupling``);
- *tilt*: the face tilted by the stated bound at each point in the apparatus (``tilt-points``); a bound, since the bound is an inequality
  ("less than pi/3600"); the sphere exactly 0 (a tilted sphere is the same sphere displaced);
- *roughness* and *plates*: computed here (``validation.budget_readings``): ranges over the readings of
  the paper's stated rms values (``validation.spectra``) and of its brass plates that the paper's own
  loops admit (``validation.consistency``), MDR in the apparatus at every point (the roughness through
  each surface's equivalent profile, its error including what that misses of the rough half-space in
  the catalogue's scenes ``roughness`` and ``roughness-faces``). A rig of one's own: the plates over
  every reading unless it states its ``plate_model`` (then exactly 0); the roughness over every reading
  of its own rms values on its own contacts (``rig_budget.rough_contacts``; plastic readings where it
  states a hardness; the one reading of its stated spectrum or measured maps where it gives them), the equivalent profile's error measured in its apparatus on the readings' own
  surfaces (``validation.rig_roughness``);
- *kink rounding*: computed here with the MDR apparatus at every point: the fillet of the kink
  (``mdr.profiles.RoundedTruncatedSphere``, of the stated widest rounding; the paper's "less than the
  rms roughness", ``budget_cells.FILLET_MAX``) against the sharp kink, a bound.

Assumptions of the mapping (stated in the table's notes): an effect measured under force control is
applied as the same relative change of the apparatus's dissipation, i.e. times the point's slip index
(MDR in the apparatus, ``point_slip_index``), except the tilt's, measured as a change of the slip index
itself (the aligned face hardly slips there), and the curvature's, the direction's, the roughness's and
the plates', changes of the slip index in the apparatus; a result spanning a range of b (Figs. 8, 9,
Table 2's two points) is "negligible" only if every b of its range is covered, and "matters" as soon as
one measured point of it does.
"""
from __future__ import annotations

import sys
from pathlib import Path

from .budget_cells import (Inputs, cell, combine, coupling_cell, curvature_cell, direction_cell, grade, kink_cell,
                           paper_inputs, scaled, size_cell, tilt_cell)
from .paper_points import RESOLUTION_ORIGIN, point_slip_index
from .sources import code_version
from .store import load_scene
from .text import num

COLUMNS = ("size", "curvature", "direction", "coupling", "tilt", "roughness", "kink", "plates")
TITLES = {"size": "half-space size", "curvature": "curvature a/R", "direction": "traction direction",
          "coupling": "coupling", "tilt": "tilt at its stated bound", "roughness": "roughness (admitted readings)",
          "kink": "kink rounding", "plates": "brass plates' reading"}
#: a result's cell over several points names where it comes from: the column's title, or this
SOURCES = {"kink": "MDR apparatus", "plates": "MDR apparatus"}


# --------------------------------------------------------------------------- the table
def budget(out="results", *, inp: Inputs | None = None, mdr_cells: bool = True, log=None, jobs: int = 1,
           members: list | None = None, readings_dir=None, executor=None) -> dict:
    """The budget of the rig ``inp`` (default the paper's, ``paper_inputs``) from the scenes stored under
    the folder ``out`` (or a dict of results by scene name, results.json's ``scenes``; a missing scene's
    cells are undetermined, naming the command that measures them) and, with ``mdr_cells``, the cells
    computed here: the kink, the plates and, for the paper, the roughness readings (their surfaces'
    curves from ``members`` where given, else ``validation.spectra.curves`` in ``jobs`` processes or on
    ``executor`` (as every surface's run here), cached
    under ``out``/readings or ``readings_dir``), the paper's loops against them and against the plates'
    readings, and the sticking transition. Every cell graded against the rig's resolution. Returns
    {"rig", "rows": [{key, title, slip_index, cells: {column: cell}}], "stale": [scene names stored by
    other sources], "resolution", and for the paper "consistency", "plates_consistency", "transition"}."""
    from . import budget_plates as BP
    from . import budget_readings as BR

    inp = inp or paper_inputs()
    log = log or (lambda msg: None)
    version, stale, cache = code_version(), [], {}
    by_name = {s.name: s for s in inp.scenes}

    def store(name):
        """A stored scene's result; one of other sources is listed stale and, for a rig of one's own (whose
        scenes this command has just run), not read: a scene that failed to rerun after an edit leaves
        its cells undetermined, not the numbers of the rig before the edit."""
        if name not in cache:
            res = out.get(name) if isinstance(out, dict) else load_scene(out, name)
            if res is not None and name in by_name and res.get("fingerprint") != by_name[name].fingerprint(version):
                stale.append(name)
                res = res if inp.paper else None
            cache[name] = res
        return cache[name]

    result = {"rig": inp.name, "paper": inp.paper, "stale": [], "resolution": inp.resolution, "tilt": inp.tilt}
    if mdr_cells and inp.paper:
        if members is None:
            from .spectra import curves

            folder = readings_dir if isinstance(out, dict) else Path(out) / "readings"
            members = curves(inp.contacts, folder, jobs=jobs, log=log, executor=executor)
        R = BR.Readings(members, inp.contacts)
        result["consistency"] = BR.consistency(R, log, jobs, executor=executor)
        admitted = BR.admitted_names(result["consistency"])
        result["plates_consistency"] = BP.consistency(log)
        plates_ok = {r["reading"] for r in result["plates_consistency"] if r["admitted"]}
        eq_error = BR.equivalent_error(store)
    elif mdr_cells:
        plates_stated = "plate_model" in inp.setup.app_kw
        R, eq_error, admitted, plates_ok = None, None, None, None
        if inp.contacts:
            R, result["equivalent"] = _rig_readings(inp, out, jobs, log, executor)
            eq_error = result["equivalent"]["error"]
        if inp.loops and R is not None:
            result["consistency"] = BR.consistency(R, log, jobs, inp.loops, executor=executor)
            admitted = BR.admitted_names(result["consistency"])
        if inp.loops and not plates_stated:
            result["plates_consistency"] = BP.consistency(log, inp.loops, inp.setup)
            plates_ok = {r["reading"] for r in result["plates_consistency"] if r["admitted"]}
    rows = []
    for r in inp.results:
        log(f"budget: {r.title}")
        si = [point_slip_index(p, setup=inp.setup) for p in r.points]
        per = {col: [scaled(fun(p, store, inp), x) for p, x in zip(r.points, si)]
               for col, fun in (("size", size_cell), ("curvature", curvature_cell), ("direction", direction_cell),
                                ("coupling", coupling_cell))}
        per["tilt"] = [tilt_cell(p, store, inp) for p in r.points]
        if mdr_cells:
            per["kink"] = [kink_cell(p, inp) for p in r.points]
            if inp.paper:
                per["roughness"] = [BR.roughness_cell(p, R, admitted, eq_error) for p in r.points]
                per["plates"] = [BP.cell(p, plates_ok) for p in r.points]
            else:
                per["roughness"] = [BR.rig_roughness_cell(p, R, eq_error, admitted) for p in r.points]
                per["plates"] = [cell(0.0, 0.0, "exact", "the rig", "the plates' reading stated") if plates_stated
                                 else BP.cell(p, plates_ok, inp.setup, "plates" if plates_ok is not None else
                                              "plates, none stated") for p in r.points]
        labels = _point_labels(r.points)
        cells = {col: combine([_at(grade(c, inp.resolution), lab) for c, lab in zip(cs, labels)],
                              SOURCES.get(col, TITLES[col])) for col, cs in per.items()}
        rows.append({"key": r.key, "title": r.title, "slip_index": [min(si), max(si)],
                     "cells": {c: cells[c] for c in COLUMNS if c in cells}})
    result.update(rows=rows, stale=sorted(set(stale)))
    if mdr_cells and inp.paper:
        log("budget: the sticking transition")
        result["transition"] = BR.transitions(R, admitted)
    return result


def _point_labels(points) -> list:
    """Each point of a result named by the fields its points differ in ('' for a result of one point)."""
    if len(points) < 2:
        return [""] * len(points)
    units = {"b": (1e6, "um"), "F0": (1.0, "N"), "dF": (1.0, "N"), "ua": (1e9, "nm"), "mu1": (1.0, ""),
             "mu2": (1.0, ""), "kx": (1e-6, "N/um")}
    vary = [k for k in units if len({getattr(p, k) for p in points}) > 1]
    return [", ".join(f"{k} = {getattr(p, k) * units[k][0]:.3g}{(' ' + units[k][1]) if units[k][1] else ''}"
                      for k in vary) for p in points]


def _at(c: dict, label: str) -> dict:
    """The cell with its point's label leading its note (a result of several points; an exact cell is the
    same at every point and keeps its note)."""
    if not label or c.get("kind") == "exact":
        return c
    return {**c, "note": f"at {label}: {c['note']}" if c.get("note") else f"at {label}"}


def _rig_readings(inp: Inputs, out, jobs: int, log, executor=None) -> tuple:
    """A rig's roughness readings on its contacts (``validation.spectra.curves``) and the equivalent
    profile's error in its apparatus (``validation.rig_roughness``), both cached under ``out``/readings."""
    from . import budget_readings as BR
    from .paper_points import rough_row_b
    from .rig_roughness import equivalent_error
    from .spectra import curves

    folder = Path(out) / "readings"
    members = curves(inp.contacts, folder, jobs=jobs, log=log, executor=executor)
    points = {}
    for r in inp.results:
        for p in r.points:
            here = points.setdefault(rough_row_b(p, inp.setup), [])
            if p not in here:
                here.append(p)
    return BR.Readings(members, inp.contacts, inp.setup), equivalent_error(
        inp.contacts, members, points, folder, apparatus=inp.setup.apparatus, jobs=jobs, log=log,
        executor=executor)


def cell_text(c: dict) -> str:
    if c["effect"] is None:
        return f"undetermined ({c['note'] or c['source']})"
    if c["kind"] == "bound":
        body = f"<= {num(abs(c['effect']) + c['error'], '.2g')}"
    elif c["kind"] == "exact":
        body = f"{num(c['effect'], 'g')} (exact)"
    elif c["kind"] == "range":
        lo, hi = c["range"]
        body = f"{num(lo, '+.2g')} to {num(hi, '+.2g')} +- {num(c['error'], '.2g')}"
    else:
        body = f"{num(c['effect'], '+.2g')} +- {num(c['error'], '.2g')}"
    verdict = {"negligible": "negligible", "matters": "**matters**"}.get(c["verdict"], "undetermined")
    return f"{body}: {verdict}" + (f" ({c['note']})" if c["note"] else "")


def markdown(b: dict) -> list:
    from .budget_readings import readings_markdown

    cols = [c for c in COLUMNS if any(c in r["cells"] for r in b["rows"])]
    paper = b.get("paper", True)
    what = "the paper's" if paper else f"the rig {b['rig']}'s"
    tilt = "pi/3600" if paper else (None if b.get("tilt") is None else num(b["tilt"], ".3g") + " rad")
    titles = {**TITLES, "tilt": TITLES["tilt"] if tilt is None else f"tilt <= {tilt}"}
    if not paper:
        titles.update(plates="plates' reading", roughness="roughness (admitted readings)" if b.get("consistency")
                      else "roughness (readings)")
    lines = [f"The change of each result's slip index when an assumption of MDR in {what} apparatus is dropped, "
             f"with its error bar, against the resolution of {b['resolution']:g}"
             + (f" ({RESOLUTION_ORIGIN}). " if paper else " of the slip index (1: gross slip). ")
             + "'<=': a bound (the change lies between 0 and it: never 'matters'). 'lo to hi': a range over the "
             + ("readings of an input the paper leaves open that its own loops admit (the roughness spectrum, the "
                "brass plates)" if paper else "readings of an input the rig leaves open (the plates' reading where "
                "it states none)")
             + ", graded 'matters' only where all of it lies beyond the resolution on one side. Effects measured on "
             f"the dissipation under force control at {'Table 2' if paper else 'the rig'}'s load count as the same "
             "relative change of the result's slip index (its range in the second column, MDR in the "
             "apparatus). A result over several points shows the point that decides; it is negligible only "
             "where every point is, and matters where one measured point does (the point shown first in its note). "
             "'undetermined': the change with its bar reaches across the resolution, is a bound above it, or was "
             "not measured (the note says which; docs/budget.md, 'Your own rig', says what resolves it).", "",
             "| result | slip index | " + " | ".join(titles[c] for c in cols) + " |",
             "|---|---|" + "---|" * len(cols)]
    for r in b["rows"]:
        lo, hi = r["slip_index"]
        span = num(lo, ".2g") if abs(hi - lo) <= 1e-3 * max(abs(hi), 1e-12) else f"{num(lo, '.2g')}-{num(hi, '.2g')}"
        lines.append(f"| {r['title']} | {span} | " + " | ".join(cell_text(r["cells"][c]) if c in r["cells"] else "-"
                                                                 for c in cols) + " |")
    eq = b.get("equivalent")
    if eq:
        lines += ["", f"What MDR with an equivalent profile misses of the rough half-space in the rig's apparatus "
                      f"(validation.rig_roughness: the readings' surfaces driven there, {len(eq['rows'])} readings x "
                      f"points): at most {num(eq['error'], '.2g')} of the slip index (|mean| + standard error), "
                      "part of every roughness cell's bar."]
    lines += readings_markdown(b)
    if b["stale"]:
        lines += ["", f"Stored by other sources than these{'' if paper else ', not read'} (rerun them): "
                      f"{', '.join(b['stale'])}."]
    return lines


PROG = "python -m validation.budget"


def build_parser():
    from common.cli import OneLineParser

    p = OneLineParser(prog=PROG,
                      description="The error budget of MDR in a fretting apparatus: for each result, the measured "
                                  "cost of every assumption. Without --scene-file the paper's (Willert 2023), from the "
                                  "scenes stored by python -m validation.compare in --out (the kink and plates "
                                  "computed here with MDR, about a minute); with --scene-file a rig of your own: its "
                                  "scenes run first (each skipped while unchanged).")
    p.add_argument("--scene-file", metavar="RIG.toml",
                   help="the budget of your own rig (validation.rig: indenter, materials, bodies, loading, apparatus, "
                        "tolerances, results; example docs/examples/my_rig.toml): runs the scenes that measure its "
                        "cells into --out and writes budget-<rig name>.md there")
    p.add_argument("--out", default="results", metavar="DIR",
                   help="the comparison's output directory (default ./results); the budget's table is written there")
    p.add_argument("--json", metavar="PATH", help="also write the budget as JSON to PATH ('-' = stdout)")
    p.add_argument("--no-mdr", action="store_true",
                   help="leave out the cells computed here: roughness, kink, plates, the paper's loops as a check "
                        "and the sticking transition (the rest still runs MDR for each point's slip index)")
    p.add_argument("--jobs", type=int, default=1, metavar="N",
                   help="processes for a rig's scenes and for the roughness readings' surfaces (default 1; both "
                        "cached under --out, so a second run reads them)")
    p.add_argument("--force", action="store_true",
                   help="with --scene-file: rerun the rig's scenes even where they are unchanged")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run a rig's scenes and the roughness readings' surfaces on the workers of a running Dask "
                        "scheduler (e.g. tcp://host:8786; needs the dist extra; excludes --jobs)")
    return p


def _checked(args):
    """The arguments checked before any work (InputError: one line): the rig (``validation.rig.load_rig``)
    and its scenes, or a folder of stored scenes; the outputs writable; --jobs and --scheduler."""
    from common.executors import check_choice
    from common.io import check_output_dir, check_output_path

    from common.errors import InputError

    if args.json not in (None, "-"):
        check_output_path(args.json, "--json")
    check_choice(args.jobs, args.scheduler)
    if args.scene_file is None:
        if args.force:
            raise InputError("--force reruns a rig's scenes: give it with --scene-file")
        if not (Path(args.out) / "scenes").is_dir():
            raise InputError(f"--out {args.out!r} holds no stored scenes: run python -m validation.compare "
                             f"--out {args.out} first, or give --scene-file RIG.toml")
        return None
    from .rig import load_rig
    from .rig_budget import inputs

    rig = load_rig(args.scene_file)
    check_output_dir(args.out, "--out")
    return inputs(rig)


def _run(args) -> int:
    """The command (``main``): the arguments checked (``_checked``), a rig's scenes run, the budget
    written; InputError and ConvergenceError reach ``common.cli.run_command`` (exit 2 and 3)."""
    from common.io import write_bytes_atomic, write_json

    inp = _checked(args)
    out = Path(args.out)

    def say(m):
        print(m, file=sys.stderr, flush=True)

    from common.executors import executor_for

    with executor_for(args.jobs, args.scheduler) as (executor, label):
        if inp is not None or executor is not None:
            say(f"executor: {label}")
        if inp is not None:
            from .compare import run_all

            say(f"validation.budget: the rig {inp.name}: {len(inp.scenes)} scene(s) -> {out}/")
            status = run_all(inp.scenes, out, executor=executor, jobs=args.jobs, force=args.force, fields=False,
                             log=say, detail=False)
            failed = [k for k, v in status.items() if v not in ("ok", "skipped")]
            if failed:
                say(f"{PROG}: scenes failed ({', '.join(failed)}): their cells read undetermined (a result stored "
                    "before is not read)")
        b = budget(out, inp=inp, mdr_cells=not args.no_mdr, jobs=args.jobs, log=say, executor=executor)
    head = "# The error budget of the paper's model" if inp is None else f"# The error budget of the rig {inp.name}"
    text = "\n".join([head, ""] + markdown(b)) + "\n"
    write_bytes_atomic(out / ("budget.md" if inp is None else f"budget-{inp.name}.md"), text.encode())
    print(text, file=sys.stderr if args.json == "-" else sys.stdout)  # stdout is the JSON's then
    if args.json is not None:
        write_json(args.json, b)
    return 0


def main(argv=None) -> int:
    from common.cli import run_command

    p = build_parser()
    p.set_defaults(func=_run)
    return run_command(p, argv, write_result=False, check_outputs=False)


if __name__ == "__main__":
    raise SystemExit(main())
