"""Run one scene through its family (``validation.families``): MDR and FE side by side, result
ladders, errors, files.

The result is plain data (JSON); ``validation.store.write_scene`` stores it with its figures
atomically in one directory per scene.
"""
from __future__ import annotations

from . import families
from .scenes import Scene


def run_scene(s: Scene, out_dir=None, *, fields: bool = True, log=None, members: list | None = None) -> dict:
    """Run one scene by its family; returns its result dict. With ``out_dir`` the VTU and figures
    are written there (the caller makes the directory atomic, ``validation.store.write_scene``);
    ``fields``: the pyvista field plot of the pair family; ``log``: a callable taking progress lines;
    ``members``: for a family of independent tasks (``tasks``, ``member``), their results, computed
    elsewhere (``validation.compare`` spreads them over its workers)."""
    extra = {} if members is None else {"members": members}
    return families.module(s.family).run(s, out_dir, fields=fields, log=log or (lambda msg: None), **extra)


def scene_tasks(s: Scene) -> list | None:
    """The independent tasks of a scene whose family has them (``tasks``), else None: the scene runs
    as one."""
    mod = families.module(s.family)
    return mod.tasks(s) if hasattr(mod, "tasks") else None


def run_member(s: Scene, task: dict) -> dict:
    """One task of ``scene_tasks`` (plain data)."""
    return families.module(s.family).member(s, task)
