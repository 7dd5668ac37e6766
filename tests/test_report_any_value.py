"""No result crashes the report: every value a stored result can hold renders.

Truth: a result is plain data (``validation.runner``), and another CPU, a coarse ladder or a
contact that does not slip can put None, NaN, +-inf, 0, a negative number or any ladder status
where a number usually stands (geom-flat's time-step ladder of exact zeros crashed the report
on one CPU and not on another). The strategy takes real results of each scene family, run on
tiny ladders, and replaces any subset of their numbers and statuses with such values; the
report must render each of them (``validation.report.render_report``: text only, no files).
"""
from __future__ import annotations

import copy
import json
from dataclasses import replace

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from common.io import dumps_json
from validation import report, runner
from validation.catalogue import CATALOGUE

# the tiny ladders are coarse on purpose; the warning that says so is for a user, not this test
pytestmark = pytest.mark.filterwarnings("ignore:coarse contact mesh:RuntimeWarning")

#: what a number of a result may be instead (None: not computed)
ODD_NUMBERS = (None, float("nan"), float("inf"), float("-inf"), 0.0, -0.0, -1.0, 1e-300, -2.5e7, 3)
#: what a ladder's or a verdict's status may be
ODD_STATUS = (None, "non-monotone", "asymptotic", "two levels", "one level", "no value", "converged",
              "order 7.1 outside 0.5-4", "")


def _tiny(name, **kw):
    s = CATALOGUE[name]
    return replace(s, fe_levels=kw.pop("fe_levels", (1 / 8, 1 / 12, 1 / 16)), mdr_cells=(25, 50, 100),
                   steps=kw.pop("steps", 24), cycles=3, **kw)


# session scope: a module fixture is torn down whenever its worker runs another module's test in
# between, and built again; its tests are grouped on one worker (xdist_group), so it is built once
@pytest.fixture(scope="session")
def results():
    """Real results of the families the report renders differently: a force-driven partial-slip
    contact, a sticking flat punch (zero dissipation on every level), an apparatus scene, the
    block/cap validity table, the curvature table, both kinds of the paper's points and a rough face (tiny ladders: structure, not accuracy; no
    directory, so no figures: the report's text is under test, the figures in test_summary_figures_*)."""
    scenes = [_tiny("sphere-md"), _tiny("geom-flat"), _tiny("app-kx2", steps=40),
              _tiny("validity", fe_levels=(1 / 8,), variants=({"block": 5.0}, {"cap": 5.0})),
              _tiny("validity-curvature", fe_levels=(1 / 6, 1 / 8, 1 / 10),
                    variants=({"a_over_R": 4.6e-3, "nu": 0.29},)),
              _tiny("halfspace-points", steps=40, variants=(CATALOGUE["halfspace-points"].variants[-2],)),
              replace(CATALOGUE["direction-points"], fe_levels=(0.3, 0.2), steps=20, cycles=3,
                      variants=CATALOGUE["direction-points"].variants[:1])]
    try:  # the roughness family (tamaas is optional): a rough face, two surfaces on two small grids
        import tamaas  # noqa: F401
        scenes.append(replace(CATALOGUE["roughness-faces"], steps=24,
                              variants=({"b": 100e-6, "rms": 1e-6, "period": 4.0, "grids": (64, 96),
                                         "seeds": (0, 1)},)))
    except ImportError:
        pass
    res = {}
    for s in scenes:
        r = runner.run_scene(s, None, fields=False)  # no directory: no figures (the report's text is under test)
        res[s.name] = json.loads(dumps_json(r))  # as stored: JSON types, non-finite as null
    return res


def _slots(obj, path=()):
    """Paths to every number (not bool) and every 'status' string of a result, skipping long
    arrays (loops and profiles, read only by the figures). A None already there stays: it may
    stand for a dict (no closed form), which no run turns into a number."""
    if isinstance(obj, dict):
        for k, v in obj.items():
            if k == "status" and (v is None or isinstance(v, str)):
                yield path + (k,), "status"
            else:
                yield from _slots(v, path + (k,))
    elif isinstance(obj, list) and len(obj) <= 8:
        for i, v in enumerate(obj):
            yield from _slots(v, path + (i,))
    elif isinstance(obj, (int, float)) and not isinstance(obj, bool):
        yield path, "number"


def _set(obj, path, value):
    for k in path[:-1]:
        obj = obj[k]
    obj[path[-1]] = value


@pytest.mark.xdist_group("report-any-value")  # the module fixture results built once, on one worker
def test_the_families_render_as_computed(results):
    text = report.render_report(results, list(results), {n: "ok" for n in results})
    for name in results:
        assert f"## {name}" in text
    # the sticking punch: zero dissipation on both sides, the time-step line rendered
    flat = results["geom-flat"]
    assert flat["mdr"]["dissipation"] == 0.0 and flat["fem"]["dissipation"] == 0.0
    assert "Time step" in text


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                   HealthCheck.too_slow])
@given(data=st.data())
@pytest.mark.xdist_group("report-any-value")  # the module fixture results built once, on one worker
def test_any_value_in_any_field_renders(results, data):
    res = copy.deepcopy(results)
    slots = [(n, p, kind) for n, r in res.items() for p, kind in _slots(r) if p[0] != "scene"]
    chosen = data.draw(st.lists(st.sampled_from(slots), min_size=1, max_size=40, unique_by=lambda x: (x[0], x[1])))
    for name, path, kind in chosen:
        _set(res[name], path, data.draw(st.sampled_from(ODD_STATUS if kind == "status" else ODD_NUMBERS)))
    status = {n: data.draw(st.sampled_from(["ok", "skipped", "stored", "RuntimeError: lost worker"])) for n in res}
    text = report.render_report(res, list(res), status, hard_cases=[{"name": "x", "error": None, "tol": float("nan"),
                                                                     "iterations": None, "time_s": float("inf")}])
    assert text.startswith("# MDR against FE")


@pytest.mark.parametrize("value", ODD_NUMBERS)
@pytest.mark.xdist_group("report-any-value")  # the module fixture results built once, on one worker
def test_a_whole_result_of_one_odd_value_renders(results, value):
    """Every number of every family at once the same odd value (all None, all NaN, all 0, ...)."""
    res = copy.deepcopy(results)
    for name, r in res.items():
        for path, kind in list(_slots(r)):
            if kind == "number" and path[0] != "scene":
                _set(r, path, value)
    report.render_report(res, list(res), {n: "ok" for n in res})


def test_summary_figures_take_any_value(tmp_path):
    """The summary figures skip what cannot be plotted (None, NaN, inf) and say so when nothing is left."""
    from validation import figures

    odd = [(1e-6, None), (2e-6, float("nan")), (float("inf"), 0.1), (5e-6, 0.2), (6e-6, float("-inf"))]
    assert (tmp_path / figures.series_figure({"mdr": odd, "fem": odd[:3]}, "b", tmp_path / "s.png")).exists()
    rows = [{"side": s, "runtime_s": t, "dissipation": W}
            for s in ("mdr", "fem") for t, W in ((None, 0.1), (0.5, float("nan")), (0.0, 0.1), (1.0, None), (1.0, 2.0))]
    for ref in (1.0, None, float("nan"), 0.0):
        res = {"scene": {"group": "g"}, "closed_form": {"dissipation": ref}, "speed_error": rows}
        figures.save(figures.speed_error_figure(figures.speed_error_points(res), "t"), tmp_path / "p.png")
    assert (tmp_path / "p.png").stat().st_size > 0


def test_speed_error_points_measure_each_level_against_the_answer_it_approximates():
    """The closed form where one exists, else the side's own extrapolated answer; no point where
    there is neither (a distance to the finest level would vanish there by construction)."""
    from validation import figures

    rows = [{"side": "fem", "runtime_s": 1.0, "dissipation": 1.1}, {"side": "fem", "runtime_s": 2.0, "dissipation": 1.02},
            {"side": "mdr", "runtime_s": 0.1, "dissipation": 0.97}]
    scene = {"group": "geometry", "name": "s"}
    pts = figures.speed_error_points({"scene": scene, "closed_form": {"dissipation": 1.0}, "speed_error": rows})
    assert [round(p["error"], 12) for p in pts] == [0.03, 0.1, 0.02] and [p["model"] for p in pts] == ["MDR", "FE", "FE"]
    v = {"dissipation": {"fem_ladder": {"extrapolated": 1.01}, "mdr_ladder": {"extrapolated": None}}}
    pts = figures.speed_error_points({"scene": scene, "closed_form": None, "verdicts": v, "speed_error": rows})
    assert [p["model"] for p in pts] == ["FE", "FE"] and pts[1]["error"] == pytest.approx(0.01 / 1.01)
    assert {p["against"] for p in pts} == {"own extrapolation"}  # never pooled with a truth's distance
