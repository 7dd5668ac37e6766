"""Command line: JSON contract, stdout output, bad input -> exit 2 with one line."""
import json
import subprocess
import sys

import numpy as np
import pytest

from mdr import reference as ref
from studies.cli import main

from conftest import STEEL


def run(args, tmp_path=None):
    return subprocess.run([sys.executable, "-m", "mdr", *args], capture_output=True, text=True, timeout=120)


def test_normal_json(tmp_path):
    out = tmp_path / "n.json"
    assert main(["normal", "--profile", "sphere", "--R", "6e-3", "--F", "0.5", "--json", str(out)]) == 0
    d = json.loads(out.read_text())
    h = ref.hertz(0.5, 6e-3, STEEL.E_star)
    assert d["contact_radius"] == pytest.approx(h["a"], rel=1e-12)
    assert d["indentation"] == pytest.approx(h["d"], rel=1e-12)
    assert d["normal_force"] == 0.5 and d["runtime_s"] > 0
    r, p = np.array(d["pressure"]["r"]), np.array(d["pressure"]["p"])
    np.testing.assert_allclose(p, ref.hertz_pressure(r, 0.5, 6e-3, STEEL.E_star), rtol=1e-9)


def test_contact_json_to_stdout():
    proc = run(["contact", "--profile", "truncated", "--R", "6e-3", "--b", "20e-6", "--mu", "0.2", "--F0", "0.5",
                "--dF", "0.1", "--ua", "150e-9", "--cycles", "3", "--steps", "200", "--json", "-"])
    assert proc.returncode == 0, proc.stderr
    d = json.loads(proc.stdout)
    for key in ("contact_radius", "indentation", "stick_radius", "dissipation", "slip_index", "runtime_s"):
        assert np.isfinite(d[key])
    assert set(d["loop"]) == {"t", "du", "Fx", "FN"} and len(d["loop"]["t"]) == 201
    assert 0 < d["slip_index"] < 1


@pytest.mark.parametrize("args,word", [
    (["normal", "--profile", "sphere", "--R", "-6e-3", "--F", "0.5"], "R"),
    (["normal", "--profile", "sphere", "--R", "6e-3", "--F", "0"], "F"),
    (["normal", "--profile", "sphere", "--R", "nan", "--F", "0.5"], "R"),
    (["normal", "--profile", "truncated", "--R", "6e-3", "--b", "-1e-6", "--F", "0.5"], "b"),
    (["normal", "--profile", "truncated", "--R", "6e-3", "--b", "6e-3", "--F", "0.5"], "b"),
    (["normal", "--profile", "cone", "--R", "6e-3", "--F", "0.5"], "profile"),
    (["normal", "--profile", "sphere", "--R", "6e-3", "--F", "0.5", "--nu1", "0.5"], "nu1"),
    (["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "-0.2", "--F0", "0.5", "--ua", "1e-7"], "mu"),
    (["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0.5"], "ua"),
    (["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0.5", "--ua", "1e-7", "--fa", "0.01"], "fa"),
    (["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0.5", "--fa", "0.2"], "fa"),
    (["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0.5", "--ua", "1e-7", "--steps", "10"], "steps"),
])
def test_bad_input_exit_2_one_line(args, word, tmp_path, capsys):
    """In this process (the command's own ``main``; the interpreter's start is the one test below)."""
    out = tmp_path / "x.json"
    try:
        code = main([*args, "--json", str(out)])
    except SystemExit as e:  # argparse's own errors
        code = e.code
    err = capsys.readouterr().err
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and word in lines[0] and "Traceback" not in err
    assert not out.exists()


def test_bad_input_of_the_command_itself_is_one_line(tmp_path):
    """``python -m mdr`` as a user runs it: exit 2, one line naming the parameter, no file."""
    out = tmp_path / "x.json"
    proc = run(["normal", "--profile", "sphere", "--R", "-6e-3", "--F", "0.5", "--json", str(out)])
    lines = proc.stderr.strip().splitlines()
    assert proc.returncode == 2 and len(lines) == 1 and "R" in lines[0] and "Traceback" not in proc.stderr
    assert not out.exists()


def test_help_lists_commands():
    proc = run(["--help"])
    assert proc.returncode == 0 and "normal" in proc.stdout and "contact" in proc.stdout


def test_apparatus_json(tmp_path):
    out = tmp_path / "a.json"
    args = ["apparatus", "--profile", "truncated", "--R", "6e-3", "--b", "20e-6", "--mu", "0.2", "--mu2", "0.1",
            "--kx", "2e6", "--F0", "0.5", "--dF", "0.1", "--alpha", "0", "--ua", "150e-9", "--cycles", "3",
            "--steps", "80", "--cells", "100", "--json", str(out)]
    assert main(args) == 0
    d = json.loads(out.read_text())
    for key in ("contact_radius", "indentation", "stick_radius", "dissipation", "slip_index", "runtime_s"):
        assert np.isfinite(d[key])
    assert {"t", "du", "Fx", "FN"} <= set(d["loop"]) and 0 < d["slip_index"] < 1


def test_unknown_study_exit_2(tmp_path):
    proc = run(["study", "fig99", "--out", str(tmp_path)])
    assert proc.returncode == 2 and "study" in proc.stderr and not any(tmp_path.iterdir())


def test_apparatus_fem_json(tmp_path):
    out = tmp_path / "fe.json"
    args = ["apparatus", "--law", "fem", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0.5",
            "--dF", "0.1", "--ua", "150e-9", "--cycles", "2", "--steps", "16", "--h-contact", "0.05",
            "--cache-dir", str(tmp_path / "meshes"), "--json", str(out)]
    assert main(args) == 0
    d = json.loads(out.read_text())
    for key in ("contact_radius", "indentation", "stick_radius", "dissipation", "slip_index"):
        assert np.isfinite(d[key])
    assert d["dofs"] > 0 and d["mesh"]["key"] and set(d["runtime_s"]) == {"setup", "cycles", "total"}
    assert d["inputs"]["law"]["law"] == "fem" and {"t", "du", "Fx", "FN", "u1", "u2", "u3"} <= set(d["loop"])
    # the FE's own contact radius at F0 is Hertz's within the mesh error
    assert d["contact_radius"] == pytest.approx(ref.hertz(0.5, 6e-3, STEEL.E_star)["a"], rel=0.02)


FE_APP = ["apparatus", "--law", "fem", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0.5",
          "--ua", "150e-9"]


@pytest.mark.parametrize("extra,word", [
    (["--h-contact", "0.5"], "h_contact"), (["--h-contact", "0"], "h_contact"),
    (["--penalty", "-1"], "penalty"), (["--penalty", "nan"], "penalty"),
    (["--al-tol=-1e-3"], "al_tol"), (["--friction-al-tol", "-1"], "friction_al_tol"),
    (["--block-size", "0"], "block_size"), (["--contact-extent", "0.9"], "contact_extent"),
    (["--steps", "42"], "steps"), (["--mu2", "-0.1"], "mu2"), (["--solver", "magic"], "solver"),
])
def test_apparatus_fem_bad_input_exit_2_before_setup(extra, word, tmp_path, capsys):
    cache, out = tmp_path / "meshes", tmp_path / "x.json"
    try:
        code = main([*FE_APP, *extra, "--cache-dir", str(cache), "--json", str(out)])
    except SystemExit as exc:  # argparse rejects the value itself
        code = exc.code
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and word in err[0]
    assert not out.exists() and not cache.exists()  # failed before the FE set-up


def test_studies_in_parallel_processes_equal_sequential(tmp_path):
    """python -m mdr study fig9,sensitivity --jobs 2: same rows as one process, both files written."""
    from studies.study import run_studies, study_names

    par = run_studies("fig9,sensitivity", tmp_path / "par", jobs=2)
    seq = run_studies(["fig9", "sensitivity"], tmp_path / "seq", jobs=1)
    assert [r["study"] for r in par] == ["fig9", "sensitivity"]
    for a, b in zip(par, seq):
        assert a["rows"] == b["rows"]
    assert (tmp_path / "par" / "fig9.csv").is_file() and (tmp_path / "par" / "sensitivity.md").is_file()
    # the CSV says its units, and its numbers are the rows' (SI)
    import csv

    with open(tmp_path / "par" / "fig9.csv") as f:
        table = list(csv.reader(f))
    assert table[0][:2] == ["b (m)", "kx (N/m)"]
    assert [float(x[1]) for x in table[1:]] == [r["kx"] for r in par[0]["rows"]]
    assert study_names("all") == ["fig8", "fig9", "loops", "sensitivity", "plates"]
    rc = main(["study", "fig9,nope", "--out", str(tmp_path / "x")])
    assert rc == 2 and not (tmp_path / "x").exists()
    # the plate reading applies to fig8, fig9, loops only (sensitivity, plates vary it themselves)
    rc = main(["study", "fig9,sensitivity", "--plate-model", "tilt", "--out", str(tmp_path / "y")])
    assert rc == 2 and not (tmp_path / "y").exists()
