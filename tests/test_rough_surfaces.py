"""Rough height maps (``rough.surfaces``): generated maps have the stated rms height exactly and the
stated Hurst exponent in their measured spectrum (an FFT of the map, independent of the generator's
filter), no power beyond the short wavelength cut-off; measured maps are read from .npy, CSV and
whitespace text with their pixel size; bad parameters and bad maps are one line each."""
import numpy as np
import pytest

from common.errors import InputError
from rough.surfaces import RoughnessParams, generate, load_height_map, radial_psd

pytest.importorskip("tamaas", reason="rough surfaces need tamaas: pip install tamaas")

#: the paper's sphere (rms ~1 um), wavelengths 8 um to L/4 on a 1.6 mm map
PAPER = dict(rms=1e-6, hurst=0.8, lambda_short=8e-6, lambda_long=0.4e-3, size=1.6e-3, n=512)


def slope(m, p):
    q, C = radial_psd(m)
    ql, qs = p.wavenumbers()
    k = 2 * np.pi / p.size
    sel = (q > 1.5 * ql * k) & (q < qs * k / 1.5)
    return np.polyfit(np.log(q[sel]), np.log(C[sel]), 1)[0], q, C


@pytest.mark.parametrize("hurst", [0.3, 0.8])
def test_generated_maps_have_the_stated_rms_and_hurst_exponent(hurst):
    p = RoughnessParams(**{**PAPER, "hurst": hurst})
    slopes = []
    for seed in range(4):
        m = generate(RoughnessParams(**{**PAPER, "hurst": hurst, "seed": seed}))
        assert m.rms == pytest.approx(1e-6, rel=1e-12) and abs(m.h.mean()) < 1e-18
        assert m.pixel == pytest.approx(1.6e-3 / 512) and m.size == pytest.approx((1.6e-3, 1.6e-3))
        s, q, C = slope(m, p)
        slopes.append(s)
        qs = p.wavenumbers()[1] * 2 * np.pi / p.size
        assert np.max(C[q > 1.2 * qs]) < 1e-6 * np.max(C)  # filtered: nothing shorter than lambda_short
    # C(q) ~ q^(-2 (1 + H)): the ensemble's slope within 0.05 of it (0.025 in H; measured 0.016, 0.015)
    assert abs(np.mean(slopes) + 2 * (1 + hurst)) < 0.05, slopes


def test_a_seed_is_a_realisation():
    a, b, c = (generate(RoughnessParams(**{**PAPER, "seed": s})) for s in (7, 7, 8))
    assert np.array_equal(a.h, b.h) and not np.allclose(a.h, c.h)


@pytest.mark.parametrize("kw,word", [
    (dict(rms=-1e-6), "rms must be > 0"),
    (dict(hurst=1.2), "hurst must be in (0, 1]"),
    (dict(lambda_short=4e-6), "lambda_short must be at least 2 pixels"),
    (dict(lambda_long=3e-3), "lambda_long must be in (lambda_short, size]"),
    (dict(n=4), "n must be"),
])
def test_bad_parameters_are_one_line(kw, word):
    with pytest.raises(InputError) as e:
        RoughnessParams(**{**PAPER, **kw})
    assert word in str(e.value) and "\n" not in str(e.value)


def test_measured_maps_from_npy_csv_and_text(tmp_path):
    h = np.random.default_rng(1).normal(0, 1e-6, (16, 20)) + 5e-6
    np.save(tmp_path / "m.npy", h)
    np.savetxt(tmp_path / "m.csv", h, delimiter=",")
    np.savetxt(tmp_path / "m.txt", h)
    for name in ("m.npy", "m.csv", "m.txt"):
        m = load_height_map(tmp_path / name, pixel=2e-6)
        assert m.h.shape == (16, 20) and m.pixel == 2e-6 and abs(m.h.mean()) < 1e-18
        assert np.allclose(m.h, h - h.mean(), rtol=0, atol=1e-15)


@pytest.mark.parametrize("content,pixel,word", [
    ("nan", 1e-6, "non-finite pixels"),
    ("1d", 1e-6, "must be a 2D grid"),
    ("small", 1e-6, "at least 8 x 8"),
    ("ok", None, "pixel size must be given"),
    ("ok", -1.0, "pixel must be > 0"),
    ("junk", 1e-6, "cannot be read as a grid of numbers"),
])
def test_bad_maps_are_one_line(tmp_path, content, pixel, word):
    h = np.zeros((10, 10))
    path = tmp_path / "m.csv"
    if content == "nan":
        h[3, 4] = np.nan
    if content == "1d":
        np.save(path.with_suffix(".npy"), np.zeros(100))
        path = path.with_suffix(".npy")
    elif content == "small":
        np.savetxt(path, np.zeros((4, 10)), delimiter=",")
    elif content == "junk":
        path.write_text("a,b,c\n1,2\n")
    else:
        np.savetxt(path, h, delimiter=",")
    with pytest.raises(InputError) as e:
        load_height_map(path, pixel=pixel)
    assert word in str(e.value) and "\n" not in str(e.value)


def test_without_tamaas_the_message_names_the_install(monkeypatch):
    import builtins

    from rough import surfaces

    real = builtins.__import__

    def no_tamaas(name, *a, **k):
        if name == "tamaas":
            raise ImportError("no tamaas")
        return real(name, *a, **k)

    monkeypatch.setattr(builtins, "__import__", no_tamaas)
    with pytest.raises(InputError, match="pip install tamaas"):
        surfaces.generate(RoughnessParams(**PAPER))


def test_rms_slope_of_a_sine():
    """h = A sin(2 pi x / lambda): rms slope A (2 pi / lambda) / sqrt(2), to round-off."""
    from rough.surfaces import HeightMap, rms_slope

    n, px, A = 64, 1e-6, 1e-7
    x = np.arange(n) * px
    h = np.tile(A * np.sin(2 * np.pi * x / (n * px / 4)), (n, 1)).T
    assert rms_slope(HeightMap(h=h, pixel=px)) == pytest.approx(A * 2 * np.pi / (n * px / 4) / np.sqrt(2), rel=1e-12)
