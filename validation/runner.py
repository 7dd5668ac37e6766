"""Run one scene through its family (``validation.families``): MDR and FE side by side, result
ladders, errors, files.

The result is plain data (JSON); ``validation.store.write_scene`` stores it with its figures
atomically in one directory per scene. The tasks of a family of independent tasks whose module states
what a task computes from (``member_physics``) are stored by that content as well (``member_key``), so
the same computation in another scene, or in a scene whose other tasks changed, is read back, not rerun.
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


def member_key(s: Scene, task: dict, version: str) -> str | None:
    """The content key of a task: a hash of what it computes from (its family's ``member_physics``) and
    the code version (``validation.sources.code_version``); None where the family states none."""
    import hashlib
    import json

    mod = families.module(s.family)
    if not hasattr(mod, "member_physics"):
        return None
    blob = json.dumps({"physics": mod.member_physics(s, task), "code": version}, sort_keys=True, default=str)
    return hashlib.sha256(blob.encode()).hexdigest()[:24]


def split_stored(s: Scene, tasks: list, out, version: str, force: bool = False) -> tuple:
    """The tasks of ``s`` whose results ``out`` stores by content (``members.load_member``; none with
    ``force``): (their results, each with its task's keys here and ``stored`` True; the other tasks as
    (task, key) pairs, key None where the family states no content)."""
    from .members import load_member

    found, todo = [], []
    for t in tasks:
        key = member_key(s, t, version)
        m = None if key is None or force else load_member(out, key)
        if m is None:
            todo.append((t, key))
        else:
            found.append({**m, **t, "stored": True})
    return found, todo


def members_here(s: Scene, out, version: str, log, force: bool = False) -> list | None:
    """The results of every task of ``s`` in this process, those stored by content read back
    (``split_stored``; none with ``force``) and the others run and stored; None for a scene without tasks
    or content."""
    from .members import write_member

    tasks = scene_tasks(s)
    if not tasks or member_key(s, tasks[0], version) is None:
        return None
    found, todo = split_stored(s, tasks, out, version, force)
    if found:
        log(f"  {len(found)} of {len(tasks)} task(s) stored by content: read back")
    for k, (t, key) in enumerate(todo, 1):
        m = run_member(s, t)
        write_member(out, key, m)
        found.append(m)
        log(f"  task {k} of {len(todo)}: {m.get('runtime_s', 0.0):.0f} s")
    return found
