"""On-disk cache of a 3D body's condensed interface: the weighted flexibility of the contact
vertices and their response at the axis probe (``fem.solid3d.interface.mortar_flexibility``,
``probe_response``), the costly part of a 3D set-up (on a ring mesh of 807 contact vertices, 25 s
of its 35 s; the factorisation 3 s).

A body's condensed interface is a pure function of its mesh, its Poisson ratio, the probe's
depth and the sparse solver (which changes it at round-off only); it scales with 1/E at a fixed
Poisson ratio, so it is stored for E = 1 Pa and every Young's modulus of that ratio shares one
file. Key: SHA-256 of those inputs and ``CONDENSED_FORMAT_VERSION``; file
``<cache_dir>/condensed3d-<key[:24]>.npz`` beside the meshes, written atomically and verified on
read (its stored inputs equal the request, the digest of its arrays matches), rebuilt and
replaced when it fails, never used (``meshes.cache.cached_artifact``, the meshes' protocol).
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field

import numpy as np

from meshes.cache import cached_artifact, params_key, read_verified, write_verified

#: bump when the condensation or the stored format changes (part of the key)
CONDENSED_FORMAT_VERSION = 1


@dataclass(frozen=True)
class CondensedParams:
    """What a body's condensed interface depends on: the mesh (its cache key), the Poisson ratio,
    the axis probe's depth (m, below the contact plane) and the solver backend (resolved)."""

    mesh_key: str
    nu: float
    probe_depth: float
    backend: str

    def resolved(self) -> "CondensedParams":
        return self

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass
class CondensedBody:
    """``D`` (3 n, 3 n) and ``R`` (3, 3, n) of a body of E = 1 Pa (divide by E), its DOF count."""

    params: CondensedParams
    D: np.ndarray
    R: np.ndarray
    ndofs: int
    key: str = ""
    info: dict = field(default_factory=dict)


def condensed_key(p: CondensedParams) -> str:
    return params_key(p, CONDENSED_FORMAT_VERSION, "condensed3d")


def _save(body: CondensedBody, path):
    return write_verified(path, {"params": body.params.as_dict(), "key": body.key, "format": CONDENSED_FORMAT_VERSION,
                                 "ndofs": int(body.ndofs), "info": {k: v for k, v in body.info.items() if k != "cache"}},
                          {"D": np.ascontiguousarray(body.D), "R": np.ascontiguousarray(body.R)})


def _load(path, expected: CondensedParams | None = None) -> CondensedBody:
    header, arrs, params = read_verified(path, CONDENSED_FORMAT_VERSION, "condensed interface", CondensedParams,
                                         expected)
    return CondensedBody(params=params, D=arrs["D"], R=arrs["R"], ndofs=int(header["ndofs"]),
                         key=header.get("key", ""), info=header.get("info", {}))


def condensed_body(hmesh, mi, nu: float, probe_depth: float, *, backend=None, cache_dir=None,
                   timings: dict | None = None) -> CondensedBody:
    """The condensed interface of a body of Poisson ratio ``nu`` on the 3D mesh ``hmesh``
    (``meshes.half3d.Half3DMesh``; ``mi`` its ``fem.solid3d.interface.MortarInterface``), for E = 1 Pa,
    from the cache if valid, else assembled, factorised and condensed
    (``fem.solid3d.interface.mortar_flexibility``, ``probe_response``) and stored. ``timings`` (a dict)
    gains the seconds of the ``assembly``, ``factorisation`` and ``condensation`` actually run (0
    on a cache hit). ``info["cache"]``: hit, miss, rebuilt, unsaved."""
    from fem.solid3d.elastic import stiffness3d
    from fem.solid3d.interface import mortar_flexibility, probe_response
    from fem.solvers import resolve_backend

    parts = {"assembly": 0.0, "factorisation": 0.0, "condensation": 0.0}
    p = CondensedParams(mesh_key=hmesh.key, nu=float(nu), probe_depth=float(probe_depth),
                        backend=resolve_backend(backend))

    def build(p):
        mesh = hmesh.mesh
        t0 = time.perf_counter()
        K, basis = stiffness3d(mesh, 1.0, p.nu)
        parts["assembly"] += time.perf_counter() - t0
        D, _, fac = mortar_flexibility(K, basis, mesh, mi, backend=p.backend, timings=parts)
        R = probe_response(fac, basis, mesh, mi, (0.0, 0.0, -p.probe_depth))
        return CondensedBody(params=p, D=D, R=R, ndofs=int(K.shape[0]))

    body = cached_artifact(p, cache_dir, False, prefix="condensed3d", key_of=condensed_key, load=_load,
                           build=build, save=_save)
    if timings is not None:
        for k, v in parts.items():
            timings[k] = timings.get(k, 0.0) + v
    return body
