"""Hard cases of issue 7, each against an independent truth (see validation/hard_cases.py,
which runs the same cases for the report's "hard cases" table).

Truths: Boussinesq flat punch, truncated-sphere closed forms, Hertz, Cattaneo-Mindlin,
Mindlin-Deresiewicz (any nu with the two-body E*, G*), the gross-slip dissipation of any
profile, energy (loop area = friction work), Coulomb |F_x| <= mu F_N, refinement.
"""
import numpy as np
import pytest

from validation import hard_cases as hc

KEYS = {"name", "model", "status", "iterations", "error", "tol", "truth", "time_s", "note"}
MARGIN = 3.0  # a row's tolerance is at most 3x its measured error (issue 11: margins 2-3x, not 10x)


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("hard_case_meshes")


def check_row(r):
    """Every row: its own measured error (a real number, never a 0/1 pass flag; None only
    with a note saying why), its tolerance, and a status that is the pass/fail."""
    assert KEYS <= set(r), r
    assert r["model"] in ("mdr", "fem", "fem3d") and r["status"] in ("ok", "flagged")
    assert r["time_s"] >= 0 and r["truth"]
    assert isinstance(r["tol"], float) and r["tol"] > 0, r
    if r["error"] is None:
        assert r["status"] == "flagged" and r["note"], r
    else:
        assert isinstance(r["error"], float) and not isinstance(r["error"], bool) and r["error"] >= 0, r
        assert (r["status"] == "ok") <= (r["error"] <= r["tol"]), r
    if r["status"] == "ok" and r["error"] >= hc.ROUNDOFF:
        # the tolerance is no looser than 3x what is measured (rows exact to rounding excepted)
        assert r["tol"] <= MARGIN * r["error"], (r["name"], r["model"], r["error"], r["tol"])


def rows_of(case, cache, quick=True):
    rows = case(quick, cache)
    for r in rows:
        check_row(r)
    return {(r["name"], r["model"]): r for r in rows}


def assert_ok(row):
    assert row["status"] == "ok", row
    assert row["error"] is not None and row["error"] <= row["tol"], row


def test_flat_punch_singular_edge_fixed_radius_stick_then_gross_slip(cache):
    rows = rows_of(hc.case_flat_punch, cache)
    for r in rows.values():
        assert_ok(r)
    fe = rows[("flat punch: normal stiffness, pressure, fixed radius", "fem")]
    assert fe["pressure_error"] < 0.02
    # the edge pressure is singular: it grows under refinement (Boussinesq: like h^(-1/2))
    pe = fe["edge_pressure"]
    assert pe[1] > 1.2 * pe[0]
    mdr = rows[("flat punch: full stick then sudden gross slip", "mdr")]
    assert mdr["error"] < 1e-12 and mdr["stick_radius_before"] == pytest.approx(30e-6, rel=1e-12, abs=0) and mdr["stick_radius_after"] == 0
    fe_t = rows[("flat punch: full stick then sudden gross slip", "fem")]
    # measured at b/20: stick radius 1.000 b (the edge extrapolated from the sticking pairs,
    # mdr.stick), slip index 4.7e-4 (at b/40: 1.000 b, 1.9e-4)
    assert fe_t["stick_radius_min"] > 0.997 * 30e-6 and fe_t["slip_index"] < 1.2e-3


def test_truncated_sphere_edge_inside_at_and_beyond_the_contact_edge(cache):
    rows = rows_of(hc.case_truncated_edge, cache)
    assert len(rows) == 6
    for (name, model), r in rows.items():
        assert_ok(r)
        if model == "fem":  # the weak (log) singularity at the kink does not spoil the pressure elsewhere
            assert r["pressure_error"] < 0.01


def test_gross_slip_ten_times_u_star_many_cycles_without_drift(cache):
    rows = rows_of(hc.case_gross_slip_many_cycles, cache)
    for r in rows.values():
        assert_ok(r)
        assert r["drift"] < 6e-13  # docs/comparison.md: drift 2e-13 mu F_N (measured 2.3e-13 MDR, 3.4e-14 FE)
    assert ("gross slip u_A = 10 u*, 50 cycles", "mdr") in rows


def test_vanishing_contact_and_contact_lost(cache):
    rows = rows_of(hc.case_vanishing_contact, cache)
    for r in rows.values():
        assert_ok(r)
    assert {("F_N = 0: contact lost", m) for m in ("mdr", "fem")} <= set(rows)
    for m in ("mdr", "fem"):  # it was in partial slip before the contact was lost
        lost = rows[("F_N = 0: contact lost", m)]
        assert lost["error"] <= hc.ROUNDOFF and "before: F_x = 0.06" in lost["note"]


@pytest.mark.slow  # an integration run of ~10 s; the fast suite stays under 5 min
def test_3d_model_hard_cases(cache):
    """The 3D half model: gross slip at 10 u* (friction work against Mindlin-Deresiewicz within
    2e-3, measured 7.8e-4; no drift; |F_x| <= mu F_N to rounding), the normal force down to 1 %
    (loop area = friction work within the time-step error, no NaN), contact lost and regained."""
    rows = rows_of(hc.case_3d, cache)
    for r in rows.values():
        assert_ok(r)
    gross = next(r for (n, m), r in rows.items() if n.startswith("gross slip"))
    assert gross["model"] == "fem3d" and gross["drift"] < 6e-13
    lost = rows[("F_N = 0: contact lost", "fem3d")]
    assert lost["error"] <= hc.ROUNDOFF and "before: F_x = 0.06" in lost["note"]


def test_vanishing_contact_energy_gap_is_a_time_step_error():
    """MDR with F_N down to 1 %: loop area - friction work is first order in the time step."""
    from mdr import MDRContact, Sphere
    from mdr.loops import loop_integral

    def gap(steps):
        t, s = hc._harmonic(3, steps)
        FN = hc.F * (1 + 0.99 * np.sin(2 * np.pi * t + np.pi / 2))
        H = MDRContact(Sphere(hc.R), hc.STEEL, hc.MU, F_max=FN.max()).run(u=0.5 * hc._u_star() * s, F_N=FN)
        last = slice(2 * steps, 3 * steps + 1)
        return abs(loop_integral(H.u[last], H.Fx[last]) / np.sum(H.work[2 * steps + 1:]) - 1)

    g = [gap(n) for n in (200, 400, 800)]
    assert g[0] > 1.6 * g[1] > 2.56 * g[2]


def test_friction_extremes(cache):
    rows = rows_of(hc.case_friction_extremes, cache)
    for r in rows.values():
        assert_ok(r)
    assert {n for n, _ in rows} == {"mu = 0.01", "mu = 1", "mu = 0 (frictionless)"}
    assert rows[("mu = 0 (frictionless)", "mdr")]["error"] == 0.0 == rows[("mu = 0 (frictionless)", "fem")]["error"]


def test_penalty_extremes_are_flagged_detected_or_handled(cache):
    rows = rows_of(hc.case_penalty_extremes, cache)
    soft = rows[("normal penalty 0.1, pure penalty", "fem")]
    # too soft: a large error (docs/comparison.md: 20 %, measured 20.2 %) that the model reports
    # (penetration) and warns about
    assert soft["status"] == "flagged" and soft["warned"] and 0.1 < soft["error"] < 0.4
    assert 0.1 < soft["penalty_error"] < 0.4
    # tangential penalty too soft: the stick radius is off by 10 % of a (dW only 0.5 %)
    fsoft = rows[("friction penalty 0.1, pure penalty", "fem")]
    assert fsoft["status"] == "flagged" and 0.05 < fsoft["stick_radius_error"] < 0.2
    assert abs(fsoft["dissipation_error"]) < 0.015
    for name in ("normal penalty 0.1, augmented Lagrangian", "friction penalty 0.1, augmented Lagrangian"):
        r = rows[(name, "fem")]
        # handled (converged to the truth) or detected (ConvergenceError), never a silent answer
        assert (r["converged"] and r["status"] == "ok") or (not r["converged"] and "ConvergenceError" in r["note"])
    # each row reports its own solve: the normal AL fails on its own; the tangential AL, started
    # from the exact Coulomb solution, converges at penalty 0.1 to the penalty-1e6 answer (the
    # normal forces differ by their AL tolerances, 1e-4 and 1e-8)
    assert "augmented Lagrangian: penetration" in rows[("normal penalty 0.1, augmented Lagrangian", "fem")]["note"]
    f01, f1e6 = (rows[(f"friction penalty {p}, augmented Lagrangian", "fem")] for p in ("0.1", "1e+06"))
    assert_ok(f01)
    assert "tangential AL passes" in f01["note"]
    assert f01["stick_radius_error"] == pytest.approx(f1e6["stick_radius_error"], rel=1e-3)
    assert "ConvergenceError" not in rows[("friction penalty 0.1, pure penalty", "fem")]["note"]
    # too stiff: the condensed (force) formulation stays well conditioned
    for name in ("normal penalty 1e+06, pure penalty", "normal penalty 1e+06, augmented Lagrangian",
                 "friction penalty 1e+06, augmented Lagrangian"):
        r = rows[(name, "fem")]
        assert_ok(r)
        assert not r.get("warned") and r["iterations"] < 10


def test_near_incompressible_does_not_lock(cache):
    """Force controlled: the dissipation at a force amplitude and the stick radius do not
    depend on the bodies' series compliance, so no calibration of the FE law enters."""
    r = rows_of(hc.case_incompressible, cache)[("nu = 0.49 (near-incompressible)", "fem")]
    assert_ok(r)
    assert r["hertz_error"] < 1.5e-3  # docs/comparison.md: Hertz error 6.1e-4 at a/20 (nu = 0.29: 6.8e-4)
    assert r["hertz_error"] < 3 * r["hertz_error_029"] + 1e-4
    assert abs(r["dissipation_error"]) < 3 * abs(r["dissipation_error_029"]) + 1e-3
    assert r["stick_radius_error"] < 3 * r["stick_radius_error_029"] + 1e-3


def test_apparatus_stiffness_from_sticking_to_sliding(cache):
    rows = rows_of(hc.case_apparatus_stiffness, cache)
    for r in rows.values():
        assert_ok(r)
    d = rows[("apparatus k_x = 0.1 .. 100 N/um", "mdr")]["slip_index"]
    assert np.all(np.diff(d) > 0) and d[0] < 0.01 and d[-1] > 0.5
    d_fe = rows[("apparatus k_x = 0.1 and 100 N/um", "fem")]["slip_index"]
    assert d_fe[0] < 0.01 and abs(d_fe[1] - d[-1]) < 0.01


def test_very_coarse_mesh_reports_a_large_error_fine_mesh_converges(cache):
    rows = rows_of(hc.case_mesh_extremes, cache)
    coarse = rows[("mesh h = a/5", "fem")]
    assert coarse["status"] == "flagged" and coarse["warned"]
    # large, but bounded and reported (docs/comparison.md: dW +4.1 %, stick radius 3.0 % of a)
    assert 0.02 < coarse["dissipation_error"] < 0.08 and 0.015 < coarse["stick_radius_error"] < 0.06
    fine = rows[("mesh h = a/80", "fem")]
    assert_ok(fine) and not fine["warned"]
    assert fine["stick_radius_error"] < coarse["stick_radius_error"] / 8  # ~ h: 16x finer


def test_a_failing_case_becomes_an_error_row(monkeypatch):
    def case_broken(quick, cache_dir):
        raise RuntimeError("boom\nsecond line")

    def case_fine(quick, cache_dir):
        return [hc._row("fine", "mdr", 0.0, 1.0, "nothing", 0.0)]

    monkeypatch.setattr(hc, "CASES", (case_broken, case_fine))
    seen = []
    row, fine = hc.hard_cases(log=seen.append)
    assert row["status"] == "error" and row["note"] == "RuntimeError: boom" and row["name"] == "broken"
    assert fine["status"] == "ok"
    assert seen == ["broken", "fine"]  # progress: once per case, with its name


def test_a_row_without_an_error_needs_a_note():
    with pytest.raises(ValueError, match="no error and no note"):
        hc._row("x", "fem", None, 1e-3, "truth", 0.0)
