"""The family ``assumptions3d``: Mindlin's assumptions (shared by MDR and the axisymmetric model)
relaxed one at a time on the 3D model, each effect the relaxed run minus the imposed one on the same
mesh, with its own ladder's error bar and its settling towards the stationary cycle.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from common.ladder import settling_error
from common.errors import InputError
from mdr.normal import approach_from_force

from .. import metrics
from . import number, result_of, variant_keys
from ..scenes import ASSUMPTIONS_3D, SETTLE_MAX_CYCLES, SETTLE_TOL_3D, Scene, a_ref
from ..sides import fe_law, materials_of, pct_or, profile_of
from ..text import LABELS, grade_text, num

#: the key of the family's rows in a result, and the title of its figure in the report
KEY = 'assumptions3d'
TITLE = 'assumptions in 3D'


#: the effects of relaxing an assumption of Mindlin's theory (and MDR) in the 3D model: metric ->
#: (tolerance key of ``Scene.tolerances``, kind, resolution); "relative": (on - off) / |off|,
#: "radius": (on - off) / contact radius; reported without a verdict when the tolerance key is None.
#: The stick zone is resolved by the mesh vertices, so its effects have an error of at least the
#: resolution of their estimator at the finest level: "quantum" (``stick_axis_quantum``: one
#: vertex joining the stick set) or "element" (the element size: the ray estimators)
EFFECTS_3D = {"dissipation": ("dissipation", "relative", None),
              "dissipation_first_cycle": ("dissipation", "relative", None),
              "stick_axis_x": ("stick_radius", "radius", "quantum"),
              "stick_axis_y": ("stick_radius", "radius", "quantum"),
              "stick_radius_x": (None, "radius", "element"),
              "stick_radius_y": (None, "radius", "element"),
              "stick_center_x": (None, "radius", "element"),
              "pressure_center_x": (None, "radius", None)}


#: the effects of ``EFFECTS_3D`` that are quantities of the cycles (the others are taken at the first loading)
CYCLE_EFFECTS = ("dissipation", "stick_axis_x", "stick_axis_y", "stick_radius_x", "stick_radius_y")


def _per_cycle(run: dict, q: str):
    """The values of metric ``q`` (``CYCLE_EFFECTS``) over the closed cycles of a 3D run (the cycle from
    rest left out), None where the run has none."""
    seq = run.get("dissipation_per_cycle") if q == "dissipation" else (run.get("per_cycle") or {}).get(q)
    return None if seq is None else list(seq)[1:]


def effect_settling(on: dict, off: dict, q: str, kind: str, floor: float = 0.0) -> dict | None:
    """How the effect ``q`` (``EFFECTS_3D``) of two 3D runs settles over their cycles: the effect of
    every closed cycle (on minus off, relative to off or to off's contact radius) through
    ``common.ladder.settling_error`` (``floor``: the change below which the runs count as settled); its
    error, the distance from the last cycle to the stationary one, joins the effect's error bar.
    The two runs ran the same cycles (``fem.contact_run.drive_3d_together``). None where ``q`` is no quantity of the cycles; a run without the
    per-cycle values gives an undetermined settling (error None)."""
    if q not in CYCLE_EFFECTS:
        return None
    a, b = _per_cycle(on, q), _per_cycle(off, q)
    if not a or not b or len(a) != len(b):
        return settling_error([None])
    effects = []
    for x, y in zip(a, b):
        scale = abs(y or 0.0) if kind == "relative" else off.get("contact_radius") or 0.0
        ok = x is not None and y is not None and np.isfinite(x) and np.isfinite(y) and scale > 0
        effects.append((x - y) / scale if ok else None)
    return settling_error(effects, floor=floor)


@dataclass(frozen=True)
class Variant:
    """One variant of an assumptions scene: the assumption it relaxes (``relax``, one of
    ``validation.scenes.ASSUMPTIONS_3D``: "direction", Mindlin's traction along x; "coupling", no
    normal-tangential coupling) and optionally the indenter's face radius ``b`` (m, > 0: a truncated
    sphere) and the block's material ``E2`` (Pa), ``nu2``; None: the scene's."""

    relax: str
    b: float | None = None
    E2: float | None = None
    nu2: float | None = None

    @classmethod
    def of(cls, v: dict, scene: Scene) -> "Variant":
        """The mapping ``v`` checked (the scene must be a 3D one; ``b`` in (0, R/2), ``E2`` > 0, ``nu2`` in
        (-1, 0.5))."""
        bad = variant_keys(scene, "assumptions", v, ("relax", "b", "E2", "nu2"))
        if scene.fe_model != "3d":
            raise InputError(f"scene {scene.name}: variants that relax an assumption need fe_model='3d'")
        if v.get("relax") not in ASSUMPTIONS_3D:
            raise bad("relax", f"one of {', '.join(ASSUMPTIONS_3D)}")
        rng = {"b": (lambda x: 0 < x < 0.5 * scene.R, f"in (0, {0.5 * scene.R:g}) (m; a truncated sphere's face)"),
               "E2": (lambda x: x > 0, "> 0 (Pa)"), "nu2": (lambda x: -1 < x < 0.5, "in (-1, 0.5)")}
        return cls(v["relax"], **{k: number(v, k, ok, bad, r) for k, (ok, r) in rng.items() if k in v})

    @property
    def label(self) -> str:
        """What the variant changes: 'sphere', 'b = 20 um', 'E2 = 70 GPa, nu2 = 0.33'."""
        fmt = (("b", lambda x: f"b = {x * 1e6:g} um"), ("E2", lambda x: f"E2 = {x / 1e9:g} GPa"),
               ("nu2", lambda x: f"nu2 = {x:g}"))
        return ", ".join(f(getattr(self, k)) for k, f in fmt if getattr(self, k) is not None) or "sphere"

    def scene(self, s: Scene) -> Scene:
        """The pair scene of this variant of ``s``: its face radius (a truncated sphere) and block."""
        kw = {k: getattr(self, k) for k in ("b", "E2", "nu2") if getattr(self, k) is not None}
        if kw.get("b"):
            kw["profile"] = "truncated"
        return replace(s, name=f"{s.name}[{self.relax}: {self.label}]", variants=(), family="pair", **kw)


def pressure_against_mdr(s: Scene, levels) -> dict:
    """The 3D pressure at F0 against MDR's (the frictionless normal contact of the imposed runs,
    "off", of an assumptions scene; as MDR's, without tangential traction): ``pressure_radius``
    (``mdr.normal.moment_radius``, an integral that needs no contact edge located between
    vertices) of every level over MDR's, minus 1; the error bar of its ladder
    (``metrics.ladder_error``), graded by ``metrics.effect_verdict`` against the catalogue's
    ``contact_radius`` tolerance (MDR's own error: round-off)."""
    from mdr.normal import pressure_radius

    prof, mat = profile_of(s), materials_of(s)
    rm = pressure_radius(prof, mat, float(approach_from_force(prof, mat, s.F0)))
    vals = [None if x["off"].get("pressure_radius") is None else x["off"]["pressure_radius"] / rm - 1
            for x in levels]
    lad = metrics.ladder_error([x["h"] for x in levels], vals)
    v = metrics.effect_verdict(lad["value"], lad, s.tolerances()["contact_radius"])
    return {"mdr": rm, "difference": v.pop("effect"), **v, "levels": vals, "ladder": lad}


def run(s: Scene, out_dir=None, *, fields: bool = True, log=None) -> dict:
    """Mindlin's assumptions, one at a time, on the 3D model: every variant at every 3D mesh level
    twice on the same mesh (``FEContact3D.assuming``) with the assumption relaxed ("on": the free
    traction direction, or the normal-tangential coupling of a dissimilar pair) and imposed ("off":
    q_y = 0, or no coupling, as in MDR and the axisymmetric model). The effect on, minus off, cancels
    the discretisation error the two runs share, so its ladder (``metrics.ladder_error``) resolves an
    effect far below the 3D model's own error; the error is at least the estimator's resolution
    (``EFFECTS_3D``), plus, for the quantities of the cycles, the finest level's settling towards
    the stationary cycle (``effect_settling``: the 3D cycles settle geometrically). The verdict of a
    metric: |effect| <= its error + the catalogue's tolerance (the assumption holds), graded by
    ``metrics.effect_verdict`` and ``metrics.with_settling`` (a spread bounds nothing)."""
    from fem.contact_run import drive_3d_together

    t0 = time.perf_counter()
    rows = []
    for v in s.typed_variants:
        sv = v.scene(s)
        relax = v.relax
        levels = []
        for h in sv.fe_levels:
            law = fe_law(sv, h)
            pair = (law.assuming(traction="free", coupling=True),
                    law.assuming(traction="x") if relax == "direction" else law.assuming(coupling=False))
            runs = dict(zip(("on", "off"), drive_3d_together(pair, sv.loading, settle=(SETTLE_TOL_3D, SETTLE_MAX_CYCLES))))
            a = runs["off"]["contact_radius"]
            eff = {}
            for q, (_, kind, _) in EFFECTS_3D.items():
                on, off = runs["on"].get(q), runs["off"].get(q)
                scale = abs(off or 0.0) if kind == "relative" else a
                ok = on is not None and off is not None and np.isfinite(on) and np.isfinite(off) and scale > 0
                eff[q] = float((on - off) / scale) if ok else None
            levels.append({"h": h, "dofs": runs["on"]["dofs"], "effects": eff,
                           **{side: {k: runs[side].get(k) for k in (*EFFECTS_3D, "traction_angle_max", "contact_radius",
                                                                     "pressure_radius", "stationary",
                                                                     "dissipation_per_cycle", "per_cycle",
                                                                     "stick_axis_quantum", "cycles_run", "settled")}
                              for side in ("on", "off")},
                           "runtime_s": runs["on"]["runtime_s"]["total"] + runs["off"]["runtime_s"]["total"]})
            log(f"  {sv.name} a/{1 / h:.0f}: dissipation {pct_or(eff['dissipation'])}, stick axes x, y "
                f"{pct_or(eff['stick_axis_x'])}, {pct_or(eff['stick_axis_y'])} of a, "
                f"{levels[-1]['runtime_s']:.0f} s")
        tol = sv.tolerances()
        verdicts = {}
        fine = levels[-1]
        floor = {"quantum": (fine["off"].get("stick_axis_quantum") or 0.0) / fine["off"]["contact_radius"],
                 "element": fine["h"] * a_ref(sv) / fine["off"]["contact_radius"], None: 0.0}
        for q, (tkey, kind, res) in EFFECTS_3D.items():
            lad = metrics.ladder_error([x["h"] for x in levels], [x["effects"][q] for x in levels])
            # the finest level's last cycle against its stationary cycle (None: no quantity of the cycles)
            settle = effect_settling(fine["on"], fine["off"], q, kind, floor=2.0 * SETTLE_TOL_3D)
            err = lad["error"]
            if err is not None:
                err = max(err, floor[res])
            ev = metrics.effect_verdict(lad["value"], lad, None if tkey is None else tol[tkey], error=err)
            verdicts[q] = {**metrics.with_settling(ev, settle), "kind": kind, "resolution": floor[res], "ladder": lad}
        rows.append({"variant": sv.name, "relax": relax, **{k: getattr(v, k) for k in ("b", "E2", "nu2") if getattr(v, k) is not None},
                     "levels": levels, "verdicts": verdicts, "pressure": pressure_against_mdr(sv, levels),
                     **dict(zip(("holds", "grade"), metrics.judged_grade(verdicts))),
                     "traction_angle_max": levels[-1]["on"]["traction_angle_max"]})
    return result_of(s, KEY, rows, t0, out_dir, figure)


def table(res) -> list:
    lines = ["Effect of relaxing one assumption of Mindlin's theory (and MDR): the 3D model with the assumption "
             "relaxed minus the same model imposing it, on the same mesh, at the finest 3D level with the error "
             "bar of the effect's own ladder (its status in brackets), at least the resolution of the stick-zone "
             "estimators (one vertex; the element for the centre); dissipation in % of the imposed run's, "
             "radii and centres in % of the contact radius. The assumption holds where |effect| <= error + "
             "the catalogue's tolerance.", "",
             "The last column is no effect: the 3D pressure at F0 with Mindlin's assumptions imposed against "
             "MDR's, by its second-moment radius (pressure_radius, which needs no contact edge located between "
             "vertices): 3D / MDR - 1 +- its ladder's error bar. *Cycles*: the 3D cycles settle geometrically, "
             "so the two runs of a pair go on together past the scene's cycles until each run's dissipation "
             "changes by at most 1e-4 per cycle, contracting (fem.contact_run.drive_3d_together); the cycles "
             "run at the finest level, and the dissipation effect's settling error (common.ladder.settling_error: "
             "the distance to the stationary cycle, part of the error bars above; bounded only once settled).", "",
             "| variant | FE DOFs | dissipation | first cycle | stick axis x | stick axis y | stick centre x "
             "| pressure centre x | largest traction angle | assumption holds? | pressure radius, 3D / MDR - 1 "
             "| cycles |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]

    def last_change(r):
        lv = (r.get("levels") or [{}])[-1]
        on = lv.get("on") or {}
        n = on.get("cycles_run")
        st = ((r.get("verdicts") or {}).get("dissipation") or {}).get("settling") or {}
        settled = {True: "settled", False: "not settled"}.get(on.get("settled"), "?")
        err = "undetermined" if st.get("error") is None else num(st["error"], ".1g", 100) + " %"
        return f"{num(n, '.0f')} ({settled}); settling {err} ({st.get('status', '?')})"

    def eff(r, q):
        x = r["verdicts"][q]
        if x["effect"] is None:
            return "undetermined"
        err = "undetermined" if x.get("error") is None else num(x["error"], ".2g", 100)
        return f"{num(x['effect'], '+.2g', 100)} +- {err} % ({x.get('status')})"

    def pressure(r):
        x = r.get("pressure")
        if not x or x["difference"] is None:
            return "undetermined"
        err = "undetermined" if x.get("error") is None else num(x["error"], ".2g", 100)
        return f"{num(x['difference'], '+.2g', 100)} +- {err} % ({x.get('status')}): {grade_text(x)}"

    for r in res["assumptions3d"]:
        failed = [LABELS.get(q, q).split(" (")[0] for q, x in r["verdicts"].items() if x["holds"] is False]
        lines.append(f"| {r['variant']} | {r['levels'][-1]['dofs']} | {eff(r, 'dissipation')} | "
                     f"{eff(r, 'dissipation_first_cycle')} | {eff(r, 'stick_axis_x')} | {eff(r, 'stick_axis_y')} | "
                     f"{eff(r, 'stick_center_x')} | {eff(r, 'pressure_center_x')} | "
                     f"{num(r['traction_angle_max'], '.3f')} | "
                     f"{grade_text(r)}{': ' + ', '.join(failed) if failed else ''} | {pressure(r)} | {last_change(r)} |")
    return lines


def figure(result: dict, out_dir) -> dict:
    """The effect of each relaxed assumption (on minus off, same mesh) against the 3D element size,
    the finest level with its error bar; grey: the catalogue's tolerance."""
    from ..figures import plt, save

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
            ax.axhspan(-100 * tol, 100 * tol, color="0.9", zorder=0, label="the catalogue's tolerance")
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.set_xscale("log")
        levels = sorted({x["h"] for r in rows for x in r["levels"]}, reverse=True)
        ax.set_xticks(levels, [f"a/{1 / h:.3g}" for h in levels])  # the mesh levels, not a decade's ticks
        ax.minorticks_off()
        ax.invert_xaxis()
        ax.set_xlabel("element size on the contact (a = a_ref)")
        ax.set_ylabel(f"relaxed - imposed ({unit})", fontsize=8)
        ax.set_title(q.replace("_", " "), fontsize=10)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.tight_layout()
    return {"assumptions3d": save(fig, Path(out_dir) / "assumptions3d.png")}
