"""rough.law: the rough half-space as a contact law of the protocol, driven by the apparatus.

Truths: MDR, exact for the smooth sphere under Mindlin's assumptions (which the rough law makes too), in
the same apparatus at Table 2's load (its normal force oscillating by dF = 0.1 N); the force-controlled
engine of ``rough.tangential`` on the window (another operator, FFTs instead of a dense matrix, and the
force prescribed instead of the displacement); the grid's conjugate-gradient normal solve
(``rough.normal.elastic_pressure``) and approach (``rough.normal._approach``) against the dense active
set on the contact's cells; the force's slope against its difference quotient; a state carried across
a growing contact against one run with every force known from the start.
"""
import numpy as np
import pytest

from common.errors import InputError
from mdr import reference as ref
from mdr.apparatus import Apparatus, run_apparatus
from mdr.loading import Loading
from mdr.materials import Materials
from mdr.profiles import Sphere
from rough.law import RoughContact
from rough.normal import Grid, _approach, elastic_pressure
from rough.surfaces import RoughnessParams, generate
from rough.tangential import TangentialContact
from studies.paper import _slip_index

pytest.importorskip("tamaas")

MAT, R, MU = Materials(), 6e-3, 0.2
A = float(ref.hertz(0.5, R, MAT.E_star)["a"])


def _rough(n=128, rms=1e-6, seed=0):
    P = 16 * A
    return Grid(P, n), generate(RoughnessParams(rms=rms, hurst=0.8, lambda_short=4 * P / n, lambda_long=0.25 * P,
                                                size=P, n=n, seed=seed))


@pytest.mark.parametrize("kx", [1.9e6, 20e6])
def test_the_smooth_sphere_in_the_apparatus_is_mdr(kx):
    """The smooth sphere at Table 2's load (F_N = 0.5 +- 0.1 N) in the apparatus: the rough law's slip
    index is MDR's within 1e-3 (measured: 1e-4 at a/8 for k_x = 1.9 N/um, 2.4e-4 at a/6-a/12 for
    20 N/um, where the contact's compliance weighs more)."""
    loading = Loading.apparatus(0.5, 0.1, 0.0, 150e-9, cycles=3, steps=120)
    law = RoughContact(Sphere(R), MAT, MU, Grid(8 * A, 64))
    out = run_apparatus(law, Apparatus(kx=kx), loading)
    si_mdr, _ = _slip_index(Sphere(R), kx)
    assert float(out["slip_index"]) == pytest.approx(float(np.ravel(si_mdr)[0]), abs=1e-3)
    assert out["cycles"].last_is_stationary
    assert law.stats["grid_normal_solves"] == 1  # the other forces on the contact's cells


def test_displacement_control_is_the_force_controlled_engine_inverted():
    """From rest to the displacement u on a rough surface at 0.5 N: the force F the rough law finds,
    prescribed on the force-controlled window engine (``rough.tangential``, FFTs, periodic=False), gives
    back u as its approach within 1e-6 of u; and the same for a step back."""
    grid, h = _rough()
    law = RoughContact(Sphere(R), MAT, MU, grid, h)
    st = law.rest_state()
    res, st1 = law.step(st, 40e-9, F_N=0.5)
    idx, p, _ = law._normal_at(0.5)
    P = np.zeros(grid.n ** 2)
    P[idx] = p
    P = P.reshape(grid.n, grid.n)
    tc = TangentialContact(grid, MAT, MU, periodic=False)
    s1 = tc.step(tc.rest_state(), P, float(res.Fx))
    assert s1.delta == pytest.approx(40e-9, rel=1e-6)
    res2, _ = law.step(st1, 10e-9, F_N=0.5)
    s2 = tc.step(s1, P, float(res2.Fx))
    assert s2.delta == pytest.approx(10e-9, rel=1e-5)
    assert 0 < float(res2.Fx) < float(res.Fx) < MU * 0.5


def test_the_normal_solves_on_the_contacts_cells_are_the_grids():
    """The dense active set on the contact's cells gives the grid's conjugate-gradient pressure within
    1e-8 of its peak and the same approach within 1e-9."""
    grid, h = _rough()
    law = RoughContact(Sphere(R), MAT, MU, grid, h)
    law.normal_load(np.array([0.6, 0.5, 0.42]))
    assert law.stats["grid_normal_solves"] == 1
    for F in (0.5, 0.42):
        idx, p, d = law._normal_at(F)
        Pg = elastic_pressure(law.surface, F, grid, MAT.E_star)
        Pd = np.zeros(grid.n ** 2)
        Pd[idx] = p
        assert np.abs(Pd - Pg.ravel()).max() <= 1e-8 * Pg.max()
        assert d == pytest.approx(_approach(Pg, law.surface, grid.pixel, MAT.E_star)[0], rel=1e-9)


def test_the_slope_is_the_forces_difference_quotient():
    """In partial slip the slope the apparatus's Newton iteration takes is dF/du of the step's branch."""
    grid, h = _rough()
    law = RoughContact(Sphere(R), MAT, MU, grid, h)
    tr = law.prepare(law.rest_state(), F_N=0.5)
    F, k = tr.force(60e-9)
    assert 0 < F < MU * 0.5 and k > 0
    dh = 1e-13
    Fp, _ = tr.force(60e-9 + dh)
    Fm, _ = tr.force(60e-9 - dh)
    assert (Fp - Fm) / (2 * dh) == pytest.approx(k, rel=1e-4)


def test_a_contact_that_grows_step_by_step_is_the_one_known_from_the_start():
    """Steps at rising forces without the history announced (the dense set grows as the contact does:
    the new cells enter at their relative position, sticking) give the forces of a law that solved every
    force first, within 1e-9 of mu F_N; without that entry rule they would not (the new cells would
    carry the whole displacement since rest)."""
    grid, h = _rough()
    forces, us = (0.3, 0.45, 0.6), (30e-9, 50e-9, 20e-9)
    known = RoughContact(Sphere(R), MAT, MU, grid, h)
    known.normal_load(np.array(forces))
    grown = RoughContact(Sphere(R), MAT, MU, grid, h)
    sa, sb = known.rest_state(), grown.rest_state()
    for F, u in zip(forces, us):
        ra, sa = known.step(sa, u, F_N=F)
        rb, sb = grown.step(sb, u, F_N=F)
        assert float(rb.Fx) == pytest.approx(float(ra.Fx), abs=1e-9 * MU * F)
    assert grown.stats["grid_normal_solves"] == 1 and grown._cells.size == known._cells.size


def test_bad_loads_get_one_line():
    law = RoughContact(Sphere(R), MAT, MU, Grid(8 * A, 32))
    with pytest.raises(InputError, match="displacement-controlled"):
        law.step(law.rest_state(), Fx=0.01, F_N=0.5)
    with pytest.raises(InputError, match="F_N = 0"):
        law.prepare(law.rest_state(), F_N=0.0)
    with pytest.raises(InputError, match="normal force F_N, not the approach"):
        law.prepare(law.rest_state(), d=1e-7)


def test_a_copy_at_another_friction_shares_the_normal_solves_and_nothing_else():
    """``with_friction``: the same apparatus run as a fresh law of that friction (slip index within 1e-9),
    without solving a force again; the original keeps its own friction."""
    grid, h = _rough()
    loading = Loading.apparatus(0.5, 0.1, 0.0, 150e-9, cycles=2, steps=40)
    first = RoughContact(Sphere(R), MAT, 0.2, grid, h)
    run_apparatus(first, Apparatus(), loading)
    solves = first.stats["normal_solves"]
    copy = first.with_friction(0.25)
    shared = float(run_apparatus(copy, Apparatus(), loading)["slip_index"])
    assert first.stats["normal_solves"] == solves and first.mu == 0.2 and copy.mu == 0.25
    fresh = float(run_apparatus(RoughContact(Sphere(R), MAT, 0.25, grid, h), Apparatus(), loading)["slip_index"])
    assert shared == pytest.approx(fresh, rel=1e-9, abs=0)


def test_a_contact_of_one_cell_is_solved():
    """The displacement-controlled box solve on a contact of a single cell (a rough face at 3.6 um touches
    at one pixel at some forces): q = clip((u - s) / K, -lim, lim), sticking or slipping, where a
    criterion relative to the range of K q (0 for one cell) was never met."""
    from rough.boxqp import solve_box_free

    K = np.array([[2.0e-12]])
    lim = np.array([4.3e8])
    for b in (-1.4e-8, -1.0e-4, 3.0e-4):
        q = solve_box_free(K.__matmul__, np.array([b]), lim, np.zeros(1), 1e-10)
        assert q[0] == pytest.approx(np.clip(-b / K[0, 0], -lim[0], lim[0]), rel=1e-9)


def test_a_contact_too_large_for_the_dense_compliance_is_one_line(monkeypatch):
    """The law holds its compliance densely (no grid path to fall back on): a contact of more cells than
    ``MAX_CELLS`` is an InputError naming the grid, not a memory blow-up."""
    import rough.law as RL

    monkeypatch.setattr(RL, "MAX_CELLS", 5)
    law = RoughContact(Sphere(R), MAT, MU, Grid(8 * A, 32))
    with pytest.raises(InputError, match="coarser grid") as e:
        law.prepare(law.rest_state(), F_N=0.5)
    assert "\n" not in str(e.value)


def test_the_compiled_box_solve_is_numpy_s_and_keeps_coulomb():
    """The dense displacement-controlled box solve compiled (numba) and with numpy's products: the same
    tractions within 1e-9 of the largest limit on a rough contact's own compliance and problem (measured
    1e-16), and both obey Coulomb's law there (K q + s - u = 0 where |q| < mu p, a bound only where the
    slip pushes against it)."""
    import rough.boxqp as bq

    grid, h = _rough()
    law = RoughContact(Sphere(R), MAT, MU, grid, h)
    tr = law.prepare(law.rest_state(), F_N=0.5)
    b = tr.s - 60e-9
    q_c = bq.solve_box_free_dense(tr.K, b, tr.lim, np.zeros_like(b), 1e-10)
    q_n = bq.solve_box_free(tr.K.__matmul__, b, tr.lim, np.zeros_like(b), 1e-10)
    assert np.max(np.abs(q_c - q_n)) <= 1e-9 * tr.lim.max()
    for q in (q_c, q_n):
        g = tr.K @ q + b
        stick = np.abs(q) < tr.lim * (1 - 1e-9)
        assert stick.any() and (~stick & (tr.lim > 0)).any()  # partial slip: both branches checked
        assert np.max(np.abs(g[stick])) <= 1e-8 * np.max(np.abs(tr.K @ q))
        at = ~stick & (tr.lim > 0)
        assert np.all(np.sign(q[at]) * g[at] <= 1e-8 * np.max(np.abs(tr.K @ q)))


def test_started_from_a_known_contact_the_law_solves_nothing_on_the_grid():
    """Given a contact of the surface already solved (``start``), the law's first normal solve runs on
    its cells too: no grid solve, the same pressures within 1e-8 of the peak as a law solving on the
    grid first."""
    grid, h = _rough()
    cold = RoughContact(Sphere(R), MAT, MU, grid, h)
    cold.normal_load(np.array([0.6, 0.5]))
    P = elastic_pressure(cold.surface, 0.5, grid, MAT.E_star)
    warm = RoughContact(Sphere(R), MAT, MU, grid, h, start=(0.5, P))
    warm.normal_load(np.array([0.6, 0.5]))
    assert cold.stats["grid_normal_solves"] == 1 and warm.stats["grid_normal_solves"] == 0
    for F in (0.6, 0.5):
        (ia, pa, da), (ib, pb, db) = cold._normal_at(F), warm._normal_at(F)
        assert np.array_equal(ia, ib) and np.max(np.abs(pa - pb)) <= 1e-8 * pa.max()
        assert db == pytest.approx(da, rel=1e-9)
    with pytest.raises(InputError, match="start pressure must lie on the grid"):
        RoughContact(Sphere(R), MAT, MU, grid, h, start=(0.5, P[:-1]))
