"""The error budget of the paper's model (validation.budget).

Truths: the verdict rule (a bound never "matters", a non-finite number is undetermined); exact zeros
where the physics has them (no kink on the sphere, a tilted sphere is the sphere, identical steels do
not couple); MDR with the equivalent profile of the smooth sphere's own Hertz curve is the smooth sphere
in the apparatus (its "roughness" is zero); the fillet's effect vanishes with its width; the sticking
transition of the smooth sphere where docs/apparatus.md measures it (delta = 0.1 at 1.0 N/um for the
sphere-like b = 10 um), moved by a softer contact; missing scenes name the command that runs them.
"""
import math
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from mdr import reference as ref
from mdr.materials import Materials
from mdr.paper import R_INDENTER
from validation import budget as B
from validation.points import loop_point

MAT = Materials()


@pytest.mark.parametrize("effect,error,kind,verdict", [
    (0.004, 0.005, "measured", "negligible"), (0.02, 0.005, "measured", "matters"),
    (0.012, 0.005, "measured", "undetermined"), (0.02, 0.0, "bound", "undetermined"),
    (0.004, 0.0, "bound", "negligible"), (float("nan"), 0.0, "measured", "undetermined"),
    (None, None, "measured", "undetermined"), (0.02, float("inf"), "spread", "undetermined")])
def test_the_verdict_rule(effect, error, kind, verdict):
    assert B.cell(effect, error, kind, "x")["verdict"] == verdict


def test_a_result_matters_if_one_point_does_and_is_negligible_only_if_all_are():
    small, big, gap = B.cell(0.001, 0.001, "measured", "a"), B.cell(0.05, 0.001, "measured", "b"), B.missing("tilt")
    assert B.combine([small, big, gap], "x")["verdict"] == "matters"
    assert B.combine([small, gap], "x")["verdict"] == "undetermined"
    assert B.combine([small, small], "x")["verdict"] == "negligible"
    assert "python -m validation.compare --scenes tilt" in gap["source"]
    # the cell shown is the one that decides: a point that matters, not a larger but uncertain one
    vague = B.cell(-0.2, 0.25, "measured", "c")
    shown = B.combine([vague, big], "x")
    assert shown["verdict"] == "matters" and shown["effect"] == 0.05
    assert B.combine([vague, small], "x")["effect"] == -0.2  # undetermined: the largest bound


def test_exact_zeros_on_the_sphere():
    p = loop_point("fig4")
    assert p.b == 0
    for c in (B.kink_cell(p), B.tilt_cell(p, lambda name: None)):
        assert c["effect"] == 0.0 and c["kind"] == "exact" and c["verdict"] == "negligible"


def test_the_fillet_costs_less_as_it_narrows_and_nothing_on_the_wide_face():
    p = loop_point("fig6")
    wide = B.kink_cell(p)
    assert abs(wide["effect"]) < 1e-3  # b = 0.6 mm: the fillet is 0.5 % of the radius (measured 1.6e-5)
    assert wide["verdict"] == "negligible"
    q = B.Point(b=20e-6)
    e3 = B.kink_cell(q)["effect"]
    old = B.FILLET_MAX
    try:
        B.FILLET_MAX = 0.5e-6
        e05 = B.kink_cell(q)["effect"]
    finally:
        B.FILLET_MAX = old
    assert abs(e05) < abs(e3)


def _hertz_row(rms, members=3, radius=R_INDENTER, **extra):
    """A stored roughness row whose 'rough' curves are a smooth sphere's own (Hertz, of ``radius``) and
    whose equivalent MDR matched the half-space exactly."""
    F = 0.5 * np.geomspace(1e-2, 1.5, 24)
    d = np.array([float(ref.hertz(f, radius, MAT.E_star)["d"]) for f in F])
    curve = {"d": d.tolist(), "F": F.tolist()}
    return {"rms": rms, "seeds": list(range(members)), "grids": [128, 256], "period": 16 * 27e-6,
            "verdicts": {"mdr_equivalent:dissipation": {"difference": 0.0, "error": 0.0}},
            "curves": [curve] * members, "curves_by_grid": {"128": [curve] * members, "256": [curve] * members},
            **extra}


def _hertz_store(rms, members=3):
    row = _hertz_row(rms, members)
    return lambda name: {"roughness": [row]} if name == "roughness" else None


def test_the_plastic_column_reads_the_plastic_surfaces_within_their_flattening_load():
    """The elastic and the plastic rough rows are told apart (the plastic one here: the curves of a sphere
    of 4 R, a flattened, stiffer contact); a point loaded beyond the plastic row's flattening load would
    flatten it further: undetermined."""
    rows = [_hertz_row(1e-6), _hertz_row(1e-6, radius=4 * R_INDENTER, hardness=2.1e9, preload=0.75)]
    store = lambda name: {"roughness": rows} if name == "roughness" else None  # noqa: E731
    p = loop_point("fig4")
    elastic, plastic = B.roughness_cell(p, store, 1e-6), B.roughness_cell(p, store, 1e-6, plastic=True)
    assert abs(elastic["effect"]) < 2e-3
    assert abs(plastic["effect"]) > B.RESOLUTION and plastic["verdict"] == "matters"  # another curve, counted
    rows[1]["preload"] = 0.9 * (p.F0 + p.dF)
    assert B.roughness_cell(p, store, 1e-6, plastic=True)["verdict"] == "undetermined"
    assert B.roughness_cell(p, store, 1e-6)["verdict"] == "negligible"


def test_the_equivalent_profile_of_a_smooth_sphere_is_no_roughness_in_the_apparatus():
    for p in (loop_point("fig4"), loop_point("fig5")):
        c = B.roughness_cell(p, _hertz_store(1e-6), 1e-6)
        assert abs(c["effect"]) < 2e-3 and c["verdict"] == "negligible"  # the curve's sampling: 24 forces


def test_a_softer_contact_moves_the_sticking_transition_up():
    from mdr.profiles import TruncatedSphere

    smooth = B.sticking_transition(TruncatedSphere(R_INDENTER, 10e-6))
    assert smooth == pytest.approx(1.0e6, rel=0.05)  # docs/apparatus.md: 1.00 N/um
    soft = B.sticking_transition(TruncatedSphere(R_INDENTER, 10e-6), replace(B.Point(b=10e-6), ua=110e-9))
    assert soft > 1.2 * smooth  # less stroke: the contact must be stiffer-driven to slip


def test_missing_scenes_are_undetermined_and_name_their_command():
    b = B.budget("/nonexistent", mdr_cells=False)
    for r in b["rows"]:
        for col in ("size", "curvature", "direction", "roughness"):
            c = r["cells"][col]
            if c["effect"] is None:
                assert c["verdict"] == "undetermined"
        assert r["cells"]["coupling"]["effect"] == 0.0
    assert B.markdown(b)  # renders


def test_the_command_refuses_a_folder_without_scenes_in_one_line(tmp_path):
    r = subprocess.run([sys.executable, "-m", "validation.budget", "--out", str(tmp_path)], capture_output=True,
                       text=True)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "--out" in r.stderr
    assert not (tmp_path / "budget.md").exists()


def test_scaled_turns_a_relative_effect_into_a_slip_index_change():
    c = B.scaled(B.cell(0.1, 0.01, "measured", "x"), 0.5)
    assert c["effect"] == pytest.approx(0.05) and c["error"] == pytest.approx(0.005) and c["verdict"] == "matters"
    a = B.cell(0.02, 0.001, "absolute", "x")
    assert B.scaled(a, 0.5) is a
    assert math.isclose(B.scaled(B.cell(0.1, 0.01, "bound", "x"), 0.05)["effect"], 0.005)


def _pair_result(fe, md, err=1e-4, bounded=True):
    return {"verdicts": {"slip_index": {"fem": fe, "mdr": md, "fem_error": err, "mdr_error": err,
                                         "bounded": bounded}}, "fem": {"contact_radius": 0.6e-3}}


def test_the_curvature_is_measured_at_the_point_where_a_scene_runs_it():
    """A point that a stored apparatus scene runs (the experiment of Fig. 6; a row of halfspace-points)
    takes its FE - MDR there, a change of the slip index; an injected 0.05 between the models matters;
    a non-finite one falls back to the sphere's bound (here: its scene missing, undetermined)."""
    from validation.scenes import CATALOGUE

    p6, p2 = loop_point("fig6"), B.Point(b=10e-6)
    i = next(i for i, v in enumerate(CATALOGUE["halfspace-points"].variants) if B.Point(**v) == p2)
    rows = [{"variant": i, "b": 10e-6, "kx": p2.kx, "slip_index_fem": 0.4221, "slip_index_mdr": 0.4224,
             "error": 6e-4, "bounded": False, "a_over_R": 0.0046}]
    stored = {"exp-fig6": _pair_result(0.5312, 0.5315), "halfspace-points": {"points": rows}}
    c = B.curvature_cell(p6, stored.get)
    assert c["source"] == "exp-fig6" and c["kind"] == "absolute" and c["verdict"] == "negligible"
    assert c["effect"] == pytest.approx(-3e-4) and c["error"] == pytest.approx(2e-4)
    c = B.curvature_cell(p2, stored.get)
    assert c["source"] == "halfspace-points" and c["verdict"] == "negligible" and "spread" in c["note"]
    stored["exp-fig6"] = _pair_result(0.5312, 0.5812)
    assert B.curvature_cell(p6, stored.get)["verdict"] == "matters"
    stored["exp-fig6"] = _pair_result(float("nan"), 0.5315)
    c = B.curvature_cell(p6, stored.get)
    assert c["verdict"] == "undetermined" and "validity-curvature" in c["source"]
    assert B.curvature_cell(replace(p2, kx=5e6), stored.get)["source"] != "halfspace-points"  # not that point


def test_every_point_with_a_face_has_a_scene_that_runs_it_in_the_apparatus():
    """The budget's curvature column is measured, not bounded, at every point of a truncated sphere: each
    is run by an apparatus scene of the catalogue (experiments, k_x series, halfspace-points)."""
    from validation.families.points import point_variant
    from validation.scenes import CATALOGUE

    hs = CATALOGUE["halfspace-points"]
    runs = [s for s in CATALOGUE.values() if s.family == "pair" and s.drive == "apparatus"]
    runs += [point_variant(hs, v) for v in hs.variants]
    for r in B.results():
        for p in r.points:
            n = sum(p.matches(s) for s in runs)
            assert n == 1 or (p.b == 0 and n <= 1), (r.key, p, n)


def test_the_direction_is_measured_at_the_point_where_a_3d_scene_runs_it():
    """A point that the stored 3D scene direction-points runs takes its free - along x there, a change of
    the slip index; an injected 0.05 matters; without the scene the force-control row of assumptions-3d
    is read (here missing: undetermined)."""
    from validation.scenes import CATALOGUE

    s = CATALOGUE["direction-points"]
    p = loop_point("fig6")
    i = next(i for i, v in enumerate(s.variants) if B.Point(**v) == p)
    row = {"variant": i, "effect": 3e-7, "error": 2e-7, "ladder_status": "two levels"}
    stored = {"direction-points": {"points": [row]}}
    c = B.direction_cell(p, stored.get)
    assert c["source"] == "direction-points" and c["kind"] == "absolute" and c["verdict"] == "negligible"
    row["effect"] = 0.05
    assert B.direction_cell(p, stored.get)["verdict"] == "matters"
    c = B.direction_cell(loop_point("fig7"), stored.get)  # another point: not this row
    assert c["source"] != "direction-points" and c["verdict"] == "undetermined"



def _face_row(b, rms=1e-6, members=3, **extra):
    """A stored rough-face row whose 'rough' curves are the smooth truncated sphere's own F_N(d) (MDR's
    normal solution of the face b, exact for the axisymmetric body) and whose equivalent MDR matched the
    half-space exactly."""
    from mdr.normal import approach_from_force
    from mdr.profiles import TruncatedSphere

    F = 0.5 * np.geomspace(1e-2, 1.5, 24)
    d = np.asarray(approach_from_force(TruncatedSphere(R_INDENTER, b), MAT, F), dtype=float)
    curve = {"d": d.tolist(), "F": F.tolist()}
    return {**_hertz_row(rms, members), "b": b, "period": 4 * b,
            "curves": [curve] * members, "curves_by_grid": {"128": [curve] * members, "256": [curve] * members},
            **extra}


def test_a_face_reads_the_rough_row_of_its_own_b_against_its_own_smooth_face():
    """The points of a face wider than the sphere's contact (Figs. 6-7: b = 0.6 mm) read scene
    roughness-faces at their own b, against the smooth truncated sphere: the smooth face's own normal
    curve is no roughness (within the 24 forces' sampling); the sphere's curve on that face's row is a far
    softer contact, which matters; a face without a row, or without the scene, is undetermined and says
    why; the sphere-like b = 10 um still reads the sphere's scene."""
    p = loop_point("fig6")
    rows = [_face_row(p.b)]
    store = lambda name: {"roughness": rows} if name == B.ROUGH_FACES else None  # noqa: E731
    c = B.roughness_cell(p, store, 1e-6)
    assert abs(c["effect"]) < 2e-3 and c["verdict"] == "negligible" and "b = 600 um" in c["note"]
    sphere_curve = _hertz_row(1e-6)["curves"][0]
    rows[0] = {**rows[0], "curves_by_grid": {"128": [sphere_curve] * 3, "256": [sphere_curve] * 3}}
    c = B.roughness_cell(p, store, 1e-6)
    assert c["effect"] < -0.05 and c["verdict"] == "matters"  # the sphere's contact: far softer than the face
    other = B.roughness_cell(B.Point(b=100e-6), store, 1e-6)
    assert other["verdict"] == "undetermined" and "b = 100 um" in other["note"]
    c = B.roughness_cell(p, lambda name: None, 1e-6)
    assert c["verdict"] == "undetermined" and "roughness-faces" in c["source"]
    sphere_like = B.roughness_cell(B.Point(b=10e-6), _hertz_store(1e-6), 1e-6)
    assert sphere_like["verdict"] == "negligible" and "b = " not in sphere_like["note"]


def test_each_contact_reads_its_own_rms_and_names_the_one_not_run():
    """The roughness columns read the sphere's 1 um and the paper's combined roughness of the contacting
    pair: 3.2 um on the sphere's contact (sphere and block), 3.6 um on a face's (turned face and block);
    a face's 3.6 um row is read at its b, and an rms not stored leaves its cell undetermined, naming it."""
    p6 = loop_point("fig6")
    assert B.roughness_rms(p6) == (1e-6, 3.6e-6) and B.roughness_rms(loop_point("fig4")) == (1e-6, 3.2e-6)
    assert B.roughness_rms(B.Point(b=10e-6)) == (1e-6, 3.2e-6)  # the face inside the sphere's contact
    rows = [_face_row(p6.b), _face_row(p6.b, rms=3.6e-6)]
    store = lambda name: {"roughness": rows} if name == B.ROUGH_FACES else None  # noqa: E731
    c = B.roughness_cell(p6, store, 3.6e-6)
    assert c["verdict"] == "negligible" and "rms 3.6 um" in c["note"]
    gap = B.roughness_cell(loop_point("fig4"), _hertz_store(1e-6), 3.2e-6)
    assert gap["verdict"] == "undetermined" and "rms 3.2 um not in the stored scene" in gap["note"]


@pytest.mark.parametrize("odd", [None, float("nan"), -1.0, 1.0])
def test_a_rough_row_of_odd_values_is_undetermined_not_a_crash(odd):
    """A stored rough row whose curve holds a value no equivalent profile can be built from (None, NaN,
    a negative or decreasing force) or whose period is not a length: the cell is undetermined and says
    so, and the sticking transition of that row too; the budget does not stop."""
    p = loop_point("fig4")
    row = _hertz_row(1e-6)
    bad = {k: [dict(c) for c in v] for k, v in row["curves_by_grid"].items()}
    bad["256"][0] = {"d": bad["256"][0]["d"], "F": [odd] + bad["256"][0]["F"][1:]}
    rows = [{**row, "curves_by_grid": bad}]
    store = lambda name: {"roughness": rows} if name == "roughness" else None  # noqa: E731
    c = B.roughness_cell(p, store, 1e-6)
    assert c["verdict"] == "undetermined" and c["effect"] is None, c
    assert all(t["kx"] is None for t in B.transitions(store)[1:])
    if not (odd is not None and odd > 0):  # (1 m is a length)
        rows[0] = {**row, "period": odd}
        assert B.roughness_cell(p, store, 1e-6)["verdict"] == "undetermined"


def _apparatus_row(p, values, eq=None, grids=(128, 256)):
    """A stored rough row whose members drove the rough half-space by the apparatus at the point ``p``:
    ``values`` per grid, per seed (the rough half-space's slip index), ``eq`` the equivalent MDR's."""
    row = _face_row(p.b) if p.b else _hertz_row(1e-6)
    from dataclasses import asdict
    from validation.families.roughness import apparatus_points

    by = {str(n): [[{"point": asdict(p), "rough_halfspace": x,
                     "mdr_equivalent": (eq if eq is not None else x)}] for x in vals]
          for n, vals in zip(grids, values)}
    v = {"grids": list(grids), "seeds": list(range(len(values[-1])))}
    return {**row, **v, "apparatus_by_grid": by, "apparatus": apparatus_points(by, v, row["period"])}


def test_the_roughness_cell_reads_the_rough_halfspace_in_the_apparatus_where_it_ran():
    """Where the row holds the rough half-space driven by the apparatus at the point, the cell is its
    ensemble against the smooth face (the equivalent profile's curves, here the smooth face's own, are
    not read): the effect its mean's difference, the error its standard error plus the grid error of the
    mean; the note says what the equivalent MDR misses there. A seed without the point, or a value that
    is no number, leaves the cell undetermined."""
    p = loop_point("fig6")
    smooth = B.point_slip_index(p)
    vals = [[smooth - 0.30, smooth - 0.32, smooth - 0.28], [smooth - 0.31, smooth - 0.33, smooth - 0.29]]
    row = _apparatus_row(p, vals, eq=smooth - 0.25)
    store = lambda name: {"roughness": [row]} if name == B.ROUGH_FACES else None  # noqa: E731
    c = B.roughness_cell(p, store, 1e-6)
    sem = float(np.std(vals[-1], ddof=1) / np.sqrt(3))
    assert c["effect"] == pytest.approx(-0.31, abs=1e-9)
    assert c["error"] >= sem and c["verdict"] == "matters"
    assert "rough half-space in the apparatus" in c["note"] and "equivalent profile +0.06" in c["note"]
    for odd in (None, float("nan"), "0.2"):
        bad = _apparatus_row(p, [vals[0], [vals[1][0], odd, vals[1][2]]])
        store = lambda name: {"roughness": [bad]} if name == B.ROUGH_FACES else None  # noqa: E731
        assert B.roughness_cell(p, store, 1e-6)["verdict"] == "undetermined"
    other = _apparatus_row(replace(p, kx=3e6), vals)  # another point only
    store = lambda name: {"roughness": [other]} if name == B.ROUGH_FACES else None  # noqa: E731
    c = B.roughness_cell(p, store, 1e-6)
    assert c["verdict"] == "undetermined" and "not run in the apparatus" in c["note"]
    ladder = _apparatus_row(p, [[0.2, 0.21, 0.19], [0.25, 0.26, 0.24], [0.26, 0.27, 0.25]], grids=(128, 192, 256))
    rh = ladder["apparatus"][0]["rough_halfspace"]
    assert rh["grid"] > 0 and rh["error"] == pytest.approx(rh["sem"] + rh["grid"])  # the grids' error counted
