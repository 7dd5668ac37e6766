"""Rough height maps: generated (self-affine, isotropic, periodic) or measured (a file).

A generated map is a realisation of the isotropic power-law spectrum of a self-affine surface,
C(q) ~ q^(-2 (1 + H)) between the wavenumbers of the long and the short wavelength cut-offs and zero
outside them: no roll-off plateau (``Isopowerlaw2D`` with q0 = q1), so no wavelength longer than the
long cut-off is in the map (``tests/test_rough_surfaces.py`` asserts it on the map's own spectrum,
``radial_psd``); filtered white noise (tamaas
``SurfaceGeneratorFilter2D``; Hu & Tonder 1992, Int. J. Mach. Tools Manufact. 32, 83), scaled to
the stated rms height exactly. The parameters are SI and checked once (``RoughnessParams``): a cut-off
must be resolved by the grid (the short wavelength at least 2 pixels, the long one at most the map).

A measured map (``load_height_map``): ``.npy`` or a plain-text grid (CSV, or whitespace as a
profilometer's text export writes it), heights in metres, with its pixel size stated; a map that is
not a finite 2D grid of at least ``MIN_PIXELS`` per side, or without a positive pixel size, is one
line naming what is wrong.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from common.errors import InputError, in_range, positive, positive_int

#: the smallest map side (pixels) a contact computation can use
MIN_PIXELS = 8
#: what to run when tamaas is missing
TAMAAS_INSTALL = "pip install tamaas (or pip install -e '.[rough]')"


def require_tamaas():
    """The tamaas module, or an InputError naming the install command."""
    try:
        import tamaas
    except ImportError:
        raise InputError(f"rough surfaces need tamaas, the rough-contact library: {TAMAAS_INSTALL}") from None
    return tamaas


@dataclass(frozen=True)
class HeightMap:
    """Heights ``h`` (ny, nx) in m on a square pixel of ``pixel`` m (periodic when generated)."""

    h: np.ndarray
    pixel: float

    @property
    def size(self) -> tuple:
        return (self.h.shape[0] * self.pixel, self.h.shape[1] * self.pixel)

    @property
    def rms(self) -> float:
        return float(np.std(self.h))


@dataclass(frozen=True)
class RoughnessParams:
    """A self-affine isotropic surface (SI): ``rms`` height (m), ``hurst`` exponent in (0, 1], the
    short and long wavelength cut-offs ``lambda_short`` < ``lambda_long`` (m), a square map of side
    ``size`` (m) on ``n`` x ``n`` pixels, the random ``seed`` of the realisation."""

    rms: float
    hurst: float
    lambda_short: float
    lambda_long: float
    size: float
    n: int = 512
    seed: int = 0

    def __post_init__(self):
        positive("rms", self.rms)
        in_range("hurst", self.hurst, 0.0, 1.0, lo_open=True)
        positive("size", self.size)
        positive_int("n", self.n, minimum=MIN_PIXELS)
        positive_int("seed", self.seed + 1)  # >= 0
        pixel = self.size / self.n
        positive("lambda_short", self.lambda_short)
        if self.lambda_short < 2 * pixel:
            raise InputError(f"lambda_short must be at least 2 pixels ({2 * pixel:.4g} m for size {self.size:g} m "
                             f"on n = {self.n}), got {self.lambda_short:g} m")
        if not self.lambda_short < self.lambda_long <= self.size:
            raise InputError(f"lambda_long must be in (lambda_short, size] = ({self.lambda_short:g}, {self.size:g}] m, "
                             f"got {self.lambda_long!r}")

    @property
    def pixel(self) -> float:
        return self.size / self.n

    def wavenumbers(self) -> tuple:
        """(q_long, q_short): the cut-offs in units of 2 pi / size (tamaas's)."""
        return max(1, int(round(self.size / self.lambda_long))), int(round(self.size / self.lambda_short))


def generate(p: RoughnessParams) -> HeightMap:
    """One realisation of ``p`` (tamaas ``SurfaceGeneratorFilter2D`` with ``Isopowerlaw2D``), zero
    mean, scaled to the rms height ``p.rms`` exactly; the same seed gives the same map."""
    tm = require_tamaas()
    q_long, q_short = p.wavenumbers()
    spectrum = tm.Isopowerlaw2D()
    spectrum.q0, spectrum.q1, spectrum.q2, spectrum.hurst = q_long, q_long, q_short, p.hurst
    gen = tm.SurfaceGeneratorFilter2D([p.n, p.n])
    gen.spectrum = spectrum
    gen.random_seed = int(p.seed) + 1  # tamaas takes seeds >= 1 (a seed < 1 is seed 1)
    h = np.array(gen.buildSurface(), dtype=float)
    h -= h.mean()
    return HeightMap(h=h * (p.rms / h.std()), pixel=p.pixel)


def load_height_map(path, pixel, *, square: bool = False) -> HeightMap:
    """A measured map from ``path`` (``.npy``, else a plain-text grid: comma- or whitespace-separated),
    heights in m, square pixels of ``pixel`` m (the instrument's lateral resolution: stated, never
    guessed); the mean is removed. ``square``: the map must be n x n (a periodic grid's)."""
    if pixel is None:
        raise InputError(f"height map {str(path)!r}: the pixel size must be given (m; the instrument's lateral "
                         "sampling)")
    pixel = positive("pixel", pixel)
    path = Path(path)
    try:
        if path.suffix == ".npy":
            h = np.load(path, allow_pickle=False)
        else:
            text = path.read_text()
            h = np.loadtxt(text.splitlines(), delimiter="," if "," in text else None, dtype=float, ndmin=2)
    except (OSError, ValueError) as e:
        raise InputError(f"height map {str(path)!r} cannot be read as a grid of numbers: "
                         f"{str(e).splitlines()[0] if str(e) else type(e).__name__}") from None
    h = np.asarray(h, dtype=float)
    if h.ndim != 2 or min(h.shape) < MIN_PIXELS:
        raise InputError(f"height map {str(path)!r} must be a 2D grid of at least {MIN_PIXELS} x {MIN_PIXELS} "
                         f"pixels, got shape {h.shape}")
    bad = int(np.size(h) - np.isfinite(h).sum())
    if bad:
        raise InputError(f"height map {str(path)!r} has {bad} non-finite pixels (NaN or inf: fill or crop them "
                         "first)")
    if square and h.shape[0] != h.shape[1]:
        raise InputError(f"height map {str(path)!r} must be square for the periodic grid, got shape {h.shape}")
    return HeightMap(h=h - h.mean(), pixel=pixel)


#: the smallest side of a periodic map over the smooth contact radius: the contact must not overlap its
#: periodic images
MIN_CONTACT_RADII = 4.0


def load_realisations(paths, pixel) -> list:
    """Measured maps as realisations of one surface (``load_height_map``, square): at least two, distinct
    and of one size; ValueError saying what they must be where they are not (the caller names the field).
    Assumes each file is one realisation on the same pixel."""
    paths = list(paths)
    if len(paths) < 2:
        raise ValueError("a list of at least 2 height-map files (one realisation is no answer)")
    read = [load_height_map(f, pixel, square=True) for f in paths]
    if len({m.h.tobytes() for m in read}) != len(read):
        raise ValueError("distinct maps (the same map twice is one realisation)")
    sizes = sorted({m.h.shape[0] for m in read})
    if len(sizes) != 1:
        raise ValueError(f"maps of one size, got {sizes} pixels")
    return read


def covers(size: float, a: float) -> str | None:
    """Why a periodic map of side ``size`` (m) cannot carry a contact of smooth radius ``a`` (at least
    ``MIN_CONTACT_RADII`` radii on a side), None where it can."""
    if size >= MIN_CONTACT_RADII * a:
        return None
    return (f"maps of at least {MIN_CONTACT_RADII:g} smooth contact radii ({MIN_CONTACT_RADII * a:.3g} m) on a side: "
            f"the contact overlaps its periodic images on {size:.3g} m")


def radial_psd(m: HeightMap) -> tuple:
    """The radially averaged power spectrum of a square periodic map: (q (1/m, angular: 2 pi / wavelength),
    C(q) (m^4)), one value per integer wavenumber ring 1 .. n/2 (isotropic surfaces: the estimate whose
    log-log slope between the cut-offs is -2 (1 + H))."""
    h = m.h
    n = h.shape[0]
    if h.shape[0] != h.shape[1]:
        raise InputError(f"radial_psd needs a square map, got shape {h.shape}")
    L = n * m.pixel
    H = np.fft.fft2(h) * m.pixel ** 2
    C = np.abs(H) ** 2 / (2 * np.pi) ** 2 / L ** 2
    k = np.fft.fftfreq(n, d=1.0 / n)
    kk = np.hypot(*np.meshgrid(k, k, indexing="ij"))
    ring = np.rint(kk).astype(int)
    rings = np.arange(1, n // 2 + 1)
    vals = np.bincount(ring.ravel(), weights=C.ravel(), minlength=n)[rings] / \
        np.maximum(np.bincount(ring.ravel(), minlength=n)[rings], 1)
    return 2 * np.pi * rings / L, vals


def rms_slope(m: HeightMap) -> float:
    """The rms gradient sqrt(<|grad h|^2>) of a periodic map (spectral derivative)."""
    h = m.h
    kx = 2 * np.pi * np.fft.fftfreq(h.shape[0], d=m.pixel)
    ky = 2 * np.pi * np.fft.fftfreq(h.shape[1], d=m.pixel)
    H = np.fft.fft2(h)
    KX, KY = np.meshgrid(kx, ky, indexing="ij")
    gx, gy = np.real(np.fft.ifft2(1j * KX * H)), np.real(np.fft.ifft2(1j * KY * H))
    return float(np.sqrt(np.mean(gx ** 2 + gy ** 2)))


def resample(m: HeightMap, n: int) -> HeightMap:
    """The same periodic surface on n x n pixels (n >= the map's): spectral interpolation, the map's
    Fourier coefficients kept and zeros above its Nyquist wavenumber. Exact for a band-limited map (a
    generated one has nothing above ``lambda_short``): a grid ladder then refines one surface, not a
    new realisation per level."""
    h = m.h
    n0 = h.shape[0]
    if h.shape[0] != h.shape[1]:
        raise InputError(f"resample needs a square map, got shape {h.shape}")
    n = positive_int("n", n, minimum=n0)
    if n == n0:
        return m
    H = np.fft.fftshift(np.fft.fft2(h))
    o = n // 2 - n0 // 2  # the zero wavenumber of the map's shifted spectrum onto the new one's
    big = np.zeros((n, n), dtype=complex)
    big[o:o + n0, o:o + n0] = H
    # the real part splits an even map's Nyquist coefficient between +- its wavenumber, as it should
    fine = np.real(np.fft.ifft2(np.fft.ifftshift(big))) * (n / n0) ** 2
    return HeightMap(h=fine, pixel=m.pixel * n0 / n)


def band_limited(p: RoughnessParams, n: int) -> HeightMap:
    """The realisation of ``p`` generated on its own grid (``p.n`` pixels) and resampled to ``n``
    (``resample``): one band-limited surface on every grid of a ladder, the one home of that pairing
    (the roughness family's members, the budget's readings)."""
    return resample(generate(p), n)
