"""Bad input everywhere: a clear error naming the parameter (and its valid range), never
NaN, a traceback or a silent wrong answer.

Python API: InputError whose message names the parameter. Commands (python -m mdr
normal|contact|apparatus|study, python -m fem normal|contact, python -m validation.compare):
exit code 2, exactly one line on stderr naming the parameter, no output file. The
commands are called in-process (argparse errors arrive as SystemExit) except
validation.compare, which is run as the documented command line.
"""
import importlib.util
import io
import json
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

from fem.cli import main as fem_main
from fem.axisym.law import FEContact
from fem.axisym.normal import solve_normal
from fem.axisym.normal_run import run_normal
from mdr import FlatPunch, GeneralProfile, InputError, Materials, MDRContact, Sphere, TruncatedSphere, make_profile
from mdr.apparatus import Apparatus, run_apparatus
from studies.cli import main as mdr_main
from mdr.drive import run_contact
from mdr.normal import approach_from_force, normal_energy, pressure
from meshes import AxisymMeshParams, cached_mesh
from meshes.cache import CacheError, load_mesh

from conftest import F0, MU, R, STEEL
from mdr.apparatus import mdr_apparatus_result
from mdr.drive import run_mdr_contact
from mdr.loading import Loading

NAN, INF = float("nan"), float("inf")


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("bad_input_meshes")


def run_cli(main, argv, tmp_path, capsys):
    """Run a command in-process; returns (exit code, stderr lines, output file exists)."""
    out = tmp_path / "out.json"
    argv = [*argv, "--json", str(out)] if "--json" not in argv else list(argv)
    capsys.readouterr()
    try:
        code = main(argv)
    except SystemExit as exc:  # argparse
        code = exc.code
    err = capsys.readouterr().err
    return code, err.strip().splitlines(), out.exists()


def assert_clean_failure(code, lines, written, word):
    assert code == 2, lines
    assert len(lines) == 1, lines
    assert word in lines[0] and "Traceback" not in lines[0]
    assert not written


# --------------------------------------------------------------------------- commands

SPH = ["--profile", "sphere", "--R", "6e-3"]
CONTACT = [*SPH, "--mu", "0.2", "--F0", "0.5"]
APP = [*SPH, "--mu", "0.2", "--F0", "0.5", "--ua", "1e-7", "--cycles", "2", "--steps", "40", "--cells", "50"]

MDR_CASES = [
    # sizes, forces, moduli: non-positive and non-finite
    (["normal", "--profile", "sphere", "--R", "0", "--F", "0.5"], "R"),
    (["normal", "--profile", "sphere", "--R", "inf", "--F", "0.5"], "R"),
    (["normal", *SPH, "--F", "-0.5"], "F"),
    (["normal", *SPH, "--F", "nan"], "F"),
    (["normal", *SPH, "--F", "inf"], "F"),
    (["normal", *SPH, "--F", "0.5", "--E1", "0"], "E1"),
    (["normal", *SPH, "--F", "0.5", "--E2", "-2e11"], "E2"),
    (["normal", *SPH, "--F", "0.5", "--E2", "inf"], "E2"),
    (["normal", "--profile", "flat", "--b", "0", "--F", "0.5"], "b"),
    (["normal", "--profile", "flat", "--b", "nan", "--F", "0.5"], "b"),
    # Poisson ratio outside (-1, 0.5)
    (["normal", *SPH, "--F", "0.5", "--nu1", "0.5"], "nu1"),
    (["normal", *SPH, "--F", "0.5", "--nu2", "-1"], "nu2"),
    (["normal", *SPH, "--F", "0.5", "--nu2", "0.7"], "nu2"),
    # b >= R
    (["normal", "--profile", "truncated", "--R", "6e-3", "--b", "7e-3", "--F", "0.5"], "b"),
    # unknown names
    (["normal", "--profile", "ellipsoid", "--R", "6e-3", "--F", "0.5"], "profile"),
    (["slide", *SPH], "slide"),
    # conflicting options
    (["normal", *SPH, "--b", "1e-6", "--F", "0.5"], "b"),
    (["normal", "--profile", "flat", "--R", "6e-3", "--b", "1e-4", "--F", "0.5"], "R"),
    (["normal", "--profile", "flat", "--b", "1e-4", "--F", "0.5", "--exact-cap"], "exact"),
    (["contact", *CONTACT, "--ua", "1e-8", "--fa", "0.01"], "fa"),
    (["contact", *CONTACT], "ua"),
    (["contact", *CONTACT, "--dF", "0.6", "--ua", "1e-8"], "dF"),
    (["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "0", "--F0", "0.5", "--fa", "1e-3"], "mu"),
    # friction, loads, resolution
    (["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "-0.1", "--F0", "0.5", "--ua", "1e-8"], "mu"),
    (["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "nan", "--F0", "0.5", "--ua", "1e-8"], "mu"),
    (["contact", *CONTACT, "--ua", "-1e-8"], "ua"),
    (["contact", *CONTACT, "--ua", "inf"], "ua"),
    (["contact", *CONTACT, "--fa", "0.2"], "fa"),
    (["contact", *CONTACT, "--ua", "1e-8", "--alpha", "nan"], "alpha"),
    (["contact", *CONTACT, "--ua", "1e-8", "--cycles", "1"], "cycles"),
    (["contact", *CONTACT, "--ua", "1e-8", "--steps", "42"], "steps"),
    (["contact", *CONTACT, "--ua", "1e-8", "--cells", "2"], "cells"),
    (["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0", "--ua", "1e-8"], "F0"),
    # apparatus
    ([*["apparatus"], *APP, "--kx", "0"], "kx"),
    ([*["apparatus"], *APP, "--kx", "nan"], "kx"),
    ([*["apparatus"], *APP, "--mu2", "-0.1"], "mu2"),
    ([*["apparatus"], *APP, "--R-bed", "0"], "R_bed"),
    ([*["apparatus"], *APP, "--dF", "0.6"], "dF"),
    ([*["apparatus"], *APP, "--plate-model", "spring"], "plate-model"),
    (["apparatus", "--profile", "truncated", "--R", "6e-3", "--b", "6e-3", "--mu", "0.2", "--F0", "0.5",
      "--ua", "1e-7"], "b"),
    (["apparatus", *SPH, "--mu", "-0.2", "--F0", "0.5", "--ua", "1e-7"], "mu"),
    (["apparatus", *SPH, "--mu", "0.2", "--F0", "0.5", "--ua", "0"], "ua"),
]


@pytest.mark.parametrize("argv,word", MDR_CASES, ids=[" ".join(a[0][:1] + a[0][-2:]) for a in MDR_CASES])
def test_mdr_command_bad_input(argv, word, tmp_path, capsys):
    assert_clean_failure(*run_cli(mdr_main, argv, tmp_path, capsys), word)


def test_mdr_study_unknown_name_writes_nothing(tmp_path, capsys):
    out = tmp_path / "study"
    code, lines, _ = run_cli(mdr_main, ["study", "fig10", "--out", str(out)], tmp_path, capsys)
    assert code == 2 and len(lines) == 1 and "fig10" in lines[0] and "study" in lines[0]
    assert not out.exists() or not any(out.iterdir())


def test_output_path_that_is_a_directory_is_an_input_error(tmp_path, capsys):
    d = tmp_path / "dir.json"
    d.mkdir()
    code, lines, _ = run_cli(mdr_main, ["normal", *SPH, "--F", "0.5", "--json", str(d)], tmp_path, capsys)
    assert code == 2 and len(lines) == 1 and "directory" in lines[0]
    assert list(d.iterdir()) == []
    code, lines, _ = run_cli(fem_main, ["normal", *SPH, "--F", "0.5", "--json", str(d)], tmp_path, capsys)
    assert code == 2 and len(lines) == 1 and "--json" in lines[0]
    f = tmp_path / "afile"
    f.write_text("x")
    code, lines, _ = run_cli(fem_main, ["normal", *SPH, "--F", "0.5", "--json", str(tmp_path / "o.json"),
                                        "--vtu", str(f / "fields.vtu")], tmp_path, capsys)
    assert code == 2 and len(lines) == 1 and "--vtu" in lines[0] and not (tmp_path / "o.json").exists()


@pytest.fixture
def unwritable(tmp_path):
    """A folder no file can be created in: mode 0555, and, where that does not stop the user (root),
    the immutable flag (chattr +i); skipped where neither works."""
    d = tmp_path / "ro"
    d.mkdir()
    d.chmod(0o555)
    flagged = False
    if os.access(d, os.W_OK):
        flagged = subprocess.run(["chattr", "+i", str(d)], capture_output=True).returncode == 0
        if not flagged:
            d.chmod(0o755)
            pytest.skip("no way to make a folder unwritable here (root without chattr)")
    yield d
    if flagged:
        subprocess.run(["chattr", "-i", str(d)], capture_output=True)
    d.chmod(0o755)


@pytest.mark.parametrize("main,argv", [
    (mdr_main, ["normal", *SPH, "--F", "0.5", "--json", "{ro}/x.json"]),
    (mdr_main, ["study", "fig9", "--out", "{ro}/study"]),
    (fem_main, ["normal", *SPH, "--F", "0.5", "--vtu", "{ro}/f.vtu", "--json", "{ok}/ok.json"]),
], ids=["mdr normal --json", "mdr study --out", "fem normal --vtu"])
def test_an_unwritable_output_is_rejected_before_any_work(main, argv, unwritable, tmp_path, capsys):
    argv = [a.format(ro=unwritable, ok=tmp_path) for a in argv]
    code, lines, _ = run_cli(main, argv, tmp_path, capsys)
    assert code == 2 and len(lines) == 1 and "cannot be written" in lines[0], lines
    assert not (tmp_path / "ok.json").exists() and list(unwritable.iterdir()) == []


def test_compare_with_an_unwritable_output_changes_no_file(unwritable, tmp_path):
    """--out or --json in a folder that takes no file: exit 2 and one line before any scene runs;
    a previous report beside it is left as it was."""
    good = tmp_path / "results"
    good.mkdir()
    (good / "report.md").write_text("previous report")
    for extra in (["--out", str(unwritable / "res")], ["--out", str(good), "--json", str(unwritable / "r.json")]):
        p = subprocess.run([sys.executable, "-m", "validation.compare", "--quick", *extra], capture_output=True,
                           text=True, timeout=300)
        lines = p.stderr.strip().splitlines()
        assert p.returncode == 2 and len(lines) == 1 and "cannot be written" in lines[0], p.stderr
        assert p.stdout == ""
    assert [f.name for f in good.iterdir()] == ["report.md"] and (good / "report.md").read_text() == "previous report"
    assert list(unwritable.iterdir()) == []


def test_negative_numbers_reach_the_range_check(tmp_path, capsys):
    """``--R -6e-3`` is a value (argparse alone takes it for an option): the range check names R."""
    code, lines, _ = run_cli(mdr_main, ["normal", "--profile", "sphere", "--R", "-6e-3", "--F", "0.5"], tmp_path, capsys)
    assert code == 2 and len(lines) == 1 and "R must be > 0" in lines[0], lines


def test_mdr_apparatus_loading_bad_input(tmp_path, capsys):
    for extra, word in ((["--cycles", "0", "--steps", "40"], "cycles"), (["--cycles", "2", "--steps", "0"], "steps"),
                        (["--cycles", "2", "--steps", "42"], "steps"), (["--alpha", "nan"], "alpha")):
        argv = ["apparatus", *SPH, "--mu", "0.2", "--F0", "0.5", "--ua", "1e-7", "--cells", "50", *extra]
        assert_clean_failure(*run_cli(mdr_main, argv, tmp_path, capsys), word)


def test_mdr_normal_points(tmp_path, capsys):
    assert_clean_failure(*run_cli(mdr_main, ["normal", *SPH, "--F", "0.5", "--points", "-3"], tmp_path, capsys),
                         "points")


FEM_NORMAL = ["normal", *SPH, "--F", "0.5", "--h-contact", "0.1"]
FEM_CONTACT = ["contact", *CONTACT, "--ua", "1e-8", "--steps", "8", "--cycles", "2", "--h-contact", "0.1"]
FEM_CASES = [
    (["normal", *SPH, "--F", "0"], "F"),
    (["normal", *SPH, "--F", "nan"], "F"),
    (["normal", "--profile", "sphere", "--R", "-6e-3", "--F", "0.5"], "R"),
    (["normal", "--profile", "sphere", "--F", "0.5"], "R"),
    (["normal", "--profile", "truncated", "--R", "6e-3", "--b", "6e-3", "--F", "0.5"], "b"),
    (["normal", "--profile", "flat", "--F", "0.5"], "b"),
    (["normal", "--profile", "cone", "--F", "0.5"], "profile"),
    ([*FEM_NORMAL, "--E1", "-1"], "E1"),
    ([*FEM_NORMAL, "--nu2", "0.5"], "nu2"),
    ([*FEM_NORMAL, "--nu1", "-1.5"], "nu1"),
    ([*FEM_NORMAL, "--penalty", "0"], "penalty"),
    ([*FEM_NORMAL, "--penalty", "nan"], "penalty"),
    ([*FEM_NORMAL, "--al-tol", "-1"], "al_tol"),
    ([*FEM_NORMAL, "--contact-extent", "0.9"], "contact_extent"),
    ([*FEM_NORMAL, "--block-size", "1e-5"], "block_radius"),
    ([*FEM_NORMAL, "--block-size", "-1"], "block_size"),
    (["normal", *SPH, "--F", "0.5", "--h-contact", "0.5"], "h_contact"),
    (["normal", *SPH, "--F", "0.5", "--h-contact", "0"], "h_contact"),
    ([*FEM_NORMAL, "--solver", "mumps"], "solver"),
    ([*FEM_NORMAL, "--b", "1e-6"], "b"),                                           # conflicting
    (["normal", "--profile", "flat", "--R", "6e-3", "--b", "1e-4", "--F", "0.5"], "R"),  # conflicting
    (["contact", *CONTACT, "--ua", "1e-8", "--fa", "0.01"], "fa"),
    (["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "-1", "--F0", "0.5", "--ua", "1e-8"], "mu"),
    (["contact", *CONTACT, "--fa", "0.5"], "fa"),
    (["contact", *CONTACT, "--ua", "nan"], "ua"),
    ([*FEM_CONTACT, "--penalty", "-1"], "penalty"),
    ([*FEM_CONTACT, "--friction-al-tol", "-1"], "friction_al_tol"),
    ([*FEM_CONTACT, "--b", "1e-6"], "b"),
    ([*FEM_CONTACT, "--E2", "0"], "E2"),
    (["contact", "--profile", "flat", "--b", "1e-4", "--exact-cap", "--mu", "0.2", "--F0", "0.5", "--ua", "1e-8"],
     "exact"),
]


@pytest.mark.parametrize("argv,word", FEM_CASES, ids=[" ".join(a[0][:1] + a[0][-2:]) for a in FEM_CASES])
def test_fem_command_bad_input(argv, word, cache, tmp_path, capsys):
    assert_clean_failure(*run_cli(fem_main, [*argv, "--cache-dir", str(cache)], tmp_path, capsys), word)


def test_fem_cache_dir_that_is_a_file(tmp_path, capsys):
    f = tmp_path / "not_a_dir"
    f.write_text("x")
    for argv in (FEM_NORMAL, FEM_CONTACT):
        code, lines, written = run_cli(fem_main, [*argv, "--cache-dir", str(f)], tmp_path, capsys)
        assert_clean_failure(code, lines, written, "cache_dir")


def test_fem_solver_failure_is_exit_3_with_diagnostics(cache, tmp_path, capsys):
    """A too soft penalty with a tight augmented-Lagrangian tolerance cannot converge in
    max_al passes: ConvergenceError with the penetration reached, exit 3, one line."""
    code, lines, written = run_cli(fem_main, [*FEM_NORMAL, "--penalty", "1e-3", "--al-tol", "1e-12",
                                              "--cache-dir", str(cache)], tmp_path, capsys)
    assert code == 3 and len(lines) == 1 and "penetration" in lines[0] and not written


@pytest.mark.skipif(importlib.util.find_spec("validation.compare") is None,
                    reason="validation.compare not written yet (issue 6)")
@pytest.mark.parametrize("extra,word", [
    (["--scenes", "no_such_scene"], "no_such_scene"),
    (["--no-such-option"], "no-such-option"),
])
def test_validation_compare_bad_input(extra, word, tmp_path):
    out = tmp_path / "report"
    js = tmp_path / "r.json"
    p = subprocess.run([sys.executable, "-m", "validation.compare", "--quick", "--out", str(out), "--json", str(js),
                        *extra], capture_output=True, text=True, timeout=300)
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2 and len(lines) == 1 and word in lines[0], p.stderr
    assert not js.exists() and (not out.exists() or not any(out.iterdir()))


# ----------------------------------------------------------------------- Python API

SPHERE = Sphere(R)


def _law():
    return MDRContact(SPHERE, STEEL, MU, F_max=0.6, n=50)


API_CASES = [
    (lambda: Sphere(0.0), "R"),
    (lambda: Sphere(NAN), "R"),
    (lambda: TruncatedSphere(R, R), "b"),
    (lambda: TruncatedSphere(R, 2 * R), "b"),
    (lambda: TruncatedSphere(R, -1e-6), "b"),
    (lambda: TruncatedSphere(np.full(3, R), np.array([1e-6, 7e-3, 2e-6])), "b"),
    (lambda: FlatPunch(-1e-4), "b"),
    (lambda: FlatPunch(INF), "b"),
    (lambda: GeneralProfile(lambda r: r**2, r_max=0.0), "r_max"),
    (lambda: GeneralProfile(lambda r: -r**2, r_max=1e-4), "nondecreasing"),
    (lambda: make_profile("cone", R), "profile"),
    (lambda: make_profile("sphere", R, 1e-6), "b"),
    (lambda: make_profile("flat", R, 1e-4), "R"),
    (lambda: make_profile("flat", None, 1e-4, exact=True), "exact"),
    (lambda: Materials(E1=0.0), "E1"),
    (lambda: Materials(E2=NAN), "E2"),
    (lambda: Materials(nu1=0.5), "nu1"),
    (lambda: Materials(nu2=-1.0), "nu2"),
    (lambda: MDRContact(SPHERE, STEEL, -0.1, F_max=1.0), "mu"),
    (lambda: MDRContact(SPHERE, STEEL, MU, F_max=-1.0), "F_max"),
    (lambda: MDRContact(SPHERE, STEEL, MU, F_max=1.0, F_min=-0.5), "F_min"),
    (lambda: MDRContact(SPHERE, STEEL, MU, F_max=1.0, n=2), "n"),
    (lambda: MDRContact("sphere", STEEL, MU, F_max=1.0), "profile"),
    (lambda: _law().step(_law().rest_state(), NAN, F_N=F0), "u"),
    (lambda: _law().step(_law().rest_state(), 0.0, d=NAN), "d"),
    (lambda: _law().step(_law().rest_state(), Fx=NAN, F_N=F0), "Fx"),
    (lambda: _law().step(_law().rest_state(), 0.0, F_N=-F0), "F_N"),
    (lambda: _law().step(_law().rest_state(), 0.0, F_N=INF), "F_N"),
    (lambda: _law().step(_law().rest_state(), Fx=0.2, F_N=F0), "Fx"),
    (lambda: _law().run(u=np.array([0.0, NAN]), F_N=np.full(2, F0)), "u"),
    (lambda: _law().run(u=np.zeros(3), d=np.array([1e-8, NAN, 1e-8])), "d"),
    (lambda: _law().run(u=np.zeros(3), F_N=np.array([F0, -1.0, F0])), "F_N"),
    (lambda: approach_from_force(SPHERE, STEEL, -1.0), "F_N"),
    (lambda: approach_from_force(TruncatedSphere(R, 20e-6), STEEL, NAN), "F_N"),
    (lambda: pressure(SPHERE, STEEL, -1e-9, [0.0]), "d"),
    (lambda: pressure(SPHERE, STEEL, NAN, [0.0]), "d"),
    (lambda: normal_energy(SPHERE, STEEL, NAN), "d"),
    (lambda: run_mdr_contact(SPHERE, STEEL, MU, Loading.of(-F0, ua=1e-8)), "F0"),
    (lambda: run_mdr_contact(SPHERE, STEEL, MU, Loading.of(F0, dF=-0.1, ua=1e-8)), "dF"),
    (lambda: run_mdr_contact(SPHERE, STEEL, MU, Loading.of(F0, ua=1e-8, fa=0.01)), "ua"),
    (lambda: run_mdr_contact(SPHERE, STEEL, 0.0, Loading.of(F0, fa=0.01)), "mu"),
    (lambda: run_contact(_law(), Loading.apparatus(F0)), "drive"),  # the apparatus's load on a contact driven directly
    (lambda: Loading(F0, 1e-8, drive="sideways"), "drive"),
    (lambda: Loading(F0, 1e-8, drive="displacement", steps=42), "steps"),
    (lambda: Loading(F0, -1e-8, drive="displacement"), "ua"),
    (lambda: Loading(F0, -0.01, drive="force"), "fa"),
    (lambda: Apparatus(kx=-1e6), "kx"),
    (lambda: Apparatus(mu2=NAN), "mu2"),
    (lambda: Apparatus(t=0.0), "t"),
    (lambda: Apparatus(plate_model="glued"), "plate_model"),
    (lambda: run_apparatus(_law(), Apparatus(), Loading.apparatus(-F0, ua=1e-7, cycles=2, steps=40)), "F0"),
    (lambda: mdr_apparatus_result(SPHERE, STEEL, Apparatus(), -MU, Loading.apparatus(F0, ua=1e-7, cycles=2, steps=40)), "mu"),
]


@pytest.mark.parametrize("call,word", API_CASES, ids=[f"{i}-{w}" for i, (_, w) in enumerate(API_CASES)])
def test_api_bad_input_names_the_parameter(call, word):
    with pytest.raises(InputError, match=word) as exc:
        call()
    assert "\n" not in str(exc.value)  # one line, also for array parameters


def test_apparatus_loading_bad_input():
    for kw, word in ((dict(cycles=0, steps=40), "cycles"), (dict(cycles=2, steps=0), "steps"),
                     (dict(alpha=NAN, cycles=2, steps=40), "alpha")):
        with pytest.raises(InputError, match=word):
            run_apparatus(_law(), Apparatus(), Loading.apparatus(F0, ua=1e-7, **kw))


API_MU = [  # the friction is the law's alone (no second copy beside it to disagree)
    (lambda: run_apparatus(MDRContact(SPHERE, STEEL, NAN, F_max=0.6, n=50), Apparatus(), Loading.apparatus(F0)), "mu"),
    (lambda: run_apparatus(_law(), Apparatus(), Loading.of(F0, ua=1e-7)), "drive"),  # a contact's load, no piezo
]


@pytest.mark.parametrize("call,word", API_MU, ids=["mu-nan", "drive"])
def test_apparatus_api_mu(call, word):
    with pytest.raises(InputError, match=word):
        call()


def test_fe_api_bad_input(cache):
    kw = dict(F_max=F0, h_contact=0.1, cache_dir=cache)
    cases = [
        (lambda: FEContact(SPHERE, STEEL, -0.2, **kw), "mu"),
        (lambda: FEContact(SPHERE, STEEL, np.array([0.1, 0.2]), **kw), "mu"),
        (lambda: FEContact(SPHERE, STEEL, MU, F_max=-1.0, h_contact=0.1, cache_dir=cache), "F_max"),
        (lambda: FEContact(SPHERE, STEEL, MU, h_contact=0.1, cache_dir=cache), "F_max"),
        (lambda: FEContact(SPHERE, STEEL, MU, penalty=0.0, **kw), "penalty"),
        (lambda: FEContact(SPHERE, STEEL, MU, friction_al_tol=NAN, **kw), "friction_al_tol"),
        (lambda: FEContact(SPHERE, STEEL, MU, max_al=0, **kw), "max_al"),
        (lambda: FEContact(SPHERE, STEEL, MU, friction_exact_start="yes", **kw), "friction_exact_start"),
        (lambda: FEContact(SPHERE, STEEL, MU, displacement="surface", **kw), "displacement"),
        (lambda: FEContact(GeneralProfile(lambda r: r**2, r_max=1e-4), STEEL, MU, **kw), "profile"),
        (lambda: FEContact(SPHERE, STEEL, MU, F_max=F0, h_contact=0.3, cache_dir=cache), "h_contact"),
        (lambda: run_normal("sphere", R=R, b=1e-6, F=F0, h_contact=0.1, cache_dir=cache), "b"),
        (lambda: run_normal("flat", R=R, b=1e-4, F=F0, h_contact=0.1, cache_dir=cache), "R"),
        (lambda: run_normal("sphere", R=R, F=F0, h_contact=0.1, cache_dir=cache, al_tol=-1.0), "al_tol"),
    ]
    for call, word in cases:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            with pytest.raises(InputError, match=word):
                call()
    law = FEContact(SPHERE, STEEL, MU, **kw)
    s0 = law.rest_state()
    for kws, word in ((dict(u=NAN, F_N=F0), "u"), (dict(u=0.0, d=NAN), "d"), (dict(u=0.0, F_N=-1.0), "F_N"),
                      (dict(u=0.0, F_N=NAN), "F_N"), (dict(Fx=INF, F_N=F0), "Fx"), (dict(Fx=0.2, F_N=F0), "Fx"),
                      (dict(F_N=F0), "u"), (dict(u=0.0), "d")):
        with pytest.raises(InputError, match=word):
            law.step(s0, **kws)
    with pytest.raises(InputError, match="F"):
        solve_normal(law.model, force=-1.0)
    with pytest.raises(InputError, match="force"):
        solve_normal(law.model, force=F0, approach=1e-7)


# ------------------------------------------------------------------ corrupt mesh cache


def _params():
    return AxisymMeshParams("sphere", R, 0.0, 30e-6, h_contact=0.1)


def _corruptions(path):
    """Ways a cache file can be damaged: truncated, emptied, overwritten with garbage,
    a flipped byte, and a well-formed file whose stored parameters were tampered with
    (digest consistent, so only the parameter check can catch it)."""
    good = path.read_bytes()
    yield "truncated", good[: len(good) // 3]
    yield "empty", b""
    yield "garbage", os.urandom(2048)
    flipped = bytearray(good)
    flipped[len(flipped) // 2] ^= 0x5A
    yield "flipped byte", bytes(flipped)
    with np.load(path) as z:
        arrs = {k: z[k] for k in z.files}
    header = json.loads(bytes(arrs.pop("__header__")).decode())
    header["params"] = dict(header["params"], h_contact="coarse")
    buf = io.BytesIO()
    np.savez(buf, __header__=np.frombuffer(json.dumps(header).encode(), dtype=np.uint8), **arrs)
    yield "tampered parameters", buf.getvalue()


def test_corrupt_cached_mesh_is_detected_and_rebuilt(tmp_path):
    p = _params()
    ref = cached_mesh(p, tmp_path)
    path = next(tmp_path.glob("axisym-*.npz"))
    for what, data in list(_corruptions(path)):
        path.write_bytes(data)
        with pytest.raises(CacheError):
            load_mesh(path, expected=p)
        with pytest.warns(RuntimeWarning, match="rebuilding mesh"):
            m = cached_mesh(p, tmp_path)
        assert m.info["cache"] == "rebuilt", what
        for b in ("indenter", "block"):
            assert np.array_equal(m.bodies[b].p, ref.bodies[b].p), what
        assert load_mesh(path, expected=p).key == ref.key  # the file was replaced by a good one


def test_corrupt_cached_mesh_through_the_command_gives_the_same_answer(tmp_path, capsys):
    argv = [*FEM_NORMAL, "--cache-dir", str(tmp_path / "c")]
    run_cli(fem_main, [*argv, "--json", str(tmp_path / "a.json")], tmp_path, capsys)
    path = next((tmp_path / "c").glob("axisym-*.npz"))
    path.write_bytes(path.read_bytes()[:100])
    with pytest.warns(RuntimeWarning, match="rebuilding mesh"):
        code, _, _ = run_cli(fem_main, [*argv, "--json", str(tmp_path / "b.json")], tmp_path, capsys)
    assert code == 0
    a, b = (json.loads((tmp_path / n).read_text()) for n in ("a.json", "b.json"))
    assert a["contact_radius"] == b["contact_radius"] and a["indentation"] == b["indentation"]
    assert a["mesh"]["cache"] == "miss" and b["mesh"]["cache"] == "rebuilt"


def test_cache_dir_that_is_a_file_is_an_input_error(tmp_path):
    f = tmp_path / "file"
    f.write_text("x")
    with pytest.raises(InputError, match="cache_dir"):
        cached_mesh(_params(), f)
