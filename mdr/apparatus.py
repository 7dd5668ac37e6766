"""Quasi-static model of the fretting apparatus around a contact law.

Reconstruction of the hybrid model of Willert, Machines 11 (2023) 484, Section 3
(whose equations and Figure 3 are missing from our copy), from its text, Table 1
and docs/design.md, section 5. Every assumption beyond the paper's text
is listed here and in the README; ``sensitivity`` measures its effect.

Degrees of freedom (x, the fretting direction): indenter foundation u_1, block
u_2, piezo u_3(t) = u_A sin(2 pi t) (prescribed). The relative displacement of
the fretting contact is du = u_2 - u_1.

- A1 (paper): quasi-static, no inertia (20 Hz far below the eigenfrequencies);
  the block is rigid; the normal force F_N(t) = F0 + dF sin(2 pi t + alpha) is
  prescribed at the contact.
- A2 (paper): the indenter sits on the normal axis of tangential stiffness k_x:
  F_x = k_x u_1 (F_x: tangential force of the contact, on the indenter).
- A3 (reconstruction): the two brass plates ("a bridge of two thin brass plates
  that is supposed to act as a parallel motion", "modeled as bent beams within the
  framework of the Euler-Bernoulli theory") join piezo and block. Table 1 gives
  E, l, B, t and one height h2; Figure 3 (missing) would say how they are placed.
  Readings (``plate_model``; heights z above the bedding plane, contact at z = h):

  * ``axial`` (default): plates along x, loaded along their length, side by side at
    z = h2: k_p = 2 E B t / l = 49 N/um. Their bending across the thickness (1.7 N/mm,
    vertical) is the parallel motion's free direction: it lets the block settle on
    its bedding; 1e-4 of the bedding's normal stiffness, neglected. No tilt.
  * ``bending``: plates upright, thickness along x, bent across it as guided beams
    (both ends clamped, the classic parallel-spring guide): 2 x 12 E I / l^3,
    I = B t^3 / 12: 1.7 N/mm, far too soft to move the block against its bedding
    (mu2 (m1 g + F0) = 0.38 N needs 0.22 mm): the block and the contact stick.
  * ``inplane``: plates upright, width along x, bent in their own plane as guided
    beams: I = t B^3 / 12, 2 x 12 E I / l^3 = 75 N/um (Euler-Bernoulli, as the
    paper says, although B/l = 1.2 makes them deep beams).
  * ``rigid``: the limit (u_2 = u_3).
  * ``tilt``: as ``axial``, but the rigid block also tilts by theta on its three
    bedding contacts under the moment of F_x (at h) and of the plate force (at h2);
    the bedding resists with the rocking stiffness k_theta of its Hertz contacts
    (``Apparatus.rocking_stiffness``: 1.6 / 2.7 / 3.4e3 N m/rad at R_bed = 1 / 5 /
    10 mm), linearised at the static load m1 g + F0 (the moment changes the sphere
    loads by up to 20 %, k_theta by up to 7 %, of a term that moves delta by < 0.03).
  * ``parallel``: the plates as a parallelogram, each E B t / l, one at the bottom
    (z = 0) and one at the top (z = h2) of the block; the block tilts on its bedding
    and the plates' couple resists the tilt too (k_a h2^2 / 2 = 4.9e3 N m/rad). An ideal
    parallel motion (no tilt at all) is ``axial`` but for the split of the bedding
    loads (equal approach, so W/3 each), which only shifts the bedding's short stick
    phase.

  Tilting block (``tilt``, ``parallel``): a point at height z moves u_b + theta z
  (u_b: bedding plane, where the bedding's tangential forces act); the contact point
  moves u_2 = u_b + theta h. Plate j (stiffness k_j at z_j) pulls with
  F_j = k_j (u_3 - u_b - theta z_j). Equilibrium of the block in x and of its moments
  about the bedding point below the contact (F_N and the weight act on the vertical
  through it; their moments F_N h theta + m1 g (h/2) theta ~ 0.04 N m/rad are 1e-5 of
  k_theta, as are the plates' bending moments 4 E I / l = 3e-4 N m/rad: neglected):

      sum_j F_j = F_x + F_bed,        sum_j F_j z_j - F_x h = k_theta theta.

  With S_n = sum_j k_j z_j^n, for a given contact displacement (F_x and u_2 known)
  the moment equation gives theta in closed form,

      theta = (S1 (u_3 - u_2) - F_x h) / (k_theta + S2 - S1 h),   u_b = u_2 - theta h,

  so the step stays one monotone equation in du (below). Without tilt theta = 0 and
  u_b = u_2. The piezo-to-contact loss is linear: u_3 - u_2 = A F_x + Bc F_bed
  (``Apparatus.stroke_loss``); one resultant at h2 gives A = 1/k_p + (h2 - h)^2 /
  k_theta and Bc = 1/k_p + h2 (h2 - h) / k_theta: as h2 ~ h the tilt barely reaches
  the contact (A rises by < 1e-3 um/N; the parallelogram: by < 0.013 um/N).
- A4 (reconstruction): the block rests on three Si3N4 half-spheres of radius
  ``R_bed`` (not given in the paper; default 5 mm), MDR contact laws with
  friction mu_2, all displaced by u_2 (no block rotation). One sphere lies at
  x = +l_1, two at x = -l_2 from the point below the contact (Table 1: l_1, l_2).
  Their normal forces follow from the vertical and moment equilibrium of the
  block under its weight m_1 g, the normal force F_N and the moment of the
  tangential forces: the contact force at height h (the block height) and the
  plate force at height h_2. The moment uses the previous step's tangential
  forces (explicit coupling; the change in one step is tiny).
- A5: h_1 and m_2 (the normal axis' geometry and mass) do not enter the
  quasi-static equilibrium in x and are not used.

Equilibrium of the block, written with compliances so that an infinitely stiff
apparatus (c = 1/k = 0) is allowed (c_p = 1/S0, zbar = S1/S0):

    r(du) = u_3 - u_b - zbar theta - c_p (F_x + F_bed),    u_2 = du + c_x F_x,

with F_x = F_x(du) of the contact law and F_bed(u_b) of the bedding laws (without
tilt: r = u_3 - u_2 - c_p (F_x + F_bed)). r is strictly decreasing in du (all contact
forces are nondecreasing in their displacement; with tilt when k_theta + S2 - S1 h > 0,
checked, and the plates' resultant not far below the contact, as in every reading),
so each step is solved by a safeguarded Newton iteration in a
shrinking bracket (``mdr.solve``) over trial, uncommitted steps of the laws:
their ``force`` gives F_x and its slope. It starts from the previous step's du moved by
the piezo's step over the slope of r there (exact while no spring or pair changes between
stick and slip), so a step typically takes two force evaluations. Any contact law of the protocol
(``mdr.protocol.ContactLaw``: ``rest_state``, ``normal_load``, ``prepare`` with
the trials' ``force``/``commit``) drops in; ``prepare`` is required.
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass, replace

import numpy as np

from . import kernels as _kernels
from common.errors import InputError, nonnegative, positive
from .drive import mdr_law
from .law import MDRContact
from .loading import Loading
from .loops import analyse_cycles, slip_index
from .paper import KX_TABLE1, MU2, STEEL_E, STEEL_NU
from .materials import Materials
from .profiles import Sphere
from .protocol import ContactLaw
from .solve import solve_increasing
from .stick import stick_radius

G_ACC = 9.81
PLATE_MODELS = ("axial", "bending", "inplane", "rigid", "tilt", "parallel")
TILT_MODELS = ("tilt", "parallel")  # plate models whose block tilts on its bedding


@dataclass(frozen=True)
class Apparatus:
    """Apparatus parameters (SI), defaults from Table 1 of Willert (2023).

    ``kx``, ``mu2``, ``R_bed`` and ``plate_model`` may be arrays of the batch
    shape of the contact law (one apparatus per scene, run in one pass).
    ``bedding=False`` (no bedding contacts) is the same as ``mu2 = 0``: a
    frictionless bedding carries no tangential force. ``plate_model``: one of
    ``PLATE_MODELS`` (module docstring, A3).
    """

    kx: float = KX_TABLE1      # tangential stiffness of the normal axis, N/m (Table 1)
    mu2: float = MU2           # friction of the Si3N4 bedding (Table 2)
    m1: float = 0.335          # block mass, kg
    m2: float = 0.047          # (not used: A5)
    E_plate: float = 100e9     # brass
    l: float = 34e-3           # plate length
    B: float = 42e-3           # plate width
    t: float = 0.2e-3          # plate thickness
    l1: float = 8e-3
    l2: float = 13e-3
    h: float = 19e-3
    h1: float = 50e-3          # (not used: A5)
    h2: float = 20e-3
    E_bed: float = 300e9
    nu_bed: float = 0.29
    R_bed: float = 5e-3        # bedding half-sphere radius (reconstruction, A4)
    plate_model: str = "axial"
    bedding: bool = True       # False: frictionless bedding, no bedding laws

    def __post_init__(self):
        for name in ("m1", "E_plate", "l", "B", "t", "l1", "l2", "h", "h2", "E_bed", "R_bed"):
            positive(name, getattr(self, name))
        kx = getattr(self, "kx")
        if not (np.all(np.asarray(kx, dtype=float) > 0)):
            raise InputError(f"kx must be > 0 (inf allowed: rigid axis), got {kx!r}")
        nonnegative("mu2", self.mu2)
        if not np.all(np.isin(np.asarray(self.plate_model), PLATE_MODELS)):
            raise InputError(f"plate_model must be one of {', '.join(PLATE_MODELS)}; got {self.plate_model!r}")

    def _per_model(self, values):
        """``values[name]`` for each scene's plate model (scalar for a scalar model)."""
        pm = np.asarray(self.plate_model)
        if pm.ndim == 0:
            return values[str(pm)]
        return np.select([pm == name for name in PLATE_MODELS], [values[name] for name in PLATE_MODELS])

    def plate_springs(self):
        """The plates as springs in x on the block: ``[(k_j, z_j), ...]`` for a scalar
        plate model (stiffness in N/m, height of the attachment above the bedding plane
        in m; A3)."""
        if np.asarray(self.plate_model).ndim:
            raise InputError("plate_springs needs a scalar plate_model")
        pm = str(self.plate_model)
        E, B, t, l, h2 = self.E_plate, self.B, self.t, self.l, self.h2
        axial_one = E * B * t / l
        k = {"axial": 2.0 * axial_one, "tilt": 2.0 * axial_one,
             "bending": 2.0 * 12.0 * E * (B * t**3 / 12.0) / l**3,
             "inplane": 2.0 * 12.0 * E * (t * B**3 / 12.0) / l**3, "rigid": np.inf}
        if pm == "parallel":
            return [(axial_one, 0.0), (axial_one, h2)]
        return [(k[pm], h2)]

    @property
    def k_plates(self):
        """Stiffness in x of the plates between piezo and block, all plates together
        (N/m; array for a batch of plate models)."""
        return self._per_model({pm: sum(k for k, _ in replace(self, plate_model=pm).plate_springs())
                                for pm in PLATE_MODELS})

    def rocking_stiffness(self, F0):
        """Resistance of the bedding to a tilt theta of the block, k_theta = dM/dtheta
        (N m/rad), at the static load m1 g + F0 without moment: each sphere a Hertz
        contact of normal stiffness k_i = 2 E* a_i, a_i = (3 N_i R_bed / (4 E*))^(1/3),
        at x_i = +l1 (one) and -l2 (two); the block turns about the bedding's elastic
        centre: k_theta = sum k_i x_i^2 - (sum k_i x_i)^2 / sum k_i."""
        E_star = Materials(self.E_bed, self.nu_bed, STEEL_E, STEEL_NU).E_star
        N1, N2 = self.bedding_loads(F0, 0.0)
        k1, k2 = (2.0 * E_star * (3.0 * N * self.R_bed / (4.0 * E_star)) ** (1.0 / 3.0) for N in (N1, N2))
        s0 = k1 + 2.0 * k2
        s1 = k1 * self.l1 - 2.0 * k2 * self.l2
        s2 = k1 * self.l1**2 + 2.0 * k2 * self.l2**2
        return s2 - s1**2 / s0

    def plate_terms(self, F0):
        """Per-scene coefficients of the block equilibrium (module docstring, "Equilibrium"):
        ``cp`` = 1/S0 (0: rigid plates), ``zbar`` = S1/S0, ``S1``, ``S2``, ``J`` = S2 - S1^2/S0
        and ``c_tilt`` = 1/k_theta, with S0, S1, S2 the sums of k_j, k_j z_j, k_j z_j^2 over
        the plates; for a model without tilt S1 = S2 = J = c_tilt = 0 (not needed)."""
        terms = {}
        for pm in PLATE_MODELS:
            springs = replace(self, plate_model=pm).plate_springs()
            S0 = sum(k for k, _ in springs)
            zbar = sum(k * z for k, z in springs) / S0 if np.isfinite(S0) else self.h2
            tilt = pm in TILT_MODELS
            S1 = sum(k * z for k, z in springs) if tilt else 0.0
            S2 = sum(k * z * z for k, z in springs) if tilt else 0.0
            terms[pm] = dict(cp=1.0 / S0, zbar=zbar, S1=S1, S2=S2, J=S2 - S1**2 / S0 if tilt else 0.0,
                             c_tilt=1.0 / self.rocking_stiffness(F0) if tilt else 0.0)
        return {key: self._per_model({pm: terms[pm][key] for pm in PLATE_MODELS}) for key in terms["axial"]}

    def stroke_loss(self, F0):
        """Compliances (A, Bc) of the piezo-to-contact path, u_3 - u_2 = A F_x + Bc F_bed
        (m/N, per scene): exact at every step of ``run_apparatus`` (the plates and the
        tilt are linear). Without tilt A = Bc = 1/k_plates; a single plate resultant at
        h2 over a tilting block gives A = 1/k_p + (h2 - h)^2 / k_theta and
        Bc = 1/k_p + h2 (h2 - h) / k_theta."""
        pt = self.plate_terms(F0)
        ct, S1, zbar, h = pt["c_tilt"], pt["S1"], pt["zbar"], self.h
        den = 1.0 + ct * (pt["S2"] - S1 * h)
        lead = 1.0 - (zbar - h) * ct * S1 / den
        return (pt["cp"] - (zbar - h) * ct * h / den) / lead, pt["cp"] / lead

    def bedding_loads(self, FN, M):
        """Normal forces (front sphere, each rear sphere) for normal force FN and moment M."""
        W = self.m1 * G_ACC + FN
        L = self.l1 + self.l2
        # N1 + 2 N2 = W ; N1 l1 - 2 N2 l2 = M
        N1 = (W * self.l2 + M) / L
        N2 = (W * self.l1 - M) / (2.0 * L)
        return N1, N2


def run_apparatus(law: ContactLaw, app: Apparatus, loading: Loading, bed_law_factory=None, xtol=1e-15,
                  state_at=None):
    """Run the apparatus with contact law ``law`` (``mdr.protocol.ContactLaw``, batch allowed; its ``mu``
    is the friction of the slip index too) under ``loading`` (drive ``"apparatus"``: the piezo amplitude,
    ``Loading.apparatus``); its ``dF``, ``alpha`` and ``app``'s array fields may be batch arrays.
    Returns a dict with per-step arrays (t, Fx, FN, u1, u2, u3, du, Fbed; ub and tilt:
    bedding-plane displacement and tilt of the block, A3) and the
    cycle analysis (dW per cycle, stationarity, slip index of the last cycle);
    ``state_at`` (a step index): also the law's state after that step, as
    ``out["state_at"]``.
    """
    if loading.drive != "apparatus":
        raise InputError(f"the apparatus is driven by its piezo (Loading.apparatus), got drive {loading.drive!r}")
    if loading.normal_steps:
        raise InputError(f"normal_steps must be 0 in the apparatus (its first step applies the normal force with the "
                         f"piezo's), got {loading.normal_steps}")
    mu = loading.check_friction(law.mu)
    F0 = loading.F0
    batch = law.batch
    t = loading.times()
    if state_at is not None and not 0 <= int(state_at) < t.size:
        raise InputError(f"state_at must be a step index in [0, {t.size - 1}], got {state_at!r}")
    FN = np.broadcast_to(loading.normal_force(), batch + t.shape)
    u3 = loading.tangential()
    cx = 0.0 if np.all(np.isinf(app.kx)) else 1.0 / np.asarray(app.kx, dtype=float)
    pt = app.plate_terms(F0)
    cp, zbar = pt["cp"], pt["zbar"]
    tilting = bool(np.any(pt["c_tilt"] > 0))
    if tilting:  # theta(du) = c_tilt (S1 (u3 - u_c) - F_x h) / den (module docstring)
        ct, S1, h = pt["c_tilt"], pt["S1"], app.h
        den = 1.0 + ct * (pt["S2"] - S1 * h)
        if np.any(den <= 0):
            raise InputError("plate heights and bedding give an unstable block (1 + (S2 - S1 h) / k_theta <= 0)")
    use_bed = bool(app.bedding and np.any(np.asarray(app.mu2) > 0))
    if use_bed:
        Wmax = app.m1 * G_ACC + loading.F_max
        bed = (bed_law_factory or _mdr_bedding)(app, Wmax, batch)
    st = law.rest_state()
    normal = law.normal_load(np.broadcast_to(FN, batch + t.shape))
    iters = 0
    du_prev = np.zeros(batch)
    out = {k: np.zeros(batch + (t.size,)) for k in ("Fx", "FN", "u1", "u2", "du", "Fbed", "a", "c", "ub", "tilt")}
    first = loading.last_cycle.start  # the last (stationary) cycle, whose stick radius is reported
    window = []
    M = np.zeros(batch)
    # the same loop compiled (mdr.kernels) for the MDR law with MDR bedding spheres; None: not applicable
    # (it solves the untilted block with the plate force at h2: not for the tilting plate readings)
    plain = type(law) is MDRContact and not tilting and np.allclose(zbar, app.h2, rtol=1e-15, atol=0.0)
    fast = _kernels.apparatus_loop(law, bed if use_bed else None, app, mu, FN, normal["d"], u3, cx, cp, first,
                                   state_at, G_ACC, xtol) if plain else None
    if fast is not None:
        out, window, iters = fast
        out["ub"], out["tilt"] = out["u2"].copy(), np.zeros_like(out["u2"])
    elif use_bed:  # the bedding stepped compiled where it is the MDR spheres of ``_mdr_bedding``, else by its step API
        bed = _kernels.CompiledBedding(bed, batch) if (_kernels.enabled() and type(bed) is MDRContact
                                                       and _kernels.parabolic_spheres(bed, batch)) else StepBedding(bed)
    # Newton predictor: the previous solution moved by the piezo's step over the slope of the equilibrium
    # there, exact while the laws stay on their linear pieces (the slope is >= 1: the contact takes a
    # part of the stroke; a step of the full stroke is right in gross slip only)
    slope = np.ones(batch)
    for k in range(t.size if fast is None else 0):
        if use_bed:
            N1, N2 = app.bedding_loads(FN[..., k], M)
            N_b = np.stack(np.broadcast_arrays(N1, N2), axis=-1)  # batch + (2,)
            if np.any(N_b <= 0):
                raise InputError("the block lifts off a bedding sphere: tangential moment too large for the bedding geometry")
            bed.normal(N_b)
        load = {key: v[..., k] for key, v in normal.items()}
        span = (np.asarray(mu) * FN[..., k] + (app.mu2 * (app.m1 * G_ACC + FN[..., k]) if use_bed else 0.0)) \
            * (cp + cx + (2.0 * ct * (h + zbar) ** 2 if tilting else 0.0)) + 1e-12
        lo = np.broadcast_to(u3[k] - span, batch).astype(float)
        hi = np.broadcast_to(u3[k] + span, batch).astype(float)

        tr = law.prepare(st, **load)

        def fun(du):
            # -r(du) and its slope: increasing in du
            nonlocal iters
            iters += 1
            F, kF = tr.force(du)
            u2 = du + cx * F
            du2 = 1.0 + cx * kF
            if tilting:  # block tilt and bedding-level displacement ub = u2 - theta h
                th = ct * (S1 * (u3[k] - u2) - F * h) / den
                dth = -ct * (S1 * du2 + kF * h) / den
                ub, dub = u2 - th * h, du2 - dth * h
            else:
                th = dth = 0.0
                ub, dub = u2, du2
            if use_bed:
                Fb, kb = bed.force(ub)
            else:
                Fb, kb = 0.0, 0.0
            sl = dub + zbar * dth + cp * (kF + kb * dub)
            slope[...] = sl  # the last evaluation is at the solution
            return ub + zbar * th + cp * (F + Fb) - u3[k], sl

        x0 = du_prev + (u3[k] - u3[max(k - 1, 0)]) / np.where(np.isfinite(slope) & (slope > 0), slope, 1.0)
        du = solve_increasing(fun, np.zeros(batch), lo, hi, x0=np.broadcast_to(x0, batch), atol=xtol, xtol=xtol,
                              what="apparatus equilibrium")
        res, st_new = tr.commit(du)
        u2 = du + cx * res.Fx
        th = ct * (S1 * (u3[k] - u2) - res.Fx * h) / den if tilting else np.zeros_like(u2)
        ub = u2 - th * app.h
        Fbed = bed.commit(ub) if use_bed else np.zeros_like(u2)
        du_prev = du
        st = st_new
        if state_at is not None and k == int(state_at):
            out["state_at"] = st
        if use_bed:
            # moment about the bedding plane for the next step's sphere loads (A4):
            # sum_j F_j z_j - F_x h = zbar (F_x + F_bed) - J theta - F_x h
            M = -res.Fx * app.h + (res.Fx + Fbed) * zbar - pt["J"] * th
        for key, x in (("Fx", res.Fx), ("FN", res.FN), ("u1", cx * res.Fx), ("u2", u2), ("du", du), ("Fbed", Fbed),
                       ("ub", ub), ("tilt", th), ("a", res.a), ("c", res.c)):
            out[key][..., k] = x
        if k >= first and res.slack is not None:
            window.append((res.slack, res.slipping))
    return _finished(out, window, law, loading, mu, u3, first, iters)


def _finished(out: dict, window: list, law, loading: Loading, mu, u3, first: int, iters: int) -> dict:
    """``run_apparatus``'s result from its per-step arrays ``out``: the cycle analysis (the piezo's u3
    prescribed, F_x free), the stick radius of the last cycle (from the nodes' slack and slip state in
    ``window`` where the law has them, else the smallest instantaneous one), the slip index and the
    dissipation of the last cycle, the evaluations per step."""
    t = loading.times()
    cyc = analyse_cycles(out["du"], out["Fx"], loading.steps, mu, loading.F0, driven="displacement")
    last_a = out["a"][..., first:]
    if window and len(window) == last_a.shape[-1]:
        out["stick_radius"] = stick_radius(law.stick_nodes, np.stack([w[0] for w in window], axis=-2),
                                           np.stack([w[1] for w in window], axis=-2), last_a, law.stick_onset)
    else:  # a law without slip state per node: smallest instantaneous stick radius of the cycle
        out["stick_radius"] = np.min(out["c"][..., first:], axis=-1)
    out["t"] = t
    out["u3"] = u3
    out["cycles"] = cyc
    out["slip_index"] = slip_index(cyc.dissipation[..., -1], mu, loading.amplitude, loading.F0)
    out["dissipation"] = cyc.dissipation[..., -1]
    out["evaluations_per_step"] = iters / t.size
    return out


class StepBedding:
    """The bedding laws of ``run_apparatus`` (batch + (2,): the front sphere and one rear sphere; the
    second rear sphere is the first's twin) stepped through the step API of ``mdr.protocol``
    (``approach``, ``prepare``, the trial's ``force`` and ``commit``): any bedding law. The state is held
    here, updated by ``commit``; ``mdr.kernels.CompiledBedding`` is the same for the MDR spheres of
    ``_mdr_bedding``, compiled."""

    def __init__(self, law):
        self.law = law
        self.state = law.rest_state()
        self.trial = None

    def normal(self, N_b):
        """The normal update at the sphere loads ``N_b`` (batch + (2,), > 0)."""
        self.trial = self.law.prepare(self.state, d=self.law.approach(N_b))

    def force(self, ub):
        """(F_bed, dF_bed/du_b) of the prepared step at the bedding-plane displacement ``ub`` (batch)."""
        F, k = self.trial.force(np.stack([ub, ub], axis=-1))
        return F[..., 0] + 2.0 * F[..., 1], k[..., 0] + 2.0 * k[..., 1]

    def commit(self, ub):
        """Commit the prepared step at ``ub``: the bedding's tangential force F_bed (batch)."""
        res, self.state = self.trial.commit(np.stack([ub, ub], axis=-1))
        return res.Fx[..., 0] + 2.0 * res.Fx[..., 1]


def _mdr_bedding(app: Apparatus, Wmax, batch=()):
    """Bedding: front sphere and one rear sphere (the second rear one is identical);
    Si3N4 half-spheres on the steel block (E = 200 GPa, nu = 0.29)."""
    mat = Materials(app.E_bed, app.nu_bed, STEEL_E, STEEL_NU)
    shape = tuple(batch) + (2,)
    per_sphere = lambda v: np.array(np.broadcast_to(np.asarray(v, dtype=float)[..., None], shape))  # noqa: E731
    return MDRContact(Sphere(per_sphere(app.R_bed)), mat, per_sphere(app.mu2), F_max=per_sphere(Wmax), n=100)


def mdr_apparatus_result(profile, materials, app: Apparatus, mu, loading: Loading, n=400, state_at=None):
    """``apparatus_result`` of the MDR law of ``n`` cells sized for the load (``python -m mdr apparatus``)."""
    return apparatus_result(mdr_law(profile, materials, mu, loading, n), app, loading, state_at=state_at)


def apparatus_result(law: ContactLaw, app: Apparatus, loading: Loading, state_at=None):
    """One apparatus scene as the JSON dict of ``python -m mdr apparatus`` (keys of ``contact``).

    ``state_at`` (a step index): return ``(result, state of the law after that step)``."""

    t0 = time.perf_counter()
    out = run_apparatus(law, app, loading, state_at=state_at)
    F0, mu, last = loading.F0, law.mu, loading.last_cycle
    cyc = out["cycles"]
    delta = float(out["slip_index"])
    result = {
        **law.contact_at(F0), "normal_force": F0,  # the law's own, never another model's
        "stick_radius": float(out["stick_radius"]),
        "dissipation": float(out["dissipation"]),
        "slip_index": None if not np.isfinite(delta) else delta,
        "dissipation_per_cycle": cyc.dissipation.tolist(),
        "stationary": bool(cyc.last_is_stationary),
        "normal_loading": loading.normal_loading_record(),  # none: the first step applies F_N (run_apparatus)
        "cycle_change": cyc.last_change(),
        "evaluations_per_step": out["evaluations_per_step"],
        "runtime_s": time.perf_counter() - t0,
        "loop": {k: out[src][last].tolist() for k, src in
                 (("t", "t"), ("du", "du"), ("Fx", "Fx"), ("FN", "FN"), ("u1", "u1"), ("u2", "u2"), ("u3", "u3"))},
        "inputs": {**law.profile.describe(), **law.materials.as_dict(), "mu": mu, **loading.as_inputs(),
                   "apparatus": {k: (None if isinstance(v, float) and not np.isfinite(v) else v)
                                 for k, v in asdict(app).items()},
                   "k_plates": app.k_plates},
    }
    return result if state_at is None else (result, out["state_at"])
