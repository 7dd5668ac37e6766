"""The README's example commands write under results/ (never into the repository root), and
the commands they use create a missing results/ directory or fail with one line (issue 12)."""
from __future__ import annotations

import json
import re
import shlex
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
OUT_FLAGS = ("--json", "--vtu", "--out")


def _commands():
    """(section, command line) of every ``python -m`` command in the bash blocks of the README and the
    docs pages it points to (continuation lines joined)."""
    text = "\n".join(p.read_text() for p in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))])
    out, section = [], ""
    in_block, cur = False, ""
    for line in text.splitlines():
        if line.startswith("## "):
            section = line[3:]
        if line.startswith("```"):
            in_block = line.strip() == "```bash"
            continue
        if not in_block:
            continue
        code = line.split("  #")[0].rstrip() if not line.lstrip().startswith("#") else ""
        cur += " " + code.rstrip("\\").strip()
        if not code.endswith("\\"):
            if "python -m" in cur:
                for part in cur.split("&&"):
                    if "python -m" in part:
                        out.append((section, part.strip()))
            cur = ""
    return out


def _outputs(cmd):
    words = shlex.split(cmd.replace("[", "").replace("]", ""))
    return [(w, words[i + 1]) for i, w in enumerate(words[:-1]) if w in OUT_FLAGS]


COMMANDS = _commands()


def test_the_readme_has_examples():
    assert len(COMMANDS) > 15 and any(_outputs(c) for _, c in COMMANDS)


def _under_results(cmd):
    return all(p == "-" or p == "results" or p.startswith("results/") for _, p in _outputs(cmd))


@pytest.mark.parametrize("section,cmd", [(s, c) for s, c in COMMANDS if _outputs(c)])
def test_examples_write_under_results(section, cmd):
    assert _under_results(cmd), (_outputs(cmd), cmd)


def test_example_creates_its_missing_results_directory(tmp_path, monkeypatch):
    """The README's first MDR example, run in an empty directory: results/ is created."""
    from studies.cli import main

    cmd = next(c for _, c in COMMANDS if c.startswith("python -m mdr normal") and "results/" in c)
    monkeypatch.chdir(tmp_path)
    assert main(shlex.split(cmd)[3:]) == 0
    path = tmp_path / _outputs(cmd)[0][1]
    assert path.parent.name == "results" and json.loads(path.read_text())["contact_radius"] > 0
    assert path.stat().st_mode & 0o777 == 0o666 & ~_umask()


def test_unwritable_results_path_fails_with_one_line(tmp_path, monkeypatch, capsys):
    from studies.cli import main

    monkeypatch.chdir(tmp_path)
    (tmp_path / "results").write_text("a file where the directory should be")
    code = main(["normal", "--profile", "sphere", "--R", "6e-3", "--F", "0.5", "--json", "results/normal.json"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "results" in err[0] and re.search(r"not a directory|file", err[0])


def _umask():
    import os

    old = os.umask(0o022)
    os.umask(old)
    return old


@pytest.mark.xdist_group("readme-quick")
def test_the_quick_comparison_prints_what_the_readme_says(tmp_path):
    """README, Set-up: the quick comparison's report tallies 37 of 37 metric verdicts of its pair scenes
    decided, all holding (the textbook anchor and four scenes of the catalogue on coarser ladders); the
    tally line in the README is the report's sentence (validation.report.tally_text)."""
    from validation import compare

    out = tmp_path / "quick"
    assert compare.main(["--quick", "--jobs", "1", "--out", str(out), "--no-hard-cases"]) == 0
    tally = next(line for line in (out / "report.md").read_text().splitlines() if line.startswith("Decided: "))
    assert tally.startswith("Decided: 37 of 37 metric verdicts of the pair scenes (37 hold,"), tally
    readme = (ROOT / "README.md").read_text().replace("\n", " ")
    assert '"Decided: 37 of 37 metric verdicts of the pair scenes (37 hold, ...)"' in readme
