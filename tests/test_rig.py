"""A rig file (``validation.rig``): the paper's rig file holds the constants the code uses for the paper,
a rig of one's own reads into the same types, and a bad file is refused in one line naming the file,
the table, the field and its range."""
import math
from pathlib import Path

import pytest

from common.errors import InputError
from validation.rig import load_rig

ROOT = Path(__file__).resolve().parents[1]
PAPER = ROOT / "docs" / "examples" / "willert2023.toml"
MINE = ROOT / "docs" / "examples" / "my_rig.toml"


def test_the_paper_rig_file_is_the_paper_the_code_holds():
    """willert2023.toml against the paper's constants where the code keeps them (``mdr.paper``, the budget,
    the spectra, the scenes): its results are the budget's points (``validation.paper_points.results``),
    each field within 1e-9 relative (the file's 0.07 is the code's 0.2 x 0.35)."""
    from mdr.materials import Materials
    from mdr.paper import B_TABLE1, KX_TABLE1, R_INDENTER, TABLE2
    from validation.budget_cells import BLOCK_HEIGHT, FILLET_MAX
    from validation.paper_points import results, same
    from validation.scenes import TILT_BOUND
    from validation.spectra import PAPER_RQ

    rig = load_rig(PAPER)
    assert (rig.indenter.profile, rig.indenter.R, rig.indenter.b) == ("truncated", R_INDENTER, B_TABLE1)
    assert rig.indenter.kink_rounding == FILLET_MAX and rig.bodies.block_height == BLOCK_HEIGHT
    assert rig.materials == Materials() and rig.materials.dundurs_beta == 0.0
    assert rig.apparatus == {"kx": KX_TABLE1}
    assert {k: rig.loading[k] for k in TABLE2} == TABLE2
    assert rig.tilt == pytest.approx(TILT_BOUND, rel=1e-15)
    assert (rig.roughness.sphere, rig.roughness.face, rig.roughness.block) == \
        (PAPER_RQ["sphere"], PAPER_RQ["face"], PAPER_RQ["block"])
    code = results()
    assert [(r.key, r.title) for r in rig.results] == [(r.key, r.title) for r in code]
    for mine, theirs in zip(rig.results, code):
        assert len(mine.points) == len(theirs.points), mine.key
        for p, q in zip(mine.points, theirs.points):
            assert all(same(getattr(p, f), getattr(q, f)) for f in p.__dataclass_fields__), (mine.key, p, q)
    assert len(rig.points()) == len({p for r in code for p in r.points})


def test_a_rig_of_ones_own():
    """my_rig.toml: steel on aluminium, Dundurs' beta from its closed form (Dundurs 1969; signed positive
    where the block is the more compressible body), a sweep's every combination, the rig's own values where a
    point changes none."""
    rig = load_rig(MINE)
    m = rig.materials
    G1, G2 = m.E1 / (2 * (1 + m.nu1)), m.E2 / (2 * (1 + m.nu2))
    beta = 0.5 * ((1 - 2 * m.nu2) / G2 - (1 - 2 * m.nu1) / G1) / ((1 - m.nu2) / G2 + (1 - m.nu1) / G1)
    assert m.dundurs_beta == pytest.approx(beta, rel=1e-12) and 0.10 < beta < 0.13
    point, sweep = rig.results
    assert point.points[0].b == rig.indenter.b and point.points[0].kx == rig.apparatus["kx"]
    assert [p.ua for p in sweep.points] == [100e-9, 200e-9, 400e-9] and all(p.b == 0 for p in sweep.points)


BAD = [  # (what is changed in the paper's file, what the one line must name)
    (("mu1 = 0.2", "mu1 = -0.2"), "[loading] mu1 must be > 0"),
    (("R = 6e-3", "R = 0.0"), "[indenter] R must be > 0 (m)"),
    (("tilt = 8.726646259971648e-4", "tilt = 0.05"), "[tolerances] tilt must be in [0, 0.01745] (rad"),
    (("block = 3e-6", "block = 3.0"), "[tolerances.roughness] block must be in [0, 0.0001] (m"),
    (("[bodies]", "[bodies]\nheight = 1.0"), "[bodies] unknown field 'height'"),
    (("[materials]", "[material]"), "unknown table [material]"),
    (("kx = 1.9e6", "kx = -1.9e6"), "[apparatus] kx must be > 0"),
    (("kink_rounding = 3e-6", "kink_rounding = 1e-3"), "[indenter] kink_rounding must be in [0, b)"),
    (('points = [{}, {b = 10e-6}]', 'points = [{}, {b = 10e-6, mu1 = -1.0}]'), "a point's mu1 is out of range"),
    (('sweep = {b = [10e-6, 50e-6, 100e-6], kx = [0.3e6, 3e6, 30e6]}', 'sweep = {b = [10e-6], k = [1.0]}'),
     "unknown point field 'k'"),
    (("nu2 = 0.29", "nu2 = 0.5"), "[materials] nu2 must be in (-1, 0.5)"),
]


@pytest.mark.parametrize("change,message", BAD, ids=[m for _, m in BAD])
def test_a_bad_rig_file_is_refused_in_one_line(tmp_path, change, message):
    text = PAPER.read_text()
    assert change[0] in text
    f = tmp_path / "bad.toml"
    f.write_text(text.replace(change[0], change[1], 1))
    with pytest.raises(InputError) as e:
        load_rig(f)
    line = str(e.value)
    assert line.startswith("bad.toml: ") and message in line and "\n" not in line, line


def test_an_unreadable_rig_file_is_refused_in_one_line(tmp_path):
    with pytest.raises(InputError, match="cannot be read"):
        load_rig(tmp_path / "missing.toml")
    (tmp_path / "broken.toml").write_text("[rig\nname = 1")
    with pytest.raises(InputError, match="is not valid TOML"):
        load_rig(tmp_path / "broken.toml")
    assert math.isfinite(load_rig(PAPER).resolution)
