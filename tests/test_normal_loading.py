"""The normal loading before the cycles (``Loading.normal_steps``, ``mdr.drive.normal_loading``): one
driver for every law, stated in each result.

Truth: for bodies without normal-tangential coupling (one material, Dundurs' beta = 0) a normal loading at
F_x = 0 puts no tangential traction into the contact, so every cycle after it is the cycle without it
(Mindlin & Deresiewicz 1953: the history of F_x alone decides). Checked on MDR and on the axisymmetric FE
law, each with and without 20 steps of it; the result says which ran.
"""
import dataclasses

import pytest

from common.errors import InputError
from mdr.drive import run_contact, run_mdr_contact
from mdr.loading import Loading
from mdr.materials import Materials
from mdr.profiles import Sphere

LOAD = Loading.of(0.5, fa=0.05, cycles=2, steps=40)
RAMP = dataclasses.replace(LOAD, normal_steps=20)


def test_an_uncoupled_law_after_a_normal_loading_runs_the_same_cycles():
    without = run_mdr_contact(Sphere(6e-3), Materials(), 0.2, LOAD)
    ramped = run_mdr_contact(Sphere(6e-3), Materials(), 0.2, RAMP)
    assert without["normal_loading"] == {"steps": 0} and ramped["normal_loading"]["steps"] == 20
    for k in ("dissipation", "dissipation_first_cycle", "stick_radius", "dissipation_open_path"):
        assert ramped[k] == pytest.approx(without[k], rel=1e-9), k


def test_the_fe_law_takes_the_same_normal_loading(monkeypatch):
    from fem.axisym.law import FEContact

    law = FEContact(Sphere(6e-3), Materials(), 0.2, F_max=0.5, h_contact=0.1, displacement="contact")
    without = run_contact(law, LOAD)
    seen, step = [], law.step

    def spy(state, **load):  # the normal loading's steps: F_x = 0, F_N rising to F0
        seen.append((load.get("Fx"), load.get("F_N")))
        return step(state, **load)

    monkeypatch.setattr(law, "step", spy)
    ramped = run_contact(law, RAMP)
    monkeypatch.undo()
    ramp = seen[:20]  # then the cycles' steps
    assert [x for x, _ in ramp] == [0.0] * 20 and [f for _, f in ramp] == pytest.approx([0.5 * k / 20 for k in range(1, 21)])
    assert ramped["normal_loading"] == {"steps": 20, "friction": True, "F_x": 0.0}
    assert ramped["dissipation"] == pytest.approx(without["dissipation"], rel=1e-6)
    # a continued history states none: its first run holds it
    _, st = run_contact(law, RAMP, return_state=True)
    assert run_contact(law, LOAD, state0=st)["normal_loading"] is None


@pytest.mark.parametrize("bad", [-1, 2.5, True])
def test_a_bad_normal_loading_is_refused(bad):
    with pytest.raises(InputError, match="normal_steps must be an integer >= 0"):
        dataclasses.replace(LOAD, normal_steps=bad)
