"""One FE fretting run with the contact driven directly: ``python -m fem contact``.

The FE law (``fem.axisym.law.FEContact``) is driven by ``mdr.drive.run_contact``, the
same harmonic loads and cycle analysis as ``python -m mdr contact``, so the
JSON keys are the same; added: ``dofs``, ``mesh``, ``solver`` and
``runtime_s`` split into ``setup`` (mesh, assembly, factorisation and
condensation of both Fourier modes) and ``cycles`` (the load history).
The displacement keys (``--ua``, ``loop.du``, ``displacement_amplitude``) are in
the measure ``displacement`` (a JSON key): ``"contact"`` (default) the
half-space comparable relative displacement of ``fem.bulk`` (plate displacement
minus the bodies' series compliance, from axis probes and Cerruti's solution),
what ``python -m mdr contact`` means by them; ``"plate"`` the indenter top plate
relative to the block bottom. ``bulk_compliance`` (m/N) is that series
compliance at F0 (plate = contact + bulk_compliance * Fx); ``contact_radius``
and ``indentation`` are the FE's own at F0 (the half-space comparable
indentation of ``fem.axisym.normal``), ``approach`` the plate approach.
"""
from __future__ import annotations

import math
import time

from dataclasses import replace

from common.errors import InputError

from mdr.drive import run_contact, run_mdr_contact
from mdr.loading import HARDLY_DISSIPATES, Loading, gross_slip_work

from fem.options import FEOptions
from fem.solid3d import runs


def run_fem_contact(profile, materials, mu, loading: Loading, options: FEOptions = FEOptions(), *, vtu=None,
                    return_law=False, paired=False, log=None):
    """FE fretting run under ``loading`` (the contact driven directly: ``Loading.of``) with the FE side
    of ``options`` (``fem.options.FEOptions``: the axisymmetric model ``fem.axisym.law.FEContact`` or
    the 3D model ``fem.solid3d.law.FEContact3D``); returns the result dict (and the law if
    ``return_law``). ``vtu`` (a path): the fields at the peak of the drive in the last cycle, written
    after the run, its path the key ``vtu``: of the axisymmetric model in the x-z plane
    (``fem.axisym.output.write_fretting_vtu``: displacements, von Mises stress and the stress
    components, contact pressure, shear traction, stick/slip status and slip), of the 3D model the
    contact disk (``fem.solid3d.output``: pressure, both shear traction components, stick/slip
    status, slip; without ``per_cycle``, the run being cut at that step). ``paired`` (3D only): also
    run the twin along x on the same set-up and add the key ``paired`` (:func:`paired_keys`). ``log``:
    called with a progress line before the set-up and before the cycles."""
    loading.check_friction(mu)  # before the costly set-up (the load itself is checked: a Loading)
    if paired:
        check_paired(materials, options, vtu)
    log = log or (lambda msg: None)
    log(f"the {options.model} model: mesh and set-up (cached meshes and condensations are read back)")
    if options.model == "3d":
        return _run_3d(profile, materials, mu, loading, options, return_law, vtu, paired, log)
    t0 = time.perf_counter()
    F0 = loading.F0
    law = options.law(profile, materials, mu, loading.F_max)
    t1 = time.perf_counter()
    log(f"set-up {t1 - t0:.1f} s; {loading.cycles} cycles of {loading.steps} steps")
    k, FN_peak = loading.last_peak()
    res = run_contact(law, loading, state_at=k if vtu is not None else None)  # the state at the peak: the fields
    out, st = res if vtu is not None else (res, None)
    t2 = time.perf_counter()
    if vtu is not None:
        from fem.axisym.output import write_fretting_vtu

        out["vtu"] = str(write_fretting_vtu(law, st, FN_peak, vtu))
    out.update(law.result_keys(F0, t0, t1, t2))  # the FE's own contact radius and indentation at F0, ...
    out["approach"] = law.normal(F_N=F0).approach
    out["displacement"] = law.displacement
    if return_law:
        return out, law
    return out


#: steps of the frictional normal loading before the cycles of a 3D run whose loading states none
#: (``with_normal_loading``; with coupling, slip during the normal loading locks traction in)
RAMP_STEPS = 20


def with_normal_loading(loading: Loading) -> Loading:
    """The loading of a 3D run: its own normal loading (``Loading.normal_steps``), or ``RAMP_STEPS`` steps
    where it states none; the result's ``normal_loading`` says which ran."""
    return loading if loading.normal_steps else replace(loading, normal_steps=RAMP_STEPS)


def check_paired(materials, options: FEOptions, vtu=None) -> None:
    """The conditions of :func:`paired_keys`, checked before any work: the 3D model with the traction
    of free direction on the aligned face, bodies without normal-tangential coupling (Dundurs' beta = 0,
    as for identical elastic constants: where MDR is the exact half-space answer under Mindlin's
    assumption), the half-space comparable displacement, no field file."""
    if options.model != "3d":
        raise InputError("paired (--paired) applies to the 3D model only (--model 3d: the twin along x on its mesh)")
    if options.traction not in (None, "free"):
        raise InputError(f"paired (--paired) needs the traction of free direction, since its twin is the run along x; "
                         f"got traction={options.traction!r}")
    if options.tilt != 0.0:
        raise InputError(f"paired (--paired) needs the aligned face (tilt 0: MDR knows no tilt), "
                         f"got tilt={options.tilt!r}")
    if abs(materials.dundurs_beta) > PAIRED_BETA_MAX:
        raise InputError(f"paired (--paired) needs bodies without normal-tangential coupling (Dundurs' beta = 0, "
                         f"as for identical elastic constants: where MDR is exact under Mindlin's assumption), "
                         f"got beta = {materials.dundurs_beta:+.3g}")
    if options.displacement != "contact":
        raise InputError("paired (--paired) needs displacement 'contact' (the half-space comparable measure MDR uses), "
                         f"got {options.displacement!r}")
    if vtu is not None:
        raise InputError("paired (--paired) runs two laws in lockstep and writes no field file: leave out --vtu")


#: MDR's steps per cycle in :func:`paired_keys`, times the 3D runs': its time step's error (-0.06 % at 100
#: steps per cycle on the sphere) out of the answer, while the 3D runs' cancels in their ratio
PAIRED_MDR_STEP_FACTOR = 10

#: |Dundurs' beta| below which a pair counts as identical for :func:`check_paired` (round-off of
#: equal constants given as different numbers)
PAIRED_BETA_MAX = 1e-9


def paired_keys(free: dict, x: dict, mindlin: dict) -> dict:
    """The dissipation of the traction of free direction as the half-space answer: the MDR law's on
    the same loading (``mindlin``: exact in the half space under Mindlin's assumption, the traction
    along x, for Dundurs' beta = 0; run on ``PAIRED_MDR_STEP_FACTOR`` times the steps) times the ratio
    of the 3D run ``free`` to its twin ``x`` along x on the same mesh, their last cycles. A control
    variate: the twin's error against the exact answer is the error both runs share (the unstructured
    mesh's quantisation of the stick and contact edges, the bodies' finite size, the time step), and
    cancels in the ratio; what is left is the mesh's error of the direction effect itself (docs/fem3d.md:
    0.06 % across the ring meshes of the sphere at a/7), and the twin's error to second order.
    Keys: ``dissipation`` (J), ``direction_effect`` (free / x - 1), ``twin_dissipation``,
    ``mindlin_dissipation`` (J), ``twin_error`` (the twin against MDR: what the ratio removed); None
    where a run dissipated nothing or not a finite amount."""
    W, Wx, Wm = (float(r["dissipation"]) if r.get("dissipation") is not None else math.nan
                 for r in (free, x, mindlin))
    twin = math.isfinite(Wx) and math.isfinite(Wm) and Wx > 0 and Wm > 0
    ok = twin and math.isfinite(W)
    return {"dissipation": Wm * W / Wx if ok else None, "direction_effect": W / Wx - 1 if ok else None,
            "twin_dissipation": Wx if math.isfinite(Wx) else None,
            "mindlin_dissipation": Wm if math.isfinite(Wm) else None,
            "twin_error": Wx / Wm - 1 if twin else None}


#: |twin_error| beyond which :func:`paired_note` speaks: the twin that far from its exact answer means a
#: mesh that does not resolve the contact (measured on the sphere: 8.8 % at a/4 left -0.36 % in the
#: paired estimate, 2 % at a/5 -0.1 %), where the shared error cancels only to first order
PAIRED_TWIN_ERROR_NOTE = 0.1


def paired_note(paired: dict) -> str | None:
    """One line for the user where the twin is more than ``PAIRED_TWIN_ERROR_NOTE`` off its exact answer
    (or none could be formed), else None."""
    e = paired.get("twin_error")
    if e is not None and abs(e) <= PAIRED_TWIN_ERROR_NOTE:
        return None
    off = "an undetermined amount" if e is None else f"{abs(e):.0%}"
    return (f"the twin along x is {off} off MDR's exact answer: the mesh does not resolve the contact, and the "
            "paired estimate cancels a shared error only to first order; refine --h-contact")


def _run_3d(profile, materials, mu, loading, options: FEOptions, return_law, vtu=None, paired=False, log=None):
    import resource

    t0 = time.perf_counter()
    law = options.law(profile, materials, mu, loading.F_max)
    t1 = time.perf_counter()
    (log or (lambda msg: None))(f"set-up {t1 - t0:.1f} s ({law.model.n} vertices); the frictional normal loading "
                                f"of {with_normal_loading(loading).normal_steps} steps, then {loading.cycles} "
                                f"cycles of {loading.steps} steps"
                                + (" (and the paired run, its traction along x)" if paired else ""))
    if paired:
        out, out_x = drive_3d_together([law, law.assuming(traction="x")], loading, t_setup=t1 - t0)
        fine = replace(loading, steps=PAIRED_MDR_STEP_FACTOR * loading.steps)
        out["paired"] = paired_keys(out, out_x, run_mdr_contact(profile, materials, mu, fine))
        out["runtime_s"]["twin"] = out_x["runtime_s"]["cycles"]  # the twin's cycles, in the total
        out["runtime_s"]["total"] += out["runtime_s"]["twin"]
    elif vtu is None:
        out = drive_3d(law, loading, t_setup=t1 - t0)
    else:  # the contact fields at the drive's peak in the last cycle (fem.solid3d.output)
        from fem.solid3d.output import write_contact_vtu

        out, st = drive_3d(law, loading, t_setup=t1 - t0, state_at=loading.last_peak()[0])
        out["vtu"] = str(write_contact_vtu(law, st, vtu))
    out["peak_memory_bytes"] = int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) * 1024  # Linux: KiB
    return (out, law) if return_law else out


#: cycles run at a time past ``cycles`` while a 3D run settles (``drive_3d``'s ``settle``): the fewest
#: ``mdr.drive.run_contact`` runs (so a run may end one cycle past ``max_cycles``)
SETTLE_BLOCK = 2


def settled(W, tol, gross=0.0) -> bool:
    """Whether a run's dissipation per cycle ``W`` has settled: its last change at most ``tol`` of
    the last cycle's, or of ``HARDLY_DISSIPATES`` x ``gross`` (4 mu F0 u_A) where that is larger,
    and still contracting (``common.ladder.contracting``: a drift that no longer shrinks has not
    settled, unless below ``common.ladder.NEGLIGIBLE`` of the tolerance); an exactly repeating cycle,
    also of zero dissipation, has."""
    from common.ladder import NEGLIGIBLE, contracting

    if len(W) < 2:
        return False
    change, allowed = abs(W[-1] - W[-2]), tol * max(abs(W[-1]), HARDLY_DISSIPATES * gross)
    return change <= allowed and (contracting(W) or change <= NEGLIGIBLE * allowed)


def drive_3d(law, loading: Loading, *, t_setup=0.0, state_at=None, settle=None):
    """A fretting run of a built 3D law (``fem.solid3d.law.FEContact3D``) under ``loading`` (``Loading.of``):
    the normal load applied in the loading's ``normal_steps`` (``RAMP_STEPS`` where it states none:
    ``with_normal_loading``) with friction active (with coupling, slip during the normal loading locks
    traction into the stick zone, Spence 1975), then the cycles of ``mdr.drive.run_contact`` from that
    state (both there: ``mdr.drive.normal_loading``). Returns the result dict with the law's 3D keys (and
    the state at step
    ``state_at`` of the cycles if given); without ``state_at`` also ``per_cycle``, the stick-zone
    keys at every cycle's peak (``fem.solid3d.runs.cycle_keys``), beside ``dissipation_per_cycle``.
    ``settle`` = (tol, max_cycles): run on until the dissipation settles (``drive_3d_together``)."""
    if settle is not None and state_at is not None:
        raise ValueError("give at most one of state_at and settle")
    if state_at is None:
        return drive_3d_together([law], loading, t_setup=t_setup, settle=settle)[0]
    run = _Run3D(law, loading, t_setup)
    out, st_at = run.start(state_at=state_at)
    return run.finish(out), st_at


def drive_3d_together(laws, loading: Loading, *, t_setup=0.0, settle=None) -> list:
    """``drive_3d`` of several 3D laws in lockstep (the two runs of an effect, or a tilt sweep and
    its aligned face): every run the same cycles, so that their differences compare cycle by cycle.

    ``settle`` = (tol, max_cycles): after the loading's ``cycles``, all go on ``SETTLE_BLOCK`` cycles at a time
    until the dissipation of every run settles (``settled``: its last change at most ``tol`` of it,
    and contracting) or ``max_cycles`` have run. The 3D cycles settle over many cycles where
    Masing's rule fails at the mesh scale (the coupled steel/aluminium pair: by ~1e-3 per cycle
    after 4 cycles, then a tail at a ratio of ~0.9, ``docs/fem3d.md``). A continued run is the
    same history as one long run (every cycle starts at the same phase; ``tests/test_settling.py``).
    Each result's last-cycle keys are those of the last cycle run; ``cycles_run`` says how many,
    ``settled`` whether the tolerance was met (None without ``settle``)."""
    runs = [_Run3D(law, loading, t_setup) for law in laws]
    outs = [r.start() for r in runs]
    done = loading.cycles
    if settle is not None:
        tol, max_cycles = float(settle[0]), int(settle[1])
        while not all(r.settled(o, tol) for r, o in zip(runs, outs)) and done < max_cycles:
            outs = [r.more(o, SETTLE_BLOCK) for r, o in zip(runs, outs)]
            done += SETTLE_BLOCK
        for r, o in zip(runs, outs):
            o["settled"] = r.settled(o, tol)
    return [r.finish(o) for r, o in zip(runs, outs)]


class _Run3D:
    """One 3D run of ``drive_3d_together``: started, continued block by block, finished."""

    def __init__(self, law, loading, t_setup):
        loading = with_normal_loading(loading)
        self.law, self.loading, self.steps, self.t_setup = law, loading, loading.steps, t_setup
        self.elapsed = 0.0  # this run's own time (the runs of a lockstep interleave)

    def _run(self, loading, **kw):
        """``run_contact`` of this run's law; its history becomes ``self.history``."""
        return run_contact(self.law, loading, on_history=lambda H: setattr(self, "history", H), **kw)

    def start(self, state_at=None):
        t = time.perf_counter()
        law, ld = self.law, self.loading
        out, self.state = self._run(ld, state_at=state_at, return_state=state_at is None)  # its normal loading first
        self.per_cycle = runs.cycle_keys(law, self.history, self.steps) if state_at is None else None
        # the centres are taken at the first peak of F_x of the first run (the first loading)
        self.centres = runs.first_loading_keys(law, self.history)
        self.done = ld.cycles
        self.elapsed += time.perf_counter() - t
        return (out, self.state) if state_at is not None else out

    def settled(self, out, tol) -> bool:
        gross = gross_slip_work(self.law.mu, self.loading.F0, float(out["displacement_amplitude"]))
        return settled(out["dissipation_per_cycle"], tol, gross)

    def more(self, out, block) -> dict:
        """``block`` more cycles from the last state; the result of the whole history."""
        t = time.perf_counter()
        law = self.law
        nxt, self.state = self._run(replace(self.loading, cycles=block), state0=self.state, return_state=True)
        for k, v in runs.cycle_keys(law, self.history, self.steps).items():
            self.per_cycle[k] += v
        self.done += block
        self.elapsed += time.perf_counter() - t
        first = {k: out[k] for k in ("dissipation_first_cycle", "dissipation_open_path", "first_stationary_cycle")}
        return {**nxt, **first, "dissipation_per_cycle": list(out["dissipation_per_cycle"]) +
                list(nxt["dissipation_per_cycle"]), "inputs": {**nxt["inputs"], "cycles": self.done}}

    def finish(self, out) -> dict:
        out.update(self.law.result_keys(self.loading.F0, -self.t_setup, 0.0, self.elapsed, F_peak=self.loading.F_max))
        out.update(runs.window_keys(self.law, self.history))  # the last run's last cycle
        out.update(self.centres)
        if self.per_cycle is not None:  # one history: its cycles are the law's runs
            out["per_cycle"] = self.per_cycle
        out.setdefault("settled", None)
        out["cycles_run"] = self.done
        out["runtime_s"]["per_step"] = self.elapsed / (self.loading.normal_steps + self.done * self.steps)
        out["model"] = "3d"
        return out
