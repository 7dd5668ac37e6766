"""Run one scene through MDR and FE side by side: result ladders, errors, files.

For each scene (``validation.scenes.Scene``):

1. MDR at each grid size of ``scene.mdr_cells`` (``mdr.law.MDRContact``);
2. FE at each mesh level of ``scene.fe_levels`` (``fem.law.FEContact`` with
   ``displacement="contact"``: the displacement is measured without the finite
   bodies' series compliance, the quantity a half-space law predicts);
3. both driven by the same code (``mdr.drive.run_contact`` for the contact
   driven directly, ``mdr.apparatus.apparatus_result`` for the apparatus), so
   the result keys are those of ``python -m mdr contact`` / ``apparatus``;
4. profiles at the mean normal force (pressure) and at the peak of the last
   cycle (tangential traction), closed forms where they exist;
5. a verdict per metric (``scene_verdicts``): the difference of the finest MDR and
   FE results beside each side's error bar, extrapolated over its ladder
   (``metrics.ladder_error``), and the scene's tolerance.

The result is plain data (JSON); ``write_scene`` stores it with its figures
atomically in one directory per scene.
"""
from __future__ import annotations

import os
import shutil
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from mdr.apparatus import Apparatus, apparatus_result
from mdr.drive import run_contact
from mdr.io import DIR_MODE, write_json
from mdr.ladder import settling_error
from mdr.law import MDRContact
from mdr.loops import STATIONARY_TOL
from mdr.materials import Materials
from mdr.normal import approach_from_force, pressure
from mdr.profiles import make_profile
from mdr import reference as ref

from . import metrics
from .scenes import SETTLE_MAX_CYCLES, SETTLE_TOL_3D, Scene, a_ref


def materials_of(s: Scene) -> Materials:
    return Materials(s.E1, s.nu1, s.E2, s.nu2)


def profile_of(s: Scene):
    return make_profile(s.profile, None if s.profile == "flat" else s.R, None if s.profile == "sphere" else s.b)


def peak_index(s: Scene) -> int:
    """Step of the positive peak of the tangential drive in the last cycle."""
    return (s.cycles - 1) * s.steps + s.steps // 4


def _drive(s: Scene, law):
    """Run the scene's loading with ``law``; returns (result dict, state at the peak step)."""
    prof, mat = profile_of(s), materials_of(s)
    k = peak_index(s)
    if s.drive == "apparatus":
        return apparatus_result(prof, mat, Apparatus(kx=s.kx, mu2=s.mu2), s.mu, s.F0, s.dF, s.alpha,
                                ua=s.amplitude, cycles=s.cycles, steps=s.steps, law=law, state_at=k)
    kw = {"fa": s.amplitude} if s.drive == "force" else {"ua": s.amplitude}
    return run_contact(prof, mat, s.mu, s.F0, s.dF, s.alpha, cycles=s.cycles, steps=s.steps, law=law,
                       state_at=k, **kw)


def _timed_median(fun, budget=0.3, repeats=5):
    """Median wall time of fun() over up to ``repeats`` calls within ~``budget`` s, after one untimed
    call (the warm-up: numba compiles the MDR kernels on their first call, seconds that belong to
    no level of a ladder); returns (value, t)."""
    fun()
    times, val = [], None
    t_all = time.perf_counter()
    for _ in range(repeats):
        t0 = time.perf_counter()
        val = fun()
        times.append(time.perf_counter() - t0)
        if time.perf_counter() - t_all > budget:
            break
    return val, statistics.median(times)


def _r_profile(a_max):
    return np.linspace(0.0, 1.2 * a_max, 241)


def _mdr_law(s: Scene, n: int) -> MDRContact:
    """The scene's MDR law with n cells."""
    return MDRContact(profile_of(s), materials_of(s), s.mu, F_max=s.F0 + s.dF,
                      F_min=s.F0 - s.dF if s.dF < s.F0 else None, n=n)


def run_mdr(s: Scene, n: int) -> dict:
    """One MDR run of the scene with n cells; result dict + profiles."""
    prof, mat = profile_of(s), materials_of(s)

    def once():
        law = _mdr_law(s, n)
        out, st = _drive(s, law)
        return law, out, st

    (law, out, st), t = _timed_median(once)
    out["runtime_s"] = t
    r = _r_profile(a_ref(s))
    d0 = float(approach_from_force(prof, mat, s.F0))
    out["profiles"] = {"r": r.tolist(), "pressure": np.asarray(pressure(prof, mat, d0, r), float).tolist(),
                       "traction": law.traction(st, r).tolist() if st is not None else None}
    out["cells"] = int(n)
    return out


#: the time-step ladder of ``time_step_error``: steps per cycle as multiples of the scene's
TIME_STEP_FACTORS = (1, 2, 4)


def time_step_error(s: Scene, first: dict, *, n: int | None = None, h: float | None = None, law=None) -> dict:
    """The time step's share of the dissipation error, which the ladders (space at the scene's steps
    per cycle) leave out: MDR with ``n`` cells, or the FE model at mesh level ``h``, at 1, 2 and 4
    times the scene's steps per cycle (``TIME_STEP_FACTORS``; ``first``, the side's result at the
    scene's steps, e.g. its ladder's finest level, and one law for the others), through
    ``metrics.ladder_error``
    (the loop integral is the trapezoidal rule, order 2 where the loop is smooth between the
    samples). Returns the ladder with ``shift``, extrapolated minus the value at the scene's steps
    as ``metrics.dissipation_error`` measures it (relative, or, for a loop that hardly dissipates,
    in units of 4 mu F0 u_A: ``shift_unit``), the error the scene's step puts into that side's
    dissipation (None where the ladder gives no extrapolation). The two models' shifts differ (the
    incremental laws discretise the load path differently), so they do not cancel in MDR - FE:
    ``error_at_scene_step`` (GCI_SAFETY x |extrapolated - value at the scene's step| where the
    ladder is asymptotic, else its spread) joins each side's error bar on the dissipation and the
    slip index (``scene_verdicts``). Costs two more runs of the side at 2 and 4 times the steps (and for the
    FE model one more set-up, unless ``law``, the law that computed ``first``, is given: a law's runs
    start from rest, so one law serves every run)."""
    from dataclasses import replace

    if (n is None) == (h is None):
        raise ValueError("give exactly one of n (MDR cells) and h (FE mesh level)")
    if law is None:
        law = _mdr_law(s, n) if n is not None else _fe_law(s, h)
    runs = [first] + [_drive(replace(s, steps=k * s.steps), law)[0] for k in TIME_STEP_FACTORS[1:]]
    W = [r["dissipation"] for r in runs]
    lad = metrics.ladder_error([1.0 / (k * s.steps) for k in TIME_STEP_FACTORS], W)
    u_A = _u_amp(runs[0])
    shift = None if lad["extrapolated"] is None else \
        metrics.dissipation_error(lad["extrapolated"], W[0], s.mu, s.F0, u_A)
    small = abs(W[0]) < 0.01 * 4.0 * s.mu * s.F0 * u_A
    # the ladder's own error is that of its finest level (4x the steps); the scene's step is the
    # coarsest: its error is the distance to the extrapolation (with the GCI's safety factor) where
    # the ladder is asymptotic, else the spread, which bounds nothing
    if lad["extrapolated"] is not None and lad["bounded"]:
        at_step = metrics.GCI_SAFETY * abs(lad["extrapolated"] - float(W[0]))
    else:
        at_step = lad["error"]
    return {**lad, "steps": [k * s.steps for k in TIME_STEP_FACTORS], "dissipation": W, "shift": shift,
            "shift_unit": "4 mu F0 u_A" if small else "relative", "error_at_scene_step": at_step}


def _fe_law(s: Scene, h, **mesh_kw):
    """The scene's FE law at mesh level h; ``mesh_kw`` the model's own mesh options (the 3D law's
    ``refine``, ``band``)."""
    if s.fe_model == "3d":
        from fem.law3d import FEContact3D

        return FEContact3D(profile_of(s), materials_of(s), s.mu, F_max=s.F0 + s.dF, h_contact=h,
                           displacement="contact", **mesh_kw)
    from fem.law import FEContact

    return FEContact(profile_of(s), materials_of(s), s.mu, F_max=s.F0 + s.dF, h_contact=h,
                     displacement="contact", **mesh_kw)


def run_fe(s: Scene, h, vtu_path=None, keep_law=False, **mesh_kw) -> tuple:
    """One FE run at mesh level h (element size / a_ref); result dict + profiles, and the
    field data for plots (pair radii, pressure, traction and slip flags at the peak); with
    ``keep_law`` also the law (its runs start from rest: it serves further runs, e.g. the time step's)."""
    t0 = time.perf_counter()
    law = _fe_law(s, h, **mesh_kw)
    out, field = _run_fe(s, h, law, t0, vtu_path)
    return (out, field, law) if keep_law else (out, field)


def _run_fe(s: Scene, h, law, t0, vtu_path=None) -> tuple[dict, dict]:
    """``run_fe`` with its law built (set-up timed from ``t0``)."""
    from fem.output import write_fretting_vtu, write_vtu

    t1 = time.perf_counter()
    out, st = _drive(s, law)
    t2 = time.perf_counter()
    if s.fe_model == "3d":
        return _fe3d_outputs(s, law, out, st, h, t0, t1, t2)
    out.update(law.result_keys(s.F0, t0, t1, t2), h_contact=h, bulk_compliance=law.c_bulk)
    nr = law.normal(F_N=s.F0)
    it = law.model.interface
    T = np.asarray(st.T) if st is not None else np.zeros(it.n)
    lam = np.asarray(st.lam) if st is not None else np.zeros(it.n)
    out["profiles"] = {"r": nr.r.tolist(), "pressure": nr.pressure.tolist(),
                       "r_pairs": it.r.tolist(), "traction": (T / it.w).tolist() if st is not None else None}
    field = {"r": it.r, "p": nr.lam / it.w, "tau": T / it.w, "contact": lam > 0,
             "slip": (np.asarray(st.sgn) != 0) & (lam > 0) if st is not None else np.zeros(it.n, bool)}
    if vtu_path is not None:
        if st is not None:  # modes 0 + 1 at the peak of the last cycle, in the x-z plane
            k = peak_index(s)
            FN_peak = s.F0 + s.dF * np.sin(2 * np.pi * k / s.steps + s.alpha)
            write_fretting_vtu(law, st, FN_peak, vtu_path)
        else:
            write_vtu(law.model, nr, vtu_path)
    return out, field


def _fe3d_outputs(s: Scene, law, out, st, h, t0, t1, t2) -> tuple[dict, None]:
    """The 3D run's result (any drive; in the apparatus beside its keys, e.g. ``slip_index``): the
    keys of ``FEContact3D.result_keys``, the stick zone and traction angle at the peak of the
    tangential drive in the last cycle (``st``), profiles along the +x axis (the vertices on the
    symmetry plane); no field data (no VTU of the 3D model yet)."""
    out.update(law.result_keys(s.F0, t0, t1, t2), h_contact=h)
    nr = law.normal(F_N=s.F0)
    if st is not None:
        out.update(law.stick_zone(np.asarray(st.q), np.asarray(st.p), nr.contact_radius))
    ray = law.x_ray
    x = law.mi.x[ray]
    out["profiles"] = {"r": x.tolist(), "pressure": nr.p[ray].tolist(), "r_pairs": x.tolist(),
                       "traction": np.asarray(st.q)[ray, 0].tolist() if st is not None else None}
    return out, None


def closed_forms(s: Scene) -> dict | None:
    """Closed-form values of the scene (None if none applies), with their source."""
    closed = s.closed_form
    if closed is None or s.drive != "force":
        return None
    mat = materials_of(s)
    Es, Gs = mat.E_star, mat.G_star
    fa, FN, mu = s.amplitude, s.F0, s.mu
    r = _r_profile(a_ref(s))
    if closed == "hertz-mindlin":
        h = ref.hertz(FN, s.R, Es)
        a, d = float(h["a"]), float(h["d"])
        us = ref.gross_slip_displacement(d, mu, Es, Gs)
        return {"source": "Hertz (1882); Cattaneo (1938); Mindlin & Deresiewicz (1953, J. Appl. Mech.)",
                "contact_radius": a, "indentation": d,
                "stick_radius": float(ref.cattaneo_mindlin_stick_radius(fa, FN, mu, a)),
                "dissipation": float(ref.mindlin_deresiewicz_dissipation_force(fa, FN, mu, us)),
                "profiles": {"r": r.tolist(), "pressure": ref.hertz_pressure(r, FN, s.R, Es).tolist(),
                             # at the peak of a stationary loop the traction is Cattaneo's at F_A (Masing)
                             "traction": ref.cattaneo_mindlin_traction(r, fa, FN, mu, a).tolist()}}
    b = s.b
    inside = r < b
    q = np.zeros_like(r)
    q[inside] = fa / (2 * np.pi * b * np.sqrt(b**2 - r[inside] ** 2))
    return {"source": "Boussinesq (1885) flat punch; Mindlin (1949, J. Appl. Mech.): full stick below mu F_N",
            "contact_radius": b, "indentation": float(ref.flat_punch_approach(FN, b, Es)),
            "stick_radius": b, "dissipation": 0.0,
            "profiles": {"r": r.tolist(), "pressure": np.asarray(ref.flat_punch_pressure(r, FN, b)).tolist(),
                         "traction": q.tolist()}}


def _u_amp(res):
    return float(res.get("displacement_amplitude") or 0.5 * np.ptp(res["loop"]["du"]))


#: a number below this fraction of its natural scale is a numerical zero (reported as 0)
ZERO = 1e-9


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
    from .scenes import DISSIPATION_FLOOR

    tol = s.tolerances()
    fe_h = [float(x["h_contact"]) for x in fe_ladder]
    md_h = [1.0 / float(x["cells"]) for x in mdr_ladder]
    mdr, fe = mdr_ladder[-1], fe_ladder[-1]
    a = float(fe["contact_radius"])
    scale_W = 4.0 * s.mu * s.F0 * _u_amp(fe)
    V = {}

    def scalar(q, scale, tolerance, unit, extra=None, floor=None):
        fv = [_zero(x.get(q), scale) for x in fe_ladder]
        mv = [_zero(x.get(q), scale) for x in mdr_ladder]
        fl = metrics.ladder_error(fe_h, fv, floor=ZERO * scale)
        ml = metrics.ladder_error(md_h, mv, floor=ZERO * scale)
        V[q] = metrics.verdict(mv[-1], fv[-1], fl, ml, tolerance, unit=unit, extra=extra, floor=floor)

    def step_bars(unit_scale):
        """Each side's time-step and settling error bars in the unit of a metric (J divided by
        ``unit_scale``). A side whose time step was not computed (a family that runs none) gets a bar
        of 0 that bounds nothing, so its verdict can be no stronger than "consistent". The settling
        ("cycles"): ``mdr.ladder.settling_error`` of the finest level's dissipation over its closed
        cycles, two cycles repeating within ``mdr.loops.STATIONARY_TOL`` being stationary."""
        out = {}
        for side, res in (("mdr", mdr), ("fem", fe)):
            ts = (time_step or {}).get(side)
            if ts is None:
                out[side] = {"time step": {"status": "not computed", "bounded": False, "error": 0.0}}
            else:
                err = ts.get("error_at_scene_step")
                out[side] = {"time step": {"status": ts.get("status"), "bounded": ts.get("bounded", False),
                                           "error": None if err is None else float(err) / unit_scale}}
            W = list(res.get("dissipation_per_cycle") or [])[1:]
            st = settling_error(W, floor=STATIONARY_TOL * max((abs(float(w)) for w in W if w is not None
                                                               and np.isfinite(w)), default=0.0))
            out[side]["cycles"] = {**st, "error": None if st["error"] is None else st["error"] / unit_scale}
        return out

    scalar("contact_radius", a, tol["contact_radius"] * a, "m")
    scalar("stick_radius", a, tol["stick_radius"] * a, "m")
    dW = abs(float(fe["dissipation"]))
    floor_W = DISSIPATION_FLOOR * scale_W
    scalar("dissipation", scale_W, tol["dissipation"] * dW, "J", extra=step_bars(1.0), floor=floor_W)
    # the slip index is dW / (4 mu u_A F0) (u_A the drive's amplitude): its tolerance is relative, the
    # dissipation's, with the same floor; its time-step bar is the dissipation's over that scale
    si = fe.get("slip_index")
    si_scale = float(fe["dissipation"]) / float(si) if si and fe.get("dissipation") else scale_W
    scalar("slip_index", 1.0, tol["slip_index"] * abs(float(si or 0.0)), "",
           extra=step_bars(si_scale if si_scale > 0 else 1.0), floor=DISSIPATION_FLOOR)
    d_fe = [_distances(s, mdr, x) for x in fe_ladder]
    d_md = [_distances(s, x, fe) for x in mdr_ladder]
    for q, dist in d_fe[-1].items():
        fl = metrics.ladder_error(fe_h, [d.get(q) for d in d_fe], floor=ZERO)
        ml = metrics.ladder_error(md_h, [d.get(q) for d in d_md], floor=ZERO)
        V[q] = metrics.verdict(_zero(dist, 1.0), None, fl, ml, tol[q], signed=False,
                               unit="relative L2" if q.endswith("profile") else ("mu F0" if q == "loop_Fx" else "u_A"))
    return V


def closed_form_errors(s: Scene, mdr: dict, fe: dict, closed: dict) -> dict:
    """Errors of the finest MDR and FE results against the scene's closed forms."""
    cfe = {}
    for side, res in (("mdr", mdr), ("fem", fe)):
        cfe[side] = {q: metrics.rel(res[q], closed[q]) for q in ("contact_radius", "stick_radius")}
        cfe[side]["dissipation"] = metrics.dissipation_error(res["dissipation"], closed["dissipation"], s.mu, s.F0,
                                                             _u_amp(res))
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
            u_A = _u_amp(res)
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


def run_scene(s: Scene, out_dir=None, *, fields: bool = True, log=None) -> dict:
    """Run one scene; returns its result dict. With ``out_dir`` the VTU and figures are
    written there (the caller makes the directory atomic, see ``write_scene``)."""
    log = log or (lambda msg: None)
    t0 = time.perf_counter()
    if s.variants and "a_over_R" in s.variants[0]:
        return _run_curvature(s, out_dir, log)
    if s.variants and "relax" in s.variants[0]:
        return _run_assumptions3d(s, out_dir, log)
    if s.variants and "tilts" in s.variants[0]:
        return _run_tilt(s, out_dir, log)
    if s.variants:
        return _run_validity(s, out_dir, log)
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
        from . import figures

        if field is not None:
            result["files"]["vtu"] = "fields.vtu"
        result["files"].update(figures.scene_figures(result, out_dir))
        if fields and field is not None:
            from . import fields as fieldplots

            try:
                result["files"]["fields"] = fieldplots.field_figure(out_dir / "fields.vtu", field, result,
                                                                    out_dir / "fields.png")
            except fieldplots.RenderError as e:
                result["files"]["fields_error"] = str(e)
                log(f"  field plot skipped: {e}")
    result["runtime_s"] = time.perf_counter() - t0
    return result


def curvature_variant(s: Scene, v: dict) -> Scene:
    """The sphere of scene ``s`` loaded to the contact radius a = a_over_R R (Hertz:
    F0 = 4 E* a^3 / (3 R)), both bodies of Poisson ratio ``nu``, force amplitude mu F0 / 2.

    For the parabolic profile only a/R matters, and the FE body's shape in units of a is
    the same for a given a/R whether F0 or R is varied; the sphere's cap is at most R high
    (20 a at a/R = 5 %), so at large a/R the real sphere is also a small body."""
    from dataclasses import replace

    nu = float(v.get("nu", s.nu1))
    E_star = Materials(s.E1, nu, s.E2, nu).E_star
    a = float(v["a_over_R"]) * s.R
    F0 = 4.0 * E_star * a ** 3 / (3.0 * s.R)
    return replace(s, name=f"{s.name}[a/R={v['a_over_R']:g},nu={nu:g}]", F0=F0, dF=0.0,
                   amplitude=0.5 * s.mu * F0, nu1=nu, nu2=nu, variants=())


def _run_curvature(s: Scene, out_dir, log) -> dict:
    """Half-space validity against the curvature a/R: every variant through both ladders
    (``curvature_variant``), so the curvature effect (FE extrapolated - MDR) stands with its
    error bar beside the tolerance, separated from the mesh error."""
    t0 = time.perf_counter()
    rows = []
    for v in s.variants:
        sv = curvature_variant(s, v)
        mdr_ladder = [run_mdr(sv, n) for n in sv.mdr_cells]
        fe_ladder = [run_fe(sv, h)[0] for h in sv.fe_levels]
        ver = scene_verdicts(sv, fe_ladder, mdr_ladder)
        row = {"a_over_R": float(v["a_over_R"]), "nu": sv.nu1, "F0": sv.F0, "dofs": fe_ladder[-1]["dofs"],
               "holds": metrics.conjunction(ver), "grade": metrics.scene_grade(ver), "verdicts": ver,
               "runtime_s": sum(x["runtime_s"]["total"] for x in fe_ladder)}
        for q in ("contact_radius", "stick_radius", "dissipation"):
            x = ver[q]
            ref_q = abs(x["fem"]) if q == "dissipation" else mdr_ladder[-1]["contact_radius"]
            # FE extrapolated where its ladder is asymptotic, else its finest level (error bar: the spread)
            fe_q = x["fem_ladder"].get("extrapolated")
            fe_q = x["fem"] if fe_q is None else fe_q
            row[f"{q}_effect"] = None if fe_q is None or x["mdr"] is None else (fe_q - x["mdr"]) / ref_q
            row[f"{q}_effect_error"] = None if x["fem_error"] is None else (x["fem_error"] + x["mdr_error"]) / ref_q
        rows.append(row)
        d = ver["dissipation"]
        log(f"  a/R = {row['a_over_R']:.2%}, nu = {row['nu']:g}: dissipation MDR - FE "
            f"{d['difference'] / abs(d['fem']):+.3%} (error bars {(d['fem_error'] + d['mdr_error']) / abs(d['fem']):.3%}, "
            f"tolerance {d['tolerance'] / abs(d['fem']):.2%}): {row['grade']}")
    result = {"scene": s.as_dict(), "closed_form": None, "curvature": rows, "errors": {"a_ref": a_ref(s)},
              "files": {}, "runtime_s": time.perf_counter() - t0}
    if out_dir is not None:
        from . import figures

        result["files"].update(figures.curvature_figure(result, Path(out_dir)))
    return result


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
    ``mdr.ladder.settling_error`` (``floor``: the change below which the runs count as settled); its
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


def assumption_variant(s: Scene, v: dict) -> Scene:
    """The scene of one variant of an assumptions scene: ``v`` may set ``b`` (a truncated sphere),
    ``E2`` and ``nu2`` (the block's material); ``relax`` names the assumption."""
    from dataclasses import replace

    kw = {k: float(v[k]) for k in ("b", "E2", "nu2") if k in v}
    if kw.get("b"):
        kw["profile"] = "truncated"
    fmt = {"b": lambda x: f"b = {x * 1e6:g} um", "E2": lambda x: f"E2 = {x / 1e9:g} GPa",
           "nu2": lambda x: f"nu2 = {x:g}"}
    label = ", ".join(f(v[k]) for k, f in fmt.items() if k in v) or "sphere"
    return replace(s, name=f"{s.name}[{v['relax']}: {label}]", variants=(), **kw)


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


def _run_assumptions3d(s: Scene, out_dir, log) -> dict:
    """Mindlin's assumptions, one at a time, on the 3D model: every variant at every 3D mesh level
    twice on the same mesh (``FEContact3D.variant``) with the assumption relaxed ("on": the free
    traction direction, or the normal-tangential coupling of a dissimilar pair) and imposed ("off":
    q_y = 0, or no coupling, as in MDR and the axisymmetric model). The effect on, minus off, cancels
    the discretisation error the two runs share, so its ladder (``metrics.ladder_error``) resolves an
    effect far below the 3D model's own error; the error is at least the estimator's resolution
    (``EFFECTS_3D``), plus, for the quantities of the cycles, the finest level's settling towards
    the stationary cycle (``effect_settling``: the 3D cycles settle geometrically). The verdict of a metric: |effect| <= its error + the catalogue's tolerance
    (the assumption holds), graded by ``metrics.effect_verdict`` (a spread bounds nothing)."""
    from fem.contact_run import drive_3d_together

    t0 = time.perf_counter()
    rows = []
    for v in s.variants:
        sv = assumption_variant(s, v)
        relax = v["relax"]
        kw = {"fa": sv.amplitude} if sv.drive == "force" else {"ua": sv.amplitude}
        levels = []
        for h in sv.fe_levels:
            law = _fe_law(sv, h)
            pair = (law.variant(traction="free", coupling=True),
                    law.variant(traction="x") if relax == "direction" else law.variant(coupling=False))
            runs = dict(zip(("on", "off"), drive_3d_together(pair, sv.mu, sv.F0, sv.dF, sv.alpha, kw.get("ua"),
                                                             kw.get("fa"), sv.cycles, sv.steps,
                                                             settle=(SETTLE_TOL_3D, SETTLE_MAX_CYCLES))))
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
            log(f"  {sv.name} a/{1 / h:.0f}: dissipation {_pct_or(eff['dissipation'])}, stick axes x, y "
                f"{_pct_or(eff['stick_axis_x'])}, {_pct_or(eff['stick_axis_y'])} of a, "
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
            if settle is not None:
                err = None if err is None or settle["error"] is None else err + settle["error"]
            bounded = lad["bounded"] and (settle is None or settle["bounded"])
            verdicts[q] = {**metrics.effect_verdict(lad["value"], lad, None if tkey is None else tol[tkey], error=err,
                                                    bounded=bounded),
                           "kind": kind, "resolution": floor[res], "ladder": lad, "settling": settle}
        rows.append({"variant": sv.name, "relax": relax, **{k: v[k] for k in ("b", "E2", "nu2") if k in v},
                     "levels": levels, "verdicts": verdicts, "pressure": pressure_against_mdr(sv, levels),
                     "holds": metrics.family_holds(verdicts.values()),
                     "grade": metrics.scene_grade({q: x for q, x in verdicts.items() if x["tolerance"] is not None}),
                     "traction_angle_max": levels[-1]["on"]["traction_angle_max"]})
    result = {"scene": s.as_dict(), "closed_form": None, "assumptions3d": rows, "errors": {"a_ref": a_ref(s)},
              "files": {}, "runtime_s": time.perf_counter() - t0}
    if out_dir is not None:
        from . import figures

        result["files"].update(figures.assumptions3d_figure(result, Path(out_dir)))
    return result


def tilt_variant(s: Scene, v: dict) -> Scene:
    """The aligned scene of one profile of a tilt scene (``v``: profile, b, tilts)."""
    from dataclasses import replace

    name = f"{s.name}[{v['profile']} b = {v['b'] * 1e6:g} um{', banded edge' if 'band' in v else ''}]"
    return replace(s, name=name, profile=v["profile"], b=float(v["b"]), variants=(),
                   fe_levels=tuple(v.get("fe_levels", s.fe_levels)))


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
    scale = 4.0 * mu * F0 * float(ref["displacement_amplitude"])
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
    ``mdr.ladder.settling_error`` of the dissipation and slip-index effects cycle by cycle
    (each cycle's dissipation over 4 mu F0 u_A of the last), with the floor the runs settled to
    (``SETTLE_TOL_3D`` of each run's dissipation or of 1 % of 4 mu F0 u_A, ``fem.contact_run.settled``,
    in the effect's unit); the loop distance, whose loops are kept for the last cycle only, gets
    ``SETTLING_RATIO_MAX`` / (1 - it) times the two runs' last loop changes (the du of
    ``mdr.loops.analyse_cycles``, in u_A as ``loop_du``; a ratcheting loop drifts in du while its
    dissipation has settled), which bound nothing; the contact area is no quantity of the cycles
    (None)."""
    from fem.contact_run import HARDLY_DISSIPATES
    from mdr.ladder import SETTLING_RATIO_MAX as r

    W = list(run.get("dissipation_per_cycle") or [])[1:]
    W0 = list(ref.get("dissipation_per_cycle") or [])[1:] if ref_cycles else [float(ref["dissipation"])] * len(W)
    if not W or len(W0) != len(W):
        none = settling_error([None])
        return {"dissipation": none, "slip_index": none, "contact_area": None, "loop_du": none}
    u, u0 = float(run["displacement_amplitude"]), float(ref["displacement_amplitude"])
    si = (lambda w, ua: None if run.get("slip_index") is None or ref.get("slip_index") is None
          else w / (4.0 * mu * F0 * ua))
    eff = [_tilt_effects({**run, "dissipation": w, "slip_index": si(w, u), "loop": run["loop"]},
                         {**ref, "dissipation": w0, "slip_index": si(w0, u0)}, relative, mu, F0)
           for w, w0 in zip(W, W0)]
    S = 4.0 * mu * F0 * u0
    settled_change = SETTLE_TOL_3D * (max(abs(W[-1]), HARDLY_DISSIPATES * S) + max(abs(W0[-1]), HARDLY_DISSIPATES * S))
    floor_W = settled_change / (abs(W0[-1]) if relative and W0[-1] else S)
    changes = [((x.get("cycle_change") or {}).get("loop")) for x in (run, ref) if "cycle_change" in x]
    loop = {"value": None, "extrapolated": None, "ratio": None, "cycles": len(W), "bounded": False,
            "status": "last loop change",
            "error": None if any(c is None for c in changes) else float(sum(changes)) * r / (1.0 - r)}
    return {"dissipation": settling_error([e["dissipation"] for e in eff], floor=floor_W),
            "slip_index": settling_error([e["slip_index"] for e in eff], floor=settled_change / S),
            "contact_area": None, "loop_du": loop}


def _with_settling(v: dict, settle: dict | None) -> dict:
    """An effect verdict (``metrics.effect_verdict``) with a settling error bar added
    (``_tilt_settling``; None: no quantity of the cycles): error and boundedness combined, regraded."""
    if settle is None:
        return {**v, "settling": None}
    err = None if v["error"] is None or settle["error"] is None else v["error"] + settle["error"]
    out = metrics.effect_verdict(v["effect"], {"status": v["status"]}, v["tolerance"], error=err,
                                 bounded=v["bounded"] and settle["bounded"])
    return {**out, "settling": settle}


def _tilt_tolerance(q, tol, relative, W0, scale, si0=None):
    """The tolerance of a tilt effect: the catalogue's, the dissipation's relative to the reference or in
    units of 4 mu F0 u_A with its floor, the slip index's relative to the reference's ``si0`` with the
    same floor (as in ``scene_verdicts``)."""
    from .scenes import DISSIPATION_FLOOR

    if q == "slip_index":
        return max(tol["slip_index"] * abs(float(si0 or 0.0)), DISSIPATION_FLOOR)
    if q != "dissipation":
        return None if TILT_METRICS[q] is None else tol[TILT_METRICS[q]]
    return tol["dissipation"] if relative else max(tol["dissipation"] * abs(W0) / scale, DISSIPATION_FLOOR)


def _run_tilt(s: Scene, out_dir, log) -> dict:
    """Misalignment of the flat face (``tilt`` family): per profile, the aligned face and every tilt
    (``v["tilts"]``, rad) on each 3D mesh level (one set-up per level, ``FEContact3D.variant``), the
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
    import warnings

    from fem.contact_run import drive_3d_together

    from .scenes import tilt_critical

    t_scene = time.perf_counter()
    tol = s.tolerances()
    rows = []
    for v in s.variants:
        sv = tilt_variant(s, v)
        mat = materials_of(sv)
        thc = tilt_critical(sv.F0, sv.b, mat.E_star)
        tilts = (0.0,) + tuple(float(t) for t in v["tilts"])
        mdr_ladder = [run_mdr(sv, n) for n in sv.mdr_cells]
        mdr = mdr_ladder[-1]
        levels = []
        for j, h in enumerate(sv.fe_levels):
            t0 = time.perf_counter()
            law = _fe_law(sv, h, **{k: v[k][j] for k in ("refine", "band") if k in v})  # the loaded edge refined
            setup = time.perf_counter() - t0
            runs = []
            laws = [law.variant(tilt=th) for th in tilts]
            with warnings.catch_warnings():  # stationarity is reported per run
                warnings.simplefilter("ignore", RuntimeWarning)
                outs = drive_3d_together(laws, sv.mu, sv.F0, sv.dF, sv.alpha, None, sv.amplitude, sv.cycles,
                                         sv.steps, settle=(SETTLE_TOL_3D, SETTLE_MAX_CYCLES))
            for th, lt, out in zip(tilts, laws, outs):
                tk = lt.tilt_keys(sv.F0)
                runs.append({"tilt": th, "contact_vertices": int(lt.contact_mask(lt.normal(F_N=sv.F0).p).sum()),
                             **{k: out.get(k) for k in ("dissipation", "slip_index", "displacement_amplitude",
                                                        "stationary", "dissipation_per_cycle", "cycle_change",
                                                        "cycles_run", "settled")},
                             "contact_area_fraction": tk["contact_area_fraction"],
                             "contact_x_min": tk["contact_x_min"], "contact_x_max": tk["contact_x_max"],
                             "loop": {k: out["loop"][k] for k in ("du", "Fx")},
                             "runtime_s": out["runtime_s"]["cycles"]})
            levels.append({"h": h, "refine": law.hmesh.params.refine_h, "band": law.hmesh.params.band_h,
                           "dofs": law.ndofs, "vertices": law.n,
                           "setup_s": setup, "runs": runs,
                           "runtime_s": time.perf_counter() - t0})
            mp = law.hmesh.params
            edge = "".join(f", {k} {x:g} a_ref" for k, x in (("ball", mp.refine_h), ("band", mp.band_h)) if x is not None)
            log(f"  {sv.name} h = {h:g} a_ref{edge} ({law.n} vertices): {len(tilts)} tilts in "
                f"{levels[-1]['runtime_s']:.0f} s")
        # the dissipation's unit, per reference: relative unless it hardly dissipates (the flat punch sticks)
        fine0 = levels[-1]["runs"][0]

        def relative(ref):
            return abs(float(ref["dissipation"])) >= 0.01 * 4.0 * sv.mu * sv.F0 * float(ref["displacement_amplitude"])

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
                pt["aligned"][q] = _with_settling(metrics.effect_verdict(lad["value"], lad, t3 if resolved else None),
                                                  settle3[q])
                if q == "contact_area":
                    continue
                tm = _tilt_tolerance(q, tol, relm, mdr["dissipation"], 4.0 * sv.mu * sv.F0 *
                                     float(mdr["displacement_amplitude"]), mdr.get("slip_index"))
                lf = metrics.ladder_error(hs, [e[q] for e in vsm])
                lm = metrics.ladder_error(md_h, mdr_side[q])
                errm = float("nan") if lf["error"] is None or lm["error"] is None else lf["error"] + lm["error"]
                pt["mdr"][q] = _with_settling(metrics.effect_verdict(lf["value"], lf, tm if resolved else None,
                                                                     error=errm, bounded=lf["bounded"] and lm["bounded"]),
                                              settlem[q])
            pt["holds"] = metrics.family_holds(pt["aligned"].values())
            pt["grade"] = metrics.scene_grade({q: x for q, x in pt["aligned"].items() if x["tolerance"] is not None}) \
                if resolved else "undetermined"
            points.append(pt)
            a = pt["aligned"]
            log(f"  {sv.name} theta = {th:.3g} rad ({th / thc:.3g} theta_c): dissipation "
                f"{_pct_or(a['dissipation']['effect'])} +- {_pct_or(a['dissipation']['error'])}, contact area "
                f"{_pct_or(a['contact_area']['effect'])}: {pt['grade']}")
        # the largest tilt up to which the aligned answer is not contradicted on the dissipation (graded
        # holds or consistent within its spread: a two-level ladder bounds nothing, so no tilt "holds")
        below = None
        for pt in points:
            if pt["aligned"]["dissipation"]["grade"] not in ("holds", "consistent within its spread"):
                break
            below = pt["tilt"]
        rows.append({"variant": sv.name, "profile": sv.profile, "b": sv.b, "theta_c": thc, "banded": "band" in v,
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
    result = {"scene": s.as_dict(), "closed_form": None, "tilt": rows, "errors": {"a_ref": a_ref(s)},
              "files": {}, "runtime_s": time.perf_counter() - t_scene}
    if out_dir is not None:
        from . import figures

        result["files"].update(figures.tilt_figure(result, Path(out_dir)))
    return result


def _pct_or(x):
    return "undetermined" if x is None else f"{100 * x:+.3f} %"


#: the bodies' size of the default FE model, in contact radii (meshes.axisym: block 200 a_ref, the cap as high)
VALIDITY_DEFAULT_SIZE = 200.0


def validity_label(v: dict) -> str:
    """A validity variant's label, saying which body is shrunk: 'block 3 a (cap 200 a)', 'cap 3 a
    (block 200 a)' or 'block 3 a, cap 3 a'."""
    if "block" in v and "cap" in v:
        return f"block {v['block']:g} a, cap {v['cap']:g} a"
    (kind, x), = v.items()
    other = "cap" if kind == "block" else "block"
    return f"{kind} {x:g} a ({other} {VALIDITY_DEFAULT_SIZE:g} a)"


def _run_validity(s: Scene, out_dir, log) -> dict:
    """Half-space validity: FE with the block or the cap shrunk (multiples of a_ref), one mesh level."""
    t0 = time.perf_counter()
    h = s.fe_levels[-1]
    a = a_ref(s)
    mdr = run_mdr(s, s.mdr_cells[-1])
    closed = closed_forms(s)
    base, _ = run_fe(s, h)
    rows = []
    for v in ({},) + tuple(s.variants):
        # each body at its own size: the default cap is as high as the block, so a block-only variant
        # keeps the cap at the default 200 a explicitly (else shrinking the block shrinks the cap)
        block, cap = v.get("block", VALIDITY_DEFAULT_SIZE), v.get("cap", VALIDITY_DEFAULT_SIZE)
        kw = {"block_size": block * a, "indenter_height": cap * a} if v else {}
        size = min(block, cap)
        if size < 25:
            kw["probe_depth"] = 0.5 * (1.25 + 0.8 * size) * a
        res = base if not v else run_fe(s, h, **kw)[0]
        row = {"variant": "default (200 a)" if not v else validity_label(v),
               "block_over_a": block, "cap_over_a": cap, "dofs": res["dofs"]}
        for q in ("contact_radius", "stick_radius", "dissipation"):
            row[q] = res[q]
            row[f"{q}_mdr_minus_fe"] = metrics.rel(mdr[q], res[q])
            row[f"{q}_vs_default"] = metrics.rel(res[q], base[q])
        row["bulk_compliance"] = res["bulk_compliance"]
        row["runtime_s"] = res["runtime_s"]["total"]
        rows.append(row)
        log(f"  {row['variant']}: a {row['contact_radius']:.4g} m (MDR-FE {row['contact_radius_mdr_minus_fe']:+.2%})")
    result = {"scene": s.as_dict(), "closed_form": closed, "mdr": mdr, "fem": base, "validity": rows,
              "errors": {"a_ref": a}, "files": {}, "runtime_s": time.perf_counter() - t0}
    if out_dir is not None:
        from . import figures

        result["files"].update(figures.validity_figure(result, Path(out_dir)))
    return result


# ---------------------------------------------------------------------- storage


def scene_dir(out_root, name) -> Path:
    return Path(out_root) / "scenes" / name


def load_scene(out_root, name) -> dict | None:
    """The stored result of a scene, or None if absent or unreadable."""
    import json

    p = scene_dir(out_root, name) / "result.json"
    try:
        return json.loads(p.read_text())
    except (OSError, ValueError):
        return None


def write_scene(s: Scene, out_root, fingerprint: str, *, fields: bool = True, log=None, meta=None) -> dict:
    """Run a scene into a temporary directory and move it into place when complete: an
    interrupted run leaves the previous result (or nothing) and never half a scene.
    ``meta``: extra keys stored in result.json (e.g. the ``worker`` that ran it)."""
    final = scene_dir(out_root, s.name)
    final.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{s.name}.", dir=final.parent))
    os.chmod(tmp, DIR_MODE)
    try:
        result = run_scene(s, tmp, fields=fields, log=log)
        result["fingerprint"] = fingerprint
        result.update(meta or {})
        write_json(tmp / "result.json", result)
        _swap_into_place(tmp, final)
        return result
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def _swap_into_place(tmp: Path, final: Path) -> None:
    """Replace the scene directory ``final`` by the complete directory ``tmp`` (same parent)."""
    old = None
    if final.exists():
        old = final.with_name(f".{final.name}.old.{os.getpid()}")
        os.replace(final, old)
    os.replace(tmp, final)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def scene_files(out_root, name) -> dict:
    """The stored files of a scene as {relative path: bytes} (to ship them from a worker)."""
    d = scene_dir(out_root, name)
    return {p.relative_to(d).as_posix(): p.read_bytes() for p in sorted(d.rglob("*")) if p.is_file()}


def install_scene_files(out_root, name, files: dict) -> None:
    """Store a scene from {relative path: bytes} (``scene_files`` of a worker), atomically as
    ``write_scene`` does; it must hold result.json."""
    if "result.json" not in files:
        raise ValueError(f"scene {name}: the shipped files hold no result.json")
    final = scene_dir(out_root, name)
    final.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{name}.", dir=final.parent))
    os.chmod(tmp, DIR_MODE)
    try:
        for rel, data in files.items():
            path = (tmp / rel).resolve()
            if tmp.resolve() not in path.parents:
                raise ValueError(f"scene {name}: shipped file {rel!r} lies outside the scene directory")
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
        _swap_into_place(tmp, final)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
