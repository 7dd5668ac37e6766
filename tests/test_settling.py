"""The settling of the cycles towards the stationary one (``common.ladder.settling_error``) and the 3D
runs that go on until they settle (``fem.contact_run.drive_3d``'s ``settle``).

Truths: a geometric sequence's limit (closed form); a continued history equals one long run; the
stationary cycle of a coupled dissimilar 3D pair, approximated by running many more cycles."""
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings, strategies as st

from common.ladder import SETTLED, SETTLING_RATIO_MAX, settling_error
from mdr.loading import Loading


def geometric(x_star, C, r, n):
    return [x_star + C * r ** k for k in range(1, n + 1)]


# the assume() below keeps changes above round-off; hypothesis's many tiny floats make it filter a lot,
# which is the intended domain, not a slow strategy
@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.filter_too_much])
@given(r=st.floats(-SETTLING_RATIO_MAX, SETTLING_RATIO_MAX), C=st.floats(-1.0, 1.0),
       n=st.integers(3, 40), x_star=st.floats(-1.0, 1.0))
# a ratio at the bound read from changes of 6e-8 of the values: decided by their last bits (found with
# numpy's AVX2 kernels switched off; common.ladder.contracting's round-off allowance)
@example(r=0.9499999999999998, C=-1.2790366919671555e-06, n=3, x_star=1.0)
def test_a_settled_contraction_is_bounded(r, C, n, x_star):
    """x_k = x* + C r^k with |r| <= SETTLING_RATIO_MAX: once the last change is below the floor,
    the stationary value x* lies within the error bar of the last cycle."""
    assume(abs(C * r ** n) > 1e-9 * (abs(x_star) + abs(C)))  # changes above round-off (the floors are >= 1e-4)
    xs = geometric(x_star, C, r, n)
    floor = abs(xs[-1] - xs[-2])
    s = settling_error(xs, floor=floor)
    assert s["status"] == "stationary" and s["bounded"]
    assert abs(x_star - xs[-1]) <= s["error"] * (1 + 1e-9) + 1e-15


def test_a_slower_contraction_is_not_called_stationary():
    """The bound rests on r <= SETTLING_RATIO_MAX: at r = 0.97 the last change alone, 9 times over,
    falls short of the stationary value, so the rule must see the ratio and call it settling (no
    bound; its estimate with the observed ratio then holds the remainder)."""
    xs = geometric(0.0, 1.0, 0.97, 10)
    d = abs(xs[-1] - xs[-2])
    assert abs(xs[-1]) > d * SETTLING_RATIO_MAX / (1 - SETTLING_RATIO_MAX)
    s = settling_error(xs, floor=d)
    assert s["status"] == "settling" and not s["bounded"]
    assert abs(xs[-1]) <= s["error"] * (1 + 1e-9)


def test_unsettled_cycles_bound_nothing():
    """A change above the floor is no bound, whatever the ratios seen so far: the coupled pair's
    effect (one mesh, cycles 1-4) extrapolated from its ratios fell short of its 20th cycle."""
    xs = [0.04458, 0.02220, 0.01648, 0.01329]  # the effect over cycles 1-4 (h = 0.3 a_ref)
    s = settling_error(xs, floor=2e-4)
    assert s["status"] == "settling" and not s["bounded"]
    assert abs(-0.00230 - xs[-1]) <= s["error"]  # its 20th cycle, within the estimate nonetheless
    assert settling_error([1.0, 2.0, 3.0])["status"] == "not contracting"
    assert settling_error([1.0, 2.0])["status"] == "two cycles"
    for bad in ([1.0, None, 2.0], [1.0, float("nan")], [1.0], []):
        s = settling_error(bad)
        assert s["error"] is None and not s["bounded"]
    assert SETTLED == ("stationary",)


def test_round_off_changes_are_settled():
    """Changes at round-off level need not contract (1e-20 after 1e-21 J on a sticking punch): below
    NEGLIGIBLE of the floor they count as settled, in ``settling_error`` and in ``settled``; above it
    a change that does not contract does not."""
    from fem.contact_run import settled
    from common.ladder import NEGLIGIBLE

    xs = [1.0, 1.0 + 1e-21, 1.0 + 1e-21 + 1e-20]
    assert settling_error(xs, floor=1e-12)["status"] == "stationary"
    assert settled([1e-14, 1e-14 + 1e-21, 1e-14 + 1e-21 + 1e-20], 1e-4, gross=1e-10)
    big = [1.0, 1.0 + 0.5e-4, 1.0 + 1.5e-4]  # within the tolerance, growing
    assert not settled(big, 1e-4) and settling_error(big, floor=1e-4)["status"] == "not contracting"
    assert settled([1.0, 1.0 + 2e-4, 1.0 + 2e-4 + 0.5e-4], 1e-4)
    assert NEGLIGIBLE < 1e-2


# ------------------------------------------------------------------ the 3D runs
MU, F0, DF, FA = 0.2, 0.5, 0.1, 0.06  # Table 2 loading with the assumptions-3d scene's force amplitude


# session scope: a module fixture is torn down whenever its worker runs another module's test in
# between, and built again; its tests are grouped on one worker (xdist_group), so it is built once
@pytest.fixture(scope="session")
def pairs(shared_mesh_cache):
    """On a coarse 3D mesh (a/5): the steel sphere with its traction free and along x, and the
    steel/aluminium pair (Dundurs beta = +0.11) coupled and not."""
    from fem.solid3d.law import FEContact3D
    from mdr.materials import Materials
    from mdr.profiles import Sphere

    cache = shared_mesh_cache
    steel = FEContact3D(Sphere(6e-3), Materials(), MU, F_max=F0 + DF, h_contact=0.2, cache_dir=cache)
    alu = FEContact3D(Sphere(6e-3), Materials(E2=70e9, nu2=0.33), MU, F_max=F0 + DF, h_contact=0.2, cache_dir=cache)
    return {"direction": (steel.assuming(traction="free"), steel.assuming(traction="x")),
            "coupling": (alu.assuming(traction="free", coupling=True), alu.assuming(coupling=False))}


def _settled_pair(pair):
    from fem.contact_run import drive_3d_together
    from validation.families.assumptions3d import effect_settling
    from validation.scenes import SETTLE_MAX_CYCLES, SETTLE_TOL_3D

    runs = dict(zip(("on", "off"), drive_3d_together(pair, Loading.of(F0, dF=DF, alpha=0.0, fa=FA, cycles=4, steps=40), settle=(SETTLE_TOL_3D, SETTLE_MAX_CYCLES))))
    s = effect_settling(runs["on"], runs["off"], "dissipation", "relative", floor=2 * SETTLE_TOL_3D)
    return runs, s


def _effect(runs):
    return runs["on"]["dissipation"] / runs["off"]["dissipation"] - 1


@pytest.mark.xdist_group("settling-pairs")  # one worker builds the pairs (--dist loadgroup)
def test_a_continued_run_is_one_long_run(pairs):
    """``settle`` continues the history from the last state: the same cycles as one long run (to the
    solver's tolerance), the centres still those of the first loading, ``per_cycle`` whole."""
    from fem.contact_run import drive_3d

    on, _ = pairs["coupling"]
    one = drive_3d(on, Loading.of(F0, dF=DF, alpha=0.0, fa=FA, cycles=8, steps=40))
    cont = drive_3d(on, Loading.of(F0, dF=DF, alpha=0.0, fa=FA, cycles=4, steps=40), settle=(0.0, 8))
    assert cont["cycles_run"] == 8 and cont["settled"] is False
    W1, W2 = np.array(one["dissipation_per_cycle"]), np.array(cont["dissipation_per_cycle"])
    assert W1.shape == W2.shape and np.max(np.abs(W1 - W2)) < 1e-9 * W1.max()
    for k in ("dissipation", "dissipation_first_cycle", "slip_index", "displacement_amplitude"):
        assert cont[k] == pytest.approx(one[k], rel=1e-9), k
    for k in ("stick_center_x", "pressure_center_x", "stick_axis_x", "stick_axis_y"):
        assert cont[k] == pytest.approx(one[k], rel=1e-9, abs=1e-12), k
    assert len(cont["per_cycle"]["stick_axis_x"]) == 8
    assert cont["per_cycle"]["stick_axis_x"][-1] == pytest.approx(cont["stick_axis_x"], rel=1e-12)


@pytest.mark.xdist_group("settling-pairs")  # one worker builds the pairs (--dist loadgroup)
def test_the_settled_direction_effect_holds_the_stationary_cycle(pairs):
    """The direction effect on the dissipation (free minus along x, relative), runs settled to
    SETTLE_TOL_3D: stationary, and the effect of 8 more cycles lies within its settling bar."""
    from fem.contact_run import drive_3d

    runs, s = _settled_pair(pairs["direction"])
    assert all(r["settled"] for r in runs.values())
    assert s["status"] == "stationary" and s["bounded"]
    n = max(r["cycles_run"] for r in runs.values()) + 8
    long = {k: drive_3d(v, Loading.of(F0, dF=DF, alpha=0.0, fa=FA, cycles=n, steps=40)) for k, v in zip(("on", "off"), pairs["direction"])}
    assert abs(_effect(long) - _effect(runs)) <= s["error"]


@pytest.mark.slow
def test_the_coupled_pair_settles_slowly_and_its_bar_holds_it(pairs):
    """The coupled steel/aluminium pair on this mesh settles in modes: a fast one gone by cycle ~9,
    then a slow tail of ~5e-5 per cycle at a ratio of ~0.93 for tens of cycles. Runs settled to
    SETTLE_TOL_3D: the effect 20 cycles later lies within the settling bar (SETTLING_RATIO_MAX),
    and a bar that assumed a fast contraction (r = 0.5: the last change itself) would not hold it."""
    from fem.contact_run import drive_3d

    runs, s = _settled_pair(pairs["coupling"])
    assert s["status"] == "stationary" and s["bounded"]
    n = max(r["cycles_run"] for r in runs.values()) + 20
    long = {k: drive_3d(v, Loading.of(F0, dF=DF, alpha=0.0, fa=FA, cycles=n, steps=40)) for k, v in zip(("on", "off"), pairs["coupling"])}
    moved = abs(_effect(long) - _effect(runs))
    assert moved <= s["error"]
    d_last = s["error"] * (1 - SETTLING_RATIO_MAX) / SETTLING_RATIO_MAX
    assert moved > d_last
    # the scene's 4 cycles alone: off the stationary effect by more than the settled bar
    W_on, W_off = long["on"]["dissipation_per_cycle"], long["off"]["dissipation_per_cycle"]
    assert abs(W_on[3] / W_off[3] - 1 - _effect(long)) > s["error"]
