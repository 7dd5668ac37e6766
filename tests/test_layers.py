"""The import graph (issue 12): layers common -> mdr -> meshes -> fem -> studies -> validation, no
arrow down-up, no cycle.

Read from the sources with ``ast``, so imports inside functions count as much as
those at the top: ``common`` (the project's infrastructure: errors, atomic io, the CLI parser,
executors, plugins, ladder error bars) imports no other package of the project, ``mdr`` (the
contact law, the apparatus: physics) only ``common``, ``meshes`` only those two, ``fem`` only
``common``, ``mdr`` and ``meshes``; ``studies`` (the paper's studies and the ``python -m mdr``
command) stands on ``fem`` and imports the FE law directly; ``validation`` sits on top. The one
arrow up is the entry point of ``python -m mdr``, ``mdr/__main__.py``: a program that no module
imports, which hands the command line to ``studies.cli``.
"""
import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("common", "mdr", "meshes", "fem", "rough", "studies", "validation")
#: the packages each package may import (besides itself); ``rough`` (rough surfaces, the half-space
#: beside the FE model) stands on ``mdr`` only
ALLOWED = {"common": set(), "mdr": {"common"}, "meshes": {"common", "mdr"}, "fem": {"common", "mdr", "meshes"},
           "rough": {"common", "mdr"}, "studies": {"common", "mdr", "meshes", "fem"},
           "validation": {"common", "mdr", "meshes", "fem", "rough", "studies"}}
#: entry points of ``python -m PACKAGE``: programs no module imports, allowed to hand over to a layer above
ENTRY_POINTS = {"mdr.__main__": {"studies.cli"}}


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
                while c and c not in mods:  # "import fem.axisym.law.x" -> the longest project module
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
    assert "fem.axisym.law" in g["fem.apparatus"] and "mdr.apparatus" in g["fem.apparatus"]
    assert "fem.axisym.mode1" in g["fem.axisym.law"]
    assert "meshes" in g["fem.axisym.law"]  # imported inside FEContact.__init__: seen too


@pytest.mark.parametrize("pkg", PACKAGES)
def test_no_package_imports_a_layer_above_it(pkg):
    bad = sorted(f"{m} -> {t}" for m, ts in import_graph().items() if m.split(".")[0] == pkg
                 for t in ts if t.split(".")[0] not in ALLOWED[pkg] | {pkg} and t not in ENTRY_POINTS.get(m, ()))
    assert not bad, bad


def test_an_entry_point_is_imported_by_no_module():
    """The exemption of ``ENTRY_POINTS`` holds only while no module imports the entry point."""
    g = import_graph()
    assert all(e in g for e in ENTRY_POINTS)
    assert not [m for m, ts in g.items() if set(ENTRY_POINTS) & ts]


def test_there_is_no_import_cycle():
    assert _cycles(import_graph()) == []


def test_the_fe_law_is_built_in_and_a_third_party_law_is_a_plugin(monkeypatch):
    """``python -m mdr apparatus --law fem`` takes the FE law directly (``studies`` stands on ``fem``);
    another package's law, registered under the entry-point group, is offered beside it and may not
    replace a built-in one."""
    from importlib.metadata import EntryPoint

    from common import plugins
    from fem.cli import FE_LAW
    from mdr.protocol import LawPlugin
    from studies.cli import build_parser, contact_laws

    eps = [EntryPoint("mylaw", "test_layers:MY_LAW", plugins.GROUP), EntryPoint("fem", "mdr:MDRContact", plugins.GROUP)]
    monkeypatch.setattr(plugins, "entry_points", lambda group: [e for e in eps if e.group == group])
    laws = contact_laws()
    assert laws["fem"] is FE_LAW and isinstance(FE_LAW, LawPlugin)
    assert laws["mylaw"] is MY_LAW and set(laws) == {"fem", "mylaw"}
    args = build_parser().parse_args(["apparatus", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0.5",
                                      "--ua", "1e-7", "--law", "mylaw", "--my-flag", "3"])
    assert args.law == "mylaw" and args.my_flag == 3.0


class _MyLaw:
    """A third-party law's plugin object (``mdr.protocol.LawPlugin``), as another package would register."""
    help = "a third-party law (test)"

    def add_arguments(self, parser):
        parser.add_argument("--my-flag", type=float, default=1.0)

    def apparatus_result(self, *args):
        raise NotImplementedError


MY_LAW = _MyLaw()
