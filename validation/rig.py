"""A fretting rig as typed data: what an error budget of one's own rig starts from (``load_rig``).

A rig file (TOML, SI units) describes the indenter, the two bodies' materials and sizes, the loading, the
apparatus, the specimens' stated tolerances and the results of interest; ``docs/examples/willert2023.toml``
is the rig of Willert, Machines 11 (2023) 484, ``docs/examples/my_rig.toml`` a worked example of another::

    [rig]          name, title, resolution (of the slip index, default 0.01)
    [indenter]     profile (sphere | truncated | flat), R, b (the face radius of the rig's own indenter),
                   kink_rounding (the widest fillet the kink may have: a bound, m; not stated: its cell
                   undetermined)
    [materials]    E1, nu1 (indenter), E2, nu2 (block)
    [bodies]       cap_height (the indenter above the contact), block_height (the contact above the
                   bedding), block_width
    [loading]      F0, dF, ua (the piezo amplitude), mu1, mu2
    [apparatus]    kx and any field of ``mdr.apparatus.Apparatus`` (the plates' reading, the bedding; the
                   fields not stated take its defaults, this project's reading of the paper's apparatus;
                   h is the bodies' block_height)
    [tolerances]   tilt (rad, a bound: "less than"; not stated: its cell undetermined), and
                   [tolerances.roughness]: each surface's rms
                   height Rq (m; ISO 4287, over the ISO 4288 band of its value): sphere (the indenter's
                   spherical part), face (its flat face), block (without a stated spectrum its shape is left
                   open: the budget runs its readings, ``validation.spectra.READINGS``); hardness (Pa, of the
                   softer body: the plastic readings run where it is stated);
                   [tolerances.roughness.spectrum] where the spectrum is known: hurst, rolloff (m, the
                   longest wavelength of the waviness; default ISO's lambda_c), profile (true: the values
                   are a profile's Rq; false: areal): the budget runs that reading alone (and its
                   plastic one where a hardness is stated); or [tolerances.roughness.maps]: files (at least
                   2 square height maps of the pair's composite topography, .npy or a text grid, relative
                   to the rig file), pixel (m): the budget runs them as the one reading
    [[loop]]       a measured loop, the check of the readings of what the rig leaves open (its roughness
                   spectrum, its plates; ``validation.consistency``): key, amplitude (the measured tangential
                   force amplitude, N), gross (true where gross slip was seen; default false) and the
                   point's fields it ran at (b, F0, dF, ua, mu1, mu2, kx: a change of the rig's own)
    [[result]]     key, title, and points = [{b, F0, dF, ua, mu1, mu2, kx}, ...] (each a change of the
                   loading, apparatus or indenter's b) or sweep = {field = [values], ...} (every
                   combination)

Every field is checked against its range once, here (``InputError``: one line naming the file, the table,
the field and its range); a result's point is a ``validation.paper_points.Point`` (the loading, the axis
stiffness and the face radius; its indenter radius and materials are the rig's, ``Rig.indenter`` and
``Rig.materials``). The paper's file holds the constants the code keeps for the paper, and its points are
the error budget's (``tests/test_rig.py``). ``python -m validation.budget --scene-file RIG.toml`` computes a rig's
error budget (``validation.rig_budget``).
"""
from __future__ import annotations

import itertools
import math
import tomllib
from dataclasses import dataclass, fields
from pathlib import Path

from common.errors import InputError
from mdr.materials import Materials

from .paper_points import RESOLUTION, Point, Result

#: the largest tilt bound a rig file may state (rad): one degree; a bound given in degrees reads far above
TILT_MAX = math.pi / 180
#: the largest rms height a rig file may state (m): a value in micrometres reads far above
RQ_MAX = 100e-6
PROFILES = ("sphere", "truncated", "flat")
#: a point's fields (``validation.paper_points.Point``) a result may set or sweep
POINT_FIELDS = tuple(f.name for f in fields(Point))


@dataclass(frozen=True)
class Indenter:
    """The indenter: its ``profile`` family, the sphere's radius ``R`` (m), its face radius ``b`` (m; 0 for
    the sphere) and the widest rounding of its kink, ``kink_rounding`` (m, a bound; None: not stated)."""

    profile: str
    R: float
    b: float = 0.0
    kink_rounding: float | None = None


@dataclass(frozen=True)
class Bodies:
    """The finite bodies (m): the indenter's height above the contact, the contact's height above the
    bedding and the block's width."""

    cap_height: float
    block_height: float
    block_width: float


@dataclass(frozen=True)
class Spectrum:
    """The surfaces' spectrum where the rig states it (every body's): the Hurst exponent ``hurst`` of its
    self-affine part, the longest wavelength of its waviness ``rolloff`` (m; None: ISO 4288's lambda_c of
    the stated value's band) and whether the stated values are a ``profile``'s Rq (ISO 4287) or the
    surfaces' areal rms."""

    hurst: float
    rolloff: float | None = None
    profile: bool = True


@dataclass(frozen=True)
class Maps:
    """The surfaces' measured height maps where the rig gives them: the ``files`` (absolute paths; one
    surface each, the pair's composite topography), their ``pixel`` (m) and side ``n`` (pixels), and each
    file's content ``digest`` (``validation.spectra.file_digest``)."""

    files: tuple
    pixel: float
    n: int
    digest: tuple


@dataclass(frozen=True)
class Roughness:
    """The surfaces' rms heights Rq (m; a profile's, ISO 4287, over the ISO 4288 band of its value; 0: not
    stated): the indenter's spherical part, its flat face, the block; the ``hardness`` (Pa) of the softer
    body's asperities, for the readings of perfectly plastic asperities (None: not stated, elastic
    readings only); the ``spectrum`` or the measured ``maps`` where given (None: left open, the budget
    runs its readings)."""

    sphere: float = 0.0
    face: float = 0.0
    block: float = 0.0
    hardness: float | None = None
    spectrum: Spectrum | None = None
    maps: Maps | None = None


@dataclass(frozen=True)
class Rig:
    """A rig (module docstring): its points are the ``results``' (``Result``, each holding
    ``validation.paper_points.Point`` s)."""

    name: str
    title: str
    indenter: Indenter
    materials: Materials
    bodies: Bodies
    loading: dict
    apparatus: dict
    tilt: float | None
    roughness: Roughness
    results: tuple
    resolution: float = RESOLUTION
    #: the file it was read from (as given)
    source: str = ""
    #: the measured loops (``validation.consistency.Loop``)
    loops: tuple = ()

    def points(self) -> tuple:
        """Every result's points, each once, in the order of the results."""
        out = []
        for r in self.results:
            out += [p for p in r.points if p not in out]
        return tuple(out)


class _Table:
    """One table of a rig file being read: its values taken one by one, each checked, the error naming the
    file, the table, the field and its range; ``done`` refuses what is left (an unknown field)."""

    def __init__(self, where: str, table, name: str):
        if not isinstance(table, dict):
            raise InputError(f"{where}: [{name}] must be a table")
        self.where, self.name, self.left = where, name, dict(table)

    def bad(self, key, rng):
        return InputError(f"{self.where}: [{self.name}] {key} must be {rng}, got {self.left.get(key, '(missing)')!r}")

    def number(self, key, ok, rng, default=None) -> float:
        if key not in self.left:
            if default is None:
                raise InputError(f"{self.where}: [{self.name}] {key} is missing ({rng})")
            return default
        v = self.left[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or not ok(float(v)):
            raise self.bad(key, rng)
        return float(self.left.pop(key))

    def integer(self, key, ok, rng, default) -> int:
        v = self.left.get(key, default)
        if isinstance(v, bool) or not isinstance(v, int) or not ok(v):
            raise self.bad(key, rng)
        self.left.pop(key, None)
        return v

    def text(self, key, choices=None, default=None) -> str:
        v = self.left.get(key, default)
        if not isinstance(v, str) or (choices is not None and v not in choices):
            raise self.bad(key, f"one of {', '.join(choices)}" if choices else "a text")
        self.left.pop(key, None)
        return v

    def done(self, valid):
        if self.left:
            raise InputError(f"{self.where}: [{self.name}] unknown field {sorted(self.left)[0]!r}; valid fields: "
                             f"{', '.join(valid)}")


def _indenter(where, t) -> Indenter:
    t = _Table(where, t, "indenter")
    profile = t.text("profile", PROFILES)
    R = t.number("R", lambda x: x > 0, "> 0 (m)")
    b = t.number("b", lambda x: 0 <= x < R and (profile != "sphere" or x == 0) and (profile == "sphere" or x > 0),
                 "in (0, R) (m) for a truncated sphere or a flat punch, 0 for the sphere", 0.0)
    k = t.number("kink_rounding", lambda x: 0 <= x < max(b, 1e-300), "in [0, b) (m; the widest fillet of the kink, "
                 "a bound)", -1.0)
    t.done(("profile", "R", "b", "kink_rounding"))
    return Indenter(profile, R, b, None if k < 0 else k)


def _materials(where, t) -> Materials:
    t = _Table(where, t, "materials")
    kw = {}
    for k in ("E1", "E2"):
        kw[k] = t.number(k, lambda x: x > 0, "> 0 (Pa)")
    for k in ("nu1", "nu2"):
        kw[k] = t.number(k, lambda x: -1 < x < 0.5, "in (-1, 0.5)")
    t.done(("E1", "nu1", "E2", "nu2"))
    return Materials(**kw)


def _bodies(where, t) -> Bodies:
    t = _Table(where, t, "bodies")
    out = Bodies(*(t.number(k, lambda x: x > 0, "> 0 (m)") for k in ("cap_height", "block_height", "block_width")))
    t.done(("cap_height", "block_height", "block_width"))
    return out


def _loading(where, t) -> dict:
    t = _Table(where, t, "loading")
    F0 = t.number("F0", lambda x: x > 0, "> 0 (N)")
    out = {"F0": F0, "dF": t.number("dF", lambda x: 0 <= x < F0, "in [0, F0) (N)", 0.0),
           "ua": t.number("ua", lambda x: x > 0, "> 0 (m; the piezo amplitude)"),
           "mu1": t.number("mu1", lambda x: x > 0, "> 0 (the contact's friction; the slip index divides by it)"),
           "mu2": t.number("mu2", lambda x: x >= 0, ">= 0 (the bedding's friction)")}
    t.done(tuple(out))
    return out


def _apparatus(where, t) -> dict:
    from mdr.apparatus import Apparatus

    valid = tuple(f.name for f in fields(Apparatus) if f.name not in ("mu2", "h"))
    if not isinstance(t, dict):
        raise InputError(f"{where}: [apparatus] must be a table")
    unknown = sorted(set(t) - set(valid))
    if unknown:
        raise InputError(f"{where}: [apparatus] unknown field {unknown[0]!r}; valid fields: {', '.join(valid)} "
                         "(mu2 is the loading's, h the bodies' block_height)")
    if "kx" not in t:
        raise InputError(f"{where}: [apparatus] kx is missing (> 0, N/m: the tangential stiffness of the normal axis)")
    try:
        Apparatus(**t)
    except (InputError, TypeError, ValueError) as e:
        raise InputError(f"{where}: [apparatus] {e}") from None
    return dict(t)


def _tolerances(where, t, folder: Path) -> tuple:
    t = _Table(where, t, "tolerances")
    tilt = t.number("tilt", lambda x: 0 <= x <= TILT_MAX, f"in [0, {TILT_MAX:.4g}] (rad: at most one degree; "
                    "a bound in degrees above that is refused)", -1.0)
    tilt = None if tilt < 0 else tilt
    r = _Table(where, t.left.pop("roughness", {}), "tolerances.roughness")
    rq = {k: r.number(k, lambda x: 0 <= x <= RQ_MAX, f"in [0, {RQ_MAX:g}] (m: an rms height; a value in "
                      "micrometres is refused)", 0.0) for k in ("sphere", "face", "block")}
    hardness = r.number("hardness", lambda x: 1e7 <= x <= 1e11, "in [1e7, 1e11] (Pa: an indentation hardness; a "
                        "value in GPa or HV is refused)", -1.0)
    spectrum = _spectrum(where, r.left.pop("spectrum"), rq) if "spectrum" in r.left else None
    maps = _maps(where, r.left.pop("maps"), folder) if "maps" in r.left else None
    if spectrum is not None and not any(rq.values()):
        raise InputError(f"{where}: [tolerances.roughness.spectrum] needs the surfaces' rms heights ([tolerances."
                         "roughness] sphere, face or block > 0, m): a spectrum without a height is no roughness")
    if spectrum is not None and maps is not None:
        raise InputError(f"{where}: [tolerances.roughness] give the surfaces' spectrum or their measured maps, "
                         "not both (the maps carry their spectrum)")
    r.done(("sphere", "face", "block", "hardness", "spectrum", "maps"))
    t.done(("tilt", "roughness"))
    return tilt, Roughness(**rq, hardness=None if hardness < 0 else hardness, spectrum=spectrum, maps=maps)


def _maps(where, t, folder: Path) -> Maps:
    """The measured maps: at least two distinct square files of one size (``rough.surfaces.load_height_map``;
    paths relative to the rig file), their pixel, and their content's hash."""
    from rough.surfaces import load_realisations

    from .spectra import file_digest

    s = _Table(where, t, "tolerances.roughness.maps")
    files = s.left.pop("files", None)
    if not isinstance(files, list) or len(files) < 2 or not all(isinstance(f, str) for f in files):
        s.left["files"] = files
        raise s.bad("files", "a list of at least 2 height-map files (.npy or a text grid; one surface each, the "
                             "pair's composite topography, paths relative to the rig file)")
    pixel = s.number("pixel", lambda x: 1e-9 <= x <= 1e-3, "in [1e-9, 1e-3] (m: the maps' lateral sampling)")
    s.done(("files", "pixel"))
    paths = tuple(str((folder / f).resolve()) for f in files)
    try:
        read = load_realisations(paths, pixel)
    except InputError as e:
        raise InputError(f"{where}: [tolerances.roughness.maps] files: {e}") from None
    except ValueError as e:
        raise InputError(f"{where}: [tolerances.roughness.maps] files must be {e}") from None
    return Maps(paths, pixel, read[0].h.shape[0], tuple(file_digest(f) for f in paths))


def _spectrum(where, t, rq: dict) -> Spectrum:
    """The stated spectrum, its waviness's end beyond the short cut-off lambda_s of every stated value's
    ISO 4288 band (``rough.spectra.Finish``)."""
    from rough.spectra import Finish

    s = _Table(where, t, "tolerances.roughness.spectrum")
    hurst = s.number("hurst", lambda x: 0 < x <= 1, "in (0, 1] (the Hurst exponent of the self-affine part)")
    rolloff = s.number("rolloff", lambda x: 1e-7 <= x <= 0.1, "in [1e-7, 0.1] (m: the longest wavelength of the "
                       "waviness; not stated: ISO 4288's lambda_c)", -1.0)
    profile = s.left.pop("profile", True)
    if not isinstance(profile, bool):
        s.left["profile"] = profile
        raise s.bad("profile", "true (the stated values are a profile's Rq) or false (the surfaces' areal rms)")
    s.done(("hurst", "rolloff", "profile"))
    out = Spectrum(hurst, None if rolloff < 0 else rolloff, profile)
    for body, value in rq.items():
        try:
            if value > 0:
                Finish(value, out.hurst, out.rolloff, out.profile)
        except InputError as e:
            raise InputError(f"{where}: [tolerances.roughness.spectrum] rolloff: with the {body}'s rms {value:g} m, "
                             f"{e}") from None
    return out


def _point(where, indenter: Indenter, loading: dict, apparatus: dict, given: dict) -> Point:
    """A point of the rig: the rig's own values (indenter's b, loading, apparatus's kx) changed by ``given``."""
    base = {"b": indenter.b, "kx": float(apparatus["kx"]),
            **{k: loading[k] for k in ("F0", "dF", "ua", "mu1", "mu2")}}
    unknown = sorted(set(given) - set(POINT_FIELDS))
    if unknown:
        raise InputError(f"{where}: unknown point field {unknown[0]!r}; valid: {', '.join(POINT_FIELDS)}")
    kw = dict(base)
    for k, v in given.items():
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise InputError(f"{where}: {k} must be a number, got {v!r}")
        kw[k] = float(v)
    from .families.points import RANGES  # a point's ranges: one home, the points family's variant

    for k, (ok, rng) in RANGES.items():
        good = ok(kw[k], indenter) and (k != "dF" or kw["dF"] < kw["F0"]) \
            and (k != "b" or indenter.profile != "sphere" or kw["b"] == 0)
        if not good:
            raise InputError(f"{where}: a point's {k} is out of range, got {kw[k]!r} (it must be {rng}"
                             f"{'; 0 for the sphere' if k == 'b' else ''})")
    return Point(**kw)


def _results(where, tables, indenter, loading, apparatus) -> tuple:
    if not isinstance(tables, list) or not tables:
        raise InputError(f"{where}: at least one [[result]] table (key, title, points or sweep) is needed")
    out = []
    for i, r in enumerate(tables, 1):
        w = f"{where}: result {i}"
        t = _Table(w, r, "result")
        key, title = t.text("key"), t.text("title", default="")
        points, sweep = t.left.pop("points", None), t.left.pop("sweep", None)
        t.done(("key", "title", "points", "sweep"))
        if (points is None) == (sweep is None):
            raise InputError(f"{w}: give points (a list of tables) or sweep (a table of lists), one of them")
        if points is not None:
            if not isinstance(points, list) or not points or not all(isinstance(p, dict) for p in points):
                raise InputError(f"{w}: points must be a non-empty list of tables")
            given = points
        else:
            if not isinstance(sweep, dict) or not sweep or not all(isinstance(v, list) and v for v in sweep.values()):
                raise InputError(f"{w}: sweep must be a table of non-empty lists")
            given = [dict(zip(sweep, combo)) for combo in itertools.product(*sweep.values())]
        out.append(Result(key, title, tuple(_point(w, indenter, loading, apparatus, g) for g in given)))
    if len({r.key for r in out}) != len(out):
        raise InputError(f"{where}: two results share a key")
    return tuple(out)


def _loops(where, tables, indenter, loading, apparatus) -> tuple:
    """The ``[[loop]]`` tables as ``validation.consistency.Loop`` s (keys unique)."""
    from .consistency import Loop

    if not isinstance(tables, list):
        raise InputError(f"{where}: [[loop]] must be an array of tables")
    out = []
    for i, t in enumerate(tables, 1):
        w = f"{where}: loop {i}"
        t = _Table(w, t, "loop")
        key = t.text("key")
        amplitude = t.number("amplitude", lambda x: x > 0, "> 0 (N: the measured tangential force amplitude)")
        gross = t.left.pop("gross", False)
        if not isinstance(gross, bool):
            raise InputError(f"{w}: [loop] gross must be true or false, got {gross!r}")
        given = {k: t.left.pop(k) for k in list(t.left) if k in POINT_FIELDS}
        t.done(("key", "amplitude", "gross") + POINT_FIELDS)
        p = _point(w, indenter, loading, apparatus, given)
        out.append(Loop(key, p, amplitude, gross))
    if len({lp.key for lp in out}) != len(out):
        raise InputError(f"{where}: two loops share a key")
    return tuple(out)


def load_rig(path) -> Rig:
    """The rig of a TOML file, every field checked (module docstring); ``InputError`` in one line naming the
    file, the table and the field with its range, on a missing or unreadable file, bad TOML, a missing or
    unknown table or field, or a value out of range."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except OSError as e:
        raise InputError(f"rig file {str(path)!r} cannot be read: {e.strerror or e}") from None
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"rig file {str(path)!r} is not valid TOML: {e}") from None
    where = path.name
    tables = ("rig", "indenter", "materials", "bodies", "loading", "apparatus", "tolerances", "loop", "result")
    unknown = sorted(set(data) - set(tables))
    if unknown:
        raise InputError(f"{where}: unknown table [{unknown[0]}]; valid tables: {', '.join(tables)}")
    missing = [k for k in tables if k not in data and k not in ("tolerances", "loop")]
    if missing:
        raise InputError(f"{where}: missing table [{missing[0]}]")
    head = _Table(where, data["rig"], "rig")
    name, title = head.text("name"), head.text("title", default="")
    resolution = head.number("resolution", lambda x: 0 < x < 1, "in (0, 1) (of the slip index)", RESOLUTION)
    head.done(("name", "title", "resolution"))
    indenter = _indenter(where, data["indenter"])
    loading = _loading(where, data["loading"])
    apparatus = _apparatus(where, data["apparatus"])
    tilt, roughness = _tolerances(where, data.get("tolerances", {}), path.parent)
    if indenter.profile == "sphere" and tilt:
        tilt = 0.0  # a tilted sphere is the same sphere displaced
    return Rig(name=name, title=title, indenter=indenter, materials=_materials(where, data["materials"]),
               bodies=_bodies(where, data["bodies"]), loading=loading, apparatus=apparatus, tilt=tilt,
               roughness=roughness, results=_results(where, data["result"], indenter, loading, apparatus),
               resolution=resolution, source=str(path),
               loops=_loops(where, data.get("loop", []), indenter, loading, apparatus))
