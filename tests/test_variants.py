"""Each scene family's typed variant (``validation.families.<family>.Variant``): a scene's variants are
checked once when the scene is made (one line naming the scene, the key and its range), and converted
to what the family's solver takes in one place."""
import pytest

from common.errors import InputError
from validation.catalogue import CATALOGUE
from validation.families import module
from validation.scenes import FAMILIES, Scene

#: per family: a scene of it with one good variant, then bad variants with the key the error must name
CASES = {
    "validity": (dict(profile="sphere", dF=0.0, amplitude=0.05, fe_levels=(1 / 40,), mdr_cells=(400,)),
                 {"block": 5.0}, [({"block": 2.0}, "sizes in contact radii > 2.5"),
                                  ({"block": 5.0, "tilt": 1.0}, "block and/or cap")]),
    "curvature": (dict(profile="sphere", dF=0.0), {"a_over_R": 1e-3, "nu": 0.3},
                  [({"a_over_R": 0.0}, "a_over_R must be in (0, 0.1]"), ({"a_over_R": 1e-3, "nu": 0.5}, "nu must be"),
                   ({"a_over_R": 1e-3, "R": 1.0}, "R must be one of the variant's keys")]),
    "points": (dict(profile="sphere", drive="apparatus", amplitude=1e-7, kx=2e6), {"kx": 2e6, "b": 1e-5},
               [({"b": 1e-5}, "each holding kx"), ({"kx": -1.0}, "kx must be > 0"),
                ({"kx": 2e6, "mu1": 0.0}, "mu1 must be > 0"), ({"kx": 2e6, "dF": 0.6}, "dF must be in [0, F0)"),
                ({"kx": 2e6, "k": 1.0}, "k must be one of the variant's keys")]),
    "assumptions3d": (dict(profile="sphere", fe_model="3d", fe_levels=(0.3,)), {"relax": "coupling", "E2": 70e9},
                      [({"relax": "tilt"}, "relax must be one of direction, coupling"),
                       ({"relax": "coupling", "nu2": 0.5}, "nu2 must be in"),
                       ({"relax": "direction", "b": -1e-6}, "b must be in")]),
    "tilt": (dict(profile="flat", b=1e-4, fe_model="3d", fe_levels=(0.3,)),
             {"profile": "flat", "b": 1e-4, "tilts": (1e-5,)},
             [({"profile": "sphere", "b": 1e-4, "tilts": (1e-5,)}, "profile must be flat or truncated"),
              ({"profile": "flat", "b": 0.0, "tilts": (1e-5,)}, "b must be in"),
              ({"profile": "flat", "b": 1e-4, "tilts": (-1e-5,)}, "tilts must be")]),
    "roughness": (dict(profile="sphere", dF=0.0), {"rms": 1e-7},
                  [({"rms": -1e-7}, "rms must be >= 0"), ({"rms": 1e-7, "hurst": 2.0}, "hurst must be in")]),
}


def test_every_family_with_variants_has_its_case():
    assert set(CASES) == {f for f, keys in FAMILIES.items() if keys}


@pytest.mark.parametrize("family", sorted(CASES))
def test_a_family_checks_its_variants_once_when_the_scene_is_made(family):
    """A good variant becomes the family's frozen ``Variant``; each bad one is refused when the scene is
    made, in one line naming the scene, the key and its range."""
    kw, good, bad = CASES[family]
    s = Scene("t", "t", family=family, variants=(good,), **kw)
    (v,) = s.typed_variants
    assert type(v) is module(family).Variant or family == "roughness"
    with pytest.raises(AttributeError):  # frozen
        v.__setattr__(next(iter(v.__dataclass_fields__)), 0)
    for variant, message in bad:
        with pytest.raises(InputError) as e:
            Scene("t", "t", family=family, variants=(variant,), **kw)
        assert "scene t" in str(e.value) and message in str(e.value) and "\n" not in str(e.value), str(e.value)


def test_the_catalogue_variants_keep_their_values():
    """A typed variant holds what its mapping says (SI units, no conversion on the way), for every
    variant of the catalogue, and the scene a family derives from it is the scene's with that value."""
    n = 0
    for s in CATALOGUE.values():
        for raw, v in zip(s.variants, s.typed_variants):
            for k, x in raw.items():  # the numbers (tilts, grids, refinements: below or by their own tests)
                if hasattr(v, k) and not isinstance(x, (tuple, list, dict, str)):
                    assert getattr(v, k) == pytest.approx(float(x), rel=1e-15), (s.name, k)
                    n += 1
            if s.family == "points":
                sv = v.scene(s)
                assert sv.kx == raw["kx"] and sv.b == raw.get("b", s.b) and sv.family == "pair"
            if s.family == "tilt":
                sv = v.scene(s)
                assert sv.b == raw["b"] and sv.profile == raw["profile"]
                assert sv.fe_levels == tuple(raw.get("fe_levels", s.fe_levels))
                for j in range(len(sv.fe_levels)):
                    opts = v.mesh_options(j)
                    assert {k: tuple(raw[k][j]) for k in ("refine", "band") if k in raw} == opts
    assert n > 50
