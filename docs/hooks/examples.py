"""MkDocs hook: the literate examples of ``docs/examples/*.py`` rendered as pages of the site.

An example is a Python script the fast suite runs (``tests/test_examples.py``): its module docstring is
Markdown (its ``::`` blocks become code blocks), and in its body a run of comment lines (``# ...``) at
the left margin is prose (``# ## Title``: a heading), everything else code. ``render`` turns one script
into one Markdown page; ``on_files`` adds a page per script under ``examples/`` and ``on_config`` lists
them in the navigation. A script that does not parse fails the build (``mkdocs build --strict``).
"""
from __future__ import annotations

import ast
import re
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _docstring(text: str) -> str:
    """The docstring's Markdown: a paragraph ending in ``::`` followed by an indented block becomes the
    paragraph and a fenced block."""
    out, lines, i = [], text.strip("\n").split("\n"), 0
    while i < len(lines):
        line = lines[i]
        if line.rstrip().endswith("::"):
            out.append(line.rstrip()[:-1])
            i += 1
            block = []
            while i < len(lines) and (not lines[i].strip() or lines[i].startswith("    ")):
                block.append(lines[i][4:])
                i += 1
            out += ["", "```bash", *[b for b in block if b.strip()], "```", ""]
            continue
        out.append(line)
        i += 1
    return "\n".join(out)


def render(source: str) -> str:
    """One example script as a Markdown page: its docstring, then prose and code in their order."""
    tree = ast.parse(source)
    doc = ast.get_docstring(tree, clean=True) or ""
    body = source.split("\n")[tree.body[0].end_lineno:] if doc else source.split("\n")
    parts, code, prose = [_docstring(doc)], [], []

    def flush_code():
        while code and not code[-1].strip():
            code.pop()
        while code and not code[0].strip():
            code.pop(0)
        if code:
            parts.append("\n".join(["```python", *code, "```"]))
        code.clear()

    def flush_prose():
        if prose:
            parts.append("\n".join(prose))
        prose.clear()

    for line in body:
        m = re.match(r"^# ?(.*)$", line)
        if m and not line.startswith("#!") and "noqa" not in line:
            flush_code()
            text = m.group(1)
            prose.append(text if not text.startswith("#") else "\n" + text)
        else:
            flush_prose()
            code.append(line)
    flush_prose()
    flush_code()
    return "\n\n".join(p for p in parts if p.strip()) + "\n"


def _pages() -> list:
    return sorted(EXAMPLES.glob("*.py"))


def _title(path: Path) -> str:
    doc = ast.get_docstring(ast.parse(path.read_text())) or path.stem
    first = doc.strip().split("\n")[0]
    return first.lstrip("# ").strip() or path.stem


def on_config(config):
    """The examples as a section of the navigation, one page each."""
    nav = config.get("nav")
    if nav is not None:
        nav.append({"Examples": [{_title(p): f"examples/{p.stem}.md"} for p in _pages()]})
    return config


def on_files(files, config):
    """A generated page ``examples/NAME.md`` per script."""
    from mkdocs.structure.files import File

    for p in _pages():
        files.append(File.generated(config, f"examples/{p.stem}.md", content=render(p.read_text())))
    return files
