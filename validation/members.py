"""The store of the tasks of a scene of independent tasks by their content (``validation.runner.
member_key``): one JSON file per task under ``OUT/members/``, written atomically, read back by any scene
of the same folder whose task has the same key.
"""
from __future__ import annotations

from pathlib import Path

from common.io import write_json


def member_path(out_root, key: str) -> Path:
    """Where a task's result of a scene of independent tasks is stored by its content key
    (``runner.member_key``): ``OUT/members/KEY.json``."""
    return Path(out_root) / "members" / f"{key}.json"


def load_member(out_root, key: str) -> dict | None:
    """A stored task's result by its content key, or None if absent or unreadable."""
    import json

    try:
        return json.loads(member_path(out_root, key).read_text())
    except (OSError, ValueError):
        return None


def write_member(out_root, key: str, member: dict) -> None:
    """Store a task's result under its content key (atomically); a failed task is not stored (a rerun
    tries it again)."""
    if member.get("failed"):
        return
    path = member_path(out_root, key)
    path.parent.mkdir(parents=True, exist_ok=True)
    write_json(path, member)
