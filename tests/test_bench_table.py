"""benchmarks/bench_table.py, the generator of docs/speed.md's table: a row with a missing or non-finite
number prints "-" (no crash), ``--write`` replaces the generated block alone (the page's text kept) and
refuses a page without one, and docs/speed.md holds a block of the table's shape."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

import bench_table as bt  # noqa: E402


def test_missing_numbers_print_a_dash():
    rows = [bt.row("m", "c", "s", 1.0, float("nan"), "p", "ps", None, 1e-3),
            bt.row("m", "c", "s", 0.0, None)]
    lines = bt.markdown(rows)
    assert len(lines) == 4 and all(line.count("|") == lines[0].count("|") for line in lines)
    assert lines[2].split("|")[5].strip() == "-" and lines[2].split("|")[8].strip() == "-"
    assert lines[3].split("|")[10].strip() == "-"  # no ratio without both times


def test_write_replaces_the_block_alone(tmp_path):
    page = tmp_path / "p.md"
    page.write_text(f"intro\n{bt.BEGIN}\nold\n{bt.END}\noutro\n")
    bt.write_doc(["| new |"], page)
    assert page.read_text() == f"intro\n{bt.BEGIN}\n| new |\n{bt.END}\noutro\n"
    bare = tmp_path / "q.md"
    bare.write_text("no block\n")
    with pytest.raises(SystemExit, match="no generated block"):
        bt.write_doc(["x"], bare)
    assert bare.read_text() == "no block\n"


def test_the_speed_page_holds_the_table():
    text = bt.DOC.read_text()
    block = text.split(bt.BEGIN, 1)[1].split(bt.END, 1)[0].strip().splitlines()
    assert block[0] == bt.markdown([])[0] and len(block) >= 6
