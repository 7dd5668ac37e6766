"""The 3D model's command line (``python -m fem contact --model 3d``) and its paired runs (``--paired``: the
same mesh's twin with an exact answer, whose error cancels the mesh's): bad input in one line before any
work, the fields and keys it writes. The model and constants of ``tests/test_contact3d.py``.
"""
import numpy as np
import pytest

from fem.options import FEOptions
from mdr import reference as ref
from mdr.loading import Loading
from test_contact3d import F, HZ, MAT, MU, R


@pytest.mark.parametrize("flags,msg", [
    (["--profile", "sphere", "--R", "6e-3", "--tilt", "0.5"], "tilt must be"),
    (["--profile", "sphere", "--R", "6e-3", "--block-size", "2e-5"], "size must be >"),
    (["--profile", "sphere", "--R", "6e-3", "--h-contact", "0.9"], "h_contact must be in"),
    (["--profile", "sphere", "--R", "6e-3", "--contact-extent", "0.9"], "contact_extent"),
    (["--profile", "sphere", "--R", "6e-3", "--ring", "0.9", "0.18", "0.5"], "band_h must be"),
    (["--profile", "sphere", "--R", "6e-3", "--vtu", "/proc/none/x.vtu"], "--vtu"),
])
def test_cli_model_3d_bad_input(flags, msg, capsys):
    from fem.cli import main

    assert main(["contact", "--model", "3d", *flags, "--mu", "0.2", "--F0", "0.5", "--fa", "0.05"]) == 2
    assert msg in capsys.readouterr().err


def test_cli_model_3d_writes_the_contact_fields(tmp_path, capsys):
    """``python -m fem contact --model 3d --vtu``: the contact disk at the drive's peak in the last cycle,
    both halves. At that turning point (Masing) the pressure is Hertz's and the stick zone
    Cattaneo-Mindlin's: the vertex pressures inside 0.8 a within 6 % of p0 in rms and 15 % at worst
    (measured 2.5 % and 7.2 % at h = a/7; 7.6 % and 27 % at a/4: the P1 multipliers converge), every
    sticking vertex inside c plus an element and every slipping one in contact outside c less one;
    the mirror image flips q_y and keeps q_x."""
    import meshio

    from fem.cli import main
    from mdr.reference import cattaneo_mindlin_stick_radius

    path = tmp_path / "c.vtu"
    fa = 0.5 * MU * F
    assert main(["contact", "--model", "3d", "--profile", "sphere", "--R", str(R), "--mu", str(MU), "--F0", str(F),
                 "--fa", str(fa), "--cycles", "2", "--steps", "24", "--h-contact", "0.15", "--vtu", str(path),
                 "--json", str(tmp_path / "o.json")]) == 0
    m = meshio.read(path)
    pd, x, y = m.point_data, m.points[:, 0], m.points[:, 1]
    r = np.hypot(x, y)
    n = r.size // 2
    hz = ref.hertz(F, R, MAT.E_star)
    a, p0 = float(hz["a"]), float(hz["p0"])
    inner = r < 0.8 * a
    e = pd["contact_pressure"][inner] - p0 * np.sqrt(1 - (r[inner] / a) ** 2)
    assert np.sqrt(np.mean(e ** 2)) < 0.06 * p0 and np.max(np.abs(e)) < 0.15 * p0
    c = float(cattaneo_mindlin_stick_radius(fa, F, MU, a))
    h = 0.15 * a
    stick, slip = pd["contact_status"] == 1, pd["contact_status"] == 2
    assert stick.any() and slip.any()
    assert r[stick].max() < c + h and r[slip].min() > c - h
    assert np.allclose(pd["shear_traction_y"][n:], -pd["shear_traction_y"][:n])
    assert np.allclose(pd["shear_traction_x"][n:], pd["shear_traction_x"][:n])
    assert np.allclose(y[n:], -y[:n]) and len(m.cells_dict["triangle"]) > 2 * n


@pytest.mark.parametrize("flags,msg", [
    (["--model", "3d", "--traction", "x"], "paired (--paired) needs the traction of free direction"),
    (["--model", "3d", "--tilt", "0.001"], "paired (--paired) needs the aligned face"),
    (["--model", "3d", "--E2", "70e9", "--nu2", "0.33"], "Dundurs' beta = 0"),
    (["--model", "3d", "--displacement", "plate"], "paired (--paired) needs displacement 'contact'"),
    (["--model", "3d", "--vtu", "x.vtu"], "leave out --vtu"),
    ([], "--paired applies to --model 3d only"),
])
def test_cli_paired_bad_input_before_any_work(flags, msg, capsys, monkeypatch):
    """--paired where its control variate is not exact: one line naming the conflict, exit 2, before
    the model is built (the set-up is replaced by a failure)."""
    from fem.cli import main
    from fem.options import FEOptions

    monkeypatch.setattr(FEOptions, "law", lambda *a, **k: pytest.fail("the model was built"))
    assert main(["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0.5", "--fa", "0.05",
                 "--paired", *flags]) == 2
    err = capsys.readouterr().err
    assert msg in err and len(err.strip().splitlines()) == 1, err


def test_paired_dissipation_cancels_the_mesh_error(shared_mesh_cache):
    """``run_fem_contact(paired=True)`` (``python -m fem contact --model 3d --paired``) on the coarse a/4
    mesh of ``law3d``, Q = mu F / 2: the free run's dissipation is far from the half-space answer without
    Mindlin's assumption (an independent boundary-element ladder: Mindlin-Deresiewicz x (1 - 0.43 %);
    measured +8.5 %), the paired estimate, MDR on the same loading times the free run over its twin along
    x on the same mesh, within 0.8 % of it (measured -0.36 %: the direction effect at a/4, -0.79 %, is
    what is left; -0.08 % at a/5, within 0.06 % at a/7 on ring meshes, ``test_ring_ensemble_dissipation_and_direction``).
    The MDR reference runs 10x the steps: Mindlin-Deresiewicz within 1e-4 (measured 2.5e-5)."""
    from conftest import BE_TURNING
    from fem.contact_run import run_fem_contact
    from mdr.profiles import Sphere

    us = ref.gross_slip_displacement(HZ["d"], MU, MAT.E_star, MAT.G_star)
    W_md = float(ref.mindlin_deresiewicz_dissipation_force(0.5 * MU * F, F, MU, us))
    out = run_fem_contact(Sphere(R), MAT, MU, Loading.of(F, fa=0.5 * MU * F, cycles=3, steps=40),
                          FEOptions(model="3d", h_contact=0.25, cache_dir=shared_mesh_cache), paired=True)
    pr, target = out["paired"], W_md * (1 + BE_TURNING)
    assert abs(pr["mindlin_dissipation"] / W_md - 1) < 1e-4, pr
    assert abs(pr["dissipation"] / target - 1) < 0.008, pr
    assert abs(out["dissipation"] / target - 1) > 0.03, out["dissipation"] / target  # what the pairing removed
    assert pr["direction_effect"] == pytest.approx(out["dissipation"] / pr["twin_dissipation"] - 1, rel=1e-12)
    assert pr["twin_error"] == pytest.approx(pr["twin_dissipation"] / pr["mindlin_dissipation"] - 1, rel=1e-12)
    assert out["runtime_s"]["twin"] > 0 and out["traction"] == "free"


def test_paired_note_where_the_twin_is_far_from_its_exact_answer(tmp_path, capsys):
    """A mesh that does not resolve the contact (the truncated sphere b = 20 um at --h-contact 0.3: the twin
    along x 44 % off MDR, the direction effect of the wrong sign) gets one line on stderr saying so; a
    twin within 10 % gets none."""
    from fem.cli import main
    from fem.contact_run import PAIRED_TWIN_ERROR_NOTE, paired_note

    assert main(["contact", "--model", "3d", "--profile", "truncated", "--R", str(R), "--b", "20e-6", "--mu", str(MU),
                 "--F0", str(F), "--fa", str(0.1 * F), "--cycles", "2", "--steps", "24", "--h-contact", "0.3",
                 "--paired", "--cache-dir", str(tmp_path), "--json", str(tmp_path / "o.json")]) == 0
    notes = [ln for ln in capsys.readouterr().err.splitlines() if "twin along x" in ln]
    assert len(notes) == 1 and "refine --h-contact" in notes[0], notes
    assert paired_note({"twin_error": 0.5 * PAIRED_TWIN_ERROR_NOTE}) is None
    assert "undetermined" in paired_note({"twin_error": None})


def test_paired_keys_of_runs_that_dissipate_nothing():
    """A twin or a reference that dissipated nothing, or not a finite amount: the ratios are None, not
    an exception or an infinity (a report prints them as missing)."""
    from fem.contact_run import paired_keys

    assert paired_keys({"dissipation": 1.0}, {"dissipation": 0.0}, {"dissipation": 1.0})["dissipation"] is None
    nan = paired_keys({"dissipation": float("nan")}, {"dissipation": 1.0}, {"dissipation": 1.0})
    assert nan["dissipation"] is None and nan["direction_effect"] is None and nan["twin_error"] == 0.0
    assert paired_keys({"dissipation": 2.0}, {"dissipation": 1.0}, {"dissipation": 3.0})["dissipation"] == 6.0


def test_cli_ring_is_for_the_3d_model(capsys):
    from fem.cli import main

    assert main(["contact", "--profile", "sphere", "--R", "6e-3", "--ring", "0.9", "0.18", "0.05", "--mu", "0.2",
                 "--F0", "0.5", "--fa", "0.05"]) == 2
    assert "--ring applies to --model 3d only" in capsys.readouterr().err


def test_cli_traction_is_for_the_3d_model(capsys):
    from fem.cli import main

    assert main(["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0.5", "--fa", "0.05",
                 "--traction", "x"]) == 2
    assert "--traction applies to --model 3d" in capsys.readouterr().err


# ------------------------------------------------------------------ the contact measure (fem.bulk in 3D)
