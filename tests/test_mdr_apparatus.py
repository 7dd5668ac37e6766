"""Apparatus model: limits, the paper's central findings, bad input."""
import numpy as np
import pytest

from mdr import FlatPunch, InputError, MDRContact, Sphere, TruncatedSphere
from mdr.apparatus import Apparatus, apparatus_result, run_apparatus
from mdr.drive import run_contact

from conftest import F0, MU, R, STEEL


def test_stiff_frictionless_apparatus_reduces_to_direct_drive():
    prof = TruncatedSphere(R, 20e-6)
    app = Apparatus(kx=np.inf, plate_model="rigid", bedding=False)
    res = apparatus_result(prof, STEEL, app, MU, F0, dF=0.1, alpha=0.3, ua=40e-9, cycles=3, steps=200)
    direct = run_contact(prof, STEEL, MU, F0, dF=0.1, alpha=0.3, ua=40e-9, cycles=3, steps=200)
    assert res["dissipation"] == pytest.approx(direct["dissipation"], rel=1e-9)
    np.testing.assert_allclose(res["loop"]["Fx"], direct["loop"]["Fx"], rtol=0, atol=1e-12 * MU * F0)
    np.testing.assert_allclose(res["loop"]["du"], direct["loop"]["du"], atol=1e-18)


def test_equilibrium_and_coulomb_bounds_hold_every_step():
    law = MDRContact(Sphere(R), STEEL, MU, F_max=0.6, F_min=0.4, n=100)
    app = Apparatus(kx=2e6)
    out = run_apparatus(law, app, MU, F0, 0.1, 0.0, 150e-9, cycles=3, steps=80)
    # indenter: F_x = kx u1; block: plates carry contact + bedding forces
    np.testing.assert_allclose(out["Fx"], app.kx * out["u1"], rtol=1e-12)
    np.testing.assert_allclose(app.k_plates * (out["u3"] - out["u2"]), out["Fx"] + out["Fbed"], atol=1e-9)
    assert np.all(np.abs(out["Fx"]) <= MU * out["FN"] * (1 + 1e-9))
    assert np.all(np.abs(out["Fbed"]) <= app.mu2 * (app.m1 * 9.81 + out["FN"]) * (1 + 1e-9))
    assert out["cycles"].last_is_stationary


def test_profile_transition_sphere_below_10um_flat_punch_above_30um():
    # the paper's central finding (Fig. 8), at two apparatus stiffnesses, one batch pass each
    b = np.array([1e-6, 5e-6, 40e-6, 100e-6, 300e-6])
    for kx in (2e6, 10e6):
        kw = dict(cycles=3, steps=120)
        trunc = MDRContact(TruncatedSphere(np.full(b.size, R), b), STEEL, MU, F_max=0.6, F_min=0.4, n=100)
        d_tr = run_apparatus(trunc, Apparatus(kx=kx), MU, F0, 0.1, 0.0, 150e-9, **kw)["slip_index"]
        flat = MDRContact(FlatPunch(b), STEEL, MU, n=8)
        d_fl = run_apparatus(flat, Apparatus(kx=kx), MU, F0, 0.1, 0.0, 150e-9, **kw)["slip_index"]
        sph = MDRContact(Sphere(R), STEEL, MU, F_max=0.6, F_min=0.4, n=100)
        d_sp = float(run_apparatus(sph, Apparatus(kx=kx), MU, F0, 0.1, 0.0, 150e-9, **kw)["slip_index"])
        np.testing.assert_allclose(d_tr[:2], d_sp, rtol=0.02)
        np.testing.assert_allclose(d_tr[2:], d_fl[2:], rtol=0.02)
        assert d_fl[2] > d_sp  # the flat punch is stiffer: pushed towards sliding


def test_slip_index_rises_with_apparatus_stiffness_and_vanishes_when_soft():
    kx = np.array([0.3e6, 1e6, 2e6, 10e6])
    deltas = []
    for k in kx:
        law = MDRContact(TruncatedSphere(R, 50e-6), STEEL, MU, F_max=0.6, F_min=0.4, n=100)
        deltas.append(float(run_apparatus(law, Apparatus(kx=k), MU, F0, 0.1, 0.0, 150e-9, cycles=3, steps=120)["slip_index"]))
    assert np.all(np.diff(deltas) > 0)
    # well below k_c = mu F0 / u_A the contact sticks (the axis follows the block)
    assert deltas[0] < 0.02 < deltas[2]


@pytest.mark.parametrize("kw,word", [({"kx": 0.0}, "kx"), ({"m1": -1.0}, "m1"), ({"mu2": -0.1}, "mu2"),
                                      ({"l": 0.0}, "l"), ({"R_bed": float("nan")}, "R_bed"),
                                      ({"plate_model": "spring"}, "plate_model")])
def test_bad_apparatus_input(kw, word):
    with pytest.raises(InputError, match=word):
        Apparatus(**kw)


def test_bad_load_input():
    law = MDRContact(Sphere(R), STEEL, MU, F_max=0.6)
    with pytest.raises(InputError, match="ua"):
        run_apparatus(law, Apparatus(), MU, F0, 0.1, 0.0, -1e-9)
    with pytest.raises(InputError, match="dF"):
        run_apparatus(law, Apparatus(), MU, F0, 0.6, 0.0, 1e-7)
