"""The compiled time loops (mdr.kernels) against the step API they mirror.

Truth: the step API of ``MDRContact`` (``step``/``prepare``/``force``/``commit``) and the
Python step loop of ``run_apparatus``, run with the compiled loops switched off
(``mdr.kernels.ENABLED = False``). The compiled loops do the same arithmetic cell by cell;
only the order of the sums differs (and numpy's SIMD kernels, which differ between CPUs), so
every history must agree to round-off (1e-12 of its scale) and the stick radius, continuous
in the slacks, within 1e-9 of its scale. Nothing is compared bit for bit: another CPU rounds
differently.
Without numba (or with MDR_PURE_PYTHON=1) everything runs through the step API.
"""
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mdr import FlatPunch, InputError, MDRContact, Sphere, TruncatedSphere, kernels
from mdr.apparatus import Apparatus, run_apparatus
from mdr.grid import make_grid
from mdr.normal import approach_from_force

from conftest import F0, MU, R, STEEL, harmonic
from mdr.loading import Loading

pytestmark = pytest.mark.skipif(not kernels.enabled(), reason="compiled loops off (numba missing or MDR_PURE_PYTHON=1)")

ROOT = Path(__file__).resolve().parent.parent
RTOL = 1e-12
#: stick radii of two code paths (round-off in the slacks, through the estimator's slope)
C_RTOL = 1e-9


def both(fn, monkeypatch):
    """fn() with the compiled loops, then with the step API."""
    fast = fn()
    monkeypatch.setattr(kernels, "ENABLED", False)
    slow = fn()
    monkeypatch.setattr(kernels, "ENABLED", True)
    return fast, slow


def close(fast, slow, rtol=RTOL, what=""):
    fast, slow = np.asarray(fast, dtype=float), np.asarray(slow, dtype=float)
    assert fast.shape == slow.shape, what
    scale = max(float(np.max(np.abs(slow))), 1e-300)
    np.testing.assert_allclose(fast, slow, rtol=0, atol=rtol * scale, err_msg=what)


def same_history(law, fast, slow):
    for f in ("u", "Fx", "FN", "d", "a", "work"):
        close(getattr(fast, f), getattr(slow, f), what=f)
    close(fast.state.ell, slow.state.ell, what="ell")
    # the state's v and u on the scale of the displacement history, d on that of d
    u_scale = RTOL * np.max(np.abs(slow.u))
    np.testing.assert_allclose(fast.state.v, slow.state.v, rtol=RTOL, atol=u_scale)
    np.testing.assert_allclose(fast.state.u, slow.state.u, rtol=0, atol=u_scale)
    np.testing.assert_allclose(fast.state.d, slow.state.d, rtol=0, atol=RTOL * np.max(np.abs(slow.d)))
    if slow.slack is not None:
        close(fast.slack, slow.slack, what="slack")
    # the stick radius is continuous in the slacks (mdr.stick): slacks equal to 1e-12 of their
    # scale move it by that much over the estimator's slope, bounded by one cell over the
    # slack's change across a cell; C_RTOL = 1e-9 of the contact radius leaves three decades
    close(fast.c, slow.c, rtol=C_RTOL, what="c")


# ---------------------------------------------------------------- displacement control
@pytest.mark.parametrize("prof", [TruncatedSphere(R, 20e-6), Sphere(R), FlatPunch(100e-6), TruncatedSphere(R, 20e-6, exact=True)],
                         ids=["truncated", "sphere", "flat", "exact-cap"])
def test_displacement_control_equals_the_step_api(prof, monkeypatch):
    t, s = harmonic(3, 200)
    FN = F0 + 0.1 * np.sin(2 * np.pi * t + 0.4)
    law = MDRContact(prof, STEEL, MU, F_max=0.6, F_min=0.4)
    fast, slow = both(lambda: law.run(u=150e-9 * s, F_N=FN, record_from=400), monkeypatch)
    same_history(law, fast, slow)
    assert np.ptp(slow.c) > 0 and np.sum(slow.work) > 0  # partial slip with a moving stick edge


def test_contact_lost_and_regained_and_a_given_start_state(monkeypatch):
    """F_N drops to zero twice (all tangential history released) and the history is
    continued from a state: both paths alike."""
    t, s = harmonic(2, 200)
    FN = np.where(np.abs(np.sin(2 * np.pi * t)) < 0.3, 0.0, F0 * (1 + 0.2 * np.cos(6 * np.pi * t)))
    law = MDRContact(Sphere(R), STEEL, MU, F_max=0.6)
    u = 150e-9 * np.sin(2 * np.pi * t + 0.3)
    fast, slow = both(lambda: law.run(u=u, F_N=FN, record_from=0), monkeypatch)
    assert np.any(slow.a == 0) and np.any(slow.a > 0)
    same_history(law, fast, slow)
    fast2, slow2 = both(lambda: law.run(u=u[::-1], F_N=FN, state=slow.state), monkeypatch)
    same_history(law, fast2, slow2)


def test_batch_of_scenes_equals_the_step_api(monkeypatch):
    b = np.array([0.0, 5e-6, 20e-6, 100e-6, 1e-3])
    mu = np.array([0.1, 0.2, 0.3, 0.2, 0.5])
    law = MDRContact(TruncatedSphere(np.full(b.size, R), b), STEEL, mu, F_max=0.6, F_min=0.4, n=120)
    t, s = harmonic(2, 150)
    u = np.outer(np.linspace(50e-9, 300e-9, b.size), s)
    fast, slow = both(lambda: law.run(u=u, F_N=F0 + 0.1 * np.sin(2 * np.pi * t), record_from=150), monkeypatch)
    same_history(law, fast, slow)


# ---------------------------------------------------------------- force control
@pytest.mark.parametrize("prof,fa", [(TruncatedSphere(R, 20e-6), 0.06), (FlatPunch(100e-6), 0.06), (Sphere(R), 0.075)],
                         ids=["truncated", "flat", "sphere"])
def test_force_control_equals_the_step_api(prof, fa, monkeypatch):
    t, s = harmonic(2, 150)
    FN = F0 + 0.1 * np.sin(2 * np.pi * t)
    law = MDRContact(prof, STEEL, MU, F_max=0.6, F_min=0.4)
    fast, slow = both(lambda: law.run(Fx=fa * s, F_N=FN, record_from=0), monkeypatch)
    # the force is met to the Newton tolerance 1e-12 mu F_N in both
    assert np.max(np.abs(fast.Fx - fa * s)) <= 2e-12 * MU * np.max(FN)
    same_history(law, fast, slow)


def test_force_control_batch_and_its_friction_limit_error(monkeypatch):
    b = np.array([1e-6, 20e-6, 300e-6])
    law = MDRContact(TruncatedSphere(np.full(3, R), b), STEEL, MU, F_max=0.6, F_min=0.4, n=100)
    t, s = harmonic(2, 100)
    Fx = np.outer([0.02, 0.05, 0.08], s)
    fast, slow = both(lambda: law.run(Fx=Fx, F_N=F0, record_from=100), monkeypatch)
    same_history(law, fast, slow)
    msgs = []
    for enabled in (True, False):
        monkeypatch.setattr(kernels, "ENABLED", enabled)
        with pytest.raises(InputError, match="friction limit") as err:
            law.run(Fx=Fx * np.array([[1.0], [1.0], [1.3]]), F_N=F0)
        msgs.append(str(err.value))
    assert msgs[0] == msgs[1]


# ---------------------------------------------------------------- apparatus
def same_apparatus(fast, slow):
    for f in ("Fx", "FN", "u1", "u2", "du", "Fbed", "a", "c"):
        close(fast[f], slow[f], what=f)
    close(fast["stick_radius"], slow["stick_radius"], what="stick_radius")
    # the dissipation as the slip index dW / (4 mu u_A F0), on the scale of its range
    # (a sticking contact dissipates ~0)
    np.testing.assert_allclose(fast["slip_index"], slow["slip_index"], rtol=RTOL, atol=RTOL)


@pytest.mark.parametrize("prof,app", [
    (TruncatedSphere(R, 50e-6), Apparatus(kx=2e6)),
    (Sphere(R), Apparatus(kx=10e6, R_bed=2.5e-3, mu2=0.2)),
    (FlatPunch(50e-6), Apparatus(kx=2e6, plate_model="bending")),
    (TruncatedSphere(R, 20e-6), Apparatus(kx=np.inf, plate_model="rigid", bedding=False)),
    (TruncatedSphere(R, 20e-6), Apparatus(kx=2e6, plate_model="inplane")),
    # the tilting readings run the step loop both times, with the compiled bedding against the step API's
    (TruncatedSphere(R, 20e-6), Apparatus(kx=2e6, plate_model="tilt")),
    (TruncatedSphere(R, 20e-6), Apparatus(kx=2e6, plate_model="parallel")),  # idem (plate force not at h2)
], ids=["truncated", "sphere", "flat-bending", "rigid-no-bedding", "inplane", "tilt", "parallel"])
def test_apparatus_equals_the_python_step_loop(prof, app, monkeypatch):
    law = MDRContact(prof, STEEL, MU, F_max=0.6, F_min=0.4, n=100) if not isinstance(prof, FlatPunch) \
        else MDRContact(prof, STEEL, MU, n=8)
    kw = dict(dF=0.1, alpha=0.3, ua=150e-9, cycles=3, steps=120)
    fast, slow = both(lambda: run_apparatus(law, app, Loading.apparatus(F0, **kw), state_at=200), monkeypatch)
    same_apparatus(fast, slow)
    # an iteration count is a discrete diagnostic: round-off may stop a bracketing search one
    # evaluation earlier or later, so it is compared as a count, not to the bit
    assert abs(fast["evaluations_per_step"] - slow["evaluations_per_step"]) <= 0.05 * slow["evaluations_per_step"]
    for f in ("v", "ell"):
        close(getattr(fast["state_at"], f), getattr(slow["state_at"], f), what=f)
    np.testing.assert_allclose(fast["state_at"].u, slow["state_at"].u, rtol=0, atol=RTOL * np.max(np.abs(slow["du"])))


def test_apparatus_batch_with_per_scene_fields_equals_the_python_step_loop(monkeypatch):
    """One batch with k_x, mu2, R_bed, the plate model, dF and alpha per scene (as the
    sensitivity study runs it)."""
    shape = (2, 3)
    b = np.array([[10e-6], [200e-6]]) * np.ones(shape)
    law = MDRContact(TruncatedSphere(np.full(shape, R), b), STEEL, MU, F_max=0.7, F_min=0.3, n=100)
    app = Apparatus(kx=np.array([1e6, 2e6, 20e6]) * np.ones(shape), mu2=np.array([0.05, 0.1, 0.0]) * np.ones(shape),
                    R_bed=np.array([2.5e-3, 5e-3, 10e-3]) * np.ones(shape),
                    plate_model=np.array([["axial", "bending", "rigid"]] * 2))
    dF = np.array([0.0, 0.1, 0.2]) * np.ones(shape)
    kw = dict(dF=dF, alpha=np.array([0.0, 1.0, 3.0]) * np.ones(shape), ua=150e-9, cycles=3, steps=80)
    fast, slow = both(lambda: run_apparatus(law, app, Loading.apparatus(F0, **kw)), monkeypatch)
    same_apparatus(fast, slow)


class OtherLaw(MDRContact):
    """The MDR law as a law without a compiled loop (``run_apparatus`` compiles ``MDRContact`` itself only):
    its steps run through the step loop, as an FE or rough law's do, with the bedding compiled or not."""


def test_the_compiled_bedding_equals_the_step_api_around_a_law_without_a_compiled_loop(monkeypatch):
    """``mdr.kernels.CompiledBedding`` (the step loop around any law) against ``mdr.apparatus.StepBedding``
    (the bedding's step API): a batch of two faces under per-scene k_x, mu2 and R_bed, untilted and
    tilting, within round-off; and the bedding carries force (with mu2 = 0 the slip index moves)."""
    import mdr.apparatus as ap

    used, real = [], kernels.CompiledBedding
    monkeypatch.setattr(kernels, "CompiledBedding", type("Spy", (real,), {
        "__init__": lambda self, *a: (used.append(1), real.__init__(self, *a))[1]}))
    b = np.array([20e-6, 200e-6])
    law = OtherLaw(TruncatedSphere(np.full(2, R), b), STEEL, MU, F_max=0.7, F_min=0.3, n=100)
    kw = dict(dF=0.1, alpha=0.3, ua=150e-9, cycles=3, steps=80)
    for plates in ("axial", "tilt"):
        app = Apparatus(kx=np.array([2e6, 20e6]), mu2=np.array([0.1, 0.2]), R_bed=np.array([2.5e-3, 5e-3]),
                        plate_model=plates)
        used.clear()
        fast, slow = both(lambda: run_apparatus(law, app, Loading.apparatus(F0, **kw)), monkeypatch)
        assert used == [1]  # compiled the first time, the step API the second
        same_apparatus(fast, slow)
        close(fast["Fbed"], slow["Fbed"], what="Fbed")
        assert np.all(np.max(np.abs(slow["Fbed"]), axis=-1) > 0.01 * MU * F0)
        free = run_apparatus(law, ap.Apparatus(kx=app.kx, mu2=0.0, plate_model=plates), Loading.apparatus(F0, **kw))
        assert np.all(np.abs(free["slip_index"] - fast["slip_index"]) > 1e3 * RTOL)


def test_the_compiled_bedding_beyond_its_grid_raises_as_the_step_api(monkeypatch):
    import mdr.apparatus as ap

    small = lambda app, Wmax, batch: ap._mdr_bedding(app, 0.5 * Wmax, batch)  # noqa: E731  (a grid too short)
    law = OtherLaw(Sphere(R), STEEL, MU, F_max=0.6, n=100)
    msgs = []
    for enabled in (True, False):
        monkeypatch.setattr(kernels, "ENABLED", enabled)
        with pytest.raises(InputError, match="exceeds the spring grid") as err:
            loading = Loading.apparatus(F0, dF=0.1, alpha=0.0, ua=150e-9, cycles=2, steps=20)
            run_apparatus(law, Apparatus(kx=2e6), loading, bed_law_factory=small)
        msgs.append(str(err.value))
    assert msgs[0] == msgs[1]


def test_apparatus_lift_off_error_is_the_same(monkeypatch):
    law = MDRContact(Sphere(R), STEEL, MU, F_max=0.6, n=100)
    app = Apparatus(kx=20e6, h=2.0, h2=0.001, l1=1e-4)  # a tall block on a short base tips over
    msgs = []
    for enabled in (True, False):
        monkeypatch.setattr(kernels, "ENABLED", enabled)
        with pytest.raises(InputError, match="lifts off") as err:
            run_apparatus(law, app, Loading.apparatus(F0, dF=0.1, alpha=0.0, ua=300e-9, cycles=2, steps=40))
        msgs.append(str(err.value))
    assert msgs[0] == msgs[1]


# ---------------------------------------------------------------- normal contact and grids
def test_compiled_approach_equals_numpy_within_its_newton_tolerance(monkeypatch):
    """The truncated sphere's approach from the force (a safeguarded Newton iteration on the
    contact radius, stopped at |F(a) - F| <= 1e-14 F or a step <= 1e-14 a) is the same
    iteration compiled. Each path stops within 1e-14 of the root in a (quadratic convergence
    makes it far less), and d = g(a) doubles a relative error in a at most (d ~ a^2 for the
    sphere, less beyond a flat face), so the two agree within 2 x 2 x 1e-14 = 4e-14."""
    b = np.geomspace(1e-7, 1e-3, 40)[:, None]
    prof = TruncatedSphere(np.full(b.shape, R), b)
    F = np.broadcast_to(np.concatenate([[0.0, 1e-9], np.linspace(0.1, 2.0, 30)]), (40, 32))
    fast, slow = both(lambda: approach_from_force(prof, STEEL, F), monkeypatch)
    np.testing.assert_allclose(fast, slow, rtol=4e-14, atol=0)
    assert np.all(fast[:, 0] == 0) and np.all(slow[:, 0] == 0)


def test_a_batch_of_equal_grids_equals_the_single_grid():
    one = make_grid(Sphere(R), 50e-6, n=100, a_min=30e-6)
    many = make_grid(Sphere(np.full((3, 2), R)), np.full((3, 2), 50e-6), n=100, a_min=np.full((3, 2), 30e-6))
    np.testing.assert_array_equal(many.edges, np.broadcast_to(one.edges, (3, 2, 101)))


# ---------------------------------------------------------------- without numba
FALLBACK = """
import sys
{block}
import numpy as np
from mdr import MDRContact, TruncatedSphere, Materials, kernels
from mdr.apparatus import Apparatus, run_apparatus
from mdr.loading import Loading
assert not kernels.enabled()
t = np.arange(241) / 120
law = MDRContact(TruncatedSphere(6e-3, 20e-6), Materials(), 0.2, F_max=0.6, F_min=0.4, n=100)
H = law.run(u=150e-9 * np.sin(2 * np.pi * t), F_N=0.5 + 0.1 * np.sin(2 * np.pi * t))
G = law.run(Fx=0.05 * np.sin(2 * np.pi * t), F_N=0.5)
o = run_apparatus(law, Apparatus(kx=2e6), Loading.apparatus(0.5, 0.1, 0.0, 150e-9, cycles=2, steps=60))
np.save(sys.argv[1], np.concatenate([H.Fx, H.work, G.u, o["Fx"], o["du"]]))
"""


@pytest.mark.parametrize("block", ["sys.modules['numba'] = None  # import numba fails", "import os"],
                         ids=["numba-missing", "MDR_PURE_PYTHON"])
def test_without_numba_everything_runs_through_the_step_api(block, tmp_path):
    """In a fresh interpreter without numba (an import that fails) or with MDR_PURE_PYTHON=1,
    the law and the apparatus run through the step API and give the compiled results."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), MDR_PURE_PYTHON="1" if block == "import os" else "")
    out = tmp_path / "fallback.npy"
    subprocess.run([sys.executable, "-c", FALLBACK.format(block=block), str(out)], check=True, env=env, cwd=ROOT)
    t = np.arange(241) / 120
    law = MDRContact(TruncatedSphere(6e-3, 20e-6), STEEL, 0.2, F_max=0.6, F_min=0.4, n=100)
    H = law.run(u=150e-9 * np.sin(2 * np.pi * t), F_N=0.5 + 0.1 * np.sin(2 * np.pi * t))
    G = law.run(Fx=0.05 * np.sin(2 * np.pi * t), F_N=0.5)
    o = run_apparatus(law, Apparatus(kx=2e6), Loading.apparatus(0.5, dF=0.1, alpha=0.0, ua=150e-9, cycles=2, steps=60))
    slow = np.load(out)
    parts = np.cumsum([H.Fx.size, H.work.size, G.u.size, o["Fx"].size])
    for fast_part, slow_part in zip((H.Fx, H.work, G.u, o["Fx"], o["du"]), np.split(slow, parts)):
        close(fast_part, slow_part)


def test_stale_compiled_loops_are_dropped(tmp_path):
    """numba checks only the file of a compiled function: a cached loop older than the one-step code it
    calls (``mdr.kernels_step.SOURCES``) is removed so that it compiles afresh; a newer one is kept,
    and so are the caches of other modules."""
    import os

    from mdr.kernels_step import DEPENDENTS, SOURCES, drop_stale_caches

    cache = tmp_path / "__pycache__"
    cache.mkdir()
    for f in SOURCES:
        (tmp_path / f).write_text("# code\n")
    old = [cache / f"{DEPENDENTS[0]}.run_law-10.py311.nbi", cache / f"{DEPENDENTS[0]}.run_law-10.py311.1.nbc"]
    new = cache / f"{DEPENDENTS[0]}.apparatus-5.py311.nbi"
    other = cache / "law.something-1.py311.nbi"
    for f in (*old, new, other):
        f.write_text("cache")
    t = (tmp_path / SOURCES[0]).stat().st_mtime
    for f in (*old, other):
        os.utime(f, (t - 100, t - 100))
    os.utime(new, (t + 100, t + 100))
    removed = drop_stale_caches(tmp_path)
    assert sorted(removed) == sorted(old) and not any(f.exists() for f in old)
    assert new.exists() and other.exists()
    assert drop_stale_caches(tmp_path / "missing") == []
