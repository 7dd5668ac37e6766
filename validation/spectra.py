"""The readings of the paper's roughness a reviewer admits, and the normal curves of their surfaces.

Willert, Machines 11 (2023) 484, Section 2 states rms roughnesses: about 1 um on the sphere, 3 um on the
block, 2 um on the turned flat face. It does not say over which band, nor what the spectrum is. Read as
a profilometer reads it (``rough.spectra``: Rq over ISO 4288's band of its class, form removed), each
value still leaves the spectrum's shape open. The budget therefore runs every reading of ``READINGS``
(the axes: where the surfaces' waviness ends, ``rolloff``, from twice the contact radius to ISO's
lambda_c; the Hurst exponent, 0.5 to 1; asperities elastic, or perfectly plastic at the steel's
hardness; the values the surfaces' areal rms, or a profile's Rq, whose areal rms is larger), each on
the contact of the sphere (sphere on block) and of each flat face (face on block): the paper's own loop
data then exclude the readings they contradict (``validation.consistency``). A rig that states its
spectrum or gives measured height maps runs that one reading instead (``Contact.readings``).

A reading on a contact is generated as the catalogue's rough surfaces are (``rough.surfaces``): on a
periodic grid of ``period`` smooth contact radii, the window [short cut-off, period] of the pair's
combined spectrum, scaled to its rms in that window (``rough.spectra.window_rms``; one power law of
the reading's Hurst exponent over the window: the bodies' band ends inside it are not kept apart); the
longer wavelengths are form the grid leaves out (``form_curvature_rms`` says how much curvature), the
shorter ones are cut (the catalogue's stated cut-off). On the sphere's contact the shortest wavelength
left out is 32 contact radii, so over the contact it is a curvature, the budget's MDR sphere of another
radius (``validation.budget_readings``); on a face's grid of 4 radii it is not, so a reading that leaves
more than ``FORM_SHARE_MAX`` of its variance beyond a face's grid is not run there (``resolved``), and
a reading that coincides with an earlier one on a contact (its waviness ends beyond the band) is run
once (``canonical``). Each reading: ``SEEDS`` surfaces, each on two
grids that refine one band-limited map. A member (reading, contact, seed, grid) returns the normal
force-approach curve of the rough half-space (``rough.normal.force_approach``, elastic; plastic:
flattened at ``ROUGH_PRELOAD`` first), the input of MDR's equivalent profile. Members run in
processes (``curves``) and are cached by content under the output folder, so a second budget reads them.
"""
from __future__ import annotations

import functools
import hashlib
import json
import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path

from common.errors import ConvergenceError, InputError
from mdr.paper import R_INDENTER, STEEL_E, STEEL_NU
from rough.normal import HARDNESS_X5CRNI18_10

#: the paper's stated rms heights (m), Section 2
PAPER_RQ = {"sphere": 1e-6, "block": 3e-6, "face": 2e-6}
#: surfaces per reading (realisations)
SEEDS = (0, 1, 2, 3)
#: the normal load the contacts' smooth radius a is taken at (N; Table 2's F0) and the curves' largest
#: force (1.5 x: above every point's F0 + dF, 0.73 N at most)
F_REF = 0.5
#: a plastic reading is flattened at this many times its contact's reference load (the paper's 0.75 N:
#: the catalogue's ``validation.scenes.ROUGH_PRELOAD``, above its largest F0 + dF)
PRELOAD = 1.5
#: the largest share of a reading's variance a face's grid may leave out as form (beyond: not resolved)
FORM_SHARE_MAX = 0.1


@dataclass(frozen=True)
class Reading:
    """One admissible reading of the stated rms values: the Hurst exponent, where the waviness ends
    (``rolloff`` in smooth contact radii of the contact; None: at ISO's lambda_c, all of the
    profilometer's band), perfectly ``plastic`` asperities (flattened at ``ROUGH_PRELOAD``) or elastic,
    the values a profile's Rq (``profile``: the areal rms larger, ``rough.spectra.Finish``) or the
    surfaces' areal rms. A rig's ``measured`` reading: its height ``maps`` (files, one surface each, the
    pair's composite topography, square, ``n`` pixels of ``pixel`` m; ``digest``: each file's content
    hash, in the cache key and checked where a surface is read, ``surface``); its spectrum then is the
    maps'."""

    name: str
    hurst: float = 0.8
    rolloff: float | None = None
    plastic: bool = False
    profile: bool = False
    maps: tuple = ()
    pixel: float | None = None
    n: int = 0
    digest: tuple = ()

    def __post_init__(self):
        object.__setattr__(self, "maps", tuple(self.maps))  # hashable (lru_cache) from plain data too
        object.__setattr__(self, "digest", tuple(self.digest))

    @property
    def measured(self) -> bool:
        return bool(self.maps)

    def finishes(self, contact: "Contact", a: float) -> tuple:
        from rough.spectra import Finish

        lam = None if self.rolloff is None else self.rolloff * a
        rq = dict(contact.rq)
        return tuple(Finish(rq[body], self.hurst, lam, self.profile) for body in contact.bodies if rq[body] > 0)


#: the readings every contact runs: the ISO band (H 0.8, typical of ground and turned steel; Persson,
#: Tribology Letters 54 (2014) 99) and the axes around it one at a time
READINGS = (Reading("ISO band"), Reading("ISO band, H 0.5", hurst=0.5), Reading("ISO band, H 1", hurst=1.0),
            Reading("waviness ends at 8 a", rolloff=8.0), Reading("waviness ends at 2 a", rolloff=2.0),
            Reading("ISO band, plastic", plastic=True), Reading("waviness ends at 8 a, plastic", rolloff=8.0, plastic=True),
            Reading("ISO band, profile Rq", profile=True))


@dataclass(frozen=True)
class Contact:
    """A rough contact of a rig's specimens (defaults: the paper's): the indenter (``b`` = 0: the sphere,
    else the truncated sphere's face radius), the bodies whose finishes meet there, the grid's side in
    smooth contact radii, its two pixel counts and the short cut-off in pixels of the coarser; the
    indenter's radius ``R``, the pair's ``materials`` (E1, nu1, E2, nu2), each body's stated rms height
    ``rq`` ((body, m) pairs; 0: not stated, no finish), the reference load ``F_ref`` (N; the curves run to
    1.5 of it, the plastic readings flatten there), the ``hardness`` (Pa) of the plastic readings
    (None: not stated, those readings not run) and the ``readings`` it runs (default ``READINGS``; a rig
    that states its spectrum or gives measured maps: that one reading and its plastic twin where a
    hardness is stated, ``validation.rig_budget.stated``)."""

    b: float
    bodies: tuple
    period: float
    grids: tuple
    short: float
    R: float = R_INDENTER
    materials: tuple = (STEEL_E, STEEL_NU, STEEL_E, STEEL_NU)
    rq: tuple = tuple(PAPER_RQ.items())
    F_ref: float = F_REF
    hardness: float | None = HARDNESS_X5CRNI18_10
    readings: tuple = READINGS

    @classmethod
    def of(cls, d: dict) -> "Contact":
        """The contact of its plain data (``dataclasses.asdict``, as a task carries it)."""
        return cls(**{**d, "bodies": tuple(d["bodies"]), "grids": tuple(d["grids"]), "materials": tuple(d["materials"]),
                      "rq": tuple(tuple(x) for x in d["rq"]),
                      "readings": tuple(Reading(**r) for r in d.get("readings", [asdict(x) for x in READINGS]))})

    def mat(self):
        from mdr.materials import Materials

        return Materials(*self.materials)

    def a(self) -> float:
        """The smooth indenter's contact radius at ``F_ref`` (m)."""
        from fem.axisym.normal_run import reference_radius

        return reference_radius("truncated" if self.b else "sphere", self.R, self.b or None, self.F_ref,
                                self.mat().E_star)

    def name(self) -> str:
        return "sphere" if not self.b else f"b = {self.b * 1e6:g} um"

    def runs(self, reading: "Reading") -> bool:
        """Whether the contact runs the reading: a finish stated (or measured maps), and a hardness for a
        plastic one."""
        return ((reading.measured or any(v > 0 for k, v in self.rq if k in self.bodies))
                and (self.hardness is not None or not reading.plastic))


#: the sphere's contact: 32 radii (the rough contact spreads over several), cut off at one radius
SPHERE = Contact(0.0, ("sphere", "block"), 32.0, (256, 384), 8.0)


def face(b: float, **rig) -> Contact:
    """A flat face's contact: 4 radii (the catalogue's face grids), cut off at 8 pixels of 256; ``rig``:
    the contact's fields of a rig of one's own (``Contact``)."""
    return Contact(float(b), ("face", "block"), 4.0, (256, 384), 8.0, **rig)


def sphere(**rig) -> Contact:
    """The sphere's contact (``SPHERE``'s grid) with the fields of a rig of one's own (``Contact``)."""
    return Contact(0.0, ("sphere", "block"), 32.0, (256, 384), 8.0, **rig)


def file_digest(path) -> str:
    """A file's content hash (a measured map's, ``Reading.digest``)."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()[:16]


@dataclass(frozen=True)
class Measured:
    """A measured map's place in ``params``: its file, side (m), pixels, and the band it holds (two pixels
    to its side); its rms is the map's own (``surface``)."""

    path: str
    size: float
    n: int
    lambda_short: float
    lambda_long: float


def params(reading: Reading, contact: Contact, seed: int):
    """The ``rough.surfaces.RoughnessParams`` of a member on the coarser grid (a measured reading's map:
    ``Measured``), and the form curvature (1/m) the grid leaves out (none of a measured map: the map is
    taken as it is given, its mean removed only; its form and tilt are the user's to remove)."""
    from rough.spectra import form_curvature_rms, window_rms
    from rough.surfaces import RoughnessParams

    if reading.measured:
        return Measured(reading.maps[int(seed)], reading.pixel * reading.n, reading.n, 2.0 * reading.pixel,
                        reading.pixel * reading.n), 0.0
    a = contact.a()
    P, n0 = contact.period * a, contact.grids[0]
    short = contact.short * P / n0
    fin = reading.finishes(contact, a)
    long = min(P, max(f.band()[1] for f in fin))
    rms = window_rms(fin, (short, long))
    p = RoughnessParams(rms=rms, hurst=reading.hurst, lambda_short=short, lambda_long=long, size=P, n=n0,
                        seed=int(seed))
    return p, form_curvature_rms(fin, P)


@functools.lru_cache(maxsize=None)
def form_share(reading: Reading, contact: Contact) -> float:
    """The share of the reading's gap variance in wavelengths longer than the contact's grid (0 for
    measured maps: the grid is theirs)."""
    from rough.spectra import variance_fraction

    if reading.measured:
        return 0.0
    a = contact.a()
    fin = reading.finishes(contact, a)
    beyond = sum(f.areal_rq() ** 2 * variance_fraction(f.hurst, f.band(), (contact.period * a, math.inf)) for f in fin)
    return beyond / sum(f.areal_rq() ** 2 for f in fin)


def resolved(reading: Reading, contact: Contact) -> bool:
    """Whether the contact's model holds the reading: the sphere's always (the form is a curvature there),
    a face's where its grid leaves at most ``FORM_SHARE_MAX`` of the variance out."""
    return not contact.b or form_share(reading, contact) <= FORM_SHARE_MAX


@functools.lru_cache(maxsize=None)
def canonical(i: int, contact: Contact) -> int:
    """The first reading that generates the same surfaces as reading ``i`` on the contact (the same
    window, rms, Hurst exponent and asperities): ``i`` itself unless an earlier one coincides."""
    rs = contact.readings
    key = (params(rs[i], contact, 0)[0], rs[i].plastic)
    return next(j for j in range(i + 1) if (params(rs[j], contact, 0)[0], rs[j].plastic) == key)


def surface(task: dict) -> tuple:
    """A member's surface (``task``: reading index, contact, seed, grid n): its ``RoughnessParams`` on the
    coarser grid (a measured map's ``Measured``), the form curvature the grid leaves out (1/m), the
    ``rough.normal.Grid``, the heights resampled to n pixels (one band-limited map on every grid; a
    measured map, InputError where its content is not the digest the rig was read with: edited since, or
    another file at that path on this worker) and the smooth indenter (as generated; a plastic reading's
    flattening is ``member``'s)."""
    from mdr.profiles import make_profile
    from rough.normal import Grid
    from rough.surfaces import band_limited, load_height_map, resample

    contact = Contact.of(task["contact"])
    reading = contact.readings[task["reading"]]
    p, kappa = params(reading, contact, task["seed"])
    n = int(task["n"])
    prof = make_profile("truncated" if contact.b else "sphere", contact.R, contact.b or None)
    if reading.measured:
        if file_digest(p.path) != reading.digest[int(task["seed"])]:
            raise InputError(f"height map {p.path!r} changed since the rig file was read (or is another file on "
                             "this worker: every worker must read the same maps at the same path)")
        heights = resample(load_height_map(p.path, reading.pixel, square=True), n)
        return p, kappa, Grid(p.size, n), heights, prof
    return p, kappa, Grid(p.size, n), band_limited(p, n), prof


def member(task: dict) -> dict:
    """One member (``task``: reading index, contact, seed, grid n): the rough half-space's normal
    force-approach curve at ``F_REF`` x ``rough.equivalent.CURVE_FRACTIONS`` (plain data), or
    ``failed`` with the reason."""
    from rough.equivalent import CURVE_FRACTIONS, flattened
    from rough.normal import force_approach

    t0 = time.perf_counter()
    contact = Contact.of(task["contact"])
    reading = contact.readings[task["reading"]]
    p, kappa, grid, heights, prof = surface(task)
    mat = contact.mat()
    rms = float(heights.h.std()) if reading.measured else p.rms
    out = {**task, "rms_window": rms, "lambda_short": p.lambda_short, "lambda_long": p.lambda_long,
           "period": p.size, "form_curvature": kappa}
    try:
        if reading.plastic:
            heights, _ = flattened(prof, mat, grid, heights, contact.hardness, PRELOAD * contact.F_ref)
        d, F = force_approach(prof, mat, contact.F_ref * CURVE_FRACTIONS, grid, heights)
        out["curve"] = {"d": d.tolist(), "F": F.tolist()}
    except ConvergenceError as e:
        out["failed"] = str(e)
    out["runtime_s"] = time.perf_counter() - t0
    return out


def tasks(contacts) -> list:
    """Every member of every reading on every contact, the finer grids first: each reading once per
    contact (``canonical``), only where the contact's grid resolves it (``resolved``)."""
    out = [{"reading": i, "contact": asdict(c), "seed": s, "n": n}
           for c in contacts for i in range(len(c.readings))
           if _runs(i, c) for s, n in _members_of(c.readings[i], c)]
    return sorted(out, key=lambda t: -t["n"])


def _members_of(reading: Reading, c: Contact) -> list:
    """A reading's (seed, grid) pairs on a contact: ``SEEDS`` on its grids, or each measured map on its own
    pixels and 1.5 times them (resampled)."""
    if reading.measured:
        return [(s, n) for s in range(len(reading.maps)) for n in (reading.n, 3 * reading.n // 2)]
    return [(s, n) for s in SEEDS for n in c.grids]


def _runs(i: int, c: Contact) -> bool:
    """Whether the contact runs reading ``i``'s surfaces: stated, once (``canonical``), resolved; a reading
    its scales cannot hold (a waviness end below the profilometer's band) is not run (its cell says so)."""
    from common.errors import InputError

    try:
        return c.runs(c.readings[i]) and canonical(i, c) == i and resolved(c.readings[i], c)
    except InputError:
        return False


#: the sources a member's curve depends on (its cache key holds their content)
MEMBER_SOURCES = ("rough/*.py", "validation/spectra.py", "mdr/profiles.py", "mdr/materials.py", "mdr/reference.py",
                  "fem/axisym/normal_run.py", "common/*.py")


def member_version(sources=MEMBER_SOURCES) -> str:
    """A digest of the files of ``sources`` (patterns from the project's root; default ``MEMBER_SOURCES``):
    a cached member of other sources is computed again."""
    from .sources import digest

    root = Path(__file__).resolve().parent.parent
    return digest([f for pattern in sources for f in sorted(root.glob(pattern))])


def _key(task: dict, version: str, tag: str | None = None) -> str:
    payload = [task, version] if tag is None else [tag, task, version]
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()[:20]


def cached_map(todo: list, fun, cache_dir, version: str, *, tag: str | None = None, jobs: int = 1, log=None,
               what: str = "surfaces", every: int = 8, executor=None) -> list:
    """``fun`` of every task of ``todo`` (plain data, a top-level function: it may run in ``jobs``
    processes, or on ``executor``, e.g. a Dask client's: ``remote_call``), in their order: each result
    read from ``cache_dir`` where one of the same task, sources (``version``) and ``tag`` is stored, else
    computed and stored there as it completes (one JSON file each, written atomically; ``cache_dir``
    None: nothing read or stored); a progress line every ``every`` results."""
    from common.io import write_json

    log = log or (lambda msg: None)
    cache = None if cache_dir is None else Path(cache_dir)
    keys = [_key(t, version, tag) for t in todo]
    done, run = {}, []
    for k, t in zip(keys, todo):
        f = None if cache is None else cache / f"{k}.json"
        if f is not None and f.is_file():
            done[k] = json.loads(f.read_text())
        else:
            run.append((k, t))
    if run:
        where = f"{jobs} process(es)" if executor is None else "the executor's workers"
        log(f"budget: {what}, {len(run)} to solve ({len(done)} cached), {where}")
    def keep(i, r):
        k = run[i][0]
        if cache is not None:
            write_json(cache / f"{k}.json", r)
        done[k] = r

    map_tasks([t for _, t in run], fun, jobs, log, what, every, executor, keep)
    return [done[k] for k in keys]


def curves(contacts, cache_dir, *, jobs: int = 1, log=None, executor=None) -> list:
    """The members of every reading on ``contacts`` (``tasks``, ``member``), cached by content under
    ``cache_dir`` (``cached_map``; in ``jobs`` processes or on ``executor``)."""
    return cached_map(tasks(contacts), member, cache_dir, member_version(), jobs=jobs, log=log,
                      what="the roughness readings' surfaces", executor=executor)


def remote_call(fun, version: str, *args):
    """``fun(*args)`` on a worker of an executor (top level: picklable), refused where the worker runs
    other sources than the caller (``version``: ``validation.sources.all_sources_version``, every module:
    its result would be cached under the caller's key)."""
    from .sources import all_sources_version, refuse_other_sources

    refuse_other_sources(all_sources_version(), version)
    return fun(*args)


def map_tasks(todo: list, fun, jobs: int, log, what: str, every: int, executor=None, keep=None) -> list:
    """``fun`` of every task, in ``jobs`` processes or on ``executor`` (``remote_call``), each result
    handed to ``keep(k, result)`` as it completes (a failed task then loses none of the finished ones;
    the tasks not started are cancelled), a progress line every ``every`` results."""
    from concurrent.futures import ProcessPoolExecutor, as_completed

    out = [None] * len(todo)

    def got(j, k, r):
        out[k] = r
        if keep is not None:
            keep(k, r)
        if j % every == 0 or j == len(todo):
            log(f"  {what}: {j} of {len(todo)}")

    def drain(ex, submit):
        futures = {submit(ex, t): k for k, t in enumerate(todo)}
        try:
            for j, f in enumerate(as_completed(futures), 1):
                got(j, futures[f], f.result())
        finally:
            for f in futures:
                f.cancel()

    if executor is not None:
        from .sources import all_sources_version

        version = all_sources_version()
        drain(executor, lambda ex, t: ex.submit(remote_call, fun, version, t))
    elif jobs <= 1 or len(todo) <= 1:
        for j, t in enumerate(todo, 1):
            got(j, j - 1, fun(t))
    else:
        with ProcessPoolExecutor(max_workers=jobs) as ex:
            drain(ex, lambda ex, t: ex.submit(fun, t))
    return out
