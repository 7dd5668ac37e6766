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


@pytest.fixture(scope="session")
def shared_mesh_cache(tmp_path_factory):
    """One mesh cache for the whole test run, shared by pytest-xdist's workers (their base temporary
    directories are siblings): a mesh or condensed interface that several modules build (the a/4 sphere,
    steel and aluminium) is built once and read back verified after (``meshes.cache``: atomic writes,
    checked reads, so two workers building the same file at once is safe). Fresh every run; tests of the
    cache itself keep their own directories."""
    base = tmp_path_factory.getbasetemp()
    root = base.parent if base.name.startswith("popen-gw") else base
    path = root / "shared-mesh-cache"
    path.mkdir(exist_ok=True)
    return path
