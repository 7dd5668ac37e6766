"""What MDR with an equivalent profile misses of the rough half-space in a rig's own apparatus: the error
the budget adds to a rig's roughness readings (``validation.budget_readings.reading_effect``), measured on
the readings' own surfaces.

For every reading a rig's contact runs (``validation.spectra``), each surface of its finer grid is driven by
the apparatus at every point of the rig on that contact (``validation.paper_points.rough_row_b``): the rough
half-space itself (``rough.law.RoughContact``) beside MDR with the equivalent profile of that surface's own
normal curve (``validation.families.roughness.rough_in_apparatus``). Per (reading, point) the difference's
mean over the surfaces and its standard error; the error is the largest |mean| + standard error over all of
them (as the paper's, ``budget_readings.equivalent_error``, over the catalogue's rough scenes). Each surface
is a task cached by content under the budget's readings folder, so a second budget reads them.
"""
from __future__ import annotations

import math
from dataclasses import asdict

import numpy as np

from common.errors import ConvergenceError, InputError

from . import spectra as SP
from .paper_points import Point


def check(task: dict) -> dict:
    """One surface (``task``: the member's ``member`` task, its ``curve`` and the ``points`` of its contact,
    plain data) driven by the apparatus at each point: ``rough_in_apparatus``'s rows, or ``failed``."""
    from rough.normal import Grid

    from .families.roughness import rough_in_apparatus

    m = task["member"]
    contact = SP.Contact.of(m["contact"])
    p, _, grid, heights, prof = SP.surface(m)
    plastic = contact.readings[m["reading"]].plastic
    try:
        rows = rough_in_apparatus(prof, contact.mat(), Grid(p.size, int(m["n"])), heights, task["curve"],
                                  [Point(**x) for x in task["points"]],
                                  hardness=contact.hardness if plastic else None,
                                  preload=SP.PRELOAD * contact.F_ref if plastic else None,
                                  app_kw=dict(task.get("apparatus") or ()))
    except (InputError, ConvergenceError) as e:
        return {"failed": str(e)}
    return {"rows": rows}


#: the sources a surface's run in the apparatus depends on besides its curve's (its cache key holds them)
CHECK_SOURCES = SP.MEMBER_SOURCES + ("mdr/*.py", "studies/paper.py", "validation/families/roughness.py",
                                     "validation/rig_roughness.py", "validation/paper_points.py",
                                     "fem/axisym/normal_run.py")


def tasks(contacts, members: list, points: dict, apparatus: tuple = ()) -> list:
    """One task per surface of each reading's finer grid on each contact with a curve (``members``:
    ``spectra.curves``'s), with the points of its contact (``points``: {b: [Point]}) and the apparatus's
    fields other than kx and mu2 (``apparatus``: (name, value) pairs)."""
    out = []
    for c in contacts:
        pts = [asdict(p) for p in points.get(c.b, ())]
        if not pts:
            continue
        ms = [m for m in members if m["contact"]["b"] == c.b and "curve" in m]
        for n in sorted({m["n"] for m in ms})[-1:]:
            out += [{"member": {k: m[k] for k in ("reading", "contact", "seed", "n")}, "curve": m["curve"],
                     "points": pts, "apparatus": [list(x) for x in apparatus]} for m in ms if m["n"] == n]
    return out


def equivalent_error(contacts, members: list, points: dict, folder, *, apparatus: tuple = (), jobs: int = 1,
                     log=None, executor=None) -> dict:
    """The equivalent profile's error in the rig's apparatus (module docstring): {"error": the largest
    |mean| + standard error, or None where a surface failed or nothing ran, "rows": [{contact, reading,
    point, mean, sem, surfaces}]}; the surfaces' runs (in ``jobs`` processes or on ``executor``) cached
    under ``folder`` (None: not cached)."""
    todo = tasks(contacts, members, points, apparatus)
    results = SP.cached_map(todo, check, folder, SP.member_version(CHECK_SOURCES), tag="apparatus", jobs=jobs,
                            log=log, what="the rough half-space in the rig's apparatus, surfaces", every=4,
                            executor=executor)
    groups = {}
    for t, r in zip(todo, results):
        g = groups.setdefault((t["member"]["contact"]["b"], t["member"]["reading"]), {"failed": False, "rows": []})
        g["failed"] |= "failed" in r
        g["rows"].append(r.get("rows") or [])
    rows, failed, by_b = [], False, {c.b: c for c in contacts}
    for (b, i), g in groups.items():
        failed |= g["failed"]
        for pt in points.get(b, ()):
            diffs = []
            for seed_rows in g["rows"]:
                hit = next((x for x in seed_rows if x["point"] == asdict(pt)), None)
                ok = hit and "failed" not in hit and hit.get("mdr_equivalent") is not None
                diffs.append(hit["mdr_equivalent"] - hit["rough_halfspace"] if ok else None)
            if any(d is None for d in diffs) or len(diffs) < 2:
                failed = True
                continue
            d = np.asarray(diffs)
            rows.append({"contact": b, "reading": by_b[b].readings[i].name, "point": asdict(pt), "mean": float(d.mean()),
                         "sem": float(d.std(ddof=1) / math.sqrt(d.size)), "surfaces": int(d.size)})
    worst = max((abs(r["mean"]) + r["sem"] for r in rows), default=None)
    return {"error": None if failed or worst is None else worst, "rows": rows}
