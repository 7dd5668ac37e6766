"""Static condensation of a linear elastic body to its contact interface.

Assumption: the body is linear elastic and contact acts only on the interface
DOFs, so the whole body is represented exactly by its flexibility (Green's
function) at those DOFs, C = [K^-1]_II (m x m, symmetric positive definite once
the Dirichlet conditions remove the rigid-body modes). It costs one sparse
factorisation and m solves (one per interface DOF), after which every contact
iteration works on dense m x m matrices. Rows of K^-1 at a few *probe* DOFs
(displacements wanted as outputs) come from the same solves for free.
"""
from __future__ import annotations

import numpy as np

from fem.solvers import blas_threads, factorize


class Condensation:
    """Flexibility of one body at ``interface_dofs`` with ``fixed_dofs`` clamped (zero).

    Attributes: ``C`` (m, m) flexibility (m/N), ``P`` (k, m) probe rows,
    ``factor`` (the sparse factorisation of K_ff, kept for field recovery),
    ``backend`` name. ``displacement(f_interface)`` returns the full DOF vector
    for forces on the interface DOFs. ``flexibility=False``: the factorisation alone
    (``C`` and ``P`` None), for field recovery where the flexibility is known already.
    """

    def __init__(self, K, fixed_dofs, interface_dofs, probe_dofs=(), backend=None, flexibility: bool = True):
        n = K.shape[0]
        self.n = n
        fixed = np.zeros(n, dtype=bool)
        fixed[np.asarray(fixed_dofs, dtype=int)] = True
        self.free = np.flatnonzero(~fixed)
        loc = -np.ones(n, dtype=np.int64)
        loc[self.free] = np.arange(self.free.size)
        self.interface_dofs = np.asarray(interface_dofs, dtype=int)
        self.probe_dofs = np.asarray(probe_dofs, dtype=int)
        self._iloc = loc[self.interface_dofs]
        if np.any(self._iloc < 0):
            raise ValueError("an interface DOF is fixed by a Dirichlet condition")
        ploc = loc[self.probe_dofs]
        Kff = K[self.free][:, self.free].tocsc()
        m = self.interface_dofs.size
        with blas_threads(1):  # SuperLU's triangular solves fight numpy's BLAS pool otherwise
            self.factor = factorize(Kff, backend)
            self.backend = self.factor.backend
            if not flexibility:
                self.C = self.P = None
                return
            rhs = np.zeros((self.free.size, m))
            rhs[self._iloc, np.arange(m)] = 1.0
            X = self.factor.solve(rhs)
        C = X[self._iloc]
        self.C = 0.5 * (C + C.T)
        # a fixed probe DOF reads zero
        self.P = np.where(ploc[:, None] >= 0, X[np.maximum(ploc, 0)], 0.0) if ploc.size else np.zeros((0, m))

    @property
    def m(self) -> int:
        return self.interface_dofs.size

    def displacement(self, f_interface, u_fixed=None):
        """Full DOF vector for interface forces (N); fixed DOFs zero (or ``u_fixed`` if the
        prescribed field is supplied as a full vector already satisfying K u = 0 off the
        fixed DOFs, e.g. a rigid translation)."""
        rhs = np.zeros(self.free.size)
        rhs[self._iloc] = np.asarray(f_interface, dtype=float)
        u = np.zeros(self.n)
        u[self.free] = self.factor.solve(rhs)
        if u_fixed is not None:
            u = u + u_fixed
        return u
