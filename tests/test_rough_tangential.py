"""rough.tangential: frictional tangential contact with memory on the FFT grid (issue 28, the engine's
first piece; docs/comparison.md has no rough family yet).

Truths: Coulomb's law cell by cell (the optimality conditions of each step, checked on the solution);
Mindlin & Deresiewicz's dissipation of the smooth sphere's stationary cycle (closed form, mdr.reference);
the friction work against the loop integral of the tangential force over the approach (energy: equal in
the limit of small steps); the periodic images' error falling as (a / period)^3.
"""
import numpy as np
import pytest

from common.errors import InputError
from mdr import reference as ref
from mdr.loops import loop_integral
from mdr.materials import Materials
from rough.normal import Grid
from rough.tangential import TangentialContact, run_force_cycles

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
