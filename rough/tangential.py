"""Frictional tangential contact with memory on the FFT grid: Coulomb friction cell by cell, stick and
slip, incremental, so that loops and their dissipation come out, for any pressure field (a smooth
indenter's, a rough one's: ``rough.normal.normal_contact``).

Assumptions (Mindlin's, as in MDR): the tangential traction runs along x only (q_y = 0) and does not
change the pressure (no normal-tangential coupling: identical materials, or Dundurs' beta = 0); linear
elasticity of two half-spaces; the periodic grid of ``rough.normal.Grid``. The relative tangential
displacement of the surfaces under the traction q is u = K q with the x-x surface compliance of both
bodies, in Fourier space (Cerruti's point solution transformed; Johnson 1985, *Contact Mechanics*, Sec. 3.2)

    K(k) = sum over the bodies of (1 - nu k_x^2 / k^2) / (G k),      K(0) = 0,

the mean (rigid) mode left to the tangential approach delta, a Lagrange multiplier of the force.

One step, under the tangential force Q (force control): the traction q minimises
(1/2) q.K q + q.s over |q| <= mu p cell by cell with sum(q) dA = Q, s the slip accumulated so far (a
convex problem: a projected conjugate gradient on the free cells, Polonsky & Keer 1999, Wear 231, 206,
with a two-sided box); its optimality conditions are Coulomb's law: in a sticking cell the slip does not
change (delta - K q = s), in a slipping cell |q| = mu p and q has the sign of its slip increment.
A cell out of contact (p = 0) carries no traction and takes its current relative position as its slip
(it enters contact sticking). The work of friction, sum of q times the slip increment, is the
dissipation (exact for the implicit step: the slipping traction is the one at the step's end).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from common.errors import InputError, nonnegative, positive

from .boxqp import solve_box
from .normal import Grid

#: the projected CG's tolerance (``rough.boxqp.solve_box``): the largest slip increment of a free cell,
#: relative to the range of the elastic displacement K q
TOLERANCE = 1e-10


#: the aliases k + 2 pi m / h summed per direction, |m| <= IMAGES (their terms fall as |m|^-3: the sum is
#: complete to ~1e-4 of the pixel-scale coefficients, far below the grid's own error)
IMAGES = 12


def compliance_xx(grid: Grid, materials, images: int = IMAGES) -> np.ndarray:
    """The influence of a pixel's uniform x traction on the x displacement of every pixel centre, both
    bodies, in discrete Fourier space (rfft2 layout, (n, n // 2 + 1), m / Pa): the cell-integrated
    Cerruti kernel of the periodic grid, sum over the aliases k_m = k + 2 pi m / h of
    K(k_m) sinc(k_m,x h / 2) sinc(k_m,y h / 2), K(k) = sum over the bodies of (1 - nu k_x^2 / k^2) / (G k)
    (the point kernel sampled alone converges non-monotonically: -1.8, -0.4, -0.8 % in the sphere's
    dissipation at a/8, a/16, a/32). The mean (k = 0, rigid) mode is 0."""
    h, n = grid.pixel, grid.n
    kx = 2.0 * np.pi * np.fft.fftfreq(n, d=h)
    ky = 2.0 * np.pi * np.fft.rfftfreq(n, d=h)
    KX0, KY0 = np.meshgrid(kx, ky, indexing="ij")
    mods = []
    for E, nu in ((materials.E1, materials.nu1), (materials.E2, materials.nu2)):
        mods.append((nu, E / (2.0 * (1.0 + nu))))
    out = np.zeros_like(KX0)
    shift = 2.0 * np.pi / h
    for mx in range(-images, images + 1):
        KX = KX0 + mx * shift
        sx = np.sinc(KX * h / (2.0 * np.pi))  # numpy's sinc(x) = sin(pi x) / (pi x)
        for my in range(-images, images + 1):
            KY = KY0 + my * shift
            k = np.hypot(KX, KY)
            zero = k == 0.0
            k = np.where(zero, 1.0, k)
            c2 = (KX / k) ** 2
            term = sum((1.0 - nu * c2) / (G * k) for nu, G in mods) * sx * np.sinc(KY * h / (2.0 * np.pi))
            out += np.where(zero, 0.0, term)
    out[0, 0] = 0.0
    return out


@dataclass
class TangentialState:
    """The memory of the contact: each cell's accumulated slip ``s`` (m), its traction ``q`` (Pa), the
    tangential approach ``delta`` (m, up to the periodic grid's rigid constant) and the friction work (J)."""

    s: np.ndarray
    q: np.ndarray
    delta: float = 0.0
    work: float = 0.0


class TangentialContact:
    """Tangential contact with memory on ``grid`` (``rough.normal.Grid``) for ``materials`` and friction
    ``mu``; ``step(state, p, Q)`` is one increment under the pressure field ``p`` (Pa, (n, n)) and the
    tangential force ``Q`` (N). Pure: the state passed in is not changed."""

    def __init__(self, grid: Grid, materials, mu, tol=TOLERANCE):
        if not isinstance(grid, Grid):
            raise InputError(f"grid must be a rough.normal.Grid, got {grid!r}")
        self.grid, self.materials = grid, materials
        self.mu = float(positive("mu", mu))
        self.tol = float(positive("tol", tol))
        self.K = compliance_xx(grid, materials)
        self.dA = grid.pixel ** 2

    def rest_state(self) -> TangentialState:
        n = self.grid.n
        return TangentialState(s=np.zeros((n, n)), q=np.zeros((n, n)))

    def displacement(self, q) -> np.ndarray:
        """K q: the relative tangential displacement of the surfaces (m) under the traction q (Pa),
        up to the rigid mean."""
        return np.fft.irfft2(self.K * np.fft.rfft2(q), s=q.shape)

    def step(self, state: TangentialState, p, Q) -> TangentialState:
        p = np.asarray(p, dtype=float)
        if p.shape != (self.grid.n,) * 2 or not np.all(np.isfinite(p)) or np.any(p < 0):
            raise InputError(f"p must be the grid's pressure field, ({self.grid.n}, {self.grid.n}), finite and >= 0")
        lim = self.mu * p
        Q = float(Q)
        cap = float(lim.sum()) * self.dA
        if abs(Q) >= cap * (1 - 1e-12):
            raise InputError(f"|Q| = {abs(Q):.4g} N must stay below the friction limit mu F_N = {cap:.4g} N "
                             "(force control has no equilibrium in gross sliding)")
        q = self._solve(state.s, lim, Q, np.clip(state.q, -lim, lim))
        g = self.displacement(q) + state.s
        stick = (lim > 0) & (np.abs(q) < lim * (1 - 1e-9))
        delta = float(np.mean(g[stick])) if stick.any() else float(np.median(g[lim > 0]))
        ds = delta - g  # 0 where sticking, the slip increment where slipping, the new position out of contact
        ds = np.where(stick, 0.0, ds)
        work = float(np.sum(q * np.where(lim > 0, ds, 0.0))) * self.dA
        return TangentialState(s=state.s + ds, q=q, delta=delta, work=state.work + work)

    def _solve(self, s, lim, Q, q):
        return solve_box(self.displacement, s, lim, Q, q, self.dA, self.tol, "tangential contact")


def run_force_cycles(contact: TangentialContact, p, fa, cycles=3, steps=40) -> dict:
    """Q(t) = fa sin(2 pi t) at the constant pressure field ``p``, from rest; the dissipation of every
    cycle (the friction work over it, J), the loop (delta, Q) of the last, and the stick area at the last
    cycle's peak (the cells whose traction is below the limit)."""
    nonnegative("fa", fa)
    st = contact.rest_state()
    t = np.arange(cycles * steps + 1) / steps
    Qs = fa * np.sin(2 * np.pi * t)
    works, deltas, stick_area = [0.0], [0.0], None
    lim = contact.mu * np.asarray(p, dtype=float)
    for k, Q in enumerate(Qs[1:], start=1):
        st = contact.step(st, p, Q)
        works.append(st.work)
        deltas.append(st.delta)
        if k == (cycles - 1) * steps + steps // 4:
            stick_area = float(np.count_nonzero((lim > 0) & (np.abs(st.q) < lim * (1 - 1e-9)))) * contact.dA
    W = np.array(works)
    per_cycle = [float(W[(c + 1) * steps] - W[c * steps]) for c in range(cycles)]
    last = slice((cycles - 1) * steps, cycles * steps + 1)
    return {"dissipation_per_cycle": per_cycle, "dissipation": per_cycle[-1], "delta": np.array(deltas)[last],
            "Q": Qs[last], "stick_area": stick_area, "state": st}


def halfspace_tangential_displacement(q, pixel, materials) -> np.ndarray:
    """The relative x displacement of the two surfaces (m) at the pixel centres under the pixel-wise
    uniform x traction ``q`` (n, n) (Pa) on half-spaces without periodic images: Cerruti's point
    solution (u_x = Q / (2 pi G) [(1 - nu) / r + nu x^2 / r^3], Johnson 1985, *Contact Mechanics*,
    Sec. 3.2) of both bodies integrated over each pixel in closed form (the corners of
    x ln(y + r) + y ln(x + r) for 1 / r and of y ln(x + r) for x^2 / r^3), a zero-padded FFT
    convolution. Unlike the periodic grid's ``delta`` it holds the rigid mode: the displacement of a
    sticking contact relative to the bodies far away, hence its tangential stiffness."""
    from .normal import _pixel_kernel, convolve_pixels

    n = q.shape[0]
    k = np.arange(-n + 1, n) * pixel
    X, Y = np.meshgrid(k, k, indexing="ij")
    a = 0.5 * pixel

    def corners(F):
        return F(X + a, Y + a) - F(X - a, Y + a) - F(X + a, Y - a) + F(X - a, Y - a)

    def H(x, y):  # int int x^2 / r^3 dx dy
        r = np.hypot(x, y)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.nan_to_num(y * np.log(x + r))

    inv_r, x2_r3 = _pixel_kernel(X, Y, pixel), corners(H)
    K = np.zeros_like(inv_r)
    for E, nu in ((materials.E1, materials.nu1), (materials.E2, materials.nu2)):
        G = E / (2.0 * (1.0 + nu))
        K += ((1.0 - nu) * inv_r + nu * x2_r3) / (2.0 * np.pi * G)
    return convolve_pixels(q, K)
