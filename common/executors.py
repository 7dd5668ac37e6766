"""Where the independent tasks of a sweep run (one home for ``--jobs`` and ``--scheduler``).

- ``--jobs 1`` (default): in this process, one task after the other;
- ``--jobs N``: ``N`` spawned local processes (``concurrent.futures.ProcessPoolExecutor``);
- ``--scheduler ADDRESS``: the workers of a running Dask distributed scheduler
  (``dask.distributed.Client(ADDRESS).get_executor()``, a ``concurrent.futures.Executor``),
  on this machine or on several. Dask is optional (``pip install 'fretting-mdr-fem[dist]'``)
  and imported only when a scheduler is asked for, never when this module is imported.

The parallelism of a cluster is set by its workers (``dask worker --nworkers``), so
``--scheduler`` with ``--jobs N > 1`` is refused. Tasks must be picklable top-level
functions of the project's packages, and every worker must run the same version of the
project (the callers check the sources hash on the worker).
"""
from __future__ import annotations

import contextlib
import os
import socket
import sys

from .errors import InputError, positive_int

#: how to get the optional distributed engine
DASK_INSTALL = "pip install 'fretting-mdr-fem[dist]' (or: pip install 'dask[distributed]')"
#: seconds to wait for the scheduler before giving up
CONNECT_TIMEOUT_S = 20.0


def check_choice(jobs: int = 1, scheduler: str | None = None) -> int:
    """Validated ``jobs``; InputError if ``scheduler`` is given with ``jobs > 1`` or is blank."""
    jobs = positive_int("jobs", jobs)
    if scheduler is not None:
        if not str(scheduler).strip():
            raise InputError("scheduler must be the address of a Dask scheduler, e.g. tcp://10.0.0.5:8786; got ''")
        if jobs > 1:
            raise InputError(f"--scheduler and --jobs {jobs} exclude each other: with --scheduler the Dask workers "
                             "set the parallelism (dask worker --nworkers N); drop --jobs")
    return jobs


def dask_client(address: str, timeout: float | None = None):
    """A ``dask.distributed.Client`` connected to the scheduler at ``address``.

    InputError if dask.distributed is not installed (with the command that installs it) or
    if the scheduler cannot be reached within ``timeout`` seconds."""
    try:
        from distributed import Client
    except ImportError as exc:
        raise InputError(f"--scheduler needs dask.distributed, which is not installed ({exc}); "
                         f"install it with {DASK_INSTALL}") from exc
    try:
        return Client(address, timeout=CONNECT_TIMEOUT_S if timeout is None else timeout)
    except (OSError, TimeoutError, ValueError) as exc:
        raise InputError(f"scheduler {address!r} cannot be reached ({type(exc).__name__}: {exc}); start one with "
                         "`dask scheduler` and workers with `dask worker ADDRESS`") from exc


@contextlib.contextmanager
def executor_for(jobs: int = 1, scheduler: str | None = None):
    """Context manager yielding ``(executor, label)``: ``executor`` is None for ``jobs == 1``
    (run in this process), a ``ProcessPoolExecutor`` of ``jobs`` spawned processes, or the
    executor of a Dask client of ``scheduler``; ``label`` says which ("serial",
    "processes:N", "dask:ADDRESS"), for the records of a run. Closed on exit."""
    jobs = check_choice(jobs, scheduler)
    if scheduler is not None:
        client = dask_client(scheduler)
        try:
            # pure=False: equal arguments are distinct tasks (no deduplication by Dask)
            ex = client.get_executor(pure=False)
            yield ex, f"dask:{client.scheduler.address}"
        finally:
            client.close()
    elif jobs == 1:
        yield None, "serial"
    else:
        import concurrent.futures as futures
        import multiprocessing

        # spawn, not fork: a forked child of a process whose BLAS, gmsh or VTK threads hold a
        # lock deadlocks; spawned workers import afresh (about 1 s each)
        ex = futures.ProcessPoolExecutor(max_workers=jobs, mp_context=multiprocessing.get_context("spawn"))
        try:
            yield ex, f"processes:{jobs}"
        finally:
            ex.shutdown(cancel_futures=True)


def worker_id() -> str:
    """Who runs this task: the Dask worker's address inside a Dask worker, else
    ``hostname:pid``."""
    if "distributed" in sys.modules:  # never imports dask itself
        try:
            return sys.modules["distributed"].get_worker().address
        except (ValueError, AttributeError):
            pass
    return f"{socket.gethostname()}:{os.getpid()}"
