"""The error budget of a rig of one's own (``validation.rig.Rig``): the scenes that measure its cells,
generated from the rig (``scenes``), and the budget's inputs (``inputs``).

Each cell takes the cheapest model that measures it at the rig's points:

- *half-space size* (``<name>-validity``, family ``validity``): the axisymmetric FE model with the cap
  and the block at the rig's sizes over the largest contact radius of its points, against the default
  bodies (200 a) on the same mesh, under force control at that point's load and face (the sphere where
  the face is the whole contact, which sticks at that mesh; force amplitude half its smallest friction
  limit, partial slip); a bound at every point (smaller contacts see larger bodies);
- *curvature* (``<name>-points``, family ``points``, axisymmetric): every point in the apparatus, the FE
  model (the cap's real sphere) against MDR on both ladders;
- *traction direction* (``<name>-direction``, family ``points``, 3D): every point in the apparatus, the
  traction of free direction against along x on the same mesh;
- *coupling* (``<name>-coupling``, family ``assumptions3d``; only for a dissimilar pair, Dundurs' beta
  not 0): the 3D model with the normal-tangential coupling against without, on the same mesh, under
  force control (``SHARE_3D`` of the friction limit) at each load (F0, dF, mu1) of the rig's points (one scene per load, ``-1``, ``-2``, ...
  where there are several), per face radius of its points there;
- *tilt* (``<name>-tilt``, family ``points``, 3D; only where the rig states a bound and a point has a
  face of at least ``TILT_MIN_FACE_ELEMENTS`` elements): every face point in its apparatus, tilted by the
  bound against aligned on the same mesh; a face that is the whole contact with its loaded edge refined as
  the catalogue's rows resolve it (``families.tilt.edge_variant``);
- *kink*, *plates*: MDR in the rig's apparatus (``validation.budget_cells.kink_cell``,
  ``validation.budget_plates.cell``), computed by the budget itself;
- *roughness*: no scene: the budget runs the readings of the rig's rms values on its rough contacts
  (``rough_contacts``, ``validation.spectra``) and what the equivalent profile misses of the rough
  half-space in its apparatus (``validation.rig_roughness``), both cached under ``--out``/readings.

The scenes in the apparatus run in the rig's (k_x, mu2 and its other fields: ``Scene.apparatus``). The
store skips a scene whose fingerprint (its data and the code) is unchanged, so a field edited in the rig
file reruns only the scenes it enters.
"""
from __future__ import annotations

from dataclasses import asdict

from common.errors import InputError

from .budget_cells import Inputs
from .paper_points import Setup, contact_radius, tiltable
from .scenes import DIRECTION_LEVELS_3D, FE_LEVELS_3D, Scene



def setup_of(rig) -> Setup:
    """The rig's indenter radius, materials and apparatus fields other than k_x; the contact's height above
    the bedding (``Apparatus.h``) is the block's height where it differs from the apparatus's default."""
    from mdr.apparatus import Apparatus

    app = {k: v for k, v in rig.apparatus.items() if k != "kx"}
    if rig.bodies.block_height != Apparatus.h:
        app["h"] = rig.bodies.block_height
    return Setup(rig.indenter.R, rig.materials, tuple(sorted(app.items())))


def _bodies(rig) -> tuple:
    """(cap, block) (m): the indenter's height above the contact where it is lower than the sphere's
    radius, else infinite (the FE model's cap is the sphere up to its equator: its finite size is in
    the curvature cell); the block's smaller extent, its height or half its width."""
    b = rig.bodies
    return (b.cap_height if b.cap_height < rig.indenter.R else float("inf"),
            min(b.block_height, 0.5 * b.block_width))


def _base(rig) -> dict:
    """The fields every scene of the rig shares: its indenter, materials and loading."""
    m, L = rig.materials, rig.loading
    return dict(profile="truncated" if rig.indenter.b > 0 else "sphere", b=rig.indenter.b, R=rig.indenter.R,
                E1=m.E1, nu1=m.nu1, E2=m.E2, nu2=m.nu2, F0=L["F0"], dF=L["dF"], mu=L["mu1"], mu2=L["mu2"])


#: the force amplitude of the coupling's 3D scenes under force control over the smallest friction limit
#: mu1 (F0 - dF): the catalogue's (0.06 N at Table 2's load), so that the paper's rig runs its rows; 0.75
#: keeps partial slip
SHARE_3D = 0.75

def _whole_contact(p, setup) -> bool:
    """Whether the point's face is its whole contact (the contact radius within 0.1 % of b: a flat
    punch's; the sphere's annulus beyond it carries next to nothing)."""
    return p.b > 0 and contact_radius(p, setup) <= p.b * (1 + 1e-3)


def _check(rig, a: float) -> None:
    """What the generated scenes need of the rig, refused in its own terms (InputError naming the file,
    the table and the field): bodies larger than ``VALIDITY_MIN_SIZE`` contact radii of its largest point
    (``a``), and for a dissimilar pair (whose coupling the 3D model measures per face) faces below R/2."""
    from .families.validity import VALIDITY_MIN_SIZE

    where = rig.source or rig.name
    if abs(rig.materials.dundurs_beta) >= 1e-12:
        big = [p.b for p in rig.points() if p.b >= 0.5 * rig.indenter.R]
        if big:
            raise InputError(f"{where}: a face radius b must be below R/2 = {0.5 * rig.indenter.R:g} m for a dissimilar "
                             f"pair (the 3D model measures its coupling), got {big[0]:g} m ([indenter] b or a "
                             "[[result]] point's b)")
    b = rig.bodies
    for field, size in (("block_height", b.block_height), ("block_width", 0.5 * b.block_width),
                        ("cap_height", b.cap_height)):
        if size <= VALIDITY_MIN_SIZE * a:
            half = " / 2" if field == "block_width" else ""
            raise InputError(f"{where}: [bodies] {field}{half} must exceed {VALIDITY_MIN_SIZE:g} contact radii of the "
                             f"rig's largest contact (> {VALIDITY_MIN_SIZE * a:.4g} m, a = {a:.4g} m), got {size:.4g} m")


def scenes(rig) -> tuple:
    """The scenes that measure the rig's cells (module docstring), in the order of the budget's columns;
    InputError where the rig's bodies or faces are out of their reach (``_check``)."""
    from .families.validity import VALIDITY_DEFAULT_SIZE

    setup, base, points = setup_of(rig), _base(rig), rig.points()
    name = rig.name
    out = []
    largest = max(points, key=lambda p: contact_radius(p, setup))
    a = contact_radius(largest, setup)
    _check(rig, a)
    inp_cap, inp_block = _bodies(rig)
    sizes = {"cap": inp_cap / a, "block": inp_block / a}
    variant = {k: x for k, x in sizes.items() if x < VALIDITY_DEFAULT_SIZE}
    if variant:  # at the largest contact's load, its face where it slips (the sizes in its contact radii)
        face = largest.b > 0 and not _whole_contact(largest, setup)
        at = {**base, "profile": "truncated" if face else "sphere", "b": largest.b if face else 0.0,
              "F0": largest.F0, "dF": largest.dF, "mu": largest.mu1}
        out.append(Scene(f"{name}-validity", f"{rig.title or name}: the bodies' size", **at, drive="force",
                         amplitude=0.5 * largest.mu1 * (largest.F0 - largest.dF), fe_levels=(1 / 40,),
                         mdr_cells=(400,), variants=(variant,), family="validity", group="validity",
                         notes="The rig's cap and block over the largest contact radius of its points (in units of "
                               "this scene's contact radius), against the default 200 a bodies on the same mesh "
                               "(h = a/40), force control at that point's load and face; where the face is the "
                               "whole contact (which sticks at this mesh under half the friction limit) the sphere "
                               "at that load, whose size effect at the same ratio of body to contact is taken as "
                               "the face's (as the paper's budget takes its sphere's sweep)."))
    apparatus = dict(drive="apparatus", amplitude=rig.loading["ua"], kx=float(rig.apparatus["kx"]),
                     apparatus=setup.apparatus, family="points")
    variants = tuple(asdict(p) for p in points)
    out.append(Scene(f"{name}-points", f"{rig.title or name}: the half-space at the points", **base, **apparatus,
                     cycles=4, steps=120, variants=variants, group="validity",
                     notes="Every point of the rig in its apparatus: the axisymmetric FE model against MDR."))
    out.append(Scene(f"{name}-direction", f"{rig.title or name}: the traction direction at the points", **base,
                     **apparatus, cycles=3, steps=60, fe_model="3d", fe_levels=DIRECTION_LEVELS_3D,
                     variants=variants, group="3d",
                     notes="Every point of the rig in its apparatus: the 3D model, traction free against along x."))
    loads = sorted({(p.F0, p.dF, p.mu1) for p in points}) if abs(rig.materials.dundurs_beta) >= 1e-12 else []
    for k, (F0, dF, mu1) in enumerate(loads):  # the coupling of a dissimilar pair, per load
        tag = "" if len(loads) == 1 else f"-{k + 1}"
        at = {**base, "F0": F0, "dF": dF, "mu": mu1}
        load = dict(drive="force", amplitude=SHARE_3D * mu1 * (F0 - dF), fe_model="3d", group="3d")
        where = f"force control at F0 = {F0:g} N, dF = {dF:g} N, mu1 = {mu1:g}"
        bs = sorted({p.b for p in points if (p.F0, p.dF, p.mu1) == (F0, dF, mu1)})
        out.append(Scene(f"{name}-coupling{tag}", f"{rig.title or name}: the normal-tangential coupling",
                         **{**at, "profile": "sphere", "b": 0.0}, **load, fe_levels=FE_LEVELS_3D, cycles=4,
                         steps=60, family="assumptions3d",
                         variants=tuple({"relax": "coupling", **({"b": b} if b else {})} for b in bs),
                         notes="The 3D model with the coupling of the rig's pair against without, on the same "
                               f"mesh, {where}, per face radius of its points there."))
    faces = [p for p in points if tiltable(p, setup)]
    if rig.tilt and faces:
        out.append(Scene(f"{name}-tilt", f"{rig.title or name}: the face tilted by its bound at the points", **base,
                         **apparatus, cycles=3, steps=40, fe_model="3d", fe_levels=DIRECTION_LEVELS_3D,
                         variants=tuple({**asdict(p), "tilt": rig.tilt} for p in faces), group="3d",
                         notes="Every face of the rig's points (of at least two elements of the 3D mesh) in its "
                               "apparatus: the 3D model with the face tilted by the rig's bound against aligned on "
                               "the same mesh; a face that is the whole contact with its loaded edge refined as the "
                               "catalogue's rows resolve its edge crescent (a ball, or a band along the rim arc far "
                               "beyond theta_c)."))
    return tuple(out)


def inputs(rig) -> Inputs:
    """The budget's inputs of the rig: its setup, bodies, bounds, results, resolution and ``scenes``;
    InputError for a flat punch (the budget's points are the sphere and the truncated sphere)."""
    if rig.indenter.profile == "flat":
        raise InputError(f"{rig.source or rig.name}: [indenter] profile flat: the budget runs the sphere and the truncated "
                         "sphere (a flat punch is the truncated sphere of a large R)")
    return Inputs(rig.name, setup_of(rig), *_bodies(rig), rig.indenter.kink_rounding, rig.tilt, rig.results,
                  rig.resolution, scenes(rig), rough_contacts(rig),
                  rerun=f"python -m validation.budget --scene-file {rig.source or 'RIG.toml'}", loops=rig.loops)


def rough_contacts(rig) -> tuple:
    """The rough contacts of the rig's points and measured loops (``validation.spectra``: the sphere's, and
    each face's that reaches into the sphere's contact, ``paper_points.rough_row_b``) with its R, materials and stated rms
    heights and hardness (none stated: elastic readings only), at the reference load F_ref: the rig's own F0
    (as the paper's contacts take Table 2's), raised where a point's largest force F0 + dF lies above the
    curves' top (``spectra.PRELOAD`` F_ref), each running the stated spectrum's reading where the rig
    states one (``stated``); () where it states no rms."""
    from . import spectra as SP
    from .paper_points import rough_row_b

    r = rig.roughness
    if not (r.sphere or r.face or r.block or r.maps):
        return ()
    setup = setup_of(rig)
    points = rig.points() + tuple(lp.point for lp in rig.loops)
    m = rig.materials
    kw = dict(R=rig.indenter.R, materials=(m.E1, m.nu1, m.E2, m.nu2),
              rq=(("sphere", r.sphere), ("block", r.block), ("face", r.face)),
              F_ref=max(rig.loading["F0"], max(p.F0 + p.dF for p in points) / SP.PRELOAD),
              hardness=r.hardness)
    bs = sorted({rough_row_b(p, setup) for p in points})
    return tuple(stated(SP.face(b, **kw) if b else SP.sphere(**kw), r, rig.source or rig.name) for b in bs)


def stated(contact, roughness, where: str = "the rig"):
    """The contact running the rig's stated spectrum (``validation.rig.Spectrum``: the waviness's end in
    the contact's smooth radii, ``spectra.Reading.rolloff``) or its measured maps (``validation.rig.Maps``:
    at least 4 smooth contact radii on a side, else InputError) as its one reading, and its plastic twin
    where the contact has a hardness; unchanged where neither is given (the readings of
    ``spectra.READINGS``)."""
    from dataclasses import replace

    from rough.surfaces import covers

    from .spectra import Reading

    spectrum, maps = roughness.spectrum, roughness.maps
    if maps is not None:
        why = covers(maps.pixel * maps.n, contact.a())
        if why:
            raise InputError(f"{where}: [tolerances.roughness.maps] files: the {contact.name()} contact needs {why}")
        r = Reading("measured maps", maps=maps.files, pixel=maps.pixel, n=maps.n, digest=maps.digest)
    elif spectrum is not None:
        rolloff = None if spectrum.rolloff is None else spectrum.rolloff / contact.a()
        r = Reading("stated spectrum", hurst=spectrum.hurst, rolloff=rolloff, profile=spectrum.profile)
    else:
        return contact
    twin = (replace(r, name=f"{r.name}, plastic", plastic=True),) if contact.hardness is not None else ()
    return replace(contact, readings=(r,) + twin)
