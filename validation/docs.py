"""The measured tables of the docs, generated from a catalogue run: ``python -m validation.docs``.

A page of ``docs/`` marks each generated table between two lines::

    <!-- generated: NAME (python -m validation.docs --write) -->
    | ... the table ... |
    <!-- end generated -->

and ``TABLES[NAME]`` writes it from the ``results.json`` of a full catalogue run
(``python -m validation.compare --jobs 2``), with the same functions the report uses (its summary
cells, the families' tables): a table in the docs is what the code computes, not a copy that drifts.
``--write`` replaces the blocks; ``--check`` (the slow suite, after its full run) compares them with
what the run gives, the words exactly and the numbers within ``CHECK_REL`` / ``CHECK_ABS`` (a CPU that
rounds differently moves the last digits of a spread, not its grade), and exits 1 naming every
difference.
"""
from __future__ import annotations

import json
import re
import sys
from pathlib import Path

from common.cli import OneLineParser

from . import families
from .report import scene_outcome, summary_cell
from .text import num

DOCS = Path(__file__).resolve().parent.parent / "docs"
BEGIN = re.compile(r"^<!-- generated: ([a-z0-9_-]+) \(python -m validation\.docs --write\) -->$")
END = "<!-- end generated -->"
#: --check: two numbers agree within CHECK_REL of the larger plus CHECK_ABS (the tables print 2-3 digits)
CHECK_REL, CHECK_ABS = 0.15, 0.02


def catalogue_table(scenes: dict) -> list:
    """Every pair scene of the catalogue: MDR - FE (FE error + MDR error + tolerance) per metric, in %
    of the FE contact radius or dissipation, the slip index of both sides and the scene's verdict
    (the report's summary without its run times)."""
    lines = ["| scene | contact radius | stick radius | dissipation | slip index MDR / FE | verdict |",
             "|---|---|---|---|---|---|"]
    for n, r in scenes.items():
        if families.of_result(r) != "pair":
            continue
        ok, why = scene_outcome(r)
        text = {True: "**holds**", False: f"**fails**: {why}", None: why}[ok]
        lines.append(f"| {n} | {summary_cell('contact_radius', r)} | {summary_cell('stick_radius', r)} | "
                     f"{summary_cell('dissipation', r)} | {num(r['mdr'].get('slip_index'), '.3f')} / "
                     f"{num(r['fem'].get('slip_index'), '.3f')} | {text} |")
    return lines


def _family_table(scene: str):
    def table(scenes: dict) -> list:
        r = scenes[scene]
        lines = families.module(families.of_result(r)).table(r)
        return lines[next(i for i, x in enumerate(lines) if x.startswith("| ")):]  # the table, not its preamble
    table.__doc__ = f"The table of scene {scene!r} as its family renders it in the report (without its preamble)."
    return table


#: where the budget's roughness readings are cached (``validation.spectra.curves``): the run's folder's
#: ``readings`` (``main`` sets it), as ``python -m validation.budget --out`` caches them
READINGS_DIR = None


def budget_table(scenes: dict) -> list:
    """The error budget of the paper's model (``validation.budget``) from the run's scenes: its table, the
    paper's loops against the readings and the sticking transition (computed with MDR; the readings'
    surfaces read from ``READINGS_DIR`` where a budget run cached them)."""
    from . import budget

    lines = budget.markdown({**budget.budget(scenes, readings_dir=READINGS_DIR), "stale": []})  # no run's staleness
    return lines[lines.index(next(x for x in lines if x.startswith("| "))):]


def bars_table(scenes: dict) -> list:
    """How each error bar of the large-body pair scenes bounds (``validation.error_models``): per metric,
    the count of bars by their ladder's status on each side (calibrated, asymptotic, converged; a spread
    or an undetermined bar bounds nothing), then the calibrated bounds in use."""
    from . import error_models

    order = ("calibrated", "asymptotic", "converged")
    counts = {}
    for r in scenes.values():
        if families.of_result(r) != "pair":
            continue
        for q, v in r.get("verdicts", {}).items():
            for side in ("fem", "mdr"):
                st = (v.get(f"{side}_ladder") or {}).get("status")
                key = st if st in order else "no bound"
                counts.setdefault(q, {}).setdefault(side, {}).setdefault(key, 0)
                counts[q][side][key] += 1
    lines = ["| metric | FE bars: " + ", ".join(order) + ", no bound | MDR bars: the same |", "|---|---|---|"]
    for q, c in counts.items():
        lines.append(f"| {q.replace('_', ' ')} | "
                     + " | ".join(" / ".join(str(c.get(side, {}).get(k, 0)) for k in order + ("no bound",))
                                  for side in ("fem", "mdr")) + " |")
    return lines + [""] + error_models.table()


def tally_line(scenes: dict) -> list:
    """The report's tally of the decided verdicts of the pair scenes (``validation.report.tally``), as the
    README and the docs quote it."""
    from .report import tally, tally_text

    return [tally_text(tally(scenes, list(scenes)))]


#: the tables read from the run's scenes of one family each (their scene must be in the run)
SCENE_TABLES = ("assumptions-3d", "validity", "validity-curvature", "halfspace-points", "direction-points",
                "tilt-points", "roughness", "roughness-faces")
#: the generated tables: name -> function of results.json's ``scenes``
TABLES = {"catalogue": catalogue_table, "budget": budget_table, "bars": bars_table, "tally": tally_line,
          **{n: _family_table(n) for n in SCENE_TABLES}}


def blocks(text: str) -> list:
    """The generated blocks of a page: (name, first line index inside, end line index)."""
    lines = text.split("\n")
    out = []
    for i, line in enumerate(lines):
        m = BEGIN.match(line)
        if m:
            j = lines.index(END, i + 1)
            out.append((m.group(1), i + 1, j))
    return out


def render(text: str, scenes: dict) -> str:
    """The page with every generated block rewritten from ``scenes``."""
    lines = text.split("\n")
    for name, i, j in reversed(blocks(text)):
        if name not in TABLES:
            raise ValueError(f"unknown generated table {name!r}; known: {', '.join(TABLES)}")
        lines[i:j] = TABLES[name](scenes)
    return "\n".join(lines)


_NUM = re.compile(r"[-+]?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def differences(old: str, new: str) -> list:
    """Where two renderings of a table differ: line by line, the words exactly, the numbers within
    ``CHECK_REL`` / ``CHECK_ABS``."""
    a, b = old.split("\n"), new.split("\n")
    if len(a) != len(b):
        return [f"{len(a)} lines against {len(b)}"]
    out = []
    for x, y in zip(a, b):
        if _NUM.sub("#", x) != _NUM.sub("#", y):
            out.append(f"words differ:\n  docs: {x}\n  run:  {y}")
            continue
        for p, q in zip(_NUM.findall(x), _NUM.findall(y)):
            p, q = float(p), float(q)
            if abs(p - q) > CHECK_REL * max(abs(p), abs(q)) + CHECK_ABS:
                out.append(f"{p:g} against {q:g}:\n  docs: {x}\n  run:  {y}")
                break
    return out


def pages(docs=DOCS) -> list:
    """The pages with generated blocks: ``docs/*.md``, and the README beside the project's own docs."""
    out = sorted(Path(docs).glob("*.md"))
    readme = Path(docs).parent / "README.md"
    return out + [readme] if Path(docs) == DOCS and readme.exists() else out


def check(scenes: dict, docs=DOCS) -> list:
    """Every generated block of every page against ``scenes``: a list of differences (empty: current)."""
    out = []
    for page in pages(docs):
        text = page.read_text()
        new = render(text, scenes)
        for (name, i, j), (_, k, l) in zip(blocks(text), blocks(new)):
            old_t, new_t = "\n".join(text.split("\n")[i:j]), "\n".join(new.split("\n")[k:l])
            out += [f"{page.name} [{name}]: {d}" for d in differences(old_t, new_t)]
    return out


def main(argv=None) -> int:
    ap = OneLineParser(prog="python -m validation.docs", description=__doc__.split("\n\n")[0])
    ap.add_argument("--results", default="results", help="output folder of a full catalogue run (default ./results)")
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--write", action="store_true", help="rewrite the generated tables of docs/*.md and the README")
    mode.add_argument("--check", action="store_true", help="compare them with the run; exit 1 on a difference")
    args = ap.parse_args(argv)
    path = Path(args.results) / "results.json"
    global READINGS_DIR
    READINGS_DIR = Path(args.results) / "readings"
    try:
        scenes = json.loads(path.read_text())["scenes"]
    except (OSError, ValueError, KeyError) as e:
        print(f"python -m validation.docs: error: --results {str(args.results)!r} holds no readable results.json "
              f"of a catalogue run ({type(e).__name__}); run python -m validation.compare --jobs 2 first",
              file=sys.stderr)
        return 2
    missing = [n for n in SCENE_TABLES if n not in scenes]
    if missing:
        print(f"python -m validation.docs: error: {path} lacks the scenes {', '.join(missing)}: a full catalogue "
              "run is needed", file=sys.stderr)
        return 2
    if args.check:
        diffs = check(scenes)
        for d in diffs:
            print(d)
        print(f"{len(diffs)} difference(s) between the docs' generated tables and {path}")
        return 1 if diffs else 0
    from common.io import write_files_atomic

    files = {}
    for page in pages():
        text = page.read_text()
        new = render(text, scenes)
        if new != text:
            files[page] = new.encode()
    write_files_atomic(files)
    print(f"rewrote {len(files)} page(s): {', '.join(p.name for p in files) or 'none changed'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
