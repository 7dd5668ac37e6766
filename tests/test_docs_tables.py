"""The docs' generated tables (``python -m validation.docs``): blocks found and rewritten, a drift
caught, a CPU's last digits let through; the catalogue's tables themselves are checked against a
full run in ``tests/test_validation_full.py::test_the_docs_tables_are_what_the_catalogue_gives``."""
import json

import pytest

from validation import docs

PAGE = """# A page

Some words 1.5 %.

<!-- generated: demo (python -m validation.docs --write) -->
| a | b |
|---|---|
| x | 1.00 (0.50 + 0.01): **holds** |
<!-- end generated -->

More words.
"""


@pytest.fixture
def demo(monkeypatch):
    def table(scenes):
        return ["| a | b |", "|---|---|", f"| x | {scenes['v']:.2f} (0.50 + 0.01): **{scenes['g']}** |"]

    monkeypatch.setitem(docs.TABLES, "demo", table)


def test_blocks_are_rewritten_and_nothing_else(demo):
    new = docs.render(PAGE, {"v": 2.0, "g": "fails"})
    assert "| x | 2.00 (0.50 + 0.01): **fails** |" in new
    assert new.replace("2.00", "1.00").replace("fails", "holds") == PAGE
    assert docs.blocks(PAGE) == [("demo", 5, 8)]


def test_check_catches_a_changed_grade_or_number_and_lets_round_off_through(demo, tmp_path):
    (tmp_path / "p.md").write_text(PAGE)
    assert docs.check({"v": 1.0, "g": "holds"}, tmp_path) == []
    assert docs.check({"v": 1.004, "g": "holds"}, tmp_path) == []  # last digits of another CPU
    assert len(docs.check({"v": 1.5, "g": "holds"}, tmp_path)) == 1  # the table drifted
    assert "words differ" in docs.check({"v": 1.0, "g": "fails"}, tmp_path)[0]


def test_unknown_table_and_missing_results_are_one_line(demo, tmp_path, capsys):
    with pytest.raises(ValueError, match="unknown generated table 'nope'"):
        docs.render(PAGE.replace("demo", "nope"), {})
    assert docs.main(["--results", str(tmp_path), "--check"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "results.json" in err
    (tmp_path / "results.json").write_text(json.dumps({"scenes": {"sphere-md": {}}}))
    assert docs.main(["--results", str(tmp_path), "--check"]) == 2
    assert "full catalogue run" in capsys.readouterr().err


def test_every_generated_block_in_the_docs_names_a_known_table():
    """Every table is generated somewhere (the README included), each once, except the one-line tally
    that the README, the guide and the comparison page quote."""
    names = [name for page in docs.pages() for name, _, _ in docs.blocks(page.read_text())]
    assert set(names) == set(docs.TABLES)
    repeated = {n for n in names if names.count(n) > 1}
    assert repeated == {"tally"} and names.count("tally") == 3
