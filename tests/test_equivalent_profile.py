"""MDR's equivalent profile of a normal force-approach curve (``mdr.equivalent.EquivalentProfile``),
checked on curves whose profile is known: built from the sphere's and the truncated sphere's own
F(d), it returns their g and f, their forces and their fretting loops, and converges at second order
in the number of samples."""
import numpy as np
import pytest

from common.errors import InputError
from mdr.drive import run_mdr_contact
from mdr.equivalent import EquivalentProfile
from mdr.loading import Loading
from mdr.materials import Materials
from mdr.normal import approach_from_force, force_from_approach
from mdr.profiles import Sphere, TruncatedSphere

MAT = Materials()
R, F_MAX = 6e-3, 1.0
PROFILES = {"sphere": Sphere(R), "truncated": TruncatedSphere(R, 20e-6)}


def curve(prof, n, materials=MAT):
    """``n`` samples of F(d) from first contact to F_MAX, geometric in d (a ~ sqrt(d) near the start)."""
    d = float(approach_from_force(prof, materials, F_MAX)) * np.geomspace(1e-4, 1.0, n)
    return d, force_from_approach(prof, materials, d)


def profile_error(prof, n) -> float:
    """The largest |g_eq - g| on (0.05, 0.95) a_max, over the largest approach."""
    d, F = curve(prof, n)
    eq = EquivalentProfile(d, F, MAT)
    x = np.linspace(0.05, 0.95, 60) * eq.x_limit
    return float(np.max(np.abs(eq.g(x) - prof.g(x))) / d[-1])


@pytest.mark.parametrize("name", PROFILES)
def test_equivalent_profile_converges_to_the_profile(name):
    """g of the equivalent profile converges to the profile's own g at second order in the samples
    (measured: 2.0e-2, 2.6e-3, 6.4e-4 of d_max at 20, 40, 80 samples for the sphere)."""
    prof = PROFILES[name]
    e = [profile_error(prof, n) for n in (20, 40, 80)]
    assert e[2] < 2e-3 and e[1] / e[2] > 3 and e[0] / e[1] > 3, e


@pytest.mark.parametrize("name", PROFILES)
def test_equivalent_profile_reproduces_force_shape_and_loops(name):
    """From 80 samples: the forces within 1e-3 (measured 3e-4), the axisymmetric profile f (MDR's
    inverse transform) within 1e-3 of d_max where the curve is smooth, and a partial-slip fretting
    cycle (force control, F_x = mu F_N / 2) with the dissipation within 2e-3 and the stick and contact
    radii within 1e-3 of the original profile's (measured 1.3e-3, 4e-4, 3e-4 for the sphere)."""
    prof = PROFILES[name]
    d, F = curve(prof, 80)
    eq = EquivalentProfile(d, F, MAT)
    assert eq.repair == 0.0
    dd = np.linspace(0.1, 0.9, 9) * d[-1]
    assert np.max(np.abs(force_from_approach(eq, MAT, dd) / force_from_approach(prof, MAT, dd) - 1)) < 1e-3
    r = np.linspace(0.1, 0.9, 9) * eq.x_limit
    if name == "sphere":  # the truncated sphere's f has its kink at b, which the interpolant rounds
        assert np.max(np.abs(eq.f(r) - prof.f(r))) < 1e-3 * d[-1]
    loading = Loading.of(0.5, fa=0.05, cycles=3, steps=80)
    a, b = run_mdr_contact(prof, MAT, 0.2, loading), run_mdr_contact(eq, MAT, 0.2, loading)
    assert abs(b["dissipation"] / a["dissipation"] - 1) < 2e-3
    assert abs(b["stick_radius"] / a["stick_radius"] - 1) < 1e-3
    assert abs(b["contact_radius"] / a["contact_radius"] - 1) < 1e-3


def test_equivalent_profile_is_specific_to_its_modulus():
    """The profile holds F(d) only with the E* it was built for: built from steel's curve with another
    pair's E*, the same law's forces are off by the ratio of the moduli (a = F' / (2 E*))."""
    prof = PROFILES["sphere"]
    d, F = curve(prof, 80)
    other = Materials(E2=70e9, nu2=0.33)
    wrong = EquivalentProfile(d, F, other)
    dd = np.linspace(0.2, 0.8, 4) * d[-1]
    ratio = force_from_approach(wrong, other, dd) / force_from_approach(prof, MAT, dd)
    assert np.all(np.abs(ratio - 1) < 2e-3)  # F(d) held with the pair's own E*
    assert np.all(np.abs(force_from_approach(wrong, MAT, dd) / force_from_approach(prof, MAT, dd)
                         - MAT.E_star / other.E_star) < 3e-3)


def test_noisy_curve_is_repaired_and_bad_curves_are_refused():
    prof = PROFILES["sphere"]
    d, F = curve(prof, 40)
    Fn = F.copy()
    Fn[20] = Fn[21]  # a plateau: the stiffness, so a(d), would fall to zero there
    eq = EquivalentProfile(d, Fn, MAT)
    assert 0 < eq.repair < 0.5 and np.all(np.diff(eq.g(np.linspace(0, eq.x_limit, 200))) >= 0)
    for dd, FF, msg in ((d[:3], F[:3], "length >= 4"), (d[::-1], F, "strictly increasing"),
                        (d, -F, "nondecreasing"), (d, np.where(d > d[5], np.nan, F), "finite")):
        with pytest.raises(InputError, match=msg):
            EquivalentProfile(dd, FF, MAT)
    with pytest.raises(InputError, match="beyond the curve's largest approach"):
        eq.g_inv(2 * d[-1])


def test_a_flat_face_whose_contact_stops_growing_keeps_its_whole_force_range():
    """The smooth face b = 0.6 mm: its contact radius grows by less than 1e-9 b up to 0.75 N (F is linear
    in d, a flat punch's), so a(d) is one plateau; the equivalent profile ends in a wall at b and carries
    the curve's whole range: every sampled force gives back its approach within 1e-3 (the flat punch's
    d = F / (2 E* b)), the largest one included."""
    mat = Materials()
    prof = TruncatedSphere(6e-3, 600e-6)
    F = 0.5 * np.geomspace(1e-2, 1.5, 24)
    d = np.asarray(approach_from_force(prof, mat, F), dtype=float)
    assert np.allclose(d, F / (2 * mat.E_star * 600e-6), rtol=1e-3, atol=0.0)
    eq = EquivalentProfile(d, F, mat)
    back = np.array([float(approach_from_force(eq, mat, f * (1 - 1e-5))) for f in F])  # the wall: 1e-6 short
    assert np.allclose(back, d, rtol=1e-3, atol=0.0)


#: a rough face's normal curve (b = 0.6 mm on a surface whose waviness ends at 2 a, steel on steel: the
#: rough half-space's F(d), m and N), on whose equivalent profile the Newton iteration of the contact radius
#: once stalled inside its bracket near 0.285 N (an undamped step across the kink of the tabulated slope)
ROUGH_FACE_D = [8.22258e-09, 1.0224e-08, 1.27126e-08, 1.58069e-08, 1.96544e-08, 2.44383e-08, 3.03867e-08,
                3.7783e-08, 4.69796e-08, 5.66371e-08, 6.57569e-08, 7.61211e-08, 8.5239e-08, 9.66864e-08,
                1.11009e-07, 1.28889e-07, 1.49534e-07, 1.64994e-07, 1.81525e-07, 2.0151e-07, 2.26315e-07,
                2.56415e-07, 2.91368e-07, 3.30369e-07]
ROUGH_FACE_F = [0.005, 0.00621703, 0.00773028, 0.00961187, 0.0119515, 0.0148605, 0.0184776, 0.0229752,
                0.0285674, 0.0355209, 0.0441669, 0.0549173, 0.0682845, 0.0849053, 0.105572, 0.131268, 0.16322,
                0.202948, 0.252347, 0.313769, 0.390143, 0.485105, 0.603182, 0.75]


def test_the_approach_of_every_force_inverts_a_rough_curves_profile():
    """Truth: the inverse of force_from_approach. Every force of the curve's range, densely, gives an
    approach whose force is the one asked, within 1e-8 (the iteration's own tolerance on its step)."""
    mat = Materials(E1=200e9, nu1=0.29, E2=200e9, nu2=0.29)
    eq = EquivalentProfile(ROUGH_FACE_D, ROUGH_FACE_F, mat)
    F = np.linspace(0.005, 0.7, 3000)
    d = approach_from_force(eq, mat, F)
    assert np.max(np.abs(force_from_approach(eq, mat, d) / F - 1)) < 1e-8
    for f in F[::10]:  # one at a time, as the apparatus asks
        assert abs(float(force_from_approach(eq, mat, approach_from_force(eq, mat, f))) / f - 1) < 1e-8
