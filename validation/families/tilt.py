"""The family ``tilt``: the flat face tilted up to the paper's bound pi/3600, each tilt against the
aligned face on the same 3D mesh (the mesh error they share cancels) and against MDR.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from common.errors import InputError
from common.ladder import settling_error
from mdr.loading import HARDLY_DISSIPATES, gross_slip_work

from .. import metrics
from . import number, result_of, variant_keys
from ..scenes import SETTLE_MAX_CYCLES, SETTLE_TOL_3D, Scene
from ..sides import fe_law, materials_of, pct_or, run_mdr
from ..text import grade_text, num

#: the key of the family's rows in a result, and the title of its figure in the report
KEY = 'tilt'
TITLE = 'tilt'


@dataclass(frozen=True)
class Variant:
    """One profile of a tilt scene: the ``profile`` ("flat" or "truncated") with face radius ``b`` (m, > 0),
    the ``tilts`` (rad, > 0) swept against the aligned face, its own 3D ``fe_levels`` (None: the scene's)
    and per level the loaded edge's refinement (``meshes.half3d.Refinement``: ``refine`` a ball, ``band`` a
    band along the rim arc; None: none)."""

    profile: str
    b: float
    tilts: tuple
    fe_levels: tuple | None = None
    refinements: tuple | None = None

    @classmethod
    def of(cls, v: dict, scene: Scene, *, force: bool = True) -> "Variant":
        """The mapping ``v`` checked: a 3D scene, force-driven (``force``; a points scene's tilted point runs
        in its apparatus); ``profile``, ``b`` in (0, R), ``tilts`` a
        non-empty list of angles in (0, pi/2); optionally ``fe_levels`` (the 3D model's range,
        non-increasing) and, one per level, ``refine`` (x, h, radius) or ``band`` (h, width, angle[, growth])
        in units of a_ref, each checked against the level's mesh (``meshes.half3d.Half3DMeshParams``)."""
        from meshes.axisym import CONTACT_EXTENT_DEFAULT
        from meshes.half3d import H_CONTACT_3D_RANGE, Half3DMeshParams, Refinement

        bad = variant_keys(scene, "tilt", v, ("profile", "b", "tilts", "fe_levels", "refine", "band"))
        if scene.fe_model != "3d" or (force and scene.drive != "force"):
            raise InputError(f"scene {scene.name}: tilt variants need fe_model='3d' and drive='force'")
        if v.get("profile") not in ("flat", "truncated"):
            raise bad("profile", "flat or truncated")
        b = number(v, "b", lambda x: 0 < x < scene.R, bad, f"in (0, {scene.R:g}) (m; the face radius)")
        try:
            tilts = tuple(float(t) for t in v.get("tilts"))
            ok = len(tilts) > 0 and all(0 < t < 0.5 * math.pi for t in tilts)
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise bad("tilts", "a non-empty list of angles in (0, pi/2) (rad)")
        lo, hi = H_CONTACT_3D_RANGE
        levels = None
        if "fe_levels" in v:
            try:
                levels = tuple(float(h) for h in v["fe_levels"])
                ok = len(levels) > 0 and all(lo <= h <= hi for h in levels) \
                    and all(x >= y for x, y in zip(levels, levels[1:]))
            except (TypeError, ValueError):
                ok = False
            if not ok:
                raise bad("fe_levels", f"a non-increasing list of element sizes / a_ref in [{lo:g}, {hi:g}]")
        hs = levels or scene.fe_levels
        refinements = None
        if {"refine", "band"} & set(v):
            extent = 1.0 if v["profile"] == "flat" else CONTACT_EXTENT_DEFAULT
            for k in ("refine", "band"):
                if k in v and (isinstance(v[k], str) or not hasattr(v[k], "__len__") or len(v[k]) != len(hs)):
                    raise bad(k, f"one {k} tuple per FE level ({len(hs)})")
            refinements = []
            for j, h in enumerate(hs):
                try:
                    r = Refinement(**{k: v[k][j] for k in ("refine", "band") if k in v})
                    Half3DMeshParams(a_ref=1.0, h_contact=h, contact_extent=extent, **r.mesh_fields())
                except (InputError, TypeError) as e:
                    raise bad("refine, band", f"valid at the level h = {h:g} a_ref ({e})") from None
                refinements.append(r)
            refinements = tuple(refinements)
        return cls(v["profile"], b, tilts, levels, refinements)

    @property
    def banded(self) -> bool:
        return any(r.band is not None for r in self.refinements or ())

    def scene(self, s: Scene) -> Scene:
        """The aligned pair scene of this profile of tilt scene ``s``."""
        name = f"{s.name}[{self.profile} b = {self.b * 1e6:g} um{', banded edge' if self.banded else ''}]"
        return replace(s, name=name, profile=self.profile, b=self.b, variants=(), family="pair",
                       fe_levels=self.fe_levels or s.fe_levels)

    def mesh_options(self, j: int) -> dict:
        """The 3D law's mesh options at level ``j`` (``refine``, ``band``; the loaded edge refined)."""
        if self.refinements is None:
            return {}
        r = self.refinements[j]
        return {k: getattr(r, k) for k in ("refine", "band") if getattr(r, k) is not None}


#: the largest tilt over theta_c a ball-refined loaded edge resolves (the catalogue's flat punch reaches
#: 7.6 at pi/3600); beyond it the crescent is thin and the band resolves it
TILT_BALL_MAX = 20.0


def edge_variant(sv: Scene, tilt: float) -> dict:
    """The tilt variant of the face of the pair scene ``sv`` (its b > 0) at ``tilt`` (rad). A face that is
    the whole contact (its half-space contact radius at F0 + dF within 0.1 % of b: a flat punch's) loses
    part of it past theta_c (``scenes.tilt_critical``, the tilted punch's at F0): its loaded edge refined
    as the catalogue's rows resolve it, a ball of 0.8 b at half the level's size on ``TILT_LEVELS_3D`` up
    to ``TILT_BALL_MAX`` theta_c (the flat punch b = 100 um, 7.6 theta_c), beyond it the thin crescent on
    meshes banded along the loaded rim arc (``TILT_BAND``: b = 0.6 mm, 274 theta_c); a face inside the
    contact on the scene's levels."""
    from ..scenes import (TILT_BAND, TILT_BAND_LEVELS, TILT_LEVELS_3D, TILT_REFINE_PUNCH, a_ref,
                          tilt_critical)

    v = {"profile": "truncated", "b": sv.b, "tilts": (tilt,)}
    if a_ref(sv) > sv.b * (1 + 1e-3):
        return v
    if tilt <= TILT_BALL_MAX * tilt_critical(sv.F0, sv.b, materials_of(sv).E_star):
        return {**v, "fe_levels": TILT_LEVELS_3D, "refine": TILT_REFINE_PUNCH}
    return {**v, "fe_levels": TILT_BAND_LEVELS, "band": TILT_BAND}


#: the metrics of a tilt, each against the aligned face: tolerance key of ``Scene.tolerances`` (None:
#: reported, not judged). ``dissipation``: relative to the aligned dissipation, or, where the aligned
#: loop hardly dissipates (below 1 % of 4 mu F0 u_A: the flat punch sticks), in units of 4 mu F0 u_A
#: (a slip-index difference; ``metrics.dissipation_error``); ``slip_index`` the difference;
#: ``contact_area`` the contact area fraction at F0 minus 1; ``loop_du`` ``metrics.loop_distance``'s du
#: a tilted contact with fewer vertices (half model, at F0 on the finest level) resolves no stick zone:
#: its verdicts are undetermined
TILT_MIN_VERTICES = 10


TILT_METRICS = {"dissipation": "dissipation", "slip_index": "slip_index", "contact_area": None, "loop_du": "loop_du"}


def _tilt_effects(run, ref, relative, mu, F0) -> dict:
    """The tilt metrics (``TILT_METRICS``) of one tilted ``run`` against a reference ``ref`` (the
    aligned 3D run on the same mesh, or MDR); ``relative``: the dissipation relative to ref's."""
    scale = float(gross_slip_work(mu, F0, float(ref["displacement_amplitude"])))
    W, W0 = float(run["dissipation"]), float(ref["dissipation"])
    d, d0 = run.get("slip_index"), ref.get("slip_index")
    return {"dissipation": (W - W0) / (abs(W0) if relative else scale) if (abs(W0) if relative else scale) > 0
            else None,
            "slip_index": None if d is None or d0 is None else float(d) - float(d0),
            "contact_area": None if run.get("contact_area_fraction") is None else run["contact_area_fraction"] - 1.0,
            "loop_du": metrics.loop_distance(run["loop"], ref["loop"], mu, F0)["du"]}


def _tilt_settling(run, ref, relative, mu, F0, *, ref_cycles: bool = True) -> dict:
    """How the tilt metrics of ``run`` against ``ref`` (``_tilt_effects``) settle over the closed
    cycles (the cycle from rest left out; the 3D runs of a level ran the same cycles,
    ``fem.contact_run.drive_3d_together``; a reference without ``ref_cycles``, MDR's, is taken as
    stationary):
    ``common.ladder.settling_error`` of the dissipation and slip-index effects cycle by cycle
    (each cycle's dissipation over 4 mu F0 u_A of the last), with the floor the runs settled to
    (``SETTLE_TOL_3D`` of each run's dissipation or of 1 % of 4 mu F0 u_A, ``fem.contact_run.settled``,
    in the effect's unit); the loop distance, whose loops are kept for the last cycle only, gets
    ``SETTLING_RATIO_MAX`` / (1 - it) times the two runs' last loop changes (the du of
    ``mdr.loops.analyse_cycles``, in u_A as ``loop_du``; a ratcheting loop drifts in du while its
    dissipation has settled), which bound nothing; the contact area is no quantity of the cycles
    (None)."""
    from common.ladder import SETTLING_RATIO_MAX as r

    W = list(run.get("dissipation_per_cycle") or [])[1:]
    W0 = list(ref.get("dissipation_per_cycle") or [])[1:] if ref_cycles else [float(ref["dissipation"])] * len(W)
    if not W or len(W0) != len(W):
        none = settling_error([None])
        return {"dissipation": none, "slip_index": none, "contact_area": None, "loop_du": none}
    u, u0 = float(run["displacement_amplitude"]), float(ref["displacement_amplitude"])
    si = (lambda w, ua: None if run.get("slip_index") is None or ref.get("slip_index") is None
          else w / float(gross_slip_work(mu, F0, ua)))
    eff = [_tilt_effects({**run, "dissipation": w, "slip_index": si(w, u), "loop": run["loop"]},
                         {**ref, "dissipation": w0, "slip_index": si(w0, u0)}, relative, mu, F0)
           for w, w0 in zip(W, W0)]
    S = float(gross_slip_work(mu, F0, u0))
    settled_change = SETTLE_TOL_3D * (max(abs(W[-1]), HARDLY_DISSIPATES * S) + max(abs(W0[-1]), HARDLY_DISSIPATES * S))
    floor_W = settled_change / (abs(W0[-1]) if relative and W0[-1] else S)
    changes = [((x.get("cycle_change") or {}).get("loop")) for x in (run, ref) if "cycle_change" in x]
    loop = {"value": None, "extrapolated": None, "ratio": None, "cycles": len(W), "bounded": False,
            "status": "last loop change",
            "error": None if any(c is None for c in changes) else float(sum(changes)) * r / (1.0 - r)}
    return {"dissipation": settling_error([e["dissipation"] for e in eff], floor=floor_W),
            "slip_index": settling_error([e["slip_index"] for e in eff], floor=settled_change / S),
            "contact_area": None, "loop_du": loop}


def _tilt_tolerance(q, tol, relative, W0, scale, si0=None):
    """The tolerance of a tilt effect: the catalogue's, the dissipation's relative to the reference or in
    units of 4 mu F0 u_A with its floor, the slip index's relative to the reference's ``si0`` with the
    same floor (as in ``scene_verdicts``)."""
    from ..scenes import DISSIPATION_FLOOR

    if q == "slip_index":
        return max(tol["slip_index"] * abs(float(si0 or 0.0)), DISSIPATION_FLOOR)
    if q != "dissipation":
        return None if TILT_METRICS[q] is None else tol[TILT_METRICS[q]]
    return tol["dissipation"] if relative else max(tol["dissipation"] * abs(W0) / scale, DISSIPATION_FLOOR)


def _levels(sv: Scene, v: Variant, tilts, log) -> list:
    """The 3D runs of one profile: per mesh level of ``sv.fe_levels`` one set-up (the loaded edge refined
    by the variant's ``refine``/``band``), the aligned face and every tilt driven together
    (``fem.contact_run.drive_3d_together``, settled), their keys per run."""
    import warnings

    from fem.contact_run import drive_3d_together
    from fem.solid3d.estimators import contact_mask

    levels = []
    for j, h in enumerate(sv.fe_levels):
        t0 = time.perf_counter()
        law = fe_law(sv, h, **v.mesh_options(j))  # the loaded edge refined
        setup = time.perf_counter() - t0
        runs = []
        laws = [law.assuming(tilt=th) for th in tilts]
        with warnings.catch_warnings():  # stationarity is reported per run
            warnings.simplefilter("ignore", RuntimeWarning)
            outs = drive_3d_together(laws, sv.loading, settle=(SETTLE_TOL_3D, SETTLE_MAX_CYCLES))
        for th, lt, out in zip(tilts, laws, outs):
            tk = lt.tilt_keys(sv.F0)
            runs.append({"tilt": th, "contact_vertices": int(contact_mask(lt.model, lt.normal(F_N=sv.F0).p).sum()),
                         **{k: out.get(k) for k in ("dissipation", "slip_index", "displacement_amplitude",
                                                    "stationary", "dissipation_per_cycle", "cycle_change",
                                                    "cycles_run", "settled")},
                         "contact_area_fraction": tk["contact_area_fraction"],
                         "contact_x_min": tk["contact_x_min"], "contact_x_max": tk["contact_x_max"],
                         "loop": {k: out["loop"][k] for k in ("du", "Fx")},
                         "runtime_s": out["runtime_s"]["cycles"]})
        levels.append({"h": h, "refine": law.model.hmesh.params.refine_h, "band": law.model.hmesh.params.band_h,
                       "dofs": law.model.ndofs, "vertices": law.n,
                       "setup_s": setup, "runs": runs,
                       "runtime_s": time.perf_counter() - t0})
        mp = law.model.hmesh.params
        edge = "".join(f", {k} {x:g} a_ref" for k, x in (("ball", mp.refine_h), ("band", mp.band_h)) if x is not None)
        log(f"  {sv.name} h = {h:g} a_ref{edge} ({law.n} vertices): {len(tilts)} tilts in "
            f"{levels[-1]['runtime_s']:.0f} s")
    return levels


def run(s: Scene, out_dir=None, *, fields: bool = True, log=None) -> dict:
    """Misalignment of the flat face (``tilt`` family): per profile, the aligned face and every tilt
    (``Variant.tilts``, rad) on each 3D mesh level (one set-up per level, ``FEContact3D.assuming``), the
    normal load applied with friction active and the force-driven cycles of the scene
    (``fem.contact_run.drive_3d``), and MDR (aligned; its own ladder). Each tilt's metrics
    (``TILT_METRICS``) against the aligned 3D run on the same mesh: the mesh error the two share
    cancels, the effect's error bar is its own ladder (``metrics.ladder_error``); the verdict
    "the aligned answer holds" is |effect| <= error + tolerance. Against MDR: the same metrics
    of the finest level, error bar the 3D ladder of the tilted value plus MDR's. Both error bars
    hold the finest level's settling towards the stationary cycle (``_tilt_settling``). A tilted contact of
    fewer than ``TILT_MIN_VERTICES`` vertices resolves nothing: its verdicts are None. ``holds_below``:
    the largest tilt up to which no swept tilt contradicts the aligned answer on the dissipation
    (graded holds or consistent within its spread: the two levels bound nothing)."""
    from ..scenes import tilt_critical

    t_scene = time.perf_counter()
    tol = s.tolerances()
    rows = []
    for v in s.typed_variants:
        sv = v.scene(s)
        mat = materials_of(sv)
        thc = tilt_critical(sv.F0, sv.b, mat.E_star)
        tilts = (0.0,) + v.tilts
        mdr_ladder = [run_mdr(sv, n) for n in sv.mdr_cells]
        mdr = mdr_ladder[-1]
        levels = _levels(sv, v, tilts, log)
        # the dissipation's unit, per reference: relative unless it hardly dissipates (the flat punch sticks)
        fine0 = levels[-1]["runs"][0]

        def relative(ref):
            return abs(float(ref["dissipation"])) >= HARDLY_DISSIPATES * float(
                gross_slip_work(sv.mu, sv.F0, ref["displacement_amplitude"]))

        rel3, relm = relative(fine0), relative(mdr)
        hs = [lv["h"] for lv in levels]
        md_h = [1.0 / float(x["cells"]) for x in mdr_ladder]
        points = []
        for i, th in enumerate(tilts[1:], start=1):
            vs3 = [_tilt_effects(lv["runs"][i], lv["runs"][0], rel3, sv.mu, sv.F0) for lv in levels]
            vsm = [_tilt_effects(lv["runs"][i], mdr, relm, sv.mu, sv.F0) for lv in levels]
            fine = levels[-1]["runs"][i]
            mdr_side = {q: [_tilt_effects(fine, x, relm, sv.mu, sv.F0)[q] for x in mdr_ladder] for q in TILT_METRICS}
            resolved = fine["contact_vertices"] >= TILT_MIN_VERTICES
            pt = {"tilt": th, "ratio": th / thc, "aligned": {}, "mdr": {}, "stationary": bool(fine["stationary"]),
                  "cycles_run": fine.get("cycles_run"), "settled": fine.get("settled"),
                  "contact_area_fraction": fine["contact_area_fraction"], "contact_vertices": fine["contact_vertices"],
                  "resolved": resolved}
            settle3 = _tilt_settling(fine, fine0, rel3, sv.mu, sv.F0)
            settlem = _tilt_settling(fine, mdr, relm, sv.mu, sv.F0, ref_cycles=False)
            for q in TILT_METRICS:
                t3 = _tilt_tolerance(q, tol, rel3, fine0["dissipation"], 4.0 * sv.mu * sv.F0 *
                                     float(fine0["displacement_amplitude"]), fine0.get("slip_index"))
                lad = metrics.ladder_error(hs, [e[q] for e in vs3])
                v3 = metrics.effect_verdict(lad["value"], lad, t3 if resolved else None)
                pt["aligned"][q] = metrics.with_settling(v3, settle3[q])
                if q == "contact_area":
                    continue
                tm = _tilt_tolerance(q, tol, relm, mdr["dissipation"], 4.0 * sv.mu * sv.F0 *
                                     float(mdr["displacement_amplitude"]), mdr.get("slip_index"))
                lf = metrics.ladder_error(hs, [e[q] for e in vsm])
                lm = metrics.ladder_error(md_h, mdr_side[q])
                errm = float("nan") if lf["error"] is None or lm["error"] is None else lf["error"] + lm["error"]
                vm = metrics.effect_verdict(lf["value"], lf, tm if resolved else None, error=errm,
                                            bounded=lf["bounded"] and lm["bounded"])
                pt["mdr"][q] = metrics.with_settling(vm, settlem[q])
            pt["holds"], pt["grade"] = metrics.judged_grade(pt["aligned"])
            if not resolved:
                pt["grade"] = "undetermined"
            points.append(pt)
            a = pt["aligned"]
            log(f"  {sv.name} theta = {th:.3g} rad ({th / thc:.3g} theta_c): dissipation "
                f"{pct_or(a['dissipation']['effect'])} +- {pct_or(a['dissipation']['error'])}, contact area "
                f"{pct_or(a['contact_area']['effect'])}: {pt['grade']}")
        # the largest tilt up to which the aligned answer is not contradicted on the dissipation (graded
        # holds or consistent within its spread: a two-level ladder bounds nothing, so no tilt "holds")
        below = None
        for pt in points:
            if pt["aligned"]["dissipation"]["grade"] not in ("holds", "consistent within its spread"):
                break
            below = pt["tilt"]
        rows.append({"variant": sv.name, "profile": sv.profile, "b": sv.b, "theta_c": thc, "banded": v.banded,
                     "dissipation_unit": "relative" if rel3 else "4 mu F0 u_A",
                     "dissipation_unit_mdr": "relative" if relm else "4 mu F0 u_A",
                     "holds_below": below, "holds_below_ratio": None if below is None else below / thc,
                     "fails_at": next((pt["tilt"] for pt in points if pt["aligned"]["dissipation"]["holds"] is False),
                                      None),
                     "mdr": {k: mdr.get(k) for k in ("dissipation", "slip_index", "displacement_amplitude")},
                     "points": points,
                     "levels": [{**lv, "runs": [{k: x for k, x in r.items() if k != "loop" or lv is levels[-1]}
                                                for r in lv["runs"]]} for lv in levels],
                     "runtime_s": sum(lv["runtime_s"] for lv in levels)})
    return result_of(s, KEY, rows, t_scene, out_dir, figure)


def cycles_text(p) -> str:
    """The cycles a tilted run ran and whether it settled (``fem.contact_run.drive_3d_together``)."""
    settled = {True: "settled", False: "not settled"}.get(p.get("settled"),
                                                          "stationary" if p.get("stationary") else "not stationary")
    return f"{num(p.get('cycles_run'), '.0f')} ({settled})"


def table(res) -> list:
    lines = ["Effect of a tilt theta of the flat face: each metric of the tilted face at the finest 3D level "
             "against the aligned face on the same mesh (the shared mesh error cancels), +- the error bar of the "
             "effect's own ladder; and against the aligned MDR result (error bar: the 3D ladder of the tilted "
             "value plus MDR's). Dissipation in % of the aligned one, or, where the aligned face hardly "
             "dissipates (the flat punch sticks), in % of 4 mu F0 u_A (a slip-index difference); loop: the "
             "largest du difference over the aligned du amplitude; contact area at F0 over the aligned. "
             "The aligned answer holds where |effect| <= error + the catalogue's tolerance on dissipation, "
             "slip index and loop. Every run of a level goes on past the scene's cycles until each run's "
             "dissipation changes by at most 1e-4 per cycle (or 1e-4 of 1 % of 4 mu F0 u_A), contracting; "
             "the error bars hold the settling to the stationary cycle (common.ladder.settling_error).", ""]

    def eff(x, digits=2):
        if x is None or x["effect"] is None:
            return "-"
        err = "?" if x["error"] is None else f"{100 * x['error']:.{digits}g}"
        return f"{100 * x['effect']:+.{digits}g} +- {err} %"

    for r in res["tilt"]:
        below = r["holds_below"]
        lines += [f"**{r['variant']}**: theta_c = {num(r.get('theta_c'))} rad; dissipation unit {r['dissipation_unit']}; "
                  f"MDR (aligned) slip index {num(r['mdr'].get('slip_index'), '.4f')}; the aligned answer is not contradicted on "
                  "the dissipation (graded holds or consistent within its spread) up to "
                  + ("no swept tilt" if below is None else f"theta = {num(below)} rad ({num(r.get('holds_below_ratio'))} "
                     "theta_c)")
                  + ("" if r["fails_at"] is None else f", not at {num(r['fails_at'])} rad")
                  + f"; {len(r['points']) + 1} runs per level, "
                  + ", ".join(f"h = {num(lv.get('h'), 'g')}" + ("" if lv.get("band") is None else f" (band {num(lv['band'], 'g')})")
                              + f": {lv.get('vertices')} vertices, {num(lv.get('runtime_s'), '.0f')} s" for lv in r["levels"])
                  + ".", "",
                  "| theta (rad) | theta / theta_c | dissipation | vs MDR | slip index | vs MDR | contact area "
                  "| loop du | vs MDR | cycles | aligned holds? |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        for p in r["points"]:
            a, m = p["aligned"], p["mdr"]
            lines.append(f"| {num(p.get('tilt'))} | {num(p.get('ratio'))} | {eff(a['dissipation'])} | {eff(m['dissipation'])} | "
                         f"{eff(a['slip_index'])} | {eff(m['slip_index'])} | {eff(a['contact_area'])} | "
                         f"{eff(a['loop_du'])} | {eff(m['loop_du'])} | {cycles_text(p)} | "
                         + (f"{grade_text(p)} |" if p.get("resolved", True) else
                            f"undetermined: {p['contact_vertices']} contact vertices |"))
        lines.append("")
    return lines


def figure(result: dict, out_dir) -> dict:
    """The effect of a tilt of the flat face against theta / theta_c (log x), one line per profile,
    each point the finest 3D level against the aligned face on the same mesh with the error bar of
    the effect's ladder: the dissipation (relative, or in units of 4 mu F0 u_A where the aligned
    face hardly dissipates; dashed: the catalogue's tolerance in that unit) and the contact area
    fraction at F0. Open markers: contacts too small to resolve (undetermined)."""
    from ..figures import plt, save

    rows = result["tilt"]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, q in ((axes[0], "dissipation"), (axes[1], "contact_area")):
        for r, mk in zip(rows, "osd^v"):
            pts = [p for p in r["points"] if p["aligned"][q]["effect"] is not None]
            if not pts:
                continue
            unit = f" ({r['dissipation_unit']})" if q == "dissipation" else ""
            label = f"{r['profile']} b = {r['b'] * 1e6:g} um{', banded edge' if r.get('banded') else ''}{unit}"
            ok = [p for p in pts if p.get("resolved", True)]
            x = np.array([p["ratio"] for p in ok])
            y = np.array([100 * p["aligned"][q]["effect"] for p in ok])
            e = np.array([100 * (p["aligned"][q]["error"] or 0.0) for p in ok])
            line = ax.errorbar(x, y, yerr=e, marker=mk, capsize=3, label=label)
            color = line.lines[0].get_color()
            bad = [p for p in pts if not p.get("resolved", True)]
            if bad:
                ax.plot([p["ratio"] for p in bad], [100 * p["aligned"][q]["effect"] for p in bad], marker=mk, ls="none",
                        mfc="none", color=color)
            tol = pts[0]["aligned"][q]["tolerance"]
            if tol:
                for sgn in (1, -1):
                    ax.axhline(sgn * 100 * tol, color=color, lw=0.8, ls="--")
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.axvline(1.0, color="0.6", lw=0.8, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("symlog", linthresh=0.01)
        ax.set_xlabel("tilt / theta_c  (theta_c = F0 / (4 E* b^2))")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    axes[0].set_ylabel("dissipation: tilted - aligned (%)", fontsize=8)
    axes[1].set_ylabel("contact area at F0: tilted / aligned - 1 (%)", fontsize=8)
    axes[0].set_title("Dissipation (dashed: tolerance; open: unresolved)", fontsize=10)
    axes[1].set_title("Contact area", fontsize=10)
    fig.tight_layout()
    return {"tilt": save(fig, Path(out_dir) / "tilt.png")}
