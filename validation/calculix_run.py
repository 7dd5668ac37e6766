"""Running CalculiX for the witness (``validation.calculix``): finding ``ccx`` (``ccx_executable``,
``require_ccx``) and one run (``run_ccx``): mesh, deck, ``ccx`` in a temporary directory, and the
quantities read back.

Read back (each the same quantity as the project's, never a differently defined one):

- ``approach``: -u_z of the loaded plate (the block bottom is clamped), the project's ``approach``;
- ``probe_approach``: u_z,block(0, -z0) - u_z,indenter(0, +z0) at the resolved ``probe_depth`` z0
  (the meshes have nodes there), the project's ``probe["u_block"] - probe["u_indenter"]``;
- ``indentation``: ``probe_approach`` plus the Boussinesq displacement below the probes
  (``fem.bulk.boussinesq_axis``, the project's formula, here summed over ring forces from the
  indenter's nodal traction below, trapezoidal ring areas, scaled to carry F), the project's
  half-space-comparable ``indentation``;
- ``p0`` and ``contact_radius`` from a least-squares line p^2 = c0 + c1 r^2 through the nodal normal
  contact traction p = -n.sigma.n of CalculiX's (extrapolated, averaged) nodal stresses at the contact
  nodes, for 0.25 a <= r <= 0.7 a (``validation.calculix_results.fit_hertz``), fitted on each body's
  surface and averaged. The same fit is applied to the project's nodal pressure (the project side's
  ``fit_p0``, ``fit_contact_radius``); the project's own extrapolated ``p0`` and edge
  ``contact_radius`` are compared as well (``p0_own``, ``contact_radius_own``).
- CalculiX's own nodal contact pressure (``CPRESS`` of ``*CONTACT FILE``) is read and fitted too
  (``fit_cpress``), but not compared: for these CAX8 faces it is biased. Measured (block and cap
  200 a, a/80): it falls below both the project's pressure and CalculiX's own surface traction
  (which agree to 2e-4) by 0.07 % at 0.2 a growing to 0.6 % at 0.7 a; at a/40 it is negative
  (down to -p0) on the first nodes outside the contact; its fitted radius is 0.5 % below the
  traction's at a/40 and a/80 alike (no convergence). Over the five geometries at the fine level
  (``validation.calculix.LEVELS``) that radius deficit ranges from 0.01 % to 0.6 %, so it depends on
  the mesh.

Assumptions: CalculiX 2.20's 2-degree sector of the axisymmetric elements (``SECTOR``, checked on
every run against the force balance); the deck's units are mm, N, MPa (``validation.calculix_deck.MM``).
"""
from __future__ import annotations

import os
import shutil
import subprocess
import tempfile
import time

import numpy as np

from common.errors import ConvergenceError, positive
from fem.bulk import boussinesq_axis

from .calculix_deck import MM, PENALTY_DEFAULT, write_inp
from .calculix_mesh import H_DEFAULT, Geometry, build_quad_mesh
from .calculix_results import _ring_forces, fit_hertz, parse_dat, parse_frd

#: the executable names tried by :func:`ccx_executable`
CCX_NAMES = ("ccx", "ccx_2.21", "ccx_2.20", "ccx_2.19")
#: how to get it on Debian
INSTALL_HINT = "apt-get install calculix-ccx"
#: CalculiX's axisymmetric elements model a 2-degree sector: printed forces are 1/180 of the total
SECTOR = 180.0
#: default wall-time limit of one ccx run (s)
TIMEOUT_DEFAULT = 900.0


class MissingDependency(RuntimeError):
    """An optional external program is not installed (the message names the install command)."""


def ccx_executable() -> str | None:
    """Path of the CalculiX solver (``$CCX`` if set, else the first of ``CCX_NAMES`` on PATH), or None."""
    env = os.environ.get("CCX")
    if env:
        return shutil.which(env) or (env if os.path.isfile(env) and os.access(env, os.X_OK) else None)
    for name in CCX_NAMES:
        path = shutil.which(name)
        if path:
            return path
    return None


def require_ccx() -> str:
    """The ccx path, or :class:`MissingDependency` naming the install command."""
    path = ccx_executable()
    if path is None:
        raise MissingDependency(f"CalculiX (ccx) not found on PATH: install it with `{INSTALL_HINT}` "
                                "(Debian package calculix-ccx) or set $CCX to the executable")
    return path


# --------------------------------------------------------------------------- runs


def run_ccx(geometry: Geometry, h: float = H_DEFAULT, *, penalty: float = PENALTY_DEFAULT,
            timeout: float = TIMEOUT_DEFAULT, threads: int = 1, workdir=None, keep: bool = False) -> dict:
    """Mesh, write, run ``ccx`` (in a temporary directory, ``timeout`` s of wall time) and read back
    (module docstring): ``approach``, ``probe_approach``, ``indentation``, ``p0``,
    ``contact_radius``, the pressure profile, checks and runtimes (s)."""
    exe = require_ccx()
    positive("timeout", timeout)
    t0 = time.perf_counter()
    p = geometry.params(h)
    mesh = build_quad_mesh(p)
    t1 = time.perf_counter()
    tmp = tempfile.mkdtemp(prefix="ccx-witness-", dir=workdir)
    try:
        write_inp(os.path.join(tmp, "witness.inp"), geometry, h, penalty=penalty, mesh=mesh)
        env = dict(os.environ, OMP_NUM_THREADS=str(threads), CCX_NPROC_EQUATION_SOLVER=str(threads),
                   CCX_NPROC_RESULTS=str(threads), CCX_NPROC_STIFFNESS=str(threads))
        t2 = time.perf_counter()
        try:
            proc = subprocess.run([exe, "-i", "witness"], cwd=tmp, env=env, capture_output=True, text=True,
                                  timeout=timeout)
        except subprocess.TimeoutExpired:
            raise ConvergenceError(f"ccx did not finish within {timeout:g} s ({geometry.name}, h = a/{1 / h:.3g})") \
                from None
        t3 = time.perf_counter()
        log = proc.stdout + proc.stderr
        if proc.returncode != 0 or "*ERROR" in log:
            err = [ln.strip() for ln in log.splitlines() if "ERROR" in ln][:3]
            raise ConvergenceError(f"ccx failed (exit {proc.returncode}): {' | '.join(err) or log[-300:]}")
        with open(os.path.join(tmp, "witness.dat")) as f:
            dat = parse_dat(f.read())
        with open(os.path.join(tmp, "witness.frd")) as f:
            frd = f.read()
        stress, cont = parse_frd(frd, "STRESS"), parse_frd(frd, "CONTACT")
    finally:
        if not keep:
            shutil.rmtree(tmp, ignore_errors=True)
    R = geometry.R
    a_ref = geometry.a_ref
    prof = {}
    for body, name in (("indenter", "ind_contact"), ("block", "blk_contact")):
        ns = sorted(mesh.sets[name], key=lambda n: mesh.nodes[n][0])
        r = np.array([mesh.nodes[n][0] for n in ns])
        z = np.array([mesh.nodes[n][1] for n in ns])
        # outward unit normal: the sphere's (centre (0, R)) for the indenter, +z for the block
        nr, nz = (r / R, (z - R) / R) if body == "indenter" else (0.0 * r, 1.0 + 0.0 * r)
        s_ = np.array([stress[n] for n in ns]) * MM**-2  # MPa -> Pa: SXX (r), SYY (z), SZZ (hoop), SXY (rz)
        p_n = -(nr * nr * s_[:, 0] + nz * nz * s_[:, 1] + 2.0 * nr * nz * s_[:, 3])
        prof[body] = (r, p_n)
    fits = {b: fit_hertz(r_, p_, a_ref) for b, (r_, p_) in prof.items()}
    fit = {"p0": 0.5 * (fits["indenter"]["p0"] + fits["block"]["p0"]),
           "a": 0.5 * (fits["indenter"]["a"] + fits["block"]["a"])}
    slave = sorted((n for n in mesh.sets["ind_contact"] if n in cont), key=lambda n: mesh.nodes[n][0])
    r_c = np.array([mesh.nodes[n][0] for n in slave])
    cpress = np.array([cont[n][3] for n in slave]) * MM**-2
    fit_cpress = fit_hertz(r_c, cpress, a_ref)
    r, pres = prof["indenter"]
    F = geometry.F
    mat = geometry.materials
    u_ind, u_blk = (MM * dat["u_probe"][mesh.probe[b]] for b in ("indenter", "block"))  # mm -> m
    lam = _ring_forces(r, pres)
    force_p = float(lam.sum())
    lam_F = lam * (F / force_p)  # the Boussinesq weights carry F (pressure near the axis is unreliable)
    z0 = p.probe_depth
    w = boussinesq_axis(lam_F, r, z0, mat.E1, mat.nu1) + boussinesq_axis(lam_F, r, z0, mat.E2, mat.nu2)
    approach = -MM * dat["u_load"]
    checks = {"reaction": SECTOR * dat["rf_bottom"] / F,
              "contact_force": (-SECTOR * dat["contact_normal_force"] / F
                                if dat["contact_normal_force"] is not None else None),
              "pressure_force": force_p / F}
    for k in ("reaction", "contact_force"):
        if checks[k] is not None and abs(checks[k] - 1.0) > 1e-3:
            raise ConvergenceError(f"ccx {k} x {SECTOR:g} is {checks[k]:.6g} F, not F: the 2-degree sector "
                                   "scaling of this CalculiX version differs from the one assumed")
    K = penalty * min(mat.E1, mat.E2) / mesh.h
    return {"approach": approach, "probe_approach": u_blk - u_ind, "indentation": u_blk - u_ind + w,
            "p0": fit["p0"], "contact_radius": fit["a"], "fit": fits, "fit_cpress": fit_cpress,
            "pressure": {"r": r.tolist(), "p": pres.tolist(), "cpress": cpress.tolist()},
            "penalty_slope": K, "penalty_error": fit["p0"] / K / approach, "checks": checks,
            "probe_depth": z0, "nodes": len(mesh.nodes), "elements": {"CAX8": mesh.n_quads, "CAX6": mesh.n_tris},
            "node_spacing": 0.5 * mesh.h, "h": h,
            "runtime_s": {"mesh": t1 - t0, "ccx": t3 - t2, "total": t3 - t0}}
