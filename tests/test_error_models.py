"""The calibrated error bounds of the pair scenes' ladders (``validation.error_models``).

Truth: a bound that claims to bound must contain the error where the answer is known. Here the answer is
the same model on a mesh (grid) far beyond the ladder (a/320; 12800 cells) and, on the closed-form anchor,
Hertz's contact radius and Cattaneo-Mindlin's stick radius; the scenes are held out of the calibration.
The rule itself (``common.ladder.modelled_error``) is checked on constructed ladders: a level that breaks
the bound refutes it, a missing level leaves the bar undetermined.
"""
from __future__ import annotations

import math

import pytest

from common.ladder import modelled_error
from validation import error_models as em


def _bound(C):
    return lambda h: C * h


def test_a_ladder_within_its_bound_is_calibrated_and_bounded():
    h = [1 / 20, 1 / 40, 1 / 80]
    q = [1.0 + 0.03 / 20, 1.0 - 0.05 / 40, 1.0 + 0.02 / 80]  # non-monotone, each within 0.1 h of 1
    lad = modelled_error(h, q, _bound(0.1))
    assert lad["status"] == "calibrated" and lad["bounded"]
    assert lad["error"] == pytest.approx(0.1 / 80) and lad["value"] == q[-1]
    # Richardson's bar where it is larger: an asymptotic ladder keeps its own, larger error
    mono = [1.0 + 0.08 / 20 ** 1, 1.0 + 0.08 / 40, 1.0 + 0.08 / 80]
    lad = modelled_error(h, mono, _bound(0.1))
    assert lad["bounded"] and lad["error"] >= 0.1 / 80


@pytest.mark.parametrize("k", [0, 1, 2])
def test_a_level_that_breaks_the_bound_refutes_it(k):
    h = [1 / 20, 1 / 40, 1 / 80]
    q = [1.0, 1.0, 1.0]
    q[k] += 3 * 0.1 * h[0]  # beyond the sum of any two levels' bounds
    lad = modelled_error(h, q, _bound(0.1))
    assert lad["status"] == "outside its calibrated bound" and not lad["bounded"]
    assert lad["error"] >= max(q) - min(q)


@pytest.mark.parametrize("k", [0, 1, 2])
def test_a_missing_level_leaves_it_undetermined(k):
    q = [1.0, 1.0, 1.0]
    q[k] = math.nan
    lad = modelled_error([1 / 20, 1 / 40, 1 / 80], q, _bound(0.1))
    assert lad["error"] is None and not lad["bounded"]


def test_the_classes_of_the_bounds():
    assert em.bound_class("sphere", 0.0, 3e-5) == "smooth"
    assert em.bound_class("truncated", 2e-5, 3e-5) == "smooth"       # kink at 0.67 a_ref
    assert em.bound_class("truncated", 3e-5, 3e-5) == "edge"          # kink at the edge
    assert em.bound_class("flat", 5e-5, 5e-5) is None                 # a fixed edge: Richardson bounds it
    assert em.bound_class("sphere", 0.0, 3e-5, gross_slip=True) == "gross"
    assert em.bound_class("truncated", 3e-5, 3e-5, gross_slip=True) == "edge"
    # gross slip at the compared instant: the stick radius exact, the traction (mu p) bounded far tighter
    # than where the stick edge quantises it; the rest (the loops and the dissipation integrate the partial
    # slip of each half-cycle) the smooth class's
    assert em.bound("fem", "stick_radius", "gross") is None
    for side in ("fem", "mdr"):
        assert em.bound(side, "traction_profile", "gross")(0.01) < 0.1 * em.bound(side, "traction_profile", "smooth")(0.01)
        for q in ("slip_index", "loop_du", "loop_Fx"):
            g, sm = em.bound(side, q, "gross"), em.bound(side, q, "smooth")
            assert (g.C, g.p) == (sm.C, sm.p), (side, q)
    assert em.bound("fem", "stick_radius", None) is None
    assert em.bound("fem", "contact_radius", "edge").C > 4 * em.bound("fem", "contact_radius", "smooth").C
    b = em.bound("fem", "stick_radius", "smooth")
    assert b(0.0125, scale=2.0) == pytest.approx(2.0 * b.C * 0.0125)


# the held-out scenes of the coverage test, per class. Smooth: the sphere in the Table 2 loading (not the
# closed-form load), the truncated sphere with its kink at 0.18 a (Table 2's loading) and the closed-form
# anchor itself. Gross slip (calibrated on exp-fig4 and app-kx2): the sphere in the apparatus of Fig. 5 and
# the truncated sphere in the stiffest but one apparatus (k_x = 10 N/um). Edge (calibrated on b = 30, 50,
# 100 um): the face b = 0.6 mm (the whole contact: its radii and slip index exact on every mesh) and a face
# b = 40 um, its kink just past the contact edge, where the radii and the slip index are quantised
HELD_OUT = {"geom-sphere": "smooth", "geom-b5um": "smooth", "sphere-md": "smooth",
            "exp-fig5": "gross", "app-kx10": "gross", "geom-b600um": "edge", "geom-b40um": "edge"}
#: element sizes (h_contact) measured: the catalogue's levels and sizes between them, where the edges
#: fall elsewhere in an element
FE_SIZES = tuple(1 / n for n in (20, 28, 34, 40, 56, 68, 80, 113))
MDR_SIZES = (100, 128, 200, 400, 512, 800, 1600)
#: the bounds' sharpness (``sharpness``), per side and class: twice the largest measured over the held-out
#: scenes' metrics. Measured: FE smooth 38 (the anchor's contact radius, whose sizes a/20, a/40, a/80 put
#: the edge on a node; the others 3.3-13), gross 81 (the loops of the stiff apparatus, whose bound is the
#: smooth class's), edge 21; MDR smooth 69, gross 344, edge 843 (MDR's errors at the finest grids are 1e-9
#: of the slip index)
SHARPNESS = {("fem", "smooth"): 80, ("fem", "gross"): 160, ("fem", "edge"): 45,
             ("mdr", "smooth"): 140, ("mdr", "gross"): 700, ("mdr", "edge"): 1700}


def _held_out(name):
    """A held-out scene: the catalogue's, or the face b = 40 um (geom-b50um's loading)."""
    import dataclasses

    from validation.catalogue import CATALOGUE

    if name == "geom-b40um":
        return dataclasses.replace(CATALOGUE["geom-b50um"], name=name, b=40e-6)
    return CATALOGUE[name]


def sharpness(sizes, errors, bnd, round_off=1e-12):
    """The median over the sizes of the bound over the largest error within a factor sqrt 2 of the size
    (the quantised errors swing by 10x between neighbouring meshes, so a single size's error says little),
    over the sizes where that error is above ``round_off``; None where none is (an exact metric)."""
    out = []
    for h in sizes:
        near = max(abs(e) for hh, e in zip(sizes, errors) if h / math.sqrt(2) <= hh <= h * math.sqrt(2))
        if near > round_off:
            out.append(bnd(h) / near)
    return sorted(out)[len(out) // 2] if out else None


@pytest.mark.slow
@pytest.mark.parametrize("side", ["fem", "mdr"])
@pytest.mark.parametrize("name", list(HELD_OUT))
def test_the_bounds_contain_the_error_on_held_out_scenes(name, side):
    """Every measured size's error against the reference (a/320, 12800 cells) lies within the bound, on
    scenes the calibration did not see (coverage 100 %; measured at most 0.88 of the bound, asserted 1);
    a metric without a bound is exact on that side; and the bounds are not loose beyond ``SHARPNESS``."""
    from validation.error_calibration import measure

    m = measure(_held_out(name), FE_SIZES if side == "fem" else MDR_SIZES, 1 / 320 if side == "fem" else 12800,
                side=side)
    cls = m["class"]
    assert cls == HELD_OUT[name]
    shares, sharp = {}, {}
    for q, v in m.items():
        if q in ("reference", "class"):
            continue
        b = em.bound(side, q, cls)
        if b is None:  # no bound: exact on this side (MDR's contact radius and pressure; gross slip's stick)
            assert max(abs(e) for e in v["errors"]) <= 1e-9, q
            continue
        share = [abs(e) / b(h) for h, e in zip(v["sizes"], v["errors"])]
        shares[q] = max(share)
        assert max(share) <= 1.0, (q, v["sizes"], v["errors"])
        sharp[q] = sharpness(v["sizes"], v["errors"], b)
        assert sharp[q] is None or sharp[q] <= SHARPNESS[(side, cls)], (q, sharp[q])
    print(name, side, cls, {q: round(x, 2) for q, x in shares.items()}, {q: x and round(x, 1) for q, x in sharp.items()})


@pytest.mark.slow
def test_the_anchor_bounds_contain_the_closed_forms():
    """On the closed-form anchor (Hertz, Cattaneo-Mindlin), the FE contact and stick radii at each
    catalogue level lie within the calibrated bound plus the bodies' own size effect (the reference
    mesh's distance to the closed form: the half-space's finite-body error, which the bound does not claim
    to hold) and MDR's within its bound."""
    from validation.catalogue import CATALOGUE
    from validation.sides import closed_forms, run_fe, run_mdr

    s = CATALOGUE["sphere-md"]
    cf = closed_forms(s)
    a = cf["contact_radius"]
    ref = run_fe(s, 1 / 320)[0]
    for q in ("contact_radius", "stick_radius"):
        body = abs(ref[q] - cf[q])
        assert body <= 1e-4 * a, q  # blocks of 200 a: the half-space within 1e-4 a
        for h in (1 / 20, 1 / 40, 1 / 80):
            fe = run_fe(s, h)[0]
            assert abs(fe[q] - cf[q]) <= em.bound("fem", q, "smooth")(h, scale=a) + body, (q, h)
        for n in (100, 400, 1600):
            md = run_mdr(s, n)
            bnd = em.bound("mdr", q, "smooth")
            assert abs(md[q] - cf[q]) <= (0.0 if bnd is None else bnd(1 / n, scale=a)) + 1e-9 * a, (q, n)


def test_the_errors_do_not_fall_with_the_mesh_so_no_size_only_bar_is_sharp_at_every_level():
    """The docs' reason why no bar is within about 5 times the error at every level: on the closed-form
    anchor the a/28 mesh puts the contact edge on a node and the finer a/34 mesh does not, so the contact
    radius's error against Hertz is far larger on the finer mesh (measured 99 times: 3.2e-5 a against
    3.2e-3 a; asserted 40). A bar that does not shrink as the mesh coarsens is then at least that many
    times the a/28 error. Both errors are far above round-off and within the calibrated bound (plus the
    bodies' own size effect, at most 1e-4 a: ``test_the_anchor_bounds_contain_the_closed_forms``)."""
    from validation.catalogue import CATALOGUE
    from validation.sides import closed_forms, run_fe

    s = CATALOGUE["sphere-md"]
    a = closed_forms(s)["contact_radius"]
    err = {n: abs(run_fe(s, 1 / n)[0]["contact_radius"] - a) / a for n in (28, 34)}
    assert err[34] > 40 * err[28] and err[28] > 1e-6, err
    for n, e in err.items():
        assert e <= em.bound("fem", "contact_radius", "smooth")(1 / n) + 1e-4, (n, e)
