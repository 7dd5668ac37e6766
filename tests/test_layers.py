"""The import graph (issue 12): layers mdr -> meshes -> fem -> validation, no arrow down-up, no cycle.

Read from the sources with ``ast``, so imports inside functions count as much as
those at the top: ``mdr`` (the contact law, the apparatus and the shared ground
floor: errors, io, the CLI helpers) imports no other package of the project,
``meshes`` only ``mdr``, ``fem`` only ``mdr`` and ``meshes``, and ``validation``
sits on top. The FE law reaches ``python -m mdr apparatus --law fem`` as an
entry-point plugin (``mdr.plugins``), not as an import.
"""
import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("mdr", "meshes", "fem", "rough", "validation")
#: the packages each package may import (besides itself); ``rough`` (rough surfaces, the half-space
#: beside the FE model) stands on ``mdr`` only
ALLOWED = {"mdr": set(), "meshes": {"mdr"}, "fem": {"mdr", "meshes"}, "rough": {"mdr"},
           "validation": {"mdr", "meshes", "fem", "rough"}}


def _modules():
    mods = {}
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg).rglob("*.py")):
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            mods[name] = path
    return mods


def import_graph() -> dict:
    """{module: set of project modules it imports anywhere in its source}."""
    mods = _modules()
    graph = {}
    for name, path in mods.items():
        is_pkg = path.name == "__init__.py"
        base = name.split(".") if is_pkg else name.split(".")[:-1]
        targets = set()
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                cands = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    up = base[:len(base) - node.level + 1]
                    src = ".".join(up + ([node.module] if node.module else []))
                else:
                    src = node.module
                # "from pkg import sub" imports the submodule pkg.sub when there is one
                cands = [f"{src}.{a.name}" if f"{src}.{a.name}" in mods else src for a in node.names]
            else:
                continue
            for c in cands:
                while c and c not in mods:  # "import fem.law.x" -> the longest project module
                    c = c.rpartition(".")[0]
                if c and c != name:
                    targets.add(c)
        graph[name] = targets
    return graph


def _cycles(graph):
    """Strongly connected components with more than one module (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_the_graph_is_read_from_the_sources():
    g = import_graph()
    assert "fem.law" in g["fem.apparatus"] and "mdr.apparatus" in g["fem.apparatus"]
    assert "fem.mode1" in g["fem.law"]
    assert "meshes" in g["fem.law"]  # imported inside FEContact.__init__: seen too


@pytest.mark.parametrize("pkg", PACKAGES)
def test_no_package_imports_a_layer_above_it(pkg):
    bad = sorted(f"{m} -> {t}" for m, ts in import_graph().items() if m.split(".")[0] == pkg
                 for t in ts if t.split(".")[0] not in ALLOWED[pkg] | {pkg})
    assert not bad, bad


def test_there_is_no_import_cycle():
    assert _cycles(import_graph()) == []


def test_the_fe_law_is_a_registered_plugin_of_the_apparatus_command():
    """python -m mdr apparatus --law fem finds the FE law through the entry point (pyproject.toml),
    and pyproject.toml declares it (a stale install would miss it: pip install -e .)."""
    from fem.cli import FE_LAW
    from mdr.plugins import GROUP, law_plugins
    from mdr.protocol import LawPlugin

    assert f'[project.entry-points."{GROUP}"]' in (ROOT / "pyproject.toml").read_text()
    plugins = law_plugins()
    assert plugins.get("fem") is FE_LAW and isinstance(FE_LAW, LawPlugin)
