"""One side of a scene, run at one level: MDR with n cells (``run_mdr``), the FE model at mesh level h
(``run_fe``), both driven by the same code (``mdr.drive.run_contact`` for the contact driven
directly, ``mdr.apparatus.apparatus_result`` for the apparatus), so that the result keys are those of
``python -m mdr contact`` / ``apparatus``; the time step's share of the dissipation error
(``time_step_error``) and the closed forms of a scene (``closed_forms``). The families
(``validation.families``) build their runs from these.
"""
from __future__ import annotations

import statistics
import time

import numpy as np

from mdr.apparatus import apparatus_result
from mdr.drive import run_contact
from mdr.law import MDRContact
from mdr.loading import HARDLY_DISSIPATES, gross_slip_work
from mdr.materials import Materials
from mdr.normal import approach_from_force, pressure
from mdr.profiles import make_profile
from mdr import reference as ref

from . import metrics
from .scenes import Scene, a_ref


def materials_of(s: Scene) -> Materials:
    return Materials(s.E1, s.nu1, s.E2, s.nu2)


def profile_of(s: Scene):
    return make_profile(s.profile, None if s.profile == "flat" else s.R, None if s.profile == "sphere" else s.b)


def peak_index(s: Scene) -> int:
    """Step of the positive peak of the tangential drive in the last cycle."""
    return s.loading.last_peak()[0]


def run_scene_loading(s: Scene, law):
    """Run the scene's loading with ``law``; returns (result dict, state at the peak step). A 3D FE law
    driven directly runs through ``fem.contact_run.drive_3d`` for its 3D keys, as ``python -m fem contact
    --model 3d`` does; every result states the normal loading that preceded its cycles (``normal_loading``:
    the scene's ``Loading.normal_steps``, 20 for a 3D law where it states none)."""
    k = peak_index(s)
    if s.drive == "apparatus":
        return apparatus_result(law, s.apparatus_of(), s.loading, state_at=k)
    from fem.solid3d.law import FEContact3D

    if isinstance(law, FEContact3D):  # the 3D law: its per-cycle 3D keys
        from fem.contact_run import drive_3d

        return drive_3d(law, s.loading, state_at=k)
    return run_contact(law, s.loading, state_at=k)


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
        out, st = run_scene_loading(s, law)
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


#: a number below this fraction of its natural scale is a numerical zero (a pair scene's radii over the
#: contact radius, its dissipation and its time step's changes over 4 mu F0 u_A)
ZERO = 1e-9


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
        law = _mdr_law(s, n) if n is not None else fe_law(s, h)
    runs = [first] + [run_scene_loading(replace(s, steps=k * s.steps), law)[0] for k in TIME_STEP_FACTORS[1:]]
    W = [r["dissipation"] for r in runs]
    u_A = u_amp(runs[0])
    # changes below ZERO x 4 mu F0 u_A are the loop integral's round-off (a sticking face's 3e-20 J
    # moving by 4e-24 J between step counts): converged, not a ladder out of its order range
    lad = metrics.ladder_error([1.0 / (k * s.steps) for k in TIME_STEP_FACTORS], W,
                               floor=ZERO * float(gross_slip_work(s.mu, s.F0, u_A)))
    shift = None if lad["extrapolated"] is None else \
        metrics.dissipation_error(lad["extrapolated"], W[0], s.mu, s.F0, u_A)
    small = abs(W[0]) < HARDLY_DISSIPATES * float(gross_slip_work(s.mu, s.F0, u_A))
    # the ladder's own error is that of its finest level (4x the steps); the scene's step is the
    # coarsest: its error is the distance to the extrapolation (with the GCI's safety factor) where
    # the ladder is asymptotic, else the spread, which bounds nothing
    if lad["extrapolated"] is not None and lad["bounded"]:
        at_step = metrics.GCI_SAFETY * abs(lad["extrapolated"] - float(W[0]))
    else:
        at_step = lad["error"]
    return {**lad, "steps": [k * s.steps for k in TIME_STEP_FACTORS], "dissipation": W, "shift": shift,
            "shift_unit": "4 mu F0 u_A" if small else "relative", "error_at_scene_step": at_step}


def fe_law(s: Scene, h, **mesh_kw):
    """The scene's FE law at mesh level h; ``mesh_kw`` the model's own mesh options (the 3D law's
    ``refine``, ``band``)."""
    if s.fe_model == "3d":
        from fem.solid3d.law import FEContact3D

        return FEContact3D(profile_of(s), materials_of(s), s.mu, F_max=s.F0 + s.dF, h_contact=h,
                           displacement="contact", **mesh_kw)
    from fem.axisym.law import FEContact

    return FEContact(profile_of(s), materials_of(s), s.mu, F_max=s.F0 + s.dF, h_contact=h,
                     displacement="contact", **mesh_kw)


def run_fe(s: Scene, h, vtu_path=None, keep_law=False, **mesh_kw) -> tuple:
    """One FE run at mesh level h (element size / a_ref); result dict + profiles, and the
    field data for plots (pair radii, pressure, traction and slip flags at the peak); with
    ``keep_law`` also the law (its runs start from rest: it serves further runs, e.g. the time step's)."""
    t0 = time.perf_counter()
    law = fe_law(s, h, **mesh_kw)
    out, field = _run_fe(s, h, law, t0, vtu_path)
    return (out, field, law) if keep_law else (out, field)


def _run_fe(s: Scene, h, law, t0, vtu_path=None) -> tuple[dict, dict]:
    """``run_fe`` with its law built (set-up timed from ``t0``)."""
    from fem.axisym.output import write_fretting_vtu, write_vtu

    t1 = time.perf_counter()
    out, st = run_scene_loading(s, law)
    t2 = time.perf_counter()
    if s.fe_model == "3d":
        return _fe3d_outputs(s, law, out, st, h, t0, t1, t2)
    out.update(law.result_keys(s.F0, t0, t1, t2), h_contact=h)
    nr = law.normal(F_N=s.F0)
    iface = law.model.interface
    T = np.asarray(st.T) if st is not None else np.zeros(iface.n)
    lam = np.asarray(st.lam) if st is not None else np.zeros(iface.n)
    out["profiles"] = {"r": nr.r.tolist(), "pressure": nr.pressure.tolist(),
                       "r_pairs": iface.r.tolist(), "traction": (T / iface.w).tolist() if st is not None else None}
    field = {"r": iface.r, "p": nr.lam / iface.w, "tau": T / iface.w, "contact": lam > 0,
             "slip": (np.asarray(st.sgn) != 0) & (lam > 0) if st is not None else np.zeros(iface.n, bool)}
    if vtu_path is not None:
        if st is not None:  # modes 0 + 1 at the peak of the last cycle, in the x-z plane
            write_fretting_vtu(law, st, s.loading.last_peak()[1], vtu_path)
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
    x = law.model.mi.x[ray]
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


def u_amp(res):
    return float(res.get("displacement_amplitude") or 0.5 * np.ptp(res["loop"]["du"]))


def pct_or(x):
    return "undetermined" if x is None else f"{100 * x:+.3f} %"
