"""Every literate example under docs/examples runs and says what its text says (scikit-fem's pattern:
the example is imported and its ``main`` run; the numbers are checked against the example's truth).

Truths: Hertz, Cattaneo-Mindlin and Mindlin-Deresiewicz for the MDR law (exact in the half-space);
MDR and the axisymmetric FE law in the same apparatus agree on the slip index of the paper's sphere
within the FE mesh's error.
"""
import importlib.util
from pathlib import Path


EXAMPLES = Path(__file__).resolve().parent.parent / "docs" / "examples"


def _load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_mdr_against_hertz_cattaneo_mindlin_and_mindlin_deresiewicz():
    """docs/examples/mdr_hertz_mindlin.py: the contact radius exact on every grid; the stick radius within
    1e-6 at 1600 springs; the dissipation about second order until the time step's error (< 1e-4)."""
    ex = _load("mdr_hertz_mindlin")
    err = ex.main(out=lambda line: None)
    assert all(abs(e["contact_radius"]) < 1e-12 for e in err.values())
    assert abs(err[1600]["stick_radius"]) < 1.5e-6 and abs(err[25]["stick_radius"]) > 100 * abs(err[1600]["stick_radius"])
    assert 5e-3 < abs(err[25]["dissipation"]) < 4e-2 and abs(err[100]["dissipation"]) < 3e-3
    assert abs(err[25]["dissipation"]) / abs(err[100]["dissipation"]) > 8  # about second order (16x)
    assert all(abs(err[n]["dissipation"]) < 1e-4 for n in (400, 1600))  # the time step's floor


def test_an_apparatus_point_with_mdr_and_the_fe_law():
    """docs/examples/apparatus_point.py: at the paper's scale MDR and the FE law of the finite bodies give
    the same slip index within the FE mesh's error (measured 3e-4 at h = a/10); the FE contact radius at
    F0 within its coarse mesh's error of MDR's (measured 0.6 %); the point slips partly."""
    ex = _load("apparatus_point")
    r = ex.main(out=lambda line: None)
    mdr, fem = r["mdr"], r["fem"]
    assert 0.05 < mdr["slip_index"] < 0.95
    assert abs(mdr["slip_index"] - fem["slip_index"]) < 1e-3
    assert abs(fem["contact_radius"] / mdr["contact_radius"] - 1) < 0.015


def test_the_pressure_under_a_truncated_sphere(tmp_path):
    """docs/examples/truncated_sphere_pressure.py: the FE contact radius within 0.1 % of MDR's (measured
    0.056 %), the FE pressure integrated to F within 1 % (measured 0.5 %: the trapezoid on the nodes), the
    face's inner half within 1e-3 of MDR's pressure (measured 3.3e-4), a peak at the kink (measured 2.95x
    the pressure at half the face), and the figure written."""
    ex = _load("truncated_sphere_pressure")
    fig = tmp_path / "p.png"
    r = ex.main(out=lambda line: None, figure=fig)
    assert abs(r["contact_radius"]["fe"] / r["contact_radius"]["mdr"] - 1) < 1e-3
    assert abs(r["force_fe"] / ex.F - 1) < 0.01
    assert r["face_pressure_difference"] < 1e-3 and r["kink_over_face"] > 1.5
    assert fig.stat().st_size > 10_000


def test_every_example_is_run_by_a_test():
    """No example is left unchecked: each script under docs/examples is named by a test here or, for the
    rough engine's (slow, tamaas), by tests/test_rough_equivalent.py."""
    tested = {"mdr_hertz_mindlin", "apparatus_point", "truncated_sphere_pressure", "rough_equivalent"}
    assert {p.stem for p in EXAMPLES.glob("*.py")} <= tested


def test_every_example_renders_into_the_docs_site_whole():
    """The docs site's Examples pages (``docs/hooks/examples.py``): each script's page holds all its code,
    in order, and its prose (the code blocks joined are the script's lines after the docstring that are
    not comments; every comment's words are on the page), titled by the docstring's first line."""
    import re

    spec = importlib.util.spec_from_file_location("examples_hook", EXAMPLES.parent / "hooks" / "examples.py")
    hook = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hook)
    scripts = sorted(EXAMPLES.glob("*.py"))
    assert len(scripts) >= 4
    for path in scripts:
        src = path.read_text()
        page = hook.render(src)
        assert page.startswith("# "), path.name
        shown = [ln for block in re.findall(r"```python\n(.*?)\n```", page, flags=re.S) for ln in block.split("\n")]
        body = src.split('"""', 2)[2].split("\n")[1:]  # after the module docstring
        code = [ln for ln in body if not re.match(r"^# ?", ln) or "noqa" in ln]
        assert [ln for ln in shown if ln.strip()] == [ln for ln in code if ln.strip()], path.name
        for ln in body:
            if ln.startswith("# ") and "noqa" not in ln:
                assert ln[2:].lstrip("# ") in page, (path.name, ln)
