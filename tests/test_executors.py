"""Where the work runs (common.executors): serial, --jobs N processes, --scheduler ADDRESS on Dask.

The scene results must not depend on where they ran: a Dask worker's result equals the
in-process one to round-off. A task that fails (an exception, a killed worker) leaves its
scene failed and the others complete; a rerun computes only what is missing.
"""
from __future__ import annotations

import concurrent.futures as cf
import json
import math
import os
import signal
import subprocess
import sys
import threading
import time
from dataclasses import replace
from pathlib import Path

import pytest

from common.errors import InputError
from common.executors import check_choice, executor_for, worker_id
from validation import compare
from validation.catalogue import CATALOGUE

distributed = pytest.importorskip("distributed")

ROOT = Path(__file__).resolve().parent.parent
#: keys that say how and where a result was computed, not what it is
VOLATILE = ("runtime_s", "runtime_cycles_s", "worker", "mesh")


def tiny(name="sphere-md", **kw):
    """A scene on very coarse ladders (seconds): structure, not accuracy."""
    return replace(CATALOGUE[name], fe_levels=(1 / 8, 1 / 16), mdr_cells=(25, 100), steps=40, cycles=3, **kw)


def physics(x):
    """The result without the volatile keys (timings, worker, mesh cache status, file names)."""
    if isinstance(x, dict):
        return {k: physics(v) for k, v in x.items() if k not in VOLATILE}
    if isinstance(x, list):
        return [physics(v) for v in x]
    return x


def assert_same(a, b, path="", rtol=1e-10):
    """Equal structure; numbers equal to round-off (the same code, another process)."""
    if isinstance(a, dict):
        assert set(a) == set(b), (path, set(a) ^ set(b))
        for k in a:
            assert_same(a[k], b[k], f"{path}/{k}", rtol)
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (u, v) in enumerate(zip(a, b)):
            assert_same(u, v, f"{path}[{i}]", rtol)
    elif isinstance(a, float) and isinstance(b, float):
        assert math.isclose(a, b, rel_tol=rtol, abs_tol=1e-300) or (math.isnan(a) and math.isnan(b)), (path, a, b)
    else:
        assert a == b, (path, a, b)


def stored(out, name):
    return json.loads((Path(out) / "scenes" / name / "result.json").read_text())


@pytest.fixture(scope="module")
def inproc_cluster():
    """A Dask scheduler with one in-process worker thread (fast to start)."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as c:
        yield c


# ---------------------------------------------------------------- choice of executor, errors


def test_scheduler_and_jobs_exclude_each_other(tmp_path, capsys):
    with pytest.raises(InputError, match="--scheduler and --jobs 2"):
        check_choice(2, "tcp://127.0.0.1:8786")
    assert check_choice(1, "tcp://127.0.0.1:8786") == 1 and check_choice(3) == 3
    assert compare.main(["--scenes", "sphere-md", "--jobs", "2", "--scheduler", "tcp://127.0.0.1:8786",
                         "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--scheduler" in err[0] and "--jobs" in err[0]
    from studies.cli import main as mdr_main

    assert mdr_main(["study", "fig9", "--jobs", "2", "--scheduler", "tcp://127.0.0.1:8786",
                     "--out", str(tmp_path / "s")]) == 2
    assert "--scheduler and --jobs 2" in capsys.readouterr().err
    assert not (tmp_path / "r").exists() and not (tmp_path / "s").exists()


def test_scheduler_without_dask_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)  # import distributed -> ImportError
    with pytest.raises(InputError, match=r"pip install 'fretting-mdr-fem\[dist\]'"):
        with executor_for(1, "tcp://127.0.0.1:8786"):
            pass


def test_unreachable_scheduler_is_bad_input(monkeypatch):
    import common.executors as ex

    monkeypatch.setattr(ex, "CONNECT_TIMEOUT_S", 1.0)
    with pytest.raises(InputError, match="tcp://127.0.0.1:9.*cannot be reached.*dask scheduler"):
        with executor_for(1, "tcp://127.0.0.1:9"):
            pass


def test_mdr_and_compare_import_no_dask():
    """Dask is optional and slow to import: no module imports it at import time."""
    code = ("import sys, mdr, studies.cli, studies.study, common.executors, validation.compare; "
            "bad = [m for m in ('dask', 'distributed') if m in sys.modules]; assert not bad, bad")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    subprocess.run([sys.executable, "-c", code], check=True, env=env, cwd=ROOT)


def test_worker_id_outside_and_inside_dask(inproc_cluster):
    import socket

    assert worker_id() == f"{socket.gethostname()}:{os.getpid()}"
    with executor_for(1, inproc_cluster.scheduler_address) as (ex, label):
        assert label == f"dask:{inproc_cluster.scheduler_address}"
        assert ex.submit(worker_id).result() == inproc_cluster.workers[0].address
    with executor_for(1) as (ex, label):
        assert ex is None and label == "serial"
    with executor_for(2) as (ex, label):
        assert label == "processes:2" and ex.submit(worker_id).result().split(":")[1] != str(os.getpid())


# ---------------------------------------------------------------- the plumbing on a Dask worker


@pytest.mark.filterwarnings("ignore:coarse contact mesh")
def test_compare_on_a_dask_worker_equals_the_serial_run(tmp_path, inproc_cluster):
    """python -m validation.compare --scheduler: the scene comes back from the worker as files
    (the output directory is the caller's), results.json records the executor and the worker,
    and the numbers equal those of the in-process run."""
    s = tiny()
    assert compare.run_all([s], tmp_path / "serial", fields=False, log=lambda m: None) == {s.name: "ok"}
    addr = inproc_cluster.scheduler_address
    with executor_for(1, addr) as (ex, label):
        st = compare.run_all([s], tmp_path / "dask", executor=ex, fields=False, log=lambda m: None)
    assert st == {s.name: "ok"}
    a, b = stored(tmp_path / "serial", s.name), stored(tmp_path / "dask", s.name)
    assert a["worker"] == worker_id()
    assert b["worker"] == inproc_cluster.workers[0].address
    assert_same(physics(a), physics(b))
    # files written by the worker arrived (the loop figure), nothing temporary is left
    assert sorted(p.name for p in (tmp_path / "dask" / "scenes" / s.name).iterdir()) == \
        sorted(p.name for p in (tmp_path / "serial" / "scenes" / s.name).iterdir())
    assert not [p for p in (tmp_path / "dask" / "scenes").iterdir() if p.name.startswith(".")]
    # results.json of the command names the executor; a rerun on the cluster skips the scene
    from validation import report

    report.write_report(tmp_path / "dask", [s.name], st, executor=label)
    res = json.loads((tmp_path / "dask" / "results.json").read_text())
    assert res["executor"] == f"dask:{addr}" and res["scenes"][s.name]["worker"] == b["worker"]


def test_compare_cli_with_scheduler_records_executor(tmp_path, inproc_cluster, monkeypatch):
    """The command line end to end, with run_all's scene work replaced by a stored result
    (the scene physics is the test above): --scheduler reaches the cluster's executor."""
    seen = {}

    def fake_run_all(scenes, out, *, executor=None, **kw):
        seen["worker"] = executor.submit(worker_id).result()
        return {s.name: "ok" for s in scenes}

    monkeypatch.setattr(compare, "run_all", fake_run_all)
    addr = inproc_cluster.scheduler_address
    assert compare.main(["--scenes", "sphere-md", "--scheduler", addr, "--out", str(tmp_path),
                         "--no-hard-cases"]) == 0
    assert seen["worker"] == inproc_cluster.workers[0].address
    assert json.loads((tmp_path / "results.json").read_text())["executor"] == f"dask:{addr}"


def test_study_on_a_dask_worker_equals_the_serial_run(tmp_path, inproc_cluster):
    from studies.study import run_studies

    a = run_studies(["fig9"], tmp_path / "serial")
    b = run_studies(["fig9"], tmp_path / "dask", scheduler=inproc_cluster.scheduler_address)
    assert a[0]["executor"] == "serial" and b[0]["executor"].startswith("dask:")
    assert b[0]["worker"] == inproc_cluster.workers[0].address
    assert a[0]["rows"] == b[0]["rows"]
    for f in ("fig9.csv", "fig9.png"):
        assert (tmp_path / "dask" / f).is_file()
    assert (tmp_path / "serial" / "fig9.csv").read_bytes() == (tmp_path / "dask" / "fig9.csv").read_bytes()


# ---------------------------------------------------------------- failures and reruns


class LosingExecutor(cf.Executor):
    """Runs tasks in threads, but the task of scene ``victim`` fails as a lost worker does."""

    def __init__(self, victim):
        self.victim, self.pool = victim, cf.ThreadPoolExecutor(max_workers=2)

    def submit(self, fn, *args, **kw):
        if args and getattr(args[0], "name", None) == self.victim:
            f = cf.Future()
            f.set_exception(OSError(f"worker running {self.victim} was lost"))
            return f
        return self.pool.submit(fn, *args, **kw)

    def shutdown(self, wait=True, **kw):
        self.pool.shutdown(wait=wait)


@pytest.mark.filterwarnings("ignore:coarse contact mesh")
def test_a_failed_task_leaves_its_scene_failed_and_a_rerun_completes_only_it(tmp_path):
    good, lost = tiny(), tiny("geom-flat")
    with LosingExecutor(lost.name) as ex:
        st = compare.run_all([good, lost], tmp_path, executor=ex, fields=False, log=lambda m: None)
    assert st[good.name] == "ok" and st[lost.name].startswith("OSError") and "lost" in st[lost.name]
    assert not (tmp_path / "scenes" / lost.name).exists()
    first = (tmp_path / "scenes" / good.name / "result.json").stat().st_mtime_ns
    with cf.ThreadPoolExecutor(max_workers=2) as ex:
        st = compare.run_all([good, lost], tmp_path, executor=ex, fields=False, log=lambda m: None)
    assert st == {good.name: "skipped", lost.name: "ok"}
    assert (tmp_path / "scenes" / good.name / "result.json").stat().st_mtime_ns == first
    assert stored(tmp_path, lost.name)["fem"]["dofs"] > 0


def test_a_worker_with_other_sources_refuses_the_scene(tmp_path):
    s = tiny()
    with pytest.raises(RuntimeError, match="other sources"):
        compare._remote(s, "fp", "not-this-version", False)


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:coarse contact mesh")
def test_a_killed_dask_worker_leaves_its_scene_failed_and_a_rerun_completes_it(tmp_path):
    """Two worker processes, one scene each: SIGKILL one worker while it computes its scene.
    That scene is failed (Dask's KilledWorker, no retry with allowed-failures 0), the other
    completes, and a rerun computes only the killed one."""
    import dask
    from distributed import Client, LocalCluster

    scenes = [tiny(), tiny("geom-flat")]
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), \
            LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        result = {}
        ex = client.get_executor(pure=False)
        th = threading.Thread(target=lambda: result.update(
            compare.run_all(scenes, tmp_path, executor=ex, fields=False, log=lambda m: None)))
        th.start()
        t0 = time.monotonic()
        while sorted(len(v) for v in client.processing().values()) != [1, 1]:
            assert time.monotonic() - t0 < 60, f"the two tasks did not start: {client.processing()}"
            time.sleep(0.05)
        time.sleep(0.5)  # both run (one thread per worker, one task each)
        victim = sorted(client.processing())[0]
        (pid,) = client.run(os.getpid, workers=[victim]).values()
        os.kill(pid, signal.SIGKILL)
        th.join(timeout=300)
        assert not th.is_alive()
    failed = [n for n, v in result.items() if v != "ok"]
    assert len(failed) == 1 and "KilledWorker" in result[failed[0]], result
    assert not (tmp_path / "scenes" / failed[0]).exists()
    (done,) = set(result) - set(failed)
    assert stored(tmp_path, done)["worker"] != victim
    st = compare.run_all(scenes, tmp_path, fields=False, log=lambda m: None)
    assert st == {failed[0]: "ok", done: "skipped"}


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:coarse contact mesh")
def test_quick_compare_on_two_dask_worker_processes_equals_jobs_2(tmp_path):
    """A quick compare subset on LocalCluster(n_workers=2, processes=True) gives the results
    of --jobs 2, and results.json names the executor and the worker of each scene."""
    from distributed import LocalCluster

    names = "sphere-md,geom-flat"
    argv = ["--quick", "--scenes", names, "--no-hard-cases", "--no-fields"]
    assert compare.main(argv + ["--jobs", "2", "--out", str(tmp_path / "jobs")]) == 0
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        assert compare.main(argv + ["--scheduler", cluster.scheduler_address, "--out", str(tmp_path / "dask")]) == 0
        workers = set(cluster.workers[i].worker_address for i in cluster.workers)
    a = json.loads((tmp_path / "jobs" / "results.json").read_text())
    b = json.loads((tmp_path / "dask" / "results.json").read_text())
    assert a["executor"] == "processes:2" and b["executor"].startswith("dask:")
    for n in names.split(","):
        assert b["scenes"][n]["worker"] in workers
        assert_same(physics(a["scenes"][n]), physics(b["scenes"][n]))


# ---------------------------------------------------------------- the budget's surfaces on a Dask worker


def _where(task):
    """A task's number and who ran it (top level: a task of ``validation.spectra.cached_map``)."""
    return {"x": task["x"], "worker": worker_id()}


def test_the_budgets_surfaces_run_on_a_dask_worker_and_are_cached_here(tmp_path, inproc_cluster):
    """python -m validation.budget --scheduler: the roughness readings' surfaces and their apparatus runs
    (``validation.spectra.cached_map``) go to the cluster's workers, come back in their order and are
    cached here (a second budget, in this process, runs none); a worker of other sources is refused."""
    from validation import spectra as SP

    todo = [{"x": k} for k in range(5)]
    with executor_for(1, inproc_cluster.scheduler_address) as (ex, _):
        got = SP.cached_map(todo, _where, tmp_path, "v1", executor=ex)
    assert [g["x"] for g in got] == list(range(5))
    assert {g["worker"] for g in got} == {inproc_cluster.workers[0].address}
    assert SP.cached_map(todo, _where, tmp_path, "v1") == got  # read back: no task runs in this process
    with pytest.raises(RuntimeError, match="other sources"):
        SP.remote_call(_where, "not this version", {"x": 0})


def _fails_at_3(task):
    if task["x"] == 3:
        raise ValueError("no convergence")
    return {"x": task["x"]}


def test_a_failed_surface_loses_none_of_the_finished_ones(tmp_path):
    """``validation.spectra.cached_map`` stores each result as it completes: a task that fails stops the map
    but the results before it are cached (a rerun computes only the rest)."""
    from validation import spectra as SP

    todo = [{"x": k} for k in range(5)]
    with pytest.raises(ValueError):
        SP.cached_map(todo, _fails_at_3, tmp_path, "v1")
    assert len(list(tmp_path.glob("*.json"))) == 3


class _Recording(cf.ThreadPoolExecutor):
    """A thread pool that counts what is submitted to it."""

    submitted = 0

    def submit(self, *a, **k):
        type(self).submitted += 1
        return super().submit(*a, **k)


def test_the_budget_hands_its_executor_to_every_surface_run(monkeypatch, tmp_path):
    """python -m validation.budget --scheduler/--jobs: the executor reaches the readings' surfaces of the
    paper's and of a rig's budget, and the measured loops' checks (those on the executor equal the serial
    ones)."""
    from pathlib import Path

    from validation import budget as B
    from validation import budget_readings as BR
    from validation import rig_budget as RB
    from validation import spectra as SP
    from validation.budget_cells import paper_inputs
    from validation.rig import load_rig

    seen = []

    class Stop(Exception):
        pass

    def curves(contacts, cache_dir, *, jobs=1, log=None, executor=None):
        seen.append(executor)
        raise Stop

    monkeypatch.setattr(SP, "curves", curves)
    ex = object()
    rig = RB.inputs(load_rig(Path(__file__).resolve().parents[1] / "docs" / "examples" / "my_rig.toml"))
    for inp in (paper_inputs(), rig):
        with pytest.raises(Stop):
            B.budget(tmp_path, inp=inp, executor=ex)
    assert seen == [ex, ex]
    # the loops' checks on an executor: the same checks as in this process
    from dataclasses import asdict

    import numpy as np

    from mdr import reference as ref

    F = 0.5 * np.geomspace(1e-2, 1.5, 24)
    d = [float(ref.hertz(f, SP.SPHERE.R, SP.SPHERE.mat().E_star)["d"]) for f in F]
    members = [{"reading": 0, "contact": asdict(SP.SPHERE), "seed": s, "n": n, "rms_window": 1e-6,
                "form_curvature": 0.0, "curve": {"d": d, "F": F.tolist()}} for s in (0, 1) for n in SP.SPHERE.grids]
    R = BR.Readings(members)
    with _Recording(2) as pool:
        on = BR.consistency(R, executor=pool)
    assert _Recording.submitted >= 2 and on == BR.consistency(R)
