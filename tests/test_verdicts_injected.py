"""A verdict an injected error cannot pass (fast suite).

Truth: a "holds" is evidence only if a wrong answer would not get it. The scene's real ladders
(geom-b20um on the quick ladders: MDR 100/400/1600 cells, FE a/20, a/40, a/80, each side's time
step at 1, 2 and 4 times the scene's steps) are graded by ``validation.families.pair.scene_verdicts``; then an
error is injected into one level of one side and the grading is repeated:

- +10 % on any one level of a metric graded "holds" takes its "holds" away, and +2 % does wherever the
  ladder's rule cannot absorb it (a Richardson ladder leaves its asymptotic range; a level leaves the
  calibrated bound's allowance of the others, ``validation.error_models``; or the difference exceeds
  the bars and the verdict fails); where a calibrated bound absorbs +2 % on a coarse level (the mesh
  itself moves that level by as much), the "holds" left is still true of the injected answer;
- a NaN on any level, coarse or fine, makes the metric undetermined (the levels left must not
  vouch for the answer);
- the time step's error bar is part of the dissipation's: without it the bars are smaller.
"""
from __future__ import annotations

import copy
import pytest

from validation import metrics, sides
from validation.families import pair
from validation.catalogue import CATALOGUE

SCALARS = ("contact_radius", "stick_radius", "dissipation", "slip_index")


# session scope: a module fixture is torn down whenever its worker runs another module's test in
# between, and built again; its tests are grouped on one worker (xdist_group), so it is built once
@pytest.fixture(scope="session")
def ladders():
    s = CATALOGUE["geom-b20um"].quick_version()
    mdr = [sides.run_mdr(s, n) for n in s.mdr_cells]
    fe = [sides.run_fe(s, h)[0] for h in s.fe_levels]
    ts = {"mdr": sides.time_step_error(s, mdr[-1], n=s.mdr_cells[-1]),
          "fem": sides.time_step_error(s, fe[-1], h=s.fe_levels[-1])}
    return s, mdr, fe, ts


def _grades(s, mdr, fe, ts):
    return {q: v["grade"] for q, v in pair.scene_verdicts(s, fe, mdr, ts).items()}


@pytest.mark.xdist_group("verdicts-ladders")  # the module fixture ladders built once, on one worker
def test_the_real_ladders_give_graded_verdicts(ladders):
    s, mdr, fe, ts = ladders
    V = pair.scene_verdicts(s, fe, mdr, ts)
    grades = {q: v["grade"] for q, v in V.items()}
    assert set(grades.values()) <= set(metrics.GRADES)
    assert grades["contact_radius"] == "holds"  # both ladders bounded (asymptotic FE, converged MDR)
    for q, v in V.items():  # "holds" only on bounded ladders, and always its inequality
        if v["grade"] == "holds":
            assert v["bounded"] and abs(v["difference"]) <= v["fem_error"] + v["mdr_error"] + v["tolerance"], q
        if v["grade"] == "consistent within its spread":
            assert not v["bounded"], q
    # the time step is inside the dissipation's error bars, on both sides
    d = V["dissipation"]
    for side in ("mdr", "fem"):
        assert d["error_parts"][side]["time step"] > 0
        assert d[f"{side}_error"] == pytest.approx(sum(d["error_parts"][side].values()), rel=1e-12)
    without = pair.scene_verdicts(s, fe, mdr, None)["dissipation"]
    assert without["fem_error"] < d["fem_error"] and without["mdr_error"] < d["mdr_error"]


def _absorbable(s, cls, ladder, side, q, k, delta, fe_finest):
    """Whether a change ``delta`` of level k of a metric's ladder stays within what its calibrated bound
    (of the class ``cls``) allows (each other level j within E_k + E_j of it): True, False, or None where
    the metric has no calibrated bound (its ladder's own error decides). Computed here from the bound, independently of
    ``common.ladder.modelled_error``."""
    from validation import error_models
    from validation.scenes import a_ref

    b = error_models.bound(side, "slip_index" if q == "dissipation" else q, cls)
    if b is None:
        return None
    a = float(fe_finest["contact_radius"])
    if side == "fem":
        hs = [float(x["h_contact"]) * a_ref(s) / a for x in ladder]
    else:
        hs = [1.0 / float(x["cells"]) for x in ladder]
    hs, qs = hs[-3:], [float(x[q]) for x in ladder][-3:]
    k -= len(ladder) - len(hs)
    if k < 0:
        return True  # a level outside the three finest decides nothing
    scale = a if q.endswith("radius") else 1.0
    qs[k] += delta
    return all(abs(qs[k] - qs[j]) <= b(hs[k], scale) + b(hs[j], scale) for j in range(len(qs)) if j != k)


@pytest.mark.parametrize("factor", [1.10, 1.02])
@pytest.mark.parametrize("side", ["fem", "mdr"])
@pytest.mark.xdist_group("verdicts-ladders")  # the module fixture ladders built once, on one worker
def test_an_error_injected_into_one_level_takes_the_holds_away(ladders, side, factor):
    """+10 % on any level takes every "holds" away. +2 % does wherever the ladder's error rule cannot
    absorb it: always under Richardson's rule; under a calibrated bound wherever the injected level leaves
    the bound's allowance of the others (``_absorbable``, from the bound). Where the bound absorbs it (a
    coarse level moved by less than the mesh itself moves it), a remaining "holds" must still be true of
    the injected answer: |MDR - FE| within the bars and the tolerance."""
    s, mdr, fe, ts = ladders
    base = _grades(s, mdr, fe, ts)
    held = [q for q in SCALARS if base[q] == "holds"]
    assert held  # the real ladders give at least one "holds" to break
    ladder = mdr if side == "mdr" else fe
    broken = 0
    for q in held:
        for k in range(len(ladder)):
            lad = copy.deepcopy(ladder)
            old = lad[k][q]
            lad[k][q] = factor * old if old else 1e-3 * factor * lad[k]["contact_radius"]
            v = pair.scene_verdicts(s, lad if side == "fem" else fe, lad if side == "mdr" else mdr, ts)[q]
            cls = pair.ladder_class(s, lad if side == "fem" else fe, lad if side == "mdr" else mdr)  # as injected
            absorbable = _absorbable(s, cls, ladder, side, q, k, lad[k][q] - old, fe[-1])
            if factor > 1.05 or absorbable is False or absorbable is None:
                assert v["grade"] != "holds", (q, side, k, factor)
                broken += 1
            elif v["grade"] == "holds":
                assert abs(v["difference"]) <= v["fem_error"] + v["mdr_error"] + v["tolerance"], (q, side, k)
    assert broken > 0


@pytest.mark.parametrize("side", ["fem", "mdr"])
@pytest.mark.xdist_group("verdicts-ladders")  # the module fixture ladders built once, on one worker
def test_a_nan_on_any_level_makes_the_verdict_undetermined(ladders, side):
    s, mdr, fe, ts = ladders
    n = len(mdr if side == "mdr" else fe)
    for q in SCALARS:
        for k in range(n):
            lad = copy.deepcopy(mdr if side == "mdr" else fe)
            lad[k][q] = float("nan")
            g = _grades(s, lad if side == "mdr" else mdr, lad if side == "fem" else fe, ts)[q]
            assert g == "undetermined", (q, side, k)


def test_a_floor_that_decides_is_below_resolution():
    """Within the tolerance only because the tolerance was raised to the resolution floor: no "holds"."""
    bar = {"error": 0.0, "status": "converged", "bounded": True}
    v = metrics.verdict(1.0, 1.004, bar, bar, 0.001, floor=0.005)  # the physics' 0.001 alone would fail
    assert v["grade"] == "below resolution" and v["holds"] is None and v["tolerance"] == 0.005
    assert metrics.verdict(1.0, 1.004, bar, bar, 0.001)["grade"] == "fails"
    # a floor above a tolerance that passes by itself decides nothing: holds (slip index 0.019: 0.5 % of
    # it is 0.95e-4, under the 1e-4 floor)
    assert metrics.verdict(1.0, 1.004, bar, bar, 0.005, floor=0.006)["grade"] == "holds"
    # a time-step bar that was not computed bounds nothing
    unbounded = metrics.verdict(1.0, 1.0, bar, bar, 0.01, extra={"fem": {"time step": {"error": 0.0, "bounded": False}}})
    assert unbounded["grade"] == "consistent within its spread"
    assert metrics.verdict(1.0, 1.0, bar, bar, 0.01, extra={"fem": {"time step": None}})["grade"] == "undetermined"
    assert metrics.effect_verdict(0.001, {"error": 0.01, "bounded": True}, 0.01, error=None)["grade"] == "undetermined"
    spread = {"error": 0.01, "status": "non-monotone", "bounded": False}
    assert metrics.verdict(1.0, 1.004, spread, bar, 0.0)["grade"] == "consistent within its spread"
    assert metrics.verdict(1.0, 1.1, spread, bar, 0.0)["grade"] == "fails"
    # a pass that only the floor allows is below resolution whether or not the bars bound
    assert metrics.verdict(1.0, 1.015, spread, bar, 0.001, floor=0.01)["grade"] == "below resolution"
    assert metrics.verdict(1.0, 1.005, spread, bar, 0.001, floor=0.01)["grade"] == "consistent within its spread"
    assert metrics.scene_grade({"a": v, "b": metrics.verdict(1.0, 1.0, bar, bar, 0.0)}) == "below resolution"


def test_the_report_tallies_the_decided_verdicts():
    """The summary's tally: holds, below resolution and fails are decided, a spread and an undetermined
    metric are not; scenes of other families are not counted; the report prints the sentence."""
    from validation import report

    bar = {"error": 0.0, "status": "converged", "bounded": True}
    spread = {"error": 0.01, "status": "non-monotone", "bounded": False}
    vs = {"a": metrics.verdict(1.0, 1.0, bar, bar, 0.01), "b": metrics.verdict(1.0, 1.004, bar, bar, 0.001, floor=0.005),
          "c": metrics.verdict(1.0, 1.1, bar, bar, 0.01), "d": metrics.verdict(1.0, 1.004, spread, bar, 0.0),
          "e": metrics.verdict(1.0, float("nan"), bar, bar, 0.01)}
    assert [v["grade"] for v in vs.values()] == ["holds", "below resolution", "fails", "consistent within its spread",
                                                 "undetermined"]
    results = {"p": {"scene": {"family": "pair"}, "verdicts": vs}, "q": {"verdicts": {"a": vs["a"]}},
               "r": {"scene": {"family": "tilt"}, "verdicts": {"x": vs["d"]}}}
    t = report.tally(results, ["p", "q", "r", "missing"])
    assert (t["decided"], t["total"], t["holds"]) == (4, 6, 2)
    assert report.tally_text(t).startswith("Decided: 4 of 6 metric verdicts")


def test_each_scene_opens_with_a_bottom_line():
    """A pair scene's bottom line: MDR - FE of each scalar metric relative to the FE value (the slip index
    absolute), the decided verdicts counted as the tally counts them, and the models' shared assumptions
    (Mindlin's traction along x only for the axisymmetric FE model)."""
    from validation import report

    bar = {"error": 0.0, "status": "converged", "bounded": True}
    spread = {"error": 0.01, "status": "non-monotone", "bounded": False}
    vs = {"contact_radius": metrics.verdict(1.0, 1.002, bar, bar, 0.01),
          "dissipation": metrics.verdict(2.0, 2.1, spread, bar, 0.1),
          "slip_index": metrics.verdict(0.2, 0.19, bar, bar, 0.001)}
    res = {"scene": {"fe_model": "axisym"}, "verdicts": vs, "fem": {"contact_radius": 1.002}}
    line = report.bottom_line(res)
    assert "contact radius -0.2 %" in line and "slip index +0.01" in line
    assert "2 of 3 verdicts decided (1 hold, 0 below resolution, 1 fail)" in line and "dissipation -4.8 %" in line
    assert "the traction along x" in line
    assert "the traction along x" not in report.bottom_line({**res, "scene": {"fe_model": "3d"}})
