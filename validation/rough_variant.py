"""A variant of the roughness family (``validation.families.roughness``) as typed data: its keys checked,
its defaults merged and its units converted once (``RoughVariant.of``), so that what the rough engine
takes comes from one function (``surface``, ``heights``).

A variant is given as a plain mapping (the catalogue, a scene file's TOML): ``rms`` (m, 0 the smooth
indenter) or ``maps`` (at least 2 square height-map files, one per realisation, with their ``pixel``
size, m), and optionally ``b`` (m, the face radius: 0 the sphere), ``hurst``, ``period`` (the grid's side
in smooth contact radii), ``short`` (the short cut-off in pixels of the coarsest grid), ``long`` (the long
cut-off as a fraction of the period), ``seeds``, ``grids``, ``hardness`` (Pa) with ``preload`` (N) and
``apparatus`` (bool). ``DEFAULTS`` holds what is left out. On its way to the engine a cut-off changes
unit once, here: ``short`` pixels -> ``lambda_short`` (m), ``long`` -> ``lambda_long`` (m), ``period`` ->
``size`` (m).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from common.errors import InputError
from mdr.paper import R_INDENTER, STEEL_E, STEEL_NU

from .families import number, variant_keys

#: the defaults of a variant: 4 surfaces, grids of 128-256 pixels over 16 smooth contact radii, Hurst 0.8,
#: the short cut-off at 4 pixels of the coarsest grid, the long one at a quarter period (no power at
#: longer wavelengths: rough.surfaces)
DEFAULTS = {"seeds": (0, 1, 2, 3), "grids": (128, 192, 256), "period": 16.0, "hurst": 0.8, "short": 4.0,
            "long": 0.25}
KEYS = ("rms", "maps", "pixel", "b", "hurst", "period", "short", "long", "seeds", "grids", "hardness", "preload",
        "apparatus")


def maps_grids(n_map: int) -> tuple:
    """The default grid ladder of measured maps of ``n_map`` pixels: theirs, 1.5x and 2x (resampled)."""
    return (n_map, 3 * n_map // 2, 2 * n_map)


@dataclass(frozen=True)
class RoughVariant:
    """One checked variant (SI; module docstring): the face radius ``b``; the realisations ``seeds`` and the
    grid ``ladder`` (pixels a side, increasing); the surface's ``rms`` (None for measured maps),
    ``hurst``, the grid's side ``size`` (m) and the cut-offs ``lambda_short``, ``lambda_long`` (m; None for
    measured maps); ``maps`` and their ``pixel``; the plastic ``hardness`` (Pa) and ``preload`` (N) or
    None; ``apparatus``."""

    b: float
    seeds: tuple
    grids: tuple
    size: float
    rms: float | None = None
    hurst: float | None = None
    lambda_short: float | None = None
    lambda_long: float | None = None
    maps: tuple | None = None
    pixel: float | None = None
    hardness: float | None = None
    preload: float | None = None
    apparatus: bool = False

    @property
    def measured(self) -> bool:
        return self.maps is not None

    @classmethod
    def of(cls, v: dict, scene) -> "RoughVariant":
        """The variant ``v`` of ``scene`` checked (one line naming the scene, the variant and the key with
        its valid range: ``InputError``) and converted; ``period`` in units of the smooth contact radius of
        the scene's indenter with the variant's face radius (``validation.scenes.a_ref``). The scene must
        be the sphere or the truncated sphere under force control at a constant normal force."""
        from .scenes import a_ref

        if scene.profile not in ("sphere", "truncated") or scene.drive != "force" or scene.dF != 0.0:
            raise InputError(f"scene {scene.name}: rough variants need profile 'sphere' or 'truncated', drive "
                             "'force' and dF = 0")
        bad = variant_keys(scene, "rough", v, KEYS)
        b = number(v, "b", lambda x: 0.0 <= x < 0.5 * scene.R, bad, f"in [0, {0.5 * scene.R:g}) (m; the face "
                    "radius, 0 the sphere)") if "b" in v else (float(scene.b) if scene.profile == "truncated" else 0.0)
        a = a_ref(scene, b)
        if "maps" in v:
            out = cls._measured(v, b, a, bad)
        else:
            out = cls._generated(v, b, a, bad)
        return out._plastic(v, scene, bad)._driven(v, scene, bad)

    @classmethod
    def _measured(cls, v, b, a, bad) -> "RoughVariant":
        from rough.surfaces import covers, load_realisations

        maps = v["maps"]
        try:
            if isinstance(maps, str) or not isinstance(maps, (list, tuple)):
                raise ValueError("a list of at least 2 height-map files (one realisation is no answer)")
            read = load_realisations(maps, v.get("pixel"))
        except InputError:  # a file that cannot be read, or no pixel size: its own line
            raise
        except ValueError as e:
            raise bad("maps", str(e)) from None
        n_map = read[0].h.shape[0]
        grids = _grids(v.get("grids", maps_grids(n_map)), bad)
        if grids[0] != n_map:
            raise bad("grids", f"at least 2 pixel counts, a ladder from the maps' {n_map} pixels")
        size = read[0].pixel * n_map
        if covers(size, a):
            raise bad("maps", covers(size, a))
        return cls(b=b, seeds=tuple(range(len(maps))), grids=grids, size=size, maps=tuple(str(f) for f in maps),
                   pixel=float(read[0].pixel))

    @classmethod
    def _generated(cls, v, b, a, bad) -> "RoughVariant":
        try:
            if isinstance(v["rms"], bool):
                raise TypeError
            rms = float(v["rms"])
            seeds = tuple(int(x) for x in v.get("seeds", DEFAULTS["seeds"]))
            grids = _grids(v.get("grids", DEFAULTS["grids"]), bad)
            period, short = float(v.get("period", DEFAULTS["period"])), float(v.get("short", DEFAULTS["short"]))
            long_, hurst = float(v.get("long", DEFAULTS["long"])), float(v.get("hurst", DEFAULTS["hurst"]))
        except (TypeError, ValueError):
            raise bad("rms, seeds, grids, period, short, long, hurst", "numbers (seeds and grids lists of "
                      "integers)") from None
        if not (math.isfinite(rms) and rms >= 0):
            raise bad("rms", ">= 0 (m)")
        if rms > 0 and (len(set(seeds)) != len(seeds) or len(seeds) < 2 or min(seeds) < 0):
            raise bad("seeds", "at least 2 distinct integers >= 0, none twice (one realisation is no answer)")
        if not period >= 4.0:
            raise bad("period", ">= 4 (smooth contact radii)")
        if not 2.0 <= short <= grids[0] / 2:
            raise bad("short", f"in [2, {grids[0] // 2}] (pixels of the coarsest grid)")
        if not short / grids[0] < long_ <= 1.0:
            raise bad("long", f"in ({short / grids[0]:.3g}, 1] (fractions of the period)")
        if not 0.0 < hurst <= 1.0:
            raise bad("hurst", "in (0, 1]")
        size = period * a
        return cls(b=b, seeds=(0,) if rms == 0.0 else seeds, grids=grids, size=size, rms=rms, hurst=hurst,
                   lambda_short=short * size / grids[0], lambda_long=long_ * size)

    def _plastic(self, v, scene, bad) -> "RoughVariant":
        if "preload" in v and "hardness" not in v:
            raise bad("preload", f">= F0 = {scene.F0:g} N, with a hardness (the largest load the plastic "
                                 "surface was flattened by)")
        if "hardness" not in v:
            return self
        hardness = number(v, "hardness", lambda x: x > 0, bad, "> 0 (Pa; perfectly plastic asperities)")
        preload = number(v, "preload", lambda x: x >= scene.F0, bad,
                          f">= F0 = {scene.F0:g} N, with a hardness (the largest load the plastic surface was "
                          "flattened by)") if "preload" in v else float(scene.F0)
        return replace(self, hardness=hardness, preload=preload)

    def _driven(self, v, scene, bad) -> "RoughVariant":
        if "apparatus" not in v:
            return self
        if not isinstance(v["apparatus"], bool):
            raise bad("apparatus", "true or false")
        steel = (scene.E1, scene.nu1, scene.E2, scene.nu2) == (STEEL_E, STEEL_NU, STEEL_E, STEEL_NU)
        if v["apparatus"] and (scene.R != R_INDENTER or not steel):
            raise bad("apparatus", f"false on this indenter: the paper's points are the steel sphere of "
                                   f"R = {R_INDENTER:g} m on steel")
        return replace(self, apparatus=v["apparatus"])

    def surface(self, seed: int):
        """The ``rough.surfaces.RoughnessParams`` of realisation ``seed`` on the coarsest grid (None for a
        smooth or measured variant)."""
        from rough.surfaces import RoughnessParams

        if self.measured or not self.rms:
            return None
        return RoughnessParams(rms=self.rms, hurst=self.hurst, lambda_short=self.lambda_short,
                               lambda_long=self.lambda_long, size=self.size, n=self.grids[0], seed=int(seed))

    def heights(self, seed: int, n: int):
        """Realisation ``seed`` on ``n`` pixels (``rough.surfaces.band_limited``: one band-limited map on
        every grid; a measured map resampled), None for the smooth indenter."""
        from rough.surfaces import band_limited, load_height_map, resample

        if self.measured:
            return resample(load_height_map(self.maps[int(seed)], self.pixel, square=True), int(n))
        p = self.surface(seed)
        return None if p is None else band_limited(p, int(n))


def _grids(grids, bad) -> tuple:
    try:
        out = tuple(int(x) for x in grids)
    except (TypeError, ValueError):
        raise bad("grids", "at least 2 pixel counts, increasing, from 16") from None
    if len(out) < 2 or out[0] < 16 or any(b <= a for a, b in zip(out, out[1:])):
        raise bad("grids", "at least 2 pixel counts, increasing, from 16")
    return out
