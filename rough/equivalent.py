"""MDR against the rough half-space: one contact through three models side by side
(``mdr_against_rough``).

1. The rough half-space (``rough.normal`` + ``rough.tangential``): the indenter plus a height map
   pressed with F0, then force-controlled fretting cycles of amplitude fa with Coulomb friction cell by
   cell (Mindlin's assumptions: traction along x, no normal-tangential coupling).
2. MDR with the equivalent profile (``mdr.equivalent.EquivalentProfile``) of the rough contact's own
   normal force-approach curve: the axisymmetric body that has the rough contact's F(d).
3. MDR with the smooth profile: what the paper's model assumes.

Compared: the dissipation per stationary cycle and the initial tangential stiffness (the rough
half-space's first small force step, in full stick, over the pressure-weighted mean of the surfaces'
relative displacement without periodic images, ``halfspace_tangential_displacement``; MDR's 2 G* a,
Mindlin's stiffness of the contact radius, which for the equivalent profile is a(F0) = F'(d) / (2 E*)). On a smooth indenter all three
agree within the grid's error (``tests/test_rough_equivalent.py``); on a rough one the first two
differ by what the rough contact's non-axisymmetric, multiply connected stick and slip zones do that
no axisymmetric body does.
"""
from __future__ import annotations

import hashlib

import numpy as np

from common.errors import InputError, positive
from mdr.drive import run_mdr_contact
from mdr.equivalent import EquivalentProfile
from mdr.loading import Loading

from .normal import Grid, force_approach, normal_contact
from .surfaces import HeightMap
from .tangential import TangentialContact, halfspace_tangential_displacement, run_force_cycles

#: the forces of the normal curve, as fractions of F0: geometric (near first contact a ~ sqrt(d)) and
#: beyond F0, so that the contact radius at F0 is read inside the curve, not at its end (there the
#: one-sided derivative put the sphere's a 0.75 % high at a/8, its dissipation +4.6 %; inside: 0.04 %)
CURVE_FRACTIONS = np.geomspace(1e-2, 1.5, 24)
#: MDR runs at this many times the caller's steps per cycle: MDR's loop integral depends on them (-0.41 %
#: at 40 steps per cycle on the smooth sphere, -0.004 % at 400)
MDR_STEP_FACTOR = 10
#: the rough half-space's steps per cycle (a multiple of 4: its steps land on the peaks of Q): under a
#: constant pressure each cell slips one way per half cycle, so the friction work of its implicit steps
#: is exact at any number of them that lands on the peaks (the same at 8 and 40 steps within 1e-8 on the
#: smooth sphere and on rms 0.1 and 1 um surfaces, ``tests/test_rough_tangential.py``,
#: ``tests/test_rough_equivalent.py``): 8 costs a fifth of the caller's 40
HALFSPACE_STEPS = 8


#: ``flattened``'s last answers (key -> (heights, plastic area)): a rough member's models and its
#: apparatus runs flatten the same surface once (the capped solve on the grid is the costliest step)
_FLATTENED: dict = {}


def flattened(profile, materials, grid: Grid, heights: HeightMap | None, hardness: float, preload: float) -> tuple:
    """The heights after a first loading to ``preload`` (N) with perfectly plastic asperities of
    ``hardness`` (Pa; ``rough.normal.normal_contact``'s capped solve): the surface lowered by each plastic
    pixel's penetration, elastic from then on (elastic shakedown), and the plastic area of that loading
    (m^2). The last few answers are kept, keyed by every input (the heights by a digest of their
    bytes); a kept map is read-only."""
    preload, hardness = positive("preload", preload), positive("hardness", hardness)
    digest = None if heights is None else hashlib.blake2b(np.ascontiguousarray(heights.h).tobytes(),
                                                          digest_size=16).hexdigest()
    key = (repr(profile.describe()), repr(materials), grid, digest, None if heights is None else heights.pixel,
           float(hardness), float(preload))
    hit = _FLATTENED.get(key)
    if hit is not None:
        return hit
    plastic = normal_contact(profile, materials, preload, grid, heights, hardness=hardness)
    h = np.zeros((grid.n, grid.n)) if heights is None else heights.h
    flat = h - plastic["flattening"]
    flat.flags.writeable = False
    if len(_FLATTENED) >= 2:
        _FLATTENED.clear()
    _FLATTENED[key] = out = (HeightMap(flat, grid.pixel), plastic["plastic_area"])
    return out


def mdr_against_rough(profile, materials, mu, F0, fa, grid: Grid, heights: HeightMap | None = None, *,
                      cycles: int = 3, steps: int = 40, hardness: float | None = None,
                      preload: float | None = None) -> dict:
    """The three models of the module docstring at normal force F0 (N) and tangential force amplitude
    fa (N, below mu F0) on ``grid``: per model ``dissipation`` (J, the last cycle's) and
    ``stiffness`` (N/m); ``equivalent`` the MDR profile's description; ``relative``: each MDR model's
    dissipation and stiffness over the rough half-space's, minus 1 (None where the rough half-space's is 0); ``curve``: the rough half-space's
    normal force-approach samples (``d``, ``F``) the equivalent profile was built from; ``pressure``:
    its pressure at F0 ((n, n), Pa; a warm start for other solves on this surface). ``hardness``
    (Pa): the asperities perfectly plastic there (``rough.normal.saturated_pressure``), flattened by a
    first loading to ``preload`` (N, at least F0; default F0): the largest normal force the surface
    has seen. Everything after is elastic on the surface that loading left (``normal_contact``'s
    ``flattening``; elastic shakedown): fretting at a constant F0 unloads and reloads it elastically,
    and the curve is that surface's elastic one, which the first loading's, softer by the plastic
    flow, would not describe. At ``preload`` = F0 the elastic pressure at F0 is the capped one (to
    1e-8 H, ``tests/test_rough_normal.py``)."""
    F0, fa = positive("F0", F0), positive("fa", fa)
    if fa >= mu * F0:
        raise InputError(f"fa must stay below mu F0 = {mu * F0:.4g} N (force control), got {fa!r}")
    plastic_area = 0.0
    if hardness is not None:  # the first, plastic loading; the surface it leaves is elastic from then on
        preload = F0 if preload is None else positive("preload", preload)
        if preload < F0:
            raise InputError(f"preload must be at least F0 = {F0:.4g} N (the largest load the surface saw), "
                             f"got {preload!r}")
        heights, plastic_area = flattened(profile, materials, grid, heights, hardness, preload)
    elif preload is not None:
        raise InputError("preload needs a hardness (the load that flattened the asperities)")
    normal = normal_contact(profile, materials, F0, grid, heights)
    tc = TangentialContact(grid, materials, mu)
    hs = run_force_cycles(tc, normal["pressure"], fa, cycles=cycles, steps=HALFSPACE_STEPS)
    Q1 = fa * np.sin(2.0 * np.pi / steps)  # the first of the caller's steps: full stick
    first = tc.step(tc.rest_state(), normal["pressure"], Q1)
    u = halfspace_tangential_displacement(first.q, grid.pixel, materials)
    stick = normal["pressure"] > 0
    k_hs = Q1 / float(np.sum(u[stick] * normal["pressure"][stick]) / np.sum(normal["pressure"][stick]))
    d, F = force_approach(profile, materials, F0 * CURVE_FRACTIONS, grid, heights, start=(F0, normal["pressure"]))
    eq = EquivalentProfile(d, F, materials)
    loading = Loading.of(F0, fa=fa, cycles=cycles, steps=MDR_STEP_FACTOR * steps)
    out = {"rough_halfspace": {"dissipation": hs["dissipation"], "stiffness": float(k_hs),
                               "contact_area": normal["contact_area"], "approach": normal["approach"],
                               "plastic_area": plastic_area},
           "equivalent": eq.describe(), "curve": {"d": d.tolist(), "F": F.tolist()}, "pressure": normal["pressure"]}
    for name, prof in (("mdr_equivalent", eq), ("mdr_smooth", profile)):
        res = run_mdr_contact(prof, materials, mu, loading)
        out[name] = {"dissipation": res["dissipation"], "stiffness": 2.0 * materials.G_star * res["contact_radius"],
                     "contact_radius": res["contact_radius"]}
    ref = out["rough_halfspace"]
    # None where the rough half-space's own value is 0 (a contact sticking everywhere dissipates nothing)
    out["relative"] = {name: {k: out[name][k] / ref[k] - 1.0 if ref[k] > 0 else None
                              for k in ("dissipation", "stiffness")}
                       for name in ("mdr_equivalent", "mdr_smooth")}
    return out
