"""The scene families, one module each: how a scene of the family runs (``run``), its table in the
report (``table``, over the rows stored under ``KEY`` in its result) and its figure (``figure``).

``pair``: MDR against the FE model on both ladders (the report's default table and figures);
``validity``: the FE bodies shrunk towards the contact; ``curvature``: the contact radius swept against
R; ``points``: the paper's apparatus points, FE against MDR at each; ``assumptions3d``: Mindlin's
assumptions relaxed one at a time in 3D; ``tilt``: the flat face tilted; ``roughness``: rough surfaces. A scene names its family (``validation.scenes.Scene.family``); adding a family is a module
here with those names and its entry in ``validation.scenes.FAMILIES``.
"""
from __future__ import annotations

import importlib


def module(family: str):
    """The module of a family (``validation.scenes.FAMILIES``)."""
    from ..scenes import FAMILIES

    if family not in FAMILIES:
        raise ValueError(f"family must be one of {', '.join(FAMILIES)}; got {family!r}")
    return importlib.import_module(f"{__name__}.{family}")


def variant_keys(scene, kind: str, v: dict, keys):
    """The error of a family's variant ``v`` (of the kind ``kind``) of ``scene``, ``bad(key, rng)``: one line
    naming the scene, the variant and the key with its valid range; returned after refusing a key of ``v``
    that is not one of ``keys``."""
    from common.errors import InputError

    def bad(key, rng):
        return InputError(f"scene {scene.name}: {kind} variant {v!r}: {key} must be {rng}")

    unknown = sorted(set(v) - set(keys))
    if unknown:
        raise bad(unknown[0], f"one of the variant's keys ({', '.join(keys)})")
    return bad


def number(v: dict, key: str, ok, bad, rng: str) -> float:
    """A variant's number ``v[key]`` as a float, checked: finite and ``ok(x)``; else ``bad(key, rng)`` (the
    family's ``InputError`` naming the scene, the variant, the key and its valid range ``rng``)."""
    import math

    try:
        if isinstance(v[key], bool):
            raise TypeError
        x = float(v[key])
    except (TypeError, ValueError):
        raise bad(key, rng) from None
    if not (math.isfinite(x) and ok(x)):
        raise bad(key, rng)
    return x


def of_result(res: dict) -> str:
    """The family of a stored result (its scene's ``family``)."""
    return (res.get("scene") or {}).get("family") or "pair"


def result_of(s, key: str, rows: list, t0: float, out_dir, figure, **extra) -> dict:
    """A family's result: its scene, its ``rows`` under ``key`` (the family's ``KEY``), ``extra`` keys
    (default ``closed_form`` None), ``errors`` with a_ref, the run time since ``t0``
    (``time.perf_counter``) and, with ``out_dir``, its ``figure(result, out_dir)`` files."""
    import time
    from pathlib import Path

    from ..scenes import a_ref

    result = {"scene": s.as_dict(), "closed_form": None, **extra, key: rows, "errors": {"a_ref": a_ref(s)},
              "files": {}, "runtime_s": time.perf_counter() - t0}
    if out_dir is not None:
        result["files"].update(figure(result, Path(out_dir)))
    return result


def members_of(s, members, tasks, member, log, describe) -> tuple:
    """The members of a family of independent tasks: ``members`` where they ran elsewhere (``validation.
    compare`` spreads them over its workers), else ``member(s, task)`` of every ``tasks(s)`` here in
    turn, each logged as ``describe(k, task, result)``; returns (members, given)."""
    if members is not None:
        return members, True
    out = []
    for k, task in enumerate(tasks(s), 1):
        out.append(member(s, task))
        log(describe(k, task, out[-1]))
    return out, False


def result_of_members(s, key: str, rows: list, t0: float, out_dir, figure, members: list, given: bool) -> dict:
    """``result_of`` for a family of independent tasks: ``members_cpu_s`` (their summed run times) beside
    the rows; where the members ran elsewhere (``given``) the scene's cost is theirs, those read back from
    the store by content (``stored``) costing nothing."""
    cpu = sum(m.get("runtime_s", 0.0) for m in members if not m.get("stored"))
    res = result_of(s, key, rows, t0, out_dir, figure, members_cpu_s=cpu)
    if given:
        res["runtime_s"] = cpu
    return res

