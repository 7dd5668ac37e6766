"""The benchmark table of docs/speed.md: each model's cost against its error, beside its peer, in one run.

    python benchmarks/bench_table.py [--write] [--no-calculix] [--json PATH]

Every row is measured in this run on this machine (medians where a case is repeated), so its ratio
compares two codes under the same load of the machine; the absolute seconds move with the machine,
the ratios much less. Rows:

1. **MDR law** (compiled, ``MDRContact.run``) against the simplest MDR, a plain numpy loop over point
   springs (``bench_mdr_kernel.plain_loop``): the truncated sphere b = 20 um under Table 2's loading,
   displacement control, 3 cycles of 400 steps; each at the smallest size whose last cycle's
   dissipation is within 2e-6 of its own 16000-cell reference on the same steps.
2. **Axisymmetric FE normal contact** against **CalculiX** (``validation.calculix.witness``: the same
   bodies, 200 contact radii, meshed and solved independently) at a/80: the contact radius of each
   (the same p^2 fit of its nodal pressure) against Hertz's, and the whole run's wall time (meshing
   included: a fresh cache).
3. **The stick radius at Q = mu F / 2** (sphere R = 6 mm, 0.5 N, mu = 0.2) by the axisymmetric FE
   model at a/80 (set-up plus two cycles of 100 steps, the mesh cached) against the **FFT boundary
   elements** of this project's half-space engine (``rough.tangential``, Mindlin's traction along x on
   a window without periodic images, Hertz's pressure as pixel means; two cycles of 40 steps) at
   a/16 and a/32, both against Cattaneo-Mindlin.
4. **The 3D sphere** (``python -m fem contact --model 3d``, the a/7 mesh with its slip ring at a/14,
   ``--ring 0.9 0.18 0.0714``; 3 cycles of 100 steps at Q = mu F / 2): from a cold cache (meshing,
   condensation) and warm (both read back), the stationary dissipation against the half-space answer
   without Mindlin's assumption, 0.9957 of Mindlin-Deresiewicz (an independent boundary-element ladder,
   -0.43 +- 0.01 %; this project's half-space engine -0.42 +- 0.02 %, docs/rough.md).
5. **The 3D sphere paired** (``--paired``, ``fem.contact_run.paired_keys``): the run of row 4 and its twin with
   the traction along x on the same set-up, in lockstep, and MDR on the same loading (exact in the half space
   under Mindlin's assumption): MDR's dissipation times free / twin, in which the error the two 3D runs share
   cancels; from a cold cache of its own and warm, against the same half-space answer.
6. **A dissimilar pair**: the sphere of row 4 on an aluminium block (beta = +0.11, the coupled
   normal-tangential increments of ``fem.solid3d.contact.solve_coupled3d``) against the identical pair on
   the same mesh, both warm: the ratio is the coupling's cost (the goal: at most 2x).

``--write`` replaces the generated table in docs/speed.md (between its ``bench_table`` markers);
``--no-calculix`` leaves out row 2 where ``ccx`` is not installed (``apt-get install calculix-ccx``).
Timings are never asserted by tests; the errors beside them are the models' own (each named in the
test suite where the docs state it).
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))  # run from a checkout without installing

from bench_mdr import median_time  # noqa: E402  (this directory is on sys.path when run as a script)
from mdr import reference as ref  # noqa: E402
from mdr.materials import Materials  # noqa: E402

DOC = ROOT / "docs" / "speed.md"
BEGIN = "<!-- generated: bench_table (python benchmarks/bench_table.py --write) -->"
END = "<!-- end generated -->"
MAT = Materials()
R, F, MU = 6e-3, 0.5, 0.2
#: the half-space answer of the 3D sphere without Mindlin's assumption: the dissipation over
#: Mindlin-Deresiewicz's (an independent boundary-element ladder: -0.43 +- 0.01 %)
HALF_SPACE_TURNING = 1.0 - 0.43e-2
#: the 3D sphere's mesh: h = a/7, the slip ring (r = 0.9 a, +- 0.18 a) at a/14
MESH_3D = ("--h-contact", "0.142857", "--ring", "0.9", "0.18", "0.0714")


def row(model, case, size, cost, error, peer=None, peer_size=None, peer_cost=None, peer_error=None):
    return {"model": model, "case": case, "size": size, "cost_s": cost, "error": error, "peer": peer,
            "peer_size": peer_size, "peer_cost_s": peer_cost, "peer_error": peer_error,
            "ratio": (peer_cost / cost) if peer_cost and cost else None}


def mdr_against_springs() -> dict:
    """Row 1: the compiled law against the plain spring loop at equal error (``bench_mdr_kernel``)."""
    import bench_mdr_kernel as bk

    ref_law = bk.dissipation(bk.law(16000).run(u=bk.U, F_N=bk.FN).Fx)
    ref_plain = bk.dissipation(bk.plain_loop(16000))
    found = {}
    for kind, sizes in (("law", (100, 200, 400, 800)), ("plain", (250, 500, 1000, 2000, 4000))):
        for n in sizes:
            if kind == "law":
                lw = bk.law(n)
                err = bk.dissipation(lw.run(u=bk.U, F_N=bk.FN).Fx) / ref_law - 1
                fun = lambda lw=lw: lw.run(u=bk.U, F_N=bk.FN)  # noqa: E731
            else:
                err = bk.dissipation(bk.plain_loop(n)) / ref_plain - 1
                fun = lambda n=n: bk.plain_loop(n)  # noqa: E731
            if abs(err) <= 2e-6:
                found[kind] = (n, err, median_time(fun, 9 if kind == "law" else 3))
                break
    (n_l, e_l, t_l), (n_p, e_p, t_p) = found["law"], found["plain"]
    return row("MDR law, compiled", "truncated sphere b = 20 um, Table 2, 3 x 400 steps, dW of the last cycle "
               "within 2e-6 of 16000 cells", f"{n_l} cells", t_l, e_l,
               "plain numpy loop over point springs", f"{n_p} springs", t_p, e_p)


def fe_against_calculix() -> dict:
    """Row 2: the axisymmetric normal contact against CalculiX at a/80 (``validation.calculix``)."""
    from validation.calculix import witness
    from validation.calculix_mesh import Geometry

    g = Geometry()
    w = witness(g, 1.0 / 80)
    a = float(ref.hertz(g.F, g.R, g.materials.E_star)["a"])
    f, c = w["fem"], w["calculix"]
    return row("axisymmetric FE, normal contact", "sphere R = 6 mm, 0.5 N, bodies of 200 a, a/80: the contact "
               "radius (p^2 fit) against Hertz's; the run from meshing", f"{f['dofs']} DOFs",
               f["runtime_s"]["total"], f["fit_contact_radius"] / a - 1,
               "CalculiX (ccx, CAX8)", "a/80", c["runtime_s"]["total"], c["contact_radius"] / a - 1)


def stick_radius_fe_against_fft() -> list:
    """Row 3: the stick radius at Q = mu F / 2 by the axisymmetric FE model and the FFT engine."""
    from fem.axisym.law import FEContact
    from mdr.profiles import make_profile
    from rough.normal import Grid
    from rough.tangential import TangentialContact, run_force_cycles, stick_radius

    h = ref.hertz(F, R, MAT.E_star)
    FA = 0.5 * MU * F
    c_ref = float(ref.cattaneo_mindlin_stick_radius(FA, F, MU, h["a"]))
    cache = tempfile.mkdtemp(prefix="bench_table_fe_")
    n = 100
    t = np.arange(2 * n + 1) / n
    fx = FA * np.sin(2 * np.pi * t)
    kw = dict(F_max=F, h_contact=1.0 / 80, cache_dir=cache)
    prof = make_profile("sphere", R)
    FEContact(prof, MAT, MU, **kw)  # the mesh into the cache
    t0 = time.perf_counter()
    law = FEContact(prof, MAT, MU, **kw)
    H = law.run(Fx=fx, F_N=np.full(t.size, F))
    t_fe = time.perf_counter() - t0
    e_fe = float(H.c[n + n // 4]) / c_ref - 1
    rows = []
    for per_a in (16, 32):
        t0 = time.perf_counter()
        pixel = float(h["a"]) / per_a
        m = int(np.ceil(2.1 * per_a)) + 2
        grid = Grid(m * pixel, m)
        p = grid.cell_mean(lambda r: ref.hertz_pressure(r, F, R, MAT.E_star))
        tc = TangentialContact(grid, MAT, MU, periodic=False)
        out = run_force_cycles(tc, p, MU * 0.5 * float(p.sum()) * grid.pixel ** 2, cycles=2, steps=40)
        c = stick_radius(out["peak"].q, p, MU, grid.radii())
        t_be = time.perf_counter() - t0
        rows.append(row("axisymmetric FE, tangential", "sphere at Q = mu F / 2: the stick radius against "
                        "Cattaneo-Mindlin; set-up and 2 cycles (mesh cached)", f"a/80, {law.dofs} DOFs", t_fe,
                        e_fe, "FFT boundary elements (rough.tangential)", f"a/{per_a}, {m}^2 pixels", t_be,
                        (c / c_ref - 1) if c else None))
    return rows


def _fem_3d(cache, *flags) -> tuple:
    """``python -m fem contact --model 3d`` on the sphere of rows 4-6 (``flags``: more flags, another pair's
    materials or ``--paired``): (wall time in s, the result's JSON)."""
    with tempfile.TemporaryDirectory() as tmp:
        js = Path(tmp) / "out.json"
        cmd = [sys.executable, "-m", "fem", "contact", "--model", "3d", "--profile", "sphere", "--R", str(R),
               "--mu", str(MU), "--F0", str(F), "--dF", "0", "--fa", str(0.5 * MU * F), "--cycles", "3",
               "--steps", "100", *MESH_3D, *flags, "--cache-dir", cache, "--json", str(js)]
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)},
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return time.perf_counter() - t0, json.loads(js.read_text())


def sphere_3d() -> list:
    """Rows 4-6: the 3D sphere from a cold and a warm cache (``python -m fem contact --model 3d``), the same
    paired with its twin along x (cold and warm), and the same sphere on an aluminium block (Dundurs'
    beta = +0.11: the coupled normal-tangential increments) on the same mesh, warm, beside the identical
    pair's warm run."""
    us = ref.gross_slip_displacement(ref.hertz(F, R, MAT.E_star)["d"], MU, MAT.E_star, MAT.G_star)
    W_md = float(ref.mindlin_deresiewicz_dissipation_force(0.5 * MU * F, F, MU, us))
    cache = tempfile.mkdtemp(prefix="bench_table_3d_")
    out = []
    for label in ("cold cache", "warm cache"):
        wall, d = _fem_3d(cache)
        out.append(row("3D FE, two-component traction", f"sphere at Q = mu F / 2, 3 cycles of 100 steps, {label}: "
                       "the dissipation against the half-space answer (0.9957 of Mindlin-Deresiewicz)",
                       f"a/7, ring a/14, {d['dofs']} DOFs", wall, d["dissipation"] / W_md / HALF_SPACE_TURNING - 1))
    paired_cache = tempfile.mkdtemp(prefix="bench_table_3d_paired_")
    for label in ("cold cache", "warm cache"):
        wall, d = _fem_3d(paired_cache, "--paired")
        out.append(row("3D FE, paired with its twin along x (--paired)", f"the sphere above, {label}: the run, its twin "
                       "along x on the same set-up, MDR; MDR's dissipation x free / twin against the half-space answer",
                       f"a/7, ring a/14, {d['dofs']} DOFs, two runs", wall,
                       d["paired"]["dissipation"] / W_md / HALF_SPACE_TURNING - 1))
    alu = ("--E2", "70e9", "--nu2", "0.33")
    _fem_3d(cache, *alu)  # the aluminium block's condensed interface, into the cache
    wall_alu, d_alu = _fem_3d(cache, *alu)
    wall_steel, d_steel = _fem_3d(cache)
    out.append(row("3D FE, dissimilar pair (coupled increments)", "the sphere above on an aluminium block "
                   "(beta = +0.11), warm cache: the cost of the normal-tangential coupling",
                   f"a/7, ring a/14, {d_alu['dofs']} DOFs", wall_alu, None, "the same sphere on steel, warm",
                   f"{d_steel['dofs']} DOFs", wall_steel, d_steel["dissipation"] / W_md / HALF_SPACE_TURNING - 1))
    return out


def _num(x, fmt):
    return "-" if x is None or not np.isfinite(x) else format(x, fmt)


def markdown(rows) -> list:
    lines = ["| model | case | size | time (s) | error | peer | peer's size | peer's time (s) | peer's error "
             "| peer's time / ours |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['model']} | {r['case']} | {r['size']} | {_num(r['cost_s'], '.3g')} | "
                     f"{_num(r['error'], '+.2e')} | {r['peer'] or '-'} | {r['peer_size'] or '-'} | "
                     f"{_num(r['peer_cost_s'], '.3g')} | {_num(r['peer_error'], '+.2e')} | "
                     f"{_num(r['ratio'], '.3g')} |")
    return lines


def write_doc(lines, path=DOC) -> None:
    """The generated block of ``path`` replaced by ``lines`` (the rest of the page kept; written whole)."""
    text = path.read_text()
    if BEGIN not in text or END not in text.split(BEGIN, 1)[1]:
        raise SystemExit(f"{path}: no generated block ({BEGIN} ... {END})")
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    tmp = path.with_suffix(".md.tmp")
    tmp.write_text(head + BEGIN + "\n" + "\n".join(lines) + "\n" + END + tail)
    tmp.replace(path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--write", action="store_true", help="replace the generated table of docs/speed.md")
    ap.add_argument("--no-calculix", action="store_true", help="leave out the CalculiX row")
    ap.add_argument("--json", default=None, help="also write the rows to this JSON file")
    args = ap.parse_args(argv)
    rows = []
    steps = [("MDR law against the spring loop", lambda: [mdr_against_springs()])]
    if not args.no_calculix:
        steps.append(("axisymmetric FE against CalculiX", lambda: [fe_against_calculix()]))
    steps += [("stick radius: FE against the FFT boundary elements", stick_radius_fe_against_fft),
              ("the 3D sphere, cold and warm, paired, and on aluminium", sphere_3d)]
    for label, fun in steps:
        t0 = time.perf_counter()
        print(f"{label} ...", file=sys.stderr, flush=True)
        rows += fun()
        print(f"  {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
    lines = markdown(rows)
    print("\n".join(lines))
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    if args.write:
        write_doc(lines)
    return 0


if __name__ == "__main__":
    sys.exit(main())
