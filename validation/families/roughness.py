"""The family ``roughness``: the sphere or the truncated sphere on self-affine rough surfaces (the
combined roughness of both bodies) through three models side by side (``rough.equivalent.mdr_against_rough``): the rough
half-space (FFT boundary elements, then Coulomb friction cell by cell with memory), MDR with
the equivalent profile of each surface's own normal force-approach curve, and MDR with the smooth
profile, the paper's model.

One answer per variant (an rms height): the ensemble of its realisations (``seeds``), each on a
ladder of grids (``grids``) that refine one band-limited surface (generated on the coarsest grid and
resampled spectrally, ``rough.surfaces.resample``), so that each member's difference carries the
grid's error bar and the ensemble its spread. The verdict of an MDR model on a quantity is the rule of
every family (``validation.metrics.grade``): |mean difference| against the ensemble's standard error
plus the mean grid error plus the catalogue's tolerance; an ensemble's spread is no upper bound, so a
rough variant is at best "consistent within its spread".

Each (variant, seed, grid) is a task of its own (``tasks``, ``member``): ``validation.compare``
spreads them over ``--jobs`` processes or a ``--scheduler``'s workers and reduces them here (``run``
with ``members``).

A variant of measured surfaces: ``maps`` (paths of square height maps, ``.npy`` or a plain-text grid,
one per realisation, at least 2) with their ``pixel`` size (m); the grid is the maps' own (its side their
side, its coarsest level their pixels, finer levels resampled).

The indenter: the scene's sphere or truncated sphere; a variant's ``b`` (m) sets the face radius (0: the
sphere), so one scene holds the faces of several results (``roughness-faces``).

Surface parameters (a variant's keys, checked and converted once by
``validation.rough_variant.RoughVariant``, defaults ``DEFAULTS`` there): ``rms`` (m; 0 is the smooth indenter),
``hurst`` (0.8: most engineering surfaces, ground and turned steel among them, have H = 0.7-0.9;
Persson, Tribology Letters 54 (2014) 99), ``period`` (the grid's side in smooth contact radii of the
scene's load), ``short`` (the short-wavelength cut-off in pixels of the coarsest grid: the surface is
truncated where the grid can resolve it, a modelling choice the result depends on and states),
``long`` (the long-wavelength cut-off as a fraction of the period: no power at longer wavelengths, no roll-off plateau); ``hardness`` (Pa,
optional): perfectly plastic asperities, the pressure capped there (``rough.normal.saturated_pressure``;
the paper's steel: ``rough.normal.HARDNESS_X5CRNI18_10``), flattened by a first loading to ``preload``
(N, at least the scene's F0, default F0; ``rough.equivalent.mdr_against_rough``), elastic after;
``apparatus`` (bool, default false; the paper's R = 6 mm steel indenter only): each member also drives
the rough half-space by the paper's apparatus at the points whose rough contact is its indenter
(``in_apparatus``): what MDR with the equivalent profile misses of it there is the error the budget adds to its roughness readings (``validation.budget_readings.equivalent_error``).
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from common.errors import ConvergenceError, InputError
from common.ladder import ladder_error

from .. import metrics
from ..rough_variant import RoughVariant
from ..scenes import Scene, a_ref
from ..text import grade_text, num
from . import members_of, result_of_members

KEY = "roughness"
TITLE = "roughness"
#: the compared quantities and the catalogue tolerance each is judged by: the stiffness 2 G* a is
#: the contact radius's (relative), the dissipation the dissipation's
QUANTITIES = {"dissipation": "dissipation", "stiffness": "contact_radius"}
MODELS = ("mdr_equivalent", "mdr_smooth")


#: the family's typed variant (its home: ``validation.rough_variant``)
Variant = RoughVariant


def variant(s: Scene, i: int) -> RoughVariant:
    """The scene's i-th variant, checked and converted once (``Scene.typed_variants``)."""
    return s.typed_variants[i]


def tasks(s: Scene) -> list:
    """The scene's independent tasks: one per (variant, seed, grid), the finest grids first (the longest
    first keeps every worker busy to the end)."""
    out = [{"variant": i, "seed": seed, "n": n} for i, v in enumerate(s.typed_variants) for seed in v.seeds
           for n in v.grids]
    return sorted(out, key=lambda t: -t["n"])


def member(s: Scene, task: dict) -> dict:
    """One task of ``tasks``: the three models on one realisation at one grid (plain data)."""
    from rough.equivalent import mdr_against_rough
    from rough.normal import Grid

    from ..sides import materials_of

    t0 = time.perf_counter()
    v = variant(s, task["variant"])
    P, n = v.size, int(task["n"])
    heights = v.heights(task["seed"], n)
    try:
        res = mdr_against_rough(indenter(s, v.b), materials_of(s), s.mu, s.F0, s.amplitude, Grid(P, n), heights,
                                cycles=s.cycles, steps=s.steps, hardness=v.hardness, preload=v.preload)
    except ConvergenceError as e:  # a level without an answer: its seed is undetermined, the scene goes on
        return {**task, "pixel": P / n, "failed": str(e), "runtime_s": time.perf_counter() - t0}
    out = {**task, "pixel": P / n, "rms": 0.0 if heights is None else heights.rms,
           "rough_halfspace": res["rough_halfspace"], "relative": res["relative"],
           "mdr_equivalent": res["mdr_equivalent"], "mdr_smooth": res["mdr_smooth"], "curve": res["curve"]}
    if v.apparatus and n == max(v.grids):  # the finest grid: what the budget reads
        out["apparatus"] = in_apparatus(s, v, Grid(P, n), heights, res["curve"], start=(s.F0, res["pressure"]))
    return {**out, "runtime_s": time.perf_counter() - t0}


def in_apparatus(s: Scene, v: RoughVariant, grid, heights, curve, start=None) -> list:
    """The rough half-space driven by the apparatus at each of the paper's points whose rough contact is
    this indenter (``validation.paper_points.rough_points``), beside MDR with the equivalent profile of
    this surface's curve (``rough_in_apparatus``)."""
    from ..paper_points import rough_points
    from ..sides import materials_of

    return rough_in_apparatus(indenter(s, v.b), materials_of(s), grid, heights, curve, rough_points(v.b),
                              hardness=v.hardness, preload=v.preload, start=start)


def rough_in_apparatus(profile, mat, grid, heights, curve, points, *, hardness=None, preload=None, start=None,
                       app_kw=None) -> list:
    """The rough half-space (``rough.law.RoughContact`` on ``heights``, elastic or perfectly plastic at
    ``hardness`` flattened at ``preload``) driven by the apparatus (``mdr.apparatus.run_apparatus``, each
    point's k_x and mu2 and the fields ``app_kw``, default the project's plates) at each of ``points`` (``validation.paper_points.Point``), beside MDR
    with the equivalent profile of this surface's ``curve`` and with the smooth ``profile`` (materials
    ``mat``), at the budget's resolution (``studies.paper.RES``: 3 cycles of 120 steps; the rough
    half-space's slip index moves by 1e-4 between 60 and 240 steps on the face of b = 0.6 mm): per point
    its fields and each model's slip index (None where the curve ends below the point's largest force); a
    point beyond a plastic surface's flattening load is left out (it would flatten the surface further).
    ``start``: (F, pressure) of a contact of this surface, where its normal solves start."""
    from dataclasses import asdict

    from mdr.apparatus import Apparatus, run_apparatus
    from mdr.equivalent import EquivalentProfile
    from mdr.loading import Loading
    from rough.law import RoughContact
    from studies.paper import RES, _slip_index

    eq = EquivalentProfile(curve["d"], curve["F"], mat)
    laws, out, done = {}, [], {}
    for p in points:
        if hardness and p.F0 + p.dF > preload * (1 + 1e-9):
            continue
        t0 = time.perf_counter()
        row = {"point": asdict(p)}
        key = (p.F0, p.dF, p.ua, p.mu1, p.mu2, p.kx)  # the sphere's points of b = 1 and 10 um are one contact
        if key in done:
            out.append({**done[key], **row, "runtime_s": 0.0})
            continue
        try:
            if p.mu1 not in laws:  # one law per friction, all sharing the normal solves of the first
                laws[p.mu1] = next(iter(laws.values())).with_friction(p.mu1) if laws else \
                    RoughContact(profile, mat, p.mu1, grid, heights, hardness=hardness, preload=preload, start=start)
            loading = Loading.apparatus(p.F0, p.dF, 0.0, p.ua, cycles=RES["cycles"], steps=RES["steps"])
            row["rough_halfspace"] = float(run_apparatus(laws[p.mu1], Apparatus(kx=p.kx, mu2=p.mu2, **(app_kw or {})),
                                                         loading)["slip_index"])
        except (ConvergenceError, InputError) as e:  # that point of the seed is undetermined
            row["failed"] = str(e)
        top = max(curve["F"])
        kw = dict(mu1=p.mu1, mu2=p.mu2, F0=p.F0, dF=p.dF, ua=p.ua, materials=mat, app_kw=app_kw)
        row["mdr_equivalent"] = None if p.F0 + p.dF > top else float(np.ravel(_slip_index(eq, p.kx, **kw)[0])[0])
        row["mdr_smooth"] = float(np.ravel(_slip_index(profile, p.kx, **kw)[0])[0])
        done[key] = row
        out.append({**row, "runtime_s": time.perf_counter() - t0})
    return out


def indenter(s: Scene, b: float):
    """The scene's indenter with the face radius ``b`` (m; 0: the sphere), a ``mdr.profiles`` profile."""
    from mdr.profiles import make_profile

    return make_profile("truncated" if b > 0 else "sphere", s.R, b if b > 0 else None)


def _variant_row(s: Scene, i: int, members: list) -> dict:
    """The reduction of one variant's members: per seed the grid ladder of each relative difference,
    then the ensemble's mean, its standard error and the mean grid error; the verdicts."""
    v = variant(s, i)
    mine = [m for m in members if m["variant"] == i]
    a = a_ref(s, v.b)
    P = v.size
    per_seed = []
    for seed in v.seeds:
        lv = sorted((m for m in mine if m["seed"] == seed), key=lambda m: m["n"])
        if [m["n"] for m in lv] != sorted(v.grids) or any("failed" in m for m in lv):
            per_seed.append(None)  # a missing or failed level: the seed is undetermined
            continue
        sizes = [P / m["n"] for m in lv]
        seed_row = {"seed": seed, "contact_area": lv[-1]["rough_halfspace"]["contact_area"]}
        for mdl in MODELS:
            for q in QUANTITIES:
                vals = [m["relative"][mdl][q] for m in lv]
                # None: the rough half-space's own value is 0 on a level (a face sticking everywhere
                # dissipates nothing), no relative difference: that quantity of the seed is undetermined
                seed_row[mdl, q] = ladder_error(sizes, vals) if all(x is not None for x in vals) else \
                    {"value": None, "error": None, "bounded": False, "status": "zero reference"}
        per_seed.append(seed_row)
    verdicts = {}
    for mdl in MODELS:
        for q, tol_key in QUANTITIES.items():
            lads = [r[mdl, q] for r in per_seed if r is not None]
            values = np.array([x["value"] if x["value"] is not None else np.nan for x in lads], dtype=float)
            grid_errs = [x["error"] for x in lads]
            complete = len(lads) == len(v.seeds) and np.all(np.isfinite(values)) and \
                all(e is not None and np.isfinite(e) for e in grid_errs)
            mean = float(values.mean()) if complete else None
            sem = (float(values.std(ddof=1) / np.sqrt(values.size)) if values.size > 1 else 0.0) if complete else None
            grid = float(np.mean(grid_errs)) if complete else None
            err = None if not complete else sem + grid
            bounded = complete and values.size == 1 and all(x["bounded"] for x in lads)
            holds, g = metrics.grade(mean, err, s.tolerances()[tol_key], bounded=bounded)
            verdicts[f"{mdl}:{q}"] = {"model": mdl, "quantity": q, "difference": mean, "error": err, "sem": sem,
                                      "grid_error": grid, "tolerance": s.tolerances()[tol_key], "holds": holds,
                                      "grade": g, "bounded": bounded,
                                      "members": values.tolist(),
                                      "grid_status": sorted({x["status"] for x in lads})}
    by_grid = {str(n): [m.get("apparatus") for m in sorted(mine, key=lambda m: m["seed"]) if m["n"] == n]
               for n in v.grids[-1:]} if v.apparatus else None
    areas = [r["contact_area"] for r in per_seed if r is not None]
    smooth_area = np.pi * a ** 2  # the smooth indenter's contact (Hertz's on the sphere)
    eq = {q: verdicts[f"mdr_equivalent:{q}"] for q in QUANTITIES}
    measured = v.measured
    rms = (float(np.mean([m["rms"] for m in mine if "rms" in m])) if any("rms" in m for m in mine) else None) \
        if measured else v.rms
    return {"variant": i, "rms": rms, "measured": list(v.maps) if measured else None,
            "hardness": v.hardness, "preload": v.preload,
            "seeds": list(v.seeds), "grids": list(v.grids),
            "period": P, "hurst": v.hurst,
            "lambda_short": v.lambda_short,
            "lambda_long": v.lambda_long,
            "b": v.b, "a_smooth": a,
            "contact_area_over_smooth": float(np.mean(areas)) / smooth_area if areas else None,
            "verdicts": verdicts, **dict(zip(("holds", "grade"), metrics.judged_grade(eq))),
            "curves": [m["curve"] for m in sorted(mine, key=lambda m: m["seed"])
                       if m["n"] == max(v.grids) and "curve" in m],
            "curves_by_grid": {str(n): [m.get("curve") for m in sorted(mine, key=lambda m: m["seed"]) if m["n"] == n]
                               for n in v.grids},
            # the rough half-space in the apparatus (``in_apparatus``): per grid, per seed, its points, and
            # per point the ensemble on the ladder (``apparatus_points``)
            "apparatus_by_grid": by_grid, "apparatus": None if by_grid is None else apparatus_points(by_grid, v, P),
            "failed": [{k: m[k] for k in ("seed", "n", "failed")} for m in mine if "failed" in m]}


def apparatus_points(by_grid: dict, v: RoughVariant, period: float) -> list:
    """Per point run in the apparatus (``in_apparatus``; ``by_grid``: per grid, per seed, the member's
    points; the catalogue runs the finest grid only) the ensemble: the rough half-space's slip index
    (``rough_halfspace``: the mean at the finest grid, its standard error, the grid error of the mean where
    coarser grids ran too, else None with the status ``finest grid only``, ``error`` their sum; None with a
    ``status`` where a seed lacks the point on a grid, failed there, or holds no finite number) and what
    MDR with the equivalent profile misses of it at the finest grid (``equivalent_minus_rough``: mean and
    standard error; None where the curve did not reach the point's force)."""
    from common.ladder import ensemble_ladder

    def number(x):
        return isinstance(x, (int, float)) and not isinstance(x, bool) and np.isfinite(x)

    seeds, grids = list(v.seeds), [n for n in v.grids if str(n) in by_grid]
    points = []
    for runs in by_grid.get(str(grids[-1])) or []:
        for r in runs or []:
            if isinstance(r, dict) and isinstance(r.get("point"), dict) and r["point"] not in points:
                points.append(r["point"])
    out = []
    for pt in points:
        rough, eq, status = [], [], None
        for n in grids:
            level = by_grid.get(str(n))
            if not isinstance(level, list) or len(level) != len(seeds):
                status = "a seed missing"
                break
            hits = [next((r for r in (runs or []) if isinstance(r, dict) and r.get("point") == pt), None)
                    for runs in level]
            if any(h is None or "failed" in h or not number(h.get("rough_halfspace")) for h in hits):
                status = "failed or not run on a seed"
                break
            rough.append([float(h["rough_halfspace"]) for h in hits])
            eq.append([float(h["mdr_equivalent"]) if number(h.get("mdr_equivalent")) else None for h in hits])
        rh, em = {"mean": None, "sem": None, "grid": None, "error": None, "status": status}, None
        if status is None and len(grids) == 1:
            fine = np.asarray(rough[-1])
            sem = float(fine.std(ddof=1) / np.sqrt(fine.size)) if fine.size > 1 else 0.0
            rh = {"mean": float(fine.mean()), "sem": sem, "grid": None, "error": None, "status": "finest grid only"}
        elif status is None:
            mean, sem, grid = ensemble_ladder(rough, [period / n for n in grids])
            rh = {"mean": mean, "sem": sem, "grid": grid, "error": None if grid is None else sem + grid,
                  "status": "measured" if grid is not None else "no grid error"}
        if status is None:
            if all(x is not None for x in eq[-1]):
                diff = np.subtract(eq[-1], rough[-1])
                em = {"mean": float(diff.mean()),
                      "sem": float(diff.std(ddof=1) / np.sqrt(diff.size)) if diff.size > 1 else 0.0}
        smooth = next((h.get("mdr_smooth") for runs in by_grid.get(str(grids[-1])) or [] for h in runs or []
                       if isinstance(h, dict) and h.get("point") == pt and number(h.get("mdr_smooth"))), None)
        out.append({"point": pt, "surfaces": len(seeds), "rough_halfspace": rh, "equivalent_minus_rough": em,
                    "mdr_smooth": smooth})
    return out


def run(s: Scene, out_dir=None, *, fields: bool = True, log=None, members: list | None = None) -> dict:
    """The scene: its tasks run here in turn unless ``members`` (their results, from ``member``) are
    given; then one row per variant (``_variant_row``)."""
    t0 = time.perf_counter()
    log = log or (lambda msg: None)
    members, given = members_of(s, members, tasks, member, log,
                                lambda k, task, m: f"  member {k}: variant {task['variant']}, seed {task['seed']}, "
                                                   f"n = {task['n']} ({m['runtime_s']:.0f} s)")
    rows = [_variant_row(s, i, members) for i in range(len(s.variants))]
    for r in rows:
        d = r["verdicts"]["mdr_equivalent:dissipation"]
        log(f"  {rms_text(r['rms'])}: equivalent MDR's dissipation {num(d['difference'], '+.2%')} "
            f"+- {num(d['error'], '.2%')}: {r['grade']}")
    return result_of_members(s, KEY, rows, t0, out_dir, figure, members, given)


def rms_text(rms) -> str:
    """An rms height as the tables show it: smooth, nm below 1 um, else um ('-' where unknown: a measured
    variant whose every member failed)."""
    if rms is None or rms != rms:
        return "-"
    if not rms:
        return "smooth"
    return f"{num(rms, '.3g', 1e9)} nm" if rms < 1e-6 else f"{num(rms, '.3g', 1e6)} um"


def indenter_text(b) -> str:
    """The indenter of a rough row: the sphere, or the truncated sphere's face radius ('-' where unknown)."""
    if b is None or b != b:
        return "-"
    if not b:
        return "sphere"
    return f"b = {num(b, '.3g', 1e3)} mm" if b >= 1e-3 else f"b = {num(b, '.3g', 1e6)} um"


def _ratio(x, y):
    """x / y, or None where either is missing or the quotient is not finite."""
    try:
        q = float(x) / float(y)
    except (TypeError, ZeroDivisionError):
        return None
    return q if np.isfinite(q) else None


def table(res) -> list:
    lines = ["The indenter on rough surfaces: each MDR model's dissipation per stationary cycle and initial "
             "tangential stiffness relative to the rough half-space's (rough.equivalent), the ensemble's mean "
             "+- (its standard error + the mean grid error of its members; each member's grid ladder refines "
             "one band-limited surface). Equivalent: MDR with the profile of the rough contact's own F_N(d); "
             "smooth: the paper's model. A spread is no upper bound: a rough row is at best consistent. a: the "
             "smooth indenter's contact radius (Hertz's on the sphere).", "",
             "| indenter | rms | seeds | grids | period / a | lambda short, long (um) | contact area / smooth | "
             "equivalent: dissipation | stiffness | smooth: dissipation | stiffness | equivalent MDR holds? |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]

    def cell(r, key):
        x = r["verdicts"][key]
        if x["difference"] is None:
            return "undetermined"
        return f"{num(x['difference'], '+.1f', 100)} +- {num(x['error'], '.1f', 100)} % ({x['grade']})"

    def lam(r):
        if r.get("measured"):
            return "measured"
        return "-" if not r["rms"] else f"{num(r['lambda_short'], '.4g', 1e6)}, {num(r['lambda_long'], '.4g', 1e6)}"

    for r in res[KEY]:
        a = r.get("a_smooth", res["errors"]["a_ref"])
        plastic = (f", H = {num(r['hardness'], '.2g', 1e-9)} GPa, flattened at "
                   f"{num(r['preload'], '.2g')} N") if r.get("hardness") else ""
        lines.append(f"| {indenter_text(r.get('b', 0.0))} | {rms_text(r['rms'])}{' (measured)' if r.get('measured') else ''}{plastic} | {len(r['seeds'])} | {', '.join(map(str, r['grids']))} | "
                     f"{num(_ratio(r['period'], a), '.0f')} | {lam(r)} | {num(r.get('contact_area_over_smooth'), '.2f')} | "
                     f"{cell(r, 'mdr_equivalent:dissipation')} | {cell(r, 'mdr_equivalent:stiffness')} | "
                     f"{cell(r, 'mdr_smooth:dissipation')} | {cell(r, 'mdr_smooth:stiffness')} | {grade_text(r)} |")
    return lines + apparatus_table(res[KEY])


def apparatus_table(rows: list) -> list:
    """The rough half-space driven by the apparatus at the paper's points (the rows' ``apparatus``): per
    indenter, surface and load, its slip index (ensemble mean +- standard error + grid error), the smooth
    indenter's (MDR) and what MDR with the equivalent profile misses of the rough one. Points of one load
    and k_x on the sphere's contact (b = 0, 1 and 10 um read the sphere) are one line. Empty without such
    rows."""
    lines = []
    for r in rows:
        seen = {}
        for x in r.get("apparatus") or []:
            pt = x.get("point") or {}
            key = tuple(pt.get(k) for k in ("F0", "dF", "ua", "mu1", "mu2", "kx"))
            if key in seen:
                continue
            seen[key] = True
            rh, em = x.get("rough_halfspace") or {}, x.get("equivalent_minus_rough")
            rough = "undetermined" if rh.get("mean") is None else \
                f"{num(rh['mean'], '.3f')} +- {num(rh['sem'], '.3f')} (finest grid)" if rh.get("error") is None else \
                f"{num(rh['mean'], '.3f')} +- {num(rh['error'], '.3f')}"
            eq = "-" if not em else f"{num(em['mean'], '+.3f')} +- {num(em['sem'], '.3f')}"
            plastic = ", plastic" if r.get("hardness") else ""
            lines.append(f"| {indenter_text(r.get('b', 0.0))} | {rms_text(r['rms'])}{plastic} | "
                         f"{num(pt.get('F0'), '.3g')} | {num(pt.get('kx'), '.3g', 1e-6)} | {rough} | "
                         f"{num(x.get('mdr_smooth'), '.3f')} | {eq} |")
    if not lines:
        return []
    return ["", "In the apparatus (rough.law): the rough half-space driven by the paper's apparatus at the "
            "points whose contact each row's indenter is (validation.paper_points.rough_points; 3 cycles of 120 "
            "steps, F_N = F0 (1 + 0.2 sin)) on the finest grid of the ladder, its slip index as the ensemble's "
            "mean +- standard error; the smooth indenter's (MDR, the paper's model) and what MDR with each "
            "surface's equivalent profile misses of the rough half-space (mean +- standard error).", "",
            "| indenter | rms | F0 (N) | k_x (N/um) | slip index: rough half-space | smooth MDR | "
            "equivalent MDR - rough |", "|---|---|---|---|---|---|---|"] + lines


def figure(result: dict, out_dir) -> dict:
    """Each MDR model's difference from the rough half-space against the rms height: the members
    (dots) and the ensemble mean with its error bar (a column without one says why); grey: the
    catalogue's tolerance."""
    from ..figures import plt, save

    rows = result[KEY]
    fig, axes = plt.subplots(1, 2, figsize=(max(10.0, 1.5 * len(rows)), 4.2))
    for ax, q in zip(axes, QUANTITIES):
        for k, (mdl, label, mk) in enumerate((("mdr_equivalent", "MDR, equivalent profile", "o"),
                                              ("mdr_smooth", "MDR, smooth indenter", "s"))):
            xs, ys, es = [], [], []
            for j, r in enumerate(rows):
                x = r["verdicts"][f"{mdl}:{q}"]
                pos = j + (k - 0.5) * 0.15
                ax.plot([pos] * len(x["members"]), 100 * np.asarray(x["members"], dtype=float), ".",
                        color=f"C{k}", alpha=0.5)
                if x["difference"] is not None and x["error"] is not None:
                    xs.append(pos), ys.append(100 * x["difference"]), es.append(100 * x["error"])
                elif k == 0:  # no ensemble mean: say why at the column's foot
                    sticks = "zero reference" in (x.get("grid_status") or [])
                    ax.annotate("undetermined: a surface sticks on a grid" if sticks else "undetermined",
                                (j, 0.5), xycoords=("data", "axes fraction"), ha="center", va="center",
                                rotation=90, fontsize=7, color="0.3")
            ax.errorbar(xs, ys, yerr=es, fmt=mk, color=f"C{k}", capsize=4, label=label)
        tol = rows[0]["verdicts"][f"mdr_equivalent:{q}"]["tolerance"] if rows else None
        if tol:
            ax.axhspan(-100 * tol, 100 * tol, color="0.85", zorder=0, label="the catalogue's tolerance")
        ax.axhline(0.0, color="0.5", lw=0.8)
        faces = any(r.get("b") for r in rows)
        ax.set_xticks(range(len(rows)), [rms_text(r["rms"]) + ("\n" + indenter_text(r.get('b', 0.0)).removeprefix('b = ') if faces else "")
                                         + ("\nplastic" if r.get("hardness") else "") for r in rows], fontsize=8)
        if faces:
            ax.set_xlabel("rms height, face radius b")
        ax.set_ylabel(f"{q}: MDR / rough half-space - 1 (%)")
        ax.set_title(f"{q} ({result['scene']['profile']}, F0 = {result['scene']['F0']:g} N, "
                     f"Q = {result['scene']['amplitude']:g} N)")
        ax.legend(fontsize=8)
    fig.tight_layout()
    return {"roughness": save(fig, Path(out_dir) / "roughness.png")}
