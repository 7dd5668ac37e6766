"""validation.compare: report structure, figures, atomic per-scene storage, metrics (fast suite).

The physics of the full catalogue is asserted in tests/test_validation_full.py (slow).

Over 500 lines for a stated reason: its tests share the module's quick comparison (``quick_report``,
about a minute); split, each part would run it again.
"""
from __future__ import annotations

import concurrent.futures as cf
import copy
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from mdr import Materials, reference as ref
from mdr.profiles import TruncatedSphere
from validation import compare, metrics, runner, sides, store
from validation.families import assumptions3d, tilt
from validation.fields import image_is_blank
from validation.catalogue import CATALOGUE, select
from validation.scenes import Scene
from validation.sources import code_version
from mdr.drive import run_mdr_contact
from mdr.loading import Loading

CONTRACT_KEYS = ("contact_radius", "indentation", "stick_radius", "dissipation", "slip_index", "runtime_s", "loop")


def tiny(name="sphere-md", **kw):
    """A scene on very coarse ladders (seconds): structure, not accuracy."""
    s = CATALOGUE[name]
    return replace(s, fe_levels=(1 / 8, 1 / 16), mdr_cells=(25, 100), steps=40, cycles=3, **kw)


# session scope: a module fixture is torn down whenever its worker runs another module's test in
# between, and built again; its tests are grouped on one worker (xdist_group), so it is built once
@pytest.fixture(scope="session")
def quick_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("compare")
    rc = compare.main(["--quick", "--scenes", "sphere-md", "--out", str(out), "--no-hard-cases"])
    return rc, out


@pytest.mark.xdist_group("validation-quick-report")  # the module fixture quick_report built once, on one worker
def test_quick_report_structure(quick_report):
    rc, out = quick_report
    assert rc == 0
    report = (out / "report.md").read_text()
    assert report.startswith("# MDR against FE")
    assert "## Summary" in report and "## sphere-md" in report
    data = json.loads((out / "results.json").read_text())
    sc = data["scenes"]["sphere-md"]
    for side in ("mdr", "fem"):
        for k in CONTRACT_KEYS:
            assert k in sc[side], (side, k)
        assert set(sc[side]["loop"]) >= {"t", "du", "Fx", "FN"}
    assert "dofs" in sc["fem"] and "setup" in sc["fem"]["runtime_s"]
    for q in ("contact_radius", "stick_radius", "dissipation", "slip_index", "pressure_profile",
              "traction_profile", "loop_du"):
        v = sc["verdicts"][q]
        assert {"mdr", "fem", "difference", "fem_error", "mdr_error", "tolerance", "holds"} <= set(v), q
        # holds is exactly the stated inequality (never True on a missing number)
        if v["holds"] is not None:
            assert v["holds"] == (abs(v["difference"]) <= v["fem_error"] + v["mdr_error"] + v["tolerance"])
    assert sc["holds"] in (True, False, None)
    assert len([r for r in sc["speed_error"] if r["side"] == "fem"]) >= 3
    assert len([r for r in sc["speed_error"] if r["side"] == "mdr"]) >= 3
    # every figure the report embeds exists
    for line in report.splitlines():
        if line.startswith("!["):
            assert (out / line.rsplit("(", 1)[1].rstrip(")")).is_file(), line


@pytest.mark.xdist_group("validation-quick-report")  # the module fixture quick_report built once, on one worker
def test_quick_report_physics(quick_report):
    """Sphere at constant F_N: both sides against Mindlin-Deresiewicz and Hertz (closed forms)."""
    _, out = quick_report
    sc = json.loads((out / "scenes" / "sphere-md" / "result.json").read_text())
    cfe = sc["errors"]["closed_form"]
    assert abs(cfe["mdr"]["dissipation"]) < 0.005  # MDR: grid and time-step error only
    v = sc["verdicts"]["dissipation"]
    fe_err = v["fem_error"] / abs(v["fem"])
    assert abs(cfe["fem"]["dissipation"]) < fe_err + 0.005
    assert abs(cfe["fem"]["contact_radius"]) < 0.005
    assert abs(cfe["mdr"]["pressure_profile"]) < 1e-3 and abs(cfe["fem"]["pressure_profile"]) < 0.01
    # the textbook case holds (issue 47): on the four scalar metrics, with every bar an upper bound (the
    # FE mesh ladder within its calibrated bound, validation.error_models, where it is not asymptotic)
    for q in ("contact_radius", "stick_radius", "dissipation", "slip_index"):
        w = sc["verdicts"][q]
        assert w["grade"] == "holds" and w["bounded"], (q, w["grade"], w["fem_ladder"]["status"])
        # and the bars hold the closed form: each side within its bar (+ the time step's) of Hertz,
        # Cattaneo-Mindlin, Mindlin-Deresiewicz (the slip index: the dissipation's)
        if q != "slip_index":
            for side in ("mdr", "fem"):
                assert abs(w[side] - sc["closed_form"][q]) <= w[f"{side}_error"] + 2e-4 * abs(sc["closed_form"][q]), \
                    (q, side)
    # the stored closed form is Mindlin-Deresiewicz's, independently recomputed here
    m = Materials()
    h = ref.hertz(0.5, 6e-3, m.E_star)
    us = ref.gross_slip_displacement(h["d"], 0.2, m.E_star, m.G_star)
    assert sc["closed_form"]["dissipation"] == pytest.approx(
        ref.mindlin_deresiewicz_dissipation_force(0.05, 0.5, 0.2, us), rel=1e-12)


@pytest.mark.xdist_group("validation-quick-report")  # the module fixture quick_report built once, on one worker
def test_field_plot_not_blank(quick_report):
    import matplotlib.image as mpimg

    _, out = quick_report
    img = mpimg.imread(out / "scenes" / "sphere-md" / "fields.png")
    assert img.shape[0] > 200 and img.shape[1] > 600
    assert not image_is_blank((img * 255).astype(np.uint8))
    assert image_is_blank(np.full((50, 50, 3), 255, np.uint8))


def test_figures_render_in_a_process_without_display_settings(tmp_path, shared_mesh_cache):
    """The README: nothing needs to be set on a machine without a display. A fresh process of the README's
    command without MPLBACKEND, VTK_DEFAULT_OPENGL_WINDOW and DISPLAY (``validation.fields`` chooses EGL,
    matplotlib its non-interactive backend) writes the scene's field plot and loops, neither blank."""
    import os
    import subprocess
    import sys

    import matplotlib.image as mpimg

    env = {k: v for k, v in os.environ.items() if k not in ("MPLBACKEND", "VTK_DEFAULT_OPENGL_WINDOW", "DISPLAY")}
    env["FRETTING_MESH_CACHE"] = str(shared_mesh_cache)
    proc = subprocess.run([sys.executable, "-m", "validation.compare", "--quick", "--scenes", "sphere-md",
                           "--no-hard-cases", "--out", str(tmp_path)], env=env, capture_output=True, text=True,
                          cwd=Path(__file__).resolve().parent.parent)
    assert proc.returncode == 0, proc.stderr[-2000:]
    for name in ("fields.png", "loops.png"):
        img = mpimg.imread(tmp_path / "scenes" / "sphere-md" / name)
        assert not image_is_blank((img[..., :3] * 255).astype(np.uint8)), name


@pytest.mark.xdist_group("validation-quick-report")  # the module fixture quick_report built once, on one worker
def test_vtu_has_fields(quick_report):
    import meshio

    _, out = quick_report
    m = meshio.read(out / "scenes" / "sphere-md" / "fields.vtu")
    assert {"mises", "u", "mises_x0", "mises_x180", "u_x0", "u_x180"} <= set(m.point_data)
    assert np.all(np.isfinite(m.point_data["mises"])) and np.max(m.point_data["mises"]) > 1e7  # ~0.6 p0


@pytest.mark.filterwarnings("ignore:coarse contact mesh")
def test_rerun_skips_unchanged_and_force_reruns(tmp_path, capsys):
    s = tiny()
    st = compare.run_all([s], tmp_path, fields=False)
    assert st == {s.name: "ok"}
    f = tmp_path / "scenes" / s.name / "result.json"
    first = f.stat().st_mtime_ns
    assert compare.run_all([s], tmp_path, fields=False) == {s.name: "skipped"}
    assert f.stat().st_mtime_ns == first
    # a changed input is rerun
    assert compare.run_all([replace(s, amplitude=0.04)], tmp_path, fields=False) == {s.name: "ok"}
    assert compare.run_all([replace(s, amplitude=0.04)], tmp_path, fields=False, force=True) == {s.name: "ok"}
    assert json.loads(f.read_text())["scene"]["amplitude"] == 0.04


def test_interrupted_scene_leaves_nothing(tmp_path, monkeypatch):
    s = tiny()

    def boom(*a, **k):
        Path(a[1], "partial.txt").write_text("half")
        raise KeyboardInterrupt

    monkeypatch.setattr(runner, "run_scene", boom)
    with pytest.raises(KeyboardInterrupt):
        store.write_scene(s, tmp_path, "x")
    assert not (tmp_path / "scenes" / s.name).exists()
    assert list((tmp_path / "scenes").iterdir()) == []


@pytest.mark.filterwarnings("ignore:coarse contact mesh")
def test_custom_executor_and_failure_isolation(tmp_path):
    """Any concurrent.futures executor runs the scenes; a failing scene does not stop the others."""
    good = tiny()
    bad = tiny("geom-b20um")
    # a scene that fails while it runs: beyond the friction limit force control has no equilibrium (the
    # Scene refuses such an amplitude when it is built, so it is set past that check here)
    object.__setattr__(bad, "amplitude", 0.5)
    with cf.ThreadPoolExecutor(max_workers=2) as ex:
        st = compare.run_all([good, bad], tmp_path, executor=ex, fields=False, log=lambda m: None)
    assert st[good.name] == "ok"
    assert st[bad.name].startswith("InputError") and "fa" in st[bad.name]
    assert not (tmp_path / "scenes" / bad.name).exists()
    from validation import report

    text = report.write_report(tmp_path, [good.name, bad.name], st).read_text()
    row = [ln for ln in text.splitlines() if ln.startswith(f"| {bad.name} |")][0]
    assert "failed: InputError" in row


def test_cli_bad_input(capsys, tmp_path):
    assert compare.main(["--scenes", "nope", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "nope" in err[0] and "sphere-md" in err[0]
    assert compare.main(["--jobs", "0", "--out", str(tmp_path)]) == 2
    assert "jobs" in capsys.readouterr().err
    f = tmp_path / "file"
    f.write_text("")
    assert compare.main(["--scenes", "sphere-md", "--out", str(f)]) == 2
    assert list(tmp_path.iterdir()) == [f]


def test_cli_list(capsys):
    assert compare.main(["--list"]) == 0
    text = capsys.readouterr().out
    for name in CATALOGUE:
        assert name in text


def test_catalogue_covers_the_issue():
    names = set(CATALOGUE)
    for b in ("5", "10", "20", "30", "50", "100", "600"):
        assert f"geom-b{b}um" in names
    assert {"geom-sphere", "geom-flat", "validity"} <= names
    assert {f"exp-fig{i}" for i in range(4, 8)} <= names
    assert {f"app-kx{k}" for k in (1, 2, 10, 20)} <= names
    for s in CATALOGUE.values():
        assert len(s.fe_levels) >= 3 or s.variants, s.name
        assert len(s.mdr_cells) >= 3 or s.variants, s.name
    quick = select(quick=True)
    assert 1 <= len(quick) < len(CATALOGUE)
    assert all(s.fingerprint(code_version()) != replace(s, mu=0.3).fingerprint(code_version()) for s in quick)


def test_code_version_covers_every_module_a_result_depends_on(tmp_path, monkeypatch):
    """The stored scenes are rerun when any module they depend on changes, those in subpackages too
    (the FE models in ``fem/axisym`` and ``fem/solid3d``, the scene families, the ladder error bars
    in ``common``), and not when only the report is re-rendered."""
    from pathlib import Path

    import validation.sources as vs

    root = Path(vs.__file__).resolve().parent.parent
    files = {p.relative_to(root).as_posix() for p in vs.source_files()}
    for f in ("fem/solid3d/law.py", "fem/axisym/law.py", "validation/families/tilt.py", "common/ladder.py",
              "mdr/law.py", "meshes/half3d.py", "validation/sides.py"):
        assert f in files, f
    assert not {"validation/report.py", "validation/compare.py", "validation/budget.py", "validation/docs.py"} & files
    # a change inside a subpackage changes the version: copy the sources, edit one file, hash again
    import shutil

    for pkg in vs.SOURCE_PACKAGES:
        shutil.copytree(root / pkg, tmp_path / pkg, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setattr(vs, "__file__", str(tmp_path / "validation" / "sources.py"))
    v0 = vs.code_version()
    law = tmp_path / "fem" / "solid3d" / "law.py"
    law.write_text(law.read_text() + "\n# edited\n")
    assert vs.code_version() != v0


def test_no_scene_run_imports_a_report_only_module():
    """The report-only modules (the report, the budget, the docs' tables) are left out of the scenes'
    code version, so no module a scene runs may import them: the runner, every scene's tasks and the
    paper's points are imported in a fresh process and none of them is loaded."""
    import subprocess
    import sys

    code = ("import sys; import validation.runner as r, validation.hard_cases, validation.fields; "
            "from validation.catalogue import CATALOGUE; from validation.sources import REPORT_ONLY; [r.scene_tasks(s) for s in CATALOGUE.values()]; "
            "print(sorted(m for m in sys.modules if m.startswith('validation.') "
            "and m.rsplit('.', 1)[-1] + '.py' in REPORT_ONLY))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]", out


def test_scene_bad_input():
    from common.errors import InputError

    with pytest.raises(InputError, match="profile"):
        Scene("x", "x", "cone")
    with pytest.raises(InputError, match="kx"):
        Scene("x", "x", "sphere", drive="apparatus")
    with pytest.raises(InputError, match="unknown scene"):
        select("sphere-md,zzz")


def test_state_at_splits_history_exactly():
    p, m = TruncatedSphere(6e-3, 20e-6), Materials()
    for kw in ({"fa": 0.06}, {"ua": 50e-9}):
        a = run_mdr_contact(p, m, 0.2, Loading.of(0.5, dF=0.1, alpha=0.3, cycles=3, steps=40, **kw))
        b, st = run_mdr_contact(p, m, 0.2, Loading.of(0.5, dF=0.1, alpha=0.3, cycles=3, steps=40, **kw), state_at=50)
        assert a["dissipation"] == b["dissipation"] and a["loop"] == b["loop"]
        assert a["stick_radius"] == b["stick_radius"]
        assert st is not None


def test_metrics():
    t = np.linspace(0, 1, 81)
    loop = {"du": np.sin(2 * np.pi * t), "Fx": np.sin(2 * np.pi * t + 0.3)}
    d = metrics.loop_distance(loop, loop, 0.2, 0.5)
    assert d == {"Fx": 0.0, "du": 0.0, "area": 0.0}
    shifted = {"du": loop["du"], "Fx": loop["Fx"] + 0.01}
    assert metrics.loop_distance(shifted, loop, 0.2, 0.5)["Fx"] == pytest.approx(0.1)
    # relative L2 error of 1.01 p against p is 1 %, whatever the shape of p
    r = np.linspace(0, 1, 200)
    p = np.sqrt(1 - r**2)
    assert metrics.profile_error(r, 1.01 * p, r, p, 1.0) == pytest.approx(0.01, rel=1e-9)
    # an integrable log peak (the truncated sphere's kink) weighs by its area, not by its samples
    q = -np.log(np.abs(r - 0.5) + 1e-9)
    e1 = metrics.profile_error(r, q, r[::2], q[::2], 1.0)
    assert e1 < 0.05
    assert metrics.rel(1.0, 0.0) is None
    assert metrics.dissipation_error(1e-3, 0.0, 0.2, 0.5, 1e-7) == pytest.approx(1e-3 / (4 * 0.2 * 0.5 * 1e-7))


@pytest.mark.xdist_group("validation-quick-report")  # the module fixture quick_report built once, on one worker
def test_report_renders_hard_cases_table(quick_report, tmp_path):
    """The hard-cases rows (validation.hard_cases) become a table; cell text cannot break it."""
    import shutil

    from validation import report

    _, out = quick_report
    dst = tmp_path / "copy"
    shutil.copytree(out, dst)
    row = {"name": "flat punch", "model": "fem", "status": "flagged", "iterations": 3.0, "error": 1e-3, "tol": 5e-4,
           "truth": "|F_x| <= mu F_N", "time_s": 0.5, "note": "a|b"}
    path = report.write_report(dst, ["sphere-md"], {"sphere-md": "ok"}, hard_cases=[row])
    text = path.read_text()
    assert "## Hard cases" in text
    line = [ln for ln in text.splitlines() if ln.startswith("| flat punch")][0]
    assert line.replace("\\|", "").count("|") == 10  # 9 columns
    assert "| 0.0005 |" in line  # the row's tolerance beside its error
    # the hard cases close the report, after every scene
    assert text.index("## Hard cases") > text.index("## sphere-md")
    assert json.loads((dst / "results.json").read_text())["hard_cases"] == [row]


@pytest.mark.xdist_group("validation-quick-report")  # the module fixture quick_report built once, on one worker
def test_force_reruns_the_hard_cases_and_no_hard_cases_keeps_the_last_table(quick_report, tmp_path, monkeypatch):
    """The hard-cases table follows --force like the scenes do; --no-hard-cases keeps the last stored
    table in the report, marked as not rerun (never drops it silently). The hard cases themselves are
    replaced by a counter here (their physics: tests/test_hard_cases.py)."""
    import shutil

    from validation import hard_cases

    _, out = quick_report
    dst = tmp_path / "copy"
    shutil.copytree(out, dst)
    calls = []
    monkeypatch.setattr(hard_cases, "hard_cases", lambda quick, log: calls.append(quick) or
                        [{"name": f"case run {len(calls)}", "model": "mdr", "status": "ok", "error": 0.0, "tol": 1e-3}])
    args = ["--quick", "--scenes", "sphere-md", "--out", str(dst), "--no-fields"]
    assert compare.main(args) == 0 and len(calls) == 1
    assert compare.main(args) == 0 and len(calls) == 1            # unchanged: read back
    monkeypatch.setattr(runner, "run_scene", lambda *a, **k: pytest.fail("--no-hard-cases must not rerun a scene"))
    assert compare.main(args + ["--no-hard-cases"]) == 0 and len(calls) == 1
    text = (dst / "report.md").read_text()
    assert "| case run 1 |" in text and "Not rerun by this run (--no-hard-cases)" in text
    assert json.loads((dst / "results.json").read_text())["hard_cases_rerun"] is False
    monkeypatch.undo()
    monkeypatch.setattr(hard_cases, "hard_cases", lambda quick, log: calls.append(quick) or
                        [{"name": f"case run {len(calls)}", "model": "mdr", "status": "ok", "error": 0.0, "tol": 1e-3}])
    # the scene's rerun under --force is the stored result again (its physics is the quick report's)
    stored = json.loads((dst / "results.json").read_text())["scenes"]["sphere-md"]
    reruns = []
    monkeypatch.setattr(runner, "run_scene", lambda s, *a, **k: reruns.append(s.name) or copy.deepcopy(stored))
    assert compare.main(args + ["--force"]) == 0 and len(calls) == 2  # --force: the hard cases again
    assert reruns == ["sphere-md"]  # and the scene
    text = (dst / "report.md").read_text()
    assert "| case run 2 |" in text and "Not rerun" not in text


@pytest.mark.xdist_group("validation-quick-report")  # the module fixture quick_report built once, on one worker
def test_json_to_stdout_keeps_stdout_clean(quick_report, capsys):
    """--json - : stdout holds only the JSON (progress goes to stderr); the stored scene is reused."""
    _, out = quick_report
    capsys.readouterr()
    rc = compare.main(["--quick", "--scenes", "sphere-md", "--out", str(out), "--no-hard-cases", "--json", "-"])
    cap = capsys.readouterr()
    assert rc == 0
    data = json.loads(cap.out)
    assert data["status"] == {"sphere-md": "skipped"} and "sphere-md" in data["scenes"]
    assert "[skip] sphere-md" in cap.err


def test_report_module_makes_no_solver_calls():
    """report.py only reads stored results: it neither imports the hard cases nor calls a runner."""
    import ast

    from validation import report

    tree = ast.parse(Path(report.__file__).read_text())
    imported = {a.name for n in ast.walk(tree) if isinstance(n, (ast.Import, ast.ImportFrom)) for a in n.names}
    imported |= {n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
    assert not any("hard_cases" in m or m.startswith("fem") for m in imported), imported
    called = {n.func.id if isinstance(n.func, ast.Name) else getattr(n.func, "attr", "")
              for n in ast.walk(tree) if isinstance(n, ast.Call)}
    assert not called & {"hard_cases", "run_scene", "write_scene", "run_fe", "run_mdr", "run_contact",
                         "run_apparatus", "solve_normal"}, called


def test_assumptions_3d_scene(tmp_path):
    """The 3D assumptions scene on two coarse levels: each variant runs relaxed and imposed on the
    same mesh. For identical bodies (Dundurs' beta = 0) the coupling is exactly absent, so relaxing
    it changes nothing (to the solver's tolerance); the free traction direction does change the
    answer (a nonzero traction angle) but only a little; every judged metric has an error bar; the
    report and the figure are written."""
    from validation import report

    s = Scene("t3a", "tiny 3D assumptions", "sphere", fe_model="3d", fe_levels=(0.3, 0.25), cycles=3, steps=12,
              group="3d", family="assumptions3d", variants=({"relax": "direction"}, {"relax": "coupling"}))
    res = runner.run_scene(s, tmp_path)
    direction, coupling = res["assumptions3d"]
    for q, x in coupling["verdicts"].items():
        assert x["effect"] is not None and abs(x["effect"]) < 1e-8, (q, x)
    # two levels bound nothing: at best consistent within their spread, never "holds"
    assert coupling["grade"] == "consistent within its spread" and coupling["holds"] is None
    assert 0.02 < direction["traction_angle_max"] < 0.3
    d = direction["verdicts"]["dissipation"]
    assert 0 < abs(d["effect"]) < 0.03 and d["error"] is not None and d["status"] == "two levels"
    for lv in direction["levels"] + coupling["levels"]:
        assert lv["off"]["traction_angle_max"] == 0.0 or lv in coupling["levels"]
        for side in ("on", "off"):  # the stationary cycle's dissipation is the last cycle's
            assert lv[side]["dissipation"] == lv[side]["dissipation_per_cycle"][-1] > 0
    assert (tmp_path / res["files"]["assumptions3d"]).exists()
    # the pressure against MDR's (Hertz's a for the sphere), by its second-moment radius: within
    # 0.5 % on both coarse levels (measured -0.27 %, +0.11 %), and judged with its ladder's error bar
    pr = direction["pressure"]
    assert abs(pr["mdr"] / ref.hertz(s.F0, s.R, sides.materials_of(s).E_star)["a"] - 1) < 1e-12
    assert all(abs(x) < 5e-3 for x in pr["levels"]) and pr["error"] is not None
    assert pr["grade"] == "consistent within its spread"
    text = "\n".join(assumptions3d.table(res))
    assert "| t3a[direction: sphere]" in text and "| t3a[coupling: sphere]" in text
    assert text.count("(two levels): consistent within its spread |") == 2
    with pytest.raises(Exception, match="relax must be one of direction, coupling"):
        Scene("t3b", "x", "sphere", fe_model="3d", family="assumptions3d", variants=({"relax": "tilt"},))
    with pytest.raises(Exception, match="need fe_model='3d'"):
        Scene("t3c", "x", "sphere", family="assumptions3d", variants=({"relax": "direction"},))


@pytest.mark.slow  # an integration run of ~10 s; the fast suite stays under 5 min
def test_tilt_scene_tiny(tmp_path):
    """A tiny tilt family (the flat punch b = 100 um, h = 0.3 and 0.2 b, 3 cycles of 20 steps): each tilt
    against the aligned face on the same mesh. The aligned answer holds (dissipation within the
    catalogue's floor, 1e-4 of 4 mu F0 u_A) at 0.2 theta_c, the closed-form bound of complete stick
    (tests/test_punch3d.py), and fails at 0.5 theta_c, where the lifted edge slips (measured +0.27 % of
    4 mu F0 u_A, 27x the floor). The report table and the figure are written; the scene is refused
    without the 3D model."""
    from validation import report
    from validation.scenes import TILT_BOUND, tilt_critical

    thc = tilt_critical(0.5, 100e-6, Materials().E_star)
    s = Scene("tt", "tiny tilt", "flat", b=100e-6, fe_model="3d", fe_levels=(0.3, 0.2), cycles=3, steps=20,
              group="3d", family="tilt",
              variants=({"profile": "flat", "b": 100e-6, "tilts": (0.2 * thc, 0.5 * thc)},))
    res = runner.run_scene(s, tmp_path)
    (row,) = res["tilt"]
    assert row["theta_c"] == pytest.approx(thc, rel=1e-12)
    at02, at05 = row["points"]
    # two mesh levels bound nothing: at 0.2 theta_c the aligned answer is consistent within their spread
    assert at02["aligned"]["dissipation"]["grade"] == "consistent within its spread"
    assert at05["aligned"]["dissipation"]["holds"] is False
    assert row["holds_below"] == pytest.approx(0.2 * thc, rel=1e-12)
    assert row["fails_at"] == pytest.approx(0.5 * thc, rel=1e-12)
    assert at05["aligned"]["dissipation"]["effect"] > 10 * at05["aligned"]["dissipation"]["tolerance"]
    assert row["dissipation_unit"] == "4 mu F0 u_A"  # the aligned punch sticks
    assert all(p["contact_area_fraction"] == 1.0 for p in row["points"])  # full contact below theta_c
    assert (tmp_path / res["files"]["tilt"]).exists()
    text = "\n".join(tilt.table(res))
    assert "tt[flat b = 100 um]" in text and "0.2 theta_c" in text
    assert report.scene_outcome(res) == (None, "see its table")
    assert TILT_BOUND == pytest.approx(np.pi / 3600, rel=1e-15)
    with pytest.raises(Exception, match="tilt variants need fe_model='3d'"):
        Scene("tt2", "x", "flat", b=1e-4, family="tilt", variants=({"profile": "flat", "b": 1e-4, "tilts": (1e-5,)},))


def test_tilt_family_in_the_catalogue():
    """The catalogue's tilt family: the flat punch b = 100 um and the truncated spheres b = 20 um and
    0.6 mm, every tilt up to the paper's bound pi/3600, which is the last."""
    from validation.catalogue import CATALOGUE
    from validation.scenes import TILT_BOUND

    s = CATALOGUE["tilt"]
    assert s.fe_model == "3d" and s.drive == "force" and (s.F0, s.dF, s.mu, s.amplitude) == (0.5, 0.1, 0.2, 0.06)
    assert [(v["profile"], v["b"]) for v in s.variants] == [("flat", 100e-6), ("truncated", 20e-6),
                                                            ("truncated", 0.6e-3), ("truncated", 0.6e-3)]
    for v in s.variants:
        t = np.asarray(v["tilts"])
        assert np.all(np.diff(t) > 0) and t[-1] == TILT_BOUND and t[0] > 0
    # the punch's loaded edge refined on every level, half the level's size, a ball of 0.8 b
    assert s.variants[0]["refine"] == tuple((-1.0, h / 2, 0.8) for h in s.fe_levels)
    # b = 0.6 mm at pi/3600 on its own banded meshes, the band finer on the finer level
    banded = s.variants[3]
    assert banded["tilts"] == (TILT_BOUND,) and len(banded["band"]) == len(banded["fe_levels"])
    assert banded["band"][1][0] < banded["band"][0][0]
    with pytest.raises(Exception, match="refine must be one refine tuple per FE level"):
        Scene("tt3", "x", "flat", b=1e-4, fe_model="3d", fe_levels=(0.3, 0.2), family="tilt",
              variants=({"profile": "flat", "b": 1e-4, "tilts": (1e-5,), "refine": ((-1.0, 0.1, 0.8),)},))
    with pytest.raises(Exception, match="band must be one band tuple per FE level"):
        Scene("tt4", "x", "flat", b=1e-4, fe_model="3d", fe_levels=(0.3,), family="tilt",
              variants=({"profile": "flat", "b": 1e-4, "tilts": (1e-5,), "band": ((0.02, 0.06, 0.45), (0.01, 0.06, 0.45))},))
    # a refinement out of its mesh's range is refused when the scene is made (before any work)
    with pytest.raises(Exception, match=r"refine, band must be valid at the level h = 0.2 a_ref \(refine_h must be"):
        Scene("tt5", "x", "flat", b=1e-4, fe_model="3d", fe_levels=(0.3, 0.2), family="tilt",
              variants=({"profile": "flat", "b": 1e-4, "tilts": (1e-5,), "refine": ((-1.0, 0.1, 0.8), (-1.0, 0.25, 0.8))},))
    with pytest.raises(Exception, match="tilts must be a non-empty list of angles"):
        Scene("tt6", "x", "flat", b=1e-4, fe_model="3d", fe_levels=(0.3,), family="tilt",
              variants=({"profile": "flat", "b": 1e-4, "tilts": ()},))


@pytest.mark.slow  # an integration run of ~10 s; the fast suite stays under 5 min
def test_a_3d_scene_runs_through_the_runner(tmp_path):
    """A scene with fe_model="3d" (fem.solid3d.law) runs like any other: verdicts on both ladders, the
    3D keys in its FE result, the du loop compared (the contact measure), figures without field
    data."""
    from validation.scenes import FE_LEVELS_3D

    s = Scene("t3d", "tiny 3D sphere", "sphere", dF=0.0, amplitude=0.05, fe_model="3d", fe_levels=(0.25, 0.2),
              mdr_cells=(100, 400), cycles=3, steps=12, group="3d")
    res = runner.run_scene(s, tmp_path)
    assert "loop_du" in res["verdicts"] and "dissipation" in res["verdicts"]
    assert res["fem"]["displacement"] == "contact"
    assert all(v["holds"] in (True, False, None) for v in res["verdicts"].values())
    fe = res["fem"]
    for k in ("stick_radius_x", "stick_radius_y", "traction_angle_max", "vertices"):
        assert k in fe
    assert abs(fe["stick_radius_x"] - fe["stick_radius_y"]) < 0.25 * fe["contact_radius"]
    assert "vtu" not in res["files"] and (tmp_path / "profiles.png").exists()
    assert len(FE_LEVELS_3D) >= 3


@pytest.mark.slow  # three 3D runs in the apparatus, ~30 s
def test_a_3d_apparatus_scene_runs_through_the_runner():
    """A scene with fe_model="3d" and drive="apparatus" (none in the catalogue, for its cost: a scene
    definition is enough) drives the 3D law through the apparatus's trial steps
    (``FEContact3D.prepare``). Its FE result is the direct call of ``mdr.apparatus.run_apparatus`` with
    ``FEContact3D`` to round-off and carries the 3D keys beside the apparatus ones; the truncated
    sphere b = 20 um (Table 2 loading, u_A = 150 nm, 3 cycles of 60 steps) converges towards MDR over
    h = 0.3, 0.2: the coarse level is off by its own ladder step (ratio in [0.5, 2]; measured 1.1 in
    tests/test_contact3d.py), the fine one within the two-level error."""
    from fem.solid3d.law import FEContact3D
    from mdr.apparatus import Apparatus, run_apparatus

    s = Scene("t3d-app", "tiny 3D truncated sphere in the apparatus", "truncated", b=20e-6, drive="apparatus",
              amplitude=150e-9, kx=1.9e6, mu2=0.1, fe_model="3d", fe_levels=(0.3, 0.2), mdr_cells=(400, 1600),
              cycles=3, steps=60, group="3d")
    res = runner.run_scene(s)
    fe = res["fem"]
    for k in ("slip_index", "dissipation", "stationary", "evaluations_per_step", "loop",
              "stick_radius_x", "stick_radius_y", "traction_angle_max", "vertices", "dofs"):
        assert k in fe, k
    assert {"u1", "u2", "u3"} <= set(fe["loop"]) and fe["displacement"] == "contact"
    assert {"slip_index", "loop_du", "loop_Fx"} <= set(res["verdicts"])
    # the runner's coarse level is the direct call
    law = FEContact3D(TruncatedSphere(s.R, s.b), Materials(s.E1, s.nu1, s.E2, s.nu2), s.mu, F_max=s.F0 + s.dF,
                      h_contact=0.3, displacement="contact")
    out = run_apparatus(law, Apparatus(kx=s.kx, mu2=s.mu2), Loading.apparatus(s.F0, dF=s.dF, alpha=s.alpha, ua=s.amplitude, cycles=s.cycles, steps=s.steps))
    coarse = res["ladder"]["fem"][0]
    for k in ("slip_index", "dissipation", "stick_radius"):
        assert coarse[k] == pytest.approx(float(out[k]), rel=1e-12, abs=0), k
    assert coarse["evaluations_per_step"] == out["evaluations_per_step"]
    assert coarse["stationary"] == bool(out["cycles"].last_is_stationary)
    # against MDR (its finest level) within the 3D model's error over its two levels
    d = [x["slip_index"] for x in res["ladder"]["fem"]]
    d_md = res["mdr"]["slip_index"]
    step = abs(d[1] - d[0])
    assert 0.5 < abs(d[0] - d_md) / step < 2
    assert abs(d[1] - d_md) <= metrics.ladder_error((0.3, 0.2), d)["error"]
    # two FE levels bound nothing: MDR is consistent with the 3D model within its spread, no more
    assert res["verdicts"]["slip_index"]["grade"] == "consistent within its spread"


@pytest.mark.xdist_group("validation-quick-report")  # the module fixture quick_report built once, on one worker
def test_a_report_that_fails_to_render_changes_no_file(quick_report, tmp_path, monkeypatch):
    """write_report renders the whole text before it writes anything: a failure there leaves the
    previous report.md, results.json and summary figures byte for byte."""
    import shutil

    from validation import report

    _, out = quick_report
    dst = tmp_path / "copy"
    shutil.copytree(out, dst)
    # bytes and inode: a file rewritten with the same bytes (a deterministic PNG) is a new inode
    state = lambda: {p.name: (p.read_bytes(), p.stat().st_ino) for p in dst.iterdir() if p.is_file()}  # noqa: E731
    before = state()
    assert "report.md" in before and "results.json" in before

    def broken(*a, **k):
        raise RuntimeError("render failed")

    monkeypatch.setattr(report, "render_report", broken)
    with pytest.raises(RuntimeError, match="render failed"):
        report.write_report(dst, ["sphere-md"], {"sphere-md": "ok"})
    assert state() == before
