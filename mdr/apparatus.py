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
- A3 (reconstruction): the two brass plates join piezo and block as a parallel
  motion, loaded along their length: each is an Euler-Bernoulli beam in
  tension/compression, k_p = E B t / l, two in parallel (``plate_model="axial"``,
  49 N/um with Table 1). The alternative, plates bent across their thickness
  as guided beams (k_p = 2 * 12 E I / l^3, I = B t^3/12, 1.7 N/mm), is offered
  as ``plate_model="bending"``; it is far too soft to move the block against its
  bedding, which rules it out for the experiments of the paper.
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
apparatus (c = 1/k = 0) is allowed:

    r(du) = u_3 - u_2 - c_p (F_x + F_bed),    u_2 = du + c_x F_x,

with F_x = F_x(du) of the contact law and F_bed(u_2) of the bedding laws. r is
strictly decreasing in du (all contact forces are nondecreasing in their
displacement), so each step is solved by a safeguarded Newton iteration in a
shrinking bracket (``mdr.solve``) over trial, uncommitted steps of the laws:
their ``force`` gives F_x and its slope. Any contact law of the protocol
(``mdr.protocol.ContactLaw``: ``rest_state``, ``normal_load``, ``prepare`` with
the trials' ``force``/``commit``) drops in; ``prepare`` is required.
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass

import numpy as np

from . import kernels as _kernels
from .errors import InputError, nonnegative, positive
from .drive import check_harmonic_load
from .law import MDRContact
from .loops import analyse_cycles, slip_index
from .materials import Materials
from .profiles import Sphere
from .protocol import ContactLaw
from .solve import solve_increasing
from .stick import stick_radius

G_ACC = 9.81
PLATE_MODELS = ("axial", "bending", "rigid")


@dataclass(frozen=True)
class Apparatus:
    """Apparatus parameters (SI), defaults from Table 1 of Willert (2023).

    ``kx``, ``mu2``, ``R_bed`` and ``plate_model`` may be arrays of the batch
    shape of the contact law (one apparatus per scene, run in one pass).
    ``bedding=False`` (no bedding contacts) is the same as ``mu2 = 0``: a
    frictionless bedding carries no tangential force.
    """

    kx: float = 1.9e6          # tangential stiffness of the normal axis, N/m
    mu2: float = 0.1           # friction of the Si3N4 bedding
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
            raise InputError(f"plate_model must be one of axial, bending, rigid; got {self.plate_model!r}")

    @property
    def k_plates(self):
        """Stiffness of the two plates between piezo and block (N/m; array for a batch of plate models)."""
        I = self.B * self.t**3 / 12.0
        k = {"axial": 2.0 * self.E_plate * self.B * self.t / self.l,
             "bending": 2.0 * 12.0 * self.E_plate * I / self.l**3, "rigid": np.inf}
        pm = np.asarray(self.plate_model)
        if pm.ndim == 0:
            return k[str(pm)]
        return np.select([pm == name for name in PLATE_MODELS], [k[name] for name in PLATE_MODELS])

    def bedding_loads(self, FN, M):
        """Normal forces (front sphere, each rear sphere) for normal force FN and moment M."""
        W = self.m1 * G_ACC + FN
        L = self.l1 + self.l2
        # N1 + 2 N2 = W ; N1 l1 - 2 N2 l2 = M
        N1 = (W * self.l2 + M) / L
        N2 = (W * self.l1 - M) / (2.0 * L)
        return N1, N2


def check_load(F0, dF, alpha, ua, cycles, steps):
    """Validate the apparatus load (dF, alpha may be batch arrays; ``mdr.drive.check_harmonic_load``
    plus the piezo amplitude ua); returns them normalised."""
    F0, dF, alpha, cycles, steps = check_harmonic_load(F0, dF, alpha, cycles, steps)
    return F0, dF, alpha, positive("ua", ua), cycles, steps


def run_apparatus(law: ContactLaw, app: Apparatus, mu, F0, dF=0.1, alpha=0.0, ua=150e-9, cycles=4, steps=200,
                  bed_law_factory=None, xtol=1e-15, state_at=None):
    """Run the apparatus with contact law ``law`` (``mdr.protocol.ContactLaw``, batch allowed).

    ``dF``, ``alpha`` and the array fields of ``app`` may be batch arrays (one
    value per scene of the law's batch); ``F0`` and ``ua`` are scalars.
    Returns a dict with per-step arrays (t, Fx, FN, u1, u2, u3, du, Fbed) and the
    cycle analysis (dW per cycle, stationarity, slip index of the last cycle);
    ``state_at`` (a step index): also the law's state after that step, as
    ``out["state_at"]``.
    """
    F0, dF, alpha, ua, cycles, steps = check_load(F0, dF, alpha, ua, cycles, steps)
    mu = nonnegative("mu", mu)
    if not np.allclose(np.asarray(law.mu, dtype=float), mu, rtol=1e-12, atol=0.0):
        # the law's mu sets the physics, this mu the slip index: they must agree
        raise InputError(f"mu={mu!r} conflicts with the contact law's mu={law.mu!r}; give the same value")
    batch = law.batch
    t = np.arange(cycles * steps + 1) / steps
    if state_at is not None and not 0 <= int(state_at) < t.size:
        raise InputError(f"state_at must be a step index in [0, {t.size - 1}], got {state_at!r}")
    FN = F0 + np.asarray(dF)[..., None] * np.sin(2 * np.pi * t + np.asarray(alpha)[..., None])
    if FN.ndim > 1:
        FN = np.broadcast_to(FN, batch + t.shape)
    u3 = ua * np.sin(2 * np.pi * t)
    cx = 0.0 if np.all(np.isinf(app.kx)) else 1.0 / np.asarray(app.kx, dtype=float)
    cp = 1.0 / np.asarray(app.k_plates, dtype=float)
    use_bed = bool(app.bedding and np.any(np.asarray(app.mu2) > 0))
    if use_bed:
        Wmax = app.m1 * G_ACC + F0 + np.asarray(dF)
        bed = (bed_law_factory or _mdr_bedding)(app, Wmax, batch)
        bed_state = bed.rest_state()
    st = law.rest_state()
    normal = law.normal_load(np.broadcast_to(FN, batch + t.shape))
    iters = 0
    du_prev = np.zeros(batch)
    out = {k: np.zeros(batch + (t.size,)) for k in ("Fx", "FN", "u1", "u2", "du", "Fbed", "a", "c")}
    first = (cycles - 1) * steps  # the last (stationary) cycle, whose stick radius is reported
    window = []
    M = np.zeros(batch)
    # the same loop compiled (mdr.kernels) for the MDR law with MDR bedding spheres; None: not applicable
    fast = _kernels.apparatus_loop(law, bed if use_bed else None, app, mu, FN, normal["d"], u3, cx, cp, first,
                                   state_at, G_ACC, xtol) if type(law) is MDRContact else None
    if fast is not None:
        out, window, iters = fast
    for k in range(t.size if fast is None else 0):
        if use_bed:
            N1, N2 = app.bedding_loads(FN[..., k], M)
            N_b = np.stack(np.broadcast_arrays(N1, N2), axis=-1)  # batch + (2,)
            if np.any(N_b <= 0):
                raise InputError("the block lifts off a bedding sphere: tangential moment too large for the bedding geometry")
            d_bed = bed.approach(N_b)
        load = {key: v[..., k] for key, v in normal.items()}
        span = (np.asarray(mu) * FN[..., k] + (app.mu2 * (app.m1 * G_ACC + FN[..., k]) if use_bed else 0.0)) \
            * (cp + cx) + 1e-12
        lo = np.broadcast_to(u3[k] - span, batch).astype(float)
        hi = np.broadcast_to(u3[k] + span, batch).astype(float)

        tr = law.prepare(st, **load)
        trb = bed.prepare(bed_state, d=d_bed) if use_bed else None

        def fun(du):
            # -r(du) and its slope: increasing in du
            nonlocal iters
            iters += 1
            F, kF = tr.force(du)
            u2 = du + cx * F
            du2 = 1.0 + cx * kF
            if use_bed:
                Fb2, kb2 = trb.force(np.stack([u2, u2], axis=-1))
                Fb, kb = Fb2[..., 0] + 2.0 * Fb2[..., 1], kb2[..., 0] + 2.0 * kb2[..., 1]
            else:
                Fb, kb = 0.0, 0.0
            return u2 + cp * (F + Fb) - u3[k], du2 + cp * (kF + kb * du2)

        du = solve_increasing(fun, np.zeros(batch), lo, hi, x0=np.broadcast_to(du_prev + u3[k] - u3[max(k - 1, 0)], batch),
                              atol=xtol, xtol=xtol, what="apparatus equilibrium")
        res, st_new = tr.commit(du)
        u2 = du + cx * res.Fx
        if use_bed:
            rb, bst = trb.commit(np.stack([u2, u2], axis=-1))
            Fbed = rb.Fx[..., 0] + 2.0 * rb.Fx[..., 1]
        else:
            bst, Fbed = None, np.zeros_like(u2)
        du_prev = du
        st = st_new
        if state_at is not None and k == int(state_at):
            out["state_at"] = st
        if use_bed:
            bed_state = bst
            # moment about the bedding plane for the next step's sphere loads (A4)
            M = -res.Fx * app.h + (res.Fx + Fbed) * app.h2
        out["Fx"][..., k] = res.Fx
        out["FN"][..., k] = res.FN
        out["u1"][..., k] = cx * res.Fx
        out["u2"][..., k] = u2
        out["du"][..., k] = du
        out["Fbed"][..., k] = Fbed
        out["a"][..., k] = res.a
        out["c"][..., k] = res.c
        if k >= first and res.slack is not None:
            window.append((res.slack, res.slipping))
    cyc = analyse_cycles(out["du"], out["Fx"], steps, mu, F0)
    last_a = out["a"][..., first:]
    if window and len(window) == last_a.shape[-1]:
        out["stick_radius"] = stick_radius(law.stick_nodes, np.stack([w[0] for w in window], axis=-2),
                                           np.stack([w[1] for w in window], axis=-2), last_a, law.stick_onset)
    else:  # a law without slip state per node: smallest instantaneous stick radius of the cycle
        out["stick_radius"] = np.min(out["c"][..., first:], axis=-1)
    out["t"] = t
    out["u3"] = u3
    out["cycles"] = cyc
    out["slip_index"] = slip_index(cyc.dissipation[..., -1], mu, ua, F0)
    out["dissipation"] = cyc.dissipation[..., -1]
    out["evaluations_per_step"] = iters / t.size
    return out


def _mdr_bedding(app: Apparatus, Wmax, batch=()):
    """Bedding: front sphere and one rear sphere (the second rear one is identical);
    Si3N4 half-spheres on the steel block (E = 200 GPa, nu = 0.29)."""
    mat = Materials(app.E_bed, app.nu_bed, 200e9, 0.29)
    shape = tuple(batch) + (2,)
    per_sphere = lambda v: np.array(np.broadcast_to(np.asarray(v, dtype=float)[..., None], shape))  # noqa: E731
    return MDRContact(Sphere(per_sphere(app.R_bed)), mat, per_sphere(app.mu2), F_max=per_sphere(Wmax), n=100)


def apparatus_result(profile, materials, app: Apparatus, mu, F0, dF=0.1, alpha=0.0, ua=150e-9, cycles=4,
                     steps=200, n=400, law=None, state_at=None):
    """One apparatus scene as the JSON dict of ``python -m mdr apparatus`` (keys of ``contact``).

    ``state_at`` (a step index): return ``(result, state of the law after that step)``."""
    from .normal import approach_from_force

    t0 = time.perf_counter()
    mu = nonnegative("mu", mu)
    if law is None:
        law = MDRContact(profile, materials, mu, F_max=F0 + dF, F_min=F0 - dF if dF < F0 else None, n=n)
    out = run_apparatus(law, app, mu, F0, dF, alpha, ua, cycles=cycles, steps=steps, state_at=state_at)
    last = slice(cycles * steps - steps, cycles * steps + 1)
    d0 = float(approach_from_force(profile, materials, F0))
    cyc = out["cycles"]
    delta = float(out["slip_index"])
    result = {
        "contact_radius": float(profile.g_inv(d0)), "indentation": d0, "normal_force": F0,
        "stick_radius": float(out["stick_radius"]),
        "dissipation": float(out["dissipation"]),
        "slip_index": None if not np.isfinite(delta) else delta,
        "dissipation_per_cycle": cyc.dissipation.tolist(),
        "stationary": bool(cyc.last_is_stationary),
        "evaluations_per_step": out["evaluations_per_step"],
        "runtime_s": time.perf_counter() - t0,
        "loop": {k: out[src][last].tolist() for k, src in
                 (("t", "t"), ("du", "du"), ("Fx", "Fx"), ("FN", "FN"), ("u1", "u1"), ("u2", "u2"), ("u3", "u3"))},
        "inputs": {**profile.describe(), **materials.as_dict(), "mu": mu, "F0": F0, "dF": dF, "alpha": alpha,
                   "ua": ua, "cycles": cycles, "steps": steps,
                   "apparatus": {k: (None if isinstance(v, float) and not np.isfinite(v) else v)
                                 for k, v in asdict(app).items()},
                   "k_plates": app.k_plates},
    }
    return result if state_at is None else (result, out["state_at"])
