"""The error budget of the paper's model (validation.budget).

Truths: the verdict rule (a bound never "matters", a non-finite number is undetermined); exact zeros
where the physics has them (no kink on the sphere, a tilted sphere is the sphere, identical steels do
not couple); MDR with the equivalent profile of the smooth sphere's own Hertz curve is the smooth sphere
in the apparatus (its "roughness" is zero); the fillet's effect vanishes with its width; a bound the paper
states as an inequality (the tilt) never matters; missing scenes name the command that runs them. The
roughness readings: tests/test_budget_readings.py.
"""
import math
import subprocess
import sys
from dataclasses import replace

import pytest

from mdr.materials import Materials
from validation import budget as B
from validation import budget_cells as C
from validation.paper_points import Point, loop_point

PAPER = C.paper_inputs()

MAT = Materials()


@pytest.mark.parametrize("effect,error,kind,verdict", [
    (0.004, 0.005, "measured", "negligible"), (0.02, 0.005, "measured", "matters"),
    (0.012, 0.005, "measured", "undetermined"), (0.02, 0.0, "bound", "undetermined"),
    (0.004, 0.0, "bound", "negligible"), (float("nan"), 0.0, "measured", "undetermined"),
    (None, None, "measured", "undetermined"), (0.02, float("inf"), "spread", "undetermined")])
def test_the_verdict_rule(effect, error, kind, verdict):
    assert C.cell(effect, error, kind, "x")["verdict"] == verdict


def test_a_result_matters_if_one_point_does_and_is_negligible_only_if_all_are():
    small, big, gap = C.cell(0.001, 0.001, "measured", "a"), C.cell(0.05, 0.001, "measured", "b"), C.missing("tilt")
    assert C.combine([small, big, gap], "x")["verdict"] == "matters"
    assert C.combine([small, gap], "x")["verdict"] == "undetermined"
    assert C.combine([small, small], "x")["verdict"] == "negligible"
    assert "python -m validation.compare --scenes tilt" in gap["source"]
    # the cell shown is the one that decides: a point that matters, not a larger but uncertain one
    vague = C.cell(-0.2, 0.25, "measured", "c")
    shown = C.combine([vague, big], "x")
    assert shown["verdict"] == "matters" and shown["effect"] == 0.05
    assert C.combine([vague, small], "x")["effect"] == -0.2  # undetermined: the largest bound


def test_exact_zeros_on_the_sphere():
    p = loop_point("fig4")
    assert p.b == 0
    for c in (C.kink_cell(p, PAPER), C.tilt_cell(p, lambda name: None, PAPER)):
        assert c["effect"] == 0.0 and c["kind"] == "exact" and c["verdict"] == "negligible"


def test_the_tilt_of_a_face_is_a_bound_that_never_matters():
    """The paper states the tilt as an inequality (< pi/3600): the change at pi/3600, measured at the point
    in its apparatus (the row of ``tilt-points`` that runs it), is a bound, so a face whose slip index moves
    by 0.03 there is 'undetermined', not 'matters' (a measured change of the same size would matter); a
    point the scene does not tilt (a face below two elements) and an unresolved tilted contact get no
    number."""
    from validation.catalogue import CATALOGUE
    from validation.scenes import TILT_BOUND

    s, p = CATALOGUE["tilt-points"], loop_point("fig6")
    i = next(i for i, v in enumerate(s.typed_variants) if p.matches(v.scene(s)))
    row = {"variant": i, "tilt": TILT_BOUND, "effect": -0.03, "error": 1e-4, "slip_index": 0.5}
    c = C.tilt_cell(p, {"tilt-points": {"points": [row]}}.get, PAPER)
    assert c["kind"] == "bound" and c["verdict"] == "undetermined" and c["effect"] == -0.03
    assert C.cell(0.03, 1e-4, "measured", "x")["verdict"] == "matters"
    assert B.cell_text(c).startswith("<= 0.03")
    unresolved = {**row, "effect": None, "error": None, "contact_vertices": 4}
    c = C.tilt_cell(p, {"tilt-points": {"points": [unresolved]}}.get, PAPER)
    assert c["effect"] is None and "not resolved (4 contact vertices)" in c["note"]
    tiny = Point(b=1e-6, kx=1e6)  # Fig. 8's 1 um face: a quarter of an element, not tilted
    assert not any(tiny.matches(v.scene(s)) for v in s.typed_variants)
    assert C.tilt_cell(tiny, {"tilt-points": {"points": [row]}}.get, PAPER)["effect"] is None
    # a scene that also tilts the point by another angle: the row at the stated bound is read
    other = replace(s, variants=s.variants + ({**s.variants[i], "tilt": 2 * TILT_BOUND},))
    rows = [{**row, "variant": len(s.variants), "effect": -0.09}, row]
    c = C.tilt_cell(p, {"tilt-points": {"points": rows}}.get, replace(PAPER, scenes=tuple(
        other if x.name == "tilt-points" else x for x in PAPER.scenes)))
    assert c["effect"] == -0.03, c
    # no scene tilts any face (a rig whose faces are all below two elements): no number, and no command to
    # run that could give one
    bare = replace(PAPER, scenes=tuple(x for x in PAPER.scenes if x.name != "tilt-points"))
    c = C.tilt_cell(p, lambda name: None, bare)
    assert c["effect"] is None and "not measured" in c["note"] and "--scenes" not in c["source"], c


def test_every_point_but_the_softest_apparatus_slides():
    """The paper's points in their apparatus (MDR): every point of its results slides as a whole for part
    of its cycle (its tangential force reaches the friction limit mu1 F_N) but Fig. 9's at k_x = 0.3 N/um,
    which stay in partial slip. Truth: Coulomb's limit, |F_x| <= mu1 F_N."""
    from validation.paper_points import friction_share, results

    for p in (p for r in results() for p in r.points):
        share = friction_share(p)
        assert share <= 1 + 1e-9, (p, share)
        assert (share < 0.9) if p.kx == 0.3e6 else (share > 1 - 1e-6), (p, share)


def test_the_fillet_costs_less_as_it_narrows_and_nothing_on_the_wide_face():
    p = loop_point("fig6")
    wide = C.kink_cell(p, PAPER)
    assert abs(wide["effect"]) < 1e-3  # b = 0.6 mm: the fillet is 0.5 % of the radius (measured 1.6e-5)
    assert wide["verdict"] == "negligible"
    q = Point(b=20e-6)
    e3 = C.kink_cell(q, PAPER)["effect"]
    e05 = C.kink_cell(q, replace(PAPER, fillet=0.5e-6))["effect"]
    assert abs(e05) < abs(e3)


def test_missing_scenes_are_undetermined_and_name_their_command():
    b = B.budget("/nonexistent", mdr_cells=False)
    for r in b["rows"]:
        for col in ("size", "curvature", "direction"):
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


def test_a_solver_failure_exits_3_in_one_line_and_writes_nothing(tmp_path, monkeypatch, capsys):
    """The exit codes of every command (``common.cli.run_command``): a solver that fails is exit 3, one line,
    and no budget is written."""
    from common.errors import ConvergenceError

    def fails(*a, **k):
        raise ConvergenceError("Newton did not converge")

    (tmp_path / "scenes").mkdir()
    monkeypatch.setattr(B, "budget", fails)
    assert B.main(["--out", str(tmp_path)]) == 3
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "solver failed" in err
    assert not (tmp_path / "budget.md").exists()


def test_scaled_turns_a_relative_effect_into_a_slip_index_change():
    c = C.scaled(C.cell(0.1, 0.01, "measured", "x"), 0.5)
    assert c["effect"] == pytest.approx(0.05) and c["error"] == pytest.approx(0.005) and c["verdict"] == "matters"
    a = C.cell(0.02, 0.001, "absolute", "x")
    assert C.scaled(a, 0.5) is a
    assert math.isclose(C.scaled(C.cell(0.1, 0.01, "bound", "x"), 0.05)["effect"], 0.005)


def _pair_result(fe, md, err=1e-4, bounded=True):
    return {"verdicts": {"slip_index": {"fem": fe, "mdr": md, "fem_error": err, "mdr_error": err,
                                         "bounded": bounded}}, "fem": {"contact_radius": 0.6e-3}}


def test_the_curvature_is_measured_at_the_point_where_a_scene_runs_it():
    """A point that a stored apparatus scene runs (the experiment of Fig. 6; a row of halfspace-points)
    takes its FE - MDR there, a change of the slip index; an injected 0.05 between the models matters;
    a non-finite one falls back to the sphere's bound (here: its scene missing, undetermined)."""
    from validation.catalogue import CATALOGUE

    p6, p2 = loop_point("fig6"), Point(b=10e-6)
    i = next(i for i, v in enumerate(CATALOGUE["halfspace-points"].variants) if Point(**v) == p2)
    rows = [{"variant": i, "b": 10e-6, "kx": p2.kx, "slip_index_fem": 0.4221, "slip_index_mdr": 0.4224,
             "error": 6e-4, "bounded": False, "a_over_R": 0.0046}]
    stored = {"exp-fig6": _pair_result(0.5312, 0.5315), "halfspace-points": {"points": rows}}
    c = C.curvature_cell(p6, stored.get, PAPER)
    assert c["source"] == "exp-fig6" and c["kind"] == "absolute" and c["verdict"] == "negligible"
    assert c["effect"] == pytest.approx(-3e-4) and c["error"] == pytest.approx(2e-4)
    c = C.curvature_cell(p2, stored.get, PAPER)
    assert c["source"] == "halfspace-points" and c["verdict"] == "negligible" and "spread" in c["note"]
    stored["exp-fig6"] = _pair_result(0.5312, 0.5812)
    assert C.curvature_cell(p6, stored.get, PAPER)["verdict"] == "matters"
    stored["exp-fig6"] = _pair_result(float("nan"), 0.5315)
    c = C.curvature_cell(p6, stored.get, PAPER)
    assert c["verdict"] == "undetermined" and "validity-curvature" in c["source"]
    assert C.curvature_cell(replace(p2, kx=5e6), stored.get, PAPER)["source"] != "halfspace-points"  # not that point


def test_every_point_with_a_face_has_a_scene_that_runs_it_in_the_apparatus():
    """The budget's curvature column is measured, not bounded, at every point of a truncated sphere: each
    is run by an apparatus scene of the catalogue (experiments, k_x series, halfspace-points)."""
    from validation.catalogue import CATALOGUE

    hs = CATALOGUE["halfspace-points"]
    runs = [s for s in CATALOGUE.values() if s.family == "pair" and s.drive == "apparatus"]
    runs += [v.scene(hs) for v in hs.typed_variants]
    for r in PAPER.results:
        for p in r.points:
            n = sum(p.matches(s) for s in runs)
            assert n == 1 or (p.b == 0 and n <= 1), (r.key, p, n)


def test_the_direction_is_measured_at_the_point_where_a_3d_scene_runs_it():
    """A point that the stored 3D scene direction-points runs takes its free - along x there, a change of
    the slip index; an injected 0.05 matters; without the scene the force-control row of assumptions-3d
    is read (here missing: undetermined)."""
    from validation.catalogue import CATALOGUE

    s = CATALOGUE["direction-points"]
    p = loop_point("fig6")
    i = next(i for i, v in enumerate(s.variants) if Point(**v) == p)
    row = {"variant": i, "effect": 3e-7, "error": 2e-7, "ladder_status": "two levels"}
    stored = {"direction-points": {"points": [row]}}
    c = C.direction_cell(p, stored.get, PAPER)
    assert c["source"] == "direction-points" and c["kind"] == "absolute" and c["verdict"] == "negligible"
    row["effect"] = 0.05
    assert C.direction_cell(p, stored.get, PAPER)["verdict"] == "matters"
    c = C.direction_cell(loop_point("fig7"), stored.get, PAPER)  # another point: not this row
    assert c["source"] != "direction-points" and c["verdict"] == "undetermined"


def test_the_kinks_bar_holds_the_apparatus_solves_own_error(monkeypatch):
    """The kink's bar (MDR's grid change, at least the round-off of the slip indices) contains what the
    apparatus solve's displacement tolerance (1e-15 m) moves the cell, over-estimated by a solve ten times
    looser, at every point of the paper's results with a face: the grid's change alone is 0 to 1e-16 at
    some (the face that is the whole contact; b = 100 um in the softest apparatus, k_x = 0.3 N/um) while the
    looser solve moves them by up to 6e-16 (measured; fails without ``ROUND_OFF``)."""
    import functools

    import mdr.apparatus as A
    import studies.paper as SP

    points = [p for r in PAPER.results for p in r.points if p.b > 2 * PAPER.fillet]
    default = [C.kink_cell(p, PAPER) for p in points]
    monkeypatch.setattr(SP, "run_apparatus", functools.partial(A.run_apparatus, xtol=1e-14))
    for p, c in zip(points, default):
        looser = C.kink_cell(p, PAPER)["effect"]
        assert abs(looser - c["effect"]) <= c["error"], (p, looser, c)
