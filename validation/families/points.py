"""The family ``points``: the half-space at the apparatus points of the paper's results
(``validation.points``) that no other scene runs, the axisymmetric FE model against MDR in the apparatus
at each, so that the error budget (``validation.budget``, its column *curvature a/R*) reads a measured
difference at every point rather than a bound from the sphere.

The FE model relaxes what MDR assumes of the bodies: their real shape (the cap is the sphere itself, up
to its equator, with slopes up to a/R at the contact edge, 17 % for b = 1 mm) and their finite size
(blocks of 200 contact radii; the displacement in the half-space comparable measure, ``fem.bulk``).
It shares Mindlin's traction along x and the absence of normal-tangential coupling with MDR (the 3D
model relaxes those: ``assumptions-3d``). Each point runs as the pair family runs a scene
(``validation.families.pair``: both ladders, the time step's and the cycles' settling in the error
bars), as one task of the scene (``tasks``, ``member``), so a comparison spreads them over its workers.
"""
from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

from .. import metrics
from . import result_of
from ..scenes import Scene
from ..text import grade_text, num

#: the key of the family's rows in a result, and the title of its figure in the report
KEY = "points"
TITLE = "the paper's points in the apparatus"

#: the verdicts a member keeps (the others are those of any pair scene; the budget reads the slip index)
KEPT = ("contact_radius", "dissipation", "slip_index", "loop_Fx", "loop_du")


def point_variant(s: Scene, v: dict) -> Scene:
    """The scene of one point: ``v`` sets ``b`` (0: the sphere, else the truncated sphere's face
    radius) and ``kx``; the rest (load, amplitude, friction, ladders, steps) is the scene's."""
    b = float(v.get("b", s.b))
    return replace(s, name=f"{s.name}[b = {b * 1e6:g} um, kx = {float(v['kx']) / 1e6:g} N/um]",
                   profile="truncated" if b > 0 else "sphere", b=b, kx=float(v["kx"]), variants=(),
                   family="pair")


def tasks(s: Scene) -> list:
    """One task per point (variant); the widest faces first (their finest meshes cost the most)."""
    return sorted(({"variant": i} for i in range(len(s.variants))),
                  key=lambda t: -float(s.variants[t["variant"]].get("b", s.b)))


def member(s: Scene, task: dict) -> dict:
    """One point (``task["variant"]``): the pair family's run of ``point_variant`` without files, reduced
    to the verdicts of ``KEPT`` and the FE contact radius (plain data)."""
    from .pair import run as run_pair

    t0 = time.perf_counter()
    i = int(task["variant"])
    sv = point_variant(s, s.variants[i])
    res = run_pair(sv, None, fields=False)
    ver = {q: res["verdicts"][q] for q in KEPT if q in res["verdicts"]}
    return {"variant": i, "b": sv.b, "kx": sv.kx, "contact_radius": res["fem"].get("contact_radius"),
            "verdicts": ver, "runtime_s": time.perf_counter() - t0}


def _row(s: Scene, m: dict) -> dict:
    """A point's row: FE minus MDR of the slip index (its effect: what the half-space's shape costs the
    slip index there) with both sides' error bars, and the verdicts."""
    si = m["verdicts"].get("slip_index") or {}
    fe, md = si.get("fem"), si.get("mdr")
    err = None if si.get("fem_error") is None or si.get("mdr_error") is None else si["fem_error"] + si["mdr_error"]
    a = m.get("contact_radius")
    holds, grade = metrics.conjunction(m["verdicts"]), metrics.scene_grade(m["verdicts"])
    return {"variant": m["variant"], "b": m["b"], "kx": m["kx"], "a_over_R": None if a is None else a / s.R,
            "slip_index_fem": fe, "slip_index_mdr": md,
            "effect": None if fe is None or md is None else fe - md, "error": err,
            "bounded": bool(si.get("bounded")), "verdicts": m["verdicts"], "holds": holds, "grade": grade,
            "runtime_s": m.get("runtime_s")}


def run(s: Scene, out_dir=None, *, fields: bool = True, log=None, members: list | None = None) -> dict:
    """The scene: its points run here in turn unless ``members`` (their results, from ``member``) are
    given; one row per point (``_row``)."""
    t0 = time.perf_counter()
    log = log or (lambda msg: None)
    given = members is not None
    if members is None:
        members = []
        for task in tasks(s):
            members.append(member(s, task))
            log(f"  point {task['variant']}: {members[-1]['runtime_s']:.0f} s")
    rows = [_row(s, m) for m in sorted(members, key=lambda m: m["variant"])]
    for r in rows:
        log(f"  b = {r['b'] * 1e6:g} um, k_x = {r['kx'] / 1e6:g} N/um: slip index FE - MDR "
            f"{num(r['effect'], '+.2g')} +- {num(r['error'], '.2g')}: {r['grade']}")
    cpu = sum(m.get("runtime_s", 0.0) for m in members)
    res = result_of(s, KEY, rows, t0, out_dir, figure, members_cpu_s=cpu)
    if given:  # the tasks ran elsewhere: the scene's cost is theirs
        res["runtime_s"] = cpu
    return res


def table(res) -> list:
    lines = ["The paper's points in its apparatus (Table 2's load; b and k_x of Figs. 8-9 and Table 2 that no "
             "other scene runs): the axisymmetric FE model (the cap's real sphere, bodies of 200 a) against MDR, "
             "both on their ladders. FE - MDR of the slip index is what the half-space's shape costs there (the "
             "budget's column *curvature a/R*), with the sum of both error bars (mesh or grid, time step, "
             "cycles); the verdict is the catalogue's over the metrics listed.", "",
             "| b (um) | k_x (N/um) | a/R | slip index (MDR) | FE - MDR | error bar | MDR holds? |",
             "|---|---|---|---|---|---|---|"]
    for r in res[KEY]:
        failed = [q for q, x in r["verdicts"].items() if x.get("holds") is False]
        lines.append(f"| {num(r['b'] * 1e6, 'g')} | {num(r['kx'] / 1e6, 'g')} | {num(r.get('a_over_R'), '.2g')} | "
                     f"{num(r.get('slip_index_mdr'), '.3g')} | {num(r.get('effect'), '+.2g')} | "
                     f"{num(r.get('error'), '.2g')}{'' if r.get('bounded') else ' (spread)'} | "
                     f"{grade_text(r)}{': ' + ', '.join(failed) if failed else ''} |")
    return lines


def figure(result: dict, out_dir) -> dict:
    """FE - MDR of the slip index (with its error bar) against k_x, one line per face radius b (set
    slightly apart where they share a k_x), inside the budget's resolution (0.01 of the slip index)."""
    from ..figures import plt, save

    rows = [r for r in result[KEY] if r.get("effect") is not None]
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    faces = sorted({r["b"] for r in rows})
    for j, b in enumerate(faces):
        sel = sorted((r for r in rows if r["b"] == b), key=lambda r: r["kx"])
        dodge = 1.0 + 0.03 * (j - (len(faces) - 1) / 2)  # side by side where the faces share a k_x
        ax.errorbar([dodge * r["kx"] / 1e6 for r in sel], [r["effect"] for r in sel],
                    yerr=[r["error"] or 0.0 for r in sel], marker="o", capsize=3, label=f"b = {b * 1e6:g} um")
    ax.axhspan(-0.01, 0.01, color="0.92", zorder=0, label="budget resolution (0.01)")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("axis stiffness k_x (N/um)")
    ax.set_ylabel("slip index, FE - MDR")
    ax.set_title("The half-space's shape at the paper's points (Table 2's load)", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    if rows:
        ax.legend(fontsize=7)
    fig.tight_layout()
    return {KEY: save(fig, Path(out_dir) / "points.png")}
