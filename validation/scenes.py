"""The scene type: every comparison of MDR and FE is a :class:`Scene` (plain data), checked once; the
catalogue of them is ``validation.catalogue``.

A scene names the geometry (profile, R, b), the materials, friction, the
loading (contact driven directly under force or displacement control, or the
apparatus of ``mdr.apparatus``), the FE model that can answer it at the least
cost, and the resolution ladders used to estimate each side's own error.

Loading conventions (SI; time in cycles):
``F_N(t) = F0 + dF sin(2 pi t + alpha)`` and, for the tangential load,
``F_x(t) = amplitude sin(2 pi t)`` (``drive="force"``),
``u(t) = amplitude sin(2 pi t)`` (``drive="displacement"``, the FE displacement
measured without the finite bodies' series compliance, see ``fem.axisym.law``), or
the piezo displacement ``u_3(t) = amplitude sin(2 pi t)`` of the apparatus
(``drive="apparatus"``, with ``kx`` and ``mu2``).

Why force control for the directly driven scenes: a finite FE body adds a bulk
tangential compliance in series with the contact; under force control the
force history, stick radius and dissipation do not depend on it (a series
spring shears the loop without changing its area), so MDR and FE compare
without a calibration. Displacement-driven loops are compared through the
apparatus, where both laws sit in the same machine.

Choices documented here (the paper's Table 2 loading is F0 = 0.5 N, dF = 0.1 N,
mu1 = 0.2, mu2 = 0.1, u_A = 150 nm):

- geometry series: the Table 2 normal load (alpha = 0) with a tangential force
  amplitude of 0.06 N, i.e. 3/4 of the smallest friction limit mu (F0 - dF) and
  1/2 of the largest: partial slip, where the profile shapes loops and stick
  zones (at 150 nm driven directly every profile is in gross slip, which
  compares nothing but mu);
- apparatus k_x series: truncated sphere b = 10 um (Fig. 9's first profile)
  at the Table 2 point;
- Figs. 4-7: the four experiments of ``studies.study.LOOP_CASES`` (k_x = 1.9 N/um,
  b = 0.6 mm from Table 1, dF = 0.1 F0 / 0.5 N);
- half-space validity: the sphere under the closed-form load case with the
  block and the indenter cap shrunk towards the contact radius.
"""
from __future__ import annotations

import hashlib
import json
import math
from dataclasses import asdict, dataclass, field, replace
from functools import cached_property
from pathlib import Path

from common.errors import InputError
from mdr.loading import Loading
from mdr.paper import B_TABLE1, R_INDENTER, STEEL_E, STEEL_NU

R_IND = R_INDENTER
STEEL = {"E1": STEEL_E, "nu1": STEEL_NU, "E2": STEEL_E, "nu2": STEEL_NU}
FE_LEVELS = (1 / 20, 1 / 40, 1 / 80)          # h_contact = element size / a_ref
FE_LEVELS_FINE = (1 / 40, 1 / 80, 1 / 160)     # where a/20 is not yet in the asymptotic range
FE_LEVELS_QUICK = (1 / 20, 1 / 40, 1 / 80)
#: the 3D half model (fem.solid3d.law), h_contact = h / a_ref. On this ladder the sphere's 3D contact
#: edge, read from the vertices, is 1.4 % inside Hertz's with a non-monotone spread of 0.6 % (its
#: pressure_radius is within 0.15 % of MDR's from a/7 on), and its dissipation within a
#: few %: a direct verdict against MDR would blame MDR for the 3D model's resolution. The 3D scene
#: (``assumptions-3d``) therefore compares the 3D model with itself on each mesh, one assumption
#: relaxed against imposed, where the shared discretisation error cancels
FE_LEVELS_3D = (0.2, 0.14, 0.1)
#: the 3D families run each 3D run past its scene's cycles until its dissipation settles to this
#: fraction per cycle, at most ``SETTLE_MAX_CYCLES`` (``fem.contact_run.drive_3d``'s ``settle``): the
#: 3D cycles settle geometrically, the coupled steel/aluminium pair over ~15-20 cycles
#: (``common.ladder.settling_error`` turns the last change into the error bar of the stationary cycle)
SETTLE_TOL_3D = 1e-4
SETTLE_MAX_CYCLES = 24
FE_MODELS = ("axisym", "3d")
#: the assumptions of Mindlin's theory (and MDR) a 3D scene can relax, one per variant: the
#: tangential traction along x, and no normal-tangential coupling of a dissimilar pair
ASSUMPTIONS_3D = ("direction", "coupling")
#: the tilt family (``tilt``): the 3D model's coarse levels (a tilt sweep of ~25 runs per level); the
#: effect of a tilt is measured against the aligned run on the same mesh, where the mesh error cancels
TILT_LEVELS_3D = (0.3, 0.2)
#: the paper's bound on the tilt of its flat faces (rad): pi / 3600, 0.05 degrees
TILT_BOUND = 3.141592653589793 / 3600
#: the flat punch's mesh per level of ``TILT_LEVELS_3D``: a ball of radius 0.8 b at its loaded edge
#: (-b, 0) refined to half the level's size (``FEContact3D`` ``refine``; the ball covers the whole
#: edge crescent at pi/3600, ``tests/test_punch3d.py``)
TILT_REFINE_PUNCH = tuple((-1.0, h / 2, 0.8) for h in TILT_LEVELS_3D)
#: the truncated sphere b = 0.6 mm at pi/3600 (274 theta_c): its own row on two meshes (h = 0.3 b)
#: banded along the loaded rim arc, band_h = b/33 and b/50 (``FEContact3D`` ``band``: (h, width,
#: angle, growth); the edge crescent reaches r = 0.96 b and |phi - pi| = 0.35 rad,
#: ``tests/test_punch3d.py``), the aligned face on the same meshes
TILT_BAND_LEVELS = (0.3, 0.3)
TILT_BAND = ((0.03, 0.06, 0.45, 1.0), (0.02, 0.06, 0.45, 1.0))
#: the smallest face a tilted point in the apparatus resolves (``validation.families.points.tilt_member``),
#: in elements of the finest 3D level over the contact radius (the 1 um faces of Fig. 8 are a quarter of
#: one: not measured)
TILT_MIN_FACE_ELEMENTS = 2.0
#: the 3D levels (h_contact / a_ref) of the 3D points scenes (``direction-points``, ``tilt-points``, a
#: rig's): the effect on one mesh cancels the error the two runs share, so two coarse levels resolve it
#: (measured: the traction direction at most 1e-4 of the slip index with its error bar, 100 times below
#: the budget's resolution)
DIRECTION_LEVELS_3D = (0.2, 0.14)
MDR_CELLS = (25, 100, 400, 1600)
MDR_CELLS_QUICK = (100, 400, 1600)
DRIVES = ("force", "displacement", "apparatus")
#: the catalogue's plastic rough surfaces are flattened by a first loading to this normal force (N):
#: above the largest of the paper's experiments (F0 + dF = 1.2 F0 = 0.73 N in Fig. 5; the budget checks
#: every point against it) and within the rough scene's force-approach curves (to 1.5 F0 = 0.75 N)
ROUGH_PRELOAD = 0.75
#: the rough flat faces (scene ``roughness-faces``): the face radii run (the budget's points with a face
#: beyond the sphere's contact), those run with plastic asperities too, and their grids: a period of 4
#: smooth contact radii (b = 100 um: the ensemble mean at 8 radii is the same within its spread, 0.148
#: against 0.140 of the apparatus slip index over 6 surfaces), 256-512 pixels, cut off at 8 pixels of the
#: coarsest grid (where the apparatus slip index of every surface is converged within 0.02 from 256 on)
ROUGH_FACES_B = (50e-6, 100e-6, B_TABLE1, 1e-3)
ROUGH_FACES_B_PLASTIC = (100e-6, B_TABLE1)
#: the paper's own roughness of a face's contact: the turned face's 2 um with the block's 3 um, combined
#: sqrt(2^2 + 3^2) = 3.6 um (Willert 2023, Section 2), on every face, and plastic on those run plastic
ROUGH_FACE_PAPER_RMS = 3.6e-6
#: the paper's combined roughness of the sphere's contact: the sphere's 1 um with the block's 3 um,
#: sqrt(1^2 + 3^2) = 3.2 um (Willert 2023, Section 2); its contact touches few pixels: grids of 384-768
#: pixels over the same 32 Hertz radii, the same band of wavelengths as rms 1 um (cut off at 12 pixels of
#: the coarsest grid = 4 of 128: 27 um), where the apparatus slip index of a surface changes by 0.001 from
#: 512 to 768 pixels (and by 0.03 from 256 to 512)
ROUGH_SPHERE_PAPER_RMS = 3.2e-6
ROUGH_SPHERE_PAPER_GRIDS, ROUGH_SPHERE_PAPER_SHORT = (384, 512, 768), 12.0
ROUGH_FACE_PERIOD, ROUGH_FACE_GRIDS, ROUGH_FACE_SHORT = 4.0, (256, 384, 512), 8.0


#: the scene families (``Scene.family``), each a module of ``validation.families`` (how it runs, its
#: table, its figure), and the key each family's variants hold (the pair has none)
FAMILIES = {"pair": None, "validity": ("block", "cap"), "curvature": ("a_over_R",), "assumptions3d": ("relax",),
            "tilt": ("tilts",), "roughness": ("rms", "maps"), "points": ("kx",)}

#: What "MDR holds" claims, beyond both models' own error bars (the verdict of a metric is
#: |MDR - FE| <= FE error + MDR error + tolerance). The half-space assumptions themselves
#: cost less than this where they hold: for R = 6 mm (a/R ~ 0.5 %) the cap's curvature
#: changes the dissipation by about +0.1 % (the validity-curvature scene measures it) and the contact radius by < 0.05 %; bodies of
#: 10 contact radii or more by < 0.1 %. Radii are relative to the FE contact radius (a stick
#: radius of 0 compares in absolute terms), the dissipation relative to the FE dissipation,
#: profiles as relative L2 norm, loops as the largest difference over mu F0 (F_x) or u_A (du),
#: the slip index relative to the FE slip index (it is the dissipation over 4 mu u_A F0: the
#: dissipation's tolerance). Each has its origin in ``TOLERANCE_ORIGINS``.
TOLERANCES = {
    "contact_radius": 0.002,
    "stick_radius": 0.01,
    "dissipation": 0.005,
    "slip_index": 0.005,
    "pressure_profile": 0.01,
    "traction_profile": 0.02,
    "loop_Fx": 0.01,
    "loop_du": 0.01,
}
#: where each tolerance comes from (the report prints them beside the verdicts)
TOLERANCE_ORIGINS = {
    "contact_radius": "relative to the FE contact radius; the half-space's own error at R = 6 mm and bodies of "
                      "10 a or more is < 0.05 % (curvature) and < 0.1 % (size): 2x the larger",
    "stick_radius": "relative to the FE contact radius; the stick edge is resolved to about 1/80 of a (a/80 "
                    "meshes): about one element",
    "dissipation": "relative to the FE dissipation; curvature a/R = 0.5 % costs about +0.1 % (validity-curvature), bodies of 10 a "
                   "< 0.1 %: 2x their sum; floor 1e-4 x 4 mu F0 u_A where a loop hardly dissipates "
                   "(then 'below resolution', never 'holds')",
    "slip_index": "relative to the FE slip index (dW / (4 mu u_A F0)): the dissipation's tolerance and floor",
    "pressure_profile": "relative L2 on 0.95 a; the kink ring of a truncated sphere excluded: 2x the FE a/40 "
                        "error against Hertz",
    "traction_profile": "relative L2 on 0.95 a at the peak; the traction is singular at a flat edge: 2x the "
                        "FE a/40 error against Cattaneo-Mindlin",
    "loop_Fx": "largest F_x difference over mu F0: 1 %, the resolution of a loop read from a figure",
    "loop_du": "largest du difference over u_A: 1 %, as loop_Fx",
}
#: a loop that hardly dissipates compares its dissipation in absolute terms: the tolerance
#: is at least this fraction of the gross-slip scale 4 mu F0 u_A
DISSIPATION_FLOOR = 1e-4
PROFILES = ("sphere", "truncated", "flat")


@dataclass(frozen=True)
class Scene:
    """One comparison (SI units). See the module docstring for the loading conventions.

    ``fe_model``: "axisym" (Fourier modes 0 + 1 on one r-z mesh: exact for an
    axisymmetric body under a tangential load with linear elasticity and
    Mindlin's uncoupled friction) or "3d" (``fem.solid3d.law``: the half model with a
    two-component traction of free direction, displacements in the half-space comparable
    contact measure as the axisymmetric model's; any drive, in the apparatus through the
    law's trial steps, ``FEContact3D.prepare``; no such scene in the catalogue, for its cost).
    ``variants``: of validity scenes mesh size overrides as multiples of a_ref, e.g.
    ``{"block": 5.0}``; of the 3D assumptions scene ``{"relax": ...}``; of the tilt family
    ``{"profile", "b", "tilts"}`` (rad) and optionally ``"fe_levels"``, ``"refine"`` and ``"band"``:
    one ``FEContact3D`` ``refine`` (x, h, radius) / a_ref, or ``band`` (h, width, angle[, growth]),
    per FE level (the loaded edge refined: a ball, a band along the rim arc; the aligned face and
    every tilt share each level's mesh).
    ``family`` (``FAMILIES``): how the scene runs and reports, a module of ``validation.families``:
    ``pair`` (MDR against the FE model, both ladders; no variants), ``validity`` (the FE bodies
    shrunk), ``curvature`` (a/R swept), ``points`` (the paper's apparatus points, variants holding a
    ``validation.paper_points.Point``'s fields: ``kx`` and any of ``b``, ``F0``, ``dF``, ``ua``, ``mu1``, ``mu2``; on a 3D scene's face a ``tilt`` in rad, the face tilted against aligned instead of the traction direction), ``assumptions3d`` (Mindlin's assumptions relaxed in 3D), ``tilt`` (the flat face tilted),
    ``roughness`` (rough surfaces); each variant of a family holds its key (``FAMILIES``).
    ``tolerance``: overrides of ``TOLERANCES`` for this scene (none in the catalogue).
    """

    name: str
    title: str
    profile: str
    b: float = 0.0
    R: float = R_IND
    mu: float = 0.2
    F0: float = 0.5
    dF: float = 0.1
    alpha: float = 0.0
    drive: str = "force"
    amplitude: float = 0.06
    kx: float | None = None
    mu2: float = 0.1
    #: the apparatus's fields other than kx and mu2, (name, value) pairs of ``mdr.apparatus.Apparatus``
    #: (its plates, bedding, masses); () its defaults
    apparatus: tuple = ()
    cycles: int = 3
    steps: int = 200
    E1: float = STEEL["E1"]
    nu1: float = STEEL["nu1"]
    E2: float = STEEL["E2"]
    nu2: float = STEEL["nu2"]
    fe_model: str = "axisym"
    fe_levels: tuple = FE_LEVELS
    mdr_cells: tuple = MDR_CELLS
    variants: tuple = ()
    family: str = "pair"
    group: str = "geometry"
    quick: bool = False
    tolerance: dict = field(default_factory=dict)
    notes: str = ""

    def __post_init__(self):
        self._check_numbers()
        if self.profile not in PROFILES:
            raise InputError(f"profile must be one of {', '.join(PROFILES)}; got {self.profile!r}")
        if self.fe_model not in FE_MODELS:
            raise InputError(f"fe_model must be one of {', '.join(FE_MODELS)}; got {self.fe_model!r}")
        if self.drive not in DRIVES:
            raise InputError(f"drive must be one of {', '.join(DRIVES)}; got {self.drive!r}")
        if self.drive == "apparatus" and not (self.kx and self.kx > 0):
            raise InputError(f"scene {self.name}: kx must be > 0 for drive='apparatus', got {self.kx!r}")
        if self.apparatus:
            self._check_apparatus()
        if len(self.fe_levels) < 1 or len(self.mdr_cells) < 1:
            raise InputError(f"scene {self.name}: fe_levels and mdr_cells must not be empty")
        if self.family not in FAMILIES:
            raise InputError(f"scene {self.name}: family must be one of {', '.join(FAMILIES)}; got {self.family!r}")
        keys = FAMILIES[self.family]
        if keys is None and self.variants:
            raise InputError(f"scene {self.name}: variants need a family ({', '.join(f for f in FAMILIES if FAMILIES[f])})"
                             f"; family 'pair' has none")
        if keys is not None and (not self.variants or any(not set(keys) & set(v) for v in self.variants)):
            raise InputError(f"scene {self.name}: family {self.family!r} needs variants, each holding "
                             f"{' or '.join(keys)}")
        self.typed_variants  # each variant checked once by its family's Variant (then kept)
        unknown = set(self.tolerance) - set(TOLERANCES)
        if unknown:
            raise InputError(f"scene {self.name}: unknown tolerance metric(s) {', '.join(sorted(unknown))}; "
                             f"valid: {', '.join(TOLERANCES)}")

    @cached_property
    def typed_variants(self) -> tuple:
        """The variants checked and converted by the family's own ``Variant`` (``Variant.of(v, scene)``: a
        frozen dataclass; an ``InputError`` naming the scene, the key and its range), once per scene."""
        if not self.variants:
            return ()
        import importlib

        # the family's module by its name (``FAMILIES``): the families stand on this module, not it on them
        family = importlib.import_module(f"{__package__}.families.{self.family}")
        return tuple(family.Variant.of(v, self) for v in self.variants)

    def _check_apparatus(self):
        """``apparatus`` as (name, value) pairs of ``mdr.apparatus.Apparatus`` other than kx and mu2, the
        apparatus they make valid (its own checks)."""
        from dataclasses import fields as fields_

        from mdr.apparatus import Apparatus

        valid = tuple(f.name for f in fields_(Apparatus) if f.name not in ("kx", "mu2"))
        try:
            kw = dict(self.apparatus)
        except (TypeError, ValueError):
            kw = None
        if kw is None or set(kw) - set(valid):
            raise InputError(f"scene {self.name}: apparatus must be (name, value) pairs of {', '.join(valid)}; got "
                             f"{self.apparatus!r}")
        try:
            Apparatus(kx=self.kx or 1.0, mu2=self.mu2, **kw)
        except (InputError, TypeError, ValueError) as e:
            raise InputError(f"scene {self.name}: apparatus: {e}") from None

    def apparatus_of(self):
        """The scene's ``mdr.apparatus.Apparatus``: its kx, mu2 and ``apparatus`` fields."""
        from mdr.apparatus import Apparatus

        return Apparatus(kx=self.kx, mu2=self.mu2, **dict(self.apparatus))

    def _check_numbers(self):
        """Every number in its valid range, the error naming the scene, the field and the range (a scene
        from a user's file, ``validation.scene_file``, is checked here, once, before any work)."""
        def check(field_, ok, rng):
            v = getattr(self, field_)
            try:
                good = ok(v)
            except (TypeError, ValueError):
                good = False
            if not good:
                raise InputError(f"scene {self.name}: {field_} must be {rng}, got {v!r}")

        fin = math.isfinite
        check("R", lambda v: fin(v) and v > 0, "> 0 (m)")
        check("b", lambda v: fin(v) and v >= 0 and (self.profile != "truncated" or v < self.R)
              and (self.profile != "flat" or v > 0), "in [0, R) (m; > 0 for a flat punch)")
        check("mu", lambda v: fin(v) and v >= 0, ">= 0")
        check("mu2", lambda v: fin(v) and v >= 0, ">= 0")
        check("F0", lambda v: fin(v) and v > 0, "> 0 (N)")
        check("dF", lambda v: fin(v) and 0 <= v < self.F0, "in [0, F0) (N)")
        check("alpha", lambda v: fin(v), "finite (rad)")
        check("amplitude", lambda v: fin(v) and v > 0, "> 0 (N for drive 'force', m otherwise)")
        check("cycles", lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 3,
              "an integer >= 3 (two closed cycles after the one from rest: the last is compared with the one "
              "before, common.ladder.settling_error)")
        check("steps", lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 8 and v % 4 == 0,
              "a multiple of 4, >= 8 (steps per cycle: the load reversals are sampled)")
        if self.drive == "force":
            check("amplitude", lambda v: v < self.mu * (self.F0 - self.dF),
                  f"below the friction limit mu (F0 - dF) = {self.mu * (self.F0 - self.dF):.4g} N (drive 'force')")
        for e in ("E1", "E2"):
            check(e, lambda v: fin(v) and v > 0, "> 0 (Pa)")
        for n in ("nu1", "nu2"):
            check(n, lambda v: fin(v) and -1 < v < 0.5, "in (-1, 0.5)")
        # non-increasing: a banded tilt row refines its band at one coarse size (0.3, 0.3); each size in the
        # range the scene's FE model meshes (checked here, before any work)
        from meshes.axisym import H_CONTACT_RANGE
        from meshes.half3d import H_CONTACT_3D_RANGE

        lo, hi = H_CONTACT_3D_RANGE if self.fe_model == "3d" else H_CONTACT_RANGE
        check("fe_levels", lambda v: len(v) >= 1 and all(fin(x) and lo <= x <= hi for x in v)
              and all(a >= b for a, b in zip(v, v[1:])),
              f"a non-increasing list of element sizes / a in [{lo:g}, {hi:g}] (the {self.fe_model} model's range)")
        check("mdr_cells", lambda v: len(v) >= 1 and all(isinstance(x, int) and x >= 4 for x in v)
              and all(a < b for a, b in zip(v, v[1:])), "an increasing list of integers >= 4 (MDR cells)")

    @property
    def loading(self) -> Loading:
        """The scene's load (``mdr.loading.Loading``): F_N, the tangential amplitude in the unit of its
        ``drive``, the time grid."""
        return Loading(self.F0, self.amplitude, self.drive, self.dF, self.alpha, self.cycles, self.steps)

    def tolerances(self) -> dict:
        """The tolerance of every metric (``TOLERANCES`` with this scene's overrides)."""
        return {**TOLERANCES, **self.tolerance}

    @property
    def closed_form(self) -> str | None:
        """Which closed form applies to the whole scene (None: compare with the finest FE)."""
        if self.drive == "apparatus" or self.dF != 0:
            return None
        if self.profile == "sphere":
            return "hertz-mindlin"
        if self.profile == "flat":
            return "flat-punch"
        return None

    def as_dict(self) -> dict:
        d = asdict(self)
        if not self.apparatus:  # the default apparatus: the record (and its fingerprint) as before the field
            d.pop("apparatus")
        else:
            d["apparatus"] = [list(x) for x in self.apparatus]
        d["fe_levels"] = list(self.fe_levels)
        d["mdr_cells"] = list(self.mdr_cells)
        d["variants"] = [dict(v) for v in self.variants]
        return d

    def fingerprint(self, code_version: str) -> str:
        """Hash of the scene's inputs and the code version (a rerun skips unchanged scenes); the files a
        scene reads (a rough variant's measured ``maps``) by their content, so an edited map reruns."""
        files = {}
        for v in self.variants:
            for f in v.get("maps", ()):
                try:
                    files[str(f)] = hashlib.sha256(Path(f).read_bytes()).hexdigest()
                except OSError:
                    files[str(f)] = None
        blob = json.dumps({"scene": self.as_dict(), "code": code_version, "files": files}, sort_keys=True,
                          default=str)
        return hashlib.sha256(blob.encode()).hexdigest()[:16]

    def quick_version(self) -> "Scene":
        """Coarser ladders and fewer steps (``--quick``): same physics, larger own errors."""
        # a one-level scene (validity: every variant against the default at one mesh) keeps its level
        return replace(self, fe_levels=FE_LEVELS_QUICK if self.fe_model == "axisym" and len(self.fe_levels) > 1
                       else self.fe_levels,
                       mdr_cells=MDR_CELLS_QUICK, steps=min(self.steps, 80), cycles=min(self.cycles, 3))


def tilt_critical(F, b, E_star) -> float:
    """The tilt (rad) at which a rigid flat circular punch of radius b under the central force F
    starts to lose contact at its trailing edge, F / (4 E* b^2) (Johnson 1985, Contact
    Mechanics, sec. 5.2). For a truncated sphere the same formula with its face radius b is the
    scale of the tilt (not a threshold: the spherical part keeps contact beyond the face)."""
    return F / (4.0 * E_star * b * b)


def tilt_sweep(b, ratios, F0=0.5) -> tuple:
    """Tilts (rad) of the tilt family for face radius b: ``ratios`` x theta_c (steel on steel at F0)
    below the paper's bound ``TILT_BOUND``, and the bound itself."""
    from mdr.materials import Materials

    thc = tilt_critical(F0, b, Materials(**STEEL).E_star)
    return tuple(sorted({float(r * thc) for r in ratios if r * thc < TILT_BOUND} | {TILT_BOUND}))


def a_ref(scene: Scene, b: float | None = None) -> float:
    """Half-space contact radius at the largest normal force (the FE mesh's a_ref); ``b``: of the scene's
    indenter with that face radius instead (0: the sphere)."""
    from fem.axisym.normal_run import reference_radius
    from mdr.materials import Materials

    E_star = Materials(scene.E1, scene.nu1, scene.E2, scene.nu2).E_star
    profile, b = (scene.profile, scene.b) if b is None else ("truncated" if b > 0 else "sphere", float(b))
    return reference_radius(profile, scene.R, b, scene.F0 + scene.dF, E_star)
