"""Elastic constants of the two contacting bodies and the effective moduli.

Assumption: both bodies are homogeneous, isotropic and linearly elastic. The
effective moduli are the two-body definitions used throughout the project
(Popov & Hess, *Method of Dimensionality Reduction in Contact Mechanics and
Friction*, Springer 2015):

    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2
    1/G* = (2 - nu1)/(4 G1) + (2 - nu2)/(4 G2),   G_i = E_i / (2 (1 + nu_i)).
"""
from __future__ import annotations

from dataclasses import dataclass

from common.errors import in_range, positive

STEEL_E = 200e9
STEEL_NU = 0.29


@dataclass(frozen=True)
class Materials:
    """Indenter (E1, nu1) against block (E2, nu2); SI units (Pa)."""

    E1: float = STEEL_E
    nu1: float = STEEL_NU
    E2: float = STEEL_E
    nu2: float = STEEL_NU

    def __post_init__(self):
        object.__setattr__(self, "E1", positive("E1", self.E1))
        object.__setattr__(self, "E2", positive("E2", self.E2))
        object.__setattr__(self, "nu1", in_range("nu1", self.nu1, -1.0, 0.5, lo_open=True, hi_open=True))
        object.__setattr__(self, "nu2", in_range("nu2", self.nu2, -1.0, 0.5, lo_open=True, hi_open=True))

    @property
    def G1(self) -> float:
        return self.E1 / (2.0 * (1.0 + self.nu1))

    @property
    def G2(self) -> float:
        return self.E2 / (2.0 * (1.0 + self.nu2))

    @property
    def E_star(self) -> float:
        """Effective normal modulus E* (Pa)."""
        return 1.0 / ((1.0 - self.nu1**2) / self.E1 + (1.0 - self.nu2**2) / self.E2)

    @property
    def G_star(self) -> float:
        """Effective tangential modulus G* (Pa)."""
        return 1.0 / ((2.0 - self.nu1) / (4.0 * self.G1) + (2.0 - self.nu2) / (4.0 * self.G2))

    @property
    def dundurs_beta(self) -> float:
        """Dundurs' second constant of the pair, signed positive when the block (body 2) is the more
        compressible one: 0 for one material (no normal-tangential coupling)."""
        G1, G2 = self.G1, self.G2
        return 0.5 * ((1 - 2 * self.nu2) / G2 - (1 - 2 * self.nu1) / G1) / ((1 - self.nu2) / G2 + (1 - self.nu1) / G1)

    def as_dict(self) -> dict:
        return {"E1": self.E1, "nu1": self.nu1, "E2": self.E2, "nu2": self.nu2}
