"""The full scene catalogue through python -m validation.compare (slow: a few minutes on 2 cores).

Asserts the agreement the physics predicts, each against an independent truth:
- the closed-form anchors (Hertz, Cattaneo-Mindlin, Mindlin-Deresiewicz; the flat punch's
  full stick below mu F_N) on both sides;
- MDR is exact for axisymmetric profiles on a half-space, and the FE bodies are 200
  contact radii large: so MDR and FE agree within the FE's own error estimate plus a
  tolerance for every profile, directly driven or in the apparatus;
- the half-space assumption fails as the block shrinks towards the contact radius.
"""
from __future__ import annotations

import json

import pytest

from validation import compare
from validation.scenes import CATALOGUE

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def full(tmp_path_factory):
    out = tmp_path_factory.mktemp("full")
    rc = compare.main(["--out", str(out), "--jobs", "2", "--no-hard-cases"])
    data = json.loads((out / "results.json").read_text())
    return rc, out, data["scenes"]


def test_every_scene_ran(full):
    rc, out, scenes = full
    assert rc == 0
    assert set(scenes) == set(CATALOGUE)
    report = (out / "report.md").read_text()
    for name in CATALOGUE:
        assert f"## {name}" in report


def test_closed_form_anchors(full):
    _, _, sc = full
    s = sc["sphere-md"]["errors"]
    cf = s["closed_form"]
    # MDR: grid and time-step error only
    assert abs(cf["mdr"]["dissipation"]) < 0.002 and abs(cf["mdr"]["stick_radius"]) < 0.002
    # FE at a/80: the accuracy (dissipation 0.5 %, stick radius 1 %, contact radius 0.5 %)
    assert abs(cf["fem"]["dissipation"]) < 0.005
    assert abs(cf["fem"]["stick_radius"]) < 0.01
    assert abs(cf["fem"]["contact_radius"]) < 0.005
    assert cf["fem"]["traction_profile"] < 0.02 and cf["fem"]["pressure_profile"] < 0.01
    # MDR and FE dissipation within the FE error plus 1 %
    assert abs(s["dissipation"]["mdr_minus_fe"]) <= s["dissipation"]["fe_error"] + 0.01
    # flat punch below mu F_N: full stick, no dissipation (Mindlin 1949)
    for name in ("flat-md", "geom-flat"):
        for side in ("mdr", "fem"):
            assert sc[name][side]["slip_index"] < 0.005, (name, side)


def test_mdr_matches_fe_across_the_geometry_series(full):
    _, _, sc = full
    for name, r in sc.items():
        if r["scene"]["group"] != "geometry" or r["scene"]["profile"] == "flat":
            continue
        e = r["errors"]
        assert abs(e["contact_radius"]["mdr_minus_fe"]) < 0.01, name
        d = e["dissipation"]
        assert abs(d["mdr_minus_fe"]) <= d["fe_error"] + 0.02, (name, d)
        assert e["pressure_profile"]["mdr_minus_fe"] < 0.02, name


def test_apparatus_scenes_agree_and_delta_rises_with_kx(full):
    _, _, sc = full
    for name, r in sc.items():
        if r["scene"]["drive"] != "apparatus":
            continue
        si = r["errors"]["slip_index"]
        assert abs(si["mdr_minus_fe"]) < 0.02, (name, si)
    deltas = [sc[f"app-kx{k}"]["fem"]["slip_index"] for k in (1, 2, 10, 20)]
    assert all(b > a for a, b in zip(deltas, deltas[1:])), deltas


def test_half_space_breaks_for_a_small_block(full):
    _, _, sc = full
    rows = {r["variant"]: r for r in sc["validity"]["validity"]}
    big = abs(rows["default (200 a)"]["contact_radius_mdr_minus_fe"])
    small = abs(rows["block 3 a"]["contact_radius_mdr_minus_fe"])
    assert big < 0.005
    assert small > 3 * big and small > 0.002
    # a block of 30 contact radii is already a half-space for the contact radius
    assert abs(rows["block 30 a"]["contact_radius_vs_default"]) < 0.002
    # the size effect on the dissipation (mesh error cancelled) falls as the body grows
    for kind in ("block", "cap"):
        eff = [abs(rows[f"{kind} {s} a"]["dissipation_vs_default"]) for s in (3, 5, 10, 30)]
        assert all(x > y for x, y in zip(eff, eff[1:])), (kind, eff)
        assert eff[-1] < 0.001
