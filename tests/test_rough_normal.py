"""Normal contact on the FFT grid (``rough.normal``): the smooth sphere against Hertz (a grid ladder at
two periods: the images fall with the period), the force exact, a vanishing roughness changes
nothing, the paper's roughness (rms 1 um) spreads a smaller real contact area over a larger radius."""
import numpy as np
import pytest

from common.errors import ConvergenceError, InputError

from mdr.materials import Materials
from mdr.profiles import make_profile
from mdr.reference import hertz

pytest.importorskip("tamaas", reason="rough contact needs tamaas: pip install tamaas")

from rough.normal import (HARDNESS_X5CRNI18_10, Grid, ensemble, force_approach, grid_ladder,  # noqa: E402
                         normal_contact, normal_error)
from rough.surfaces import HeightMap, RoughnessParams, generate, rms_slope  # noqa: E402

MAT, R, F = Materials(), 6e-3, 0.5
SPHERE = make_profile("sphere", R)
HZ = hertz(F, R, MAT.E_star)


def test_the_smooth_sphere_is_hertz_on_its_grid_ladder():
    """Period 16 a, pixels a/8 .. a/32: the pressure radius converges to Hertz's a (measured 0.99987 at
    a/32, the ladder asymptotic) and the peak pressure to p0 (1.00006); on a period of 8 a the images
    shift them by -0.13 % and +0.25 %: the period is an error of its own, 8x smaller at twice the period."""
    a, p0 = HZ["a"], HZ["p0"]
    lad = grid_ladder(SPHERE, MAT, F, 16 * a, ns=(128, 256, 512))
    pr, pm = lad["pressure_radius"], lad["p_max"]
    assert abs(pr["value"] / a - 1) < 4e-4 and abs(pm["value"] / p0 - 1) < 3e-4, (pr["values"], pm["values"])
    assert pr["status"] == "asymptotic" and abs(pr["extrapolated"] / a - 1) < 4e-4
    short = normal_contact(SPHERE, MAT, F, Grid(8 * a, 256))
    long = normal_contact(SPHERE, MAT, F, Grid(16 * a, 512))  # the same pixel, twice the period
    e8, e16 = short["pressure_radius"] / a - 1, long["pressure_radius"] / a - 1
    assert -2.5e-3 < e8 < -0.6e-3 and abs(e16) < abs(e8) / 4  # (a / period)^3: 8x (measured 9.6x)
    assert short["force"] == pytest.approx(F, rel=1e-9) and long["force"] == pytest.approx(F, rel=1e-9)


def test_roughness_vanishing_and_the_papers():
    """On one grid (period 1.6 mm = 58 a, 512 pixels of 3.1 um): an rms of 1 nm leaves the contact as
    the smooth one (pressure radius within 0.5 %); the paper's sphere roughness, rms 1 um (Hurst 0.8,
    wavelengths 8 um to 0.4 mm), touches a real area below a fifth of Hertz's spread over more than
    twice its radius (measured on seeds 3, 4, 5: 0.08-0.12 of the area, 3.8-6.9 a; peak pressures
    16-20 p0, 5-6 GPa: the asperities would yield, which this elastic model leaves out)."""
    grid = Grid(1.6e-3, 512)
    smooth = normal_contact(SPHERE, MAT, F, grid)
    rp = dict(hurst=0.8, lambda_short=8e-6, lambda_long=0.4e-3, size=grid.period, n=grid.n, seed=3)
    tiny = normal_contact(SPHERE, MAT, F, grid, generate(RoughnessParams(rms=1e-9, **rp)))
    rough = normal_contact(SPHERE, MAT, F, grid, generate(RoughnessParams(rms=1e-6, **rp)))
    assert abs(tiny["pressure_radius"] / smooth["pressure_radius"] - 1) < 5e-3
    assert rough["contact_area"] < 0.2 * np.pi * HZ["a"] ** 2
    assert rough["pressure_radius"] > 2 * HZ["a"] and rough["force"] == pytest.approx(F, rel=1e-9)


def test_the_error_bar_holds_hertz_only_with_the_period_in_it():
    """Period 8 a (cheap, its images large): the whole error bar (pixel + period) holds Hertz's a and
    p0; the pixel's ladder alone does not (the images are the larger error: measured -0.13 % and
    +0.25 % against pixel bars of ~1e-5 and 4e-4)."""
    a, p0 = HZ["a"], HZ["p0"]
    e = normal_error(SPHERE, MAT, F, 8 * a, ns=(64, 128, 256))
    for k, ref in (("pressure_radius", a), ("p_max", p0)):
        x = e[k]
        assert abs(x["value"] - ref) <= x["error"], (k, x)
        assert x["pixel_error"] is not None and abs(x["value"] - ref) > x["pixel_error"], (k, x)


def test_the_truncated_sphere_agrees_with_mdr_within_its_error_bar():
    """An independent half-space code for the kink: the smooth truncated sphere b = 20 um (F = 0.5 N,
    a = 28.5 um) on the FFT grid (period 16 a, a/8 .. a/32) against MDR's pressure radius (exact for an
    axisymmetric profile on a half-space): measured -1.0e-4 with an error bar of 2.4e-4 (asymptotic
    pixel ladder plus the period). At b = 50 um, where the contact edge lies 0.6 % outside the kink, the
    ladder is non-monotone: +0.9e-4 +- 3.8e-3."""
    from mdr.normal import approach_from_force, pressure_radius

    prof = make_profile("truncated", R, b=20e-6)
    d = float(approach_from_force(prof, MAT, F))
    a, rm = float(prof.g_inv(d)), pressure_radius(prof, MAT, d)
    x = normal_error(prof, MAT, F, 16 * a)["pressure_radius"]
    assert x["status"] == "asymptotic" and abs(x["value"] - rm) <= x["error"] < 1e-3 * rm, x


@pytest.mark.slow  # four solves on 512^2 grids (about 18 s)
def test_a_nominally_flat_rough_contact_grows_its_real_area_with_the_load():
    """The rough engine against the asymptotic law of rough contact: at small loads the real contact
    area of a nominally flat self-affine surface is proportional to the load, A / A0 = kappa p /
    (E* h'_rms), with kappa = sqrt(2 pi) = 2.5 for Bush, Gibson & Thomas (1975, Wear 35, 87) and about
    2.0-2.3 in converged boundary-element studies (Hyun, Pei, Molinari & Robbins 2004, Phys. Rev. E 70,
    026117). Two realisations, area fractions 0.5-2 %: kappa 2.24-2.48 measured, constant within 3 %."""
    L, n = 1e-3, 512
    flat = make_profile("flat", b=L)  # a face wider than the grid: nominally flat
    for seed in (1, 2):
        m = generate(RoughnessParams(rms=1e-6, hurst=0.8, lambda_short=8 * L / n, lambda_long=L / 4, size=L, n=n,
                                     seed=seed))
        hs = rms_slope(m)
        kappa = []
        for frac in (0.005, 0.02):
            p = frac * MAT.E_star * hs / 2
            r = normal_contact(flat, MAT, p * L * L, Grid(L, n), m)
            kappa.append(r["contact_area"] / L ** 2 * MAT.E_star * hs / p)
        assert all(1.8 < k < 2.8 for k in kappa), kappa
        assert abs(kappa[1] / kappa[0] - 1) < 0.1, kappa  # proportional to the load


def test_an_ensemble_says_what_one_realisation_cannot():
    """Four realisations of the paper's sphere roughness (rms 1 um) on one grid: their real contact
    areas differ by more than 10 % (measured 20 %: one realisation is no answer), where an rms of 1 nm
    (1 % of the approach) leaves their pressure radii within 5e-3 of each other (measured 1.2e-3: the
    smooth limit); the statistics are the members' own."""
    grid = Grid(1.6e-3, 256)
    base = RoughnessParams(rms=1e-6, hurst=0.8, lambda_short=16e-6, lambda_long=0.4e-3, size=grid.period, n=256)
    from dataclasses import replace

    rough = ensemble(SPHERE, MAT, F, grid, base, seeds=(1, 2, 3, 4))
    tiny = ensemble(SPHERE, MAT, F, grid, replace(base, rms=1e-9), seeds=(1, 2, 3, 4))
    A = rough["contact_area"]
    assert A["std"] / A["mean"] > 0.1 and A["mean"] < 0.3 * np.pi * HZ["a"] ** 2
    assert tiny["pressure_radius"]["std"] / tiny["pressure_radius"]["mean"] < 5e-3
    v = np.array(A["values"])
    assert A["mean"] == pytest.approx(v.mean()) and A["sem"] == pytest.approx(v.std(ddof=1) / 2)
    with pytest.raises(InputError, match="at least 2 seeds"):
        ensemble(SPHERE, MAT, F, grid, base, seeds=(1,))


def test_a_hardness_caps_the_pressure_and_spreads_the_contact():
    """Perfectly plastic asperities (``hardness``): the force is carried, no pixel exceeds the hardness; a
    cap the pressure never reaches is tamaas's elastic contact (the same kernel, to the solvers'
    tolerance); a cap below Hertz's p0 spreads the contact and deepens the approach, the more the lower;
    the fully plastic limit carries F on the area F / H (Tabor)."""
    a = float(HZ["a"])
    grid = Grid(16 * a, 128)
    elastic = normal_contact(SPHERE, MAT, F, grid, solver="tamaas")
    high = normal_contact(SPHERE, MAT, F, grid, hardness=1e12)
    assert np.max(np.abs(high["pressure"] - elastic["pressure"])) < 1e-7 * elastic["p_max"]  # measured 1.4e-9
    assert high["plastic_area"] == 0.0 and high["approach"] == pytest.approx(elastic["approach"], rel=1e-7)
    approach = elastic["approach"]
    for H in (0.95 * elastic["p_max"], 0.6 * elastic["p_max"], elastic["p_max"] / 6):
        r = normal_contact(SPHERE, MAT, F, grid, hardness=H)
        assert r["force"] == pytest.approx(F, rel=1e-9) and r["p_max"] <= H * (1 + 1e-12)
        assert r["plastic_area"] > 0 and r["contact_area"] >= elastic["contact_area"]
        assert r["approach"] > approach
        approach = r["approach"]
    assert r["plastic_area"] * H == pytest.approx(F, rel=0.02)  # measured 0.996 at p0 / 6


def test_the_flattened_surface_unloads_elastically_and_stiffer_than_it_loaded():
    """The plastic pixels' penetration (``flattening``) lowers the surface: the elastic contact of the
    flattened surface at the same force has the capped pressure (the optimality conditions coincide;
    measured to 7e-12 H on rms 1 um at a/4 pixels, a third of the contact pixels plastic); a cap the
    pressure never reaches flattens nothing; and the flattened surface's curve near F (its elastic
    unloading) is stiffer than the plastic first loading's (the plastic flow softens the loading)."""
    a = float(HZ["a"])
    grid = Grid(32 * a, 128)
    h = generate(RoughnessParams(rms=1e-6, hurst=0.8, lambda_short=4 * grid.pixel, lambda_long=0.25 * grid.period,
                                 size=grid.period, n=grid.n, seed=1))
    H = HARDNESS_X5CRNI18_10
    plastic = normal_contact(SPHERE, MAT, F, grid, h, hardness=H)
    assert 0.1 < plastic["plastic_area"] / plastic["contact_area"] < 0.6
    flat = HeightMap(h.h - plastic["flattening"], h.pixel)
    elastic = normal_contact(SPHERE, MAT, F, grid, flat)
    assert np.max(np.abs(elastic["pressure"] - plastic["pressure"])) < 1e-8 * H
    assert np.all((plastic["flattening"] > 0) <= (plastic["pressure"] >= H * (1 - 1e-9)))
    assert not normal_contact(SPHERE, MAT, F, grid, h, hardness=1e12)["flattening"].any()
    loads = F * np.array([0.85, 0.95, 1.0, 1.05, 1.15])
    (d_un, F_un), (d_lo, F_lo) = force_approach(SPHERE, MAT, loads, grid, flat), \
        force_approach(SPHERE, MAT, loads, grid, h, hardness=H)
    assert np.all(np.diff(F_un) / np.diff(d_un) > 1.04 * np.diff(F_lo) / np.diff(d_lo))  # measured 1.08-1.12


def test_a_bad_hardness_is_one_line():
    grid = Grid(16 * float(HZ["a"]), 32)
    for H, word in ((-1.0, "hardness"), (1e3, "whole grid")):
        with pytest.raises(InputError, match=word) as e:
            normal_contact(SPHERE, MAT, F, grid, hardness=H)
        assert "\n" not in str(e.value)


def test_the_warm_started_elastic_solve_is_tamaas_s_contact():
    """``elastic_pressure`` (Polonsky & Keer's algorithm, this project's, with a start) against tamaas's
    solve of the same contact, on an rms 1 um surface at loads from first contact to 1.5 F: the same
    pressure (within 1e-8 of its peak) and approach (within 1e-9; measured 2e-11), cold or started from
    the previous load's contact (the force-approach curve's warm start: fewer iterations, the same
    answer)."""
    from rough.normal import _rigid_surface, elastic_pressure

    a = HZ["a"]
    grid = Grid(32 * a, 128)
    h = generate(RoughnessParams(rms=1e-6, hurst=0.8, lambda_short=4 * grid.pixel, lambda_long=0.25 * grid.period,
                                 size=grid.period, n=grid.n, seed=1))
    s = _rigid_surface(SPHERE, grid, h)
    loads = F * np.geomspace(0.1, 1.5, 5)
    prev = None
    for k, load in enumerate(loads):
        try:
            ref = normal_contact(SPHERE, MAT, load, grid, h, solver="tamaas")
        except ConvergenceError:  # tamaas's error measure undefined (a contact of one pixel): no reference
            prev = elastic_pressure(s, load, grid, MAT.E_star)
            continue
        for start in (None, None if prev is None else prev * (load / loads[k - 1])):
            p = elastic_pressure(s, load, grid, MAT.E_star, start)
            assert np.max(np.abs(p - ref["pressure"])) < 1e-8 * ref["p_max"]
            assert p.sum() * grid.pixel ** 2 == pytest.approx(load, rel=1e-12)
        prev = p
    d, kept = force_approach(SPHERE, MAT, loads, grid, h)
    assert np.array_equal(kept, loads)  # every load resolved, one pixel or more
    # the default solver is this project's: tamaas's contact within the same bounds
    top = normal_contact(SPHERE, MAT, loads[-1], grid, h)
    ref = normal_contact(SPHERE, MAT, loads[-1], grid, h, solver="tamaas")
    assert np.max(np.abs(top["pressure"] - ref["pressure"])) < 1e-8 * ref["p_max"]
    assert top["approach"] == pytest.approx(ref["approach"], rel=1e-9)
    # started from that contact, the curve's first loads run on its cells: the same approaches
    d_start, kept_start = force_approach(SPHERE, MAT, loads, grid, h, start=(loads[-1], top["pressure"]))
    assert np.array_equal(kept_start, loads) and np.allclose(d_start, d, rtol=1e-9, atol=0)
    with pytest.raises(InputError, match="solver must be one of"):
        normal_contact(SPHERE, MAT, F, grid, h, solver="fft")
    for x, dx in zip(kept, d):
        try:
            assert dx == pytest.approx(normal_contact(SPHERE, MAT, x, grid, h, solver="tamaas")["approach"], rel=1e-9)
        except ConvergenceError:
            pass


def test_the_curve_on_the_contacts_cells_is_the_grids(monkeypatch):
    """``force_approach`` solving each load on the last load's contact cells (``dense_elastic_pressure``,
    ``contact_approach``) and on the grid alone: the same approaches within 1e-9 (measured 1e-11 on the
    paper's faces at 512^2)."""
    import rough.normal as RN
    from mdr.profiles import Sphere
    from rough.surfaces import RoughnessParams, generate

    mat, R, P, n = Materials(), 6e-3, 16 * 27.4e-6, 128
    h = generate(RoughnessParams(rms=1e-6, hurst=0.8, lambda_short=4 * P / n, lambda_long=0.25 * P, size=P, n=n, seed=2))
    loads = 0.5 * np.geomspace(1e-2, 1.5, 12)
    d_dense, _ = RN.force_approach(Sphere(R), mat, loads, RN.Grid(P, n), h)
    monkeypatch.setattr(RN, "DENSE_CURVE_MAX", 0)
    monkeypatch.setattr(RN, "dense_elastic_pressure", lambda *a, **k: None)
    d_grid, _ = RN.force_approach(Sphere(R), mat, loads, RN.Grid(P, n), h)
    np.testing.assert_allclose(d_dense, d_grid, rtol=1e-9, atol=0)


@pytest.mark.parametrize("screen_max", [4000, 0])
def test_a_contact_grown_from_a_smaller_one_is_the_grids(screen_max, monkeypatch):
    """``dense_elastic_pressure`` started from a smaller load's contact must find the cells the larger
    load brings into contact outside its candidates: through the single-precision screen (the cells it
    cannot clear checked in double precision) or, beyond ``SCREEN_MAX`` of them, the grid's transforms in
    double precision. Either way the grid's conjugate-gradient pressure within 1e-8 of the peak, the
    contact grown by the cells found (without the check it would stay on the smaller contact's cells)."""
    import rough.normal as RN
    from rough.normal import _rigid_surface, dense_elastic_pressure, elastic_pressure

    monkeypatch.setattr(RN, "SCREEN_MAX", screen_max)
    a = HZ["a"]
    grid = Grid(16 * a, 128)
    h = generate(RoughnessParams(rms=1e-6, hurst=0.8, lambda_short=4 * grid.pixel, lambda_long=0.25 * grid.period,
                                 size=grid.period, n=grid.n, seed=3))
    s = _rigid_surface(SPHERE, grid, h)
    small = elastic_pressure(s, 0.2 * F, grid, MAT.E_star)
    ref = elastic_pressure(s, F, grid, MAT.E_star)
    assert np.count_nonzero(ref > 0) > np.count_nonzero(small > 0)
    dense = dense_elastic_pressure(s, F, grid, MAT.E_star, small * 5.0)
    assert dense is not None and np.max(np.abs(dense - ref)) <= 1e-8 * ref.max()
    assert np.array_equal(dense > 0, ref > 0)
