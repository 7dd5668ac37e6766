"""Normal contact of an axisymmetric indenter with a rough surface on a half-space: FFT boundary
elements on a periodic grid (Polonsky & Keer's constrained conjugate gradient, 1999, Wear 231, 206:
this project's ``elastic_pressure``, which starts from a given pressure, or tamaas's
``PolonskyKeerRey``, the rough-contact library's, its witness: the same contact within 1e-8 of the
peak pressure, ``tests/test_rough_normal.py``).

The indenter's profile (``mdr.profiles``) plus a height map (``rough.surfaces.HeightMap``, the
combined roughness of both bodies: the sum of the two maps, or one map of the combined rms) is a rigid
surface pressed on an elastic half-space of modulus E* (``mdr.materials.Materials``): frictionless,
no adhesion, linear elasticity (the asperities' plasticity is left out and reported elsewhere). The
grid is periodic with side ``period``: the contact's periodic images add an error that falls as
(a / period)^3 (measured below), so ``period`` is part of the error bar, as the pixel is.

Measured on the smooth sphere (R = 6 mm, F = 0.5 N, steel), the second-moment pressure radius over
Hertz's and the peak pressure over p0: period 8 a, pixels a/16, a/32, a/64: 0.99894, 0.99876,
0.99875 and 1.0015, 1.0023, 1.0025 (the images: -0.13 %, +0.25 %); period 16 a, the same pixels:
1.00112, 1.00003, 0.99987 and 0.9959, 0.9993, 1.00006 (``tests/test_rough_normal.py``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from common.errors import ConvergenceError, InputError, positive, positive_int
from common.ladder import GCI_SAFETY, ladder_error

from .boxqp import solve_box
from .halfspace import _boussinesq_kernel, _periodic_kernel, among_cells, halfspace_displacement, periodic_displacement
from .surfaces import MIN_PIXELS, HeightMap, require_tamaas

#: the solver's relative tolerance (tamaas's error norm of the complementarity)
TOLERANCE = 1e-12


@dataclass(frozen=True)
class Grid:
    """A periodic square of side ``period`` (m) on ``n`` x ``n`` pixels, centred on the indenter's axis."""

    period: float
    n: int

    def __post_init__(self):
        positive("period", self.period)
        positive_int("n", self.n, minimum=MIN_PIXELS)

    @property
    def pixel(self) -> float:
        return self.period / self.n

    def radii(self, centre=(0.0, 0.0)) -> np.ndarray:
        """The distance of each pixel centre from the axis (n, n); from the point ``centre`` (m, from the
        grid's centre) where given."""
        x = (np.arange(self.n) + 0.5) * self.pixel - 0.5 * self.period
        X, Y = np.meshgrid(x - centre[0], x - centre[1], indexing="ij")
        return np.hypot(X, Y)

    def cell_mean(self, f, centre=(0.0, 0.0), sub: int = 8) -> np.ndarray:
        """The mean over each pixel (n, n) of the axisymmetric field f(r) about ``centre`` (m), by the
        midpoint rule on sub x sub points: the pixel-wise constant field of the same force. A field
        sampled at the pixel centres instead jumps where its support ends inside a pixel (Hertz's
        pressure at r = a): its force and every result change by a pixel's share as the edge crosses a
        centre, and a grid ladder of them is not monotone."""
        positive_int("sub", sub)
        offsets = ((np.arange(sub) + 0.5) / sub - 0.5) * self.pixel
        return sum(f(self.radii((centre[0] - dx, centre[1] - dy))) for dx in offsets for dy in offsets) / sub ** 2


#: the hardness of the paper's steel X5CrNi18-10 (AISI 304), solution annealed: at most 215 HB
#: (EN 10088-3), about 2.1 GPa (Brinell's kgf/mm^2 x 9.81 MPa): the mean pressure a fully plastic
#: asperity carries (Tabor, *The Hardness of Metals*, Oxford 1951)
HARDNESS_X5CRNI18_10 = 2.1e9
#: the capped solve's tolerance (``rough.boxqp.solve_box``: of the range of the elastic displacement)
SATURATED_TOLERANCE = 1e-10


def saturated_pressure(surface, F, grid: Grid, E_star, hardness) -> np.ndarray:
    """The pressure (n, n) (Pa) of a rigid ``surface`` (heights, m: the highest point touches first) pressed
    with the force ``F`` on the periodic elastic half-space with the pressure capped at ``hardness`` (Pa):
    perfectly plastic asperities (the elastic-perfectly-plastic half-space of Almqvist et al. 2007,
    Tribology International 40, 574). With the gap g0 = max(z) - z it minimises (1/2) p.Kp + p.g0 over
    0 <= p <= H with sum(p) dA = F: contact (p > 0) closes the gap, a plastic pixel (p = H) penetrates.
    Solved as the symmetric box |p - H/2| <= H/2 (K of a constant is 0) by ``rough.boxqp.solve_box``."""
    n, dA = grid.n, grid.pixel ** 2
    H = float(positive("hardness", hardness))
    if F >= H * n * n * dA:
        raise InputError(f"F = {F:.4g} N needs more than the hardness {H:.3g} Pa over the whole grid "
                         f"({H * n * n * dA:.4g} N): raise the hardness or the period")
    apply = periodic_displacement(grid, E_star)
    z = np.asarray(surface, dtype=float)
    lim = np.full((n, n), 0.5 * H)
    q = solve_box(apply, z.max() - z, lim, F - 0.5 * H * n * n * dA, -lim, dA, SATURATED_TOLERANCE,
                  "saturated normal contact")
    return np.clip(q + 0.5 * H, 0.0, H)


#: ``normal_contact``'s elastic solvers: this project's (``elastic_pressure``, the default: 3-4x faster than
#: tamaas's on 768^2 pixels, and it resolves a contact of one pixel) and tamaas's, its witness
SOLVERS = ("project", "tamaas")


def normal_contact(profile, materials, F, grid: Grid, heights: HeightMap | None = None, *,
                   hardness: float | None = None, solver: str = "project") -> dict:
    """The frictionless normal contact of ``profile`` (+ ``heights``, on the same grid) under the force
    ``F`` (N) on the periodic ``grid``; with ``hardness`` (Pa) its pressure capped there, perfectly
    plastic asperities (``saturated_pressure``; the plastic pixels penetrate, so the approach is read from
    the elastic contact pixels alone; a first loading: no unloading, no memory of plastic flow). Returns ``contact_area`` (m^2, the pixels in contact),
    ``contact_radius_area`` (sqrt(area / pi)), ``pressure_radius`` (sqrt(5 M2 / (2 F)) with M2 the
    pressure's second moment about the axis: exact for Hertz, and defined for any pressure: a rough
    contact's spread), ``p_max`` (Pa), ``approach`` (m, the rigid approach since first contact in the
    half-space without periodic images: ``halfspace_displacement``) and ``approach_spread``,
    ``pressure`` (n, n) (Pa), ``plastic_area`` (m^2, the pixels at the hardness; 0 without one) and the
    grid. The elastic ``solver``: one of ``SOLVERS``."""
    if solver not in SOLVERS:
        raise InputError(f"solver must be one of {', '.join(SOLVERS)}, got {solver!r}")
    F = positive("F", F)
    r = grid.radii()
    z = _rigid_surface(profile, grid, heights)
    if hardness is not None:
        return _contact_result(saturated_pressure(z, F, grid, materials.E_star, hardness), z, F, grid, r, materials,
                               hardness)
    if solver == "project":
        return _contact_result(elastic_pressure(z, F, grid, materials.E_star), z, F, grid, r, materials, None)
    tm = require_tamaas()
    tm.set_log_level(tm.LogLevel.error)
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [grid.period, grid.period], [grid.n, grid.n])
    model.E, model.nu = float(materials.E_star), 0.0  # tamaas's E* = E / (1 - nu^2)
    solver = tm.PolonskyKeerRey(model, z, TOLERANCE, tm.PolonskyKeerRey.pressure, tm.PolonskyKeerRey.pressure)
    try:
        solver.solve(F / grid.period ** 2)
    except tm.FloatingPointError as e:  # tamaas: a contact of one pixel has no complementarity error
        raise ConvergenceError(f"the contact at F = {F:.4g} N is a single pixel of {grid.pixel:.3g} m: raise the "
                               f"load or refine the grid ({e})") from e
    p = np.array(model.traction, dtype=float).reshape(grid.n, grid.n)
    return _contact_result(p, z, F, grid, r, materials, None)


def _rigid_surface(profile, grid: Grid, heights: HeightMap | None) -> np.ndarray:
    """The rigid surface (n, n) (m, the highest point touches first): minus the profile's gap plus the
    heights; a flat punch's face must lie inside the grid (beyond its rim: far away)."""
    r = grid.radii()
    with np.errstate(invalid="ignore"):
        g = np.asarray(profile.f(r), dtype=float)
    finite = np.isfinite(g)
    if not finite[r <= 0.25 * grid.period].all():
        raise InputError("the profile must be finite within a quarter period of the axis (a flat punch's face "
                         "must lie inside the grid)")
    g = np.where(finite, g, np.max(g[finite]) + 1.0 * grid.period)  # beyond a punch's rim: far away
    surface = -g
    if heights is not None:
        if heights.h.shape != (grid.n, grid.n) or not np.isclose(heights.pixel, grid.pixel, rtol=1e-9):
            raise InputError(f"the height map must lie on the grid: {grid.n} x {grid.n} pixels of {grid.pixel:.4g} m, "
                             f"got {heights.h.shape} of {heights.pixel:.4g} m")
        surface = surface + heights.h
    return np.ascontiguousarray(surface)


#: ``elastic_pressure``'s tolerance: the frictionless contact's optimality conditions violated by at most
#: this share of the range of the elastic displacement (its approaches agree with tamaas's at
#: ``TOLERANCE`` within 1e-9 on an rms 1 um surface, measured 2e-11: ``tests/test_rough_normal.py``)
ELASTIC_TOLERANCE = 1e-10
#: the elastic solve's largest number of iterations
ELASTIC_MAX_ITER = 5000


def elastic_pressure(surface, F, grid: Grid, E_star, start=None) -> np.ndarray:
    """The pressure (n, n) (Pa) of the rigid ``surface`` (m) pressed with the force ``F`` (N) on the
    periodic elastic half-space of modulus E* (the kernel of ``normal_compliance``, tamaas's): Polonsky &
    Keer's constrained conjugate gradient (1999, Wear 231, 206; the algorithm of tamaas's
    ``PolonskyKeerRey``), which, unlike tamaas's, starts from a given pressure: ``start`` (n, n), e.g.
    the contact of a nearby load scaled to F, the force-approach curve's warm start (3.4x fewer
    iterations on an rms 1 um surface's 24 loads). Converged where, with g = K p + max(z) - z and delta
    its mean over the contact, |g - delta| and the overlap delta - g outside it are at most
    ``ELASTIC_TOLERANCE`` of the range of K p. A contact of one pixel is an answer (the pixel-wise
    discrete contact's; tamaas's solve can fail there, its error measure undefined)."""
    n, dA = grid.n, grid.pixel ** 2
    apply = periodic_displacement(grid, E_star)
    z = np.asarray(surface, dtype=float)
    gap0 = z.max() - z
    unit = np.zeros((n, n))
    unit[0, 0] = 1.0
    self_compliance = float(apply(unit)[0, 0])  # a pixel's displacement under its own unit pressure
    pbar = float(positive("F", F)) / (dA * n * n)
    p = np.full((n, n), pbar) if start is None else np.maximum(np.asarray(start, dtype=float), 0.0)
    if not p.sum() > 0:
        p = np.full((n, n), pbar)
    p *= pbar / p.mean()
    t, G_old, conjugate = np.zeros((n, n)), 1.0, 0.0
    for _ in range(ELASTIC_MAX_ITER):
        u = apply(p)
        contact = p > 0
        g = u + gap0
        g -= float(g[contact].mean())
        violation = max(float(np.abs(g[contact]).max()), float(np.maximum(-g[~contact], 0.0).max(initial=0.0)))
        if violation <= ELASTIC_TOLERANCE * max(float(np.ptp(u)), 1e-300):
            return p
        G = float(np.sum(g[contact] ** 2))
        t = np.where(contact, g + (conjugate * G / G_old if G_old > 0 else 0.0) * t, 0.0)
        G_old = G
        r = apply(t)
        r -= float(r[contact].mean())
        curvature = float(np.sum(r[contact] * t[contact]))
        if curvature > 0:
            tau = float(np.sum(g[contact] * t[contact])) / curvature
        else:  # the contact's gaps all equal (one pixel): only the overlap moves, by a pixel's own compliance
            tau = 1.0 / self_compliance
        p = np.maximum(p - tau * t, 0.0)
        overlap = (p == 0) & (g < 0)  # out of contact but penetrating: in, and the conjugation restarts
        conjugate = 0.0 if overlap.any() else 1.0
        p[overlap] -= tau * g[overlap]
        p *= pbar / p.mean()
    raise ConvergenceError(f"the elastic normal contact at F = {F:.4g} N did not converge in {ELASTIC_MAX_ITER} "
                           "iterations")


def dense_elastic_pressure(surface, F, grid: Grid, E_star, start, cells=(), max_cells: int = 8000):
    """``elastic_pressure``'s contact solved on the cells near a known one: the candidates are the cells
    of ``start`` (a nearby force's pressure, (n, n)) and ``cells`` (flat indices); a primal active set
    over the dense periodic compliance among them (the pressures of a set from K p + g0 = d there and
    their total F, cells of negative pressure dropped, penetrating candidates added), then checked on
    the whole grid with one transform (penetrating cells outside the candidates join them and the solve
    repeats). The same optimality conditions as ``elastic_pressure``'s to ``ELASTIC_TOLERANCE``; a few
    dense solves of the contact's size instead of an FFT per iteration (a rough contact touches a few
    hundred pixels). None where the active set cycles or the candidates exceed ``max_cells`` (the
    caller then solves on the grid)."""
    n, dA = grid.n, grid.pixel ** 2
    kernel, screen = _periodic_kernel(grid, float(E_star))
    z = np.asarray(surface, dtype=float)
    g0 = (z.max() - z).ravel()
    start = np.asarray(start, dtype=float).ravel()
    cand = np.union1d(np.flatnonzero(start > 0), np.asarray(cells, dtype=np.int64))
    for _ in range(20):  # candidate sets
        if cand.size > max_cells:
            return None
        K = among_cells(kernel, cand, n, periodic=True)
        act = start[cand] > 0
        p = None
        for _ in range(4 * cand.size + 20):  # active sets
            A = np.flatnonzero(act)
            m = A.size
            if m == 0:
                return None
            M = np.zeros((m + 1, m + 1))
            M[:m, :m] = K[np.ix_(A, A)]
            M[:m, m], M[m, :m] = -1.0, 1.0
            x = np.linalg.solve(M, np.concatenate([-g0[cand[A]], [float(F) / dA]]))
            pa, d = x[:m], x[m]
            if np.any(pa < 0):
                act[A[pa < 0]] = False
                continue
            p = np.zeros(cand.size)
            p[A] = pa
            g = K @ p + g0[cand] - d
            worse = ~act & (g < -ELASTIC_TOLERANCE * max(float(np.ptp(K @ p)), 1e-300))
            if not worse.any():
                break
            act[worse] = True
            p = None
        if p is None:
            return None
        P = np.zeros(n * n)
        P[cand] = p
        # the whole grid screened in single precision (3-4x faster transforms; its error ~1e-7 of the
        # displacement, far below the screen's margin), the cells it cannot clear checked in double
        u = screen(P.reshape(n, n)).ravel()
        scale = max(float(np.ptp(u)), 1e-300)
        near = np.setdiff1d(np.flatnonzero(u + (g0 - d) < SCREEN_MARGIN * scale), cand)
        if near.size > SCREEN_MAX:  # too many to check one by one: the double-precision transforms
            u = periodic_displacement(grid, E_star)(P.reshape(n, n)).ravel()
            scale = max(float(np.ptp(u)), 1e-300)
            out = np.setdiff1d(np.flatnonzero(u + g0 - d < -ELASTIC_TOLERANCE * scale), cand)
        else:
            g = among_cells(kernel, cand, n, periodic=True, at=near) @ p + g0[near] - d
            out = near[g < -ELASTIC_TOLERANCE * scale]
        if out.size == 0:
            return P.reshape(n, n)
        cand = np.union1d(cand, out)
    return None


#: ``dense_elastic_pressure``'s screen: a cell outside the candidates whose single-precision gap is below
#: this share of the displacement's range is checked in double precision (the single-precision
#: displacement is off by ~1e-7 of it), at most ``SCREEN_MAX`` of them (beyond, the grid in double)
SCREEN_MARGIN, SCREEN_MAX = 1e-4, 4000


def _contact_result(p, z, F, grid, r, materials, hardness) -> dict:
    """``normal_contact``'s keys of the pressure ``p`` on the rigid surface ``z``."""
    dA = grid.pixel ** 2
    area = float(np.count_nonzero(p > 0)) * dA
    M2 = float(np.sum(p * r ** 2)) * dA
    plastic = np.zeros(p.shape, dtype=bool) if hardness is None else p >= hardness * (1.0 - 1e-9)
    d, spread = _approach(p, z, grid.pixel, float(materials.E_star), elastic=~plastic)
    return {"plastic_area": float(np.count_nonzero(plastic)) * dA, "contact_area": area, "contact_radius_area": float(np.sqrt(area / np.pi)),
            "pressure_radius": float(np.sqrt(5.0 * M2 / (2.0 * F))), "p_max": float(p.max()),
            "force": float(p.sum()) * dA, "approach": d, "approach_spread": spread, "pressure": p,
            "flattening": _flattening(p, z, grid, float(materials.E_star), plastic),
            "period": grid.period, "n": grid.n}


def _flattening(p, z, grid, E_star, plastic) -> np.ndarray:
    """The plastic pixels' penetration (n, n) (m, >= 0; 0 elsewhere): with u = K p the periodic
    half-space's displacement and delta the approach of the elastic contact pixels (where
    u + max(z) - z = delta), a plastic pixel has u + max(z) - z < delta by its penetration. The surface
    lowered by it, z - flattening, is the flattened surface whose elastic contact at the same force has
    the same pressure (the capped solve's optimality conditions are the elastic one's there): it
    unloads elastically."""
    out = np.zeros(p.shape)
    elastic = (p > 0) & ~plastic
    if not plastic.any() or not elastic.any():
        return out
    w = periodic_displacement(grid, E_star)(p) + z.max() - z
    delta = float(np.mean(w[elastic]))
    out[plastic] = np.maximum(delta - w[plastic], 0.0)
    return out


#: ``force_approach`` solves a load on its contact's cells (``dense_elastic_pressure``) up to this many
#: candidates, and reads its approach there (``contact_approach``); beyond, on the grid
DENSE_CURVE_MAX = 3000


def contact_approach(p, surface, pixel, E_star) -> float:
    """``_approach``'s d of an elastic contact: over the contact's cells alone where they are at most
    ``DENSE_CURVE_MAX`` (Boussinesq's pixel kernel among them, no periodic image: the same sum as the
    zero-padded FFT's, without the grid's transforms), else ``_approach``'s."""
    p = np.asarray(p, dtype=float)
    idx = np.flatnonzero(p.ravel() > 0)
    if idx.size == 0 or idx.size > DENSE_CURVE_MAX:
        return _approach(p, surface, pixel, E_star)[0]
    n = p.shape[0]
    Kb = among_cells(_boussinesq_kernel(n, float(pixel), float(E_star)), idx, n, periodic=False)
    pc = p.ravel()[idx]
    sf = np.asarray(surface, dtype=float)
    dd = Kb @ pc + sf.max() - sf.ravel()[idx]
    return float(np.sum(dd * pc) / np.sum(pc))


def _approach(p, surface, pixel, E_star, elastic=None) -> tuple:
    """The rigid approach d of the indenter since first contact (m) and its spread over the contact
    (relative): in contact the half-space's displacement u is d minus the initial gap max(z) - z, so
    d = u + max(z) - z, averaged with the pressure as weight (the spread: its range over d, the grid's
    and the period's inconsistency); over the ``elastic`` pixels alone where given (a plastic pixel
    penetrates)."""
    c = (p > 0) if elastic is None else (p > 0) & elastic
    if not np.any(c):
        if np.any(p > 0):
            raise ConvergenceError("every contact pixel is at the hardness: no elastic pixel fixes the approach; "
                                   "refine the grid")
        return 0.0, 0.0
    u = halfspace_displacement(p, pixel, E_star)
    dd = u[c] + surface.max() - surface[c]
    d = float(np.sum(dd * p[c]) / np.sum(p[c]))
    return d, float(np.ptp(dd) / d) if d > 0 else 0.0


#: the order of the periodic images' error in a / period (measured 9.6x smaller at twice the period
#: on the smooth sphere, against 2^3 = 8: ``tests/test_rough_normal.py``)
PERIOD_ORDER = 3


def grid_ladder(profile, materials, F, period, ns=(128, 256, 512), keys=("pressure_radius", "p_max")) -> dict:
    """The smooth indenter on one period at the pixel counts ``ns`` (coarse to fine): each key's
    values and its error bar (``common.ladder.ladder_error`` over the pixel size), which holds the
    pixel's error only."""
    runs = [normal_contact(profile, materials, F, Grid(period, n)) for n in ns]
    return {k: {"values": [x[k] for x in runs], **ladder_error([period / n for n in ns], [x[k] for x in runs])}
            for k in keys}


def normal_error(profile, materials, F, period, ns=(128, 256, 512), keys=("pressure_radius", "p_max")) -> dict:
    """Each key at the finest grid with its whole error bar: the pixel's (``grid_ladder``) plus the
    period's, the change from half the period at the same pixel extrapolated as (a / period)^3
    (``PERIOD_ORDER``) with Roache's safety factor: 1.25 |X(P) - X(P / 2)| / (2^3 - 1). Bounded where
    the pixel's ladder is (the period's order is measured, not observed per run)."""
    lad = grid_ladder(profile, materials, F, period, ns, keys)
    half = normal_contact(profile, materials, F, Grid(0.5 * period, ns[-1] // 2))
    out = {}
    for k in keys:
        g = lad[k]
        period_err = GCI_SAFETY * abs(g["value"] - half[k]) / (2 ** PERIOD_ORDER - 1)
        err = None if g["error"] is None else g["error"] + period_err
        out[k] = {"value": g["value"], "error": err, "pixel_error": g["error"], "period_error": period_err,
                  "status": g["status"], "bounded": g["bounded"], "values": g["values"]}
    return out


#: the ensemble statistics of ``ensemble``
ENSEMBLE_KEYS = ("contact_area", "pressure_radius", "p_max")


def ensemble(profile, materials, F, grid: Grid, params, seeds) -> dict:
    """The indenter on one rough realisation per seed (``params``: a ``rough.surfaces.RoughnessParams``
    on this grid, its seed replaced): per key of ``ENSEMBLE_KEYS`` the members' values, their mean,
    standard deviation (ddof 1) and the standard error of the mean. One realisation is no answer:
    at the paper's roughness the members' contact areas differ by tens of per cent."""
    from dataclasses import replace

    from .surfaces import generate

    seeds = list(seeds)
    if len(seeds) < 2:
        raise InputError(f"an ensemble needs at least 2 seeds, got {len(seeds)}")
    if params.n != grid.n or not np.isclose(params.size, grid.period, rtol=1e-12):
        raise InputError(f"the roughness must lie on the grid: size {grid.period:g} m on n = {grid.n}, got size "
                         f"{params.size:g} m on n = {params.n}")
    runs = [normal_contact(profile, materials, F, grid, generate(replace(params, seed=int(seed)))) for seed in seeds]
    out = {"seeds": seeds}
    for k in ENSEMBLE_KEYS:
        v = np.array([r[k] for r in runs])
        sd = float(np.std(v, ddof=1))
        out[k] = {"values": v.tolist(), "mean": float(v.mean()), "std": sd, "sem": sd / np.sqrt(v.size)}
    return out


def force_approach(profile, materials, loads, grid: Grid, heights: HeightMap | None = None, *,
                   hardness: float | None = None, start: tuple | None = None) -> tuple:
    """The normal force-approach curve of the indenter (+ ``heights``) at the forces ``loads`` (N,
    increasing): (approaches d (m), forces (N)), the input of MDR's equivalent profile
    (``mdr.equivalent.EquivalentProfile``). Sample the loads geometrically from a small fraction of
    the largest: near first contact a ~ sqrt(d). Elastic: ``elastic_pressure``, each load started from
    the last one's contact (tamaas's solve has no start; the same approaches within 1e-9, 4x faster
    over 24 loads); with ``hardness``, ``normal_contact``'s capped solve. A load whose contact the
    solver cannot resolve is left out: a sample less of a monotone
    curve (near first contact the equivalent profile joins the first resolved load to d = 0; the
    elastic solve resolves every load, a contact of one pixel included). At least 4 loads and the
    largest must be resolved. ``start``: (F, pressure (n, n)) of a contact of this surface already
    solved, where the first elastic load starts (else on the grid from a uniform pressure)."""
    loads = np.asarray(loads, dtype=float)
    if loads.ndim != 1 or loads.size < 4 or np.any(np.diff(loads) <= 0) or loads[0] <= 0:
        raise InputError(f"loads must be >= 4 increasing positive forces (N), got {loads!r}")
    d, kept, p, seeded = [], [], None, start is not None
    if seeded:  # as if the last load resolved were the given contact
        p, kept = np.asarray(start[1], dtype=float), [float(positive("start force", start[0]))]
    if hardness is None:
        z = _rigid_surface(profile, grid, heights)
    for F in loads:
        try:
            if hardness is None:  # elastic: each load from the last resolved one's contact, on its cells first
                guess = None if p is None else p * (F / kept[-1])
                dense = None if guess is None else dense_elastic_pressure(z, F, grid, materials.E_star, guess,
                                                                          max_cells=DENSE_CURVE_MAX)
                p = dense if dense is not None else elastic_pressure(z, F, grid, materials.E_star, guess)
                d.append(contact_approach(p, z, grid.pixel, float(materials.E_star)))
            else:
                d.append(normal_contact(profile, materials, F, grid, heights, hardness=hardness)["approach"])
            kept.append(F)
        except ConvergenceError:  # a load whose contact the solver cannot resolve is a sample less
            pass
    if seeded:
        kept = kept[1:]
    if len(kept) < 4 or kept[-1] != loads[-1]:
        raise ConvergenceError(f"{len(kept)} of {loads.size} loads give a contact the solver resolves, the largest "
                               f"{'among them' if kept and kept[-1] == loads[-1] else 'not'}: the curve needs 4 and "
                               "its top; raise the loads or refine the grid")
    return np.array(d), np.array(kept)
