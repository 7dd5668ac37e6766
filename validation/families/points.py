"""The family ``points``: the paper's results at their own apparatus points (``validation.paper_points``),
each point a task of the scene (``tasks``, ``member``), so a comparison spreads them over its workers.
What a point measures is what the scene's FE model relaxes beyond MDR there:

- ``fe_model = "axisym"`` (scene ``halfspace-points``): **the half-space's shape**, the axisymmetric FE
  model against MDR, as the pair family runs a scene (``validation.families.pair``: both ladders, the
  time step's and the cycles' settling in the error bars). The FE model relaxes what MDR assumes of
  the bodies: their real shape (the cap is the sphere itself, up to its equator, with slopes up to
  a/R at the contact edge, 17 % for b = 1 mm) and their finite size (blocks of 200 contact radii; the
  displacement in the half-space comparable measure, ``fem.bulk``). It shares Mindlin's traction along
  x and the absence of normal-tangential coupling with MDR.
- ``fe_model = "3d"`` (scene ``direction-points``): **Mindlin's traction direction**, the 3D model with
  a traction of free direction against the same mesh with q_y = 0 (``FEContact3D.assuming``), both in
  the apparatus; the difference of the pair cancels the discretisation error the two share, so a
  short 3D ladder resolves it (``direction_member``).
- ``fe_model = "3d"``, a point with a ``tilt`` (scene ``tilt-points``): **the face's alignment**, the 3D
  model with the face tilted about y by ``tilt`` against the aligned face on the same mesh, the loaded
  edge refined as the tilt family's rows resolve it (``tilt_member``).

The effect of a point is a change of its slip index (the dissipation per cycle over 4 mu1 F0 u_A),
what the error budget (``validation.budget``: columns *curvature a/R*, *traction direction*, *tilt*) reads.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from pathlib import Path

from .. import metrics
from . import members_of, number, result_of_members, variant_keys
from ..paper_points import RESOLUTION, SCENE_FIELDS
from ..scenes import Scene
from ..text import grade_text, num

#: the key of the family's rows in a result, and the title of its figure in the report
KEY = "points"
TITLE = "the paper's points in the apparatus"

#: the verdicts a member keeps (the others are those of any pair scene; the budget reads the slip index)
KEPT = ("contact_radius", "dissipation", "slip_index", "loop_Fx", "loop_du")


#: a point variant's fields and their valid ranges (``Variant.of``; ``R`` the scene's indenter radius)
RANGES = {"kx": (lambda x, s: x > 0, "> 0 (N/m)"),
          "b": (lambda x, s: 0 <= x < s.R, "in [0, R) (m; 0 the sphere)"),
          "F0": (lambda x, s: x > 0, "> 0 (N)"),
          "dF": (lambda x, s: x >= 0, ">= 0 (N), below F0"),
          "ua": (lambda x, s: x > 0, "> 0 (m)"),
          "mu1": (lambda x, s: x > 0, "> 0 (the slip index divides by it)"),
          "mu2": (lambda x, s: x >= 0, ">= 0")}


@dataclass(frozen=True)
class Variant:
    """One apparatus point of a points scene: its axis stiffness ``kx`` (N/m) and optionally the other
    fields of a point (``validation.paper_points.Point``: ``b`` (0: the sphere, else the truncated sphere's
    face radius), the load ``F0`` and ``dF``, the amplitude ``ua``, the friction ``mu1``, ``mu2``; None:
    the scene's). The ladders, steps and FE model are the scene's."""

    kx: float
    b: float | None = None
    F0: float | None = None
    dF: float | None = None
    ua: float | None = None
    mu1: float | None = None
    mu2: float | None = None
    #: a 3D point's face tilted about y by this angle (rad) against aligned (None: the traction direction)
    tilt: float | None = None

    @classmethod
    def of(cls, v: dict, scene: Scene) -> "Variant":
        """The mapping ``v`` checked (``RANGES``; the point's scene then meets the scene's own checks; a
        ``tilt`` in (0, pi/2) rad on a 3D scene's face, b > 0)."""
        bad = variant_keys(scene, "point", v, tuple(SCENE_FIELDS) + ("tilt",))
        if "kx" not in v:
            raise bad("kx", RANGES["kx"][1])
        out = cls(**{k: number(v, k, lambda x, ok=ok: ok(x, scene), bad, rng)
                     for k, (ok, rng) in RANGES.items() if k in v})
        if "tilt" in v:
            if scene.fe_model != "3d" or not (v.get("b", scene.b) or 0) > 0:
                raise bad("tilt", "only on a face (b > 0) of a scene with fe_model '3d'")
            out = replace(out, tilt=number(v, "tilt", lambda x: 0 < x < 0.5 * math.pi, bad, "in (0, pi/2) (rad)"))
        sv = out.scene(scene)  # the point's scene checked whole (dF below F0, the drive's ranges)
        if out.tilt is not None:
            from .tilt import Variant as TiltVariant, edge_variant

            TiltVariant.of(edge_variant(sv, out.tilt), sv, force=False)  # its meshes, checked before any run
        return out

    def given(self) -> dict:
        """The fields the variant sets (the rest are the scene's)."""
        return {k: getattr(self, k) for k in SCENE_FIELDS if getattr(self, k) is not None}

    def scene(self, s: Scene) -> Scene:
        """The pair scene of this point of ``s`` (the sphere where b = 0, else the truncated sphere)."""
        kw = {SCENE_FIELDS[k]: x for k, x in self.given().items()}
        b = kw.get("b", s.b)
        load = "" if not {"F0", "dF", "ua", "mu1", "mu2"} & set(self.given()) else f", F0 = {kw.get('F0', s.F0):g} N"
        return replace(s, name=f"{s.name}[b = {b * 1e6:g} um, kx = {kw['kx'] / 1e6:g} N/um{load}]",
                       profile="truncated" if b > 0 else "sphere", variants=(), family="pair", **kw)


def tasks(s: Scene) -> list:
    """One task per point (variant); the widest faces first (their finest meshes cost the most)."""
    b = [s.b if v.b is None else v.b for v in s.typed_variants]
    return sorted(({"variant": i} for i in range(len(b))), key=lambda t: -b[t["variant"]])


def member(s: Scene, task: dict) -> dict:
    """One point (``task["variant"]``), plain data: of an axisymmetric scene the pair family's run of
    the point's scene (``Variant.scene``) without files, reduced to the verdicts of ``KEPT`` and the FE
    contact radius; of a 3D scene ``direction_member``, or ``tilt_member`` for a point with a tilt. A solver that does not converge leaves the point ``failed`` (its
    row undetermined) and the scene goes on."""
    from .pair import run as run_pair

    from common.errors import ConvergenceError

    t0 = time.perf_counter()
    i = int(task["variant"])
    v = s.typed_variants[i]
    sv = v.scene(s)
    try:
        if s.fe_model == "3d":
            return {"variant": i, "b": sv.b, "kx": sv.kx,
                    **(direction_member(sv) if v.tilt is None else tilt_member(sv, v.tilt)),
                    "runtime_s": time.perf_counter() - t0}
        res = run_pair(sv, None, fields=False)
    except ConvergenceError as e:  # a point without an answer is undetermined; the scene goes on
        return {"variant": i, "b": sv.b, "kx": sv.kx, "failed": str(e), "runtime_s": time.perf_counter() - t0}
    ver = {q: res["verdicts"][q] for q in KEPT if q in res["verdicts"]}
    return {"variant": i, "b": sv.b, "kx": sv.kx, "contact_radius": res["fem"].get("contact_radius"),
            "verdicts": ver, "runtime_s": time.perf_counter() - t0}


#: the scene fields that name a point's run but do not enter its numbers
_NAMING = ("name", "title", "notes", "group", "quick")


def member_physics(s: Scene, task: dict) -> dict:
    """What a point's run computes from (``validation.runner.member_key``): its pair scene's data
    (``Variant.scene``) but the fields that name it, numbers to 12 significant digits, so the same point
    in two scenes (the catalogue's and a rig's: a file's 0.07 and the code's 0.2 x 0.35) is one
    computation. The numbers of the two differ by the rounding of their inputs alone (1e-12 relative)."""
    v = s.typed_variants[int(task["variant"])]
    tilt = {} if v.tilt is None else {"tilt": v.tilt}
    return _rounded({**{k: x for k, x in v.scene(s).as_dict().items() if k not in _NAMING}, **tilt})


def _rounded(x):
    """``x`` with every float to 12 significant digits (nested lists and dicts)."""
    if isinstance(x, float):
        return float(f"{x:.12g}")
    if isinstance(x, dict):
        return {k: _rounded(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_rounded(v) for v in x]
    return x


#: the 3D time step: the effect at the coarsest level again with this many times the steps; the change
#: joins the effect's error bar (the 3D runs cost too much to ladder the step at the finest level). Not
#: about half the steps: those runs are off by as much as the scene's own (Fig. 7's tilt on the coarser
#: mesh: -0.0227, -0.0234, -0.0263, -0.0264 at 20, 40, 80, 160 steps; the bar of the finer mesh's -0.0247
#: holds its -0.0276 at 160 steps: tests/test_points_family.py)
STEP_FACTOR = 2


def _effects_per_cycle(relaxed: dict, reference: dict) -> list:
    """The effect relaxed - reference of every closed cycle (the cycle from rest left out) in slip-index
    units."""
    scale = reference["slip_index"] / reference["dissipation"] if reference["dissipation"] else 0.0
    return [(f - x) * scale for f, x in zip(relaxed["dissipation_per_cycle"][1:],
                                             reference["dissipation_per_cycle"][1:])]


def _relaxed_member(sv: Scene, pair, levels) -> dict:
    """What relaxing an assumption at the point ``sv`` costs its slip index in the apparatus: ``pair(law,
    loading)`` gives the (relaxed, reference) apparatus runs on one 3D mesh, ``levels`` the (h, mesh
    options) of its ladder. The effect's error bar is its ladder's (``metrics.ladder_error``; two levels:
    their difference, a spread), plus the change when the coarsest level runs ``STEP_FACTOR`` times the
    steps, plus the finest level's settling over its cycles (``common.ladder.settling_error``). The
    apparatus's dissipation settles within a cycle or two."""
    from common.ladder import settling_error

    from ..sides import fe_law

    out, coarsest = [], None
    for h, mesh in levels:
        law = fe_law(sv, h, **mesh)
        coarsest = coarsest or law
        new, ref = pair(law, sv.loading)
        out.append({"h": h, "slip_index": {"relaxed": new["slip_index"], "reference": ref["slip_index"]},
                    "effect": new["slip_index"] - ref["slip_index"], "per_cycle": _effects_per_cycle(new, ref)})
    new, ref = pair(coarsest, replace(sv, steps=STEP_FACTOR * sv.steps).loading)
    step = abs(new["slip_index"] - ref["slip_index"] - out[0]["effect"])
    lad = metrics.ladder_error([x["h"] for x in out], [x["effect"] for x in out])
    settle = settling_error(out[-1]["per_cycle"], floor=1e-9)  # 1e-9 of the slip index: round-off
    parts = {"mesh": lad["error"], "time step": step, "cycles": settle["error"]}
    ok = all(x is not None and math.isfinite(x) for x in parts.values())
    return {"levels": out, "ladder": lad, "settling": settle, "error_parts": parts, "effect": lad["value"],
            "error": sum(parts.values()) if ok else None, "slip_index_reference": out[-1]["slip_index"]["reference"],
            "bounded": False}


def direction_member(sv: Scene) -> dict:
    """Mindlin's traction direction at the point ``sv`` in the apparatus (``_relaxed_member``): the slip
    index with the traction free minus along x on each 3D level of ``sv.fe_levels``."""
    from mdr.apparatus import apparatus_result

    app = sv.apparatus_of()

    def pair(law, loading):
        return tuple(apparatus_result(law.assuming(traction=tr), app, loading) for tr in ("free", "x"))

    return {"measures": "direction", **_relaxed_member(sv, pair, [(h, {}) for h in sv.fe_levels])}


def tilt_member(sv: Scene, tilt: float) -> dict:
    """The face of the point ``sv`` tilted about y by ``tilt`` (rad) against aligned, in the apparatus
    (``_relaxed_member``), on the tilt family's meshes for that face (``tilt.edge_variant``: the loaded
    edge refined where the face is the whole contact). A tilted contact of fewer than
    ``tilt.TILT_MIN_VERTICES`` vertices (half model) at the smallest normal force F0 - dF on the finest
    level resolves nothing: its effect is None."""
    from fem.solid3d.estimators import contact_mask
    from mdr.apparatus import apparatus_result

    from .tilt import TILT_MIN_VERTICES, Variant as TiltVariant, edge_variant

    var = TiltVariant.of(edge_variant(sv, tilt), sv, force=False)
    hs = var.fe_levels or sv.fe_levels
    app, vertices = sv.apparatus_of(), []

    def pair(law, loading):
        tilted = law.assuming(tilt=tilt)
        vertices.append(int(contact_mask(tilted.model, tilted.normal(F_N=sv.F0 - sv.dF).p).sum()))
        return tuple(apparatus_result(x, app, loading) for x in (tilted, law))

    out = _relaxed_member(replace(sv, fe_levels=hs), pair, [(h, var.mesh_options(j)) for j, h in enumerate(hs)])
    fine = vertices[len(hs) - 1]  # the levels in turn, then the coarsest with its steps doubled
    resolved = fine >= TILT_MIN_VERTICES
    return {**out, "measures": "tilt", "tilt": tilt, "contact_vertices": fine, "resolved": resolved,
            **({} if resolved else {"effect": None, "error": None})}


def _relaxed_row(s: Scene, m: dict) -> dict:
    """A 3D point's row: the effect of what it relaxes (``measures``: the traction direction, the face's
    tilt) on the slip index, its error bar."""
    e, err = m.get("effect"), m.get("error")
    ok = e is not None and err is not None and math.isfinite(e) and math.isfinite(err)
    grade = "undetermined" if not ok else ("below the budget's resolution" if abs(e) + err <= RESOLUTION
                                           else "beyond the budget's resolution")
    v = s.typed_variants[m["variant"]]
    sv = v.scene(s)  # this scene's point (a member read back ran another's, within rounding)
    return {"variant": m["variant"], **v.given(), "b": sv.b, "kx": sv.kx, "failed": m.get("failed"),
            "measures": m.get("measures"), "tilt": m.get("tilt"), "contact_vertices": m.get("contact_vertices"),
            "slip_index": m.get("slip_index_reference"), "effect": e if ok else None, "error": err if ok else None,
            "error_parts": m.get("error_parts"), "ladder_status": (m.get("ladder") or {}).get("status"),
            "bounded": False, "grade": grade, "holds": None, "runtime_s": m.get("runtime_s")}


def _row(s: Scene, m: dict) -> dict:
    """A point's row: FE minus MDR of the slip index (its effect: what the half-space's shape costs the
    slip index there) with both sides' error bars, and the verdicts (none where the point failed: its
    row is undetermined)."""
    m = {**m, "verdicts": m.get("verdicts") or {}}
    si = m["verdicts"].get("slip_index") or {}
    fe, md = si.get("fem"), si.get("mdr")
    err = None if si.get("fem_error") is None or si.get("mdr_error") is None else si["fem_error"] + si["mdr_error"]
    a = m.get("contact_radius")
    holds, grade = metrics.conjunction(m["verdicts"]), metrics.scene_grade(m["verdicts"])
    sv = s.typed_variants[m["variant"]].scene(s)  # this scene's point (a member read back ran another's, within rounding)
    return {"variant": m["variant"], "failed": m.get("failed"), "b": sv.b, "kx": sv.kx, "a_over_R": None if a is None else a / s.R,
            "slip_index_fem": fe, "slip_index_mdr": md,
            "effect": None if fe is None or md is None else fe - md, "error": err,
            "bounded": bool(si.get("bounded")), "verdicts": m["verdicts"], "holds": holds, "grade": grade,
            "runtime_s": m.get("runtime_s")}


def run(s: Scene, out_dir=None, *, fields: bool = True, log=None, members: list | None = None) -> dict:
    """The scene: its points run here in turn unless ``members`` (their results, from ``member``) are
    given; one row per point (``_row``)."""
    t0 = time.perf_counter()
    log = log or (lambda msg: None)
    members, given = members_of(s, members, tasks, member, log,
                                lambda k, task, m: f"  point {task['variant']}: {m['runtime_s']:.0f} s")
    reduce = _relaxed_row if s.fe_model == "3d" else _row
    rows = [reduce(s, m) for m in sorted(members, key=lambda m: m["variant"])]
    what = WHAT[measures(s.as_dict())[-1]][0]
    for r in rows:
        log(f"  b = {num(r['b'], 'g', 1e6)} um, k_x = {num(r['kx'], 'g', 1e-6)} N/um: slip index {what} "
            f"{num(r['effect'], '+.2g')} +- {num(r['error'], '.2g')}: {r['grade']}")
    return result_of_members(s, KEY, rows, t0, out_dir, figure, members, given)


#: what a points scene measures (``measures``): the difference's label, the figure's title and file
WHAT = {"shape": ("FE - MDR", "The half-space's shape at the paper's points (FE against MDR, in the apparatus)",
                  "points.png"),
        "direction": ("free - along x", "Mindlin's traction direction at the paper's points (3D, in the apparatus)",
                      "directions.png"),
        "tilt": ("tilted - aligned", "The face tilted at the paper's points (3D, in the apparatus)", "tilts.png")}


def measures(scene: dict) -> tuple:
    """What the points scene (its data) measures: ("shape",) the half-space's shape (axisymmetric); of a 3D
    scene ("direction",) Mindlin's traction direction at points without a tilt, ("tilt",) the face's tilt
    at points with one, both where it has both kinds (the table and figure name the last)."""
    if scene.get("fe_model") != "3d":
        return ("shape",)
    tilted = {"tilt" in v for v in scene.get("variants") or ()}
    return tuple(w for w, t in (("direction", False), ("tilt", True)) if t in tilted)


def table(res) -> list:
    what = measures(res.get("scene") or {})[-1]
    if what != "shape":
        return _relaxed_table(res, what)
    lines = ["The paper's points in its apparatus (Table 2's load; b and k_x of Figs. 8-9 and Table 2 that no "
             "other scene runs): the axisymmetric FE model (the cap's real sphere, bodies of 200 a) against MDR, "
             "both on their ladders. FE - MDR of the slip index is what the half-space's shape costs there (the "
             "budget's column *curvature a/R*), with the sum of both error bars (mesh or grid, time step, "
             "cycles); the verdict is the catalogue's over the metrics listed.", "",
             "| b (um) | k_x (N/um) | a/R | slip index (MDR) | FE - MDR | error bar | MDR holds? |",
             "|---|---|---|---|---|---|---|"]
    for r in res[KEY]:
        failed = [q for q, x in r["verdicts"].items() if x.get("holds") is False]
        lines.append(f"| {num(r.get('b'), 'g', 1e6)} | {num(r.get('kx'), 'g', 1e-6)} | {num(r.get('a_over_R'), '.2g')} | "
                     f"{num(r.get('slip_index_mdr'), '.3g')} | {num(r.get('effect'), '+.2g')} | "
                     f"{num(r.get('error'), '.2g')}{'' if r.get('bounded') else ' (spread)'} | "
                     f"{grade_text(r)}{': ' + ', '.join(failed) if failed else ''} |")
    return lines


def _relaxed_table(res, what: str) -> list:
    """The table of a 3D points scene: per point the change of the slip index when the traction's direction
    is freed or the face tilted, its error bar and status."""
    from .tilt import TILT_MIN_VERTICES

    head = ("the 3D model with a traction of free direction minus the same mesh with the traction along x "
            "(Mindlin's assumption, MDR's and the axisymmetric model's)" if what == "direction" else
            "the 3D model with the face tilted about y (its loaded edge refined where the face is the whole "
            f"contact) minus the aligned face on the same mesh; a tilted contact of fewer than {TILT_MIN_VERTICES} "
            "vertices at F0 - dF resolves nothing (undetermined)")
    ref = "along x" if what == "direction" else "aligned"
    lines = [f"The paper's points in its apparatus (every point of the budget's results, at its own load): {head}, "
             "the change of the slip index, with its error bar (the effect's 3D ladder, its time step, its "
             "settling); the budget's resolution is 0.01.", "",
             f"| b (um) | k_x (N/um) | F0 (N) | slip index ({ref}) | {WHAT[what][0]} | error bar | status |",
             "|---|---|---|---|---|---|---|"]
    for r in res[KEY]:
        lines.append(f"| {num(r.get('b'), 'g', 1e6)} | {num(r.get('kx'), 'g', 1e-6)} | {num(r.get('F0'), 'g')} | "
                     f"{num(r.get('slip_index'), '.3g')} | {num(r.get('effect'), '+.2g')} | {num(r.get('error'), '.2g')} "
                     f"(spread) | {r.get('grade')} |")
    return lines


def figure(result: dict, out_dir) -> dict:
    """The effect of each point on its slip index (FE - MDR; the 3D traction free - along x; the face tilted -
    aligned: ``WHAT``) with its
    error bar against k_x, one line per face radius b (set slightly apart where they share a k_x): left
    against the budget's resolution (0.01 of the slip index), right zoomed to the measured values."""
    from ..figures import plt, save

    label, title, file = WHAT[measures(result.get("scene") or {})[-1]]
    rows = [r for r in result[KEY] if all(isinstance(r.get(k), (int, float)) and math.isfinite(r[k])
                                          for k in ("b", "kx", "effect"))]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    faces = sorted({r["b"] for r in rows})
    for ax in axes:
        for j, b in enumerate(faces):
            sel = sorted((r for r in rows if r["b"] == b), key=lambda r: r["kx"])
            dodge = 1.0 + 0.03 * (j - (len(faces) - 1) / 2)  # side by side where the faces share a k_x
            ax.errorbar([dodge * r["kx"] / 1e6 for r in sel], [r["effect"] for r in sel],
                        yerr=[r["error"] if isinstance(r.get("error"), (int, float)) and math.isfinite(r["error"])
                              else 0.0 for r in sel], marker="o", ms=4, lw=0.8, capsize=3,
                        label=f"b = {b * 1e6:g} um")
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.set_xscale("log")
        ax.set_xlabel("axis stiffness k_x (N/um)")
        ax.grid(alpha=0.3, which="both")
    axes[0].axhspan(-RESOLUTION, RESOLUTION, color="0.92", zorder=0, label=f"budget resolution ({RESOLUTION:g})")
    axes[0].set_ylim(-1.1 * RESOLUTION, 1.1 * RESOLUTION)
    axes[0].set_ylabel(f"slip index, {label}")
    axes[0].set_title("against the budget's resolution", fontsize=10)
    axes[1].set_title("zoomed: the measured effects and their error bars", fontsize=10)
    if rows:
        axes[0].legend(fontsize=7)
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return {KEY: save(fig, Path(out_dir) / file)}
