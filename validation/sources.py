"""Which sources a stored scene result depends on, and their digest: a result of other sources is rerun
(``validation.store``), a report says which sources it was made from.

Every module of ``SOURCE_PACKAGES`` counts except the report-only modules of ``validation``
(``REPORT_ONLY``: they only read stored scenes, and no scene imports them, which
``tests/test_validation.py`` checks in a fresh process), so editing the report, the budget or the docs'
tables reruns nothing.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

# validation modules that only read stored scenes (the report, the budget and its readings, the docs'
# tables; no scene imports them): editing them reruns nothing
REPORT_ONLY = ("report.py", "compare.py", "__main__.py", "budget.py", "budget_readings.py", "spectra.py",
               "consistency.py", "docs.py", "budget_cells.py", "rig.py", "rig_budget.py", "rig_roughness.py",
               "budget_plates.py")


#: the packages whose sources a scene result depends on (every module below them, subpackages included)
SOURCE_PACKAGES = ("common", "mdr", "meshes", "fem", "rough", "studies", "validation")


def source_files() -> list:
    """The sources a scene result depends on: every ``.py`` below ``SOURCE_PACKAGES`` (subpackages
    included), without the report-only modules of ``validation``; sorted by their path from the
    repository root."""
    root = Path(__file__).resolve().parent.parent
    out = []
    for pkg in SOURCE_PACKAGES:
        for p in (root / pkg).rglob("*.py"):
            if p.parent.name == "validation" and p.name in REPORT_ONLY:
                continue
            out.append(p)
    return sorted(out, key=lambda p: p.relative_to(root).as_posix())


def code_version() -> str:
    """Hash of the sources a scene result depends on (``source_files``, by path and content): results of
    other code are rerun."""
    return digest(source_files())


def all_sources_version() -> str:
    """Hash of every module of ``SOURCE_PACKAGES``, the report-only ones included: what a worker computing
    for this process (a scene, a task, a roughness reading's surface) must share with it."""
    root = Path(__file__).resolve().parent.parent
    return digest(sorted((p for pkg in SOURCE_PACKAGES for p in (root / pkg).rglob("*.py")),
                         key=lambda p: p.relative_to(root).as_posix()))


def digest(files) -> str:
    """Hash of ``files`` (paths below the repository's root, in the given order) by path and content."""
    root = Path(__file__).resolve().parent.parent
    h = hashlib.sha256()
    for p in files:
        h.update(Path(p).relative_to(root).as_posix().encode())
        h.update(Path(p).read_bytes())
    return h.hexdigest()[:16]


def refuse_other_sources(here: str, caller: str) -> None:
    """RuntimeError where a worker's sources (``here``) are not the caller's: its results would be stored
    under the caller's keys."""
    if here != caller:
        from common.executors import worker_id

        raise RuntimeError(f"worker {worker_id()} runs other sources (hash {here}) than the caller ({caller}): "
                           "install the same version of the project on every worker")
