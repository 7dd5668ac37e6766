"""The roughness cell of a rig of one's own (``validation.rig_budget.rough_contacts``, ``validation.
rig_roughness``, ``validation.budget_readings``): the rig's rough contacts, its readings (the paper's set, a
stated spectrum or measured maps) and what the equivalent profile misses in the rig's apparatus.

Truths: MDR with the equivalent profile of a smooth sphere's own Hertz curve is that sphere (no roughness);
a stated spectrum or measured maps that are a reading's own give that reading's surfaces, height for
height; the rough half-space and MDR with each surface's equivalent profile agree on nearly smooth
surfaces (two independent models); a measured loop excludes the readings that cannot make it; bad
statements are refused in one line before any work."""
import subprocess
import sys
from dataclasses import replace

import pytest

from common.errors import InputError
from validation import budget_cells as C
from validation import rig_budget as RB
from validation.rig import load_rig

from test_rig_budget import MINE, ROOT, _edited


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
    digest in the key: a cached surface of the old map is not read; a task of the old content refuses the
    new one)."""
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
    with pytest.raises(InputError, match="changed since the rig file was read"):
        SP.surface(next(t for t in tasks if t["seed"] == 0))
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


def test_a_spectrum_without_an_rms_height_is_refused(tmp_path):
    text = MINE.read_text()
    for body in ("sphere", "face", "block"):
        text = "\n".join(ln for ln in text.splitlines() if not ln.startswith(f"{body} = "))
    (tmp_path / "rig.toml").write_text(text + SPECTRUM + "hurst = 0.8\n")
    with pytest.raises(InputError, match="spectrum without a height"):
        load_rig(tmp_path / "rig.toml")
