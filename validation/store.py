"""The store of an output folder: one directory per scene under ``OUT/scenes/``, written atomically (a
run goes to a temporary directory that replaces the scene's when complete), read back by the report;
and the tables computed once per code version (the hard cases, the CalculiX witness: ``cached``).
"""
from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from common.io import DIR_MODE, write_json

from .scenes import Scene

from .sources import code_version


def scene_dir(out_root, name) -> Path:
    return Path(out_root) / "scenes" / name


def load_scene(out_root, name) -> dict | None:
    """The stored result of a scene, or None if absent or unreadable."""
    import json

    p = scene_dir(out_root, name) / "result.json"
    try:
        return json.loads(p.read_text())
    except (OSError, ValueError):
        return None


def write_scene(s: Scene, out_root, fingerprint: str, *, fields: bool = True, log=None, meta=None,
                members: list | None = None) -> dict:
    """Run a scene into a temporary directory and move it into place when complete: an
    interrupted run leaves the previous result (or nothing) and never half a scene.
    ``meta``: extra keys stored in result.json (e.g. the ``worker`` that ran it); ``members``: the
    results of the scene's tasks where they ran elsewhere (``runner.run_scene``)."""
    final = scene_dir(out_root, s.name)
    final.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{s.name}.", dir=final.parent))
    os.chmod(tmp, DIR_MODE)
    try:
        from . import runner

        result = runner.run_scene(s, tmp, fields=fields, log=log, members=members)
        result["fingerprint"] = fingerprint
        result.update(meta or {})
        write_json(tmp / "result.json", result)
        _swap_into_place(tmp, final)
        return result
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def _swap_into_place(tmp: Path, final: Path) -> None:
    """Replace the scene directory ``final`` by the complete directory ``tmp`` (same parent)."""
    old = None
    if final.exists():
        old = final.with_name(f".{final.name}.old.{os.getpid()}")
        os.replace(final, old)
    os.replace(tmp, final)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def scene_files(out_root, name) -> dict:
    """The stored files of a scene as {relative path: bytes} (to ship them from a worker)."""
    d = scene_dir(out_root, name)
    return {p.relative_to(d).as_posix(): p.read_bytes() for p in sorted(d.rglob("*")) if p.is_file()}


def install_scene_files(out_root, name, files: dict) -> None:
    """Store a scene from {relative path: bytes} (``scene_files`` of a worker), atomically as
    ``write_scene`` does; it must hold result.json."""
    if "result.json" not in files:
        raise ValueError(f"scene {name}: the shipped files hold no result.json")
    final = scene_dir(out_root, name)
    final.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{name}.", dir=final.parent))
    os.chmod(tmp, DIR_MODE)
    try:
        for rel, data in files.items():
            path = (tmp / rel).resolve()
            if tmp.resolve() not in path.parents:
                raise ValueError(f"scene {name}: shipped file {rel!r} lies outside the scene directory")
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(data)
        _swap_into_place(tmp, final)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def stored(path, key: str):
    """What a previous run stored under ``key`` in the code-versioned JSON file ``path`` (``cached``):
    ``(value, code version)``, or ``(None, None)`` if absent or unreadable."""
    import json

    try:
        data = json.loads(Path(path).read_text())
        return data[key], data.get("code")
    except (OSError, ValueError, KeyError, TypeError):
        return None, None


def cached(path, key: str, compute, *, what: str, force: bool = False, log=print):
    """``compute()``'s value, stored under ``key`` in ``path`` with the code version
    (``validation.sources.code_version``): a rerun with unchanged code reads it back (saying so
    through ``log``, naming ``what``), unless ``force``."""
    value, code = stored(path, key)
    version = code_version()
    if value is not None and code == version and not force:
        log(f"[skip] {what}: unchanged since the last run (--force reruns)")
        return value
    value = compute()
    write_json(path, {"code": version, key: value})
    return value

