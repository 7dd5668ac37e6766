"""Every command says its version and what to cite (``--version``), and CITATION.cff agrees with it.

Truths: the installed version is pyproject.toml's; the cited paper is the one whose experiment and model
the package follows (its DOI); CITATION.cff is valid YAML of the Citation File Format's required keys.
"""
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
VERSION = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
DOI = "10.3390/machines11040484"


@pytest.mark.parametrize("module", ["validation.compare", "validation.budget", "validation.docs",
                                    "validation.error_calibration", "mdr", "fem"])
def test_every_command_prints_its_version_and_what_to_cite(module):
    r = subprocess.run([sys.executable, "-m", module, "--version"], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0] == f"fretting-mdr-fem {VERSION}" and DOI in r.stdout and "Willert" in r.stdout
    assert "CITATION.cff" in r.stdout


def test_the_citation_file_names_this_version_and_the_paper():
    yaml = pytest.importorskip("yaml")
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    for key in ("cff-version", "message", "title", "authors"):
        assert cff.get(key), key
    assert cff["version"] == VERSION
    assert any(ref.get("doi") == DOI for ref in cff["references"])
