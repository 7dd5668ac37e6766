"""fem.solvers.blas_threads: the BLAS pools limited inside a block and restored after it, found once.

The 3D contact law enters the block at every step; finding the pools (reading /proc/self/maps)
each time took a third of a 3D step (``fem.solvers._blas_pools``)."""
import sys

import numpy as np
import pytest

from fem import solvers
from fem.solvers import blas_threads


def _sizes():
    return [get() for _, get in solvers._openblas_handles()]


@pytest.fixture
def without_threadpoolctl(monkeypatch):
    """The ctypes path (threadpoolctl is optional): its import fails, the pools are found afresh."""
    monkeypatch.setitem(sys.modules, "threadpoolctl", None)
    monkeypatch.setattr(solvers, "_POOLS", {})


def test_the_pools_are_limited_inside_the_block_and_restored(without_threadpoolctl):
    np.ones(2) @ np.ones(2)  # numpy's OpenBLAS is loaded
    before = _sizes()
    if not before:
        pytest.skip("no OpenBLAS loaded in this process (another BLAS: threadpoolctl's path)")
    with blas_threads(1):
        inside = _sizes()
        with blas_threads(1):  # nested, same size: nothing changes
            assert _sizes() == inside
    assert inside == [1] * len(before)
    assert _sizes() == before


def test_the_pools_are_found_once_per_set_of_modules(without_threadpoolctl, monkeypatch):
    calls = []
    found = solvers._openblas_handles

    def counting():
        calls.append(1)
        return found()

    monkeypatch.setattr(solvers, "_openblas_handles", counting)
    for _ in range(5):
        with blas_threads(1):
            pass
    assert len(calls) == 1
    monkeypatch.setitem(sys.modules, "a_module_that_may_load_another_blas", sys)  # a new import: found again
    with blas_threads(1):
        pass
    assert len(calls) == 2
