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


def test_the_paper_rigs_tilt_runs_the_catalogues_tilted_points():
    """One code path for the tilt: every face point of willert2023.toml is tilted by the very computation of
    the catalogue's tilt-points (the member's data, ``points.member_physics``, equal: the same point, tilt
    and meshes), so the rig's tilt cells are the paper's, and its store reads them back."""
    from validation.catalogue import CATALOGUE
    from validation.families import points

    cat = CATALOGUE["tilt-points"]
    mine = next(s for s in RB.scenes(load_rig(PAPER_FILE)) if s.name == "willert2023-tilt")
    theirs = [points.member_physics(cat, {"variant": i}) for i in range(len(cat.variants))]
    for i in range(len(mine.variants)):
        assert points.member_physics(mine, {"variant": i}) in theirs, mine.variants[i]
    assert len(mine.variants) == len(cat.variants)


def test_an_edited_field_reruns_only_the_scenes_it_enters(tmp_path):
    """The store skips a scene whose fingerprint is unchanged (``validation.compare.run_all``): editing the
    tilt bound changes the tilt scene's only, the kink's rounding none (MDR computes it in the budget),
    the block's width the size scene's only, its height that and the apparatus scenes' (the bedding's
    lever h; the tilt runs in the apparatus too), the block's material every scene's."""
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
                               {"my-rig-validity", "my-rig-points", "my-rig-direction", "my-rig-tilt"}),
                              ("E2 = 70e9", "E2 = 110e9", set(base))):
        now = prints(_edited(tmp_path, old, new))
        changed = {k for k in base if now.get(k) != base[k]} | (set(now) - set(base))
        assert changed == touched, (old, changed)


def test_scenes_follow_the_rig():
    """One material: no coupling scene (its cell exactly 0); no tilt bound or no face: no tilt scene; every
    point of the rig run by exactly one variant of its points and direction scenes, every face point by one
    of its tilt scene."""
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
        if s.family == "points":  # the tilt: every face point (the sphere has no tilt)
            runs = [v.scene(s) for v in s.typed_variants]
            here = [p for p in mine.points() if p.b > 0 or not s.name.endswith("-tilt")]
            assert all(sum(p.matches(r) for r in runs) == 1 for p in here) and len(runs) == len(here), s.name
    # a face that is the whole contact has its loaded edge refined as the catalogue's rows that resolve it:
    # the ball of the flat punch (b = 100 um at 7.6 theta_c), the band of the 0.6 mm face (274 theta_c); a
    # face inside the contact on the scene's levels; the 1 um faces (a fifth of an element) not tilted
    from validation.families.tilt import edge_variant
    from validation.scenes import TILT_BAND, TILT_REFINE_PUNCH

    tilt = next(s for s in RB.scenes(rig) if s.name == "willert2023-tilt")
    edge = {}
    for v in tilt.typed_variants:
        e = edge_variant(v.scene(tilt), v.tilt)
        edge[v.scene(tilt).b] = ("band" if e.get("band") == TILT_BAND else "ball" if e.get("refine") == TILT_REFINE_PUNCH
                                 else None)
    assert edge == {1e-05: None, 5e-05: None, 1e-04: "ball", 6e-04: "band", 1e-03: "band"}
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
    assert moved == {"my-rig-points", "my-rig-direction", "my-rig-tilt"}  # the force-driven ones have none
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
    """The coupling is measured under force control: a rig whose points sweep the normal force gets one
    scene per load, and each point's cell reads the scene at its own load. The tilt is measured at each
    point in its apparatus (one scene: its cell reads the row of that very point)."""
    rig = load_rig(_edited(tmp_path, "sweep = {b = [0.0], ua = [100e-9, 200e-9, 400e-9]}",
                           "sweep = {b = [0.0, 50e-6], F0 = [0.5, 1.0]}"))
    inp = RB.inputs(rig)
    names = {s.name for s in inp.scenes}
    assert {"my-rig-coupling-1", "my-rig-coupling-2", "my-rig-tilt"} <= names
    low = next(p for p in rig.points() if p.F0 == 0.5 and p.b == 50e-6)
    rows = {s.name: {"assumptions3d": [{"relax": "coupling", "b": 50e-6, "verdicts": {"dissipation": {
        "effect": 0.01 * (k + 1), "error": 0.001}}}]} for k, s in enumerate(inp.of_family("assumptions3d"))}
    c = C.coupling_cell(low, rows.get, inp)
    at = next(s for s in inp.of_family("assumptions3d") if s.F0 == 0.5)
    assert c["source"] == at.name and c["effect"] == rows[at.name]["assumptions3d"][0]["verdicts"]["dissipation"]["effect"]
    tilt = next(s for s in inp.scenes if s.name == "my-rig-tilt")
    i = next(i for i, v in enumerate(tilt.typed_variants) if low.matches(v.scene(tilt)))
    row = {"variant": i, "tilt": rig.tilt, "effect": -0.02, "error": 0.001, "slip_index": 0.3}
    c = C.tilt_cell(low, {"my-rig-tilt": {"points": [row]}}.get, inp)
    assert c["source"] == "my-rig-tilt" and c["effect"] == -0.02 and c["kind"] == "bound"
    other = next(p for p in rig.points() if p.F0 == 1.0 and p.b == 50e-6)  # the same face at the other load
    assert C.tilt_cell(other, {"my-rig-tilt": {"points": [row]}}.get, inp)["effect"] is None


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
