"""The error budget of the paper's model: what each of its assumptions costs each of its results.

``python -m validation.budget [--out DIR]`` prints (and writes to ``DIR/budget.md``) one table: a row
per result of Willert, Machines 11 (2023) 484 (the loops of Figs. 4-5 on the sphere and of Figs. 6-7
on the truncated sphere b = 0.6 mm, the slip-index curves of Figs. 8 and 9, the Table 2 point), a
column per assumption of the half-space MDR model in the paper's apparatus, each cell the change of the
result's slip index (its dissipation per cycle over 4 mu F0 u_A, what Figs. 8-9 plot and the loops of
Figs. 4-7 enclose) when the assumption is dropped, with its error bar, where it was measured, and a
verdict against the figures' resolution ``RESOLUTION``:

- ``negligible``: |effect| + error <= resolution;
- ``matters``: |effect| - error > resolution (a measured effect, not a bound); a *range* over readings
  of an input the paper leaves open matters only where all of it, with its error, lies beyond the
  resolution on one side (``validation.budget_readings.grade_range``);
- ``undetermined``: in between, a bound above the resolution, a range that reaches across it, or not
  measured at the result's conditions (the cell says what would measure it).

Where the cells come from (``COLUMNS``):

- *half-space size*, *traction direction*, *tilt*: the stored results of the catalogue's scenes
  (``validity``, ``assumptions-3d``, ``direction-points``, ``tilt``; ``python -m validation.compare``
  in the same ``--out``). Size effects grow monotonically with the body's smallness, so the row
  measured at the nearest smaller body is a *bound*: the true effect lies between 0 and it. The tilt
  the paper states as an inequality ("less than pi/3600"): its change at pi/3600 is a bound too;
- *curvature*: measured at each point itself, the axisymmetric FE model (the cap's real sphere)
  against MDR in the apparatus there (``measured_in_apparatus``: the experiment scenes, the k_x
  series, ``halfspace-points``), a change of the slip index; where none is stored, bounded by the
  sphere's ``validity-curvature`` row at the next larger a/R;
- *coupling*: exactly 0: the paper's indenter and block are the same steel (Dundurs' beta = 0);
- *tilt* of the sphere: exactly 0 (a tilted sphere is the same sphere displaced);
- *roughness* and *plates*: computed here (``validation.budget_readings``): ranges over the readings of
  the paper's stated rms values (``validation.spectra``) and of its brass plates that the paper's own
  loops admit (``validation.consistency``), MDR in the apparatus at every point (the roughness through
  each surface's equivalent profile, its error including what that misses of the rough half-space in
  the catalogue's scenes ``roughness`` and ``roughness-faces``);
- *kink rounding*: computed here with the MDR apparatus at every point: the fillet of the kink
  (``mdr.profiles.RoundedTruncatedSphere``, width ``FILLET_MAX``, the paper's bound "less than the rms
  roughness") against the sharp kink, a bound.

Assumptions of the mapping (stated in the table's notes): an effect measured under force control at
Table 2's load is applied as the same relative change of the apparatus's dissipation, i.e. times the
point's slip index (MDR in the apparatus, ``point_slip_index``), except the tilt's, measured as a change
of the slip index itself (the aligned face hardly slips there), and the curvature's, the roughness's and
the plates', changes of the slip index in the apparatus; a result spanning a range of b (Figs. 8, 9,
Table 2's two points) is "negligible" only if every b of its range is covered, and "matters" as soon as
one measured point of it does.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

from mdr.paper import R_INDENTER

from .paper_points import RESOLUTION, RESOLUTION_ORIGIN, Point, contact_radius, difference_with_grid, point_slip_index, results, slip_indices
from .catalogue import CATALOGUE
from .scenes import TILT_BOUND
from .sources import code_version
from .store import load_scene
from .text import num

#: the widest rounding of the kink the paper allows: "less than the rms roughness", up to 3 um
FILLET_MAX = 3e-6
#: the paper's block: the indenter's contact lies h = 19 mm above the bedding (Table 1)
BLOCK_HEIGHT = 19e-3
COLUMNS = ("size", "curvature", "direction", "coupling", "tilt", "roughness", "kink", "plates")
TITLES = {"size": "half-space size", "curvature": "curvature a/R", "direction": "traction direction",
          "coupling": "coupling", "tilt": "tilt <= pi/3600", "roughness": "roughness (admitted readings)",
          "kink": "kink rounding",
          "plates": "brass plates' reading"}


# ----------------------------------------------------------------------------------- cells
def cell(effect, error, kind, source, note="") -> dict:
    """One cell: ``effect`` (relative change of the result's quantity), its ``error``, ``kind``
    (``measured``, ``bound``: the effect lies between 0 and ``effect``, ``exact``, ``spread``: the
    largest change over readings of an unknown, ``absolute``: a change of the slip index itself), where
    it comes from and the verdict."""
    finite = effect is not None and error is not None and math.isfinite(effect) and math.isfinite(error)
    if not finite:
        v = "undetermined"
    elif abs(effect) + error <= RESOLUTION:
        v = "negligible"
    elif kind != "bound" and abs(effect) - error > RESOLUTION:
        v = "matters"
    else:
        v = "undetermined"
    return {"effect": effect if finite else None, "error": error if finite else None, "kind": kind,
            "source": source, "note": note, "verdict": v}


def missing(scene: str, why: str = "") -> dict:
    return cell(None, None, "measured", f"not run: python -m validation.compare --scenes {scene}", why)


def combine(cells: list, source: str) -> dict:
    """A result over several points: ``matters`` if one measured point matters; ``negligible`` only if
    every point is; else undetermined. The cell shown is the one that decides: of the points that matter
    the one that matters most surely (the largest |effect| - error), else the largest |effect| + error."""
    verdicts = [c["verdict"] for c in cells]
    deciding = [c for c in cells if c["verdict"] == "matters"]
    shown = max(deciding, key=lambda c: _extent(c) - c["error"]) if deciding else \
        max((c for c in cells if c["effect"] is not None), key=lambda c: _extent(c) + c["error"],
            default=cells[0])
    out = dict(shown)
    out["source"] = source if len(cells) > 1 else shown["source"]
    out["verdict"] = "matters" if "matters" in verdicts else ("negligible" if all(v == "negligible" for v in verdicts)
                                                              else "undetermined")
    gaps = sorted({c["note"] for c in cells if c["effect"] is None and c["note"]})
    out["note"] = "; ".join(([shown["note"]] if shown["note"] and shown["effect"] is not None else []) + gaps)
    return out


def _extent(c: dict) -> float:
    """The largest |effect| a cell holds: its range's farther end where it has one."""
    return max(abs(c["range"][0]), abs(c["range"][1])) if c.get("range") else abs(c["effect"])


# --------------------------------------------------------------- cells from stored scenes
def size_cell(p: Point, store) -> dict:
    """The bodies shrunk (``validity``): the indenter's cap R / a and the block's height over a, each
    bounded by the measured row at the largest size not above it (the effect falls with size)."""
    res = store("validity")
    if res is None:
        return missing("validity")
    a = contact_radius(p)
    rows = {r["variant"]: r for r in res["validity"]}
    total, parts = 0.0, []
    for body, size in (("cap", R_INDENTER / a), ("block", BLOCK_HEIGHT / a)):
        measured = sorted(x for x in (3.0, 5.0, 10.0, 30.0)
                          if any(k.startswith(f"{body} {x:g} a (") for k in rows))
        below = [x for x in measured if x <= size]
        if not below:
            return cell(None, None, "bound", "validity", f"{body} {size:.2g} a: smaller than any measured body")
        x = below[-1]
        r = next(v for k, v in rows.items() if k.startswith(f"{body} {x:g} a ("))
        e = r.get("dissipation_vs_default")
        if e is None or not math.isfinite(e):
            return cell(None, None, "bound", "validity", f"{body} {x:g} a: no finite size effect stored")
        total += abs(e)  # bounds add by magnitude: opposite signs must not cancel
        parts.append(f"{body} {size:.0f} a (row {x:g} a)")
    return cell(-total, 0.0, "bound", "validity", ", ".join(parts))


def _row_at(p: Point, s, res):
    """The row of a stored result ``res`` of the ``points`` scene ``s`` whose variant runs the point
    ``p`` (``validation.families.points.Variant``), or None."""
    for r in (res or {}).get("points", []):
        i = r.get("variant")
        if isinstance(i, int) and 0 <= i < len(s.variants) and p.matches(s.typed_variants[i].scene(s)):
            return r
    return None


def measured_in_apparatus(p: Point, store):
    """The slip index's FE - MDR at the point itself, from a stored scene that runs it in the apparatus:
    a pair scene of the catalogue (the experiments of Figs. 4-7, the k_x series) or a row of
    ``halfspace-points`` (``validation.families.points``); (scene name, effect, error, bounded, a/R)
    or None where none is stored (or its numbers are not finite)."""
    for name, s in CATALOGUE.items():
        found = None
        if s.family == "pair" and p.matches(s):
            res = store(name)
            if res is not None:
                v = res["verdicts"]["slip_index"]
                a = (res.get("fem") or {}).get("contact_radius")
                found = (v.get("fem"), v.get("mdr"), v.get("fem_error"), v.get("mdr_error"), v.get("bounded"), a)
        elif s.family == "points" and s.fe_model == "axisym":
            row = _row_at(p, s, store(name))
            if row is not None:
                found = (row.get("slip_index_fem"), row.get("slip_index_mdr"), row.get("error"), 0.0,
                         row.get("bounded"), None if row.get("a_over_R") is None else row["a_over_R"] * s.R)
        if found is not None:
            fe, md, e1, e2, bounded, a = found
            nums = (fe, md, e1, e2)
            if all(x is not None and math.isfinite(x) for x in nums):
                return name, fe - md, e1 + e2, bool(bounded), None if a is None else a / R_INDENTER
    return None


def curvature_cell(p: Point, store) -> dict:
    """The half-space's shape at the point: measured where a stored scene runs the point in the apparatus
    (``measured_in_apparatus``: the axisymmetric FE model, whose cap is the real sphere, against MDR, a
    change of the slip index); else bounded by the sphere's row of ``validity-curvature`` (nu = 0.29)
    at the smallest measured a/R not below the point's (the effect grows with a/R)."""
    m = measured_in_apparatus(p, store)
    if m is not None:
        name, effect, error, bounded, x = m
        return cell(effect, error, "absolute", name,
                    f"FE - MDR at the point{'' if x is None else f', a/R = {x:.2g}'}"
                    f"{'' if bounded else ' (the FE ladder non-monotone: its spread)'}")
    res = store("validity-curvature")
    if res is None:
        return missing("validity-curvature")
    x = contact_radius(p) / R_INDENTER
    rows = sorted((r for r in res["curvature"] if abs(r["nu"] - 0.29) < 1e-9), key=lambda r: r["a_over_R"])
    above = [r for r in rows if r["a_over_R"] >= x]
    if not above:
        return cell(None, None, "bound", "validity-curvature",
                    f"a/R = {x:.2g}, beyond the largest measured {rows[-1]['a_over_R']:.2g}" if rows else "no rows")
    r = above[0]
    return cell(r["dissipation_effect"], r["dissipation_effect_error"], "bound", "validity-curvature",
                f"a/R = {x:.2g} (row {r['a_over_R']:.2g})")


def direction_in_apparatus(p: Point, store):
    """The slip index's change at the point itself when the 3D model's traction turns free (against along
    x), from a stored 3D scene of the family ``points`` (``direction-points``); (scene name, row) or None
    where none is stored."""
    for name, s in CATALOGUE.items():
        if s.family != "points" or s.fe_model != "3d":
            continue
        r = _row_at(p, s, store(name))
        if r is not None:
            return name, r
    return None


def direction_cell(p: Point, store) -> dict:
    """Mindlin's traction along x relaxed in 3D: measured at the point itself in the apparatus where a
    stored scene runs it (``direction_in_apparatus``, a change of the slip index); else under force
    control at Table 2's load (``assumptions-3d``): the sphere's row, or the truncated sphere's of the
    same b, a relative change of the dissipation."""
    m = direction_in_apparatus(p, store)
    if m is not None:
        name, r = m
        return cell(r.get("effect"), r.get("error"), "absolute", name,
                    f"3D, free - along x at the point, {'sphere' if p.b == 0 else f'b = {p.b * 1e6:g} um'} "
                    f"(ladder {r.get('ladder_status')})")
    res = store("assumptions-3d")
    if res is None:
        return missing("assumptions-3d")
    for r in res["assumptions3d"]:
        if r["relax"] == "direction" and abs(float(r.get("b", 0.0)) - p.b) < 1e-9:
            d = r["verdicts"]["dissipation"]
            return cell(d["effect"], d["error"], "measured", "assumptions-3d",
                        "sphere" if p.b == 0 else f"b = {p.b * 1e6:g} um")
    return cell(None, None, "measured", "assumptions-3d", f"b = {p.b * 1e6:g} um not measured in 3D")


def tilt_cell(p: Point, store) -> dict:
    """The flat face tilted by the paper's bound (``tilt``): the sphere exactly 0; a face of the same b at
    pi/3600 (the banded row where there is one): the change of the slip index itself (absolute: the
    aligned face hardly slips under the scene's force control, so a relative change has no meaning),
    against the resolution of the slip index's full scale (1, gross slip). The paper states the tilt
    as an inequality ("less than pi/3600"), so the change at pi/3600 is a bound: the true change lies
    between 0 and it (kind ``bound``: never "matters")."""
    if p.b == 0:
        return cell(0.0, 0.0, "exact", "symmetry", "a tilted sphere is the same sphere displaced")
    res = store("tilt")
    if res is None:
        return missing("tilt")
    rows = [r for r in res["tilt"] if abs(r["b"] - p.b) < 1e-9]
    rows.sort(key=lambda r: not r.get("banded"))
    for r in rows:
        pt = next((x for x in r["points"] if abs(x["tilt"] - TILT_BOUND) < 1e-3 * TILT_BOUND and x["resolved"]), None)
        if pt is None:
            continue
        si = pt["aligned"]["slip_index"]
        aligned = r["levels"][-1]["runs"][0].get("slip_index")
        return cell(si["effect"], si["error"], "bound", "tilt",
                    f"{r['variant']}: slip index {num(aligned, '.2g')} aligned, force control at Table 2's load")
    return cell(None, None, "bound", "tilt", f"b = {p.b * 1e6:g} um at pi/3600 not measured (or not resolved)")


# ------------------------------------------------------------------ cells computed with MDR
def kink_cell(p: Point) -> dict:
    """The kink rounded by a fillet of ``FILLET_MAX`` against the sharp kink: the slip index's change
    (MDR in the apparatus; the effect grows with the width: a bound)."""
    from mdr.profiles import RoundedTruncatedSphere, TruncatedSphere

    if p.b == 0:
        return cell(0.0, 0.0, "exact", "geometry", "no kink")
    if p.b < 2 * FILLET_MAX:
        return cell(None, None, "bound", "MDR apparatus", f"b = {p.b * 1e6:g} um: the fillet would take the face")

    def fun(n):
        return slip_indices([RoundedTruncatedSphere(R_INDENTER, p.b, FILLET_MAX), TruncatedSphere(R_INDENTER, p.b)],
                             [p, p], n=n)

    e, err = difference_with_grid(fun)
    return cell(e, err, "bound", "MDR apparatus", f"fillet {FILLET_MAX * 1e6:g} um")


def scaled(c: dict, slip_index: float) -> dict:
    """A cell of a relative effect on the dissipation as the change of the point's slip index: effect
    and error times ``slip_index``, the verdict taken again."""
    if c["kind"] == "absolute" or c["effect"] is None:
        return c
    out = cell(c["effect"] * slip_index, c["error"] * slip_index, c["kind"], c["source"], c["note"])
    return out


# --------------------------------------------------------------------------- the table
def budget(out="results", *, mdr_cells: bool = True, log=None, jobs: int = 1, members: list | None = None,
           readings_dir=None) -> dict:
    """The budget from the scenes stored under the folder ``out`` (or a dict of results by scene name,
    results.json's ``scenes``; a missing scene's cells are undetermined, naming the command that
    measures them) and, with ``mdr_cells``, the cells computed here: the roughness readings (their
    surfaces' curves from ``members`` where given, else ``validation.spectra.curves`` in ``jobs``
    processes, cached under ``out``/readings or ``readings_dir``), the paper's loops against them and against the plates'
    readings, the kink, the plates and the sticking transition. Returns {"rows": [{key, title,
    slip_index, cells: {column: cell}}], "stale": [scene names stored by other sources], "resolution",
    "consistency", "plates_consistency", "transition"}."""
    from . import budget_readings as BR

    log = log or (lambda msg: None)
    version, stale, cache = code_version(), [], {}

    def store(name):
        if name not in cache:
            res = out.get(name) if isinstance(out, dict) else load_scene(out, name)
            if res is not None and name in CATALOGUE and res.get("fingerprint") != CATALOGUE[name].fingerprint(version):
                stale.append(name)
            cache[name] = res
        return cache[name]

    result = {"stale": [], "resolution": RESOLUTION}
    if mdr_cells:
        if members is None:
            from .spectra import curves

            folder = readings_dir if isinstance(out, dict) else Path(out) / "readings"
            members = curves(BR.contacts(), folder, jobs=jobs, log=log)
        R = BR.Readings(members)
        result["consistency"] = BR.consistency(R, log, jobs)
        admitted = BR.admitted_names(result["consistency"])
        result["plates_consistency"] = BR.plates_consistency(log)
        plates_ok = {r["reading"] for r in result["plates_consistency"] if r["admitted"]}
        eq_error = BR.equivalent_error(store)
    rows = []
    for r in results():
        log(f"budget: {r.title}")
        si = [point_slip_index(p) for p in r.points]
        cells = {}
        for col, fun in (("size", size_cell), ("curvature", curvature_cell), ("direction", direction_cell)):
            cells[col] = combine([scaled(fun(p, store), x) for p, x in zip(r.points, si)], TITLES[col])
        cells["tilt"] = combine([tilt_cell(p, store) for p in r.points], TITLES["tilt"])
        cells["coupling"] = cell(0.0, 0.0, "exact", "Dundurs", "indenter and block of one steel: beta = 0")
        if mdr_cells:
            cells["roughness"] = combine([BR.roughness_cell(p, R, admitted, eq_error) for p in r.points],
                                         TITLES["roughness"])
            cells["kink"] = combine([kink_cell(p) for p in r.points], "MDR apparatus")
            cells["plates"] = combine([BR.plates_cell(p, plates_ok) for p in r.points], "MDR apparatus")
        rows.append({"key": r.key, "title": r.title, "slip_index": [min(si), max(si)],
                     "cells": {c: cells[c] for c in COLUMNS if c in cells}})
    result.update(rows=rows, stale=sorted(set(stale)))
    if mdr_cells:
        log("budget: the sticking transition")
        result["transition"] = BR.transitions(R, admitted)
    return result


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
    lines = [f"The change of each result's slip index when an assumption of the paper's model is dropped, with "
             f"its error bar, against the figures' resolution of {b['resolution']:g} ({RESOLUTION_ORIGIN}). "
             "'<=': a bound (the change lies between 0 and it: never 'matters'). 'lo to hi': a range over the "
             "readings of an input the paper leaves open that its own loops admit (the roughness spectrum, the "
             "brass plates), graded 'matters' only where all of it lies beyond the resolution on one side. "
             "Effects measured on the dissipation under force control at Table 2's load count as the same "
             "relative change of the result's slip index (its range in the second column, MDR in the "
             "apparatus). A result over several points shows the point that decides; it is negligible only "
             "where every point is, and matters where one measured point does.", "",
             "| result | slip index | " + " | ".join(TITLES[c] for c in cols) + " |",
             "|---|---|" + "---|" * len(cols)]
    for r in b["rows"]:
        lo, hi = r["slip_index"]
        span = num(lo, ".2g") if abs(hi - lo) <= 1e-3 * max(abs(hi), 1e-12) else f"{num(lo, '.2g')}-{num(hi, '.2g')}"
        lines.append(f"| {r['title']} | {span} | " + " | ".join(cell_text(r["cells"][c]) if c in r["cells"] else "-"
                                                                 for c in cols) + " |")
    lines += readings_markdown(b)
    if b["stale"]:
        lines += ["", f"Stored by other sources than these (rerun them): {', '.join(b['stale'])}."]
    return lines


def build_parser():
    from common.cli import OneLineParser

    p = OneLineParser(prog="python -m validation.budget",
                      description="The error budget of the paper's model: for each of its results, the measured "
                                  "cost of every assumption, from the scenes stored by python -m validation.compare "
                                  "in --out (the kink and plates computed here with MDR, about a minute).")
    p.add_argument("--out", default="results", metavar="DIR",
                   help="the comparison's output directory (default ./results); budget.md is written there")
    p.add_argument("--json", metavar="PATH", help="also write the budget as JSON to PATH ('-' = stdout)")
    p.add_argument("--no-mdr", action="store_true",
                   help="leave out the cells computed here: roughness, kink, plates, the paper's loops as a check "
                        "and the sticking transition (the rest still runs MDR for each point's slip index)")
    p.add_argument("--jobs", type=int, default=1, metavar="N",
                   help="processes for the rough surfaces of the roughness readings (default 1; cached under "
                        "--out/readings, so a second run reads them)")
    return p


def main(argv=None) -> int:
    from common.errors import InputError
    from common.io import check_output_path, write_bytes_atomic, write_json

    p = build_parser()
    args = p.parse_args(argv)
    try:
        out = Path(args.out)
        if not (out / "scenes").is_dir():
            raise InputError(f"--out {args.out!r} holds no stored scenes: run python -m validation.compare "
                             f"--out {args.out} first")
        if args.json not in (None, "-"):
            check_output_path(args.json, "--json")
        if args.jobs < 1:
            raise InputError(f"--jobs must be a whole number >= 1, got {args.jobs}")
    except InputError as e:
        print(f"{p.prog}: error: {e}", file=sys.stderr)
        return 2
    b = budget(out, mdr_cells=not args.no_mdr, jobs=args.jobs, log=lambda m: print(m, file=sys.stderr, flush=True))
    text = "\n".join(["# The error budget of the paper's model", ""] + markdown(b)) + "\n"
    write_bytes_atomic(out / "budget.md", text.encode())
    print(text, file=sys.stderr if args.json == "-" else sys.stdout)  # stdout is the JSON's then
    if args.json is not None:
        write_json(args.json, b)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
