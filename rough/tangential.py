"""Frictional tangential contact with memory on the FFT grid: Coulomb friction cell by cell, stick and
slip, incremental, so that loops and their dissipation come out, for any pressure field (a smooth
indenter's, a rough one's: ``rough.normal.normal_contact``).

Assumptions (Mindlin's, as in MDR, by default): the tangential traction runs along x only (q_y = 0;
``traction="free"`` lets it turn, a disk |q| <= mu p per cell) and does not change the pressure (no
normal-tangential coupling: identical materials, or Dundurs' beta = 0); linear elasticity of two
half-spaces; the periodic grid of ``rough.normal.Grid`` (``periodic=False``: a window on the half-spaces
without images, the linear convolution with the pixel-integrated Cerruti kernel). The relative tangential
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

import functools
from dataclasses import dataclass

import numpy as np

from common.assumptions import check_traction
from common.errors import InputError, nonnegative, positive

from .boxqp import COMPILED, numba, solve_box, solve_disk
from .halfspace import PixelConvolution, among_cells
from .normal import Grid

#: the projected CG's tolerance (``rough.boxqp.solve_box``): the largest slip increment of a free cell,
#: relative to the range of the elastic displacement K q
TOLERANCE = 1e-10
#: the same for the traction free to turn (``rough.boxqp.solve_disk``: an accelerated projected gradient,
#: slower than the box's conjugate gradient; the dissipation to ~1e-7)
TOLERANCE_FREE = 1e-8


#: a step along x is solved on the contact's cells with a dense compliance up to this many of them
#: (``TangentialContact._dense_box``: DENSE_MAX^2 doubles, 72 MB), beyond on the grid with transforms
DENSE_MAX = 3000


#: the aliases k + 2 pi m / h summed per direction, |m| <= IMAGES (their terms fall as |m|^-3: the sum is
#: complete to ~1e-4 of the pixel-scale coefficients, far below the grid's own error)
IMAGES = 12


def _check_component(component) -> None:
    if component not in ("xx", "xy", "yy"):
        raise InputError(f"component must be 'xx', 'xy' or 'yy', got {component!r}")


def compliance(grid: Grid, materials, component: str = "xx", images: int = IMAGES) -> np.ndarray:
    """The influence of a pixel's uniform tangential traction on the tangential displacement of every
    pixel centre, both bodies, in discrete Fourier space (rfft2 layout, (n, n // 2 + 1), m / Pa), for
    ``component`` "xx", "xy" or "yy" (the displacement along the first axis under the traction along
    the second): the cell-integrated Cerruti kernel of the periodic grid, sum over the aliases
    k_m = k + 2 pi m / h of K_ij(k_m) sinc(k_m,x h / 2) sinc(k_m,y h / 2),

        K_ij(k) = sum over the bodies of (delta_ij - nu k_i k_j / k^2) / (G k)

    (the point kernel sampled alone converges non-monotonically: -1.8, -0.4, -0.8 % in the sphere's
    dissipation at a/8, a/16, a/32). The mean (k = 0, rigid) mode is 0."""
    _check_component(component)
    return _compliance(grid, materials, component, int(images))


@functools.lru_cache(maxsize=16)
def _compliance(grid: Grid, materials, component: str, images: int) -> np.ndarray:
    """``compliance``, kept per (grid, materials, component, images): the members of an ensemble on one
    grid share it (read-only). Compiled where numba is installed (``_image_sum``: the same terms in the
    same order, the sincs of each direction tabulated once), else numpy over the grid per alias."""
    h, n = grid.pixel, grid.n
    kx = 2.0 * np.pi * np.fft.fftfreq(n, d=h)
    ky = 2.0 * np.pi * np.fft.rfftfreq(n, d=h)
    mods = [(nu, E / (2.0 * (1.0 + nu))) for E, nu in ((materials.E1, materials.nu1), (materials.E2, materials.nu2))]
    inv_G, nu_over_G = sum(1.0 / G for _, G in mods), sum(nu / G for nu, G in mods)
    diag = 1.0 if component != "xy" else 0.0
    if _image_sum is not None:
        shifts = np.arange(-images, images + 1) * (2.0 * np.pi / h)
        KXs, KYs = kx[None, :] + shifts[:, None], ky[None, :] + shifts[:, None]
        # numpy's sinc(x) = sin(pi x) / (pi x)
        out = _image_sum(KXs, KYs, np.sinc(KXs * h / (2.0 * np.pi)), np.sinc(KYs * h / (2.0 * np.pi)),
                         "xy".index(component[0]), "xy".index(component[1]), diag * inv_G, nu_over_G)
        out[0, 0] = 0.0
        out.flags.writeable = False
        return out
    KX0, KY0 = np.meshgrid(kx, ky, indexing="ij")
    out = np.zeros_like(KX0)
    shift = 2.0 * np.pi / h
    KYs = [KY0 + my * shift for my in range(-images, images + 1)]
    sys_ = [np.sinc(KY * h / (2.0 * np.pi)) for KY in KYs]  # numpy's sinc(x) = sin(pi x) / (pi x)
    for mx in range(-images, images + 1):
        KX = KX0 + mx * shift
        sx = np.sinc(KX * h / (2.0 * np.pi))
        for KY, sy in zip(KYs, sys_):
            k = np.hypot(KX, KY)
            zero = k == 0.0
            k = np.where(zero, 1.0, k)
            ki, kj = {"xx": (KX, KX), "xy": (KX, KY), "yy": (KY, KY)}[component]
            # sum over the bodies of (delta_ij - nu k_i k_j / k^2) / (G k)
            term = (diag * inv_G - nu_over_G * (ki / k) * (kj / k)) / k * (sx * sy)
            out += np.where(zero, 0.0, term)
    out[0, 0] = 0.0
    out.flags.writeable = False
    return out


def _image_sum_loop(KXs, KYs, SX, SY, ci, cj, diag_inv_G, nu_over_G):
    """``_compliance``'s sum over the aliases written out per coefficient (compiled by numba as
    ``_image_sum``): KXs (2m + 1, n) and KYs (2m + 1, n // 2 + 1) the aliased wavenumbers of each
    direction, SX and SY their sincs, (ci, cj) the component's axes (0: x, 1: y); the terms summed in
    the numpy path's order (x's aliases outer, y's inner)."""
    nx, ny, na = KXs.shape[1], KYs.shape[1], KXs.shape[0]
    out = np.zeros((nx, ny))
    cx, cy = 1.0 if ci == 0 else 0.0, 1.0 if cj == 0 else 0.0
    for a in range(na):
        for b in range(na):
            ky, sy = KYs[b], SY[b]
            for i in range(nx):
                KX, sx = KXs[a, i], SX[a, i]
                row = out[i]
                for j in range(ny):
                    KY = ky[j]
                    k2 = KX * KX + KY * KY
                    if k2 > 0.0:
                        k = np.sqrt(k2)
                        ki = cx * KX + (1.0 - cx) * KY
                        kj = cy * KX + (1.0 - cy) * KY
                        row[j] += (diag_inv_G - nu_over_G * (ki / k) * (kj / k)) / k * (sx * sy[j])
    return out


_image_sum = numba.njit(cache=True)(_image_sum_loop) if numba is not None and COMPILED else None


def cerruti_pixel_kernel(n: int, pixel: float, materials, component: str = "xx") -> np.ndarray:
    """The tangential displacement (m) at the pixel centres offset by -(n - 1) .. n - 1 pixels from a
    pixel of side ``pixel`` carrying a uniform unit traction (Pa), both bodies, on half-spaces without
    periodic images, for ``component`` "xx", "xy" or "yy" ((2n - 1, 2n - 1); read-only, kept per grid,
    materials and component: a rough member's engines share it): Cerruti's point solution
    (u_i = Q_j / (2 pi G) [(1 - nu) delta_ij / r + nu x_i x_j / r^3], Johnson 1985, *Contact
    Mechanics*, Sec. 3.2) integrated over the pixel in closed form: the corners of
    x ln(y + r) + y ln(x + r) for 1 / r, of y ln(x + r) for x^2 / r^3, of x ln(y + r) for y^2 / r^3 and
    of -r for x y / r^3."""
    _check_component(component)
    return _cerruti_pixel_kernel(int(n), float(pixel), materials, component)


@functools.lru_cache(maxsize=8)
def _cerruti_pixel_kernel(n: int, pixel: float, materials, component: str) -> np.ndarray:
    from .halfspace import inverse_r_kernel

    k = np.arange(-n + 1, n) * pixel
    X, Y = np.meshgrid(k, k, indexing="ij")
    a = 0.5 * pixel

    def corners(F):
        return F(X + a, Y + a) - F(X - a, Y + a) - F(X + a, Y - a) + F(X - a, Y - a)

    def log_term(u, v):  # int int u^2 / r^3 du dv = v ln(u + r)
        r = np.hypot(u, v)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.nan_to_num(v * np.log(u + r))

    if component == "xx":
        inv_r, second, diag = inverse_r_kernel(n, pixel), corners(log_term), 1.0
    elif component == "yy":
        inv_r, second, diag = inverse_r_kernel(n, pixel), corners(lambda x, y: log_term(y, x)), 1.0
    else:
        inv_r, second, diag = 0.0, corners(lambda x, y: -np.hypot(x, y)), 0.0
    K = np.zeros_like(X)
    for E, nu in ((materials.E1, materials.nu1), (materials.E2, materials.nu2)):
        G = E / (2.0 * (1.0 + nu))
        K += (diag * (1.0 - nu) * inv_r + nu * second) / (2.0 * np.pi * G)
    K.flags.writeable = False
    return K


def magnitude(q) -> np.ndarray:
    """|q| cell by cell (n, n) of a traction (n, n) along x or (2, n, n)."""
    return np.abs(q) if np.ndim(q) == 2 else np.hypot(q[0], q[1])


def sticking(q, lim) -> np.ndarray:
    """The cells in contact (lim > 0) whose traction ``q`` ((n, n) along x or (2, n, n)) is below its
    limit ``lim`` (Pa): a boolean (n, n)."""
    return (lim > 0) & (magnitude(q) < lim * (1 - 1e-9))


@dataclass
class TangentialState:
    """The memory of the contact: each cell's accumulated slip ``s`` (m), its traction ``q`` (Pa), the
    tangential approach ``delta`` (m, along x; up to the periodic grid's rigid constant) and the
    friction work (J). With the traction free to turn (``traction="free"``) ``s`` and ``q`` carry both
    components, (2, n, n), and ``delta_y`` is the approach across the force."""

    s: np.ndarray
    q: np.ndarray
    delta: float = 0.0
    work: float = 0.0
    delta_y: float = 0.0


class TangentialContact:
    """Tangential contact with memory on ``grid`` (``rough.normal.Grid``) for ``materials`` and friction
    ``mu``; ``step(state, p, Q)`` is one increment under the pressure field ``p`` (Pa, (n, n)) and the
    tangential force ``Q`` (N, along x). Pure: the state passed in is not changed.

    ``periodic=False``: the grid is a window on two half-spaces, without periodic images (the linear
    convolution with ``cerruti_pixel_kernel``; the contact must lie inside the window), and ``delta``
    holds the rigid mode. ``traction="free"``: the traction has both components and turns with the
    slip, |q| <= mu p a disk per cell (Cerruti's cross term x y / r^3 couples them), the total along y
    zero; the default "x" is Mindlin's assumption."""

    def __init__(self, grid: Grid, materials, mu, tol=None, *, periodic=True, traction="x"):
        if not isinstance(grid, Grid):
            raise InputError(f"grid must be a rough.normal.Grid, got {grid!r}")
        check_traction(traction)
        self.grid, self.materials = grid, materials
        self.mu = float(positive("mu", mu))
        self.tol = float(positive("tol", (TOLERANCE if traction == "x" else TOLERANCE_FREE) if tol is None else tol))
        self.periodic, self.traction = bool(periodic), traction
        self.dA = grid.pixel ** 2
        comps = ("xx",) if traction == "x" else ("xx", "xy", "yy")
        if periodic:
            self.K = {c: compliance(grid, materials, c) for c in comps}
            ops = {c: (lambda q, K=self.K[c]: np.fft.irfft2(K * np.fft.rfft2(q), s=q.shape)) for c in comps}
            symbols = self.K
        else:
            ops = {c: PixelConvolution(cerruti_pixel_kernel(grid.n, grid.pixel, materials, c)) for c in comps}
            symbols = {c: op.circulant_eigenvalues() for c, op in ops.items()} if traction == "free" else {}
        self._ops = ops
        self._dense, self._real_kernel = {}, None  # the contact's dense compliance (``_dense_box``)
        if traction == "free":
            a, b, c = symbols["xx"], symbols["xy"], symbols["yy"]
            # the largest eigenvalue of the 2 x 2 symbol: bounds the operator (the window's restriction too)
            self.L = float(np.max(0.5 * (a + c) + np.sqrt(0.25 * (a - c) ** 2 + b ** 2)))

    def rest_state(self) -> TangentialState:
        n = self.grid.n
        shape = (n, n) if self.traction == "x" else (2, n, n)
        return TangentialState(s=np.zeros(shape), q=np.zeros(shape))

    def displacement(self, q) -> np.ndarray:
        """K q: the relative tangential displacement of the surfaces (m) under the traction q (Pa),
        (n, n) along x or (2, n, n) in the plane; up to the rigid mean on the periodic grid."""
        if self.traction == "x":
            return self._ops["xx"](q)
        # one transform per component, shared by the kernels that read it
        if self.periodic:
            f0, f1 = np.fft.rfft2(q[0]), np.fft.rfft2(q[1])
            back = lambda z: np.fft.irfft2(z, s=q.shape[1:])  # noqa: E731
            hats = self.K["xx"], self.K["xy"], self.K["yy"]
        else:
            xx = self._ops["xx"]
            f0, f1, back = xx.transform(q[0]), xx.transform(q[1]), xx.back
            hats = xx.hat, self._ops["xy"].hat, self._ops["yy"].hat
        return np.stack([back(hats[0] * f0 + hats[1] * f1), back(hats[1] * f0 + hats[2] * f1)])

    def _dense_box(self, state: TangentialState, lim, Q):
        """The traction along x of a step solved on the contact's cells alone (at most ``DENSE_MAX``): the
        same problem as ``solve_box``'s on the grid, with the compliance among those cells a dense matrix
        (the periodic kernel in real space, or the window's pixel kernel), so that each iteration is a
        product of the contact's size, not two transforms of the grid (a rough contact touches a few
        hundred pixels of 512^2). The same conditions to the same tolerance; None beyond ``DENSE_MAX``."""
        cells = np.flatnonzero(lim.ravel() > 0)
        if cells.size == 0 or cells.size > DENSE_MAX:
            return None
        key = cells.tobytes()
        K = self._dense.get(key)
        if K is None:
            n = self.grid.n
            if self._real_kernel is None:  # the displacement under a unit traction on pixel 0
                self._real_kernel = np.fft.irfft2(self.K["xx"], s=(n, n)) if self.periodic else \
                    cerruti_pixel_kernel(n, self.grid.pixel, self.materials, "xx")
            K = among_cells(self._real_kernel, cells, n, self.periodic)
            if len(self._dense) >= 4:
                self._dense.clear()
            self._dense[key] = K
        lc = lim.ravel()[cells]
        qc = solve_box(K.__matmul__, state.s.ravel()[cells], lc, Q, np.clip(state.q.ravel()[cells], -lc, lc),
                       self.dA, self.tol, "tangential contact")
        q = np.zeros(lim.size)
        q[cells] = qc
        return q.reshape(lim.shape)

    def sticking(self, q, p) -> np.ndarray:
        """The cells in contact whose traction is below the limit mu p (a boolean (n, n))."""
        return sticking(q, self.mu * np.asarray(p, dtype=float))

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
        if self.traction == "x":
            q = self._dense_box(state, lim, Q)
            if q is None:
                q = solve_box(self.displacement, state.s, lim, Q, np.clip(state.q, -lim, lim), self.dA, self.tol,
                              "tangential contact")
        else:
            q = solve_disk(self.displacement, state.s, lim, (Q, 0.0), state.q, self.dA, self.tol, self.L,
                           "tangential contact")
        g = self.displacement(q) + state.s
        stick = self.sticking(q, p)
        inside = lim > 0
        pick = stick if stick.any() else inside
        reduce = np.mean if stick.any() else np.median
        if self.traction == "x":
            delta = float(reduce(g[pick]))
            ds = np.where(stick, 0.0, delta - g)  # 0 sticking, the slip increment slipping, the new position out of contact
            work = float(np.sum(q * np.where(inside, ds, 0.0))) * self.dA
            return TangentialState(s=state.s + ds, q=q, delta=delta, work=state.work + work)
        delta = np.array([float(reduce(g[0][pick])), float(reduce(g[1][pick]))])
        ds = np.where(stick, 0.0, delta[:, None, None] - g)
        work = float(np.sum(q * np.where(inside, ds, 0.0))) * self.dA
        return TangentialState(s=state.s + ds, q=q, delta=float(delta[0]), work=state.work + work,
                               delta_y=float(delta[1]))


def run_force_cycles(contact: TangentialContact, p, fa, cycles=3, steps=40) -> dict:
    """Q(t) = fa sin(2 pi t) at the constant pressure field ``p``, from rest; the dissipation of every
    cycle (the friction work over it, J), the loop (delta, Q) of the last, the state at the last cycle's
    peak (``peak``) and its stick area (the cells whose traction is below the limit)."""
    nonnegative("fa", fa)
    st = contact.rest_state()
    t = np.arange(cycles * steps + 1) / steps
    Qs = fa * np.sin(2 * np.pi * t)
    works, deltas, stick_area, peak = [0.0], [0.0], None, None
    for k, Q in enumerate(Qs[1:], start=1):
        st = contact.step(st, p, Q)
        works.append(st.work)
        deltas.append(st.delta)
        if k == (cycles - 1) * steps + steps // 4:
            stick_area, peak = float(np.count_nonzero(contact.sticking(st.q, p))) * contact.dA, st
    W = np.array(works)
    per_cycle = [float(W[(c + 1) * steps] - W[c * steps]) for c in range(cycles)]
    last = slice((cycles - 1) * steps, cycles * steps + 1)
    return {"dissipation_per_cycle": per_cycle, "dissipation": per_cycle[-1], "delta": np.array(deltas)[last],
            "Q": Qs[last], "stick_area": stick_area, "peak": peak, "state": st}


def halfspace_tangential_displacement(q, pixel, materials) -> np.ndarray:
    """The relative x displacement of the two surfaces (m) at the pixel centres under the pixel-wise
    uniform x traction ``q`` (n, n) (Pa) on half-spaces without periodic images
    (``cerruti_pixel_kernel``, a zero-padded FFT convolution). Unlike the periodic grid's ``delta`` it
    holds the rigid mode: the displacement of a sticking contact relative to the bodies far away, hence
    its tangential stiffness."""
    return PixelConvolution(cerruti_pixel_kernel(q.shape[0], pixel, materials, "xx"))(q)


def stick_radius(q, p, mu, radii) -> float | None:
    """The radius (m) of a stick zone that is a disk about the point the pixel distances ``radii`` (m,
    (n, n)) are measured from, out of the traction ``q`` (Pa; (n, n) along x or (2, n, n)) under the
    pressure ``p``: the root c of the straight line fitted to (mu p - |q|)^2 against r^2 over the stick
    cells beyond half the outermost stick cell's radius. Assumes the traction's deficit vanishes like the
    square root of the distance to a smooth stick edge (Cattaneo-Mindlin's, exactly:
    (mu p - q)^2 = (3 mu F / (2 pi a^3))^2 (c^2 - r^2)); continuous in the fields, unlike the count of
    stick cells, which jumps as the edge crosses a pixel centre (+1.7, +0.6, +0.4 % on a/16, a/24, a/32
    against the fit's +0.1, +0.06, +0.04 %). None with fewer than 3 such cells or no root."""
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    mag, lim = magnitude(q), mu * p
    stick = sticking(q, lim)
    if not stick.any():
        return None
    r_out = float(np.max(radii[stick]))
    sel = stick & (radii > 0.5 * r_out)
    if np.count_nonzero(sel) < 3:
        return None
    slope, icpt = np.polyfit(radii[sel] ** 2, (lim - mag)[sel] ** 2, 1)
    if not (slope < 0 and icpt > 0):
        return None
    return float(np.sqrt(-icpt / slope))
