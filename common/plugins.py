"""Third-party contact laws, found as plugins (entry points): the MDR and FE laws are built into
``python -m mdr`` (``studies.cli.contact_laws``); another package offers its own law to
``python -m mdr apparatus --law NAME`` and ``study --law NAME`` by registering an object under the
entry-point group :data:`GROUP` in its ``pyproject.toml``::

    [project.entry-points."fretting.contact_laws"]
    mylaw = "mypackage.cli:MY_LAW"

The object (see :class:`mdr.protocol.LawPlugin`) has ``help`` (one line for the
``--law`` help), ``add_arguments(parser)`` (its own flags, added to the
apparatus command) and ``apparatus_result(profile, materials, app, mu, loading,
args)`` (the result dict of the command; ``loading`` a ``mdr.loading.Loading``). The entry
points are read from the installed package metadata: after adding one, run
``pip install -e .`` again.
"""
from __future__ import annotations

import warnings
from importlib.metadata import entry_points

GROUP = "fretting.contact_laws"


def law_plugins(builtin=("mdr",)) -> dict:
    """{name: plugin object} of the installed contact-law plugins, sorted by name; names in
    ``builtin`` (the command's own laws) are not overridden.

    A plugin that cannot be imported is left out with a warning (it must not break
    the commands that do not use it)."""
    found = {}
    for ep in sorted(entry_points(group=GROUP), key=lambda e: e.name):
        if ep.name in found or ep.name in builtin:
            continue
        try:
            found[ep.name] = ep.load()
        except Exception as exc:  # noqa: BLE001 (any import failure of a third-party plugin)
            warnings.warn(f"contact-law plugin {ep.name!r} ({ep.value}) cannot be loaded: {exc}", RuntimeWarning)
    return found
