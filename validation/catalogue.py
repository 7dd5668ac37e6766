"""The scene catalogue: the data of ``python -m validation.compare`` (``CATALOGUE``, by name) and the
choice of scenes a run takes (``select``). The scene type, its checks, the tolerances and the constants
the scenes share are ``validation.scenes``; each family's runner is ``validation.families``.

The catalogue holds the pair scenes (the textbook cases, the geometry series, the paper's experiments and
apparatus points), the finite bodies' validity, the paper's points in the apparatus, the 3D model's
assumptions and tilts, and the rough surfaces; every scene's notes say what it measures and why its
ladders are what they are.
"""
from __future__ import annotations

from dataclasses import replace

from common.errors import InputError
from mdr.paper import B_TABLE1, DF_OVER_F0, KX_TABLE1, UA_TABLE2
from rough.normal import HARDNESS_X5CRNI18_10
from studies.study import LOOP_CASES

from .scenes import (DIRECTION_LEVELS_3D, FE_LEVELS, FE_LEVELS_3D, FE_LEVELS_FINE, ROUGH_FACE_GRIDS, ROUGH_FACE_PAPER_RMS, ROUGH_FACE_PERIOD,
                     ROUGH_FACE_SHORT, ROUGH_FACES_B, ROUGH_FACES_B_PLASTIC, ROUGH_PRELOAD, ROUGH_SPHERE_PAPER_GRIDS,
                     ROUGH_SPHERE_PAPER_RMS, ROUGH_SPHERE_PAPER_SHORT, TILT_BAND, TILT_BAND_LEVELS, TILT_BOUND,
                     TILT_LEVELS_3D, TILT_REFINE_PUNCH, Scene, tilt_sweep)


def _um(x):
    return f"{x * 1e6:g} um"


def _points_scene(sc: list) -> Scene:
    """The scene ``halfspace-points``: every point of the paper's results (``validation.paper_points``) with a
    face (b > 0) that no apparatus scene of ``sc`` runs; they all lie at Table 2's load."""
    from .paper_points import results

    ran = [s for s in sc if s.drive == "apparatus"]
    base = Scene("halfspace-points", "The half-space at the paper's points: FE against MDR in the apparatus",
                 "truncated", b=B_TABLE1, drive="apparatus", amplitude=UA_TABLE2, kx=KX_TABLE1, cycles=4, steps=120,
                 family="points", group="validity", variants=({"kx": KX_TABLE1},))
    points = []
    for p in (p for r in results() for p in r.points if p.b > 0):
        if any(p.matches(s) for s in ran) or p in points:
            continue
        if not p.matches(replace(base, b=p.b, kx=p.kx)):
            raise RuntimeError(f"point {p} is not at Table 2's load: give it a scene of its own")
        points.append(p)
    return replace(base, variants=tuple({"b": p.b, "kx": p.kx} for p in points),
                   notes="Table 2's load (F0 = 0.5 N, dF = 0.1 N, u_A = 150 nm, mu1 = 0.2, mu2 = 0.1), steel on "
                         "steel, R = 6 mm: the points of Figs. 8-9 and Table 2 (b and k_x) that the experiment and "
                         "apparatus scenes do not run, each through both full ladders as a pair scene. FE - MDR of "
                         "the slip index measures the half-space's shape there (the cap's real sphere, slopes up to "
                         "a/R); the error budget reads it.")


def _direction_points_scene() -> Scene:
    """The scene ``direction-points``: every point of the paper's results (``validation.paper_points``) in the
    3D model, the traction free against along x, each variant the point's own fields."""
    from dataclasses import asdict

    from .paper_points import results

    points = list(dict.fromkeys(p for r in results() for p in r.points))
    return Scene("direction-points", "Mindlin's traction direction at the paper's points: 3D in the apparatus",
                 "truncated", b=B_TABLE1, drive="apparatus", amplitude=UA_TABLE2, kx=KX_TABLE1, cycles=3, steps=60,
                 fe_model="3d", fe_levels=DIRECTION_LEVELS_3D, family="points", group="3d",
                 variants=tuple(asdict(p) for p in points),
                 notes="Every point of the error budget's results (Figs. 4-7 at their loads; Figs. 8-9 and Table 2 "
                       "at Table 2's), steel on steel, R = 6 mm, in the apparatus: the 3D model twice on each mesh, "
                       "the traction of free direction and along x (Mindlin's q_y = 0, as MDR), 3 cycles of 60 "
                       "steps; the effect on the slip index with the error bar of its two-level ladder, of twice "
                       "the steps on the coarser mesh and of its settling. The error budget reads it.")


def _tilt_points_scene() -> Scene:
    """The scene ``tilt-points``: every face of the paper's results in the 3D model tilted by the bound
    pi/3600 against aligned, in its apparatus (the faces it resolves, ``paper_points.tiltable``)."""
    from dataclasses import asdict

    from .paper_points import results, tiltable

    points = [p for p in dict.fromkeys(p for r in results() for p in r.points) if tiltable(p)]
    return Scene("tilt-points", "The face tilted by pi/3600 at the paper's points: 3D in the apparatus",
                 "truncated", b=B_TABLE1, drive="apparatus", amplitude=UA_TABLE2, kx=KX_TABLE1, cycles=3, steps=40,
                 fe_model="3d", fe_levels=DIRECTION_LEVELS_3D, family="points", group="3d",
                 variants=tuple({**asdict(p), "tilt": TILT_BOUND} for p in points),
                 notes="Every face of the error budget's results (b = 10 um and more; Figs. 6-7 at their loads, "
                       "Figs. 8-9 and Table 2 at Table 2's), steel on steel, R = 6 mm, in the apparatus: the 3D "
                       "model twice on each mesh, the face tilted about y by the paper's bound pi/3600 and aligned, "
                       "3 cycles of 40 steps; a face that is the whole contact on the tilt family's meshes (its "
                       "loaded edge refined: a ball, or a band along the rim arc far beyond theta_c). The effect on "
                       "the slip index with the error bar of its two-level ladder, of twice the steps on the "
                       "coarser mesh and of its settling. The error budget reads it.")


def _catalogue() -> dict:
    sc = []
    # closed-form anchor: Hertz + Cattaneo-Mindlin + Mindlin-Deresiewicz (constant F_N)
    sc.append(Scene("sphere-md", "Sphere, constant F_N, partial slip (closed forms)", "sphere", dF=0.0,
                    amplitude=0.5 * 0.2 * 0.5, group="anchor", quick=True,
                    notes="Force amplitude mu F0 / 2. Hertz (1882), Mindlin & Deresiewicz (1953, J. Appl. Mech.) "
                          "hold exactly for this half-space problem."))
    sc.append(Scene("flat-md", "Flat punch b = 50 um, constant F_N (closed forms)", "flat", b=50e-6, dF=0.0,
                    amplitude=0.5 * 0.2 * 0.5, group="anchor",
                    notes="Pressure and traction share the profile 1/sqrt(b^2 - r^2) below mu F_N: full stick, "
                          "no dissipation in the half-space (Mindlin 1949, J. Appl. Mech.)."))
    # geometry series at the Table 2 normal load
    for b in (0.0, 5e-6, 10e-6, 20e-6, 30e-6, 50e-6, 100e-6, 0.6e-3):
        kind = "sphere" if b == 0 else "truncated"
        name = "geom-sphere" if b == 0 else f"geom-b{b * 1e6:g}um"
        # b = 30, 50 um: the contact edge lies within 10 % of the kink r = b, where a/20 does not
        # resolve the edge (non-monotone ladders): refine to a/160 instead
        levels = FE_LEVELS_FINE if b in (30e-6, 50e-6) else FE_LEVELS
        sc.append(Scene(name, f"{'Sphere' if b == 0 else 'Truncated sphere b = ' + _um(b)}, Table 2 load",
                        kind, b=b, quick=(b == 20e-6), group="geometry", fe_levels=levels))
    sc.append(Scene("geom-flat", "Flat punch b = 50 um, Table 2 load", "flat", b=50e-6, group="geometry", quick=True))
    # the paper's experiments (Figs. 4-7) in the apparatus
    for fig, (kind, F0, ua, mu1, mu2) in LOOP_CASES.items():
        b = 0.0 if kind == "sphere" else B_TABLE1
        sc.append(Scene(f"exp-{fig}", f"Experiment {fig[3:]}: {kind}, F0 = {F0} N, u_A = {ua * 1e9:g} nm, "
                        f"mu1 = {mu1}, mu2 = {mu2}", kind, b=b, mu=mu1, mu2=mu2, F0=F0, dF=DF_OVER_F0 * F0,
                        drive="apparatus", amplitude=ua, kx=KX_TABLE1, cycles=4, steps=120, group="experiments",
                        quick=(fig == "fig4")))
    # apparatus stiffness series at the Table 2 point
    for kx in (1e6, 2e6, 10e6, 20e6):
        sc.append(Scene(f"app-kx{kx / 1e6:g}", f"Apparatus k_x = {kx / 1e6:g} N/um, b = 10 um, Table 2 point",
                        "truncated", b=10e-6, drive="apparatus", amplitude=UA_TABLE2, kx=kx, cycles=4, steps=120,
                        quick=(kx == 2e6), group="apparatus"))
    # half-space validity: shrink the block and the cap towards the contact
    variants = tuple({"block": s} for s in (3.0, 5.0, 10.0, 30.0)) + \
        tuple({"cap": s} for s in (3.0, 5.0, 10.0, 30.0)) + tuple({"block": s, "cap": s} for s in (3.0, 10.0))
    sc.append(Scene("validity", "Half-space validity: block and cap size against the contact radius", "sphere",
                    dF=0.0, amplitude=0.5 * 0.2 * 0.5, fe_levels=(1 / 40,), mdr_cells=(400,), variants=variants,
                    family="validity",
                    group="validity",
                    notes="Sizes as multiples of the Hertz contact radius: the block alone (the cap at the "
                          "default 200 a), the cap alone (the block at 200 a), and both; every variant at h = a/40 "
                          "against the default FE model (200 a) at the same mesh size."))
    # half-space validity: the curvature a/R of the sphere (F0 from Hertz at R = 6 mm), three nu
    curvature = tuple({"a_over_R": x, "nu": 0.29} for x in (5e-4, 1.5e-3, 4.6e-3, 1.5e-2, 5e-2)) + \
        tuple({"a_over_R": x, "nu": nu} for nu in (0.1, 0.45) for x in (4.6e-3, 5e-2))
    sc.append(Scene("validity-curvature", "Half-space validity: curvature a/R of the sphere", "sphere", dF=0.0,
                    cycles=3, steps=40, variants=curvature, family="curvature", group="validity",
                    notes="The sphere (R = 6 mm) at constant F_N loaded to a/R = 0.05 .. 5 % (F0 = 4 E* a^3 / (3 R)), "
                          "force amplitude mu F0 / 2 (the closed-form case of sphere-md), both bodies of Poisson "
                          "ratio nu; every variant through the full FE and MDR ladders, so the curvature effect "
                          "(FE extrapolated - MDR) stands with its error bar beside the tolerance."))
    # the half-space at the paper's apparatus points that no scene above runs (the budget's curvature)
    sc.append(_points_scene(sc))
    # Mindlin's traction direction in 3D at every point of the paper's results (the budget's direction)
    sc.append(_direction_points_scene())
    sc.append(_tilt_points_scene())
    sc += _scenes_3d() + _scenes_rough()
    out = {}
    for s in sc:
        if s.name in out:
            raise RuntimeError(f"duplicate scene name {s.name}")
        out[s.name] = s
    return out


def _scenes_3d() -> list:
    """The 3D model's scenes: Mindlin's assumptions relaxed one at a time, the tilted flat faces."""
    sc = []
    # Mindlin's assumptions (shared by MDR and the axisymmetric model), relaxed one at a time in 3D
    sc.append(Scene("assumptions-3d", "Mindlin's assumptions in 3D: traction along x, no normal-tangential coupling",
                    "sphere", fe_model="3d", fe_levels=FE_LEVELS_3D, cycles=4, steps=60, group="3d",
                    family="assumptions3d",
                    variants=({"relax": "direction"}, {"relax": "direction", "b": 20e-6},
                              {"relax": "coupling", "E2": 70e9, "nu2": 0.33}),
                    notes="Table 2 loading (F0 = 0.5 N, dF = 0.1 N, force amplitude 0.06 N). Each variant runs "
                          "twice on every 3D mesh: with the assumption relaxed (a two-component traction of "
                          "free direction; the coupling of steel on an aluminium alloy, Dundurs' beta = +0.11) "
                          "and imposed (q_y = 0; no coupling), the normal load applied with friction active. "
                          "The effect is the difference of the pair, with the error bar of its own ladder."))
    # misalignment: the flat face tilted about y, against the aligned 3D model on the same mesh and MDR
    sc.append(Scene("tilt", "Misalignment: the flat face tilted up to the paper's bound pi/3600", "flat", b=100e-6,
                    fe_model="3d", fe_levels=TILT_LEVELS_3D, cycles=4, steps=40, group="3d", family="tilt",
                    variants=({"profile": "flat", "b": 100e-6, "tilts": tilt_sweep(100e-6, (0.1, 0.2, 0.3, 0.5, 1, 2, 4)),
                               "refine": TILT_REFINE_PUNCH},
                              {"profile": "truncated", "b": 20e-6, "tilts": tilt_sweep(20e-6, (0.03, 0.1, 0.2)),
                               "fe_levels": (0.2, 0.14)},
                              {"profile": "truncated", "b": 0.6e-3,
                               "tilts": tilt_sweep(0.6e-3, (0.1, 0.2, 0.3, 0.5, 1, 3, 10, 30, 100))},
                              {"profile": "truncated", "b": 0.6e-3, "tilts": (TILT_BOUND,),
                               "fe_levels": TILT_BAND_LEVELS, "band": TILT_BAND}),
                    notes="Table 2 loading (F0 = 0.5 N, dF = 0.1 N, mu = 0.2; force amplitude 0.06 N as the "
                          "geometry series), steel on steel, R = 6 mm. theta_c = F0 / (4 E* b^2), the tilted punch's "
                          "loss of full contact at F0 (for the truncated spheres the same formula with b as the "
                          "scale). Every tilt runs on the same 3D mesh as the aligned face (FEContact3D.assuming), "
                          "so the effect of the tilt is free of the mesh error the two share; its error bar is the "
                          "effect's two-level ladder (b = 20 um: h = 0.2, 0.14 a_ref, since at 0.3 a_ref its slip "
                          "annulus is not resolved and the aligned dissipation is 10x off). The rotation is held by "
                          "the mount, the load line through the face centre. The flat punch's mesh is refined at "
                          "its loaded edge (a ball of 0.8 b at half the level's size), which resolves its edge "
                          "crescent up to pi/3600; b = 0.6 mm at pi/3600 has its own row on meshes banded along "
                          "the loaded rim arc (band_h = b/33, b/50), where its edge crescent is resolved. A tilted "
                          "contact of fewer than 10 vertices (half model, at F0) is undetermined."))
    return sc


def _scenes_rough() -> list:
    """The rough surfaces: the sphere's and the flat faces', the rough half-space against MDR."""
    sc = []
    # roughness: the sphere on self-affine surfaces, the rough half-space against MDR (smooth, equivalent)
    sc.append(Scene("roughness", "Rough surfaces: the sphere on self-affine roughness, smooth and equivalent MDR",
                    "sphere", dF=0.0, amplitude=0.5 * 0.2 * 0.5, cycles=3, steps=40, group="rough",
                    family="roughness", fe_levels=(1 / 8,), mdr_cells=(400,),
                    variants=({"rms": 0.0}, {"rms": 30e-9}, {"rms": 100e-9}, {"rms": 1e-6, "period": 32.0, "apparatus": True},
                              {"rms": 1e-6, "period": 32.0, "hardness": HARDNESS_X5CRNI18_10,
                               "preload": ROUGH_PRELOAD, "apparatus": True},
                              {"rms": ROUGH_SPHERE_PAPER_RMS, "period": 32.0, "grids": ROUGH_SPHERE_PAPER_GRIDS,
                               "short": ROUGH_SPHERE_PAPER_SHORT, "apparatus": True},
                              {"rms": ROUGH_SPHERE_PAPER_RMS, "period": 32.0, "grids": ROUGH_SPHERE_PAPER_GRIDS,
                               "short": ROUGH_SPHERE_PAPER_SHORT, "hardness": HARDNESS_X5CRNI18_10,
                               "preload": ROUGH_PRELOAD, "apparatus": True}),
                    notes="Table 2's normal load (F0 = 0.5 N) held, force amplitude mu F0 / 2, mu = 0.2, steel on "
                          "steel, R = 6 mm; the combined roughness of both bodies as one self-affine surface "
                          "(Hurst 0.8, no power beyond a quarter period, cut off at 4 pixels of the coarsest grid), "
                          "4 realisations per rms on grids of 128, 192 and 256 pixels (the smooth sphere: one); "
                          "period 16 Hertz radii (32 at the paper's rms 1 um, its sphere's, whose contact spreads "
                          "over several). The paper's combined roughness of sphere and block, 3.2 um, touches few "
                          "pixels: on grids of 384, 512 and 768 pixels over the same 32 radii, the same wavelengths "
                          "(cut off at 27 um). rms 1 um again with perfectly plastic asperities at the steel's hardness "
                          "(2.1 GPa), flattened at 0.75 N (above the paper's largest load, 0.73 N in Fig. 5) and "
                          "elastic after; 3.2 um too. The rms 1 um and 3.2 um surfaces are also driven by the paper's apparatus at its points "
                          "on the sphere's contact (rough.law; the error budget reads them). "
                          "Needs tamaas (pip install -e '.[rough]')."))
    # the same on the flat faces of the paper's truncated spheres (the budget's points: b = 50 um - 1 mm)
    face = {"rms": 1e-6, "period": ROUGH_FACE_PERIOD, "grids": ROUGH_FACE_GRIDS, "short": ROUGH_FACE_SHORT,
            "apparatus": True}
    plastic = {"hardness": HARDNESS_X5CRNI18_10, "preload": ROUGH_PRELOAD}
    sc.append(Scene("roughness-faces", "Rough flat faces: the truncated sphere on self-affine roughness, smooth and "
                    "equivalent MDR", "truncated", b=B_TABLE1, dF=0.0, amplitude=0.5 * 0.2 * 0.5, cycles=3, steps=40,
                    group="rough", family="roughness", fe_levels=(1 / 8,), mdr_cells=(400,),
                    variants=tuple({"b": b, **face} for b in ROUGH_FACES_B)
                    + tuple({"b": b, **face, **plastic} for b in ROUGH_FACES_B_PLASTIC)
                    + tuple({"b": b, **face, "rms": ROUGH_FACE_PAPER_RMS} for b in ROUGH_FACES_B)
                    + tuple({"b": b, **face, **plastic, "rms": ROUGH_FACE_PAPER_RMS} for b in ROUGH_FACES_B_PLASTIC),
                    notes="As scene roughness, on the truncated sphere (R = 6 mm) with the flat faces of the "
                          "paper's results: b = 50 and 100 um (Figs. 8-9), 0.6 mm (Figs. 6-7, Table 2) and 1 mm "
                          "(Fig. 8), at the sphere's rms 1 um (Hurst 0.8), 4 realisations per face on grids of "
                          "256, 384 and 512 pixels over 4 smooth contact radii, cut off at 8 pixels of the "
                          "coarsest grid (2 % of the period: 75 um on b = 0.6 mm), with no power beyond one contact radius. The faces "
                          "touch at a few asperity clusters: a grid of 128 pixels leaves single-pixel contacts "
                          "whose force-control dissipation jumps by orders of magnitude between grids. b = 100 um "
                          "and 0.6 mm again with perfectly plastic asperities, flattened at 0.75 N, and at the "
                          "paper's own roughness of a face's contact, the turned face's 2 um with the block's 3 um "
                          "(3.6 um combined) on every face, plastic on b = 100 um and 0.6 mm. Every surface is also driven by the paper's apparatus at the points "
                          "of its face (rough.law; the error budget reads them). "
                          "Needs tamaas (pip install -e '.[rough]')."))
    return sc


CATALOGUE = _catalogue()


def select(names=None, quick: bool = False, catalogue: dict | None = None) -> list[Scene]:
    """Scenes by name (comma list or iterable; None: all, or the quick subset), quick ladders if asked;
    from ``catalogue`` (default ``CATALOGUE``; a user's file: ``validation.scene_file``, whose scenes
    all run under ``--quick``)."""
    own = catalogue is not None
    catalogue = CATALOGUE if catalogue is None else catalogue
    if names is None:
        chosen = [s for s in catalogue.values() if s.quick or not quick or own]
    else:
        if isinstance(names, str):
            names = [n.strip() for n in names.split(",") if n.strip()]
        unknown = [n for n in names if n not in catalogue]
        if unknown:
            raise InputError(f"unknown scene name(s) {', '.join(unknown)}; valid scenes: {', '.join(catalogue)}")
        if not names:
            raise InputError("scenes must name at least one scene")
        chosen = [catalogue[n] for n in dict.fromkeys(names)]
    return [s.quick_version() for s in chosen] if quick else chosen
