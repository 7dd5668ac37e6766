"""Scenes a user writes (``python -m validation.compare --scene-file``, ``validation.scene_file``).

The example file of the docs runs through the comparison as a user would run it, and its results
are held against closed forms (Hertz for the sphere on aluminium, with the pair's E*); every kind
of bad file is one line naming the field and its range, exit 2, before any work.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from mdr import Materials, reference as ref
from common.errors import InputError
from validation import compare
from validation.scene_file import load_scene_file
from validation.sides import materials_of

ROOT = Path(__file__).resolve().parent.parent
EXAMPLE = ROOT / "docs" / "examples" / "scenes.toml"


# slow (25 s: the example's full ladders, a/80 and 1600 cells); the fast suite runs a file of tiny
# ladders through the same command below
@pytest.mark.slow
def test_the_example_file_runs_and_its_sphere_is_hertz(tmp_path):
    scenes = load_scene_file(EXAMPLE)
    assert list(scenes) == ["alu-sphere", "apparatus-b15um"]
    rc = compare.main(["--scene-file", str(EXAMPLE), "--out", str(tmp_path), "--no-hard-cases", "--no-fields"])
    assert rc == 0
    data = json.loads((tmp_path / "results.json").read_text())
    assert set(data["scenes"]) == set(scenes)
    s = scenes["alu-sphere"]
    r = data["scenes"]["alu-sphere"]
    E_star = Materials(s.E1, s.nu1, s.E2, s.nu2).E_star
    a = ref.hertz(s.F0, s.R, E_star)["a"]
    assert r["mdr"]["contact_radius"] == pytest.approx(a, rel=1e-9)  # MDR is exact for the sphere
    assert r["fem"]["contact_radius"] == pytest.approx(a, rel=5e-3)   # the FE at a/80 (measured within 0.1 %)
    for name in scenes:  # no metric fails: the half-space holds for these large bodies
        assert data["scenes"][name]["holds"] is not False, (name, data["scenes"][name]["verdicts"])
    assert "## alu-sphere" in (tmp_path / "report.md").read_text()


TINY = """
[[scene]]
name = "alu-sphere-tiny"
title = "Steel sphere R = 10 mm on aluminium, tiny ladders"
profile = "sphere"
R = 10e-3
E2 = 70e9
nu2 = 0.33
mu = 0.3
F0 = 1.0
dF = 0.0
drive = "force"
amplitude = 0.15
cycles = 3
steps = 24
fe_levels = [0.125, 0.0833333333, 0.0625]
mdr_cells = [25, 50, 100]
"""


@pytest.mark.filterwarnings("ignore:coarse contact mesh:RuntimeWarning")  # coarse on purpose
def test_a_file_of_tiny_ladders_runs_and_its_sphere_is_hertz(tmp_path):
    """The example's first scene on tiny ladders (a/8 .. a/16, 25 .. 100 cells), through the same
    command: the results carry the file's scene, MDR's contact radius is Hertz's with the pair's E*
    (exact for the sphere) and the FE one within 0.5 % (the bound of the full example at a/80; measured
    2e-6 at a/8: the contact edge is read between the nodes, not at one)."""
    path = tmp_path / "tiny.toml"
    path.write_text(TINY)
    (s,) = load_scene_file(path).values()
    rc = compare.main(["--scene-file", str(path), "--out", str(tmp_path / "out"), "--no-fields"])
    assert rc == 0
    # a scene file runs its own scenes only: no hard case unless --hard-cases asks for them
    assert not (tmp_path / "out" / "hard_cases.json").exists()
    text = (tmp_path / "out" / "report.md").read_text()
    assert "## Hard cases" not in text
    # the report echoes the file's materials and says what both models leave out for a dissimilar pair
    assert "block E2 = 70 GPa, nu2 = 0.33" in text and "leave out the normal-tangential coupling" in text
    r = json.loads((tmp_path / "out" / "results.json").read_text())["scenes"]["alu-sphere-tiny"]
    E_star = materials_of(s).E_star
    a = ref.hertz(s.F0, s.R, E_star)["a"]
    assert E_star != Materials().E_star  # the file's block, not steel
    assert r["mdr"]["contact_radius"] == pytest.approx(a, rel=1e-9)
    assert r["fem"]["contact_radius"] == pytest.approx(a, rel=5e-3)
    assert "## alu-sphere-tiny" in (tmp_path / "out" / "report.md").read_text()


@pytest.mark.parametrize("text,word", [
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nradius = 1e-3\n', "unknown field(s) radius"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nR = -6e-3\n', "R must be > 0"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nF0 = "half a newton"\n', "F0 must be a number"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\ndF = 0.6\n', "dF must be in [0, F0)"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\ncycles = 2\n', "cycles must be an integer >= 3"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nfe_levels = [0.0125, 0.05]\n', "fe_levels must be"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nfe_levels = [4e-9, 2e-9]\n', "in [0.001, 0.25] (the axisym"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "cone"\n', "profile must be one of"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "truncated"\nb = 0.01\n', "b must be in [0, R)"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\ndrive = "apparatus"\n', "kx must be > 0"),
    ('[[scene]]\ntitle = "t"\nprofile = "sphere"\n', "missing field(s) name"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\n[[scene]]\nname = "x"\ntitle = "u"\nprofile = "sphere"\n',
     "used twice"),
    ('[scene]\nname = "x"\n', "one or more [[scene]] tables"),
    ('[[scene]]\nname = ".."\ntitle = "t"\nprofile = "sphere"\n', "name must be letters"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nsteps = 10\n', "steps must be a multiple of 4"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\namplitude = 0.09\n', "below the friction limit"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nfamily = "validity"\nvariants = [{block = -3.0}]\n',
     "validity variant"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nvariants = [{block = 3.0}]\n', "variants need a family"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nfamily = "wobble"\n', "family must be one of"),
    ('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nfamily = "tilt"\nvariants = [{block = 3.0}]\n',
     "needs variants, each holding tilts"),
    ('[[scene]\nname = "x"\n', "not valid TOML"),
])
def test_a_bad_file_is_one_line_naming_the_field(text, word, tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text(text)
    with pytest.raises(InputError, match=None) as err:
        load_scene_file(f)
    assert word in str(err.value) and "\n" not in str(err.value), str(err.value)


def test_the_command_refuses_a_bad_file_before_any_work(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text('[[scene]]\nname = "x"\ntitle = "t"\nprofile = "sphere"\nmu = -0.2\n')
    out = tmp_path / "out"
    p = subprocess.run([sys.executable, "-m", "validation.compare", "--scene-file", str(f), "--out", str(out)],
                       capture_output=True, text=True, timeout=300, cwd=ROOT)
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1 and "mu must be >= 0" in lines[0] and "bad.toml" in lines[0], p.stderr
    assert not out.exists()
    p = subprocess.run([sys.executable, "-m", "validation.compare", "--scene-file", str(tmp_path / "missing.toml")],
                       capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert p.returncode == 2 and "cannot be read" in p.stderr


def test_every_catalogue_scene_and_variant_passes_the_checks():
    """The range checks a user's scene meets hold for every built-in scene and every scene a family
    derives from its variants (a banded tilt row refines its band at one size: levels (0.3, 0.3))."""
    from validation.catalogue import CATALOGUE

    n = 0
    for s in CATALOGUE.values():
        for v in s.typed_variants:
            if hasattr(v, "scene"):  # a family that derives a scene from its variant
                v.scene(s)._check_numbers()
                n += 1
        s.quick_version()._check_numbers()
    assert n >= 10
