"""The on-disk cache of the 3D bodies' condensed interfaces (``fem.solid3d.condensed``): a warm set-up
reads what a cold one computed (the same model to the last bit), skips the condensation, one file
serves every Young's modulus of a Poisson ratio, and a corrupt file is rebuilt, never used."""
import warnings

import numpy as np
import pytest

from fem.solid3d.law import FEContact3D
from mdr.materials import Materials
from mdr.profiles import Sphere

R, MU, F = 6e-3, 0.2, 0.5


def law(cache, **kw):
    return FEContact3D(Sphere(R), kw.pop("mat", Materials()), MU, F_max=F, h_contact=0.3, cache_dir=cache, **kw)


def files(cache):
    return sorted(p.name for p in cache.glob("condensed3d-*.npz"))


def test_a_warm_set_up_is_the_cold_one_without_the_condensation(tmp_path):
    cold = law(tmp_path)
    assert cold.model.condensed["block"]["cache"] == "miss" and cold.model.timings["condensation"] > 0
    warm = law(tmp_path)
    assert warm.model.condensed["block"]["cache"] == "hit"
    assert warm.model.timings["condensation"] == 0 and warm.model.timings["factorisation"] == 0
    assert np.array_equal(warm.model.rf.Dt, cold.model.rf.Dt) and np.array_equal(warm.model.rf.Dn, cold.model.rf.Dn)
    assert warm.model.ndofs == cold.model.ndofs and warm.model.c_bulk == cold.model.c_bulk
    a, b = cold.normal(F_N=F), warm.normal(F_N=F)
    assert np.array_equal(a.p, b.p) and a.approach == b.approach
    # against the condensation of a body of E = 200 GPa directly (the cache stores E = 1 Pa): round-off
    from fem.solid3d.elastic import stiffness3d
    from fem.solid3d.interface import mortar_flexibility

    m = Materials()
    K, basis = stiffness3d(cold.model.hmesh.mesh, m.E2, m.nu2)
    D, _, _ = mortar_flexibility(K, basis, cold.model.hmesh.mesh, cold.model.mi)
    Dt_direct = np.asarray(D)[:2 * cold.n, :2 * cold.n]
    blk = np.asarray(cold.model.Dt_plate)  # block + indenter, steel on steel: twice the block's
    assert np.max(np.abs(blk[:2 * cold.n, :2 * cold.n] - 2 * Dt_direct)) < 1e-10 * np.max(np.abs(Dt_direct))


def test_one_file_per_poisson_ratio_and_every_modulus_shares_it(tmp_path):
    steel = law(tmp_path)
    # other moduli of the same E* (the same mesh) and the same nu: the same file, scaled by 1/E
    other = law(tmp_path, mat=Materials(E1=200e9 * 2 / 3, E2=400e9))
    assert len(files(tmp_path)) == 1 and other.model.condensed["block"]["cache"] == "hit"
    assert np.allclose(other.model.rf.Dt, steel.model.rf.Dt, rtol=1e-12, atol=0)  # 3/400 + 1/400 = 2/200
    # a dissimilar pair (another E*: its own mesh): one file per body, both read back the next time
    alu = law(tmp_path, mat=Materials(E2=70e9, nu2=0.33))
    assert alu.model.condensed["block"]["cache"] == alu.model.condensed["indenter"]["cache"] == "miss"
    assert len(files(tmp_path)) == 3
    again = law(tmp_path, mat=Materials(E2=70e9, nu2=0.33))
    assert again.model.condensed["block"]["cache"] == again.model.condensed["indenter"]["cache"] == "hit"
    assert np.array_equal(again.model.rf.Dt, alu.model.rf.Dt) and again.model.beta == alu.model.beta


def test_a_corrupt_file_is_rebuilt_not_used(tmp_path):
    cold = law(tmp_path)
    (path,) = tmp_path.glob("condensed3d-*.npz")
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF  # one flipped byte inside the arrays
    path.write_bytes(bytes(data))
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        again = law(tmp_path)
    assert again.model.condensed["block"]["cache"] == "rebuilt" and any("digest" in str(x.message) or "unreadable"
                                                                   in str(x.message) for x in w)
    assert np.array_equal(again.model.rf.Dt, cold.model.rf.Dt)
    assert law(tmp_path).model.condensed["block"]["cache"] == "hit"
