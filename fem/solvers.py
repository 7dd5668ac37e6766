"""Sparse factorisation of SPD stiffness matrices with fast backends and a fallback.

Backends, in order of preference (measured on 2D P2 elasticity, docs/design.md sec. 4):

1. ``cholmod``: CHOLMOD supernodal Cholesky through scikit-sparse
   (``pip install scikit-sparse``; needs the SuiteSparse headers, Debian
   ``libsuitesparse-dev``; builds at 0.4.16 against Debian 12's SuiteSparse).
2. ``pardiso``: MKL PARDISO through ``pypardiso`` (pulls MKL, about 0.7 GB).
3. ``superlu``: ``scipy.sparse.linalg.splu``, always available (about 10x
   slower on large systems and many right-hand sides).

The backend is chosen by the argument ``backend`` or the environment variable
``FRETTING_SPARSE_SOLVER`` (``auto`` by default: the first one importable).
Assumption: the matrix is symmetric positive definite (Dirichlet conditions
already removed); CHOLMOD raises if it is not.

Threads: MKL (PARDISO) and numpy's OpenBLAS each start a thread pool; on a
2-core machine they fight and small dense solves become 40x slower (docs/design.md sec. 4).
:func:`blas_threads` limits the BLAS pools for a block of small dense work when
``threadpoolctl`` is installed (optional) or, without it, through the OpenBLAS ctypes API.
"""
from __future__ import annotations

import contextlib
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from common.errors import InputError

BACKENDS = ("cholmod", "pardiso", "superlu")


def available_backends() -> list[str]:
    out = []
    try:
        import sksparse.cholmod  # noqa: F401

        out.append("cholmod")
    except Exception:
        pass
    try:
        import pypardiso  # noqa: F401

        out.append("pardiso")
    except Exception:
        pass
    out.append("superlu")
    return out


def _openblas_handles():
    """(set, get) ctypes functions of every OpenBLAS loaded in this process (numpy's and
    scipy's wheels each bundle their own)."""
    import ctypes

    out = []
    try:
        with open("/proc/self/maps") as fh:
            paths = {line.split()[-1] for line in fh if "openblas" in line.lower() and ".so" in line}
    except OSError:  # not Linux
        return out
    for path in sorted(paths):
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for pre, suf in (("", ""), ("scipy_", ""), ("scipy_", "64_"), ("", "64_")):
            try:
                setter = getattr(lib, f"{pre}openblas_set_num_threads{suf}")
                getter = getattr(lib, f"{pre}openblas_get_num_threads{suf}")
            except AttributeError:
                continue
            setter.argtypes, getter.restype = [ctypes.c_int], ctypes.c_int
            out.append((setter, getter))
            break
    return out


@contextlib.contextmanager
def blas_threads(n: int = 1):
    """Limit the BLAS thread pools to ``n`` threads inside the block.

    Uses ``threadpoolctl`` when installed, else sets every loaded OpenBLAS
    directly through ctypes. Measured here: with numpy's and scipy's OpenBLAS
    pools both at 2 threads, the dense active-set solves of a 200-pair
    interface took 2.4 s instead of 8 ms (the idle pool spins while the other
    works).

    Nested blocks with the same ``n`` cost nothing; an outer block sets the pools' sizes (the
    pools themselves are found once per set of imported modules, ``_blas_pools``).
    """
    if _BLAS_LIMIT and _BLAS_LIMIT[-1] == n:
        yield
        return
    _BLAS_LIMIT.append(n)
    try:
        with _blas_threads(n):
            yield
    finally:
        _BLAS_LIMIT.pop()


_BLAS_LIMIT: list = []


def _blas_pools():
    """The BLAS thread pools loaded in this process: a ``threadpoolctl.ThreadpoolController`` or, without
    it, the OpenBLAS ctypes handles. Found once per set of imported modules (a new import may load
    another BLAS): finding them reads /proc/self/maps, which took a third of a 3D contact step when
    every step did it."""
    key = len(sys.modules)
    if _POOLS.get("key") != key:
        try:
            from threadpoolctl import ThreadpoolController
        except ImportError:
            pools = _openblas_handles()
        else:
            pools = ThreadpoolController()
        _POOLS.update(key=key, pools=pools)
    return _POOLS["pools"]


_POOLS: dict = {}


@contextlib.contextmanager
def _blas_threads(n):
    pools = _blas_pools()
    if not isinstance(pools, list):  # threadpoolctl
        with pools.limit(limits=n, user_api="blas"):
            yield
        return
    old = [get() for _, get in pools]
    for set_, _ in pools:
        set_(n)
    try:
        yield
    finally:
        for (set_, _), k in zip(pools, old):
            set_(k)


class Factor:
    """A factorised SPD matrix: ``solve(b)`` for a vector or an (n, k) block of right-hand sides."""

    backend = "?"

    def __init__(self, A):
        self.n = A.shape[0]

    def solve(self, b):
        raise NotImplementedError

    def __call__(self, b):
        return self.solve(b)


class _Cholmod(Factor):
    backend = "cholmod"

    def __init__(self, A):
        super().__init__(A)
        from sksparse.cholmod import cholesky

        self._f = cholesky(sp.csc_matrix(A))

    def solve(self, b):
        b = np.asarray(b, dtype=float)
        return self._f(b)


class _Pardiso(Factor):  # pragma: no cover - optional backend
    backend = "pardiso"

    def __init__(self, A):
        super().__init__(A)
        import pypardiso

        self._s = pypardiso.PyPardisoSolver(mtype=2)  # real SPD
        self._A = sp.triu(sp.csr_matrix(A), format="csr")
        self._s.factorize(self._A)

    def solve(self, b):
        b = np.asarray(b, dtype=float)
        return self._s.solve(self._A, b)


class _SuperLU(Factor):
    backend = "superlu"

    def __init__(self, A):
        super().__init__(A)
        # MMD on A^T + A suits symmetric matrices better than COLAMD
        self._lu = spla.splu(sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A",
                             options={"SymmetricMode": True})

    def solve(self, b):
        b = np.asarray(b, dtype=float)
        return self._lu.solve(b)


_CLASSES = {"cholmod": _Cholmod, "pardiso": _Pardiso, "superlu": _SuperLU}


def factorize(A, backend: str | None = None) -> Factor:
    """Factorise the SPD sparse matrix ``A`` with the chosen (or best available) backend.

    ``backend``: ``auto`` (default, or ``$FRETTING_SPARSE_SOLVER``), ``cholmod``,
    ``pardiso`` or ``superlu``. An unavailable explicit backend falls back to
    ``auto`` with no error only when chosen through the environment; as an
    argument it raises :class:`InputError`.
    """
    return _CLASSES[resolve_backend(backend)](A)


def resolve_backend(backend: str | None = None) -> str:
    """The backend ``factorize`` uses for ``backend`` (see there): a name of ``BACKENDS``."""
    explicit = backend is not None
    name = backend or os.environ.get("FRETTING_SPARSE_SOLVER", "auto")
    avail = available_backends()
    if name == "auto":
        name = avail[0]
    if name not in BACKENDS:
        raise InputError(f"solver backend must be one of auto, {', '.join(BACKENDS)}; got {name!r}")
    if name not in avail:
        if explicit:
            raise InputError(f"solver backend {name!r} is not installed; available: {', '.join(avail)}")
        name = avail[0]
    return name
