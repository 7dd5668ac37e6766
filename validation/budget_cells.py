"""The error budget's cells (``validation.budget``): the verdict rule, a result over several points, and
each assumption's cell at one point of a rig (``Inputs``), read from the stored scenes that measure it or
computed with MDR.

A cell is the change of the point's slip index when the assumption is dropped, with its error bar, its
kind (``measured``; ``bound``: the change lies between 0 and it; ``exact``; ``absolute``: measured as a
change of the slip index itself; ``range``: over readings of an open input) and its verdict against the
rig's resolution (``grade``). The stored scenes are found by their family in ``Inputs.scenes`` (the
catalogue's for the paper, ``validation.rig_scenes`` for a rig of one's own), so one code path reads both.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .paper_points import PAPER, RESOLUTION, Point, Setup, contact_radius, difference_with_grid, same, slip_indices
from .text import num

#: the paper's widest rounding of the kink: "less than the rms roughness", up to 3 um
FILLET_MAX = 3e-6
#: the paper's block: the indenter's contact lies h = 19 mm above the bedding (Table 1)
BLOCK_HEIGHT = 19e-3


@dataclass(frozen=True)
class Inputs:
    """What a budget reads besides its stored results: the rig's ``setup`` (R, materials, apparatus), its
    bodies (``cap_height``, ``block`` (m): the indenter above the contact, infinite where it is the
    whole sphere up to its equator, as the FE model's cap; the block's smaller extent, its height above
    the bedding or half its width), the kink's ``fillet`` bound (m), the ``tilt`` bound
    (rad), its ``results`` (``validation.paper_points.Result``), the ``resolution`` of the slip index,
    the ``scenes`` that measure its cells, its rough ``contacts`` (``validation.spectra.Contact``; none
    where it states no roughness) and whether its readings are the paper's (``paper``: the roughness
    spectrum and the plates checked against the paper's loops)."""

    name: str
    setup: Setup
    cap_height: float
    block: float
    fillet: float | None
    tilt: float | None
    results: tuple
    resolution: float
    scenes: tuple
    contacts: tuple = ()
    paper: bool = False
    #: the command that runs a scene of ``scenes`` ({scene}: its name)
    rerun: str = "python -m validation.compare --scenes {scene}"
    #: a rig's measured loops (``validation.consistency.Loop``), the check of its readings (the paper's
    #: are ``consistency.paper_loops``)
    loops: tuple = ()

    def of_family(self, family: str, fe_model: str | None = None) -> tuple:
        return tuple(s for s in self.scenes if s.family == family and fe_model in (None, s.fe_model))

    def at_load(self, family: str, p: Point) -> tuple:
        """The force-controlled scenes of ``family`` that measure the point: for a rig of one's own those
        at its load (F0, dF, mu1), for the paper all (its effects mapped from Table 2's load, stated)."""
        scenes = self.of_family(family)
        if self.paper:
            return scenes
        return tuple(s for s in scenes if same(s.F0, p.F0) and same(s.dF, p.dF) and same(s.mu, p.mu1))


def paper_inputs() -> Inputs:
    """The paper's rig (Willert 2023) with the catalogue's scenes, its roughness readings checked by its own
    loops (``paper``). ``docs/examples/willert2023.toml`` holds the same setup, bodies, bounds, points and
    resolution (``tests/test_rig_budget.py``); read as a rig of one's own it gets the generated scenes and
    unchecked readings."""
    from .budget_readings import contacts
    from .catalogue import CATALOGUE
    from .paper_points import results
    from .scenes import TILT_BOUND

    return Inputs("willert2023", PAPER, float("inf"), BLOCK_HEIGHT, FILLET_MAX, TILT_BOUND, results(), RESOLUTION,
                  tuple(CATALOGUE.values()), contacts(), paper=True)


# ------------------------------------------------------------------------------- the verdicts
def verdict(effect, error, kind, resolution=RESOLUTION) -> str:
    """``negligible``: |effect| + error <= resolution; ``matters``: |effect| - error > resolution and not a
    bound; else (or not finite) ``undetermined``."""
    if effect is None or error is None or not (math.isfinite(effect) and math.isfinite(error)):
        return "undetermined"
    if abs(effect) + error <= resolution:
        return "negligible"
    return "matters" if kind != "bound" and abs(effect) - error > resolution else "undetermined"


def cell(effect, error, kind, source, note="", resolution=RESOLUTION) -> dict:
    """One cell: ``effect`` (the change), its ``error``, ``kind`` (module docstring), where it comes from,
    a note and the verdict (``verdict``)."""
    finite = effect is not None and error is not None and math.isfinite(effect) and math.isfinite(error)
    return {"effect": effect if finite else None, "error": error if finite else None, "kind": kind,
            "source": source, "note": note, "verdict": verdict(effect, error, kind, resolution)}


def grade(c: dict, resolution: float) -> dict:
    """The cell graded against ``resolution`` (a range cell by ``budget_readings.grade_range``; one with an
    admitted reading its grid does not resolve, or a bar known to be incomplete, stays undetermined)."""
    from .budget_readings import grade_range

    if c.get("kind") == "range":
        v = "undetermined" if c.get("range") is None or c.get("unresolved") or c.get("incomplete") else \
            grade_range(*c["range"], c["error"], resolution)
    else:
        v = verdict(c["effect"], c["error"], c["kind"], resolution)
    return {**c, "verdict": v}


def missing(scene: str, why: str = "", inp: Inputs | None = None) -> dict:
    """An undetermined cell whose scene is not stored, naming the command that runs it (the rig's)."""
    template = inp.rerun if inp is not None else Inputs.rerun
    rerun = template.format(scene=scene)
    return cell(None, None, "measured", f"not run: {rerun}" if "{scene}" in template else f"{scene} not run: {rerun}",
                why)


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


def scaled(c: dict, slip_index: float) -> dict:
    """A cell of a relative effect on the dissipation as the change of the point's slip index: effect
    and error times ``slip_index``, the verdict taken again."""
    if c["kind"] == "absolute" or c["effect"] is None:
        return c
    return cell(c["effect"] * slip_index, c["error"] * slip_index, c["kind"], c["source"], c["note"])


# --------------------------------------------------------------- cells from stored scenes
def size_cell(p: Point, store, inp: Inputs) -> dict:
    """The bodies shrunk (family ``validity``): the indenter's cap and the block over the point's contact
    radius. The effect falls with either body's size, so a stored row whose bodies are both no larger
    than the point's bounds it from above, and one whose bodies are both no smaller from below. The sum
    of the two one-body rows at the largest sizes not above the point's is a bound where the bodies'
    effects add, an assumption the rows check: the sum is used only where no row bounds the effect from
    below by more. The smallest bound is the cell. Bodies of at least the FE model's default size
    (200 a) count as its half-space."""
    from .families.validity import VALIDITY_DEFAULT_SIZE

    a = contact_radius(p, inp.setup)
    cap, block = inp.cap_height / a, inp.block / a
    where = ("the cap the whole sphere" if math.isinf(cap) else f"cap {cap:.0f} a") + f", block {block:.0f} a"
    scenes = inp.of_family("validity")
    name = scenes[0].name if scenes else "validity"
    if min(cap, block) >= VALIDITY_DEFAULT_SIZE:
        return cell(0.0, 0.0, "bound", name, f"{where}: the FE model's default bodies")
    rows = [r for s in scenes for r in (store(s.name) or {}).get("validity", [])]
    if not rows:
        return missing(name, inp=inp)
    big = VALIDITY_DEFAULT_SIZE
    fin = [r for r in rows if isinstance(r.get("dissipation_vs_default"), float)
           and math.isfinite(r["dissipation_vs_default"])]
    bounds = [(abs(r["dissipation_vs_default"]), f"the row of block {r['block_over_a']:.3g} a, cap {r['cap_over_a']:.3g} a")
              for r in fin if r["block_over_a"] <= block * (1 + 1e-9) and r["cap_over_a"] <= cap * (1 + 1e-9)]
    one = {}
    for body, size, other in (("block", block, "cap_over_a"), ("cap", cap, "block_over_a")):
        alone = [r for r in fin if r[other] >= big and r[f"{body}_over_a"] <= size * (1 + 1e-9)]
        if size >= big:
            one[body] = (0.0, f"{body} >= {big:g} a")
        elif alone:
            r = max(alone, key=lambda r: r[f"{body}_over_a"])
            one[body] = (abs(r["dissipation_vs_default"]), f"the {body} row of {r[f'{body}_over_a']:.3g} a")
    below = max((abs(r["dissipation_vs_default"]) for r in fin
                 if r["block_over_a"] >= block * (1 - 1e-9) and r["cap_over_a"] >= min(cap, big) * (1 - 1e-9)),
                default=0.0)
    if len(one) == 2 and one["block"][0] + one["cap"][0] >= below:
        bounds.append((one["block"][0] + one["cap"][0], f"{one['block'][1]} + {one['cap'][1]}"))
    if not bounds:
        return cell(None, None, "bound", name, f"{where}: smaller than any measured body")
    e, how = min(bounds, key=lambda x: x[0])
    return cell(-e, 0.0, "bound", name, f"{where}: bounded by {how}")


def _row_at(p: Point, s, res, tilt: float | None = None):
    """The row of a stored result ``res`` of the ``points`` scene ``s`` whose variant runs the point
    ``p`` (``validation.families.points.Variant``) with the face tilted by ``tilt`` (rad; None: not
    tilted, the traction direction's or the half-space's rows), or None."""
    for r in (res or {}).get("points", []):
        i = r.get("variant")
        if not (isinstance(i, int) and 0 <= i < len(s.variants)):
            continue
        v = s.typed_variants[i]
        ok = v.tilt is None if tilt is None else v.tilt is not None and abs(v.tilt - tilt) <= 1e-3 * tilt
        if ok and p.matches(v.scene(s)):
            return r
    return None


def measured_in_apparatus(p: Point, store, inp: Inputs):
    """The slip index's FE - MDR at the point itself, from a stored scene of ``inp`` that runs it in the
    apparatus: a pair scene (the experiments of Figs. 4-7, the k_x series) or a row of an axisymmetric
    ``points`` scene (``validation.families.points``); (scene name, effect, error, bounded, a/R) or None
    where none is stored (or its numbers are not finite)."""
    for s in inp.scenes:
        found = None
        if s.family == "pair" and p.matches(s):
            res = store(s.name)
            if res is not None:
                v = res["verdicts"]["slip_index"]
                a = (res.get("fem") or {}).get("contact_radius")
                found = (v.get("fem"), v.get("mdr"), v.get("fem_error"), v.get("mdr_error"), v.get("bounded"), a)
        elif s.family == "points" and s.fe_model == "axisym":
            row = _row_at(p, s, store(s.name))
            if row is not None:
                found = (row.get("slip_index_fem"), row.get("slip_index_mdr"), row.get("error"), 0.0,
                         row.get("bounded"), None if row.get("a_over_R") is None else row["a_over_R"] * s.R)
        if found is not None:
            fe, md, e1, e2, bounded, a = found
            if all(x is not None and math.isfinite(x) for x in (fe, md, e1, e2)):
                return s.name, fe - md, e1 + e2, bool(bounded), None if a is None else a / inp.setup.R
    return None


def curvature_cell(p: Point, store, inp: Inputs) -> dict:
    """The half-space's shape at the point: measured where a stored scene runs the point in the apparatus
    (``measured_in_apparatus``: the axisymmetric FE model, whose cap is the real sphere, against MDR, a
    change of the slip index); else bounded by the sphere's row of a ``curvature`` scene (nu = 0.29)
    at the smallest measured a/R not below the point's (the effect grows with a/R)."""
    m = measured_in_apparatus(p, store, inp)
    if m is not None:
        name, effect, error, bounded, x = m
        return cell(effect, error, "absolute", name,
                    f"FE - MDR at the point{'' if x is None else f', a/R = {x:.2g}'}"
                    f"{'' if bounded else ' (the FE ladder non-monotone: its spread)'}")
    scenes = inp.of_family("curvature")
    res = store(scenes[0].name) if scenes else None
    if res is None:
        return missing(scenes[0].name if scenes else next((s.name for s in inp.of_family("points", "axisym")),
                                                           "validity-curvature"), inp=inp)
    x = contact_radius(p, inp.setup) / inp.setup.R
    rows = sorted((r for r in res["curvature"] if abs(r["nu"] - 0.29) < 1e-9), key=lambda r: r["a_over_R"])
    above = [r for r in rows if r["a_over_R"] >= x]
    if not above:
        return cell(None, None, "bound", scenes[0].name,
                    f"a/R = {x:.2g}, beyond the largest measured {rows[-1]['a_over_R']:.2g}" if rows else "no rows")
    r = above[0]
    return cell(r["dissipation_effect"], r["dissipation_effect_error"], "bound", scenes[0].name,
                f"a/R = {x:.2g} (row {r['a_over_R']:.2g})")


def _assumption_row(p: Point, store, inp: Inputs, relax: str):
    """(scene name, stored row) of the ``assumptions3d`` scene of ``inp`` that relaxes ``relax`` on the
    point's indenter (its b), (scene name, None) where none is stored, or (None, None) without a scene."""
    scenes = inp.at_load("assumptions3d", p)
    for s in scenes:
        res = store(s.name)
        for r in (res or {}).get("assumptions3d", []):
            if r["relax"] == relax and abs(float(r.get("b") or 0.0) - p.b) < 1e-9:
                return s.name, r
    return (scenes[0].name if scenes else None), None


def _relaxing(inp: Inputs, what: str) -> tuple:
    """The 3D ``points`` scenes of ``inp`` that measure ``what`` (``families.points.measures``: "direction",
    "tilt") at their points in the apparatus (each of their points, ``_row_at``, with a tilt or without)."""
    from .families.points import measures

    return tuple(s for s in inp.of_family("points", "3d") if what in measures(s.as_dict()))


def direction_cell(p: Point, store, inp: Inputs) -> dict:
    """Mindlin's traction along x relaxed in 3D: measured at the point itself in the apparatus where a
    stored 3D ``points`` scene runs it (a change of the slip index); else under force control (an
    ``assumptions3d`` scene): the row of the same b, a relative change of the dissipation."""
    for s in _relaxing(inp, "direction"):
        r = _row_at(p, s, store(s.name))
        if r is not None:
            return cell(r.get("effect"), r.get("error"), "absolute", s.name,
                        f"3D, free - along x at the point, {'sphere' if p.b == 0 else f'b = {p.b * 1e6:g} um'} "
                        f"(ladder {r.get('ladder_status')})")
    name, r = _assumption_row(p, store, inp, "direction")
    if r is None:
        own = next((s.name for s in _relaxing(inp, "direction")), None)
        return missing(own or name or "direction-points", "" if own or name else "no 3D scene measures it", inp)
    d = r["verdicts"]["dissipation"]
    return cell(d["effect"], d["error"], "measured", name, "sphere" if p.b == 0 else f"b = {p.b * 1e6:g} um")


def coupling_cell(p: Point, store, inp: Inputs) -> dict:
    """The normal-tangential coupling of a dissimilar pair (Dundurs' beta), which MDR leaves out: exactly 0
    where beta = 0 (one material); else the 3D model under force control with the coupling against
    without on the same mesh (an ``assumptions3d`` row relaxing ``coupling`` on the point's b), a
    relative change of the dissipation."""
    beta = inp.setup.materials.dundurs_beta
    if abs(beta) < 1e-12:
        return cell(0.0, 0.0, "exact", "Dundurs", "indenter and block of one material: beta = 0")
    name, r = _assumption_row(p, store, inp, "coupling")
    if r is None:
        return missing(name or "assumptions-3d", f"beta = {beta:+.3f}", inp)
    d = r["verdicts"]["dissipation"]
    return cell(d["effect"], d["error"], "measured", name,
                f"3D, beta = {beta:+.3f}, {'sphere' if p.b == 0 else f'b = {p.b * 1e6:g} um'}")


def _stated(bound, unstated: str, zero: str) -> dict | None:
    """The cell of a rig's bound that decides without a model: not stated (None), undetermined; stated 0,
    exactly 0; else None (a model measures it)."""
    if bound is None:
        return cell(None, None, "bound", "the rig", unstated)
    if bound == 0:
        return cell(0.0, 0.0, "exact", "the rig", zero)
    return None


def tilt_cell(p: Point, store, inp: Inputs) -> dict:
    """The flat face tilted by the rig's bound: the sphere exactly 0; a face: the change of the slip index
    at the point itself in its apparatus, tilted minus aligned on the same 3D mesh (a stored 3D ``points``
    scene whose points carry the tilt, ``families.points.tilt_member``). The tilt is stated as an
    inequality ("less than"), so the change at the bound is a bound too (kind ``bound``: never
    "matters"). (Under force control below the friction limit, the tilt family's, it would bound no point
    that slides: a sliding point's change differs in sign and size, ``tests/test_punch3d.py``.)"""
    if p.b == 0:
        return cell(0.0, 0.0, "exact", "symmetry", "a tilted sphere is the same sphere displaced")
    stated = _stated(inp.tilt, "no tilt bound stated ([tolerances] tilt)", "a tilt of 0 stated")
    if stated is not None:
        return stated
    scenes = _relaxing(inp, "tilt")
    for s in scenes:
        res = store(s.name)
        if res is None:
            return missing(s.name, inp=inp)
        r = _row_at(p, s, res, tilt=inp.tilt)
        if r is None:
            continue
        why = "" if r.get("effect") is not None else (
            f": not resolved ({r.get('contact_vertices')} contact vertices)" if r.get("contact_vertices") is not None
            else ": no answer")
        return cell(r.get("effect"), r.get("error"), "bound", s.name,
                    f"3D, tilted - aligned at the point, b = {p.b * 1e6:g} um (aligned slip index "
                    f"{num(r.get('slip_index'), '.2g')}){why}")
    return cell(None, None, "bound", scenes[0].name if scenes else "the rig",
                f"b = {p.b * 1e6:g} um at {inp.tilt:.3g} rad not measured (a face below "
                "two elements of the 3D mesh)")


# ------------------------------------------------------------------ cells computed with MDR
def kink_cell(p: Point, inp: Inputs) -> dict:
    """The kink rounded by a fillet of the rig's bound against the sharp kink: the slip index's change
    (MDR in the apparatus; the effect grows with the width: a bound)."""
    from mdr.profiles import RoundedTruncatedSphere, TruncatedSphere

    if p.b == 0:
        return cell(0.0, 0.0, "exact", "geometry", "no kink")
    stated = _stated(inp.fillet, "no rounding of the kink stated ([indenter] kink_rounding)", "a sharp kink stated")
    if stated is not None:
        return stated
    if p.b < 2 * inp.fillet:
        return cell(None, None, "bound", "MDR apparatus", f"b = {p.b * 1e6:g} um: the fillet would take the face")
    R = inp.setup.R

    def fun(n):
        return slip_indices([RoundedTruncatedSphere(R, p.b, inp.fillet), TruncatedSphere(R, p.b)], [p, p], n=n,
                            setup=inp.setup)

    e, err = difference_with_grid(fun)
    return cell(e, err, "bound", "MDR apparatus", f"fillet {inp.fillet * 1e6:g} um")
