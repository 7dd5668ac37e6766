"""The elastic half-space's influence kernels on a grid of square pixels (Love 1929, the uniform pressure
on a rectangle; the 1/r kernel of the tangential problem): the periodic compliance in Fourier space
(``normal_compliance``, ``periodic_displacement``), its dense blocks among chosen cells
(``among_cells``), and the non-periodic displacement of a window by a zero-padded FFT
(``PixelConvolution``, ``halfspace_displacement``). One home for ``rough.normal``, ``rough.law`` and
``rough.tangential``. A ``grid`` is a ``rough.normal.Grid`` (its ``n`` pixels a side, ``pixel`` size).
"""
from __future__ import annotations

import functools

import numpy as np
import scipy.fft as sfft

def normal_compliance(grid, E_star) -> np.ndarray:
    """The periodic half-space's surface compliance in discrete Fourier space (rfft2 layout, m / Pa):
    u(k) = 2 p(k) / (E* |k|) (Westergaard's, the kernel of tamaas's elastic solve: the same contact for
    a cap the pressure never reaches, ``tests/test_rough_normal.py``), the mean (rigid) mode 0."""
    kx = 2.0 * np.pi * np.fft.fftfreq(grid.n, d=grid.pixel)
    ky = 2.0 * np.pi * np.fft.rfftfreq(grid.n, d=grid.pixel)
    k = np.hypot(*np.meshgrid(kx, ky, indexing="ij"))
    out = np.zeros_like(k)
    out[k > 0] = 2.0 / (float(E_star) * k[k > 0])
    return out


def periodic_displacement(grid, E_star):
    """p -> K p: the periodic half-space's surface displacement (m) under the pixel pressures p (Pa),
    with ``normal_compliance``'s kernel (its mean mode 0)."""
    K = normal_compliance(grid, E_star)

    def apply(p):
        return sfft.irfft2(K * sfft.rfft2(p), s=p.shape)

    return apply


def among_cells(kernel, cells, n: int, periodic: bool, at=None) -> np.ndarray:
    """The dense matrix of a convolution kernel among the pixels ``cells`` (flat indices of an (n, n)
    grid): entry (a, b) the kernel at the offset of pixel a from pixel b, ``kernel`` (n, n) of the periodic
    grid (offsets modulo n) or (2n - 1, 2n - 1) of the window (offsets -(n - 1) .. n - 1). ``at``: the
    rows' pixels instead (flat indices; the field at those pixels of sources on ``cells``)."""
    i, j = np.divmod(np.asarray(cells, dtype=np.int64), n)
    ia, ja = (i, j) if at is None else np.divmod(np.asarray(at, dtype=np.int64), n)
    di, dj = ia[:, None] - i[None, :], ja[:, None] - j[None, :]
    return kernel[di % n, dj % n] if periodic else kernel[di + n - 1, dj + n - 1]


@functools.lru_cache(maxsize=4)
def _periodic_kernel(grid, E_star: float):
    """The periodic half-space's displacement under a unit pressure on pixel 0, in real space (n, n),
    and ``periodic_displacement``'s operator in single precision (kept per grid: a screen, not an
    answer)."""
    K = normal_compliance(grid, E_star)
    kernel = np.fft.irfft2(K, s=(grid.n, grid.n))
    kernel.flags.writeable = False
    K32 = K.astype(np.float32)

    def screen(p):
        return sfft.irfft2(K32 * sfft.rfft2(np.asarray(p, dtype=np.float32)), s=p.shape)

    return kernel, screen


def _pixel_kernel(X, Y, h):
    """int of 1 / r over the pixel of side h centred at (X, Y) (closed form: the corners of
    x ln(y + r) + y ln(x + r))."""
    def F(x, y):
        r = np.hypot(x, y)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.nan_to_num(x * np.log(y + r)) + np.nan_to_num(y * np.log(x + r))

    a = 0.5 * h
    return F(X + a, Y + a) - F(X - a, Y + a) - F(X + a, Y - a) + F(X - a, Y - a)


def halfspace_displacement(p, pixel, E_star) -> np.ndarray:
    """The normal displacement (m) of a half-space of modulus E* at the pixel centres under the
    pixel-wise uniform pressure ``p`` (n, n) (Pa), without periodic images (Boussinesq's 1 / (pi E* r)
    integrated over each pixel, a zero-padded FFT convolution): the approach of a contact whose
    pressure vanishes at the grid's border, as a half-space has it."""
    return _boussinesq(p.shape[0], float(pixel), float(E_star))(p)


@functools.lru_cache(maxsize=4)
def _boussinesq(n: int, pixel: float, E_star: float) -> "PixelConvolution":
    """``halfspace_displacement``'s convolution on one grid, kept for the force-approach curve's loads
    (the same bits as building it per call)."""
    return PixelConvolution(_boussinesq_kernel(n, pixel, E_star))


@functools.lru_cache(maxsize=4)
def _boussinesq_kernel(n: int, pixel: float, E_star: float) -> np.ndarray:
    """The half-space's normal displacement (m) at the pixel centres offset by -(n - 1) .. n - 1 pixels
    under a unit pressure (Pa) on one pixel, without periodic images ((2n - 1, 2n - 1), read-only; kept
    per grid: ``contact_approach`` gathers its contacts' matrices from it)."""
    out = inverse_r_kernel(n, pixel) / (np.pi * E_star)
    out.flags.writeable = False
    return out


@functools.lru_cache(maxsize=4)
def inverse_r_kernel(n: int, pixel: float) -> np.ndarray:
    """int of 1 / r over a pixel of side ``pixel`` at the offsets -(n - 1) .. n - 1 pixels
    ((2n - 1, 2n - 1), read-only; kept per grid: Boussinesq's and Cerruti's pixel kernels share it)."""
    k = np.arange(-n + 1, n) * pixel
    X, Y = np.meshgrid(k, k, indexing="ij")
    out = _pixel_kernel(X, Y, pixel)
    out.flags.writeable = False
    return out


class PixelConvolution:
    """field -> sum_j K(x_i - x_j) field_j at the pixel centres of an (n, n) field, for a kernel ``K``
    (2n - 1, 2n - 1) sampled at the offsets -(n - 1) .. n - 1 pixels: a linear (not circular)
    convolution by zero-padded FFTs, so no periodic image enters; the kernel's FFT kept (read-only)."""

    def __init__(self, K):
        import scipy.fft as sfft

        self.n = (K.shape[0] + 1) // 2
        # a linear (not circular) convolution of n and 2n - 1 samples needs 3n - 2; a fast FFT length
        self.m = sfft.next_fast_len(3 * self.n - 2, real=True)
        self.hat = sfft.rfft2(K, s=(self.m, self.m))
        self.hat.flags.writeable = False

    def transform(self, field) -> np.ndarray:
        """The zero-padded field's FFT (several kernels applied to one field share it)."""
        import scipy.fft as sfft

        return sfft.rfft2(field, s=(self.m, self.m))

    def back(self, spectrum) -> np.ndarray:
        """The window of the inverse FFT of a product of kernel and field transforms."""
        import scipy.fft as sfft

        n = self.n
        return sfft.irfft2(spectrum, s=(self.m, self.m))[n - 1:2 * n - 1, n - 1:2 * n - 1]

    def __call__(self, field) -> np.ndarray:
        return self.back(self.transform(field) * self.hat)

    def circulant_eigenvalues(self) -> np.ndarray:
        """The eigenvalues of the circulant on the padded grid that embeds this convolution, for an even
        kernel (real): their largest bounds the (n, n) window's operator."""
        n, m = self.n, self.m
        k = np.arange(m)
        shift = np.exp(2j * np.pi * (n - 1) * k / m)  # the kernel's offset 0 moved to index 0
        return (self.hat * shift[:, None] * shift[None, :self.hat.shape[1]]).real
