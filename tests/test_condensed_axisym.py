"""The on-disk cache of the axisymmetric model's condensed mode-1 interface (``fem.axisym.condensed``):
a warm set-up reads what a cold one computed (the same flexibility and bulk probes to the last bit, so
the same steps), the field output's factorisations are rebuilt on demand and agree with it to
round-off, another material is another file, and a corrupt file is rebuilt, never used."""
import warnings

import numpy as np

from fem.axisym.law import FEContact
from mdr.materials import Materials
from mdr.profiles import Sphere

R, MU, F = 6e-3, 0.2, 0.5


def law(cache, **kw):
    return FEContact(Sphere(R), kw.pop("mat", Materials()), MU, F_max=F, h_contact=0.1, cache_dir=cache, **kw)


def files(cache):
    return sorted(p.name for p in cache.glob("condensed-axisym-*.npz"))


def test_a_warm_set_up_is_the_cold_one_and_the_fields_condense_on_demand(tmp_path):
    cold = law(tmp_path)
    assert cold.condensed_cache == "miss" and len(files(tmp_path)) == 1
    warm = law(tmp_path)
    assert warm.condensed_cache == "hit" and warm._mode1 is None  # nothing factorised for mode 1
    assert np.array_equal(warm.Ct, cold.Ct) and np.array_equal(warm.bulk.c_indenter, cold.bulk.c_indenter)
    assert np.array_equal(warm.bulk.c_block, cold.bulk.c_block) and warm.dofs == cold.dofs
    ra, _ = cold.step(cold.rest_state(), F_N=F, Fx=0.05)
    rb, _ = warm.step(warm.rest_state(), F_N=F, Fx=0.05)
    assert float(ra.u) == float(rb.u) and float(ra.c) == float(rb.c)
    # the bodies' factorisations rebuilt for the field output (no condensation): their displacement at the
    # contact nodes under forces there is the condensed flexibility's, to round-off
    from fem.axisym.law import condensed_mode1

    full = condensed_mode1(cold.model, cold.amesh, cold.materials, cold.bulk_probe_depth, None)[0]
    rng = np.random.default_rng(0)
    for name in ("indenter", "block"):
        cond, ref = warm.mode1[name][3], full[name][3]
        f = rng.standard_normal(ref.C.shape[0])  # a force on each of the body's contact nodes
        assert cond.C is None
        u = cond.displacement(f)[ref.interface_dofs]
        assert np.max(np.abs(u - ref.C @ f)) <= 1e-10 * np.max(np.abs(ref.C @ f))
    assert warm.dofs == warm.model.dofs + sum(v[1].N for v in warm.mode1.values())


def test_another_material_is_another_file(tmp_path):
    law(tmp_path)
    alu = law(tmp_path, mat=Materials(E2=70e9, nu2=0.33))
    assert alu.condensed_cache == "miss" and len(files(tmp_path)) == 2
    assert law(tmp_path, mat=Materials(E2=70e9, nu2=0.33)).condensed_cache == "hit"


def test_a_corrupt_file_is_rebuilt_not_used(tmp_path):
    cold = law(tmp_path)
    (path,) = tmp_path.glob("condensed-axisym-*.npz")
    with np.load(path) as z:  # one entry of the flexibility changed, the header (and its digest) kept
        arrs = {k: z[k].copy() for k in z.files}
    arrs["block/C"][0, 0] *= 1.0 + 1e-6
    np.savez(path, **arrs)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        again = law(tmp_path)
    assert again.condensed_cache == "rebuilt" and any("digest" in str(x.message) or "unreadable" in str(x.message)
                                                     for x in w)
    assert np.array_equal(again.Ct, cold.Ct)
    assert law(tmp_path).condensed_cache == "hit"
