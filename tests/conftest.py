import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mdr import Materials

STEEL = Materials()
R = 6e-3
F0 = 0.5
MU = 0.2
#: an independent boundary-element ladder (run for an audit of this project, not part of it): the dissipation
#: of the traction free to turn against Mindlin's along x, steel on steel, the smooth sphere at Q = mu F / 2
#: (a/12 .. a/24): -0.43 +- 0.01 %, the half-space answer without Mindlin's assumption
BE_TURNING, BE_TURNING_ERROR = -0.43e-2, 0.01e-2


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


@pytest.hookimpl(trylast=True)  # after pytest-xdist has suffixed the grouped ids
def pytest_collection_modifyitems(config, items):
    """Warn when ``--dist loadgroup`` does not group: pytest-xdist marks a grouped test by a suffix
    ``@group`` on its node id, and with a pytest it cannot edit the id of (pytest-dev/pytest-xdist#1386,
    pytest 9.2 with xdist 3.8) the tests are spread one by one without a word. Nothing fails then, but
    each group's heavy fixture is built on both workers (about 40 s of the fast suite)."""
    if getattr(config.option, "loadgroup", False) is not True:
        return  # not an xdist worker under loadgroup
    grouped = [item for item in items if item.get_closest_marker("xdist_group") is not None]
    if grouped and not any("@" in item.nodeid for item in grouped):
        import warnings

        warnings.warn(pytest.PytestWarning(
            "pytest-xdist's --dist loadgroup does not group with this pytest (pytest-dev/pytest-xdist#1386): "
            "the grouped heavy fixtures are built on every worker; install the test extra's pytest "
            "(pip install -e '.[test]') or run without -n"))


# ------------------------------------------------------------------ the full catalogue (slow)
#: the README's command for the full catalogue, run as a user runs it (a fresh process, hard cases included)
README_COMMAND = [sys.executable, "-m", "validation.compare", "--jobs", "2"]
ROOT = Path(__file__).resolve().parent.parent


# session scope and one xdist group (the modules that read it: ``pytest.mark.xdist_group("catalogue")``):
# a module fixture is torn down whenever its worker runs another module's test in between; under -n the
# group keeps the tests that share it on one worker
@pytest.fixture(scope="session")
def full_run(tmp_path_factory):
    """The README's full comparison in a fresh process: (the process, its output folder)."""
    out = tmp_path_factory.mktemp("full")
    proc = subprocess.run(README_COMMAND + ["--out", str(out)], capture_output=True, text=True, cwd=ROOT)
    return proc, out


@pytest.fixture(scope="session")
def full(full_run):
    """The full comparison, asserted to have run: (exit code, output folder, its scenes' results)."""
    proc, out = full_run
    assert proc.returncode == 0, proc.stderr[-3000:]
    data = json.loads((out / "results.json").read_text())
    return proc.returncode, out, data["scenes"]


@pytest.fixture(scope="session")
def paper_budget(full):
    """The paper's budget as a user runs it on the catalogue's folder (``python -m validation.budget``):
    (the folder, the budget's JSON)."""
    _, out, _ = full
    r = subprocess.run([sys.executable, "-m", "validation.budget", "--out", str(out), "--jobs", "2", "--json",
                        str(out / "budget.json")], capture_output=True, text=True, cwd=ROOT, check=False)
    assert r.returncode == 0, r.stderr[-2000:]
    return out, json.loads((out / "budget.json").read_text())
