"""The budget's roughness over the admitted readings (validation.budget_readings).

Truths: MDR with the equivalent profile of the smooth sphere's own Hertz curve is the smooth sphere in the
apparatus (a 'reading' of such surfaces changes no slip index beyond the curve's sampling); a softer
contact (a Hertz curve of a lower modulus) lowers the slip index and moves the sticking transition up; the
range spans exactly the admitted readings; a range is graded 'matters' only where all of it lies beyond
the resolution on one side.
"""
from dataclasses import asdict

import numpy as np
import pytest

from mdr import reference as ref
from mdr.materials import Materials
from mdr.paper import R_INDENTER
from validation import budget_readings as BR
from validation import spectra as SP
from validation.paper_points import RESOLUTION, loop_point

MAT = Materials()


def _members(scale_by_reading, contact=SP.SPHERE, seeds=(0, 1, 2)):
    """Members whose curves are Hertz's for E* / scale (scale per reading index; 1: the smooth sphere)."""
    F = 0.5 * np.geomspace(1e-2, 1.5, 24)
    out = []
    for i, scale in scale_by_reading.items():
        for s in seeds:
            for n in contact.grids:
                k = scale * (1 + 0.02 * s)  # surfaces that differ a little
                d = [float(ref.hertz(f, R_INDENTER, MAT.E_star / k)["d"]) for f in F]
                out.append({"reading": i, "contact": asdict(contact), "seed": s, "n": n, "rms_window": 1e-6,
                            "form_curvature": 0.0, "curve": {"d": d, "F": F.tolist()}})
    return out


@pytest.mark.parametrize("fig", ["fig4", "fig5"])
def test_the_smooth_spheres_own_curve_is_no_roughness(fig):
    R = BR.Readings(_members({0: 1.0}, seeds=(0,)))
    p = loop_point(fig)
    from validation.paper_points import point_slip_index

    e = BR.reading_effect(R, 0.0, 0, p, point_slip_index(p), 0.0)
    assert e is None  # one surface per grid: no spread, no effect
    R = BR.Readings(_members({0: 1.0}, seeds=(0, 0)))
    e = BR.reading_effect(R, 0.0, 0, p, point_slip_index(p), 0.0)
    assert abs(e["effect"]) < 3e-3 and e["sampling"] < 3e-3 and e["surfaces_sd"] == 0.0


def test_the_range_spans_the_admitted_readings_and_grades_by_its_far_end():
    p = loop_point("fig5")
    R = BR.Readings(_members({0: 1.0, 1: 3.0, 2: 10.0}))
    names = [r.name for r in SP.READINGS]
    admitted = {"sphere": {names[0], names[1]}, "face": set()}
    c = BR.roughness_cell(p, R, admitted, 0.002)
    per = {k: v for k, v in c["readings"].items() if v is not None}
    assert set(per) == {names[0], names[1], names[2]} and c["admitted"] == sorted(admitted["sphere"])
    lo, hi = c["range"]
    for k in admitted["sphere"]:
        assert lo <= per[k]["effect"] <= hi
    assert per[names[2]]["effect"] < lo  # the stiffest exclusion is not in the range
    assert per[names[1]]["effect"] < per[names[0]]["effect"]  # softer: less slip in the apparatus
    assert c["verdict"] == BR.grade_range(lo, hi, c["error"])
    assert c["error"] >= max(v["surfaces_sd"] for v in per.values() if v is not None and v is not per[names[2]])
    # nothing admitted: undetermined, said so
    none = BR.roughness_cell(p, R, {"sphere": set(), "face": set()}, 0.002)
    assert none["verdict"] == "undetermined" and "excluded" in none["note"]


@pytest.mark.parametrize("lo,hi,err,verdict", [
    (-0.3, -0.1, 0.01, "matters"), (0.05, 0.2, 0.01, "matters"), (-0.3, 0.05, 0.01, "undetermined"),
    (-0.3, -0.005, 0.001, "undetermined"), (-0.004, 0.003, 0.005, "negligible"), (-0.004, 0.003, 0.007, "undetermined")])
def test_a_range_matters_only_where_all_of_it_lies_beyond_the_resolution(lo, hi, err, verdict):
    assert RESOLUTION == 0.01
    assert BR.grade_range(lo, hi, err) == verdict


def test_a_softer_contact_moves_the_sticking_transition_up():
    from dataclasses import replace

    from mdr.profiles import TruncatedSphere

    smooth = BR.sticking_transition(TruncatedSphere(R_INDENTER, 10e-6))
    assert smooth == pytest.approx(1.0e6, rel=0.05)  # docs/apparatus.md: 1.00 N/um
    soft = BR.sticking_transition(TruncatedSphere(R_INDENTER, 10e-6), replace(BR.Point(b=10e-6), ua=110e-9))
    assert soft > 1.2 * smooth  # less stroke: the contact must be stiffer-driven to slip
    R = BR.Readings(_members({0: 3.0}))
    t = BR.transitions(R, {"sphere": {SP.READINGS[0].name}})
    assert t["rows"][1]["kx"] > 1.2 * t["rows"][0]["kx"] and t["range"][0] < t["rows"][1]["kx"] < t["range"][1]


def test_the_equivalent_profiles_error_is_read_from_the_stored_rough_scenes():
    row = {"apparatus": [{"equivalent_minus_rough": {"mean": -0.003, "sem": 0.001}},
                         {"equivalent_minus_rough": {"mean": 0.002, "sem": 0.0005}}, {"equivalent_minus_rough": None}]}
    store = lambda name: {"roughness": [row]} if name == "roughness" else None  # noqa: E731
    assert BR.equivalent_error(store) == pytest.approx(0.004)
    assert BR.equivalent_error(lambda name: None) is None
    c = BR.roughness_cell(loop_point("fig4"), BR.Readings([]), {"sphere": set(), "face": set()}, None)
    assert c["verdict"] == "undetermined" and "roughness" in c["note"]


def test_the_spheres_form_beyond_its_grid_widens_the_range_as_a_curvature():
    """The form the sphere's grid leaves out enters as the sphere's curvature 1/R -+ 2 kappa: no form,
    no change; a flatter sphere (stiffer contact) slips more, a sharper one less; small kappa acts
    linearly (half the curvature, half the change, within 15 %); the cell's range holds the form."""
    p = loop_point("fig5")
    from validation.paper_points import point_slip_index

    smooth = point_slip_index(p)
    assert BR.form_effect(p, 0.0, smooth) == [0.0, 0.0]
    k = 0.05 / R_INDENTER
    lo, hi = BR.form_effect(p, k, smooth)
    lo2, hi2 = BR.form_effect(p, k / 2, smooth)
    assert lo < 0 < hi
    assert lo2 == pytest.approx(lo / 2, rel=0.15) and hi2 == pytest.approx(hi / 2, rel=0.15)
    names = [r.name for r in SP.READINGS]
    flat = BR.roughness_cell(p, BR.Readings(_members({0: 1.5}, seeds=(0, 1))), {"sphere": {names[0]}, "face": set()}, 0.0)
    members = _members({0: 1.5}, seeds=(0, 1))
    for m in members:
        m["form_curvature"] = k
    formed = BR.roughness_cell(p, BR.Readings(members), {"sphere": {names[0]}, "face": set()}, 0.0)
    e = flat["readings"][names[0]]["effect"]
    assert formed["range"] == pytest.approx([e + lo, e + hi], abs=1e-9)
    assert flat["range"] == pytest.approx([e, e], abs=1e-12)


def test_a_face_reading_beyond_its_grid_leaves_the_cell_undetermined():
    """On the face b = 50 um the ISO reading leaves most of its variance beyond the grid of 4 radii: it is
    not run and, admitted, leaves the cell undetermined whatever the resolved readings say."""
    from validation.paper_points import Point

    c = SP.face(50e-6)
    names = [r.name for r in SP.READINGS]
    assert not SP.resolved(SP.READINGS[0], c) and SP.form_share(SP.READINGS[0], c) > 0.5
    assert SP.resolved(SP.READINGS[4], c) and SP.form_share(SP.READINGS[4], c) == 0.0
    assert not any(t["reading"] == 0 for t in SP.tasks([c]))
    # docs/budget.md: the ISO readings leave 74-98 % beyond the grids of b = 50 and 100 um, 3-5 % beyond 0.6 mm's
    iso = [i for i, r in enumerate(SP.READINGS) if r.rolloff is None]
    small = [SP.form_share(SP.READINGS[i], SP.face(b)) for i in iso for b in (50e-6, 100e-6)]
    assert 0.72 < min(small) and max(small) < 0.99
    wide = [SP.form_share(SP.READINGS[i], SP.face(600e-6)) for i in iso]
    assert 0.02 < min(wide) and max(wide) < 0.06 < SP.FORM_SHARE_MAX
    p = Point(b=50e-6)
    R = BR.Readings(_members({4: 10.0}, contact=c, seeds=(0, 1)))
    alone = BR.roughness_cell(p, R, {"sphere": set(), "face": {names[4]}}, 0.0)
    assert alone["verdict"] == "matters"
    both = BR.roughness_cell(p, R, {"sphere": set(), "face": {names[0], names[4]}}, 0.0)
    assert both["verdict"] == "undetermined" and both["unresolved"] == [names[0]] and "beyond the grid" in both["note"]
    assert both["range"] == alone["range"]


def test_readings_that_coincide_on_a_contact_are_run_once():
    """On the face b = 1 mm the grid (4 mm) is longer than ISO's lambda_c (2.5 mm): waviness that ends at 8 a
    is the ISO band's, the same generated map; on the sphere (8 a = 0.22 mm) it is not."""
    from rough.surfaces import generate

    big = SP.face(1e-3)
    assert SP.canonical(3, big) == 0 and SP.canonical(6, big) == 5 and SP.canonical(3, SP.SPHERE) == 3
    h0, h3 = (generate(SP.params(SP.READINGS[i], big, 1)[0]).h for i in (0, 3))
    assert np.allclose(h0, h3, rtol=0, atol=1e-12 * np.abs(h0).max())
    s0, s3 = (generate(SP.params(SP.READINGS[i], SP.SPHERE, 1)[0]).h for i in (0, 3))
    assert not np.allclose(s0, s3, atol=0.1 * np.abs(s0).std())
    tasks = SP.tasks([big])
    assert {t["reading"] for t in tasks} == {0, 1, 2, 4, 5, 7}
    # docs/speed.md: 176 surfaces over the budget's five contacts (320 with every reading everywhere)
    assert len(SP.tasks(BR.contacts())) == 176 and len(SP.READINGS) * 4 * 2 * len(BR.contacts()) == 320


def test_the_loops_check_each_surface_once_in_any_number_of_processes():
    """consistency: the same rows from one process and from two; a reading that coincides with another
    on a contact shares its surfaces' checks (the same objects' results)."""
    members = _members({0: 1.0}, seeds=(0, 1))
    one = BR.consistency(BR.Readings(members), jobs=1)
    two = BR.consistency(BR.Readings(members), jobs=2)
    assert one == two
    iso = one["sphere"][0]
    assert iso["reading"] == SP.READINGS[0].name and len(iso["surfaces"]) == 2 and iso["admitted"]
    assert all(not r["surfaces"] for r in one["face"])  # no face member given: nothing checked


def test_the_sphere_form_widens_the_sticking_transition_range():
    """The form beyond the sphere's grid moves the transition as it moves the smooth sphere's at
    1/R -+ 2 kappa: a flatter sphere (stiffer contact) sticks at a lower k_x; the range over the admitted
    readings holds those factors (without form, the factors are 1 and the range is means -+ sd)."""
    from mdr.profiles import TruncatedSphere

    smooth = BR.sticking_transition(TruncatedSphere(R_INDENTER, 0.0))
    lo, hi = BR.form_factors(0.15 / R_INDENTER, smooth)
    assert lo < 1.0 < hi and BR.form_factors(0.0, smooth) == [1.0, 1.0]
    members = _members({0: 3.0})
    plain = BR.transitions(BR.Readings(members), {"sphere": {SP.READINGS[0].name}})
    for m in members:
        m["form_curvature"] = 0.15 / R_INDENTER
    formed = BR.transitions(BR.Readings(members), {"sphere": {SP.READINGS[0].name}})
    assert formed["range"][0] == pytest.approx(plain["range"][0] * lo, rel=1e-9)
    assert formed["range"][1] == pytest.approx(plain["range"][1] * hi, rel=1e-9)
