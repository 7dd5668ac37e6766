"""The paper's results as points of its apparatus: one home for the conditions at which the error budget
(``validation.budget``) and the catalogue's scene of those points (``halfspace-points``) evaluate them.

Willert, Machines 11 (2023) 484: the loops of Figs. 4-5 (sphere) and 6-7 (truncated sphere b = 0.6 mm)
at their own loads (``studies.study.LOOP_CASES``); the slip-index curves of Fig. 8 (against b) and
Fig. 9 (against the axis stiffness k_x), taken at their ends and middles; the Table 2 point. Every
point but the loops' is at Table 2's load (``mdr.paper.TABLE2``), with Table 1's k_x where the figure
does not vary it.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from mdr.materials import Materials
from mdr.paper import B_TABLE1, DF_OVER_F0, KX_TABLE1, R_INDENTER, TABLE2

#: the resolution of a result read from the paper's figures, as a change of the slip index (the
#: dissipation over 4 mu F0 u_A; 1 is gross slip): 1 % of its full scale, as a loop is read to 1 % of
#: its height (the budget's own constant: the catalogue's loop tolerance has the same origin)
RESOLUTION = 0.01
RESOLUTION_ORIGIN = ("0.01 of the slip index, 1 % of its full scale (1: gross slip), as a loop is read to 1 % of "
                     "its height")


#: a point's fields -> the fields of a scene (``validation.scenes.Scene``) that hold them
SCENE_FIELDS = {"b": "b", "F0": "F0", "dF": "dF", "ua": "amplitude", "mu1": "mu", "mu2": "mu2", "kx": "kx"}


def same(x, y) -> bool:
    """Two values of a point's field the same within 1e-9 relative (a scene's and a point's, a stored
    row's and a point's)."""
    return abs(float(x) - float(y)) <= 1e-9 * max(abs(float(x)), abs(float(y)), 1e-30)


@dataclass(frozen=True)
class Point:
    """One apparatus point of a result (SI): the indenter (``b`` = 0: the sphere, else the truncated
    sphere's face radius), the normal force F0 and its amplitude dF, the piezo amplitude ``ua``, the
    friction of the contact (mu1) and of the bedding (mu2), the axis stiffness ``kx``."""

    b: float
    F0: float = TABLE2["F0"]
    dF: float = TABLE2["dF"]
    ua: float = TABLE2["ua"]
    mu1: float = TABLE2["mu1"]
    mu2: float = TABLE2["mu2"]
    kx: float = KX_TABLE1

    def matches(self, s) -> bool:
        """True where the scene ``s`` (``validation.scenes.Scene``) runs this point: the apparatus drive,
        the same indenter, load, amplitude, friction and k_x (within 1e-9 relative, ``same``)."""
        b = 0.0 if s.profile == "sphere" else s.b
        return (s.drive == "apparatus" and s.profile in ("sphere", "truncated") and same(b, self.b)
                and all(same(getattr(s, f), getattr(self, k)) for k, f in SCENE_FIELDS.items() if k != "b"))


@dataclass(frozen=True)
class Setup:
    """What a rig's points share and a point does not hold: the indenter's radius ``R`` (m), the pair's
    ``materials`` (``mdr.materials.Materials``) and the apparatus's fields other than ``kx`` and ``mu2``
    (``apparatus``: (name, value) pairs of ``mdr.apparatus.Apparatus``; () its defaults, the project's
    reading of the paper's plates and bedding). ``PAPER``: the paper's (R = 6 mm, steel on steel)."""

    R: float = R_INDENTER
    materials: Materials = Materials()
    apparatus: tuple = ()

    @property
    def app_kw(self) -> dict:
        return dict(self.apparatus)


PAPER = Setup()


@dataclass(frozen=True)
class Result:
    """One of the paper's results: its key, title and points."""

    key: str
    title: str
    points: tuple


def contact_radius(p: Point, setup: Setup = PAPER) -> float:
    """The smooth indenter's half-space contact radius (m) at the point's largest force F0 + dF (the
    setup's R and materials)."""
    from fem.axisym.normal_run import reference_radius

    kind = "sphere" if p.b == 0 else "truncated"
    return reference_radius(kind, setup.R, p.b or None, p.F0 + p.dF, setup.materials.E_star)


def rough_row_b(p: Point, setup: Setup = PAPER) -> float:
    """The face radius of the rough contact a point reads (the budget's roughness columns): its own b
    where the face is wider than half the sphere's Hertz radius (it reaches into the contact), else 0,
    the sphere's contact."""
    return p.b if p.b > 0.5 * contact_radius(replace(p, b=0.0), setup) else 0.0


def rough_points(b: float) -> tuple:
    """The paper's points whose rough contact is the indenter of face radius ``b`` (0: the sphere;
    ``rough_row_b``), each once, in the order of ``results``."""
    out = []
    for r in results():
        for p in r.points:
            if same(rough_row_b(p), b) and p not in out:
                out.append(p)
    return tuple(out)


def loop_point(fig: str) -> Point:
    """The point of the loop experiment ``fig`` ("fig4" .. "fig7") at its own load (Table 1's b and k_x)."""
    from studies.study import LOOP_CASES

    kind, F0, ua, mu1, mu2 = LOOP_CASES[fig]
    return Point(b=0.0 if kind == "sphere" else B_TABLE1, F0=F0, dF=DF_OVER_F0 * F0, ua=ua, mu1=mu1, mu2=mu2)


def results() -> tuple:
    """The paper's results and their points (Figs. 8, 9: the ends and the middle of their ranges)."""
    fig8 = tuple(Point(b=b, kx=kx) for b in (1e-6, 10e-6, 100e-6, 1e-3) for kx in (1e6, 20e6))
    fig9 = tuple(Point(b=b, kx=kx) for b in (10e-6, 50e-6, 100e-6) for kx in (0.3e6, 3e6, 30e6))
    return (Result("figs4-5", "Figs. 4-5: loops, sphere", (loop_point("fig4"), loop_point("fig5"))),
            Result("figs6-7", "Figs. 6-7: loops, truncated b = 0.6 mm", (loop_point("fig6"), loop_point("fig7"))),
            Result("fig8", "Fig. 8: slip index against b = 1 um - 1 mm", fig8),
            Result("fig9", "Fig. 9: slip index against k_x, b = 10-100 um", fig9),
            Result("table2", "Table 2 point: b = 0.6 mm and 10 um", (Point(b=B_TABLE1), Point(b=10e-6))))


def slip_indices(profiles, points, app_kw=None, n=100, setup: Setup = PAPER):
    """The apparatus slip index of each (profile, point) (``studies.paper._slip_index``), the setup's
    materials and apparatus (``app_kw`` changes its fields)."""
    return [float(np.asarray(_apparatus_run(prof, p, n, setup, app_kw)["slip_index"]).ravel()[0])
            for prof, p in zip(profiles, points)]


def _apparatus_run(profile, p: Point, n: int, setup: Setup, app_kw=None) -> dict:
    """MDR's run of ``profile`` at the point in the setup's apparatus (``studies.paper._slip_index``; n
    cells; ``app_kw`` changes the apparatus's fields): its result's arrays."""
    from studies.paper import RES, _slip_index

    _, out = _slip_index(profile, p.kx, mu1=p.mu1, mu2=p.mu2, F0=p.F0, dF=p.dF, ua=p.ua, res={**RES, "n": n},
                         app_kw={**setup.app_kw, **(app_kw or {})} or None, materials=setup.materials)
    return out


def difference_with_grid(fun, n=(100, 400)):
    """fun(n) -> (test, reference): their difference at the finer n, error the change from the coarser
    (MDR's spring-cell ladder), at least ``ROUND_OFF``: the apparatus solve's own
    error (its displacement tolerance, 1e-15 m: a solve ten times looser moves the kink's cells by up to
    6e-16 at points where the grid's change is 0 to 1e-16) and the rounding of the difference."""
    vals = [float(np.subtract(*fun(k))) for k in n]
    return vals[-1], max(abs(vals[-1] - vals[0]), ROUND_OFF)


#: the error of a difference of slip indices from the apparatus solve and rounding (``difference_with_grid``;
#: in the slip index's unit, 4 mu1 F0 u_A, where a slip index is of order one): 16 eps
ROUND_OFF = 16 * float(np.finfo(float).eps)


def tiltable(p: Point, setup: Setup = PAPER) -> bool:
    """Whether the 3D points scenes tilt the point: a face of at least ``scenes.TILT_MIN_FACE_ELEMENTS``
    elements of their finest level (``scenes.DIRECTION_LEVELS_3D``, in units of its contact radius)."""
    from .scenes import DIRECTION_LEVELS_3D, TILT_MIN_FACE_ELEMENTS

    return p.b >= TILT_MIN_FACE_ELEMENTS * DIRECTION_LEVELS_3D[-1] * contact_radius(p, setup)


def friction_share(p: Point, n: int = 100, setup: Setup = PAPER) -> float:
    """The largest share of the friction limit the point's tangential force takes in its apparatus over
    the last cycle (MDR, the sharp profile): max |F_x| / (mu1 F_N), 1 where the contact slides as a whole
    (the limit follows the normal force)."""
    from mdr.profiles import TruncatedSphere
    from studies.paper import RES

    out = _apparatus_run(TruncatedSphere(setup.R, p.b), p, n, setup)
    Fx, FN = (np.asarray(out[k], dtype=float).ravel() for k in ("Fx", "FN"))
    last = slice(Fx.size - Fx.size // RES["cycles"], Fx.size)
    return float(np.max(np.abs(Fx[last]) / (p.mu1 * FN[last])))


def point_slip_index(p: Point, n: int = 400, setup: Setup = PAPER) -> float:
    """The point's slip index: MDR in the setup's apparatus, the sharp profile."""
    from mdr.profiles import TruncatedSphere

    return slip_indices([TruncatedSphere(setup.R, p.b)], [p], n=n, setup=setup)[0]
