"""Hard cases of issue 7: numerical stability of the MDR and FE contact models, each held
against an independent truth (closed forms of ``mdr.reference``, energy conservation,
refinement), one row per case for the report's "hard cases" table.

``hard_cases(quick=True)`` returns rows with keys

- ``name``, ``model`` ("mdr", "fem" or "fem3d", the 3D half model),
- ``status``: "ok" (error within the case's tolerance ``tol``), "flagged" (the model
  itself warned or reported the case as doubtful: e.g. a too soft penalty, a too coarse
  mesh; or the error is above ``tol``), "error" (an exception: ``note`` holds it),
- ``iterations``: Newton (active-set) iterations per step of the FE friction solver
  (``FEContact.stats``) or of the normal solve, ``None`` where not applicable (MDR is
  explicit),
- ``error``: the row's own measured error against ``truth`` (a text naming it), a real
  number (relative unless the truth says otherwise), or ``None`` when the case produced no
  number (a detected ``ConvergenceError``: ``note`` says so); the pass/fail is ``status``,
  never a 0/1 stored as an error,
- ``tol`` (the row's tolerance, 2-3x the error measured when it was set, for ``quick``
  and for the full table separately), ``time_s``, ``note``.

Every case is a function ``case_*(quick, cache_dir) -> list[row]`` so the tests
(``tests/test_hard_cases.py``) can run them one by one. ``quick`` uses coarse meshes and
few steps (the whole quick table takes well under a minute on 2 cores); ``quick=False``
refines (finer meshes, the a/320 mesh, 50 FE cycles).

This module holds the table: the cases in order (``CASES``), their run (``hard_cases``), its
store per code version and ``python -m validation.hard_cases [--full]``. The cases live beside it,
one module per subject, and are importable from here as well:

- ``validation.hard_cases_base``: the scene (steel, R, F, mu: the assumptions), the row, the
  shared loop measures and truths,
- ``validation.hard_cases_profiles``: flat punch, truncated sphere,
- ``validation.hard_cases_loading``: gross slip over many cycles, vanishing normal force,
  friction extremes, apparatus stiffness,
- ``validation.hard_cases_numerics``: penalty extremes, near-incompressible bodies, mesh
  extremes, the 3D model.
"""
from __future__ import annotations

import time
import traceback

from .hard_cases_base import (F, MU, R, ROUNDOFF, STEEL, TOL_INCOMPRESSIBLE, TOL_MD_FORCE, TRUTH_MD_FORCE,
                              _harmonic, _row, _u_star)
from .hard_cases_loading import (case_apparatus_stiffness, case_friction_extremes, case_gross_slip_many_cycles,
                                 case_vanishing_contact)
from .hard_cases_numerics import case_3d, case_incompressible, case_mesh_extremes, case_penalty_extremes
from .hard_cases_profiles import case_flat_punch, case_truncated_edge

#: the public names, the cases' among them; with three helpers of ``validation.hard_cases_base``
#: that the tests reach through this module (``_harmonic``, ``_row``, ``_u_star``)
__all__ = ["CASES", "MU", "ROUNDOFF", "STEEL", "TOL_INCOMPRESSIBLE", "TOL_MD_FORCE", "TRUTH_MD_FORCE", "F", "R",
           "_harmonic", "_row", "_u_star", "case_3d", "case_apparatus_stiffness", "case_flat_punch",
           "case_friction_extremes", "case_gross_slip_many_cycles", "case_incompressible",
           "case_mesh_extremes", "case_name", "case_penalty_extremes", "case_truncated_edge",
           "case_vanishing_contact", "hard_cases", "hard_cases_cached", "stored_hard_cases"]


CASES = (case_flat_punch, case_truncated_edge, case_gross_slip_many_cycles, case_vanishing_contact,
         case_friction_extremes, case_penalty_extremes, case_incompressible, case_apparatus_stiffness,
         case_mesh_extremes, case_3d)


def case_name(case) -> str:
    """The table name of a case function: ``case_flat_punch`` -> "flat punch"."""
    return case.__name__.removeprefix("case_").replace("_", " ")


def hard_cases(quick: bool = True, cache_dir=None, log=None) -> list[dict]:
    """Run every hard case; one row per case and model (see the module docstring). A case
    that raises becomes a row with status "error" and the exception in ``note``. ``log``:
    a callable called once per case with its name (``case_name``) before it runs, for
    progress output (default: none), e.g. ``log=lambda s: print(s, file=sys.stderr)``."""
    rows = []
    for case in CASES:
        if log is not None:
            log(case_name(case))
        t0 = time.perf_counter()
        try:
            rows += case(quick, cache_dir)
        except Exception as exc:  # a hard case must report, not abort the table
            rows.append({"name": case_name(case), "model": "-",
                         "status": "error", "iterations": None, "error": None, "tol": None, "truth": "",
                         "time_s": time.perf_counter() - t0,
                         "note": f"{type(exc).__name__}: {exc}".splitlines()[0][:300],
                         "traceback": traceback.format_exc(limit=3)})
    return rows


def _hard_cases_path(out, quick: bool):
    from pathlib import Path

    return Path(out) / ("hard_cases_quick.json" if quick else "hard_cases.json")


def stored_hard_cases(out, quick: bool):
    """The hard-cases table a previous run stored in ``out``: ``(rows, code version)``, or ``(None, None)``."""
    from .store import stored

    return stored(_hard_cases_path(out, quick), "rows")


def hard_cases_cached(out, quick: bool, log=print, force: bool = False):
    """Rows of :func:`hard_cases`, stored in ``out`` per code version (``validation.store.cached``: a
    rerun with unchanged code reads them back, unless ``force``); ``log`` reports each phase and case."""
    from .store import cached

    def compute():
        log(f"hard cases ({'quick' if quick else 'full'}) ...")
        t0 = time.perf_counter()
        rows = hard_cases(quick=quick, log=lambda name: log(f"  hard case: {name}"))
        log(f"hard cases done in {time.perf_counter() - t0:.0f} s")
        return rows

    return cached(_hard_cases_path(out, quick), "rows", compute, what="hard cases", force=force, log=log)


if __name__ == "__main__":  # pragma: no cover
    import sys

    for r in hard_cases(quick="--full" not in sys.argv, log=lambda s: print(f"[{s}]", file=sys.stderr, flush=True)):
        err = "-" if r["error"] is None else f"{r['error']:.2e}"
        it = "-" if r["iterations"] is None else f"{r['iterations']:.3g}"
        print(f"{r['status']:8s} {r['model']:4s} {r['name'][:55]:55s} err {err:9s} it {it:5s} "
              f"{r['time_s']:6.2f}s  {r['note']}")
