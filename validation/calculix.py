"""CalculiX (``ccx``) as an independent witness of the axisymmetric normal contact of ``fem normal``.

The same finite bodies as ``fem.axisym.normal_run.run_normal`` (resolved ``meshes.AxisymMeshParams``: a spherical cap
of radius R and height ``indenter_height`` on a cylindrical block of radius and height ``block_size``,
both given here in units of the Hertz contact radius a_ref) are meshed anew with gmsh as 8-node
quadrilaterals (CAX8, the few triangles left by the recombination as CAX6; midside nodes on the
exact sphere), written as a CalculiX input deck and solved by ``ccx``. Nothing of the project's
solver is used on the CalculiX side: not its mesh, its pairing, its condensation nor its contact
algorithm. Only the geometry parameters and the two post-processing formulas named in
``validation.calculix_run`` are shared.

The witness in its steps, one module each (all their public names are importable from here):

- ``validation.calculix_mesh``: the bodies (``Geometry``) and their CAX8/CAX6 mesh (``build_quad_mesh``);
- ``validation.calculix_deck``: the input deck (``write_inp``): the model, its boundary conditions and
  load steps, and the facts about CalculiX 2.20 it relies on;
- ``validation.calculix_results``: reading ``ccx``'s output files (``parse_dat``, ``parse_frd``) and the
  Hertz fit of a nodal pressure (``fit_hertz``);
- ``validation.calculix_run``: finding and running ``ccx`` (``require_ccx``, ``run_ccx``) and the
  quantities read back;
- this module: the project's side (``run_fem``), the comparison of both codes with their error bars
  (``witness``, ``witness_levels``, ``agrees``, ``table``), the stored five-geometry table
  (``witness_cached``) and ``python -m validation.calculix``.

Error bars (:func:`witness_levels`): each code is run at two mesh levels, ``LEVELS``: (a/40,
grading 0.25, the project's default) and (a/80, grading 0.125), the fine one halving every element
size of the graded mesh (h_min + growth * distance; the far-field cap h_max stays). The bar of a
quantity is |q(fine) - q(coarse)| / |q(fine)|, the change on halving the element size. This change
estimates the error of the coarser level; taking it as the error of the finer one is conservative
for a converging quantity, but it is no bound. Halving the contact size alone is not enough: the
probes sit where the element size is set by the grading (``fem.bulk``), and with block and cap 3 a
the probes' approach of the two codes differed by 4.8e-4 at a/80 with the default grading, against
h-halving bars of 0.4e-4 (CalculiX) and 2.5e-4 (project); grading 0.1 brought the difference to
0.4e-4 (the project's reading moved by 3.8e-4, CalculiX's by 1.3e-4). The bar is a discretisation
bar only: it says nothing about modelling errors both codes share (small strain, linear elasticity,
the geometry). CalculiX's penalty error is not removed (no augmented Lagrangian) and a bar at a fixed
penalty factor does not see it; its size is estimated as ``penalty_error`` = p0 / K / approach (the
largest penetration relative to the approach: 4e-5 at a/80) and added by the tests.
"""
from __future__ import annotations

import dataclasses
import math
import shutil
import subprocess
import sys
import tempfile

import numpy as np

from common.errors import ConvergenceError, InputError
from common.io import check_output_path, write_json
from fem.axisym.normal_run import run_normal
from meshes import AxisymMeshParams

from .calculix_deck import MM, PENALTY_DEFAULT, write_inp
from .calculix_mesh import H_DEFAULT, Geometry, QuadMesh, build_quad_mesh
from .calculix_results import FIT_WINDOW, fit_hertz, parse_dat, parse_frd
from .calculix_run import (CCX_NAMES, INSTALL_HINT, SECTOR, TIMEOUT_DEFAULT, MissingDependency, ccx_executable,
                           require_ccx, run_ccx)

#: the public names of the witness, those of its step modules among them
__all__ = ["CCX_NAMES", "COMPARED", "FIT_WINDOW", "GEOMETRIES", "GROWTH_DEFAULT", "H_DEFAULT", "INSTALL_HINT",
           "LEVELS", "MM", "PENALTY_DEFAULT", "SECTOR", "TIMEOUT_DEFAULT", "Geometry", "MissingDependency",
           "QuadMesh", "agrees", "build_quad_mesh", "ccx_executable", "fit_hertz", "main", "parse_dat",
           "parse_frd", "require_ccx", "run_ccx", "run_fem", "table", "witness", "witness_cached",
           "witness_levels", "write_inp"]

#: the five (block, cap) sizes in units of the contact radius a_ref
GEOMETRIES = ((200.0, 200.0), (10.0, 200.0), (10.0, 10.0), (3.0, 200.0), (3.0, 3.0))
#: the project's far-field grading (element size h_min + growth * distance from the contact)
GROWTH_DEFAULT = AxisymMeshParams.growth
#: the two mesh levels (h / a_ref, growth) of the error bars: the fine one halves every graded size
LEVELS = ((1.0 / 40.0, GROWTH_DEFAULT), (1.0 / 80.0, GROWTH_DEFAULT / 2.0))


# --------------------------------------------------------------------------- the project's side


def run_fem(geometry: Geometry, h: float = H_DEFAULT, *, cache_dir=None) -> dict:
    """The project's ``fem.axisym.normal_run.run_normal`` for the same bodies at contact size h * a_ref, with the
    quantities of :func:`run_ccx` (``fit_p0`` / ``fit_contact_radius``: the same p^2 fit applied to the
    project's nodal pressure). ``cache_dir`` None: a fresh directory, so the runtime includes meshing."""
    import warnings

    tmp = None
    if cache_dir is None:
        tmp = cache_dir = tempfile.mkdtemp(prefix="ccx-witness-fem-")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # coarse-mesh notice at h > a/10
            o = run_normal("sphere", R=geometry.R, F=geometry.F, materials=geometry.materials, h_contact=h,
                           cache_dir=cache_dir, **geometry.run_kwargs())
    finally:
        if tmp is not None:
            shutil.rmtree(tmp, ignore_errors=True)
    r, pres = np.asarray(o["pressure"]["r"]), np.asarray(o["pressure"]["p"])
    fit = fit_hertz(r, pres, geometry.a_ref)
    return {"approach": o["approach"], "probe_approach": o["probe"]["u_block"] - o["probe"]["u_indenter"],
            "indentation": o["indentation"], "p0": o["p0"], "contact_radius": o["contact_radius"],
            "fit_p0": fit["p0"], "fit_contact_radius": fit["a"], "fit": fit,
            "probe_depth": o["probe"]["z0"], "dofs": o["dofs"], "node_spacing": 0.5 * h * geometry.a_ref, "h": h,
            "runtime_s": o["runtime_s"]}


# --------------------------------------------------------------------------- both codes compared


#: quantities compared; for p0 and the contact radius the CalculiX fit is compared with the same fit
#: of the project's pressure (``like``) and with the project's own values (``own``)
COMPARED = {"approach": "approach", "probe_approach": "probe_approach", "indentation": "indentation",
            "p0": "fit_p0", "contact_radius": "fit_contact_radius",
            "p0_own": "p0", "contact_radius_own": "contact_radius"}


def witness(geometry: Geometry, h: float = H_DEFAULT, **kw) -> dict:
    """Both codes on ``geometry`` at contact size h * a_ref (and the grading ``geometry.growth``):
    ``calculix`` (:func:`run_ccx`), ``fem`` (:func:`run_fem`), ``diff`` {quantity: (CalculiX -
    project) / project} (``COMPARED``) and ``runtime_ratio`` (CalculiX total / project total).
    Keywords go to :func:`run_ccx` (``cache_dir`` to :func:`run_fem`)."""
    cache_dir = kw.pop("cache_dir", None)
    c = run_ccx(geometry, h, **kw)
    f = run_fem(geometry, h, cache_dir=cache_dir)
    diff = {q: (c[q.replace("_own", "")] - f[k]) / f[k] for q, k in COMPARED.items()}
    return {"geometry": {"block": geometry.block, "cap": geometry.cap, "R": geometry.R, "F": geometry.F,
                         "a_ref": geometry.a_ref},
            "h": h, "growth": geometry.params(h).growth, "calculix": c, "fem": f, "diff": diff,
            "runtime_ratio": c["runtime_s"]["total"] / f["runtime_s"]["total"]}


def witness_levels(geometry: Geometry, levels=LEVELS, **kw) -> dict:
    """:func:`witness` at each mesh level (h, growth) of ``levels``, coarse to fine (``growth`` None:
    the project's default). Returns ``levels`` and, for every compared quantity, the finest level's
    relative difference ``diff`` and the two codes' error bars ``bar_calculix``, ``bar_fem``
    (relative change between the two finest levels; module docstring)."""
    if len(levels) < 2:
        raise InputError(f"levels needs at least two (h, growth) mesh levels (coarse, fine), got {levels!r}")
    runs = [witness(dataclasses.replace(geometry, growth=g), h, **kw) for h, g in levels]
    fine, coarse = runs[-1], runs[-2]
    out = {}
    for q, k in COMPARED.items():
        qc = q.replace("_own", "")
        out[q] = {"diff": fine["diff"][q],
                  "bar_calculix": abs(fine["calculix"][qc] - coarse["calculix"][qc]) / abs(fine["calculix"][qc]),
                  "bar_fem": abs(fine["fem"][k] - coarse["fem"][k]) / abs(fine["fem"][k])}
    return {"geometry": fine["geometry"], "levels": [[r["h"], r["growth"]] for r in runs], "runs": runs,
            "compare": out}


def table(results) -> str:
    """Plain-text table of :func:`witness_levels` results (one block of rows per geometry)."""
    rows = []
    for res in results:
        g = res["geometry"]
        fine, coarse = res["runs"][-1], res["runs"][-2]
        tc, tf = (fine["calculix"]["runtime_s"]["total"], coarse["calculix"]["runtime_s"]["total"]), \
            (fine["fem"]["runtime_s"]["total"], coarse["fem"]["runtime_s"]["total"])
        rows.append(f"block {g['block']:g} a, cap {g['cap']:g} a: fine a/{1 / fine['h']:.3g} growth "
                    f"{fine['growth']:g}, coarse a/{1 / coarse['h']:.3g} growth {coarse['growth']:g}; runtime fine "
                    f"(coarse): CalculiX {tc[0]:.1f} s ({tc[1]:.1f} s), fem {tf[0]:.2f} s ({tf[1]:.2f} s), "
                    f"ratio {fine['runtime_ratio']:.0f} ({coarse['runtime_ratio']:.0f}); "
                    f"CalculiX penalty error {fine['calculix']['penalty_error']:.1e}")
        for q, k in COMPARED.items():
            c = res["compare"][q]
            qc = q.replace("_own", "")
            rows.append(f"  {q:20s} ccx {fine['calculix'][qc]:.7g}  fem {fine['fem'][k]:.7g}  diff {c['diff']:+.2e}  "
                        f"bar ccx {c['bar_calculix']:.1e}  bar fem {c['bar_fem']:.1e}")
    return "\n".join(rows)


def agrees(res) -> dict:
    """Per compared quantity of a :func:`witness_levels` result: whether the two codes agree within
    both error bars (|diff| <= bar_calculix + bar_fem + the CalculiX penalty error), or None where a
    number is missing."""
    fine = (res.get("runs") or [{}])[-1]
    pen = (fine.get("calculix") or {}).get("penalty_error") or 0.0
    out = {}
    for q, c in (res.get("compare") or {}).items():
        nums = (c.get("diff"), c.get("bar_calculix"), c.get("bar_fem"))
        out[q] = None if any(x is None or not math.isfinite(x) for x in nums) else \
            bool(abs(nums[0]) <= nums[1] + nums[2] + pen)
    return out


# --------------------------------------------------------------------------- the five geometries


def witness_cached(out, log=print, force: bool = False, levels=LEVELS) -> list:
    """The five geometries (``GEOMETRIES``) through :func:`witness_levels`, stored in
    ``out/witness_calculix.json`` per code version (``validation.store.cached``: a rerun with unchanged
    code reads them back, unless ``force``): ``python -m validation.compare --witness``. Needs ccx
    (``require_ccx``)."""
    from pathlib import Path

    from .store import cached

    def compute():
        require_ccx()
        results = []
        for block, cap in GEOMETRIES:
            log(f"  CalculiX witness: block {block:g} a, cap {cap:g} a (two mesh levels, about half a minute)")
            try:
                results.append(witness_levels(Geometry(block, cap), tuple(levels)))
            except (ConvergenceError, RuntimeError, subprocess.SubprocessError, OSError) as e:
                # one geometry that fails is reported as such (undetermined in the report); the others go on
                log(f"  CalculiX witness FAILED for block {block:g} a, cap {cap:g} a: {type(e).__name__}: {e}")
                results.append({"geometry": {"block": block, "cap": cap}, "error": f"{type(e).__name__}: {e}",
                                "runs": [], "compare": {}})
        return results

    return cached(Path(out) / "witness_calculix.json", "results", compute, what="CalculiX witness", force=force,
                  log=log)


def _level(text):
    h, _, g = text.partition(":")
    return float(h), (float(g) if g else None)


def main(argv=None) -> int:
    """``python -m validation.calculix [--levels H:GROWTH ...] [--json PATH]``: the five geometries,
    table to stdout (about 5 min of CalculiX at the default levels)."""
    from common.cli import OneLineParser

    ap = OneLineParser(prog="python -m validation.calculix", description=__doc__.splitlines()[0])
    ap.add_argument("--levels", type=_level, nargs="+", default=list(LEVELS), metavar="H[:GROWTH]",
                    help="mesh levels coarse to fine: contact size / a and far-field grading (default "
                         + " ".join(f"{h:g}:{g:g}" for h, g in LEVELS) + ")")
    ap.add_argument("--json", default=None, help="write the full results to this JSON file")
    ap.add_argument("--threads", type=int, default=1, help="ccx threads (default 1)")
    args = ap.parse_args(argv)
    try:
        require_ccx()
        if args.json and args.json != "-":
            check_output_path(args.json, "--json")
    except (MissingDependency, InputError) as exc:
        sys.stderr.write(f"python -m validation.calculix: error: {exc}\n")
        return 2
    results = []
    for block, cap in GEOMETRIES:
        results.append(witness_levels(Geometry(block, cap), tuple(args.levels), threads=args.threads))
        print(table(results[-1:]), flush=True)
    if args.json:
        write_json(args.json, results)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
