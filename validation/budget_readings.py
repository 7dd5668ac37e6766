"""The budget's cells over readings of an input the paper leaves open, each checked against the paper's own
loops (``validation.consistency``): the roughness and the brass plates.

The roughness: each admitted reading of the paper's roughness at each point, and the range they
span (``roughness_cell``), the paper's loops as the check that admits a reading (``admitted``), the
sticking transition over the admitted readings (``transitions``).

A reading on a contact (``validation.spectra.READINGS``, or a rig's stated spectrum or measured maps: the
contact's ``readings``) is four surfaces (one per measured map), each on two grids; each surface's
normal force-approach curve gives MDR's equivalent profile (``mdr.equivalent.EquivalentProfile``), driven by
the apparatus at the point at the paper's mu1. Per reading the change of the slip index against the smooth
indenter is the surfaces' mean on the finer grid, and its bar, for the paper's one specimen pair, is

- the standard deviation over the surfaces (``surfaces_sd``; the standard error ``sem`` is the bar of the
  ensemble mean, named as such);
- the grid: the change of the mean from the coarser grid;
- the curve's sampling: the largest change of a surface's slip index when its curve is read from every
  other load (``rough.equivalent.CURVE_FRACTIONS``: 24 loads against 12);
- what MDR with the equivalent profile misses of the rough half-space itself in the apparatus: the largest
  |mean difference| + its standard error over every point where the catalogue's scenes ``roughness`` and
  ``roughness-faces`` ran both (``equivalent_error``).

The cell's ``range`` is [smallest, largest] change over the readings the paper's loops admit
(``validation.consistency``: the sphere's readings by Figs. 4-5, a face's by Figs. 6-7), its ``error`` the
largest bar among them; it "matters" only where the whole range with that bar lies beyond the resolution
on one side, is "negligible" where all of it lies within, and is "undetermined" otherwise.

Wavelengths longer than a contact's grid are form (``validation.spectra``). On the sphere's contact (the
shortest of them 32 contact radii) the form is a curvature: each reading's range adds the change of the
slip index when the sphere's curvature takes the form's two standard deviations (``form_effect``; the
cell's ``form_curvature`` is that rms curvature times R). On a face (the grid 4 radii) a reading that
leaves more than ``spectra.FORM_SHARE_MAX`` of its variance out is not resolved, and a cell with an
admitted reading unresolved is undetermined; below that share, the error holds share x |effect| (the
effect taken as proportional to the variance).

The brass plates: ``validation.budget_plates``.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from common.errors import ConvergenceError, InputError
from mdr.materials import Materials

from . import spectra as SP
from .paper_points import PAPER, RESOLUTION, Point, Setup, point_slip_index, rough_row_b, slip_indices
from .scenes import ROUGH_FACES_B

R_INDENTER = SP.R_INDENTER

#: the scenes whose rough half-space in the apparatus measures what the equivalent profile misses
ROUGH_SCENES = ("roughness", "roughness-faces")
#: the slip index that marks the sticking transition of Fig. 9 (docs/apparatus.md: the paper's lies
#: between 1 and 2 N/um at 0.1)
TRANSITION_SLIP_INDEX = 0.1


def contacts() -> tuple:
    """The rough contacts of the paper's points: the sphere's and each face's of ``ROUGH_FACES_B``."""
    return (SP.SPHERE,) + tuple(SP.face(b) for b in ROUGH_FACES_B)


def equivalent_error(store):
    """The largest |equivalent MDR - rough half-space| + its standard error of the slip index over every
    apparatus point of the stored rough scenes, or None where none is stored."""
    worst = None
    for name in ROUGH_SCENES:
        for row in (store(name) or {}).get("roughness", []):
            for x in row.get("apparatus") or []:
                em = x.get("equivalent_minus_rough") if isinstance(x, dict) else None
                if em and all(isinstance(em.get(k), (int, float)) and math.isfinite(em[k]) for k in ("mean", "sem")):
                    e = abs(em["mean"]) + em["sem"]
                    worst = e if worst is None else max(worst, e)
    return worst


class Readings:
    """The equivalent profiles of every reading's surfaces on every contact (``members``: from
    ``validation.spectra.curves`` on ``contacts``, default the paper's), with the slip indices they give
    at points (in the apparatus of ``setup``) computed once each."""

    def __init__(self, members: list, contacts: tuple | None = None, setup: Setup = PAPER):
        self.contacts = {c.b: c for c in (contacts or globals()["contacts"]())}
        self.setup = setup
        self.by = {}
        for m in members:
            key = (m["contact"]["b"], m["reading"])
            self.by.setdefault(key, []).append(m)
        self._si = {}

    def members(self, b: float, reading: int):
        """(coarser grid's, finer grid's) members of a reading on a contact, each sorted by seed; None
        where one failed."""
        ms = self.by.get((b, SP.canonical(reading, self.contacts[b])), [])
        if not ms or any("failed" in m for m in ms):
            return None
        grids = sorted({m["n"] for m in ms})
        return tuple(sorted((m for m in ms if m["n"] == n), key=lambda m: m["seed"]) for n in grids)

    @staticmethod
    def profile(m: dict, every: int = 1):
        """A member's equivalent profile (its contact's materials)."""
        from mdr.equivalent import EquivalentProfile

        d, F = np.asarray(m["curve"]["d"]), np.asarray(m["curve"]["F"])
        mat = Materials(*m["contact"]["materials"])
        return EquivalentProfile(d[::-1][::every][::-1], F[::-1][::every][::-1], mat)

    def slip_index(self, m: dict, p: Point, every: int = 1) -> float:
        """The apparatus slip index of a member's equivalent profile at the point (its curve read from
        every ``every``-th load, counted from the largest)."""
        key = (id(m), p, every)
        if key not in self._si:
            self._si[key] = slip_indices([self.profile(m, every)], [p], setup=self.setup)[0]
        return self._si[key]


def form_effect(p: Point, kappa: float, smooth: float, setup: Setup = PAPER) -> list:
    """The sphere's form beyond the grid: the slip index's changes [lo, hi] (0 included) when the
    indenter's curvature 1/R takes the form's two standard deviations, 1/R -+ 2 kappa (``kappa``: the rms
    mean curvature the grid leaves out, 1/m; MDR in the apparatus; the changes added to the roughness's:
    the form and the asperities taken as independent)."""
    from mdr.profiles import TruncatedSphere

    if kappa <= 0:
        return [0.0, 0.0]
    c = 2.0 * kappa
    R0 = setup.R
    if c * R0 >= 1.0:
        raise InputError(f"the form's curvature 2 x {kappa:.3g} 1/m turns the sphere concave")
    radii = [1.0 / (1.0 / R0 + c), 1.0 / (1.0 / R0 - c)]
    si = slip_indices([TruncatedSphere(r, 0.0) for r in radii], [p, p], setup=setup)
    return [min(0.0, *(x - smooth for x in si)), max(0.0, *(x - smooth for x in si))]


def reading_effect(R: Readings, b: float, i: int, p: Point, smooth: float, eq_error: float | None) -> dict | None:
    """One reading's change of the point's slip index with its bar (module docstring) and, on the sphere,
    the range its form beyond the grid adds (``form``); None where a member failed or gives no equivalent
    profile, or where one grid or one surface leaves a part of the bar unmeasured; {"effect": None,
    "unresolved": why} where the contact's grid does not resolve the reading (``spectra.resolved``).
    ``eq_error`` None: the equivalent profile's error not measured (left out of the bar, said by
    ``roughness_cell``)."""
    contact = R.contacts[b]
    try:
        if not SP.resolved(contact.readings[i], contact):
            share = SP.form_share(contact.readings[i], contact)
            return {"effect": None, "unresolved": f"{share:.0%} of its variance lies beyond the grid of {contact.period:g} a"}
    except InputError as e:  # a reading the contact's scales cannot hold (its waviness below the band)
        return {"effect": None, "unresolved": str(e)}
    levels = R.members(b, i)
    if levels is None or len(levels) < 2 or len(levels[-1]) < 2:
        return None  # one grid gives no grid error, one surface no spread
    try:
        coarse = np.array([R.slip_index(m, p) for m in levels[0]])
        fine = np.array([R.slip_index(m, p) for m in levels[-1]])
        half = np.array([R.slip_index(m, p, every=2) for m in levels[-1]])
    except (InputError, ConvergenceError):
        return None
    sd = float(fine.std(ddof=1)) if fine.size > 1 else 0.0
    grid, sampling = abs(fine.mean() - coarse.mean()), float(np.max(np.abs(half - fine)))
    m0 = levels[-1][0]
    try:
        form = form_effect(p, m0["form_curvature"], smooth, R.setup) if not b else [0.0, 0.0]
    except InputError as e:  # the form beyond the grid as large as the sphere's own curvature
        return {"effect": None, "unresolved": str(e)}
    beyond = SP.form_share(contact.readings[i], contact) * abs(fine.mean() - smooth) if b else 0.0
    return {"effect": float(fine.mean() - smooth), "form": form, "slip_index": float(fine.mean()), "surfaces_sd": sd,
            "sem": sd / math.sqrt(fine.size), "grid": float(grid), "sampling": sampling, "equivalent": eq_error,
            "beyond_grid": beyond, "error": sd + grid + sampling + (eq_error or 0.0) + beyond, "members": fine.tolist(),
            "rms_window": m0["rms_window"], "form_curvature": m0["form_curvature"] * contact.R}


def grade_range(lo: float, hi: float, err: float, resolution: float = RESOLUTION) -> str:
    """The verdict of a range of effects with a bar: ``matters`` only where all of it lies beyond the
    resolution on one side, ``negligible`` where all of it lies within."""
    if max(abs(lo), abs(hi)) + err <= resolution:
        return "negligible"
    if hi + err < -resolution or lo - err > resolution:
        return "matters"
    return "undetermined"


def range_cell(per: dict, admitted: set | None, source: str, what: str) -> dict:
    """A cell over readings: ``per`` {name: effect dict or None}; the range over the ``admitted`` ones
    (None: every reading, none checked: a rig without measured loops)."""
    checked = admitted is not None
    admitted = set(per) if admitted is None else admitted
    ok = {k: v for k, v in per.items() if v is not None and v["effect"] is not None and k in admitted}
    unresolved = sorted(k for k, v in per.items() if k in admitted and v is not None and v.get("unresolved"))
    excluded = sorted(k for k in per if k not in admitted)
    out = {"kind": "range", "source": source, "readings": per, "excluded": excluded, "admitted": sorted(ok),
           "unresolved": unresolved}
    if not ok:
        why = ("every reading excluded by the paper's loops" if per and len(excluded) == len(per) else
               f"no admitted reading resolved ({per[unresolved[0]]['unresolved']})" if unresolved else "not computed")
        return {**out, "effect": None, "error": None, "range": None, "verdict": "undetermined",
                "note": f"{what}: {why}"}
    err = max(v["error"] for v in ok.values())
    lo = min(v["effect"] + v.get("form", [0.0, 0.0])[0] for v in ok.values())
    hi = max(v["effect"] + v.get("form", [0.0, 0.0])[1] for v in ok.values())
    ref = ok.get("ISO band") or next(iter(ok.values()))
    note = (f"{what}: {len(ok)} of {len(per)} readings {'admitted' if checked else 'run'}, slip index {min(v['slip_index'] for v in ok.values()):.2g}"
            f"-{max(v['slip_index'] for v in ok.values()):.2g}")
    if unresolved:
        note += f"; {len(unresolved)}{' admitted' if checked else ''} not resolved by the grid ({per[unresolved[0]]['unresolved']})"
    return {**out, "effect": ref["effect"], "error": err, "range": [lo, hi], "surfaces_sd": ref["surfaces_sd"],
            "sem": ref["sem"], "form_curvature": max(v["form_curvature"] for v in ok.values()),
            "verdict": "undetermined" if unresolved else grade_range(lo, hi, err), "note": note}


def roughness_cell(p: Point, R: Readings, admitted: dict, eq_error, eq_missing: str | None = None) -> dict:
    """The point's roughness cell: every reading on the point's contact (``rough_row_b``: the sphere's for
    faces inside its contact), the range over those ``admitted`` (by contact kind: "sphere", "face").
    ``eq_error`` None: the paper's cell names the scenes that measure it; a rig's (``eq_missing``, why)
    shows the range without it, ``incomplete``: undetermined whatever its range."""
    b = rough_row_b(p, R.setup)
    what = "sphere" if not b else f"b = {b * 1e6:g} um"
    if eq_error is None and eq_missing is None:
        return {"kind": "range", "effect": None, "error": None, "range": None, "verdict": "undetermined",
                "source": "roughness readings", "note": f"{what}: the equivalent profile's error not measured "
                "(run python -m validation.compare --scenes roughness,roughness-faces)"}
    smooth = point_slip_index(replace(p, b=b), setup=R.setup)
    per = {r.name: reading_effect(R, b, i, p, smooth, eq_error) for i, r in enumerate(R.contacts[b].readings)
           if R.contacts[b].runs(r)}
    c = range_cell(per, admitted["face" if b else "sphere"], "roughness readings", what)
    if admitted["face" if b else "sphere"] is None and any(v is None for v in per.values()):
        c = {**c, "verdict": "undetermined", "incomplete": True,
             "note": f"{c['note']}; a reading failed ({', '.join(k for k, v in per.items() if v is None)})"}
    if eq_error is None:
        c = {**c, "verdict": "undetermined", "incomplete": True, "note": f"{c['note']}; {eq_missing}"}
    return c


def rig_roughness_cell(p: Point, R: Readings | None, eq_error: float | None, admitted: dict | None = None) -> dict:
    """A rig of one's own: the readings of its stated rms values on its contacts (``R``; None where it
    states none) that its measured loops admit (``admitted``: {kind: names}, from ``consistency``; a kind
    without loops, or None: every reading), with the equivalent profile's error measured in the rig's
    apparatus (``validation.rig_roughness``; None where a surface failed there: the cell shows its range
    and is undetermined)."""
    if R is None:
        return {"kind": "range", "effect": None, "error": None, "range": None, "verdict": "undetermined",
                "source": "roughness readings", "note": "the rig states no rms roughness"}
    c = roughness_cell(p, R, {"sphere": None, "face": None, **(admitted or {})}, eq_error,
                       "the equivalent profile's error in the rig's apparatus not measured (a surface failed)")
    if R.contacts[rough_row_b(p, R.setup)].hardness is None:
        c = {**c, "note": f"{c['note']}; elastic readings only (no hardness stated)"}
    return c


def surface_checks(m: dict, loops: tuple, app_kw=None) -> dict:
    """The measured ``loops`` of a contact (``validation.consistency.Loop``) against one surface (a
    member's equivalent profile, on its contact's materials; ``app_kw``: the apparatus's fields): {loop:
    check}, or {"failed": why}."""
    from .consistency import check

    try:
        prof = Readings.profile(m)
        return {lp.key: check(prof, lp, app_kw, prof.materials) for lp in loops}
    except (InputError, ConvergenceError) as e:
        return {"failed": str(e)}


def _surface_checks(args: tuple) -> dict:
    """``surface_checks`` of one task (member, loops, apparatus fields): top level, a task of
    ``validation.spectra.map_tasks``."""
    return surface_checks(*args)


def loop_contacts(loops: tuple, setup: Setup = PAPER) -> dict:
    """The measured loops by the kind of their rough contact ("sphere", "face": ``rough_row_b``): {kind:
    (b, loops)}; InputError where a kind's loops lie on two face radii (one face contact checks a reading)."""
    out = {}
    for lp in loops:
        b = rough_row_b(lp.point, setup)
        kind = "face" if b else "sphere"
        if kind in out and out[kind][0] != b:
            raise InputError(f"the measured loops lie on faces of two radii ({out[kind][0]:g} and {b:g} m): "
                             "give the loops of one face")
        out[kind] = (b, out.get(kind, (b, ()))[1] + (lp,))
    return out


def consistency(R: Readings, log=None, jobs: int = 1, loops: tuple | None = None, executor=None) -> dict:
    """The measured loops (default the paper's, ``consistency.paper_loops``) against every reading
    (``surface_checks``) on each surface of the finer grid of each loop's contact (``loop_contacts``: the
    paper's sphere by Figs. 4-5, its face of b = 0.6 mm by Figs. 6-7); each surface once (a reading that
    coincides with another on a contact shares its surfaces), in ``jobs`` processes or on ``executor``
    (``validation.spectra.map_tasks``). Returns {"sphere" |
    "face": [{reading, surfaces: [{loop: check}], consistent_surfaces, admitted}]}; a reading is admitted
    where at least one of its surfaces passes every check of its contact (the specimen may be that
    surface), excluded where none does."""
    from .consistency import paper_loops

    log = log or (lambda msg: None)
    contacts = loop_contacts(paper_loops() if loops is None else loops, R.setup)
    levels = {(kind, i): R.members(b, i) for kind, (b, _) in contacts.items()
              for i in range(len(R.contacts[b].readings))}
    todo = {}
    for (kind, _), lv in levels.items():
        for m in (lv[-1] if lv else []):
            todo.setdefault((kind, id(m)), (m, contacts[kind][1], R.setup.app_kw or None))
    log(f"budget: the measured loops against {len(todo)} surfaces, "
        + (f"{jobs} process(es)" if executor is None else "the executor's workers"))
    keys = list(todo)
    done = dict(zip(keys, SP.map_tasks([todo[k] for k in keys], _surface_checks, jobs, log, "the measured loops' "
                                       "surfaces", max(1, len(keys)), executor)))
    out = {}
    for kind, (b, _) in contacts.items():
        rows = []
        for i, r in enumerate(R.contacts[b].readings):
            lv = levels[(kind, i)]
            surfaces = [done[(kind, id(m))] for m in (lv[-1] if lv else [])]
            good = sum(1 for x in surfaces if "failed" not in x and all(c["consistent"] for c in x.values()))
            m0 = lv[-1][0] if lv else {}
            try:
                j = SP.canonical(i, R.contacts[b])
            except InputError:
                j = i
            rows.append({"reading": r.name, "same_as": None if j == i else R.contacts[b].readings[j].name,
                         "surfaces": surfaces, "consistent_surfaces": good,
                         "admitted": good > 0, "window": {"rms": m0.get("rms_window"),
                                                          "form": m0.get("form_curvature", 0.0) * R.contacts[b].R}})
        out[kind] = rows
    return out


def admitted_names(cons: dict) -> dict:
    return {kind: {r["reading"] for r in rows if r["admitted"]} for kind, rows in cons.items()}


def sticking_transition(profile, p: Point = Point(b=0.0), *, lo=0.05e6, hi=100e6, iters=12) -> float | None:
    """The axis stiffness k_x (N/m) where the apparatus's slip index passes ``TRANSITION_SLIP_INDEX`` at
    the point's load (Table 2's), by bisection on log k_x (the slip index grows with k_x: a stiffer
    axis leaves more of the stroke to the contact); None where it does not pass it in [lo, hi]."""
    def si(kx):
        return slip_indices([profile], [replace(p, kx=kx)])[0] - TRANSITION_SLIP_INDEX

    if si(lo) > 0 or si(hi) < 0:
        return None
    for _ in range(iters):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if si(mid) < 0 else (lo, mid)
    return math.sqrt(lo * hi)


def form_factors(kappa: float, smooth: float) -> list:
    """The sphere's form beyond the grid on the sticking transition: [lo, hi] factors (1 included) of the
    smooth sphere's transition when its curvature takes the form's two standard deviations, 1/R -+ 2 kappa
    (``form_effect``'s reading of the form, applied as the same relative change to a rough reading's)."""
    from mdr.profiles import TruncatedSphere

    if kappa <= 0:
        return [1.0, 1.0]
    c = 2.0 * kappa
    ks = [sticking_transition(TruncatedSphere(1.0 / (1.0 / R_INDENTER + s * c), 0.0)) for s in (1.0, -1.0)]
    ratios = [k / smooth for k in ks if k is not None]
    return [min(1.0, *ratios), max(1.0, *ratios)]


def transitions(R: Readings, admitted: dict) -> dict:
    """The sticking transition of the smooth sphere and of every reading of the sphere's roughness (the
    surfaces of the finer grid: mean, standard deviation, and the factors its form beyond the grid adds,
    ``form_factors``), and the range over the admitted readings: means -+ one standard deviation, times
    the form's factors."""
    from mdr.profiles import TruncatedSphere

    smooth = sticking_transition(TruncatedSphere(SP.R_INDENTER, 0.0))
    rows = [{"reading": "smooth", "kx": smooth, "sd": 0.0, "form": [1.0, 1.0], "admitted": True}]
    for i, r in enumerate(R.contacts[0.0].readings):
        levels = R.members(0.0, i)
        ks = None
        if levels:
            try:
                ks = [sticking_transition(R.profile(m)) for m in levels[-1]]
            except (InputError, ConvergenceError):
                ks = None
        ok = ks is not None and all(k is not None for k in ks)
        form = form_factors(levels[-1][0]["form_curvature"], smooth) if ok else [1.0, 1.0]
        rows.append({"reading": r.name, "kx": float(np.mean(ks)) if ok else None,
                     "sd": float(np.std(ks, ddof=1)) if ok and len(ks) > 1 else None, "form": form,
                     "admitted": r.name in admitted["sphere"]})
    ad = [x for x in rows[1:] if x["admitted"] and x["kx"] is not None]
    rng = None if not ad else [min((x["kx"] - (x["sd"] or 0.0)) * x["form"][0] for x in ad),
                               max((x["kx"] + (x["sd"] or 0.0)) * x["form"][1] for x in ad)]
    return {"rows": rows, "range": rng}


def readings_markdown(b: dict) -> list:
    """The budget's tables of the readings: the paper's loops against each reading of the roughness and of
    the plates (admitted or excluded, and why), and the sticking transition per reading."""
    from .text import num

    lines, paper = [], b.get("paper", True)
    intro = ("The paper's loops as a check of each reading of its roughness (validation.consistency: mu1 fitted to "
             "the measured force amplitude mu1 F0 as the paper fitted it, within 0.02 F0; Figs. 6-7 in gross slip "
             "at the fitted mu1)" if paper else
             "The rig's measured loops as a check of each reading of its roughness (validation.consistency: mu1 "
             "fitted to each loop's measured force amplitude, within 0.02 F0; gross slip at the fitted mu1 where "
             "it was seen)")
    for kind, rows in (b.get("consistency") or {}).items():
        figs = sorted({f for r in rows for s in r["surfaces"] for f in s if f != "failed"})
        if not lines:
            lines += ["", intro + ": per reading the surfaces that pass every check, the largest reachable "
                          "amplitude over the surfaces and the fitted mu1 (N; '-' where unreachable). A reading "
                          "is admitted where one surface passes.", "",
                      "| contact | reading | rms in the window (um) | form curvature x R | "
                      + " | ".join(f"{f}: reachable, mu1" for f in figs) + " | surfaces consistent | admitted |",
                      "|---|---|---|---|" + "---|" * len(figs) + "---|---|"]
        for r in rows:
            ok = [s for s in r["surfaces"] if "failed" not in s]
            cols = []
            for f in figs:
                reach = max((s[f]["reachable"] for s in ok if f in s), default=None)
                mus = [s[f]["mu_fit"] for s in ok if f in s and s[f]["mu_fit"] is not None]
                cols.append(f"{num(reach, '.3f')}, " + (f"{min(mus):.2f}-{max(mus):.2f}" if mus else "-"))
            w = (r.get("window") or {})
            name = r["reading"] + (f" (= {r['same_as']} here)" if r.get("same_as") else "")
            lines.append(f"| {kind} | {name} | {num(w.get('rms'), '.2f', 1e6)} | {num(w.get('form'), '.2g')} | "
                         + " | ".join(cols) + f" | {r['consistent_surfaces']} of {len(r['surfaces'])} | "
                         f"{'yes' if r['admitted'] else '**no**'} |")
    pc = b.get("plates_consistency") or []
    if pc:
        lines += ["", "The same check of the brass plates' readings (the smooth indenters, "
                      f"{'Figs. 4-7' if paper else 'the measured loops'}): "
                      + "; ".join(f"{r['reading']} {'admitted' if r['admitted'] else 'excluded (' + '; '.join(c['why'] for c in r['checks'].values() if not c['consistent']) + ')'}"
                                  for r in pc) + "."]
    t = b.get("transition")
    if t:
        lines += ["", f"The sticking transition (Fig. 9: k_x where the slip index passes {TRANSITION_SLIP_INDEX:g}; "
                      "the paper's lies between 1 and 2 N/um), the sphere at Table 2's load in the apparatus, MDR "
                      "with the smooth profile and with each reading's equivalent profiles (mean +- standard "
                      "deviation over its surfaces):", "", "| surface | k_x (N/um) | admitted |", "|---|---|---|"]
        for x in t["rows"]:
            val = "undetermined" if x["kx"] is None else num(x["kx"], ".2f", 1e-6) + (
                f" +- {num(x['sd'], '.2f', 1e-6)}" if x["sd"] else "")
            lines.append(f"| {x['reading']} | {val} | {'yes' if x['admitted'] else 'no'} |")
        if t["range"]:
            lines += ["", f"Over the admitted readings the transition lies in {num(t['range'][0], '.2f', 1e-6)}-"
                          f"{num(t['range'][1], '.2f', 1e-6)} N/um (means +- one standard deviation, widened by "
                          "the form beyond the grid: the smooth sphere's transition at 1/R -+ 2 kappa)."]
    return lines
