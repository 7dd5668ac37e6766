"""One FE fretting run with the contact driven directly: ``python -m fem contact``.

The FE law (``fem.law.FEContact``) is driven by ``mdr.drive.run_contact``, the
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
indentation of ``fem.normal``), ``approach`` the plate approach.
"""
from __future__ import annotations

import time

from mdr.drive import check_loading, run_contact
from mdr.errors import InputError, in_range
from meshes.axisym import H_CONTACT_DEFAULT, H_CONTACT_RANGE

from .friction import DEFAULT_FRICTION_AL_TOL
from .law import FEContact
from .normal import DEFAULT_AL_TOL, DEFAULT_PENALTY


def run_fem_contact(profile, materials, mu, F0, dF=0.0, alpha=0.0, ua=None, fa=None, cycles=3, steps=400, *,
                    h_contact=H_CONTACT_DEFAULT, contact_extent=None, block_size=None, penalty=DEFAULT_PENALTY,
                    al_tol=DEFAULT_AL_TOL, friction_al_tol=DEFAULT_FRICTION_AL_TOL, cache_dir=None,
                    backend=None, displacement="contact", return_law=False, model="axisym", traction=None,
                    tilt=0.0, ring=None):
    """FE fretting run; returns the result dict (and the law if ``return_law``). ``model``:
    ``"axisym"`` (``fem.law.FEContact``) or ``"3d"`` (``fem.law3d.FEContact3D``: exact contact
    constraints, so ``penalty``, ``al_tol`` and ``friction_al_tol`` do not apply; ``h_contact``
    in the 3D range; ``traction`` the 3D law's, ``fem.law3d.TRACTIONS``; ``tilt`` of the flat
    face, rad; ``ring`` (r, width, h) / a_ref, the 3D mesh's refined ring, ``fem.law3d.FEContact3D``).
    ``contact_extent`` None: 1.25 (the flat punch of the 3D model: its face, 1)."""
    check_loading(F0, dF, alpha, mu, ua, fa, cycles, steps)  # validate before the costly set-up
    if model == "3d":
        return _run_3d(profile, materials, mu, F0, dF, alpha, ua, fa, cycles, steps, h_contact=h_contact,
                       contact_extent=contact_extent, block_size=block_size, cache_dir=cache_dir, backend=backend,
                       displacement=displacement, return_law=return_law, traction=traction or "free", tilt=tilt,
                       ring=ring)
    if ring is not None:
        raise InputError("ring (the refined ring of the mesh) applies to the 3D model only")
    if traction is not None:
        raise InputError("traction applies to the 3D model only")
    if model != "axisym":
        raise InputError(f"model must be 'axisym' or '3d', got {model!r}")
    if tilt != 0:
        raise InputError(f"tilt is a parameter of the 3D model only (--model 3d), got tilt={tilt!r}")
    contact_extent = 1.25 if contact_extent is None else contact_extent
    in_range("h_contact", h_contact, *H_CONTACT_RANGE)
    t0 = time.perf_counter()
    law = FEContact(profile, materials, mu, F_max=F0 + dF, h_contact=h_contact, contact_extent=contact_extent,
                    block_size=block_size, penalty=penalty, al_tol=al_tol, friction_al_tol=friction_al_tol,
                    cache_dir=cache_dir, backend=backend, displacement=displacement)
    t1 = time.perf_counter()
    out = run_contact(profile, materials, mu, F0, dF, alpha, ua=ua, fa=fa, cycles=cycles, steps=steps, law=law)
    t2 = time.perf_counter()
    out.update(law.result_keys(F0, t0, t1, t2))  # the FE's own contact radius and indentation at F0, ...
    out["approach"] = law.normal(F_N=F0).approach
    out["displacement"] = law.displacement
    out["bulk_compliance"] = law.plate_bulk_compliance(F0)
    if return_law:
        return out, law
    return out


#: steps of the frictional normal loading before the cycles of a 3D run
RAMP_STEPS = 20


def _run_3d(profile, materials, mu, F0, dF, alpha, ua, fa, cycles, steps, *, h_contact, contact_extent, block_size,
            cache_dir, backend, displacement, return_law, traction, tilt, ring=None):
    import resource

    from .law3d import FEContact3D

    t0 = time.perf_counter()
    law = FEContact3D(profile, materials, mu, F_max=F0 + dF, h_contact=h_contact, contact_extent=contact_extent,
                      block_size=block_size, cache_dir=cache_dir, backend=backend, displacement=displacement,
                      traction=traction, tilt=tilt, ring=ring)
    t1 = time.perf_counter()
    out = drive_3d(law, mu, F0, dF, alpha, ua, fa, cycles, steps, t_setup=t1 - t0)
    out["peak_memory_bytes"] = int(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss) * 1024  # Linux: KiB
    return (out, law) if return_law else out


def drive_3d(law, mu, F0, dF, alpha, ua, fa, cycles, steps, *, t_setup=0.0, state_at=None):
    """A fretting run of a built 3D law (``fem.law3d.FEContact3D``): the normal load applied in
    ``RAMP_STEPS`` steps with friction active (with coupling, slip during the normal loading locks
    traction into the stick zone, Spence 1975), then the cycles of ``mdr.drive.run_contact`` from
    that state. Returns the result dict with the law's 3D keys (and the state at step
    ``state_at`` of the cycles if given)."""
    import numpy as np

    t1 = time.perf_counter()
    st = law.rest_state()
    for f in np.arange(1, RAMP_STEPS + 1) / RAMP_STEPS * (F0 + dF * np.sin(alpha)):
        _, st = law.step(st, Fx=0.0, F_N=f)
    res = run_contact(law.profile, law.materials, mu, F0, dF, alpha, ua=ua, fa=fa, cycles=cycles, steps=steps,
                      law=law, state0=st, state_at=state_at)
    out, st_at = res if state_at is not None else (res, None)
    t2 = time.perf_counter()
    out.update(law.result_keys(F0, t1 - t_setup, t1, t2, F_peak=F0 + abs(dF)))
    out["normal_ramp_steps"] = RAMP_STEPS
    out["runtime_s"]["per_step"] = (t2 - t1) / (RAMP_STEPS + cycles * steps)  # the mean, ramp included
    out["model"] = "3d"
    return (out, st_at) if state_at is not None else out
