"""The family ``pair``: MDR against the FE model, each on its own refinement ladder.

For each scene: MDR at each grid size of ``scene.mdr_cells``, the FE model at each mesh level of
``scene.fe_levels`` (the axisymmetric model with ``displacement="contact"``: the displacement measured
without the finite bodies' series compliance, the quantity a half-space law predicts), profiles at the
mean normal force (pressure) and at the peak of the last cycle (tangential traction), closed forms where
they exist, and a verdict per metric (``scene_verdicts``): the difference of the finest MDR and FE
results beside each side's error bar, extrapolated over its ladder (``metrics.ladder_error``), with the
time step's and the cycles' settling, and the scene's tolerance. Its table and figures are the
report's default (``validation.report``, ``validation.figures.scene_figures``).
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from common.ladder import settling_error
from mdr.loops import STATIONARY_TOL
from mdr.loading import gross_slip_work

from .. import error_models, metrics
from ..scenes import Scene, a_ref
from ..sides import ZERO, closed_forms, run_fe, run_mdr, time_step_error, u_amp

#: the result key of the family's table (None: the report's default scene table)
KEY = None


def _zero(x, scale):
    """x, or 0.0 where it is a numerical zero against ``scale`` (None stays None)."""
    if x is None:
        return None
    x = float(x)
    return 0.0 if np.isfinite(x) and abs(x) <= ZERO * scale else x


def _kink_ring(s: Scene, a):
    """The ring |r - b| < 0.05 a around the kink of a truncated sphere inside the compared disk
    (log-singular pressure there), left out of the profile metrics; None elsewhere."""
    if s.profile != "truncated" or not 0 < s.b < 0.95 * a:
        return None
    return (s.b - 0.05 * a, s.b + 0.05 * a)


def _distances(s: Scene, mdr: dict, fe: dict) -> dict:
    """Distance metrics between an MDR and an FE result of the scene (profiles, loops)."""
    out = {}
    pm, pf = mdr["profiles"], fe["profiles"]
    a = min(float(mdr["contact_radius"]), float(fe["contact_radius"]))
    r_edge, kink = 0.95 * a, _kink_ring(s, a)
    out["pressure_profile"] = metrics.profile_error(pm["r"], pm["pressure"], pf["r"], pf["pressure"], r_edge,
                                                    exclude=kink)
    if pm.get("traction") is not None and pf.get("traction") is not None:
        out["traction_profile"] = metrics.profile_error(pm["r"], pm["traction"], pf["r_pairs"], pf["traction"], r_edge,
                                                        exclude=kink)
    lp = metrics.loop_distance(mdr["loop"], fe["loop"], s.mu, s.F0)
    # the prescribed component of a loop is equal on both sides: compare the other one
    if s.drive != "force":
        out["loop_Fx"] = lp["Fx"]
    if s.drive != "displacement":
        out["loop_du"] = lp["du"]
    return out


def ladder_class(s: Scene, fe_ladder: list, mdr_ladder: list) -> str | None:
    """The class of the scene's calibrated bounds (``error_models.bound_class``): gross slip where every
    level of both ladders has a stick radius of 0 (within ``ZERO`` of the finest FE contact radius)."""
    a = float(fe_ladder[-1]["contact_radius"])
    gross = all(_zero(x.get("stick_radius"), a) == 0.0 for x in list(fe_ladder) + list(mdr_ladder))
    return error_models.bound_class(s.profile, s.b, a_ref(s), gross_slip=gross)


def scene_verdicts(s: Scene, fe_ladder: list, mdr_ladder: list, time_step: dict | None = None) -> dict:
    """Per metric: MDR, FE, difference, each side's error bar (``metrics.ladder_error`` over
    its ladder), the scene's tolerance and ``holds`` (``metrics.verdict``).

    Scalars (``contact_radius``, ``stick_radius``, ``dissipation``, ``slip_index``) compare
    the finest levels; their error bars come from the ladders of the quantity. Distance
    metrics (profiles, loops) compare the finest profiles; their error bars come from the
    ladders of the distance between one side's levels and the other side's finest level.
    Tolerances (``Scene.tolerances``) are absolute in the verdict: radii relative to the FE
    contact radius (so a stick radius of 0 compares in absolute terms), dissipation relative
    to the FE dissipation with a floor of ``DISSIPATION_FLOOR`` x 4 mu F0 u_A (a verdict within the
    floor only is graded "below resolution"). ``time_step``: each side's ``time_step_error`` (or
    None), whose error bar joins that side's on the dissipation and the slip index.
    """
    from ..scenes import DISSIPATION_FLOOR

    tol = s.tolerances()
    mdr, fe = mdr_ladder[-1], fe_ladder[-1]
    a, a0 = float(fe["contact_radius"]), a_ref(s)
    # the sizes in the units of the calibrated bounds (``validation.error_models``): element size / a, 1 / cells
    fe_h = [float(x["h_contact"]) * a0 / a for x in fe_ladder]
    md_h = [1.0 / float(x["cells"]) for x in mdr_ladder]
    scale_W = float(gross_slip_work(s.mu, s.F0, u_amp(fe)))
    cls = ladder_class(s, fe_ladder, mdr_ladder)
    V = {}

    def bars(q, fv, mv, scale, floor, bound_of=None):
        """Each side's error bar of metric q (``error_models.ladder``: its calibrated bound in units of
        ``scale``, that of ``bound_of`` where given, else the ladder's own error)."""
        key = bound_of or q
        return (error_models.ladder("fem", key, cls, fe_h, fv, scale=scale, floor=floor),
                error_models.ladder("mdr", key, cls, md_h, mv, scale=scale, floor=floor))

    def scalar(q, scale, tolerance, unit, extra=None, floor=None, bound_of=None):
        fv = [_zero(x.get(q), scale) for x in fe_ladder]
        mv = [_zero(x.get(q), scale) for x in mdr_ladder]
        fl, ml = bars(q, fv, mv, scale, ZERO * scale, bound_of)
        V[q] = metrics.verdict(mv[-1], fv[-1], fl, ml, tolerance, unit=unit, extra=extra, floor=floor)

    # each side's settling ("cycles"): ``common.ladder.settling_error`` of the finest level's dissipation
    # over its closed cycles (J), two cycles repeating within ``mdr.loops.STATIONARY_TOL`` being stationary
    settling = {}
    for side, res in (("mdr", mdr), ("fem", fe)):
        W = list(res.get("dissipation_per_cycle") or [])[1:]
        settling[side] = settling_error(W, floor=STATIONARY_TOL * max((abs(float(w)) for w in W if w is not None
                                                                       and np.isfinite(w)), default=0.0))

    def step_bars(unit_scale):
        """Each side's time-step and settling (``settling``) error bars in the unit of a metric (J
        divided by ``unit_scale``). A side whose time step was not computed (a family that runs none)
        gets a bar of 0 that bounds nothing, so its verdict can be no stronger than "consistent"."""
        out = {}
        for side in ("mdr", "fem"):
            ts = (time_step or {}).get(side)
            if ts is None:
                out[side] = {"time step": {"status": "not computed", "bounded": False, "error": 0.0}}
            else:
                err = ts.get("error_at_scene_step")
                out[side] = {"time step": {"status": ts.get("status"), "bounded": ts.get("bounded", False),
                                           "error": None if err is None else float(err) / unit_scale}}
            st = settling[side]
            out[side]["cycles"] = {**st, "error": None if st["error"] is None else st["error"] / unit_scale}
        return out

    scalar("contact_radius", a, tol["contact_radius"] * a, "m")
    scalar("stick_radius", a, tol["stick_radius"] * a, "m")
    dW = abs(float(fe["dissipation"]))
    floor_W = DISSIPATION_FLOOR * scale_W
    scalar("dissipation", scale_W, tol["dissipation"] * dW, "J", extra=step_bars(1.0), floor=floor_W,
           bound_of="slip_index")  # the dissipation in units of 4 mu F0 u_A is the slip index
    # the slip index is dW / (4 mu u_A F0) (u_A the drive's amplitude): its tolerance is relative, the
    # dissipation's, with the same floor; its time-step bar is the dissipation's over that scale
    si = fe.get("slip_index")
    si_scale = float(fe["dissipation"]) / float(si) if si and fe.get("dissipation") else scale_W
    scalar("slip_index", 1.0, tol["slip_index"] * abs(float(si or 0.0)), "",
           extra=step_bars(si_scale if si_scale > 0 else 1.0), floor=DISSIPATION_FLOOR)
    d_fe = [_distances(s, mdr, x) for x in fe_ladder]
    d_md = [_distances(s, x, fe) for x in mdr_ladder]
    for q, dist in d_fe[-1].items():
        fl, ml = bars(q, [d.get(q) for d in d_fe], [d.get(q) for d in d_md], 1.0, ZERO)
        V[q] = metrics.verdict(_zero(dist, 1.0), None, fl, ml, tol[q], signed=False,
                               unit="relative L2" if q.endswith("profile") else ("mu F0" if q == "loop_Fx" else "u_A"))
    return V


def closed_form_errors(s: Scene, mdr: dict, fe: dict, closed: dict) -> dict:
    """Errors of the finest MDR and FE results against the scene's closed forms."""
    cfe = {}
    for side, res in (("mdr", mdr), ("fem", fe)):
        cfe[side] = {q: metrics.rel(res[q], closed[q]) for q in ("contact_radius", "stick_radius")}
        cfe[side]["dissipation"] = metrics.dissipation_error(res["dissipation"], closed["dissipation"], s.mu, s.F0,
                                                             u_amp(res))
        p = res["profiles"]
        cfe[side]["pressure_profile"] = metrics.profile_error(p["r"], p["pressure"], closed["profiles"]["r"],
                                                              closed["profiles"]["pressure"], 0.95 * closed["contact_radius"])
        if p.get("traction") is not None:
            rr = p["r_pairs"] if side == "fem" else p["r"]
            cfe[side]["traction_profile"] = metrics.profile_error(rr, p["traction"], closed["profiles"]["r"],
                                                                  closed["profiles"]["traction"],
                                                                  0.95 * closed["contact_radius"])
    return cfe


def speed_error(s: Scene, fe_ladder: list, mdr_ladder: list, closed: dict | None) -> list:
    """Rows (side, level, dofs or cells, runtime, dissipation error vs finest FE and vs closed form)."""
    best = fe_ladder[-1]
    rows = []
    for side, ladder in (("fem", fe_ladder), ("mdr", mdr_ladder)):
        for res in ladder:
            u_A = u_amp(res)
            rt = res["runtime_s"]["total"] if isinstance(res["runtime_s"], dict) else res["runtime_s"]
            row = {"side": side, "level": (f"a/{1 / res['h_contact']:.0f}" if side == "fem" else f"n={res['cells']}"),
                   "size": res["dofs"] if side == "fem" else res["cells"], "runtime_s": rt,
                   "runtime_cycles_s": res["runtime_s"]["cycles"] if side == "fem" else rt,
                   "dissipation": res["dissipation"],
                   "error_vs_fe": None if res is best else
                   metrics.dissipation_error(res["dissipation"], best["dissipation"], s.mu, s.F0, u_A),
                   "error_vs_closed_form": None if closed is None else
                   metrics.dissipation_error(res["dissipation"], closed["dissipation"], s.mu, s.F0, u_A)}
            rows.append(row)
    return rows


def _strip(res: dict) -> dict:
    """Ladder entries without the bulky arrays (kept for the finest levels only)."""
    return {k: v for k, v in res.items() if k not in ("loop", "profiles", "dissipation_per_cycle")}


def run(s: Scene, out_dir=None, *, fields: bool = True, log=None) -> dict:
    """MDR against the FE model on both ladders (``scene.mdr_cells``, ``scene.fe_levels``), the time
    step's share of each side's dissipation error at its finest level, a verdict per metric
    (``scene_verdicts``), the closed forms where they exist; with ``out_dir`` the VTU, the figures
    (``validation.figures.scene_figures``) and the pyvista field plot written there."""
    log = log or (lambda msg: None)
    t0 = time.perf_counter()
    out_dir = Path(out_dir) if out_dir is not None else None
    mdr_ladder = []
    for n in s.mdr_cells:
        mdr_ladder.append(run_mdr(s, n))
        log(f"  mdr n={n}: dW={mdr_ladder[-1]['dissipation']:.4g} J in {mdr_ladder[-1]['runtime_s']:.3g} s")
    fe_ladder, field = [], None
    for i, h in enumerate(s.fe_levels):
        last = i == len(s.fe_levels) - 1
        vtu = out_dir / "fields.vtu" if (last and out_dir is not None and s.fe_model == "axisym") else None
        res, fld, law = run_fe(s, h, vtu_path=vtu, keep_law=True)  # the finest law serves the time step too
        fe_ladder.append(res)
        if last:
            field = fld
        log(f"  fem a/{1 / h:.0f} ({res['dofs']} DOFs): dW={res['dissipation']:.4g} J, set-up "
            f"{res['runtime_s']['setup']:.2f} s, cycles {res['runtime_s']['cycles']:.2f} s")
    closed = closed_forms(s)
    mdr, fe = mdr_ladder[-1], fe_ladder[-1]
    # the time step's share, each side at its finest level (the 3D model's runs cost too much to triple),
    # inside the dissipation's and the slip index's error bars
    time_step = {"mdr": time_step_error(s, mdr, n=s.mdr_cells[-1]),
                 "fem": None if s.fe_model == "3d" else time_step_error(s, fe, h=s.fe_levels[-1], law=law)}
    verdicts = scene_verdicts(s, fe_ladder, mdr_ladder, time_step)
    errors = {"a_ref": a_ref(s), "time_step": time_step}
    if closed is not None:
        errors["closed_form"] = closed_form_errors(s, mdr, fe, closed)
    result = {"scene": s.as_dict(), "closed_form": closed, "mdr": mdr, "fem": fe,
              "verdicts": verdicts, "holds": metrics.conjunction(verdicts), "errors": errors,
              "ladder": {"mdr": [_strip(x) for x in mdr_ladder], "fem": [_strip(x) for x in fe_ladder]},
              "speed_error": speed_error(s, fe_ladder, mdr_ladder, closed),
              "files": {}}
    if out_dir is not None:
        from .. import figures

        if field is not None:
            result["files"]["vtu"] = "fields.vtu"
        result["files"].update(figures.scene_figures(result, out_dir))
        if fields and field is not None:
            from .. import fields as fieldplots

            try:
                result["files"]["fields"] = fieldplots.field_figure(out_dir / "fields.vtu", field, result,
                                                                    out_dir / "fields.png")
            except fieldplots.RenderError as e:
                result["files"]["fields_error"] = str(e)
                log(f"  field plot skipped: {e}")
    result["runtime_s"] = time.perf_counter() - t0
    return result
