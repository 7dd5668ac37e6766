"""The paper's rig file read as a rig of one's own reproduces the paper's budget (slow: minutes).

Truth: one code path. ``docs/examples/willert2023.toml`` holds the paper's setup, bodies, bounds, points
and resolution (``tests/test_rig_budget.py``); ``python -m validation.budget --scene-file`` on it
generates its own scenes and readings (unchecked by the paper's loops: the rig file's own measured loops
check them), where the paper's budget reads the catalogue's scenes. Both are measurements of the same
effects with their own error bars, so each cell of the rig's must lie within the two bars of the paper's
and read the same verdict. The size cells are bounds without a bar on both sides, from different rows:
the rig's at its own bodies, the paper's from the catalogue's sweep row of bodies no larger. The effect
falls with either body's size, so the rig's bound lies within the paper's.

Cost: the catalogue's points run in the catalogue's folder are the rig's too (``validation.runner.
member_key``): the rig's traction-direction and tilt scenes run none of their 23 and 19 points again.
"""
from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group("catalogue")]  # the catalogue's worker

ROOT = Path(__file__).resolve().parents[1]
PAPER_FILE = ROOT / "docs" / "examples" / "willert2023.toml"


def _cells(b) -> dict:
    return {r["key"]: r["cells"] for r in b["rows"]}


def _within(mine: dict, theirs: dict) -> bool:
    """Two measurements of one cell agree: their difference (a range's ends, each) within the sum of their
    error bars (plus round-off)."""
    tol = mine["error"] + theirs["error"] + 1e-15
    if mine.get("range") and theirs.get("range"):
        return all(abs(x - y) <= tol for x, y in zip(mine["range"], theirs["range"]))
    return abs(mine["effect"] - theirs["effect"]) <= tol


def test_the_paper_rig_file_reproduces_the_papers_budget(paper_budget, tmp_path_factory):
    out, paper = paper_budget
    mine = tmp_path_factory.mktemp("willert2023")
    for shared in ("members", "readings"):  # what the catalogue's folder computed, by content
        shutil.copytree(out / shared, mine / shared)
    r = subprocess.run([sys.executable, "-m", "validation.budget", "--scene-file", str(PAPER_FILE), "--out",
                        str(mine), "--jobs", "2", "--json", str(mine / "budget.json")],
                       capture_output=True, text=True, cwd=ROOT, check=False)
    assert r.returncode == 0, r.stderr[-3000:]
    assert "willert2023-direction done: its 23 task(s) stored by content" in r.stderr
    assert "willert2023-tilt done: its 19 task(s) stored by content" in r.stderr
    rig = json.loads((mine / "budget.json").read_text())
    assert not rig["stale"]
    ours, theirs = _cells(rig), _cells(paper)
    assert set(ours) == set(theirs)
    compared = 0
    for key, row in theirs.items():
        for col, t in row.items():
            m = ours[key][col]
            assert m["verdict"] == t["verdict"], (key, col, m, t)
            if t["effect"] is None or m["effect"] is None:
                assert t["effect"] is None and m["effect"] is None, (key, col)
                continue
            if col == "size":  # two bounds without a bar: the rig's own bodies within the sweep's row
                assert m["kind"] == t["kind"] == "bound" and m["error"] == t["error"] == 0.0
                assert abs(m["effect"]) <= abs(t["effect"]) + 1e-15, (key, m, t)
                continue
            assert _within(m, t), (key, col, m, t)
            compared += 1
    assert compared >= 5 * len(theirs)  # the curvature, direction, coupling, tilt, kink at least, per row
