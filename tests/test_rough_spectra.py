"""What a stated rms means as a spectrum (rough.spectra), against generated maps' own spectra.

Truths: the variance of a self-affine isotropic spectrum between two wavelengths grows as lambda^(2H)
(the closed form ``variance_fraction``), measured on generated maps band-pass filtered by FFT; the mean
curvature of a band (``form_curvature_rms``) measured as half the maps' spectral Laplacian; the generator
puts no power beyond its cut-offs (its docstring's claim, on its own radial spectrum); ISO 4288's bands by
the Ra class.
"""
import math

import numpy as np
import pytest

from common.errors import InputError
from rough.spectra import Finish, form_curvature_rms, iso_band, variance_fraction, window_rms
from rough.surfaces import RoughnessParams, generate, radial_psd

P, N = 400e-6, 256


def _maps(hurst, short, long, seeds=(0, 1, 2, 3)):
    return [generate(RoughnessParams(rms=1e-6, hurst=hurst, lambda_short=short, lambda_long=long, size=P, n=N,
                                     seed=s)) for s in seeds]


def _band_variance(m, lo, hi):
    """The variance of a periodic map between the wavelengths lo and hi (sharp FFT band-pass on |q|)."""
    H = np.fft.fft2(m.h)
    k = np.fft.fftfreq(N, d=m.pixel)
    lam = 1.0 / np.maximum(np.hypot(*np.meshgrid(k, k, indexing="ij")), 1e-30)
    keep = (lam >= lo) & (lam <= hi)
    return float(np.sum(np.abs(H[keep]) ** 2)) / N ** 4


@pytest.mark.parametrize("hurst", [0.5, 0.8, 1.0])
def test_the_variance_between_two_wavelengths_grows_as_lambda_to_the_2h(hurst):
    short, long = 8 * P / N, P / 2
    maps = _maps(hurst, short, long)
    window = (short, 4 * short)
    measured = np.mean([_band_variance(m, *window) / _band_variance(m, short, long) for m in maps])
    expected = variance_fraction(hurst, (short, long), window)
    assert measured == pytest.approx(expected, rel=0.12), (measured, expected)
    # the spectrum's exponent matters: the fraction of H = 0.5 is not H = 1's
    other = variance_fraction(1.5 - hurst if hurst != 1.0 else 0.5, (short, long), window)
    assert abs(other - expected) > 0.25 * expected


def test_the_generator_has_no_power_beyond_its_cut_offs():
    """rough.surfaces' docstring: zero outside [long, short] cut-offs (no roll-off plateau), the power law
    -2 (1 + H) between them."""
    m = _maps(0.8, 8 * P / N, P / 4, seeds=(0,))[0]
    q, C = radial_psd(m)
    q_long, q_short = 2 * np.pi / (P / 4), 2 * np.pi / (8 * P / N)
    below, inside = C[q < 0.99 * q_long], C[(q > 1.5 * q_long) & (q < 0.7 * q_short)]
    assert below.max() < 1e-12 * inside.max()  # nothing longer than the long cut-off
    assert C[q > 1.01 * q_short].max() < 1e-12 * inside.max()  # nor shorter than the short one
    sel = (q > 1.5 * q_long) & (q < 0.7 * q_short)
    slope = np.polyfit(np.log(q[sel]), np.log(C[sel]), 1)[0]
    assert slope == pytest.approx(-2 * 1.8, abs=0.25)


def test_the_form_curvature_is_half_the_laplacian_of_the_band():
    """A finish whose waviness ends at 100 um: the band [20, 100] um generated at the rms the closed form
    gives it, its mean curvature measured as half the spectral Laplacian, against form_curvature_rms."""
    f = Finish(0.3e-6, 0.8, rolloff=100e-6)
    rms = f.rq * math.sqrt(variance_fraction(f.hurst, f.band(), (20e-6, 100e-6)))
    maps = [generate(RoughnessParams(rms=rms, hurst=0.8, lambda_short=20e-6, lambda_long=100e-6, size=P, n=N,
                                     seed=s)) for s in range(4)]
    k = 2 * np.pi * np.fft.fftfreq(N, d=P / N)
    q2 = np.add.outer(k ** 2, k ** 2)
    kappa = [np.std(np.real(np.fft.ifft2(-q2 * np.fft.fft2(m.h)))) / 2 for m in maps]
    assert np.mean(kappa) == pytest.approx(form_curvature_rms([f], 20e-6), rel=0.1)
    assert form_curvature_rms([f], 100e-6) == 0.0  # nothing longer than the roll-off


def test_iso_bands_by_the_ra_class_and_the_window_of_a_pair():
    assert iso_band(1e-6) == (2.5e-6, 0.8e-3)  # Ra 0.8 um: class 0.1-2 um
    assert iso_band(3e-6) == (8e-6, 2.5e-3)  # Ra 2.4 um: class 2-10 um
    with pytest.raises(InputError):
        iso_band(1e-3)
    pair = (Finish(1e-6), Finish(3e-6))
    whole = window_rms(pair, (1e-9, 1.0))
    assert whole == pytest.approx(math.sqrt(1e-12 + 9e-12))  # the variances add
    assert window_rms(pair, (27e-6, 219e-6)) < 0.2 * whole  # the contact scale holds little of it at H 0.8
    rolled = (Finish(1e-6, rolloff=219e-6), Finish(3e-6, rolloff=219e-6))
    assert window_rms(rolled, (27e-6, 219e-6)) > 0.9 * whole  # unless the waviness ends there


@pytest.mark.parametrize("hurst", [0.5, 0.8, 1.0])
def test_a_profiles_variance_is_a_fraction_of_the_areal_one(hurst):
    """Every row of generated isotropic maps, filtered along x to the maps' band (sharp FFT band-pass on
    |q_x|), has the variance profile_variance_ratio(H) of the maps' areal variance over that band (the
    oblique waves longer than the band along x are filtered out; within 6 %: the band's finite upper
    edge); a Finish of a profile's Rq has the areal rms Rq / sqrt(ratio)."""
    from rough.spectra import profile_variance_ratio

    n, short, long = 1024, 4 * P / 1024, P / 16  # the band far from the grid's longest waves
    ratios = []
    for s in (0, 1):
        m = generate(RoughnessParams(rms=1e-6, hurst=hurst, lambda_short=short, lambda_long=long, size=P, n=n, seed=s))
        rows = np.fft.fft(m.h, axis=1)
        lam = 1.0 / np.maximum(np.abs(np.fft.fftfreq(n, d=m.pixel)), 1e-30)
        profile = float(np.sum(np.abs(rows[:, (lam >= short) & (lam <= long)]) ** 2)) / n ** 3
        ratios.append(profile / float(np.var(m.h)))
    assert np.mean(ratios) == pytest.approx(profile_variance_ratio(hurst), rel=0.06)
    assert profile_variance_ratio(hurst) < 0.65  # a profile sees well under the areal variance
    # docs/budget.md: 0.54 at H = 0.8, an areal rms 1.36 times a profile's Rq
    assert profile_variance_ratio(0.8) == pytest.approx(0.54, abs=0.005)
    assert 1 / math.sqrt(profile_variance_ratio(0.8)) == pytest.approx(1.36, abs=0.005)
    f = Finish(2e-6, hurst, profile=True)
    assert f.areal_rq() == pytest.approx(2e-6 / math.sqrt(profile_variance_ratio(hurst)), rel=1e-12)
    assert Finish(2e-6, hurst).areal_rq() == 2e-6
