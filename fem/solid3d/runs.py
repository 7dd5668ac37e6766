"""The 3D keys read from a run: pure functions of a 3D law (its model, friction and tilt) and the
``mdr.law.History`` of one of its runs, whose ``fields`` hold the vertex tractions ``q`` and
pressures ``p`` of every step (``FEContact3D.run``). Nothing here is kept in the law: the history
a caller holds is the only record of a run.
"""
from __future__ import annotations

import numpy as np

from mdr.law import History

from fem.solid3d import estimators as est
from fem.solid3d.contact import WHOLE

#: the stick-zone keys of :func:`cycle_keys`: those :func:`window_keys` reports at the last cycle's peak
CYCLE_KEYS = ("stick_radius_x", "stick_radius_y", "stick_axis_x", "stick_axis_y", "traction_angle_max")
#: the keys :func:`window_keys` reports (``fem.solid3d.estimators.stick_zone``)
WINDOW_KEYS = ("stick_radius_x", "stick_radius_y", "stick_axis_x", "stick_axis_y", "stick_axis_quantum",
               "stick_fit_x", "stick_fit_y", "traction_angle_max")


def _recorded(H: History) -> bool:
    return H is not None and H.fields is not None and len(H.fields["q"]) > 0


def _zone(law, H: History, k: int) -> dict:
    return law.stick_zone(np.asarray(H.fields["q"][k]), np.asarray(H.fields["p"][k]), float(H.a[k]))


def window_peak(H: History) -> int:
    """The step of the peak of F_x in the history's recorded window (``record_from``: the last cycle;
    the whole history where it recorded none)."""
    Fx = np.asarray(H.Fx)
    first = Fx.size - (H.slack.shape[-2] if H.slack is not None else 0)
    k0 = first if first < Fx.size else 0
    return k0 + int(np.argmax(Fx[k0:]))


def window_keys(law, H: History) -> dict:
    """``WINDOW_KEYS`` of the stick zone at the peak of F_x of the recorded window (the last cycle);
    empty where the history kept no fields."""
    if not _recorded(H):
        return {}
    z = _zone(law, H, window_peak(H))
    return {key: z[key] for key in WINDOW_KEYS}


def first_loading_keys(law, H: History) -> dict:
    """``stick_center_x`` and ``pressure_center_x`` at the history's first peak of F_x (its first
    loading; without one, the peak of its recorded window); empty where it kept no fields."""
    if not _recorded(H):
        return {}
    Fx = np.asarray(H.Fx)
    peaks = np.flatnonzero((Fx[1:-1] >= Fx[:-2]) & (Fx[1:-1] > Fx[2:]) & (Fx[1:-1] > 0)) + 1
    k1 = int(peaks[0]) if peaks.size else window_peak(H)
    z1 = _zone(law, H, k1)
    return {"stick_center_x": z1["stick_center_x"], "pressure_center_x": z1["pressure_center_x"]}


def cycle_keys(law, H: History, steps: int) -> dict:
    """``CYCLE_KEYS`` at the peak of F_x of every full cycle of the history (cycles of ``steps`` steps
    from its first sample; a run from rest or from the normal ramp's state), lists over the cycles
    (None where not finite): how the last cycle's values of :func:`window_keys` settled
    (``common.ladder.settling_error``). Empty where the history kept no fields."""
    if not _recorded(H):
        return {}
    Fx = np.asarray(H.Fx)
    out = {key: [] for key in CYCLE_KEYS}
    for k in range((Fx.size - 1) // int(steps)):
        j = k * steps + int(np.argmax(Fx[k * steps:(k + 1) * steps + 1]))
        z = _zone(law, H, j)
        for key in out:
            out[key].append(None if not np.isfinite(z[key]) else float(z[key]))
    return out


def law_keys(law, F_N, t0, t1, t2, F_peak=None) -> dict:
    """The keys of a 3D law that need no run (``FEContact3D.result_keys``, ``python -m fem contact
    --model 3d``): the FE's own contact radius and approach at F_N without tangential traction (for a
    dissimilar pair the run's coupled steps differ slightly: see ``pressure_center_x``),
    ``pressure_radius`` (``fem.solid3d.estimators``) and ``indentation`` there, ``bulk_compliance``
    (``plate_bulk_compliance`` at F_N), ``dofs``, ``vertices``, ``beta``, ``mesh``, ``solver``,
    ``runtime_s`` (setup, cycles, total from the times t0 < t1 < t2, and of the set-up the
    factorisation and the condensation: ``Model3D.timings``); and :func:`tilt_keys` at the peak
    normal force ``F_peak`` (default F_N)."""
    m = law.model
    nr = law.normal(F_N=F_N)
    out = {"contact_radius": nr.contact_radius, "pressure_radius": est.pressure_radius(m, nr.p),
           "approach": nr.approach, "indentation": law.indentation(nr),
           "bulk_compliance": law.plate_bulk_compliance(F_N), "displacement": m.displacement,
           "traction": law.traction, "coupling": law.coupling, "dofs": m.ndofs, "vertices": m.n,
           "beta": m.beta, "mesh": law.mesh_summary(), "solver": {"backend": m.backend, **law.stats},
           "runtime_s": {"setup": t1 - t0, "cycles": t2 - t1, "total": t2 - t0,
                         **{k: m.timings[k] for k in ("factorisation", "condensation")}}}
    out.update(tilt_keys(law, F_N if F_peak is None else F_peak))
    return out


def tilt_keys(law, F_N) -> dict:
    """``tilt``, ``contact_area_fraction``, ``contact_x_min``, ``contact_x_max`` at the normal force F_N
    without tangential traction: the contact area (``fem.solid3d.estimators``) over that of the punch
    face (pi b^2 up to the faceting of the meshed rim) for the flat punch, over the aligned contact's
    for a sphere or truncated sphere (the same estimator); the contact's extent along the symmetry
    plane."""
    m = law.model
    nr = law.normal(F_N=F_N)
    ref = float(WHOLE * m.mi.A.sum()) if m.flat else est.contact_area(m, law.normal(F_N=F_N, aligned=True).p)
    x0, x1 = est.contact_extent_x(m, nr.p)
    return {"tilt": law.tilt, "contact_area_fraction": est.contact_area(m, nr.p) / ref,
            "contact_x_min": x0, "contact_x_max": x1}
