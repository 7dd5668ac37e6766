"""rough.tangential: frictional tangential contact with memory on the FFT grid (the rough half-space's
tangential engine).

Truths: Coulomb's law cell by cell (the optimality conditions of each step, checked on the solution);
Mindlin & Deresiewicz's dissipation of the smooth sphere's stationary cycle and Cattaneo & Mindlin's stick
radius (closed forms, mdr.reference) on a grid ladder whose Richardson extrapolation they must meet
within 0.2 %; the friction work against the loop integral of the tangential force over the approach
(energy: equal in the limit of small steps); the periodic images' error falling as (a / period)^3; the
traction free to turn against Mindlin's along x: the same where Poisson's ratio vanishes (Cerruti's
cross term is nu x y / r^3), and for steel below it by what an independent boundary-element ladder
measured.
"""
import numpy as np
import pytest

from conftest import BE_TURNING, BE_TURNING_ERROR
from common.errors import InputError
from mdr import reference as ref
from mdr.loops import loop_integral
from common.ladder import ladder_error
from mdr.materials import Materials
from rough.normal import Grid
from rough.tangential import TangentialContact, run_force_cycles, stick_radius

MAT, R, F, MU = Materials(), 6e-3, 0.5, 0.2
HZ = ref.hertz(F, R, MAT.E_star)
A = float(HZ["a"])


def _hertz_grid(per_a, periods):
    grid = Grid(periods * A, int(periods * per_a))
    p = ref.hertz_pressure(grid.radii(), F, R, MAT.E_star)
    return grid, p, float(p.sum()) * grid.pixel ** 2


def _md(FN, Q):
    u_star = float(ref.gross_slip_displacement(HZ["d"], MU, MAT.E_star, MAT.G_star))
    return float(ref.mindlin_deresiewicz_dissipation_force(Q, FN, MU, u_star))


def test_every_step_obeys_coulomb_cell_by_cell():
    """|q| <= mu p everywhere; a cell below the limit does not slip; a slipping cell's traction is at the
    limit with the sign of its slip increment; the traction carries the force."""
    grid, p, FN = _hertz_grid(8, 8)
    tc = TangentialContact(grid, MAT, MU)
    st, lim = tc.rest_state(), MU * p
    for Q in 0.5 * MU * FN * np.sin(np.linspace(0, 2 * np.pi, 9)[1:]):
        new = tc.step(st, p, Q)
        ds = new.s - st.s
        assert np.all(np.abs(new.q) <= lim * (1 + 1e-12))
        assert float(new.q.sum()) * tc.dA == pytest.approx(Q, rel=1e-9, abs=1e-15)
        stick = (lim > 0) & (np.abs(new.q) < lim * (1 - 1e-9))
        slip = (lim > 0) & ~stick & (np.abs(ds) > 0)
        scale = float(np.ptp(tc.displacement(new.q)))
        assert np.all(ds[stick] == 0.0)
        assert np.all(new.q[slip] * ds[slip] >= -1e-9 * scale * lim[slip])
        st = new


def test_the_smooth_sphere_dissipates_mindlin_deresiewicz():
    """Q = mu F_N / 2 on a/8 pixels, period 16 a: the stationary cycle's friction work within 1 % of
    Mindlin-Deresiewicz (measured +0.48 %; a/16: +1.3 %, a/32 at period 8 a: -0.65 %: the slip annulus,
    0.21 a wide, spans 1.6-6.6 pixels on these grids, and the ladder is not yet monotone); the second
    and third cycles repeat (Masing)."""
    grid, p, FN = _hertz_grid(8, 16)
    out = run_force_cycles(TangentialContact(grid, MAT, MU), p, 0.5 * MU * FN, cycles=3, steps=8)
    W = out["dissipation_per_cycle"]
    assert W[2] == pytest.approx(W[1], rel=1e-9)
    assert W[2] == pytest.approx(_md(FN, 0.5 * MU * FN), rel=0.01)


def _window(per_a, centre=(0.0, 0.0), materials=MAT):
    """The smooth sphere's contact on a window of two half-spaces (no periodic images) of pixel a /
    per_a (a Hertz's radius for ``materials``), the pressure Hertz's pixel means (``Grid.cell_mean``)
    about ``centre`` (m)."""
    h = float(ref.hertz(F, R, materials.E_star)["a"]) / per_a
    n = int(np.ceil(2.1 * per_a)) + 2
    grid = Grid(n * h, n)
    p = grid.cell_mean(lambda r: ref.hertz_pressure(r, F, R, materials.E_star), centre)
    return grid, p


def _smooth_ladder(centre, per_a=(16, 24, 32)):
    """The stationary dissipation over Mindlin-Deresiewicz's and the stick radius (``stick_radius``) over
    Cattaneo-Mindlin's at Q = mu F / 2, per grid of the ladder."""
    W, c = [], []
    for k in per_a:
        grid, p = _window(k, centre)
        tc = TangentialContact(grid, MAT, MU, periodic=False)
        FN = float(p.sum()) * tc.dA
        out = run_force_cycles(tc, p, 0.5 * MU * FN, cycles=2, steps=8)
        W.append(out["dissipation"] / _md(FN, 0.5 * MU * FN))
        c.append(stick_radius(out["peak"].q, p, MU, grid.radii(centre)) / float(ref.cattaneo_mindlin_stick_radius(0.5 * MU * FN, FN, MU, A)))
    return W, c


@pytest.mark.parametrize("centre, per_a", [
    ((0.0, 0.0), (16, 24, 32)),
    pytest.param((0.37, 0.11), (32, 48, 64), marks=pytest.mark.slow),
])
def test_the_smooth_sphere_meets_mindlin_deresiewicz_and_cattaneo_mindlin_within_0_2_percent(centre, per_a):
    """Q = mu F / 2 on two half-spaces (no periodic images), the sphere's axis on a pixel centre (a/16,
    a/24, a/32) or off it by (0.37, 0.11) finest pixels (a/32, a/48, a/64: the stick edge's pixel
    pattern, ~0.1 % at a/32, needs the finer ladder): the dissipation converges at second order (the
    pressure as pixel means: pixel-centre samples give a non-monotone ladder, -5.3, +1.4, +0.2 % at
    a/8 .. a/32 on the centre) and its Richardson extrapolation meets Mindlin-Deresiewicz within 0.2 %
    (measured +0.04 and -0.05 %), Mindlin-Deresiewicz inside the ladder's error bar; the stick radius
    meets Cattaneo-Mindlin within 0.2 % on every grid (measured +0.04 and +0.01 % at the finest)."""
    sizes = [1 / k for k in per_a]
    W, c = _smooth_ladder(tuple(x * A / per_a[-1] for x in centre), per_a)
    lad = ladder_error(sizes, W)
    assert lad["status"] == "asymptotic" and 1.2 < lad["order"] < 2.6, (W, lad)
    assert abs(lad["extrapolated"] - 1) < 2e-3, (W, lad)
    assert abs(lad["value"] - 1) <= lad["error"], (W, lad)
    assert all(abs(x - 1) < 2e-3 for x in c), c


def test_pressure_sampled_at_pixel_centres_gives_a_non_monotone_ladder():
    """The same ladder (a/8, a/16, a/32, axis on a pixel centre) with Hertz's pressure sampled at the
    pixel centres instead of averaged over the pixels: the dissipation jumps with the pixels the contact
    edge encloses (-5.3, +1.4, +0.2 % of Mindlin-Deresiewicz measured), a ladder without an order."""
    W = []
    for per_a in (8, 16, 32):
        grid, _ = _window(per_a)
        p = ref.hertz_pressure(grid.radii(), F, R, MAT.E_star)
        tc = TangentialContact(grid, MAT, MU, periodic=False)
        FN = float(p.sum()) * tc.dA
        W.append(run_force_cycles(tc, p, 0.5 * MU * FN, cycles=2, steps=8)["dissipation"] / _md(FN, 0.5 * MU * FN))
    assert ladder_error([1 / 8, 1 / 16, 1 / 32], W)["status"] == "non-monotone", W
    assert W[0] < 0.97 and W[1] > 1.005, W


def test_the_friction_work_is_the_loop_integral_in_the_limit_of_small_steps():
    """At a constant pressure each cell slips one way per half cycle, so the friction work of the
    implicit step is exact at any step count (equal at 8 and 32 steps); the trapezoidal loop integral
    of Q over the approach converges to it (measured with tamaas's pressure on a/8, period 8 a: -3.1 %,
    -2.1 %, -1.9 % at 20, 40, 80 steps)."""
    grid, p, FN = _hertz_grid(8, 8)
    tc = TangentialContact(grid, MAT, MU)
    runs = {n: run_force_cycles(tc, p, 0.5 * MU * FN, cycles=2, steps=n) for n in (8, 32)}
    assert runs[32]["dissipation"] == pytest.approx(runs[8]["dissipation"], rel=1e-8)
    gaps = [abs(loop_integral(r["delta"], r["Q"]) / r["dissipation"] - 1) for r in runs.values()]
    assert gaps[1] < 0.5 * gaps[0]


def test_the_periodic_images_fall_as_the_period_cubed():
    """a/4 pixels, periods 8, 16, 32 a: the dissipation changes by 1.2e-2, then 1.4e-3 (8x: (a / P)^3)."""
    W = []
    for periods in (8, 16, 32):
        grid, p, FN = _hertz_grid(4, periods)
        W.append(run_force_cycles(TangentialContact(grid, MAT, MU), p, 0.5 * MU * FN, cycles=2, steps=8)["dissipation"])
    d1, d2 = abs(W[1] - W[0]), abs(W[2] - W[1])
    assert 4 < d1 / d2 < 16


def test_bad_input_is_one_line():
    grid, p, FN = _hertz_grid(4, 8)
    tc = TangentialContact(grid, MAT, MU)
    with pytest.raises(InputError, match="friction limit"):
        tc.step(tc.rest_state(), p, 1.01 * MU * FN)
    with pytest.raises(InputError, match="pressure field"):
        tc.step(tc.rest_state(), p[:-1], 0.01)
    with pytest.raises(InputError, match="mu"):
        TangentialContact(grid, MAT, 0.0)
    with pytest.raises(InputError, match="traction must be one of free, x"):
        TangentialContact(grid, MAT, MU, traction="y")


def _free_against_x(materials, per_a, steps=4, cycles=2):
    """The two tractions under the same pressure (Hertz's pixel means for ``materials``) on a window."""
    grid, p = _window(per_a, materials=materials)
    fa = 0.5 * MU * float(p.sum()) * grid.pixel ** 2
    out = {}
    for traction in ("x", "free"):
        tc = TangentialContact(grid, materials, MU, periodic=False, traction=traction)
        out[traction] = run_force_cycles(tc, p, fa, cycles=cycles, steps=steps)
    return grid, p, out


def test_without_poisson_s_ratio_the_traction_does_not_turn():
    """nu = 0 on both bodies: Cerruti's cross term vanishes, no force pulls across x, and the traction
    free to turn is Mindlin's along x: the same dissipation (within the solves' tolerances) and no q_y.
    With steel (nu = 0.3) it turns: q_y is a few per cent of the limit and the dissipation drops."""
    grid, p, out = _free_against_x(Materials(nu1=0.0, nu2=0.0), 4)
    x, pl = out["x"], out["free"]
    assert pl["dissipation"] == pytest.approx(x["dissipation"], rel=1e-6)
    assert np.max(np.abs(pl["state"].q[1])) < 1e-6 * MU * p.max()
    grid, p, out = _free_against_x(MAT, 4)
    assert np.max(np.abs(out["free"]["state"].q[1])) > 1e-3 * MU * p.max()
    assert out["free"]["dissipation"] < out["x"]["dissipation"] * (1 - 1e-3)


def test_a_turning_traction_obeys_coulomb_as_a_disk():
    """Every step: |q| <= mu p; a cell below the limit does not slip; a slipping cell's traction is at
    the limit and points along its slip increment; the traction carries Q along x and nothing across."""
    grid, p = _window(6)
    tc = TangentialContact(grid, MAT, MU, periodic=False, traction="free")
    st, lim, FN = tc.rest_state(), MU * p, float(p.sum()) * tc.dA
    for Q in MU * FN * np.array([0.3, 0.6, 0.2, -0.4, -0.6, 0.1]):
        new = tc.step(st, p, Q)
        ds, mag = new.s - st.s, np.hypot(new.q[0], new.q[1])
        assert np.all(mag <= lim * (1 + 1e-12))
        assert new.q[0].sum() * tc.dA == pytest.approx(Q, rel=1e-9) and abs(new.q[1].sum()) * tc.dA < 1e-9 * abs(Q)
        stick = tc.sticking(new.q, p)
        assert np.all(ds[:, stick] == 0.0)
        scale = float(np.ptp(np.hypot(*tc.displacement(new.q))))  # the solve's tolerance is relative to it
        slip = (lim > 0) & ~stick & (np.hypot(ds[0], ds[1]) > 1e-5 * scale)
        cosine = np.sum(new.q * ds, axis=0)[slip] / (mag[slip] * np.hypot(ds[0], ds[1])[slip])
        assert slip.any() and np.all(cosine > 1 - 1e-4), cosine.min()
        st = new


@pytest.mark.slow
def test_a_turning_traction_dissipates_what_the_boundary_elements_measured():
    """Steel on steel at Q = mu F / 2 on two half-spaces: the traction free to turn against Mindlin's along
    x. Its friction work depends on the steps (the slip turns within a half cycle; an implicit step slips
    along its end direction): on a/12, 16, 32, 64 steps a cycle converge with an observed order near 1.1
    (-0.381, -0.393, -0.399 %), and Richardson adds -0.023 % +- 0.006 % to the 16 steps' value
    (``ladder_error``, with the GCI's safety factor; -0.023 % on a/16 too). The grid at 16 steps: a/12,
    a/16, a/24 give -0.381, -0.385, -0.395 %, not yet asymptotic, so the error is their spread (0.014 %).
    The engine: -0.419 +- 0.021 %, the independent boundary-element ladder's -0.43 +- 0.01 % within both
    bars (asserted within twice their sum); Mindlin's traction on both sides gives 0 and fails by 7x. The
    stick zone is the same: its radius within 0.1 % (measured 0.03 %)."""
    steps, per_a = (16, 32, 64), (12, 16, 24)
    ratio, sticks = {}, []
    for k, n in [(12, n) for n in steps] + [(k, steps[0]) for k in per_a[1:]]:
        grid, p, out = _free_against_x(MAT, k, steps=n)
        ratio[k, n] = out["free"]["dissipation"] / out["x"]["dissipation"] - 1
        c = [stick_radius(out[t]["peak"].q, p, MU, grid.radii()) for t in ("x", "free")]
        sticks.append(c[1] / c[0] - 1)
    in_steps = ladder_error([1.0 / n for n in steps], [ratio[12, n] for n in steps])
    assert in_steps["status"] == "asymptotic", (in_steps, ratio)
    in_grid = ladder_error([1.0 / k for k in per_a], [ratio[k, steps[0]] for k in per_a])
    engine = in_grid["value"] + (in_steps["extrapolated"] - ratio[12, steps[0]])
    error = in_grid["error"] + in_steps["error"]
    assert abs(engine - BE_TURNING) < 2 * (error + BE_TURNING_ERROR), (engine, error, ratio)
    assert all(abs(s) < 1e-3 for s in sticks), sticks


@pytest.mark.parametrize("traction", ["x", "free"])
def test_a_contact_that_never_slipped_unloads_to_no_traction(traction):
    """The smooth face b = 100 um under mu F0 / 2 sticks everywhere (its edge pixel's pressure is finite
    on the grid); unloaded to Q = 0 it carries no traction at all (nothing slipped: the elastic problem
    is homogeneous, its solution zero). The solves reach it: their residual's scale has a floor (the range
    of K lim), where the range of K q vanishes with q (without it the box solve ran out of iterations)."""
    from mdr.profiles import TruncatedSphere
    from rough.normal import normal_contact

    g = Grid(400.0377e-6, 64)
    p = normal_contact(TruncatedSphere(6e-3, 100e-6), MAT, 0.5, g)["pressure"]
    tc = TangentialContact(g, MAT, MU, traction=traction)
    st = tc.rest_state()
    for Q in (0.035, 0.05, 0.035, 0.0):
        st = tc.step(st, p, Q)
    assert st.work == pytest.approx(0.0, abs=1e-20)  # it never slipped
    assert np.max(np.abs(st.q)) < 1e-6 * MU * p.max()


@pytest.mark.parametrize("periodic", [True, False])
def test_the_steps_on_the_contacts_cells_are_the_grids(periodic, monkeypatch):
    """A rough contact's cycles solved with the dense compliance among its cells (``_dense_box``) and on
    the grid with transforms (``DENSE_MAX`` = 0): the same dissipation and loop within 1e-7 (both solves
    stop at 1e-10 of the displacement's range), on the periodic grid and on the window."""
    from rough.normal import normal_contact
    from rough.surfaces import RoughnessParams, generate
    from mdr.profiles import Sphere
    import rough.tangential as T

    P, n = 16 * A, 96
    h = generate(RoughnessParams(rms=1e-6, hurst=0.8, lambda_short=4 * P / n, lambda_long=0.25 * P, size=P, n=n,
                                 seed=1))
    grid = Grid(P, n)
    p = normal_contact(Sphere(R), MAT, F, grid, h)["pressure"]
    runs = []
    for dense_max in (T.DENSE_MAX, 0):
        monkeypatch.setattr(T, "DENSE_MAX", dense_max)
        runs.append(run_force_cycles(TangentialContact(grid, MAT, MU, periodic=periodic), p, 0.5 * MU * F, cycles=2,
                                     steps=8))
    (a, b) = runs
    assert a["dissipation"] == pytest.approx(b["dissipation"], rel=1e-7, abs=0)
    np.testing.assert_allclose(a["delta"], b["delta"], rtol=0, atol=1e-7 * np.ptp(b["delta"]))


@pytest.mark.parametrize("component", ["xx", "xy", "yy"])
def test_the_compiled_image_sum_is_numpy_s(component, monkeypatch):
    """The periodic compliance's sum over the aliases, compiled (numba, the sincs tabulated per
    direction) and in numpy over the grid per alias: the same coefficients within 1e-13 of the largest
    (measured 3e-16), on an odd and an even grid."""
    import rough.tangential as rt

    if rt._image_sum is None:
        pytest.skip("the compiled image sum is off (numba not installed, or ROUGH_PURE_PYTHON=1): "
                    "only the numpy path runs")
    for n in (31, 48):
        grid = Grid(8 * A, n)
        a = rt._compliance.__wrapped__(grid, MAT, component, 12)
        monkeypatch.setattr(rt, "_image_sum", None)
        b = rt._compliance.__wrapped__(grid, MAT, component, 12)
        monkeypatch.undo()
        assert np.max(np.abs(a - b)) <= 1e-13 * np.max(np.abs(b))
