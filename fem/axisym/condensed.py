"""On-disk cache of the axisymmetric model's condensed mode-1 interface: each body's tangential
flexibility at its contact nodes and the x displacement of its axis probe per unit force there
(``fem.axisym.law.condensed_mode1``), the costliest part of an FE law's set-up after the mesh (0.35 s
of its 0.5 s at a/80, paid again by every scene and ladder level on the same mesh).

A body's condensed interface is a pure function of its mesh, its Young's modulus and Poisson ratio,
the probe's depth and the sparse solver (which changes it at round-off only). Key: SHA-256 of those
inputs and ``CONDENSED_FORMAT_VERSION``; file ``<cache_dir>/condensed-axisym-<key[:24]>.npz`` beside
the meshes, written atomically and verified on read (its stored inputs equal the request, the digest
of its arrays matches), rebuilt and replaced when it fails, never used (``meshes.cache.cached_artifact``,
the meshes' protocol). The bodies' factorisations, which only the field output needs, are not
stored: the law rebuilds them on demand.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

from meshes.cache import cached_artifact, params_key, read_verified, write_verified

#: bump when the condensation or the stored format changes (part of the key)
CONDENSED_FORMAT_VERSION = 1
BODIES = ("indenter", "block")


@dataclass(frozen=True)
class CondensedMode1Params:
    """What the condensed mode-1 interface depends on: the mesh (its cache key), both bodies' moduli
    (Pa) and Poisson ratios, the axis probes' depth (m) and the solver backend (resolved)."""

    mesh_key: str
    E1: float
    nu1: float
    E2: float
    nu2: float
    probe_depth: float
    backend: str

    def resolved(self) -> "CondensedMode1Params":
        return self

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass
class CondensedMode1:
    """Per body: ``C[body]`` its flexibility at the contact nodes (m/N), ``rows[body]`` its axis
    probe's x displacement per unit x force on each of them, ``ndofs[body]`` its mode-1 DOFs."""

    params: CondensedMode1Params
    C: dict
    rows: dict
    ndofs: dict
    key: str = ""
    info: dict = field(default_factory=dict)


def condensed_key(p: CondensedMode1Params) -> str:
    return params_key(p, CONDENSED_FORMAT_VERSION, "condensed-axisym")


def _save(obj: CondensedMode1, path):
    arrs = {}
    for b in BODIES:
        arrs[f"{b}/C"] = np.ascontiguousarray(obj.C[b])
        arrs[f"{b}/rows"] = np.ascontiguousarray(obj.rows[b])
    return write_verified(path, {"params": obj.params.as_dict(), "key": obj.key, "format": CONDENSED_FORMAT_VERSION,
                                 "ndofs": {b: int(obj.ndofs[b]) for b in BODIES},
                                 "info": {k: v for k, v in obj.info.items() if k != "cache"}}, arrs)


def _load(path, expected: CondensedMode1Params | None = None) -> CondensedMode1:
    header, arrs, params = read_verified(path, CONDENSED_FORMAT_VERSION, "condensed interface", CondensedMode1Params,
                                         expected)
    return CondensedMode1(params=params, C={b: arrs[f"{b}/C"] for b in BODIES},
                          rows={b: arrs[f"{b}/rows"] for b in BODIES},
                          ndofs={b: int(header["ndofs"][b]) for b in BODIES}, key=header.get("key", ""),
                          info=header.get("info", {}))


def cached_condensed_mode1(params: CondensedMode1Params, build, cache_dir=None) -> CondensedMode1:
    """The condensed mode-1 interface for ``params`` from the cache if valid, else ``build()`` (a
    ``CondensedMode1`` of those parameters) stored. ``info["cache"]``: hit, miss, rebuilt, unsaved."""
    return cached_artifact(params, cache_dir, False, prefix="condensed-axisym", key_of=condensed_key, load=_load,
                           build=lambda p: build(), save=_save)
