"""``python -m validation.compare``: run the scenes through MDR and FE and write the report.

Usage::

    python -m validation.compare --quick            # representative subset, < 2 min
    python -m validation.compare                    # full catalogue
    python -m validation.compare --scenes sphere-md,geom-b20um --jobs 2 --out results
    python -m validation.compare --list             # the catalogue
    python -m validation.compare --scheduler tcp://HOST:8786   # on a Dask cluster

Where the scenes run: in this process (default), ``--jobs N`` local processes, or
``--scheduler ADDRESS`` the workers of a running Dask scheduler (``common.executors``);
results.json records the ``executor`` and each scene the ``worker`` that computed it.

Each scene is written to ``OUT/scenes/NAME/`` atomically when it finishes
(result.json, fields.vtu, PNGs); a rerun skips scenes whose inputs and code
are unchanged (``--force`` reruns them). ``OUT/report.md`` and
``OUT/results.json`` are rebuilt from the stored scenes at the end. Hidden
temporary scene directories left by a killed run are removed at the start
(:func:`remove_stale_tmp`); progress is printed (on stderr with ``--json -``) and
never stops for more than ``HEARTBEAT_S`` seconds (:class:`Heartbeat`).
Exit codes: 0 all scenes ran, 1 a scene failed (the others are reported),
2 bad input.
"""
from __future__ import annotations

import argparse
import concurrent.futures as futures
import glob
import multiprocessing
import os
import re
import shutil
import sys
import threading
import time
import traceback
from pathlib import Path

from common.cli import OneLineParser, run_command
from common.errors import ConvergenceError, InputError

from . import report
from common.executors import check_choice, executor_for, worker_id

from .runner import members_here, scene_tasks, split_stored
from .members import write_member
from .store import install_scene_files, load_scene, scene_files, write_scene
from .catalogue import CATALOGUE, select
from .sources import code_version, refuse_other_sources


#: after this many seconds without a message ``main`` says what it is still doing (mesh
#: generation, set-up, figures, a hard case, a worker's scene); with the 1 s poll it is never
#: silent for more than about 10 s
HEARTBEAT_S = 8.0
#: a hidden scene directory ``.NAME.XXXX`` older than this is the leftover of a killed run
STALE_TMP_S = 600.0


class Heartbeat:
    """A ``log`` callable that also speaks when nothing else does: a daemon thread repeats the
    last message with the time since it whenever ``interval`` seconds pass without one."""

    def __init__(self, log, interval=None):
        self._log, self.interval = log, float(HEARTBEAT_S if interval is None else interval)
        self._lock = threading.Lock()
        self._last, self._msg, self._t0 = time.monotonic(), "", time.monotonic()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._beat, daemon=True, name="compare-heartbeat")

    def __call__(self, msg):
        with self._lock:
            self._log(msg)
            self._last, self._msg = time.monotonic(), str(msg).strip()

    def _beat(self):
        while not self._stop.wait(min(1.0, self.interval / 4)):
            with self._lock:
                now = time.monotonic()
                if now - self._last >= self.interval:
                    self._log(f"  ... still working ({now - self._t0:.0f} s since the start; last: {self._msg[:90]})")
                    self._last = now

    def __enter__(self):
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()


def remove_stale_tmp(out, names, *, older_than=STALE_TMP_S, log=None) -> list:
    """Remove the hidden temporary scene directories (``scenes/.NAME.XXXX``, made by
    ``store.write_scene``, and ``scenes/.NAME.old.PID``) a killed run left behind: those of
    the given scene names whose mtime is older than ``older_than`` seconds, or whose embedded
    pid (``.old.PID``) is not a live process. A live run's directory is younger (it is
    touched whenever a file is written into it) and is kept. Returns the removed paths."""
    root = Path(out) / "scenes"
    if not root.is_dir():
        return []
    now, removed = time.time(), []
    for name in names:
        for d in root.glob(f".{glob.escape(name)}.*"):
            tail = d.name[len(name) + 2:]
            if not d.is_dir() or not re.fullmatch(r"[A-Za-z0-9_]+|old\.\d+", tail):
                continue
            try:
                age = now - d.stat().st_mtime
            except OSError:
                continue
            dead = tail.startswith("old.") and not _pid_alive(int(tail[4:]))
            if age > older_than or dead:
                shutil.rmtree(d, ignore_errors=True)
                if not d.exists():
                    removed.append(d)
                    if log is not None:
                        log(f"[clean] removed {d} (left by an interrupted run, {age / 60:.0f} min old)")
    return removed


def _pid_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # exists, owned by someone else
        return True
    return True


def _work(scene, out, fingerprint, fields, verbose, stored=True, force=False):
    """One scene, stored under ``out`` with the worker that ran it. ``verbose``: False
    (quiet), True (stdout), "stderr", or a callable taking one line (in-process); ``stored``: its
    tasks stored by content under ``out`` read back (not with ``force``) and its new ones stored
    (``runner.members_here``; not on a worker's temporary folder)."""
    from fem.solvers import blas_threads

    if callable(verbose):
        log = lambda msg: verbose(f"[{scene.name}] {msg.strip()}")  # noqa: E731
    else:
        stream = sys.stderr if verbose == "stderr" else sys.stdout
        log = (lambda msg: print(f"[{scene.name}] {msg.strip()}", file=stream, flush=True)) if verbose else None
    with blas_threads(1):
        members = members_here(scene, out, code_version(), log or (lambda msg: None), force) if stored else None
        res = write_scene(scene, out, fingerprint, fields=fields, log=log, meta={"worker": worker_id()},
                          members=members)
    return _summary(res)


def _remote(scene, fingerprint, version, fields):
    """One scene on a worker of an executor (top level: picklable for any executor): run into
    a temporary directory local to the worker and return ``(summary, files)``, the scene
    directory as {relative path: bytes}; the caller stores it (``store.install_scene_files``),
    so the output directory need not be shared with the workers. Refuses to run if the
    worker's sources differ from the caller's (``version``, ``sources.code_version``): its
    result would be stored under the wrong fingerprint."""
    import tempfile

    refuse_other_sources(code_version(), version)
    with tempfile.TemporaryDirectory(prefix="fretting-scene-") as tmp:
        msg = _work(scene, tmp, fingerprint, fields, False, stored=False)
        return msg, scene_files(tmp, scene.name)


def _summary(res) -> str:
    v = res.get("verdicts")
    if not v:
        return f"{res.get('runtime_s', 0):.1f} s"
    from .metrics import scene_grade

    failed = [q for q, x in v.items() if x["holds"] is False]
    return (f"{res['runtime_s']:.1f} s, MDR: {scene_grade(v)}"
            + (f" ({', '.join(failed)} beyond error bars + tolerance)" if failed else ""))


def _tasks_or_none(scene):
    """``scene_tasks``, or None where they cannot be listed (a measured map gone since the scene was
    read: the scene's own run then fails and says why)."""
    try:
        return scene_tasks(scene)
    except (InputError, OSError, ValueError):
        return None


def expected_cost(scene, out) -> float:
    """A scene's expected run time (s), to schedule the longest first: its last stored run's (of a scene
    of tasks: their CPU time), else a rough count of its runs (3D levels cost about ten axisymmetric ones; each variant runs the ladder
    or a pair of runs again)."""
    old = load_scene(out, scene.name)
    if old is not None and isinstance(old.get("members_cpu_s"), (int, float)):
        return float(old["members_cpu_s"])
    if old is not None and isinstance(old.get("runtime_s"), (int, float)):
        return float(old["runtime_s"])
    tasks = _tasks_or_none(scene)
    if tasks:  # a rough member: about 12 s at 128^2 pixels on one core, growing with the pixel count
        return sum(12.0 * (t.get("n", 128) / 128.0) ** 2 for t in tasks)
    per_level = 10.0 if scene.fe_model == "3d" else 1.0
    return per_level * len(scene.fe_levels) * max(1, len(scene.variants)) * scene.cycles * scene.steps / 600.0


def run_all(scenes, out, *, executor: futures.Executor | None = None, jobs: int = 1, force: bool = False,
            fields: bool = True, log=print, detail=True) -> dict:
    """Run the scenes (skipping unchanged stored ones); returns {name: "ok"|"skipped"|error text}.

    ``executor``: any ``concurrent.futures.Executor`` (e.g. the executor of a Dask client,
    ``common.executors.executor_for``); default: in-process for ``jobs == 1``, else a
    ``ProcessPoolExecutor(jobs)`` of spawned processes. On an executor each scene runs in a
    directory local to its worker and comes back as files, stored here atomically. A scene
    whose task fails (an exception, a lost worker) is reported failed and the others go on;
    it has no stored result, so a rerun computes it (and skips the completed ones).
    """
    out = Path(out)
    remove_stale_tmp(out, [s.name for s in scenes], log=log)
    version = code_version()
    status, todo = {}, []
    for s in scenes:
        fp = s.fingerprint(version)
        old = load_scene(out, s.name)
        if not force and old is not None and old.get("fingerprint") == fp:
            status[s.name] = "skipped"
            log(f"[skip] {s.name}: unchanged since the last run (--force reruns)")
        else:
            todo.append((s, fp))
    # longest first: a long scene started last would run on alone while the other workers idle (the 3D
    # scenes take several times an axisymmetric one); the report keeps the catalogue's order
    todo.sort(key=lambda sf: -expected_cost(sf[0], out))
    n = len(todo)
    t0 = time.perf_counter()
    own = None
    if executor is None and jobs > 1 and (n > 1 or any(len(_tasks_or_none(s) or ()) > 1 for s, _ in todo)):
        # spawn, not fork: a forked child of a process whose BLAS, gmsh or VTK threads hold a
        # lock deadlocks (seen under pytest); spawned workers import afresh (~1 s each)
        executor = own = futures.ProcessPoolExecutor(max_workers=jobs, mp_context=multiprocessing.get_context("spawn"))
    try:
        if executor is None:
            for i, (s, fp) in enumerate(todo, 1):
                log(f"[{i}/{n}] {s.name}: {s.title}")
                try:
                    status[s.name] = "ok"
                    log(f"[{i}/{n}] {s.name} done: {_work(s, out, fp, fields, log if detail else False, force=force)}")
                except (InputError, ConvergenceError, RuntimeError, ValueError, ArithmeticError) as e:
                    status[s.name] = f"{type(e).__name__}: {e}"
                    log(f"[{i}/{n}] {s.name} FAILED: {status[s.name]}")
        else:
            _run_on(executor, todo, out, version, fields, status, log, t0, jobs if own else "the given", force)
    finally:
        if own is not None:
            own.shutdown(cancel_futures=True)
    return status


def _member_remote(scene, task, version):
    """One task of a scene of independent tasks (``runner.scene_tasks``) on a worker of an executor
    (top level: picklable); refuses other sources than the caller's, as ``_remote``."""
    refuse_other_sources(code_version(), version)
    from fem.solvers import blas_threads

    from .runner import run_member

    with blas_threads(1):
        return run_member(scene, task)


def _run_on(executor, todo, out, version, fields, status, log, t0, workers, force=False):
    """The scenes ``todo`` on ``executor``: a scene of independent tasks (``runner.scene_tasks``) as one
    job per task, reduced and stored here when its last task is back (a failed task fails its scene);
    every other scene as one job. Jobs go out longest first (``expected_cost``, a scene's split over its
    tasks by their pixel count squared)."""
    jobs, pending, got, failed, ready = [], {}, {}, {}, []
    for s, fp in todo:
        try:
            tasks = scene_tasks(s)
            cost = expected_cost(s, out)
        except (InputError, OSError, ValueError) as e:  # e.g. a measured map gone since the scene was read
            status[s.name] = f"{type(e).__name__}: {e}"
            log(f"{s.name} FAILED: {status[s.name]}")
            continue
        if not tasks:
            jobs.append((cost, s, fp, None, None))
            continue
        total = sum(float(t.get("n", 1)) ** 2 for t in tasks)
        found, todo_tasks = split_stored(s, tasks, out, version, force)
        pending[s.name], got[s.name] = len(todo_tasks), found
        if found and todo_tasks:
            log(f"  {s.name}: {len(found)} of {len(tasks)} task(s) stored by content: read back")
        if not todo_tasks:
            ready.append((s, fp))
        jobs += [(cost * float(t.get("n", 1)) ** 2 / total, s, fp, t, key) for t, key in todo_tasks]
    jobs.sort(key=lambda j: -j[0])
    futs = {(executor.submit(_remote, s, fp, version, fields) if t is None
             else executor.submit(_member_remote, s, t, version)): (s, fp, t, key) for _, s, fp, t, key in jobs}
    n = len(todo)
    log(f"running {n} scene(s) as {len(futs)} job(s) on {workers} executor workers")
    done = 0

    def reduced(s, fp) -> str:
        """A scene whose tasks are all in (``got``), reduced and stored here: its summary."""
        return _summary(write_scene(s, out, fp, fields=fields, meta={"worker": worker_id()}, members=got[s.name]))

    for s, fp in ready:  # every task stored by content
        done += 1
        try:
            msg = reduced(s, fp)
            status[s.name] = "ok"
            log(f"[{done}/{n}] {s.name} done: its {len(got[s.name])} task(s) stored by content: {msg}")
        except Exception as e:  # a failed scene must not stop the others
            status[s.name] = f"{type(e).__name__}: {e}"
            log(f"[{done}/{n}] {s.name} FAILED: {status[s.name]}")
    for f in futures.as_completed(futs):
        s, fp, t, key = futs[f]
        try:
            if t is None:
                msg, files = f.result()
                install_scene_files(out, s.name, files)
            else:
                got[s.name].append(f.result())
                if key is not None:
                    write_member(out, key, got[s.name][-1])
                pending[s.name] -= 1
                log(f"  {s.name}: task {len(got[s.name])} of {len(got[s.name]) + pending[s.name]} done "
                    f"({time.perf_counter() - t0:.0f} s elapsed)")
                if pending[s.name] or s.name in failed:
                    continue
                msg = reduced(s, fp)
            done += 1
            status[s.name] = "ok"
            log(f"[{done}/{n}] {s.name} done: {msg} ({time.perf_counter() - t0:.0f} s elapsed)")
        except Exception as e:  # a failed scene must not stop the others
            if s.name in failed:
                continue
            done += 1
            failed[s.name] = True
            status[s.name] = f"{type(e).__name__}: {e}"
            log(f"[{done}/{n}] {s.name} FAILED: {status[s.name]}")
            traceback.print_exception(e, file=sys.stderr)


def build_parser() -> argparse.ArgumentParser:
    p = OneLineParser(
        prog="python -m validation.compare",
        description="Run the scene catalogue through the MDR and FE contact models and write a report "
                    "(report.md, results.json, figures, VTU) saying where the half-space model holds.")
    p.add_argument("--quick", action="store_true",
                   help="representative subset on coarser ladders (about 30 s on 2 cores once the meshes are cached, about a minute on a first run)")
    p.add_argument("--scenes", metavar="NAME,...", help="comma-separated scene names (see --list)")
    p.add_argument("--scene-file", metavar="PATH",
                   help="run your own scenes from a TOML file of [[scene]] tables instead of the catalogue "
                        "(fields of validation.scenes.Scene, SI units; example: docs/examples/scenes.toml)")
    p.add_argument("--jobs", type=int, default=1, metavar="N", help="scenes in parallel processes (default 1)")
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help="run the scenes on the workers of a running Dask scheduler (e.g. tcp://host:8786; "
                        "needs the dist extra; excludes --jobs)")
    p.add_argument("--out", default="results", metavar="DIR",
                   help="output directory, created with its parents if missing (default ./results)")
    p.add_argument("--json", metavar="PATH", help="also write results.json to PATH ('-' = stdout)")
    p.add_argument("--force", action="store_true",
                   help="rerun scenes and hard cases even if their stored results are current")
    p.add_argument("--no-fields", action="store_true", help="skip the pyvista field plots")
    p.add_argument("--no-hard-cases", action="store_true",
                   help="do not run the hard cases (the report keeps the last stored table, marked as not rerun)")
    p.add_argument("--hard-cases", action="store_true",
                   help="with --scene-file: also run the hard cases (the numerical stability checks of the "
                        "models, none about your scenes; without --scene-file they always run)")
    p.add_argument("--witness", action="store_true",
                   help="also run an independent FE code, CalculiX, on the same finite bodies (five block/cap "
                        "sizes, normal contact; about 6 minutes; needs apt-get install calculix-ccx) and add its "
                        "agreement and run time beside the project's to the report")
    p.add_argument("--list", action="store_true", help="list the scenes and exit")
    p.set_defaults(func=compare)
    return p


class _Background:
    """``fun()`` in a daemon thread: ``result()`` waits for it and returns its value or raises its error."""

    def __init__(self, fun):
        import threading

        self._box = {}
        self._thread = threading.Thread(target=self._run, args=(fun,), name="background", daemon=True)
        self._thread.start()

    def _run(self, fun):
        try:
            self._box["value"] = fun()
        except BaseException as exc:  # noqa: BLE001 - handed to the caller of result()
            self._box["error"] = exc

    def result(self):
        self._thread.join()
        if "error" in self._box:
            raise self._box["error"]
        return self._box["value"]


def main(argv=None) -> int:
    """The command line: exit 0, 1 if a scene failed, 2 on bad input (``common.cli.run_command``)."""
    return run_command(build_parser(), argv, write_result=False)


def compare(args) -> int:
    """Run the selected scenes and write the report (the body of :func:`main`); returns the exit code."""
    jobs = check_choice(args.jobs, args.scheduler)
    if args.hard_cases and args.no_hard_cases:
        raise InputError("give at most one of --hard-cases and --no-hard-cases")
    # a user's scene file runs its own scenes only, unless the hard cases are asked for
    run_hard = not args.no_hard_cases and (not args.scene_file or args.hard_cases)
    catalogue = None
    if args.scene_file:
        from .scene_file import load_scene_file

        catalogue = load_scene_file(args.scene_file)
    if args.list:
        shown = catalogue or CATALOGUE
        w = max(len(s.name) for s in shown.values()) + 2
        print(f"{'scene':{w}s}{'quick ':6s}{'group':12s} title")
        for s in shown.values():
            print(f"{s.name:{w}s}{'quick ' if s.quick else '      '}{s.group:12s} {s.title}")
        return 0
    scenes = select(args.scenes, quick=args.quick, catalogue=catalogue)
    if args.witness:
        from .calculix import MissingDependency, require_ccx

        try:
            require_ccx()
        except MissingDependency as exc:
            raise InputError(f"--witness: {exc}") from None
    out = Path(args.out)  # --out and --json were checked writable before the run (common.cli.run_command)
    t0 = time.perf_counter()
    # progress goes to stderr when the JSON goes to stdout
    stream = sys.stderr if args.json == "-" else sys.stdout

    def say(m):
        print(m, file=stream, flush=True)

    with Heartbeat(say) as say:
        say(f"validation.compare: {len(scenes)} scene(s){' (quick)' if args.quick else ''} -> {out}/")
        from .hard_cases import hard_cases_cached, stored_hard_cases

        def hard_cases():
            return hard_cases_cached(out, quick=args.quick, log=say, force=args.force)

        hard_running = None
        with executor_for(jobs, args.scheduler) as (executor, label):
            say(f"executor: {label}")
            if executor is not None and run_hard:
                # this process only waits on the workers: it runs the hard cases meanwhile (their own
                # results, independent of the scenes'), so no core idles at the scenes' tail; a daemon
                # thread, so that an interrupted run exits at once (their table is written atomically)
                hard_running = _Background(hard_cases)
            status = run_all(scenes, out, executor=executor, jobs=jobs, force=args.force,
                             fields=not args.no_fields, log=say)

        hard_note, hard = None, None  # a scene file's report holds its own scenes only (unless --hard-cases)
        if args.no_hard_cases:  # keep the last table, said to be not rerun
            hard, code = stored_hard_cases(out, args.quick)
            if hard is not None:
                hard_note = (f"Not rerun by this run (--no-hard-cases): the table of the last run that computed it "
                             f"(sources {code}{'' if code != code_version() else ', the same as this run'}).")
        elif run_hard:
            hard = hard_running.result() if hard_running is not None else hard_cases()
        witness = None
        if args.witness:
            from .calculix import witness_cached

            witness = witness_cached(out, log=say, force=args.force)
        say("writing the report and the summary figures")
        path = report.write_report(out, [s.name for s in scenes], status, hard_cases=hard, json_path=args.json,
                                   quick=args.quick, executor=label, hard_cases_note=hard_note, witness=witness)
    failed = [k for k, v in status.items() if v not in ("ok", "skipped")]
    say(f"report: {path} ({time.perf_counter() - t0:.0f} s)"
          + (f"; FAILED: {', '.join(failed)}" if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
