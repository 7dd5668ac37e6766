"""What a stated rms roughness means as a spectrum: the profilometer's band and the part of it a contact
sees.

A specimen's "rms roughness" is the profile parameter Rq (ISO 4287): the rms height after form removal,
of the profile filtered to the band [lambda_s, lambda_c] that ISO 4288 fixes by the roughness class
(``iso_band``, by the arithmetic mean height Ra; for Gaussian heights Ra = sqrt(2 / pi) Rq). A
self-affine surface of Hurst exponent H has the isotropic power spectrum C(q) ~ q^(-2 (1 + H)) between
the wavenumbers of its long and short cut-offs (``Finish``); its height variance between two
wavelengths is then the closed form ``variance_fraction``: int 2 pi q C(q) dq ~ lambda^(2 H). Each body
of a pair has its own finish; the gap sees their sum, the variances add (``window_rms``).

What a contact model on a periodic grid sees is the window [lambda_short, period] of that spectrum
(``window_rms``: the rms of the pair's combined spectrum inside the window, the number a generated map
is scaled to, ``rough.surfaces.RoughnessParams``); wavelengths shorter than the window's are left out
(a stated cut-off of the model), longer ones are form: ``form_curvature_rms`` says how much mean
curvature they add to the gap, so that a reader sees what leaving them out costs.

A profile's Rq is not the surface's areal rms over the same band: filtering a profile along x to the
band also removes the oblique waves whose wavelength along x is longer than lambda_c, so for an
isotropic power law the profile's variance is ``profile_variance_ratio`` (0.54 at H = 0.8) of the areal
one. A finish says which its rq is (``Finish.profile``); the spectra here are areal.

Assumptions: sharp band edges (the ISO filters are Gaussian; a sharp edge moves the fractions by the
filters' transition width), isotropic surfaces, the same Hurst
exponent over a body's whole band, and no power beyond a finish's cut-offs (no roll-off plateau:
exactly what ``rough.surfaces.generate`` makes).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from common.errors import InputError, in_range, positive

#: ISO 4288 (1996) Table 1 / ISO 3274: the cut-offs (lambda_s, lambda_c) in m of a non-periodic profile by
#: its Ra class (upper bound of Ra in m, inclusive)
ISO_BANDS = ((0.02e-6, 2.5e-6, 0.08e-3), (0.1e-6, 2.5e-6, 0.25e-3), (2e-6, 2.5e-6, 0.8e-3),
             (10e-6, 8e-6, 2.5e-3), (80e-6, 25e-6, 8e-3))
#: Ra over Rq of Gaussian heights
RA_OVER_RQ = math.sqrt(2.0 / math.pi)


def iso_band(rq: float) -> tuple:
    """(lambda_s, lambda_c) (m) of ISO 4288's roughness class of a profile of rms height ``rq`` (m), its
    Ra taken as sqrt(2 / pi) Rq (Gaussian heights): Rq 1 um -> (2.5 um, 0.8 mm), Rq 3 um -> (8 um,
    2.5 mm)."""
    ra = RA_OVER_RQ * positive("rq", rq)
    for top, ls, lc in ISO_BANDS:
        if ra <= top:
            return ls, lc
    raise InputError(f"rq must give Ra <= {ISO_BANDS[-1][0]:g} m (ISO 4288's classes), got {rq!r}")


def variance_fraction(hurst: float, band: tuple, window: tuple) -> float:
    """The fraction of the height variance of a self-affine spectrum over ``band`` (lambda_short,
    lambda_long) (m) that lies inside ``window`` (lo, hi) (m): (hi^2H - lo^2H) / (long^2H - short^2H)
    over the overlap, 0 where they do not overlap."""
    in_range("hurst", hurst, 0.0, 1.0, lo_open=True)
    s, l = band
    lo, hi = max(window[0], s), min(window[1], l)
    if not 0 < s < l:
        raise InputError(f"band must be 0 < short < long (m), got {band!r}")
    if hi <= lo:
        return 0.0
    e = 2.0 * hurst
    return (hi ** e - lo ** e) / (l ** e - s ** e)


def profile_variance_ratio(hurst: float) -> float:
    """A profile's height variance over a band of wavenumbers along it, over the areal variance of the
    isotropic surface over the same band of |q|: Gamma(H + 1/2) / (sqrt(pi) Gamma(H + 1)) for the power
    law C(q) ~ q^(-2 (1 + H)) (the profile's spectrum int C(sqrt(qx^2 + qy^2)) dqy ~ qx^(-1 - 2H); exact
    for a band wide against its edges): 0.64 at H = 0.5, 0.54 at 0.8, 0.5 at 1."""
    hurst = in_range("hurst", hurst, 0.0, 1.0, lo_open=True)
    return math.gamma(hurst + 0.5) / (math.sqrt(math.pi) * math.gamma(hurst + 1.0))


@dataclass(frozen=True)
class Finish:
    """One body's surface (SI): the rms height ``rq`` over its profilometer band (``iso_band`` of rq:
    what the stated value means), a self-affine spectrum of Hurst exponent ``hurst`` with no power
    beyond its cut-offs: short at lambda_s, long at ``rolloff`` where given and shorter than lambda_c
    (a surface whose waviness ends there: then all of rq lies in [lambda_s, rolloff]), else at
    lambda_c. ``profile``: rq is a profile's Rq (the areal rms over the band is rq over the square root
    of ``profile_variance_ratio``), else the surface's areal rms."""

    rq: float
    hurst: float = 0.8
    rolloff: float | None = None
    profile: bool = False

    def __post_init__(self):
        positive("rq", self.rq)
        iso_band(self.rq)
        in_range("hurst", self.hurst, 0.0, 1.0, lo_open=True)
        if self.rolloff is not None and not self.rolloff > self.band()[0]:
            raise InputError(f"rolloff must be longer than lambda_s = {self.band()[0]:g} m, got {self.rolloff!r}")

    def areal_rq(self) -> float:
        """The surface's areal rms height over its band (m)."""
        return self.rq / math.sqrt(profile_variance_ratio(self.hurst)) if self.profile else self.rq

    def band(self) -> tuple:
        """(short, long) cut-offs of the spectrum (m)."""
        ls, lc = iso_band(self.rq)
        return ls, lc if self.rolloff is None else min(self.rolloff, lc)


def window_rms(finishes, window: tuple) -> float:
    """The rms height (m) of the gap's spectrum (the bodies' ``finishes`` added) inside ``window``
    (lambda_short, lambda_long) (m): sqrt(sum rq^2 x variance_fraction)."""
    return math.sqrt(sum(f.areal_rq() ** 2 * variance_fraction(f.hurst, f.band(), window) for f in finishes))


def form_curvature_rms(finishes, longer_than: float) -> float:
    """The rms mean curvature (1/m) that the wavelengths of the ``finishes`` longer than ``longer_than``
    (m) add to the gap: sqrt(int q^4 C(q) 2 pi q dq) / 2 over that part of each band (the Laplacian's
    variance over 4), the curvature a model that leaves those wavelengths out as form omits."""
    total = 0.0
    for f in finishes:
        s, l = f.band()
        if l <= longer_than:
            continue
        e = 2.0 * f.hurst
        q1, q2, qs = 2 * math.pi / l, 2 * math.pi / max(longer_than, s), 2 * math.pi / s
        norm = f.areal_rq() ** 2 * e / (q1 ** -e - qs ** -e)  # C(q) 2 pi q = norm q^(-1-2H)
        total += norm * (q2 ** (4 - e) - q1 ** (4 - e)) / (4 - e)
    return math.sqrt(total) / 2.0
