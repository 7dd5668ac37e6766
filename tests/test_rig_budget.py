"""The error budget of a rig of one's own (``validation.rig_budget``, ``python -m validation.budget
--scene-file``).

Truths: the paper's rig file gives the paper's budget inputs; the scenes generated for it run the very
computations the catalogue runs at the paper's points (the same scene data, so the same numbers); a field
edited in a rig file changes the fingerprints of exactly the scenes it enters (the store reruns only
those); a cell reads its own rig's scenes (a dissimilar pair's coupling, Dundurs' beta, measured by the 3D
model; one material: exactly 0); the size bound follows the rows' order (the effect falls with either
body's size); a bad rig file is refused in one line before any work."""
import math
import subprocess
import sys
from dataclasses import fields, replace
from pathlib import Path

import pytest

from common.errors import InputError
from validation import budget_cells as C
from validation import rig_budget as RB
from validation.rig import load_rig
from validation.sources import code_version

ROOT = Path(__file__).resolve().parents[1]
PAPER_FILE = ROOT / "docs" / "examples" / "willert2023.toml"
MINE = ROOT / "docs" / "examples" / "my_rig.toml"


def _edited(tmp_path, old: str, new: str, src=MINE) -> Path:
    text = src.read_text()
    assert old in text, old
    path = tmp_path / "rig.toml"
    path.write_text(text.replace(old, new, 1))
    return path


def test_the_paper_rig_file_gives_the_paper_inputs():
    """willert2023.toml's inputs are the paper's (``budget_cells.paper_inputs``) but for the scenes: the
    setup, the bodies, the bounds, the rough contacts (R, materials, rms heights, reference load, hardness),
    the points and the resolution (within 1e-9 relative)."""
    from validation.paper_points import same

    mine, paper = RB.inputs(load_rig(PAPER_FILE)), C.paper_inputs()
    assert mine.setup.R == paper.setup.R and mine.setup.materials == paper.setup.materials
    assert mine.setup.app_kw == paper.setup.app_kw == {}
    assert math.isinf(mine.cap_height) and math.isinf(paper.cap_height)  # the cap is the whole sphere
    for f in ("block", "fillet", "tilt", "resolution"):
        assert same(getattr(mine, f), getattr(paper, f)), f
    # the same rough contacts, so the same readings' surfaces (their cache keys) as the paper's budget
    assert mine.contacts == paper.contacts
    pts = [p for r in mine.results for p in r.points]
    ref = [p for r in paper.results for p in r.points]
    assert len(pts) == len(ref) and all(same(getattr(p, f.name), getattr(q, f.name))
                                        for p, q in zip(pts, ref) for f in fields(p))


#: the fields of a scene that name or describe it; the others make its numbers
_NAMES = ("name", "title", "notes", "group", "quick", "variants", "family", "tolerance")


def _same_physics(s, t) -> bool:
    """The scenes' data that make their numbers equal, numbers within 1e-9 relative (the file's 0.07 is
    the code's 0.2 x 0.35)."""
    return all(_same_physics_field(getattr(s, f.name), getattr(t, f.name)) for f in fields(s) if f.name not in _NAMES)


def _same_physics_field(x, y) -> bool:
    """Two fields' values equal, numbers within 1e-9 relative."""
    from validation.paper_points import same

    if isinstance(x, float) or isinstance(y, float):
        return isinstance(x, (int, float)) and isinstance(y, (int, float)) and same(x, y)
    if isinstance(x, tuple) and isinstance(y, tuple):
        return len(x) == len(y) and all(_same_physics_field(a, b) for a, b in zip(x, y))
    return x == y


def test_the_paper_rig_runs_the_catalogues_computations_at_its_points():
    """One code path: at every point of willert2023.toml the curvature and the direction cells read a run
    whose scene data equal the catalogue's run of that point (the experiment and k_x scenes, the rows of
    halfspace-points and direction-points; numbers within 1e-9 relative), so the rig's budget reproduces
    the paper's cells there, within rounding of the inputs, far inside their bars. The size scene differs:
    the rig's measures its own sizes (the catalogue's sweeps them); the tilt: the next test."""
    from validation.catalogue import CATALOGUE

    paper = C.paper_inputs()
    rig = {s.name: s for s in RB.scenes(load_rig(PAPER_FILE))}
    runs = {}
    for kind, fe in (("points", "axisym"), ("direction", "3d")):
        s = rig[f"willert2023-{kind}"]
        runs[fe] = [v.scene(s) for v in s.typed_variants]
    cat_axisym = [s for s in paper.scenes if s.family == "pair" and s.drive == "apparatus"]
    cat_axisym += [v.scene(CATALOGUE["halfspace-points"]) for v in CATALOGUE["halfspace-points"].typed_variants]
    cat_3d = [v.scene(CATALOGUE["direction-points"]) for v in CATALOGUE["direction-points"].typed_variants]
    for r in paper.results:
        for p in r.points:
            for fe, cat in (("axisym", cat_axisym), ("3d", cat_3d)):
                mine = [s for s in runs[fe] if p.matches(s)]
                theirs = [s for s in cat if p.matches(s)]
                assert len(mine) == 1, (fe, p)
                if fe == "axisym" and p.b == 0 and not theirs:
                    continue  # a sphere's point the catalogue bounds by validity-curvature
                assert theirs and any(_same_physics(mine[0], t) for t in theirs), (fe, p)


def test_the_paper_rigs_tilt_at_table_2s_load_runs_the_catalogues_banded_row():
    """One code path for the tilt: the paper's rig's 0.6 mm face at Table 2's load is run with the very data
    of the catalogue's banded row (the variant, and the scene's load, amplitude, cycles, steps, materials),
    so its number is the catalogue's (measured: 0.0237716445398642 and ...645). The other points' faces
    run at their own loads (the paper's budget maps Table 2's row to them)."""
    from validation.catalogue import CATALOGUE

    cat = CATALOGUE["tilt"]
    row = next(v for v in cat.variants if v.get("band"))
    mine = next(s for s in RB.scenes(load_rig(PAPER_FILE)) if s.family == "tilt" and s.F0 == 0.5)
    assert row in mine.variants
    keep = {"name", "title", "notes", "variants", "profile", "b"}  # the variant sets profile and b
    assert all(_same_physics_field(getattr(mine, f.name), getattr(cat, f.name))
               for f in fields(mine) if f.name not in keep | set(_NAMES)), \
        [f.name for f in fields(mine) if not _same_physics_field(getattr(mine, f.name), getattr(cat, f.name))]


def test_an_edited_field_reruns_only_the_scenes_it_enters(tmp_path):
    """The store skips a scene whose fingerprint is unchanged (``validation.compare.run_all``): editing the
    tilt bound changes the tilt scene's only, the kink's rounding none (MDR computes it in the budget),
    the block's width the size scene's only, its height that and the apparatus scenes' (the bedding's
    lever h), the block's material every scene's."""
    v = code_version()

    def prints(path):
        return {s.name: s.fingerprint(v) for s in RB.scenes(load_rig(path))}

    base = prints(MINE)
    assert set(base) == {f"my-rig-{k}" for k in ("validity", "points", "direction", "coupling", "tilt")}
    for old, new, touched in (("tilt = 5e-4", "tilt = 4e-4", {"my-rig-tilt"}),
                              ("kink_rounding = 1e-6", "kink_rounding = 2e-6", set()),
                              ("block_width = 30e-3", "block_width = 8e-3", {"my-rig-validity"}),
                              # the block's height is the apparatus's h too (the bedding's lever)
                              ("block_height = 5e-3", "block_height = 3e-3",
                               {"my-rig-validity", "my-rig-points", "my-rig-direction"}),
                              ("E2 = 70e9", "E2 = 110e9", set(base))):
        now = prints(_edited(tmp_path, old, new))
        changed = {k for k in base if now.get(k) != base[k]} | (set(now) - set(base))
        assert changed == touched, (old, changed)


def test_scenes_follow_the_rig():
    """One material: no coupling scene (its cell exactly 0); no tilt bound or no face: no tilt scene; every
    point of the rig run by exactly one variant of its points and direction scenes."""
    rig = load_rig(PAPER_FILE)
    names = {s.name for s in RB.scenes(rig)}
    assert not any("coupling" in n for n in names) and any(n.startswith("willert2023-tilt") for n in names)
    assert not any("tilt" in s.name for s in RB.scenes(replace(rig, tilt=0.0)))
    assert not any("tilt" in s.name for s in RB.scenes(replace(rig, tilt=None)))
    p = rig.results[0].points[0]
    c = C.coupling_cell(p, lambda name: None, RB.inputs(rig))
    assert c["kind"] == "exact" and c["effect"] == 0.0
    mine = load_rig(MINE)
    for s in RB.scenes(mine):
        if s.family == "points":
            runs = [v.scene(s) for v in s.typed_variants]
            assert all(sum(p.matches(r) for r in runs) == 1 for p in mine.points()), s.name
    # a face that is the whole contact has its loaded edge refined as the catalogue's rows that resolve it:
    # the ball of the flat punch (b = 100 um at 7.6 theta_c), the band of the 0.6 mm face (274 theta_c)
    from validation.scenes import TILT_BAND, TILT_REFINE_PUNCH

    table2 = next(s for s in RB.scenes(rig) if s.family == "tilt" and s.F0 == 0.5)
    edge = {v["b"]: ("band" if v.get("band") == TILT_BAND else "ball" if v.get("refine") == TILT_REFINE_PUNCH
                     else None) for v in table2.variants}
    assert edge == {1e-06: None, 1e-05: None, 5e-05: None, 1e-04: "ball", 6e-04: "band", 1e-03: "band"}
    # the bodies' size at the largest contact (the paper's b = 1 mm face of Fig. 8): its a_ref is that
    # contact's radius, the block over it the rig's 19 mm
    from validation.paper_points import contact_radius
    from validation.scenes import a_ref

    v = next(s for s in RB.scenes(rig) if s.family == "validity")
    a = max(contact_radius(p, RB.setup_of(rig)) for p in rig.points())
    assert v.variants[0]["block"] * a == pytest.approx(19e-3, rel=1e-9)
    # that face is the whole contact (it sticks at the scene's mesh): the sphere at its load measures it
    assert v.profile == "sphere" and v.F0 == 0.5
    # my_rig's largest contact is its 50 um face with the kink inside: the face itself, its a_ref that radius
    w = next(s for s in RB.scenes(mine) if s.family == "validity")
    assert w.b == 50e-6 and a_ref(w) == pytest.approx(max(contact_radius(p, RB.setup_of(mine))
                                                          for p in mine.points()), rel=1e-9)


def test_the_coupling_of_a_dissimilar_pair_is_read_from_its_3d_scene():
    """my_rig (steel on aluminium, beta = +0.117): the coupling cell is the rig's own 3D row of the point's
    face radius, a relative change of the dissipation; an injected 5 % with a small bar matters once scaled
    by a slip index near 1; without the stored scene it is undetermined and names the scene to run."""
    inp = RB.inputs(load_rig(MINE))
    p = inp.results[0].points[0]
    row = {"relax": "coupling", "b": p.b, "verdicts": {"dissipation": {"effect": -0.002, "error": 0.001}}}
    store = {"my-rig-coupling": {"assumptions3d": [{**row, "b": None}, row]}}.get
    c = C.coupling_cell(p, store, inp)
    assert c["effect"] == -0.002 and c["source"] == "my-rig-coupling" and "+0.117" in c["note"]
    row["verdicts"]["dissipation"] = {"effect": 0.05, "error": 0.002}
    assert C.scaled(C.coupling_cell(p, store, inp), 0.9)["verdict"] == "matters"
    gap = C.coupling_cell(p, lambda name: None, inp)
    assert gap["verdict"] == "undetermined" and "my-rig-coupling" in gap["source"]


def test_the_size_bound_takes_the_tightest_row_not_larger_than_the_rig():
    """The effect falls with either body's size: a row with both bodies no larger than the point's bounds
    it from above; the sum of the one-body rows too where the effects add, which a row with bodies no
    smaller than the point's checks (a sum below such a row is not a bound and is not used); the cell is
    the smallest bound; bodies of at least the FE model's default (200 a) count as its half-space (0);
    none measured small enough: undetermined."""
    inp = RB.inputs(load_rig(MINE))
    p = inp.results[0].points[0]
    a = C.contact_radius(p, inp.setup)
    block = inp.block / a  # 87 a
    tight = replace(inp, block=20 * a, cap_height=30 * a)

    def rows(*r):
        return {s.name: {"validity": [{"block_over_a": b, "cap_over_a": c, "dissipation_vs_default": e}
                                      for b, c, e in r]} for s in inp.scenes if s.family == "validity"}.get

    assert 50 < block < 200 and math.isinf(inp.cap_height)
    assert C.size_cell(p, rows(), replace(inp, block=300 * a))["effect"] == 0.0
    c = C.size_cell(p, rows((10.0, 200.0, -0.004), (200.0, 10.0, -0.001), (10.0, 10.0, -0.006), (30.0, 30.0, -0.0001)), tight)
    assert c["effect"] == pytest.approx(-0.005) and c["kind"] == "bound"  # 10 a + 10 a rows; (30, 30) too large
    c = C.size_cell(p, rows((15.0, 25.0, -0.002), (10.0, 200.0, -0.004), (200.0, 10.0, -0.001)), tight)
    assert c["effect"] == pytest.approx(-0.002)
    # a row at the point's own bodies measures more than the one-body rows' sum: the sum is no bound
    c = C.size_cell(p, rows((20.0, 30.0, -0.006), (10.0, 200.0, -0.004), (200.0, 10.0, -0.001)), tight)
    assert c["effect"] == pytest.approx(-0.006)
    assert C.size_cell(p, rows((50.0, 200.0, -0.001)), tight)["effect"] is None


@pytest.mark.parametrize("old,new,named", [
    ("mu1 = 0.3", "mu1 = -0.3", "mu1"),
    ("E2 = 70e9", "E2 = 70e9\ncolour = 1", "colour"),
    ("tilt = 5e-4", "tilt = 0.05", "tilt"),
    ('profile = "truncated"', 'profile = "flat"', "flat"),
    ("mu1 = 0.3", "mu1 = 0.0", "[loading] mu1"),                        # no slip index without friction
    ("block_height = 5e-3", "block_height = 40e-6", "[bodies] block_height"),  # below 2.5 contact radii
    ("R = 10e-3\nb = 50e-6", "R = 10e-3\nb = 5.5e-3", "R/2"),           # a dissimilar face beyond R/2
])
def test_a_bad_rig_file_is_refused_in_one_line_before_any_work(tmp_path, old, new, named):
    out = tmp_path / "out"
    r = subprocess.run([sys.executable, "-m", "validation.budget", "--scene-file", str(_edited(tmp_path, old, new)),
                        "--out", str(out)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and named in r.stderr, r.stderr
    assert not out.exists()


def test_a_missing_rig_file_is_refused_in_one_line(tmp_path):
    r = subprocess.run([sys.executable, "-m", "validation.budget", "--scene-file", str(tmp_path / "none.toml"),
                        "--out", str(tmp_path / "out")], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "none.toml" in r.stderr


@pytest.mark.slow
def test_my_rig_end_to_end(tmp_path):
    """The README's command on docs/examples/my_rig.toml (2 processes): every column of the table for
    both results, the coupling measured by the rig's own 3D scene (steel on aluminium: a nonzero effect
    with its bar), the table written as budget-my-rig.md; run again, every scene is skipped; the tilt bound
    edited, only the tilt scene runs again."""
    import json

    out = tmp_path / "out"

    def run(path):
        r = subprocess.run([sys.executable, "-m", "validation.budget", "--scene-file", str(path), "--out", str(out),
                            "--jobs", "2", "--json", str(tmp_path / "b.json")], capture_output=True, text=True,
                           timeout=1800)
        assert r.returncode == 0, r.stderr[-3000:]
        return r, json.loads((tmp_path / "b.json").read_text())

    r, b = run(MINE)
    assert (out / "budget-my-rig.md").read_text().startswith("# The error budget of the rig my-rig")
    assert [row["key"] for row in b["rows"]] == ["point", "sphere-ua"]
    for row in b["rows"]:
        assert set(row["cells"]) == {"size", "curvature", "direction", "coupling", "tilt", "roughness", "kink",
                                     "plates"}
    c = b["rows"][0]["cells"]["coupling"]
    assert c["source"] == "my-rig-coupling" and c["effect"] not in (None, 0.0) and c["error"] > 0
    for row in b["rows"]:
        for col in ("size", "curvature", "direction"):
            assert row["cells"][col]["effect"] is not None, (row["key"], col)
    assert b["rows"][0]["cells"]["size"]["source"] == "my-rig-validity"
    r, _ = run(MINE)
    assert r.stderr.count("[skip]") == 5 and "done:" not in r.stderr
    r, _ = run(_edited(tmp_path, "tilt = 5e-4", "tilt = 4e-4"))
    assert r.stderr.count("[skip]") == 4 and "my-rig-tilt done" in r.stderr


def asdict_(x):
    from dataclasses import asdict

    return asdict(x)


def _hertz_members(contact, seeds=(0, 0)):
    """Members on ``contact`` whose curves are its smooth sphere's own Hertz curve (its R and materials)."""
    from dataclasses import asdict

    import numpy as np

    from mdr import reference as ref

    from validation import spectra as SP

    F = contact.F_ref * np.geomspace(1e-2, 1.5, 24)
    E = contact.mat().E_star
    d = [float(ref.hertz(f, contact.R, E)["d"]) for f in F]
    run = sorted({t["reading"] for t in SP.tasks([contact])})
    return [{"reading": i, "contact": asdict(contact), "seed": s, "n": n, "rms_window": 1e-7, "form_curvature": 0.0,
             "curve": {"d": d, "F": F.tolist()}} for i in run for s in seeds for n in contact.grids]


def test_the_rigs_rough_contacts_carry_the_rig():
    """my_rig's rough contacts: the sphere's and the face's of b = 50 um (it reaches into the sphere's
    contact), each with the rig's R, materials and rms heights, elastic readings only (no hardness stated),
    their curves reaching above every point's largest force; the paper's contacts keep the catalogue's
    flattening load (validation.scenes.ROUGH_PRELOAD)."""
    from validation import spectra as SP
    from validation.scenes import ROUGH_PRELOAD

    rig = load_rig(MINE)
    cs = RB.rough_contacts(rig)
    assert [c.b for c in cs] == [0.0, 50e-6]
    for c in cs:
        assert c.R == rig.indenter.R and c.mat() == rig.materials and c.hardness is None
        assert dict(c.rq) == {"sphere": 0.4e-6, "face": 0.8e-6, "block": 0.8e-6}
        assert 1.5 * c.F_ref >= max(p.F0 + p.dF for p in rig.points()) and c.F_ref >= rig.loading["F0"]
        assert not any(c.runs(r) for r in SP.READINGS if r.plastic) and all(c.runs(r) for r in SP.READINGS
                                                                              if not r.plastic)
    assert SP.PRELOAD * SP.F_REF == pytest.approx(ROUGH_PRELOAD, rel=1e-12)
    assert RB.rough_contacts(replace(rig, roughness=type(rig.roughness)())) == ()


def test_the_rigs_smooth_curve_is_no_roughness_and_an_unmeasured_bar_leaves_its_cell_undetermined():
    """MDR with the equivalent profile of the rig's smooth sphere's own Hertz curve (steel on aluminium,
    R = 10 mm) is that sphere in the rig's apparatus: no effect beyond the curve's sampling; read with the
    paper's steel the same curve is a different profile (the rig's materials reach the readings). Where the
    equivalent profile's error in the rig's apparatus is not measured (a surface failed there) the cell
    shows its range but is undetermined, even where the range lies far beyond the resolution; measured, it
    joins every reading's bar."""
    from validation import budget_readings as BR
    from validation.paper_points import PAPER, point_slip_index

    inp = RB.inputs(load_rig(MINE))
    sphere = inp.contacts[0]
    p = inp.results[1].points[1]  # the sphere at 200 nm
    R = BR.Readings(_hertz_members(sphere), inp.contacts, inp.setup)
    smooth = point_slip_index(p, setup=inp.setup)
    e = BR.reading_effect(R, 0.0, 0, p, smooth, None)
    assert abs(e["effect"]) < 3e-3 and e["equivalent"] is None
    assert BR.Readings.profile(R.members(0.0, 0)[-1][0]).materials == inp.setup.materials
    # the same curve read as the paper's steel is another profile: its contact radius at the top load
    steel = {**_hertz_members(sphere)[0], "contact": {**asdict_(sphere), "materials": (200e9, 0.29, 200e9, 0.29)}}
    a = [float(BR.Readings.profile(m).g_inv(m["curve"]["d"][-1])) for m in (_hertz_members(sphere)[0], steel)]
    assert a[1] < 0.9 * a[0]
    assert BR.Readings(_hertz_members(sphere), inp.contacts, PAPER).setup is PAPER
    c = BR.rig_roughness_cell(p, R, None)
    assert c["verdict"] == "undetermined" and c["incomplete"] and "not measured" in c["note"]
    assert "elastic readings only" in c["note"]
    m = BR.rig_roughness_cell(p, R, 0.004)
    assert not m.get("incomplete") and m["readings"]["ISO band"]["equivalent"] == 0.004
    assert m["error"] == pytest.approx(c["error"] + 0.004)
    gone = [x for x in _hertz_members(sphere) if x["reading"] != 3]  # a reading's surfaces failed
    f = BR.rig_roughness_cell(p, BR.Readings(gone, inp.contacts, inp.setup), 0.004)
    assert f["verdict"] == "undetermined" and f["incomplete"] and "failed" in f["note"]
    far = {**c, "range": [-0.3, -0.2], "error": 0.01}
    assert C.grade(far, 0.01)["verdict"] == "undetermined"
    assert C.grade({**far, "incomplete": False}, 0.01)["verdict"] == "matters"
    assert "no rms" in BR.rig_roughness_cell(p, None, None)["note"]


def _small_contact(rig, rms):
    """The rig's sphere contact on small grids (64, 96 pixels over 8 radii: a test's cost) at ``rms``."""
    c = RB.rough_contacts(rig)[0]
    return replace(c, period=8.0, grids=(64, 96), short=4.0, rq=(("sphere", rms), ("block", 0.0), ("face", 0.0)))


@pytest.mark.slow
def test_the_equivalent_profiles_error_in_the_rigs_apparatus_is_measured_on_the_readings_surfaces():
    """On nearly smooth surfaces (rms 1 nm) the rough half-space in the rig's apparatus (the boundary-element
    engine) and MDR with each surface's equivalent profile agree within 1e-3 of the slip index (measured
    3e-4): two independent models of the same contact; the error is |mean| + standard error over the
    surfaces. A surface whose curve stops below a point's force leaves the error unmeasured (None)."""
    from validation import rig_roughness as RR
    from validation import spectra as SP

    rig = load_rig(MINE)
    c = _small_contact(rig, 1e-9)
    p = rig.results[1].points[1]
    members = [SP.member(t) for t in SP.tasks([c]) if t["reading"] == 0 and t["n"] == c.grids[-1]]
    assert len(members) == len(SP.SEEDS) and all("curve" in m for m in members)
    eq = RR.equivalent_error([c], members, {0.0: [p]}, None)
    assert len(eq["rows"]) == 1 and eq["rows"][0]["surfaces"] == len(SP.SEEDS)
    r = eq["rows"][0]
    assert eq["error"] == pytest.approx(abs(r["mean"]) + r["sem"]) and eq["error"] < 1e-3, eq
    # the runs are the rig's: MDR's smooth sphere there is the point's slip index in the rig's setup
    from validation.paper_points import point_slip_index

    run = RR.check(RR.tasks([c], members[:1], {0.0: [p]}, RB.inputs(rig).setup.apparatus)[0])["rows"][0]
    assert run["mdr_smooth"] == pytest.approx(point_slip_index(p, n=100, setup=RB.inputs(rig).setup), abs=2e-3)
    short = [{**m, "curve": {"d": m["curve"]["d"][:6], "F": m["curve"]["F"][:6]}} for m in members[:2]]
    assert RR.equivalent_error([c], short, {0.0: [p]}, None)["error"] is None


def test_the_equivalent_error_is_the_largest_mean_plus_its_standard_error(monkeypatch, tmp_path):
    """The reduction over surfaces (each surface's run replaced by given numbers): per (reading, point) the
    mean of MDR-equivalent minus rough over the surfaces and its standard error, the error the largest
    |mean| + standard error; a failed run leaves it None; the runs are cached (a second call runs none)."""
    from validation import rig_roughness as RR

    rig = load_rig(MINE)
    c = RB.rough_contacts(rig)[0]
    pts = list(rig.results[1].points[:2])
    diffs = {0: [0.010, 0.012, 0.008, 0.010], 1: [-0.02, -0.03, -0.025, -0.025]}
    calls = []

    def fake(task):
        calls.append(task)
        s = task["member"]["seed"]
        return {"rows": [{"point": x, "rough_halfspace": 0.3, "mdr_equivalent": 0.3 + diffs[k][s]}
                         for k, x in enumerate(task["points"])]}

    members = [{"reading": 0, "contact": {"b": 0.0}, "seed": s, "n": 384, "curve": {"d": [s], "F": [1.0]}}
               for s in range(4)]
    monkeypatch.setattr(RR, "check", fake)
    eq = RR.equivalent_error([c], members, {0.0: pts}, tmp_path)
    import numpy as np

    d = np.array(diffs[1])
    assert eq["error"] == pytest.approx(abs(d.mean()) + d.std(ddof=1) / 2) and len(eq["rows"]) == 2
    assert len(calls) == 4 and RR.equivalent_error([c], members, {0.0: pts}, tmp_path)["error"] == eq["error"]
    assert len(calls) == 4  # cached
    monkeypatch.setattr(RR, "check", lambda task: {"failed": "no convergence"})
    assert RR.equivalent_error([c], members, {0.0: pts}, None)["error"] is None


def test_the_rigs_apparatus_and_indenter_reach_every_model(tmp_path):
    """A rig that states its plates (rigid) and a thin block (h = 5 mm): the apparatus scenes run in that
    apparatus (the scene's data, so its fingerprint), the rough half-space's runs carry it, and the MDR
    cells see it: the point's slip index moves with the plates' reading (they take a share of the stroke);
    the plates' cell is exactly 0 (stated); the kink's cell is the rig's R's (another R, another number)."""
    from validation import rig_roughness as RR
    from validation.paper_points import PAPER, point_slip_index

    rig = load_rig(_edited(tmp_path, "kx = 5e6", 'kx = 5e6\nplate_model = "rigid"'))
    inp = RB.inputs(rig)
    assert dict(inp.setup.apparatus) == {"plate_model": "rigid", "h": 5e-3}
    for s in inp.scenes:
        if s.drive == "apparatus":
            assert s.apparatus == inp.setup.apparatus
            assert all(v.scene(s).apparatus_of().plate_model == "rigid" for v in s.typed_variants)
    base = {s.name: s.fingerprint("v") for s in RB.scenes(load_rig(MINE))}
    moved = {s.name for s in inp.scenes if s.fingerprint("v") != base[s.name]}
    assert moved == {"my-rig-points", "my-rig-direction"}  # the force-driven scenes have no apparatus
    p = inp.results[0].points[0]
    own, default = point_slip_index(p, setup=inp.setup), point_slip_index(p, setup=replace(inp.setup, apparatus=()))
    assert abs(own - default) > 0.01
    t = RR.tasks(inp.contacts, [{"reading": 0, "contact": {"b": 0.0}, "seed": 0, "n": 384, "curve": {}}],
                 {0.0: [inp.results[1].points[0]]}, inp.setup.apparatus)
    assert dict(map(tuple, t[0]["apparatus"])) == {"plate_model": "rigid", "h": 5e-3}
    plates = C.cell(0.0, 0.0, "exact", "the rig", "the plates' reading stated")
    assert "plate_model" in inp.setup.app_kw and plates["verdict"] == "negligible"
    k = C.kink_cell(p, inp)
    assert k["kind"] == "bound" and k["effect"] != C.kink_cell(p, replace(inp, setup=replace(inp.setup, R=PAPER.R)))["effect"]


def test_a_force_controlled_effect_is_read_at_the_points_own_load(tmp_path):
    """The coupling and the tilt are measured under force control: a rig whose points sweep the normal
    force gets one scene per load, and each point's cell reads the scene at its own load (the tilt's
    effect scales with theta / theta_c, theta_c = F / (4 E* b^2): a row at another load is no bound)."""
    rig = load_rig(_edited(tmp_path, "sweep = {b = [0.0], ua = [100e-9, 200e-9, 400e-9]}",
                           "sweep = {b = [0.0, 50e-6], F0 = [0.5, 1.0]}"))
    inp = RB.inputs(rig)
    names = {s.name for s in inp.scenes}
    assert {"my-rig-coupling-1", "my-rig-coupling-2", "my-rig-tilt-1", "my-rig-tilt-2"} <= names
    low = next(p for p in rig.points() if p.F0 == 0.5 and p.b == 50e-6)
    rows = {s.name: {"assumptions3d": [{"relax": "coupling", "b": 50e-6, "verdicts": {"dissipation": {
        "effect": 0.01 * (k + 1), "error": 0.001}}}]} for k, s in enumerate(inp.of_family("assumptions3d"))}
    c = C.coupling_cell(low, rows.get, inp)
    at = next(s for s in inp.of_family("assumptions3d") if s.F0 == 0.5)
    assert c["source"] == at.name and c["effect"] == rows[at.name]["assumptions3d"][0]["verdicts"]["dissipation"]["effect"]
    assert C.tilt_cell(low, lambda name: None, inp)["source"].startswith(next(
        s.name for s in inp.of_family("tilt") if s.F0 == 0.5))


def test_the_paper_rig_files_loops_are_the_papers():
    """willert2023.toml's [[loop]] tables are the loops the paper's readings are checked by
    (``validation.consistency.paper_loops``: the points, the amplitudes mu1 F0, gross slip in Figs. 6-7)."""
    from validation.consistency import paper_loops
    from validation.paper_points import same

    mine, theirs = load_rig(PAPER_FILE).loops, paper_loops()
    assert [lp.key for lp in mine] == [lp.key for lp in theirs]
    for a, b in zip(mine, theirs):
        assert same(a.amplitude, b.amplitude) and a.gross == b.gross
        assert all(same(getattr(a.point, f.name), getattr(b.point, f.name)) for f in fields(a.point))


def test_a_rigs_measured_loop_excludes_the_readings_that_cannot_make_it(tmp_path):
    """A rig that states a loop measured on its sphere (the amplitude the smooth sphere gives at the
    loop's mu1 in its apparatus, MDR): a reading whose surfaces are the smooth sphere passes it and is
    admitted; one whose surfaces are 20 times more compliant cannot reach the amplitude at any mu1 and is
    excluded, and the rig's roughness cell spans the admitted reading only. Without the loop both count."""
    import numpy as np

    from mdr import reference as ref
    from mdr.profiles import TruncatedSphere
    from validation import budget_readings as BR
    from validation import consistency as K
    from validation import spectra as SP

    rig0 = load_rig(MINE)
    inp0 = RB.inputs(rig0)
    sphere = inp0.contacts[0]
    p = rig0.results[1].points[1]
    target = K.loop(TruncatedSphere(rig0.indenter.R, 0.0), K.Loop("x", p, 0.0), p.mu1, inp0.setup.app_kw,
                    rig0.materials)["amplitude"]
    text = f"[[loop]]\nkey = \"bench\"\namplitude = {target!r}\nb = 0.0\nua = {p.ua!r}\n\n[[result]]"
    rig = load_rig(_edited(tmp_path, "[[result]]", text))
    inp = RB.inputs(rig)
    assert rig.loops[0].point == p and inp.contacts == inp0.contacts  # the loop's contact is a point's

    def members(i, scale):
        F = sphere.F_ref * np.geomspace(1e-2, 1.5, 24)
        d = [float(ref.hertz(f, sphere.R, sphere.mat().E_star / scale)["d"]) for f in F]
        return [{"reading": i, "contact": asdict_(sphere), "seed": s, "n": n, "rms_window": 1e-6,
                 "form_curvature": 0.0, "curve": {"d": d, "F": F.tolist()}} for s in (0, 1) for n in sphere.grids]

    R = BR.Readings(members(0, 1.0) + members(1, 20.0), inp.contacts, inp.setup)
    cons = BR.consistency(R, loops=rig.loops)
    rows = {r["reading"]: r for r in cons["sphere"]}
    assert rows[SP.READINGS[0].name]["admitted"] and not rows[SP.READINGS[1].name]["admitted"]
    admitted = BR.admitted_names(cons)
    c = BR.rig_roughness_cell(p, R, 0.001, admitted)
    assert c["admitted"] == [SP.READINGS[0].name] and SP.READINGS[1].name in c["excluded"]
    both = BR.rig_roughness_cell(p, R, 0.001)
    assert set(both["admitted"]) == {SP.READINGS[0].name, SP.READINGS[1].name}


def test_a_result_of_several_points_names_the_point_that_decides():
    """The sweep over u_A: each point's cell leads its note with the field it varies in, so the cell a
    result shows says which point it is."""
    from validation import budget as B

    rig = load_rig(MINE)
    labels = B._point_labels(rig.results[1].points)
    assert labels == ["ua = 100 nm", "ua = 200 nm", "ua = 400 nm"] and B._point_labels(rig.results[0].points) == [""]
    c = C.combine([B._at(C.cell(0.001, 0.001, "measured", "x", "n"), labels[0]),
                   B._at(C.cell(0.05, 0.001, "measured", "x", "n"), labels[2])], "x")
    assert c["note"].startswith("at ua = 400 nm")


def test_force_without_a_rig_is_refused_in_one_line(tmp_path):
    r = subprocess.run([sys.executable, "-m", "validation.budget", "--force", "--out", str(tmp_path)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "--force" in r.stderr


def test_a_bound_not_stated_is_undetermined_and_a_stated_zero_is_exact():
    """A rig that states no tilt bound or kink rounding gets no number for them (undetermined, naming the
    field), not a zero; a stated 0 is exactly 0; the sphere has neither whatever is stated."""
    inp = RB.inputs(load_rig(MINE))
    face, sphere = inp.results[0].points[0], inp.results[1].points[0]
    for cell_of, field in ((lambda i: C.tilt_cell(face, lambda n: None, i), "tilt"),
                           (lambda i: C.kink_cell(face, i), "fillet")):
        none = cell_of(replace(inp, **{field: None}))
        assert none["effect"] is None and none["verdict"] == "undetermined" and "stated" in none["note"]
        zero = cell_of(replace(inp, **{field: 0.0}))
        assert zero["kind"] == "exact" and zero["effect"] == 0.0
    assert C.tilt_cell(sphere, lambda n: None, replace(inp, tilt=None))["kind"] == "exact"
    assert C.kink_cell(sphere, replace(inp, fillet=None))["kind"] == "exact"


def test_a_rigs_scene_stored_by_other_inputs_is_not_read():
    """A result stored before an edit (another fingerprint: its scene failed to rerun) is listed stale and
    not read for a rig: its cells are undetermined, naming the rig's command, not the old rig's numbers."""
    from validation import budget as B

    inp = RB.inputs(load_rig(MINE))
    name = next(s.name for s in inp.scenes if s.family == "validity")
    old = {name: {"fingerprint": "before the edit",
                  "validity": [{"block_over_a": 50.0, "cap_over_a": 200.0, "dissipation_vs_default": -1e-4}]}}
    b = B.budget(old, inp=inp, mdr_cells=False)
    assert b["stale"] == [name]
    size = b["rows"][0]["cells"]["size"]
    assert size["effect"] is None and size["verdict"] == "undetermined" and "--scene-file" in size["source"]


def test_the_paper_rigs_size_scene_measures_a_slipping_contact():
    """The paper's rig's largest contact is the b = 1 mm face, its whole contact, which sticks under half
    the friction limit at the scene's mesh (no dissipation to compare): the sphere at that load measures
    the 19 a block. Truths: the default bodies' contact radius is Hertz's (MDR's) within the FE model's
    calibrated bound at a/40; the block of 19 a is the more compliant body (a larger contact radius) and its effect on
    the dissipation is finite and small (the half-space within 1e-3)."""
    from validation import error_models as em
    from validation.families import validity

    v = next(s for s in RB.scenes(load_rig(PAPER_FILE)) if s.family == "validity")
    default, small = validity.run(v, None, fields=False, log=lambda m: None)["validity"]
    # MDR's contact radius is Hertz's (exact in the half-space, at the same instant)
    assert abs(default["contact_radius_mdr_minus_fe"]) <= em.bound("fem", "contact_radius", "smooth")(1 / 40)
    assert small["contact_radius_vs_default"] > 0
    assert 0 < abs(small["dissipation_vs_default"]) < 1e-3


SPECTRUM = "\n[tolerances.roughness.spectrum]\n"


def test_a_stated_spectrum_is_the_rigs_one_reading(tmp_path):
    """A rig that states its surfaces' spectrum ([tolerances.roughness.spectrum]) runs that reading alone on
    each rough contact, and its plastic twin where a hardness is stated. Stated as the ISO band reading
    (Hurst 0.8, the waviness to lambda_c, the values areal) its surfaces are that reading's own, height
    for height; a waviness end in m is the reading's in the contact's smooth radii."""
    from dataclasses import asdict

    import numpy as np

    from validation import spectra as SP

    text = MINE.read_text() + SPECTRUM + "hurst = 0.8\nprofile = false\n"
    (tmp_path / "iso.toml").write_text(text)
    rig = load_rig(tmp_path / "iso.toml")
    assert rig.roughness.spectrum.hurst == 0.8 and rig.roughness.spectrum.rolloff is None
    stated, default = RB.rough_contacts(rig), RB.rough_contacts(load_rig(MINE))
    for c, d in zip(stated, default):
        assert [r.name for r in c.readings] == ["stated spectrum"]
        tasks = SP.tasks([c])  # the face's grid does not resolve the ISO band: not run there, as the default's
        assert len(tasks) == len([t for t in SP.tasks([d]) if t["reading"] == 0]) == (0 if c.b else 8)
        for t in tasks[:2]:
            mine = SP.surface(t)[3].h
            theirs = SP.surface({**t, "contact": asdict(d)})[3].h  # the default's reading 0: the ISO band
            assert SP.READINGS[0].name == "ISO band" and np.array_equal(mine, theirs)
    # the cell: a range of that one reading (members whose curves are the smooth sphere's: no effect)
    from validation import budget_readings as BR

    inp = RB.inputs(rig)
    R = BR.Readings(_hertz_members(inp.contacts[0]), inp.contacts, inp.setup)
    c = BR.rig_roughness_cell(inp.results[1].points[1], R, 0.004)
    assert list(c["readings"]) == ["stated spectrum"] and c["admitted"] == ["stated spectrum"]
    assert c["range"][0] == c["range"][1] == c["readings"]["stated spectrum"]["effect"] and abs(c["effect"]) < 3e-3
    # a waviness end in m, the plastic twin with a hardness
    text = MINE.read_text().replace("# hardness = 1.0e9", "hardness = 1.0e9") + SPECTRUM + "hurst = 0.6\nrolloff = 2e-4\n"
    (tmp_path / "wavy.toml").write_text(text)
    for c in RB.rough_contacts(load_rig(tmp_path / "wavy.toml")):
        el, pl = c.readings
        assert (el.hurst, el.profile, el.plastic, pl.plastic) == (0.6, True, False, True)
        assert el.rolloff * c.a() == pytest.approx(2e-4, rel=1e-12)


@pytest.mark.parametrize("body, named", [
    ("hurst = 1.5\n", "hurst must be in (0, 1]"),
    ("profile = false\n", "hurst is missing"),
    ("hurst = 0.8\nprofile = 'yes'\n", "profile must be true"),
    ("hurst = 0.8\nrolloff = 1e-6\n", "rolloff: with the"),
    ("hurst = 0.8\nband = 2\n", "unknown field 'band'"),
])
def test_a_bad_stated_spectrum_is_refused_in_one_line(tmp_path, body, named):
    (tmp_path / "rig.toml").write_text(MINE.read_text() + SPECTRUM + body)
    r = subprocess.run([sys.executable, "-m", "validation.budget", "--scene-file", str(tmp_path / "rig.toml"),
                        "--out", str(tmp_path / "out")], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and named in r.stderr, r.stderr
    assert "[tolerances.roughness.spectrum]" in r.stderr and not (tmp_path / "out").exists()


def _iso_maps(tmp_path, seeds=(0, 1)):
    """The ISO band reading's surfaces on my_rig's sphere contact (its coarser grid), written as measured
    maps: (the rig file's text that gives them, the contact)."""
    import numpy as np

    from validation import spectra as SP

    sphere = RB.rough_contacts(load_rig(MINE))[0]
    files = []
    for s in seeds:
        t = next(t for t in SP.tasks([sphere]) if t["reading"] == 0 and t["seed"] == s and t["n"] == sphere.grids[0])
        p, _, _, h, _ = SP.surface(t)
        np.save(tmp_path / f"map{s}.npy", h.h)
        files.append(f"map{s}.npy")
    import json

    return MINE.read_text() + f"\n[tolerances.roughness.maps]\nfiles = {json.dumps(files)}\npixel = {h.pixel!r}\n", sphere


def test_measured_maps_are_the_rigs_one_reading_surface_for_surface(tmp_path):
    """Measured height maps ([tolerances.roughness.maps]) run as the rig's one reading, each map a surface
    on its own pixels and 1.5 times them: maps that are the ISO band reading's generated surfaces give
    that reading's surfaces, height for height on both grids; another map's content is another task (its
    digest in the key: a cached surface of the old map is not read)."""
    import numpy as np

    from validation import spectra as SP

    text, sphere = _iso_maps(tmp_path)
    (tmp_path / "rig.toml").write_text(text)
    rig = load_rig(tmp_path / "rig.toml")
    c = RB.rough_contacts(rig)[0]
    assert [r.name for r in c.readings] == ["measured maps"] and c.readings[0].n == sphere.grids[0]
    tasks = [t for t in SP.tasks([c]) if t["contact"]["b"] == 0.0]
    assert sorted((t["seed"], t["n"]) for t in tasks) == [(s, n) for s in (0, 1) for n in sphere.grids]
    for t in tasks:
        mine = SP.surface(t)[3]
        theirs = SP.surface({**t, "reading": 0, "contact": asdict_(sphere)})[3]
        assert mine.pixel == pytest.approx(theirs.pixel, rel=1e-12)
        assert np.allclose(mine.h, theirs.h - theirs.h.mean(), rtol=0, atol=1e-12 * np.abs(theirs.h).max())
    key = SP._key(tasks[0], "v")
    np.save(tmp_path / "map0.npy", 2 * np.load(tmp_path / "map0.npy"))
    assert SP._key(next(t for t in SP.tasks(RB.rough_contacts(load_rig(tmp_path / "rig.toml")))
                        if (t["seed"], t["n"]) == (tasks[0]["seed"], tasks[0]["n"]) and t["contact"]["b"] == 0.0),
                   "v") != key


@pytest.mark.parametrize("edit, named", [
    (lambda t: t.replace('"map1.npy"]', '"map0.npy"]'), "distinct maps"),
    (lambda t: t.replace(', "map1.npy"]', "]"), "at least 2 height-map files"),
    (lambda t: t.replace('"map1.npy"]', '"gone.npy"]'), "gone.npy"),
    (lambda t: t.rsplit("pixel = ", 1)[0] + "pixel = 2e-3\n", "pixel must be"),
    (lambda t: t + "\n[tolerances.roughness.spectrum]\nhurst = 0.8\n", "not both"),
])
def test_bad_maps_are_refused_in_one_line(tmp_path, edit, named):
    text, _ = _iso_maps(tmp_path)
    (tmp_path / "rig.toml").write_text(edit(text))
    r = subprocess.run([sys.executable, "-m", "validation.budget", "--scene-file", str(tmp_path / "rig.toml"),
                        "--out", str(tmp_path / "out")], capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and named in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()


def test_maps_smaller_than_four_contact_radii_are_refused(tmp_path):
    text, sphere = _iso_maps(tmp_path)
    small = 3.0 * sphere.a() / sphere.grids[0]  # 3 contact radii on a side
    import re

    (tmp_path / "rig.toml").write_text(re.sub(r"pixel = [0-9.e-]+\n", f"pixel = {small!r}\n", text))
    with pytest.raises(InputError, match="at least 4 smooth contact radii"):
        RB.inputs(load_rig(tmp_path / "rig.toml"))
