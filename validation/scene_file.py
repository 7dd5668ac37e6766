"""Scenes a user writes: a TOML file of ``[[scene]]`` tables (``python -m validation.compare --scene-file``).

Each table holds the fields of :class:`validation.scenes.Scene` (SI units) and nothing else; what is
left out takes the catalogue's default (steel on steel, R = 6 mm, Table 2's load, the full ladders).
Every field is checked once, here and in ``Scene``, before any work: an unknown key, a wrong type or a
number out of its range is one line naming the file, the scene, the field and what it must be.

Example (``docs/examples/scenes.toml`` holds a complete one, run by the tests)::

    [[scene]]
    name = "my-sphere"
    title = "My 10 mm sphere on aluminium"
    profile = "sphere"
    R = 10e-3
    E2 = 70e9
    nu2 = 0.33
    F0 = 1.0
    dF = 0.0
    amplitude = 0.1          # N: the tangential force amplitude (drive = "force")

A scene names its ``family`` (``validation.scenes.FAMILIES``; default ``"pair"``: MDR against the FE
model on both ladders, no variants); the other families take ``variants``, tables each read into the
family's typed ``Variant`` (``validation.families.<family>.Variant``, its docstring lists the keys and
ranges): ``{block, cap}`` (``"validity"``), ``{a_over_R, nu}`` (``"curvature"``), ``{kx, b, F0, dF, ua,
mu1, mu2}`` (``"points"``), ``{relax, b, E2, nu2}`` (``"assumptions3d"``), ``{profile, b, tilts,
fe_levels, refine, band}`` (``"tilt"``) or ``{rms | maps, ...}`` (``"roughness"``,
``validation.rough_variant``).
"""
from __future__ import annotations

import re
import tomllib
from dataclasses import fields
from pathlib import Path

from common.errors import InputError

from .scenes import Scene

#: fields whose TOML arrays become tuples (the Scene holds them as tuples: hashable, fingerprinted)
_TUPLES = ("fe_levels", "mdr_cells", "variants")
#: fields that are floats in SI units (an integer in the file, e.g. F0 = 1, is taken as 1.0)
_FLOATS = ("b", "R", "mu", "F0", "dF", "alpha", "amplitude", "kx", "mu2", "E1", "nu1", "E2", "nu2")


def _tuple(v):
    """A TOML value with its arrays as tuples (nested: a variant's ``tilts``, ``refine``, ``band``)."""
    if isinstance(v, list):
        return tuple(_tuple(x) for x in v)
    if isinstance(v, dict):
        return {k: _tuple(x) for k, x in v.items()}
    return v


def scene_from_table(table: dict, where: str = "scene", base: Path | None = None) -> Scene:
    """One ``[[scene]]`` table as a checked :class:`Scene` (InputError naming ``where`` and the field);
    a rough variant's measured ``maps`` relative to ``base`` (the scene file's folder) made absolute, so
    any worker reads the same files."""
    valid = {f.name for f in fields(Scene)}
    unknown = sorted(set(table) - valid)
    if unknown:
        raise InputError(f"{where}: unknown field(s) {', '.join(unknown)}; valid fields: {', '.join(sorted(valid))}")
    missing = [k for k in ("name", "title", "profile") if k not in table]
    if missing:
        raise InputError(f"{where}: missing field(s) {', '.join(missing)} (every scene needs name, title and profile)")
    kw = {}
    for k, v in table.items():
        if k in _FLOATS and isinstance(v, int) and not isinstance(v, bool):
            v = float(v)
        if k in _FLOATS and not isinstance(v, float):
            raise InputError(f"{where}: {k} must be a number, got {v!r}")
        if k in _TUPLES:
            if not isinstance(v, list):
                raise InputError(f"{where}: {k} must be an array, got {v!r}")
            v = _tuple(v)
        if k == "variants" and not all(isinstance(x, dict) for x in v):
            raise InputError(f"{where}: variants must be an array of tables, got {table[k]!r}")
        if k == "apparatus":  # a table of the apparatus's fields -> (name, value) pairs, sorted
            if not isinstance(v, dict):
                raise InputError(f"{where}: apparatus must be a table of mdr.apparatus.Apparatus fields, got {v!r}")
            v = tuple(sorted(v.items()))
        if k == "variants" and base is not None:
            v = tuple({**x, "maps": tuple(str((base / m).resolve()) if isinstance(m, str) else m for m in x["maps"])}
                      if isinstance(x.get("maps"), (list, tuple)) else x for x in v)
        kw[k] = v
    kw.setdefault("group", "user")
    if not isinstance(kw["name"], str) or not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.\-]*", kw["name"]):
        raise InputError(f"{where}: name must be letters, digits and _ . - starting with a letter or digit "
                         f"(an output folder is named after it), got {kw['name']!r}")
    try:
        return Scene(**kw)
    except InputError as e:
        raise InputError(f"{where}: {e}") from None
    except TypeError as e:  # a wrong type reached a comparison
        raise InputError(f"{where}: {e}") from None


def load_scene_file(path) -> dict:
    """The scenes of a TOML file, ``{name: Scene}`` in file order (InputError on a missing or unreadable
    file, bad TOML, no ``[[scene]]`` table, a repeated name, or any bad field)."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as e:
        raise InputError(f"--scene-file {str(path)!r} cannot be read: {e.strerror or e}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"--scene-file {str(path)!r} is not valid TOML: {e}") from None
    extra = sorted(set(data) - {"scene"})
    tables = data.get("scene")
    if extra or not isinstance(tables, list) or not tables:
        raise InputError(f"--scene-file {str(path)!r} must hold one or more [[scene]] tables and nothing else"
                         + (f" (found {', '.join(extra)})" if extra else ""))
    out = {}
    for i, t in enumerate(tables, 1):
        s = scene_from_table(t, f"{path.name}: scene {i} ({t.get('name', 'no name')})", base=path.resolve().parent)
        if s.name in out:
            raise InputError(f"{path.name}: scene {i}: the name {s.name!r} is used twice")
        out[s.name] = s
    return out
