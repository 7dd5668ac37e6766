"""python -m mdr study fig8|fig9 --law NAME: the studies with a plugin law beside MDR (studies.law_study).

The plumbing is checked against an existing path: with the MDR law itself as the plugin, the
study points equal the vectorised MDR study to round-off. The FE law is reused from its rest
state for every apparatus point of a geometry. FE-backed Fig. 9 points agree with MDR within
the FE own error plus the slip-index tolerance of the verdicts (slow).
"""
from __future__ import annotations

import argparse
import concurrent.futures as cf
import csv
import json

import numpy as np
import pytest

from studies.cli import build_parser, main as mdr_main
from mdr.law import MDRContact
from studies.law_study import law_study, pick, study_points
from studies.study import R_IND, RES, TABLE2, fig9, run_studies
from mdr.loading import Loading


class MDRPlugin:
    """The MDR law as a plugin: RES["n"] cells, divided by ``coarsen`` for the coarser levels."""

    help = "MDR as a plugin (test)"

    @staticmethod
    def add_arguments(parser):
        pass

    @staticmethod
    def make_law(profile, materials, mu, F_max, args, coarsen=1.0):
        F0, dF = TABLE2["F0"], TABLE2["dF"]
        return MDRContact(profile, materials, mu, F_max=F_max, F_min=F0 - dF, n=int(RES["n"] / coarsen))


def test_pick_spreads_points_with_both_ends():
    v = list(range(30))
    assert pick(v, 5) == [0, 7, 14, 22, 29]
    assert pick(v, 2) == [0, 29] and pick(v, 40) == v and pick([3, 1, 3, 2], 9) == [1, 2, 3]


@pytest.mark.parametrize("threads", [False, True])
def test_plugin_points_equal_the_vectorised_mdr_study(threads):
    """The MDR law as the plugin: every point of the (geometry, level) tasks equals the batch
    MDR study at the same b and k_x (one law per geometry, reused from rest for each k_x), and
    the own error is the two-level difference to the study at half the cells."""
    rows = fig9(nk=5)
    pool = cf.ThreadPoolExecutor(2) if threads else None
    try:
        out, tasks = law_study("fig9", rows, "mdr2", MDRPlugin(), argparse.Namespace(), R=R_IND, load=TABLE2,
                               res=RES, points=2, levels=2, executor=pool)
    finally:
        if pool is not None:
            pool.shutdown()
    assert len(out) == 6 and len(tasks) == 6 and all(t["points"] == 2 for t in tasks)
    assert sorted({r["kx"] for r in out}) == pick([r["kx"] for r in rows], 2)
    batch = {(r["b"], r["kx"]): r["slip_index_truncated"] for r in rows}
    from studies import study

    half = dict(RES, n=RES["n"] // 2)
    b = np.array([r["b"] for r in out])
    k = np.array([r["kx"] for r in out])
    from mdr.profiles import TruncatedSphere

    d_half, _ = study._slip_index(TruncatedSphere(np.full(b.shape, R_IND), b), k, res=half)
    for r, dh in zip(out, d_half):
        assert r["slip_index_mdr2"] == pytest.approx(batch[(r["b"], r["kx"])], rel=1e-9, abs=1e-12)
        assert abs(r["difference"]) <= 1e-9 * max(r["slip_index_mdr"], 1e-3)
        assert r["slip_index_mdr2_c2"] == pytest.approx(dh, rel=1e-9, abs=1e-12)
        assert r["mdr2_error"] == pytest.approx(abs(r["slip_index_mdr2_c1"] - r["slip_index_mdr2_c2"]), rel=1e-12, abs=1e-15)
        assert r["mdr2_status"] == "two levels"


def test_fig8_points_take_every_stiffness_at_each_chosen_b():
    rows = [{"b": b, "kx": k} for b in (1e-6, 1e-5, 1e-4, 1e-3) for k in (1e6, 2e6)]
    assert study_points("fig8", rows, 2) == {1e-6: [1e6, 2e6], 1e-3: [1e6, 2e6]}


def test_law_study_bad_input(tmp_path, capsys):
    out = tmp_path / "s"
    for argv, word in ((["study", "loops", "--law", "fem"], "fig8"),
                       (["study", "fig9", "--law", "fem", "--points", "1"], "points"),
                       (["study", "fig9", "--law", "fem", "--levels", "0"], "levels"),
                       (["study", "fig9", "--points", "3"], "--law"),
                       (["study", "fig9", "--law", "fem", "--h-contact", "2"], "h_contact")):
        assert mdr_main(argv + ["--out", str(out)]) == 2, argv
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and word in err[-1], (argv, err)
    assert not out.exists()


@pytest.mark.filterwarnings("ignore:coarse contact mesh")
def test_the_fe_law_is_reused_from_its_rest_state():
    """One FE law for several apparatus points: a point run after another gives the result of
    the same point on a fresh law (the law is pure; each run starts from rest_state)."""
    from fem.cli import FE_LAW
    from mdr.apparatus import Apparatus, run_apparatus
    from mdr.materials import Materials
    from mdr.profiles import TruncatedSphere

    args = argparse.Namespace(h_contact=0.25, contact_extent=1.25, block_size=None, penalty=None, al_tol=None,
                              friction_al_tol=None, cache_dir=None, solver="auto")
    F0, dF, mu = TABLE2["F0"], TABLE2["dF"], TABLE2["mu1"]

    def run(law, kx):
        return run_apparatus(law, Apparatus(kx=kx, mu2=0.1), Loading.apparatus(F0, dF=dF, alpha=0.0, ua=TABLE2["ua"], cycles=2, steps=40))

    make = lambda: FE_LAW.make_law(TruncatedSphere(R_IND, 10e-6), Materials(), mu, F0 + dF, args)  # noqa: E731
    with FE_LAW.session():
        law = make()
        first = run(law, 2e6)
        run(law, 20e6)
        again = run(law, 2e6)
        fresh = run(make(), 2e6)
    assert 0.05 < first["slip_index"] < 0.95  # partial slip: the tangential history matters
    for res in (again, fresh):
        assert res["slip_index"] == pytest.approx(first["slip_index"], rel=1e-12, abs=1e-15)
        assert np.allclose(res["Fx"], first["Fx"], rtol=1e-12, atol=1e-15 * F0)


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:coarse contact mesh")
def test_fe_backed_fig9_agrees_with_mdr_and_is_the_same_on_dask(tmp_path):
    """FE-backed Fig. 9 at 3 k_x per b (a/5 and a/10): every point within the FE own error plus
    the slip-index tolerance of the verdicts of MDR; the study on a LocalCluster of 2 worker
    processes gives the rows of --jobs 2 (the same law, other processes)."""
    from distributed import LocalCluster

    from fem.cli import FE_LAW
    from validation.scenes import TOLERANCES

    argv = ["study", "fig9", "--law", "fem", "--h-contact", "0.1", "--points", "3"]
    assert mdr_main(argv + ["--jobs", "2", "--out", str(tmp_path / "jobs"), "--json", str(tmp_path / "j.json")]) == 0
    rows = json.loads((tmp_path / "j.json").read_text())["rows"]
    assert len(rows) == 9
    for r in rows:
        assert r["fem_error"] is not None and r["fem_error"] < 0.01  # resolution: own error below 0.01
        assert abs(r["difference"]) <= r["fem_error"] + TOLERANCES["slip_index"], r
        # docs/apparatus.md: own error <= 7e-4 and |FE - MDR| <= 4e-4 at a/10 (measured at 35 points)
        assert r["fem_error"] < 2e-3 and abs(r["difference"]) < 1e-3, r
    with open(tmp_path / "jobs" / "fig9_fem.csv") as f:
        assert [float(x["slip_index_fem"]) for x in csv.DictReader(f)] == [r["slip_index_fem"] for r in rows]
    assert (tmp_path / "jobs" / "fig9_fem.png").stat().st_size > 10_000
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        args = build_parser().parse_args(argv)
        dask = run_studies(["fig9"], tmp_path / "dask", scheduler=cluster.scheduler_address, law="fem",
                           plugin=FE_LAW, law_args=args, points=3)
    assert dask[0]["executor"].startswith("dask:") and len({t["worker"] for t in dask[0]["tasks"]}) == 2
    for a, b in zip(rows, dask[0]["rows"]):
        assert set(a) == set(b)
        for k in a:
            assert a[k] == pytest.approx(b[k], rel=1e-10, abs=1e-15) if isinstance(a[k], float) else a[k] == b[k]


@pytest.mark.filterwarnings("ignore:coarse contact mesh")
@pytest.mark.parametrize("kx", [0.5e6, 2e6, 20e6])
def test_fe_apparatus_point_equals_the_classical_augmented_lagrangian(kx):
    """An FE apparatus point as the studies run it (the exact-start friction AL with its exact
    tangent, step details worked out at commits only, the Newton predictor from the last slope)
    equals the same point with the classical AL converged to 1e-12 of the slip limit, both
    equilibria solved to round-off (xtol 1e-19 m): slip index, stick radius and loop (du, F_x,
    F_bed) to 1e-10 of their scale (measured 3e-12), at a sticking, a partly slipping and a
    sliding contact, in fewer force evaluations per step."""
    from fem.axisym.law import FEContact
    from mdr.apparatus import Apparatus, run_apparatus
    from mdr.materials import Materials
    from mdr.profiles import TruncatedSphere

    F0, dF, mu = TABLE2["F0"], TABLE2["dF"], TABLE2["mu1"]
    prof = TruncatedSphere(R_IND, 10e-6)
    kw = dict(F_max=F0 + dF, h_contact=0.2, displacement="contact")
    new, ref = (run_apparatus(law, Apparatus(kx=kx, mu2=TABLE2["mu2"]), Loading.apparatus(F0, dF=dF, alpha=0.0, ua=TABLE2["ua"], cycles=2, steps=60), xtol=1e-19)
                for law in (FEContact(prof, Materials(), mu, **kw),
                            FEContact(prof, Materials(), mu, friction_al_tol=1e-12, friction_exact_start=False,
                                      **kw)))
    assert new["slip_index"] == pytest.approx(ref["slip_index"], rel=0, abs=1e-10)
    assert new["stick_radius"] == pytest.approx(ref["stick_radius"], rel=0, abs=1e-10 * prof.b)
    for key in ("du", "Fx", "Fbed"):
        assert np.max(np.abs(new[key] - ref[key])) <= 1e-10 * np.max(np.abs(ref[key])), key
    assert new["evaluations_per_step"] < ref["evaluations_per_step"]
