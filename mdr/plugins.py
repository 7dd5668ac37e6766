"""Contact laws beyond MDR, found as plugins (entry points), so ``mdr`` imports no package above it.

A package that provides a contact law for ``python -m mdr apparatus --law NAME``
registers an object under the entry-point group :data:`GROUP` in its
``pyproject.toml``::

    [project.entry-points."fretting.contact_laws"]
    fem = "fem.cli:FE_LAW"

The object (see :class:`mdr.protocol.LawPlugin`) has ``help`` (one line for the
``--law`` help), ``add_arguments(parser)`` (its own flags, added to the
apparatus command) and ``apparatus_result(profile, materials, app, mu, F0, dF,
alpha, ua, cycles, steps, args)`` (the result dict of the command). The entry
points are read from the installed package metadata: after adding one, run
``pip install -e .`` again.
"""
from __future__ import annotations

import warnings
from importlib.metadata import entry_points

GROUP = "fretting.contact_laws"


def law_plugins() -> dict:
    """{name: plugin object} of the installed contact-law plugins, sorted by name.

    A plugin that cannot be imported is left out with a warning (it must not break
    the commands that do not use it)."""
    found = {}
    for ep in sorted(entry_points(group=GROUP), key=lambda e: e.name):
        if ep.name in found or ep.name == "mdr":  # the MDR law is built in
            continue
        try:
            found[ep.name] = ep.load()
        except Exception as exc:  # noqa: BLE001 (any import failure of a third-party plugin)
            warnings.warn(f"contact-law plugin {ep.name!r} ({ep.value}) cannot be loaded: {exc}", RuntimeWarning)
    return found
