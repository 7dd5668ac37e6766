import numpy as np
import pytest

from mdr import Materials

STEEL = Materials()
R = 6e-3
F0 = 0.5
MU = 0.2


@pytest.fixture
def steel():
    return STEEL


def harmonic(cycles, steps):
    t = np.arange(cycles * steps + 1) / steps
    return t, np.sin(2 * np.pi * t)
