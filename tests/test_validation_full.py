"""The full scene catalogue through python -m validation.compare (slow: minutes on 2 cores).

Asserts the agreement the physics predicts, each against an independent truth:
- the closed-form anchors (Hertz, Cattaneo-Mindlin, Mindlin-Deresiewicz; the flat punch's
  full stick below mu F_N) on both sides;
- MDR is exact for axisymmetric profiles on a half-space, the FE bodies are 200 contact
  radii large and R = 6 mm (a/R ~ 0.5 %): every verdict of these scenes holds, i.e. every
  metric agrees within both sides' extrapolated error bars plus the stated tolerance;
- the one stick radius converges on both ladders (MDR error bar < 1 %, FE < 2 %);
- the half-space assumption fails as the block shrinks towards the contact radius and as
  the curvature a/R grows: there the verdicts must fail.

Over 500 lines for a stated reason: every test reads the one full catalogue run of the session fixture
``full_run`` (tests/conftest.py; minutes), which keeps its readers on one worker of one xdist group.
"""
from __future__ import annotations

import json
import re

import numpy as np

import pytest

from validation import metrics
from validation.catalogue import CATALOGUE

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("catalogue")]  # one worker runs the catalogue once


def test_the_readme_command_writes_the_whole_report_without_warnings(full_run):
    """``python -m validation.compare --jobs 2`` in a fresh process: exit 0, report.md and results.json
    hold all 28 scenes and the hard cases, every figure the report links exists and is not blank, and
    the run prints no warning (a user could act on none)."""
    from matplotlib.image import imread

    from validation.fields import image_is_blank

    proc, out = full_run
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "Warning" not in proc.stdout + proc.stderr, [ln for ln in (proc.stdout + proc.stderr).splitlines()
                                                        if "Warning" in ln][:5]
    data = json.loads((out / "results.json").read_text())
    assert set(data["scenes"]) == set(CATALOGUE) and len(CATALOGUE) == 28
    assert data["hard_cases"] and data["hard_cases_rerun"] is True
    report = (out / "report.md").read_text()
    for name in CATALOGUE:
        assert f"## {name}" in report
    assert "## Hard cases" in report
    figs = re.findall(r"!\[[^\]]*\]\(([^)]+\.png)\)", report)
    assert len(figs) >= 2 * len(CATALOGUE)
    for f in figs:
        assert not image_is_blank((imread(out / f) * 255).astype(np.uint8)), f  # PNG read as 0..1


def _large_body_scenes(sc):
    return {n: r for n, r in sc.items() if r["scene"]["group"] not in ("validity", "3d", "rough")}


def test_every_scene_ran(full):
    rc, out, scenes = full
    assert rc == 0
    assert set(scenes) == set(CATALOGUE)
    report = (out / "report.md").read_text()
    for name in CATALOGUE:
        assert f"## {name}" in report


def test_every_verdict_is_its_stated_inequality(full):
    """Each grade is its inequality: within the sum for holds, consistent within its spread and below
    resolution; beyond it for fails; "holds" only on bounded error bars (asymptotic or converged
    ladders, the time step's included)."""
    _, _, sc = full
    for name, r in _large_body_scenes(sc).items():
        for q, v in r["verdicts"].items():
            if v["grade"] == "undetermined":
                assert v["holds"] is None, (name, q)
                continue
            within = abs(v["difference"]) <= v["fem_error"] + v["mdr_error"] + v["tolerance"]
            assert within == (v["grade"] != "fails"), (name, q)
            assert (v["grade"] == "holds") == (v["holds"] is True) and (v["grade"] != "holds" or v["bounded"])
        assert r["holds"] == metrics.conjunction(r["verdicts"]), name


def test_mdr_holds_for_every_large_body_scene(full):
    """Large bodies, small a/R: no metric of a directly driven or apparatus scene fails or is
    undetermined; each agrees within the error bars plus the tolerance, graded "holds" where both
    ladders are bounded and "consistent within its spread" where one is not (docs/comparison.md). The one
    exception docs/comparison.md names: the truncated sphere b = 0.6 mm driven directly (a/R = 10 %),
    whose displacement loop departs (the cap's compliance in shear)."""
    _, _, sc = full
    bad = {n: [q for q, v in r["verdicts"].items() if v["grade"] in ("fails", "undetermined")]
           for n, r in _large_body_scenes(sc).items()}
    assert {n: q for n, q in bad.items() if q} == {"geom-b600um": ["loop_du"]}, bad
    # issue 47's bar: at least 90 % of the 141 verdicts decided (README and docs quote the report's tally,
    # generated: python -m validation.docs), none undetermined; the anchors decided on every metric
    grades = [v["grade"] for r in _large_body_scenes(sc).values() for v in r["verdicts"].values()]
    assert len(grades) == 141 and grades.count("fails") == 1 and grades.count("undetermined") == 0
    assert 2 <= grades.count("below resolution") <= 8
    from validation.report import tally

    t = tally(sc, list(_large_body_scenes(sc)))
    assert t["decided"] == len(grades) - grades.count("consistent within its spread") and t["total"] == 141
    assert t["decided"] >= 0.9 * t["total"], t
    for name in ("sphere-md", "flat-md"):
        assert all(v["grade"] != "consistent within its spread" for v in sc[name]["verdicts"].values()), name
    for name in ("geom-flat", "flat-md", "exp-fig6", "exp-fig7"):  # docs/comparison.md: graded "holds" throughout
        assert sc[name]["holds"] is True, name
    du = sc["geom-b600um"]["verdicts"]["loop_du"]
    # docs/comparison.md: the FE contact is 3.6 % of u_A more compliant, beyond 0.35 % + 1 %
    assert 0.018 < du["difference"] < 0.072
    # in the apparatus of Figs. 6-7 (same profile) the displacement agrees
    for name in ("exp-fig6", "exp-fig7"):
        assert sc[name]["verdicts"]["loop_du"]["holds"] is True


def test_closed_form_anchors(full):
    _, _, sc = full
    cf = sc["sphere-md"]["errors"]["closed_form"]
    # MDR: grid and time-step error only (docs/comparison.md: dissipation -0.016 %, stick radius < 1e-5)
    assert abs(cf["mdr"]["dissipation"]) < 4e-4 and abs(cf["mdr"]["stick_radius"]) < 2e-5
    # FE at a/80 (docs/comparison.md: dissipation +0.10 %, stick radius +0.02 %, traction 0.4 % relative L2)
    assert 0 < cf["fem"]["dissipation"] < 0.0025
    assert abs(cf["fem"]["stick_radius"]) < 5e-4
    assert abs(cf["fem"]["contact_radius"]) < 1e-4
    assert cf["fem"]["traction_profile"] < 0.01 and cf["fem"]["pressure_profile"] < 5e-4
    # flat punch below mu F_N: full stick, no dissipation (Mindlin 1949), both sides
    for name in ("flat-md", "geom-flat"):
        for side in ("mdr", "fem"):
            assert sc[name][side]["slip_index"] < 1e-3, (name, side)
            assert sc[name][side]["stick_radius"] == pytest.approx(sc[name]["scene"]["b"], rel=1e-9)


def test_stick_radius_converges_on_both_ladders(full):
    """Issue 11: the one stick radius converges on both ladders in every geometry scene
    (b = 5 um included). docs/comparison.md: MDR error bar below 3e-4 of c, FE below 1.7 %."""
    _, _, sc = full
    for name, r in sc.items():
        if r["scene"]["group"] != "geometry":
            continue
        v = r["verdicts"]["stick_radius"]
        scale = max(v["fem"], 1e-3 * r["fem"]["contact_radius"])
        assert v["mdr_error"] < 6e-4 * scale, (name, v["mdr_error"], scale)
        assert v["fem_error"] < 0.035 * scale, (name, v["fem_error"], scale)


def test_apparatus_delta_rises_with_kx(full):
    _, _, sc = full
    deltas = [sc[f"app-kx{k}"]["fem"]["slip_index"] for k in (1, 2, 10, 20)]
    assert all(b > a for a, b in zip(deltas, deltas[1:])), deltas


def test_half_space_breaks_for_a_small_block(full):
    _, _, sc = full
    rows = {r["variant"]: r for r in sc["validity"]["validity"]}
    big = abs(rows["default (200 a)"]["contact_radius_mdr_minus_fe"])
    small = abs(rows["block 3 a (cap 200 a)"]["contact_radius_mdr_minus_fe"])
    assert big < 0.005
    assert small > 3 * big and small > 0.002
    # a block of 30 contact radii is already a half-space for the contact radius
    assert abs(rows["block 30 a (cap 200 a)"]["contact_radius_vs_default"]) < 0.002
    # the size effect on the dissipation (mesh error cancelled) falls as the body grows
    for kind in ("block", "cap"):
        other = "cap" if kind == "block" else "block"
        eff = [abs(rows[f"{kind} {s} a ({other} 200 a)"]["dissipation_vs_default"]) for s in (3, 5, 10, 30)]
        assert all(x > y for x, y in zip(eff, eff[1:])), (kind, eff)
        assert eff[-1] < 0.001


def test_half_space_breaks_with_curvature(full):
    """The curvature axis: MDR holds at small a/R and fails at a/R = 5 %, where the FE
    dissipates measurably more than the half-space (the cap's compliance under shear).
    docs/comparison.md: +0.11 % at a/R = 0.46 %, +0.45 % at 1.5 %, +1.7 % at 5 % (nu = 0.29), +1.4 % and
    +2.0 % at 5 % for nu = 0.1 and 0.45; radii within 0.07 %."""
    _, _, sc = full
    rows = sc["validity-curvature"]["curvature"]
    by = {(r["a_over_R"], r["nu"]): r for r in rows}
    for x in (5e-4, 1.5e-3, 4.6e-3, 1.5e-2):  # no metric fails (graded holds, consistent or below resolution)
        assert by[(x, 0.29)]["holds"] is not False and by[(x, 0.29)]["grade"] != "undetermined", (x, by[(x, 0.29)])
    for nu in (0.1, 0.29, 0.45):
        big = by[(5e-2, nu)]
        assert big["holds"] is False and big["verdicts"]["dissipation"]["holds"] is False, nu
        assert big["dissipation_effect"] > 2 * big["dissipation_effect_error"], nu
    eff = {x: by[(x, 0.29)]["dissipation_effect"] for x in (5e-4, 1.5e-3, 4.6e-3, 1.5e-2, 5e-2)}
    assert 0.0085 < eff[5e-2] < 0.034
    assert 0.0022 < eff[1.5e-2] < 0.009
    assert abs(eff[4.6e-3]) < 0.003 and abs(eff[5e-4]) < 0.003
    assert eff[5e-2] > eff[1.5e-2] > eff[4.6e-3]
    assert 0.007 < by[(5e-2, 0.1)]["dissipation_effect"] < by[(5e-2, 0.45)]["dissipation_effect"] < 0.04
    for r in rows:
        for q in ("contact_radius", "stick_radius"):
            assert abs(r[f"{q}_effect"]) < 0.0015, (r["a_over_R"], r["nu"], q)


def test_tolerances_hold_for_bodies_of_ten_radii(full):
    """docs/comparison.md: MDR's half-space error stays within the tolerances (0.5 % dissipation, 0.2 %
    contact radius) once both bodies are 10 contact radii large (and a/R <= 1.5 %, above)."""
    _, _, sc = full
    rows = {r["variant"]: r for r in sc["validity"]["validity"]}
    for label in ("block 10 a (cap 200 a)", "block 30 a (cap 200 a)", "cap 10 a (block 200 a)",
                  "cap 30 a (block 200 a)", "block 10 a, cap 10 a"):
        r = rows[label]
        assert abs(r["dissipation_vs_default"]) < 0.005 and abs(r["contact_radius_vs_default"]) < 0.002, label
    # and not below: a block of 3 contact radii (docs/comparison.md: -2.4 % dissipation)
    assert -0.048 < rows["block 3 a (cap 200 a)"]["dissipation_vs_default"] < -0.012


def _pct(r, q):
    """MDR - FE of a scalar metric in % of its docs/comparison.md reference (FE contact radius or dissipation)."""
    v = r["verdicts"][q]
    ref = r["fem"]["contact_radius"] if q != "dissipation" else abs(v["fem"])
    return 100 * v["difference"] / ref, 100 * v["fem_error"] / ref


def test_readme_catalogue_table(full):
    """docs/comparison.md's table "What the full catalogue shows", each bound with a 2.5x margin."""
    _, _, sc = full
    d, e = _pct(sc["sphere-md"], "dissipation")
    assert -0.28 < d < 0 and e < 0.95
    for name in ("geom-sphere", "geom-b5um", "geom-b10um", "geom-b20um"):
        r = sc[name]
        assert abs(_pct(r, "contact_radius")[0]) < 0.175 and _pct(r, "contact_radius")[1] < 1.5, name
        assert abs(_pct(r, "stick_radius")[0]) < 0.3 and _pct(r, "stick_radius")[1] < 2.0, name
        assert -0.3 < _pct(r, "dissipation")[0] < 0.0 and _pct(r, "dissipation")[1] < 1.25, name
    for name in ("geom-b30um", "geom-b50um"):
        assert abs(_pct(sc[name], "contact_radius")[0]) < 0.1 and abs(_pct(sc[name], "stick_radius")[0]) < 0.7, name
    for name in ("geom-b100um", "geom-flat", "flat-md"):
        assert abs(_pct(sc[name], "contact_radius")[0]) < 0.025 and abs(_pct(sc[name], "stick_radius")[0]) < 0.0025
        assert sc[name]["verdicts"]["dissipation"]["difference"] == 0.0 or name == "geom-b100um"
    for name in ("exp-fig4", "exp-fig5", "exp-fig6", "exp-fig7", "app-kx1", "app-kx2", "app-kx10", "app-kx20"):
        r = sc[name]
        assert abs(_pct(r, "contact_radius")[0]) < 0.15, name
        # the FE error bar includes the time step's (measured up to 0.082 % at 120 steps per cycle)
        assert 0 < _pct(r, "dissipation")[0] < 0.65 and _pct(r, "dissipation")[1] < 0.2, name
        assert abs(r["mdr"]["slip_index"] - r["fem"]["slip_index"]) < 0.0025, name


def test_mindlin_assumptions_in_3d(full):
    """docs/fem3d.md "Mindlin's assumptions in 3D" (scene assumptions-3d, each effect against the same
    3D mesh with the assumption imposed, both runs settled). The free traction direction lowers the
    sphere's stationary dissipation by 0.49 +- 0.04 % (a half-space boundary-element solution without
    Mindlin's approximation: -0.2 +- 0.4 %), within the tolerance: the assumption holds; the largest
    traction angle is 0.10 (half-space: ~0.1). The coupling of steel on aluminium (beta = +0.11)
    leaves the stationary cycle within its error (-0.5 +- 2 %) but raises the friction work of the first
    cycle after the normal loading by 30 +- 2 %: there MDR's uncoupled answer does not hold. The 3D pressure at F0
    with the assumptions imposed holds MDR's (pressure radius within 0.1 %). Bounds 2x."""
    _, _, sc = full
    rows = {r["variant"].split("[", 1)[1].rstrip("]"): r for r in sc["assumptions-3d"]["assumptions3d"]}
    sphere, coupling = rows["direction: sphere"], rows["coupling: E2 = 70 GPa, nu2 = 0.33"]
    d = sphere["verdicts"]["dissipation"]
    not_failed = ("holds", "consistent within its spread")
    assert -0.0094 < d["effect"] < -0.0019 and d["error"] < 0.0026 and d["grade"] in not_failed
    assert 0.06 < sphere["traction_angle_max"] < 0.25 and sphere["grade"] in not_failed
    assert coupling["verdicts"]["dissipation"]["grade"] in not_failed
    # the first cycle's friction work after the normal loading, coupled against uncoupled on each mesh
    # (docs/fem3d.md: +30 +- 2 %; Table 2's varying normal force)
    first = coupling["verdicts"]["dissipation_first_cycle"]
    assert 0.15 < first["effect"] < 0.6 and first["holds"] is False and coupling["holds"] is False
    # the 3D pressure against MDR's, by the pressure radius of the imposed runs (docs/fem3d.md: -0.04 +- 0.44,
    # -0.10 +- 0.23, -0.04 +- 0.44 %; a/5 0.16-0.41 % off, the finer levels within 0.1 %): it holds on
    # every variant
    for name, row in rows.items():
        pr = row["pressure"]
        bound = 0.002 if "b = 20 um" in name else 0.001
        assert pr["grade"] in not_failed and abs(pr["difference"]) < bound and pr["error"] < 0.009, pr
        assert all(abs(x) < 0.002 for x in pr["levels"][1:]) and 0.0008 < abs(pr["levels"][0]) < 0.008, pr
    # the 3D cycles settle geometrically, the pairs run on together until both settle to 1e-4 per cycle
    # (docs/fem3d.md: the direction pairs after 4-12 cycles, the coupled pair after 10-18): every
    # level's pair ran the same cycles and settled, the coupled pair at its finest level past the
    # scene's 4, and the settling error is part of each cycle effect's error bar
    for row in rows.values():
        for lv in row["levels"]:
            assert lv["on"]["settled"] and lv["off"]["settled"], (row["variant"], lv["h"])
            assert lv["on"]["cycles_run"] == lv["off"]["cycles_run"] >= 4
            W = np.asarray(lv["on"]["dissipation_per_cycle"])
            assert abs(W[-1] / W[-2] - 1) <= 1e-4
        st = row["verdicts"]["dissipation"]["settling"]
        assert st["status"] == "stationary" and row["verdicts"]["dissipation"]["error"] >= st["error"]
    assert coupling["levels"][-1]["on"]["cycles_run"] > 8


def test_the_docs_tables_are_what_the_catalogue_gives(full):
    """The generated tables of docs/*.md (``python -m validation.docs``) against this run: the words
    (grades, verdicts) exactly, the numbers within the check's tolerance. A table left behind by a
    change of the code fails here."""
    from validation import docs

    _, _, sc = full
    diffs = docs.check(sc)
    assert not diffs, "\n".join(diffs[:10])


def test_rough_surfaces_in_the_catalogue(full):
    """docs/rough.md, *The scene roughness*: on the smooth sphere the rough half-space's engine agrees with
    MDR (exact there) within its grid error and the tolerance; on rough surfaces the smooth profile misses
    the dissipation and the stiffness far beyond every error bar from rms 100 nm on (docs: -44 % and
    +32 % at 100 nm, -70 % and +201 % at 1 um), while the equivalent profile stays within its spread on
    the dissipation (docs: -1.1, -1.0, +5.7 %) and is a few per cent stiff (docs: +1.3 to +1.8 %). The
    plastic row is told apart by its hardness."""
    _, _, sc = full
    rows = {r["rms"]: r["verdicts"] for r in sc["roughness"]["roughness"] if not r.get("hardness")}
    assert set(rows) == {0.0, 30e-9, 100e-9, 1e-6, 3.2e-6}
    # the plastic row (docs: rms 1 um, flattened at 0.75 N): a larger real contact than the elastic one's
    # (docs: 0.15 against 0.10 of Hertz's), the smooth profile still far too stiff (docs: +121 +- 29 %), the
    # equivalent one within its spread on the dissipation
    elastic, plastic = ([r for r in sc["roughness"]["roughness"] if r["rms"] == 1e-6 and bool(r.get("hardness")) == h]
                        for h in (False, True))
    assert len(plastic) == 1 and plastic[0]["preload"] == 0.75
    assert plastic[0]["contact_area_over_smooth"] > 1.2 * elastic[0]["contact_area_over_smooth"]
    k = plastic[0]["verdicts"]["mdr_smooth:stiffness"]
    assert k["grade"] == "fails" and k["difference"] > 0.4
    assert plastic[0]["verdicts"]["mdr_equivalent:dissipation"]["grade"] != "fails"
    for k, v in rows[0.0].items():
        assert v["grade"] != "fails" and abs(v["difference"]) < 0.03, k  # docs: within 1 %
    for rms in (100e-9, 1e-6):
        d, k = rows[rms]["mdr_smooth:dissipation"], rows[rms]["mdr_smooth:stiffness"]
        assert d["grade"] == "fails" and d["difference"] < -0.2 and k["grade"] == "fails" and k["difference"] > 0.1
    # driven by the apparatus at the paper's points (docs: the equivalent MDR within 0.002, the smooth
    # sphere's slip index two to four times the rough one's: off by 0.19-0.36)
    _driven_by_the_apparatus([r for r in sc["roughness"]["roughness"] if r["rms"] in (1e-6, 3.2e-6)], 0.006, 0.1)
    for rms in (30e-9, 100e-9, 1e-6):
        e = rows[rms]["mdr_equivalent:dissipation"]
        assert e["grade"] != "fails" and e["error"] < 0.8, rms
        assert 0.0 < rows[rms]["mdr_equivalent:stiffness"]["difference"] < 0.05, rms


def test_rough_flat_faces_in_the_catalogue(full):
    """docs/rough.md, *The flat faces*: every face of the budget's points is run with 4 surfaces at rms 1 um and
    at the paper's 3.6 um, b = 100 um and 0.6 mm plastic too; a rough face touches on less than 1 % of the smooth face's contact (asserted:
    3 %), the smooth MDR is 8-56 times too stiff (asserted: more than 3 times) and misses the dissipation
    (the smooth face sticks: -100 %), while the equivalent profile has the stiffness within a few per cent
    (asserted: 10 %) and the dissipation within its spread."""
    _, _, sc = full
    rows = sc["roughness-faces"]["roughness"]
    assert sorted((r["b"], r["rms"], bool(r.get("hardness"))) for r in rows) == sorted(
        [(b, rms, False) for b in (50e-6, 100e-6, 600e-6, 1e-3) for rms in (1e-6, 3.6e-6)]
        + [(b, rms, True) for b in (100e-6, 600e-6) for rms in (1e-6, 3.6e-6)])
    for r in rows:
        v = r["verdicts"]
        assert len(r["seeds"]) == 4 and r["contact_area_over_smooth"] < 0.03, r["b"]
        assert v["mdr_smooth:stiffness"]["difference"] > 2.0, r["b"]
        if r["rms"] == 1e-6:  # the paper's 3.6 um: a member may stick entirely on one grid (undetermined)
            assert not r["failed"] and v["mdr_smooth:dissipation"]["difference"] < -0.9
            assert abs(v["mdr_equivalent:stiffness"]["difference"]) < 0.1, r["b"]
            assert v["mdr_equivalent:dissipation"]["grade"] != "fails", r["b"]
    _driven_by_the_apparatus(rows, 0.015, 0.1)  # docs: within 0.006; the smooth MDR off by 0.24-0.8


def _driven_by_the_apparatus(rows, eq_bound, smooth_above):
    """docs/rough.md, *Driven by the apparatus*: every row ran every point of its indenter
    (validation.paper_points.rough_points; a plastic surface those within its flattening load) on every seed
    on the finest grid with a determined slip index and standard error; MDR with the equivalent profile follows the rough
    half-space within ``eq_bound`` at every point, the smooth indenter's MDR is off by more than
    ``smooth_above`` at one point of every row at least."""
    from validation.paper_points import Point, rough_points

    for r in rows:
        want = [p for p in rough_points(r["b"]) if not r.get("hardness") or p.F0 + p.dF <= r["preload"] * (1 + 1e-9)]
        got = {Point(**x["point"]): x for x in r["apparatus"]}
        assert set(got) == set(want), (r["b"], r["rms"])
        worst = 0.0
        for p, x in got.items():
            rh = x["rough_halfspace"]
            assert rh["mean"] is not None and rh["status"] == "finest grid only" and rh["sem"] < 0.15, (p, rh)
            assert abs(x["equivalent_minus_rough"]["mean"]) < eq_bound, (p, x)
            worst = max(worst, abs(x["mdr_smooth"] - rh["mean"]))
        assert worst > smooth_above, (r["b"], r["rms"], worst)


def test_the_budget_of_the_paper_from_the_catalogue(paper_budget):
    """docs/budget.md, run as a user runs it (python -m validation.budget on the catalogue's folder):
    negligible where docs/budget.md says so (size, coupling, the kink, the sphere's tilt); no bound
    matters (the tilt is the paper's inequality); the roughness and the plates are ranges over the readings
    the paper's loops admit, each admitted reading inside its range, graded by the range's far end; the
    smooth model is admitted by its own loops (the plates' reference reading)."""
    from validation import spectra as SP
    from validation.budget_readings import grade_range

    out, b = paper_budget
    assert (out / "budget.md").read_text().startswith("# The error budget")
    assert not b["stale"]
    cells = {x["key"]: x["cells"] for x in b["rows"]}
    for key, c in cells.items():
        for col in ("size", "coupling"):
            assert c[col]["verdict"] == "negligible", (key, col)
        for col, x in c.items():
            if x["kind"] == "bound":
                assert x["verdict"] != "matters", (key, col, x)
    assert cells["figs4-5"]["tilt"]["effect"] == 0.0 and cells["figs6-7"]["kink"]["verdict"] == "negligible"
    for key in ("figs6-7", "fig8"):
        assert cells[key]["tilt"]["kind"] == "bound" and cells[key]["tilt"]["verdict"] == "undetermined"
    # the ranges: every admitted reading inside, the verdict the range's
    for key, c in cells.items():
        for col in ("roughness", "plates"):
            x = c[col]
            if x["range"] is None:
                assert x["verdict"] == "undetermined", (key, col, x)
                continue
            lo, hi = x["range"]
            for name in x["admitted"]:
                assert lo - 1e-12 <= x["readings"][name]["effect"] <= hi + 1e-12, (key, col, name)
            # an admitted reading the contact's grid does not resolve leaves the cell undetermined
            expected = "undetermined" if x.get("unresolved") else grade_range(lo, hi, x["error"])
            assert x["verdict"] == expected, (key, col, x)
    plates = {p["reading"]: p for p in b["plates_consistency"]}
    assert plates["axial"]["admitted"]  # the paper's own model reproduces its loops
    for kind in ("sphere", "face"):
        assert len(b["consistency"][kind]) == len(SP.READINGS) and all(len(r["surfaces"]) == 4 for r in b["consistency"][kind])
    kx = {t["reading"]: t["kx"] for t in b["transition"]["rows"]}
    assert 0.9e6 < kx["smooth"] < 1.1e6
    # docs/budget.md, "What it shows": the loops exclude the elastic readings whose waviness ends near the
    # sphere's contact (2.7-3.1 um in its window) and admit the ISO ones (1.5-2.2 um) and every face reading
    cons = {r["reading"]: r for r in b["consistency"]["sphere"]}
    for name in ("waviness ends at 8 a", "waviness ends at 2 a"):
        assert not cons[name]["admitted"] and 2.2e-6 < cons[name]["window"]["rms"] < 3.6e-6, name
    for name in ("ISO band", "ISO band, H 0.5", "ISO band, H 1", "ISO band, plastic", "ISO band, profile Rq"):
        assert cons[name]["admitted"] and 1.2e-6 < cons[name]["window"]["rms"] < 2.6e-6, name
    assert all(r["admitted"] for r in b["consistency"]["face"])
    # roughness matters whatever the admitted spectrum (lowering the slip index by about 0.08-0.45), is
    # undetermined on Fig. 9's small faces (unresolved readings); the transition 1.0-2.6 N/um
    for key in ("figs4-5", "figs6-7", "fig8", "table2"):
        x = cells[key]["roughness"]
        assert x["verdict"] == "matters" and -0.9 < x["range"][0] and x["range"][1] < -0.04, (key, x["range"])
    assert cells["fig9"]["roughness"]["verdict"] == "undetermined" and cells["fig9"]["roughness"]["unresolved"]
    lo, hi = b["transition"]["range"]
    assert 0.8e6 < lo < 1.4e6 and 1.8e6 < hi < 4e6  # the paper's 1-2 N/um inside
    for key, c in cells.items():  # the plates: undetermined, -0.03 to +0.09
        assert c["plates"]["verdict"] == "undetermined" and -0.06 < c["plates"]["range"][0] <= 0 <= c["plates"]["range"][1] < 0.18
    # the statements of docs/budget.md, "What it shows" (2-3x margins)
    for key, c in cells.items():
        assert abs(c["size"]["effect"]) + c["size"]["error"] < 2e-3, key  # docs: < 1e-3
        if c["kink"]["effect"] is not None:
            assert abs(c["kink"]["effect"]) + c["kink"]["error"] < 2e-3, key  # docs: < 1e-3
    # the traction direction, measured in 3D at every point of every result (docs: below 1e-4)
    for key, c in cells.items():
        d = c["direction"]
        assert d["verdict"] == "negligible" and d["kind"] == "absolute", (key, d)
        assert abs(d["effect"]) + d["error"] < 3e-4, (key, d)
    # the half-space's shape, measured at every point of every result (docs: < 2e-3; FE - MDR within 3e-4,
    # error bars below 1.3e-3; docs/comparison.md, "At the paper's own points")
    for key, c in cells.items():
        cv = c["curvature"]
        assert cv["verdict"] == "negligible" and cv["kind"] == "absolute", (key, cv)
        assert abs(cv["effect"]) + cv["error"] < 4e-3, (key, cv)


@pytest.mark.parametrize("fig", ["fig4", "fig5"])
def test_the_equivalent_profiles_bar_holds_the_rough_half_space_on_an_admitted_reading(full, fig):
    """The bar of a roughness reading holds what MDR with a surface's equivalent profile misses of the rough
    half-space (``equivalent_error``, measured on the catalogue's rough scenes): checked on a reading the
    paper's loops admit, the ISO band on the sphere, its four surfaces on the finer grid, each driven by
    the apparatus at the loop's point as the rough half-space itself (rough.law), against its equivalent
    MDR's slip index within that error and the curve's sampling (the budget's cached surfaces)."""
    from mdr.apparatus import Apparatus, run_apparatus
    from mdr.loading import Loading
    from mdr.materials import Materials
    from rough.law import RoughContact
    from studies.paper import RES
    from validation import budget_readings as BR
    from validation import spectra as SP
    from validation.paper_points import loop_point

    _, out, sc = full
    E = BR.equivalent_error(lambda name: sc.get(name))
    assert E is not None and E < 0.02
    R = BR.Readings(SP.curves([SP.SPHERE], out / "readings", jobs=2))
    p = loop_point(fig)
    for m in R.members(0.0, 0)[-1]:
        _, _, grid, heights, prof = SP.surface(m)
        law = RoughContact(prof, Materials(), p.mu1, grid, heights)
        loading = Loading.apparatus(p.F0, p.dF, 0.0, p.ua, cycles=RES["cycles"], steps=RES["steps"])
        rough = float(run_apparatus(law, Apparatus(kx=p.kx, mu2=p.mu2), loading)["slip_index"])
        eq, half = R.slip_index(m, p), R.slip_index(m, p, every=2)
        assert abs(rough - eq) <= E + abs(half - eq), (m["seed"], rough, eq, E)


def test_the_half_space_shape_at_the_papers_points(full):
    """docs/comparison.md, "At the paper's own points": FE - MDR of the slip index below 3e-4 at each of
    the 17 points (asserted: 1e-3) with error bars below 1.3e-3 (asserted: 3e-3), every point partial or
    gross slip or stick as MDR says; at b = 1 mm, k_x = 20 N/um the FE loop's F_x differs by about 1.2 %
    of mu F0 (asserted: 0.5-3 %)."""
    _, _, scenes = full
    rows = scenes["halfspace-points"]["points"]
    assert len(rows) == len(CATALOGUE["halfspace-points"].variants) == 17
    for r in rows:
        assert abs(r["effect"]) < 1e-3 and r["error"] < 3e-3, r
    wide = next(r for r in rows if r["b"] == 1e-3 and r["kx"] == 20e6)
    assert 0.15 < wide["a_over_R"] < 0.2
    assert 0.005 < abs(wide["verdicts"]["loop_Fx"]["difference"]) < 0.03


def test_the_traction_direction_at_the_papers_points(full):
    """docs/fem3d.md, "At the paper's points": in the apparatus the free traction moves no slip index of
    the 23 points by more than 1e-4 with its error bar (asserted: 3e-4); on the sphere of Figs. 4-5 it
    raises it (4-8e-5), where under force control it lowers the dissipation (-0.49 %); the faces of
    b = 0.6 and 1 mm hardly slip partially: below 1e-6 (asserted: 3e-6)."""
    _, _, scenes = full
    rows = scenes["direction-points"]["points"]
    assert len(rows) == len(CATALOGUE["direction-points"].variants) == 23
    for r in rows:
        assert abs(r["effect"]) + r["error"] < 3e-4, r
    sphere = [r for r in rows if r["b"] == 0.0]
    assert len(sphere) == 2 and all(r["effect"] - r["error"] > 0 for r in sphere), sphere
    wide = [r for r in rows if r["b"] >= 0.6e-3]  # docs: below 1e-6 (measured at most 4.7e-7)
    assert len(wide) == 5 and all(abs(r["effect"]) < 3e-6 for r in wide), wide


def test_the_tilt_at_the_papers_points(full):
    """docs/fem3d.md, "the face tilted in the apparatus": every one of the 19 faces resolved; where the
    face is the whole contact (b >= 50 um) and the point slides, the tilt lowers its slip index by
    0.02-0.06 (asserted 0.01-0.1) beyond its error bar; the 10 um faces and the points in partial slip
    (k_x = 0.3 N/um) move by less than 1e-3 (asserted 3e-3)."""
    _, _, scenes = full
    rows = scenes["tilt-points"]["points"]
    assert len(rows) == len(CATALOGUE["tilt-points"].variants) == 19
    for r in rows:
        assert r["effect"] is not None and r["contact_vertices"] >= 10, r
        if r["b"] >= 50e-6 and r["kx"] != 0.3e6:
            assert -0.1 < r["effect"] < -0.01 and abs(r["effect"]) > 2 * r["error"], r  # measured >= 4
        else:
            assert abs(r["effect"]) + r["error"] < 3e-3, r
    # Fig. 6's point against the same experiment run on its own by tests/test_punch3d.py (FEContact3D and
    # run_apparatus directly, band b/50: -10.3 % of the slip index in its benchmark)
    fig6 = next(r for r in rows if r["b"] == 0.6e-3 and r["F0"] == pytest.approx(0.31))
    assert -0.2 < fig6["effect"] / fig6["slip_index"] < -0.05, fig6


def test_tilt_family(full):
    """The catalogue's tilt family (the docs/fem3d.md numbers): the aligned answer is not contradicted on the
    dissipation (graded consistent within the two levels' spread; catalogue tolerance: 0.5 %, or 1e-4
    of 4 mu F0 u_A where the aligned face sticks) up to 0.3
    theta_c and fails from 0.5 theta_c on for the flat punch b = 100 um (3.4e-5, 5.7e-5 rad) and the
    truncated sphere b = 0.6 mm (9.5e-7, 1.6e-6 rad); the truncated sphere b = 20 um, mostly spherical,
    holds at 8.6e-5 rad and loses dissipation from 2.9e-4 rad on (measured -6.4 +- 1.9 %, -27 +- 9 % at
    pi/3600). At theta_c the punch slips (slip index 0.022) and its du loop widens (+24 %). The punch's
    mesh is refined at its loaded edge (``TILT_REFINE_PUNCH``), so at pi/3600 its edge crescent is
    resolved (measured 0.162, 0.178 of the face on the two levels, 42 vertices): the aligned answer
    fails there (slip index +0.031 +- 0.002, dissipation +0.067 +- 0.006 of 4 mu F0 u_A). The edge
    contact of b = 0.6 mm at pi/3600 (2 % of its face on these meshes) spans under 10 vertices:
    undetermined; on its own meshes banded along the loaded rim arc (b/33, b/50) it is resolved
    (0.0046 of the aligned contact, 20 vertices) and the aligned answer fails (slip index +0.024 where
    the aligned face sticks; dissipation +0.18 of 4 mu F0 u_A; the du loop 7.5 aligned u_A away). Read
    from the catalogue's run (the README's command), which computes the scene once."""
    flat, t20, t600, t600b = full[2]["tilt"]["tilt"]
    for row in (flat, t600):
        assert row["holds_below_ratio"] == pytest.approx(0.3, rel=1e-9)
        assert row["fails_at"] / row["theta_c"] == pytest.approx(0.5, rel=1e-9)
    assert t20["holds_below"] == pytest.approx(t20["points"][0]["tilt"], rel=1e-12)
    d = [p["aligned"]["dissipation"] for p in t20["points"]]
    assert d[1]["holds"] is False and d[1]["effect"] < 0 and d[-1]["effect"] < d[1]["effect"]
    at_c = next(p for p in flat["points"] if abs(p["ratio"] - 1) < 1e-9)
    assert 0.01 < at_c["aligned"]["slip_index"]["effect"] < 0.04  # the aligned punch: 0 (measured 0.022)
    assert 0.12 < at_c["aligned"]["loop_du"]["effect"] < 0.5  # measured 0.24
    assert -0.15 < d[1]["effect"] < -0.02 and -0.6 < d[-1]["effect"] < -0.1  # measured -0.064, -0.27
    # the punch at the paper's bound: its refined edge resolves the crescent, the aligned answer fails
    bound = flat["points"][-1]
    assert bound["resolved"] is True and bound["holds"] is False
    assert 0.14 < bound["contact_area_fraction"] < 0.22  # measured 0.178 (0.162 on the coarse level)
    assert 0.015 < bound["aligned"]["slip_index"]["effect"] < 0.06  # measured 0.031
    assert 0.03 < bound["aligned"]["dissipation"]["effect"] < 0.15  # measured 0.067 (of 4 mu F0 u_A)
    # b = 0.6 mm at the bound: not resolved on these meshes, undetermined, never a verdict
    assert t600["points"][-1]["contact_area_fraction"] < 0.04  # measured 0.019
    assert t600["points"][-1]["resolved"] is False and t600["points"][-1]["holds"] is None
    # ... and on its banded meshes resolved: the crescent slips where the aligned face sticks
    (band,) = t600b["points"]
    assert band["resolved"] is True and band["holds"] is False
    assert 0.002 < band["contact_area_fraction"] < 0.009  # measured 0.0046 (+- 0.0015)
    assert 0.012 < band["aligned"]["slip_index"]["effect"] < 0.06  # measured 0.024 (b/70 benchmark: 0.029)
    assert 0.08 < band["aligned"]["dissipation"]["effect"] < 0.4  # measured 0.18 (of 4 mu F0 u_A)
    assert 3 < band["aligned"]["loop_du"]["effect"] < 20  # measured 7.5 +- 0.5


def test_full_hard_cases_table(full_run):
    """quick=False: finer meshes (a/80, a/160), 50 FE cycles, and the a/320 mesh; the rows of the catalogue's
    run (the README's command runs the full hard cases once, ``validation.hard_cases.hard_cases``)."""
    from test_hard_cases import check_row

    proc, out = full_run
    assert proc.returncode == 0, proc.stderr[-3000:]
    rows = json.loads((out / "results.json").read_text())["hard_cases"]
    expected_flagged = {"normal penalty 0.1, pure penalty", "normal penalty 0.1, augmented Lagrangian",
                        "friction penalty 0.1, pure penalty", "friction penalty 0.1, augmented Lagrangian",
                        "mesh h = a/5"}
    for r in rows:
        assert r["status"] != "error", r
        check_row(r)
        if r["name"] not in expected_flagged:
            assert r["status"] == "ok", r
    names = {r["name"] for r in rows}
    assert "mesh h = a/320 (normal)" in names and "gross slip u_A = 10 u*, 50 cycles" in names
    fine = next(r for r in rows if r["name"] == "mesh h = a/320 (normal)")
    assert fine["error"] < 6e-4 and fine["iterations"] < 20  # measured 2.1e-4, 12 Newton / 2 AL
