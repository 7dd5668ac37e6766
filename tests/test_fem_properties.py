"""Property tests of the FE contact law on one small fixed mesh (built once per module):
random load histories, friction coefficients and force levels.

Properties (conservation and Coulomb, independent of any closed form): the friction work of
every step is >= 0; |F_x| <= mu F_N (to the solver's tolerance); a stationary loop at
constant normal force closes and its area equals the friction work summed over the pairs
(the bodies store and return everything else); contact lost gives F_x = 0.
A different material needs a new model, so materials are a small fixed sample.
"""
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fem.axisym.law import FEContact
from mdr import Materials, Sphere, TruncatedSphere
from mdr.loops import loop_integral

R = 6e-3
F_MAX = 0.6
SETTINGS = dict(max_examples=12, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
MATERIALS = {"steel": Materials(), "steel-aluminium": Materials(200e9, 0.29, 70e9, 0.33),
             "rubber-like nu": Materials(200e9, 0.45, 200e9, 0.45)}


@pytest.fixture(scope="module")
def laws(tmp_path_factory):
    """One coarse mesh (h = a/10) per (profile, material); the friction coefficient is a
    parameter of the return map only, so a law is re-used with another mu by copying."""
    cache = tmp_path_factory.mktemp("fem_property_meshes")
    out = {}
    for mname, mat in MATERIALS.items():
        out[("sphere", mname)] = FEContact(Sphere(R), mat, 0.2, F_max=F_MAX, h_contact=0.1, cache_dir=cache)
    out[("truncated", "steel")] = FEContact(TruncatedSphere(R, 20e-6), Materials(), 0.2, F_max=F_MAX,
                                            h_contact=0.1, cache_dir=cache)
    return out


def with_mu(law, mu):
    """The same FE model with another friction coefficient (the slip limits are mu lam)."""
    import copy

    new = copy.copy(law)
    new.mu = float(mu)
    new.stats = dict(law.stats)
    return new


keys = st.sampled_from([("sphere", m) for m in MATERIALS] + [("truncated", "steel")])


@settings(**SETTINGS)
@given(key=keys, mu=st.floats(0.02, 1.0), seed=st.integers(0, 2**31 - 1))
def test_random_history_respects_coulomb_and_dissipates(laws, key, mu, seed):
    rng = np.random.default_rng(seed)
    law = with_mu(laws[key], mu)
    T = 40
    FN = np.clip(0.35 + np.cumsum(rng.normal(0, 0.04, T)), 0.0, F_MAX)
    FN[rng.integers(0, T, 2)] = 0.0  # contact lost now and then
    us = mu * 1.2 * 125e-9  # ~ the gross-slip displacement at F = 0.5 N
    u = np.cumsum(rng.normal(0, 0.4 * us, T))
    H = law.run(u=u, F_N=FN)
    for k in ("Fx", "FN", "c", "a", "work"):
        assert np.all(np.isfinite(getattr(H, k)))
    assert np.all(np.abs(H.Fx) <= mu * H.FN * (1 + 1e-9) + 1e-15)
    assert np.all(H.work >= 0)
    assert np.all(H.Fx[FN == 0] == 0) and np.all((H.c >= 0) & (H.c <= H.a * (1 + 1e-12)))


@settings(**SETTINGS)
@given(key=keys, mu=st.floats(0.05, 1.0), F=st.floats(0.1, F_MAX), q=st.floats(0.2, 3.0),
       force=st.booleans())
def test_stationary_loop_closes_and_its_area_is_the_friction_work(laws, key, mu, F, q, force):
    """Constant F_N, harmonic drive (displacement u_A = q u*, or force 0.9 q/3 mu F_N):
    the third cycle repeats the second, closes, and loop area = friction work."""
    law = with_mu(laws[key], mu)
    steps, cycles = 40, 3
    t = np.arange(cycles * steps + 1) / steps
    s = np.sin(2 * np.pi * t)
    FN = np.full(t.size, F)
    if force:
        H = law.run(Fx=min(0.9 * q / 3.0, 0.9) * mu * F * s, F_N=FN)
    else:
        H = law.run(u=q * mu * 1.2 * 125e-9 * (F / 0.5) ** (2 / 3) * s, F_N=FN)
    c2 = slice(steps, 2 * steps + 1)
    c3 = slice(2 * steps, 3 * steps + 1)
    scale = mu * F
    assert np.max(np.abs(H.Fx[c3] - H.Fx[c2])) <= 1e-6 * scale          # stationary
    assert abs(H.Fx[c3][-1] - H.Fx[c3][0]) <= 1e-6 * scale               # closes
    assert abs(H.u[c3][-1] - H.u[c3][0]) <= 1e-6 * np.ptp(H.u[c3]) + 1e-18
    area = abs(loop_integral(H.u[c3], H.Fx[c3]))
    work = float(np.sum(H.work[2 * steps + 1:]))
    assert np.all(np.abs(H.Fx) <= mu * F * (1 + 1e-9))
    # energy: equal up to the time-step error of the trapezoidal area (40 steps)
    assert abs(area - work) <= 0.03 * work + 1e-6 * scale * np.ptp(H.u[c3])
