"""Run one scene through its family (``validation.families``): MDR and FE side by side, result
ladders, errors, files.

The result is plain data (JSON); ``validation.store.write_scene`` stores it with its figures
atomically in one directory per scene.
"""
from __future__ import annotations

from . import families
from .scenes import Scene


def run_scene(s: Scene, out_dir=None, *, fields: bool = True, log=None) -> dict:
    """Run one scene by its family; returns its result dict. With ``out_dir`` the VTU and figures
    are written there (the caller makes the directory atomic, ``validation.store.write_scene``);
    ``fields``: the pyvista field plot of the pair family; ``log``: a callable taking progress lines."""
    return families.module(s.family).run(s, out_dir, fields=fields, log=log or (lambda msg: None))
