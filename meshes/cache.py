"""On-disk cache of meshes: a mesh is a pure function of its parameters.

Key: SHA-256 of the canonical JSON of the *resolved* parameters, the mesh
format version and the gmsh major.minor version (a different mesher may place
nodes differently). File: ``<cache_dir>/axisym-<key[:24]>.npz`` holding the
vertex and triangle arrays and the named boundary facets of each body, plus a
JSON header with the parameters and a SHA-256 digest of the arrays. It is
written atomically (temporary file + rename) and verified on read (header
parameters equal the request, digest matches); a file that fails the check is
rebuilt and replaced, never used.

Cache directory: argument ``cache_dir``, else the environment variable
``FRETTING_MESH_CACHE``, else ``~/.cache/fretting-meshes``.
"""
from __future__ import annotations

import hashlib
import io
import json
import os
import warnings
from pathlib import Path

import numpy as np

from common.errors import InputError
from common.io import write_bytes_atomic

from .axisym import BODIES, MESH_FORMAT_VERSION, AxisymMesh, AxisymMeshParams, build_mesh


def default_cache_dir() -> Path:
    env = os.environ.get("FRETTING_MESH_CACHE")
    return Path(env) if env else Path.home() / ".cache" / "fretting-meshes"


def _gmsh_version() -> str:
    try:
        import gmsh

        return ".".join(gmsh.__version__.split(".")[:2])
    except Exception:  # pragma: no cover
        return "unknown"


def mesh_key(params: AxisymMeshParams) -> str:
    """Hash of the resolved parameters (hex SHA-256)."""
    p = params.resolved()
    blob = json.dumps({"params": p.as_dict(), "format": MESH_FORMAT_VERSION, "gmsh": _gmsh_version()},
                      sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(blob.encode()).hexdigest()


def _arrays(amesh: AxisymMesh) -> dict:
    arrs = {}
    for b in BODIES:
        m = amesh.bodies[b]
        arrs[f"{b}/p"] = np.ascontiguousarray(m.p, dtype=np.float64)
        arrs[f"{b}/t"] = np.ascontiguousarray(m.t, dtype=np.int32)
        for name, facets in sorted((m.boundaries or {}).items()):
            arrs[f"{b}/boundary/{name}"] = np.ascontiguousarray(np.asarray(facets), dtype=np.int32)
    return arrs


def _digest(arrs: dict) -> str:
    h = hashlib.sha256()
    for k in sorted(arrs):
        a = arrs[k]
        h.update(k.encode())
        h.update(str(a.dtype).encode())
        h.update(str(a.shape).encode())
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


def params_key(params, fmt: int, kind: str) -> str:
    """The cache key of an artifact of ``kind`` (hex SHA-256) from its resolved parameters (a dataclass
    with ``as_dict``) and its format version ``fmt``: the condensed interfaces' key."""
    blob = json.dumps({"params": params.as_dict(), "format": fmt, "kind": kind}, sort_keys=True,
                      separators=(",", ":"))
    return hashlib.sha256(blob.encode()).hexdigest()


def write_verified(path, header: dict, arrs: dict) -> Path:
    """Write ``arrs`` and a JSON ``header`` (to which the arrays' digest is added) atomically to
    ``path`` (.npz): the one format of every cached artifact, read back by :func:`read_verified`."""
    header = dict(header, digest=_digest(arrs))
    buf = io.BytesIO()
    np.savez(buf, __header__=np.frombuffer(json.dumps(header, sort_keys=True).encode(), dtype=np.uint8),
             **arrs)
    return write_bytes_atomic(path, buf.getvalue())


def read_verified(path, fmt: int, what: str, params_cls, expected=None) -> tuple:
    """Read a file of :func:`write_verified` and verify it: its format ``fmt``, the digest of its
    arrays, its stored parameters (``params_cls(**header["params"])``) equal to ``expected``
    (resolved) if given. Returns ``(header, arrays, params)``; :class:`CacheError` naming ``what``
    if anything is off."""
    try:
        with np.load(path, allow_pickle=False) as z:
            header = json.loads(bytes(z["__header__"]).decode())
            arrs = {k: z[k] for k in z.files if k != "__header__"}
    except Exception as exc:
        raise CacheError(f"unreadable {what} cache file {path}: {exc}") from exc
    if not isinstance(header, dict):
        raise CacheError(f"{path}: header is not a JSON object (corrupt file)")
    if header.get("format") != fmt:
        raise CacheError(f"{path}: not a {what} of format {fmt} (format {header.get('format')})")
    if _digest(arrs) != header.get("digest"):
        raise CacheError(f"{path}: array digest mismatch (corrupt file)")
    try:
        params = params_cls(**header["params"])
    except Exception as exc:  # missing, unknown or invalid stored parameters
        raise CacheError(f"{path}: stored parameters unreadable ({exc})") from exc
    if expected is not None and params.as_dict() != expected.resolved().as_dict():
        raise CacheError(f"{path}: stored parameters differ from the request")
    return header, arrs, params


def save_mesh(amesh: AxisymMesh, path) -> Path:
    """Write ``amesh`` atomically to ``path`` (.npz with a verified header)."""
    return write_verified(path, {"params": amesh.params.as_dict(), "key": amesh.key, "format": MESH_FORMAT_VERSION,
                                 "info": amesh.info}, _arrays(amesh))


class CacheError(RuntimeError):
    """A cached mesh file failed verification."""


def load_mesh(path, expected: AxisymMeshParams | None = None) -> AxisymMesh:
    """Read and verify a mesh file; raise :class:`CacheError` if anything is off."""
    from skfem import MeshTri1

    header, arrs, params = read_verified(path, MESH_FORMAT_VERSION, "mesh", AxisymMeshParams, expected)
    bodies = {}
    for b in BODIES:
        m = MeshTri1(arrs[f"{b}/p"], arrs[f"{b}/t"])
        bnd = {k.split("/", 2)[2]: v for k, v in arrs.items() if k.startswith(f"{b}/boundary/")}
        bodies[b] = m.with_boundaries(bnd)
    return AxisymMesh(params=params, bodies=bodies, key=header.get("key", ""), info=header.get("info", {}))


def cached_mesh(params: AxisymMeshParams, cache_dir=None, *, refresh: bool = False) -> AxisymMesh:
    """The mesh for ``params``: from the cache if present and valid, else built and stored.

    ``info["cache"]`` tells what happened: ``"hit"``, ``"miss"``, ``"rebuilt"``
    (a stored file failed verification) or ``"unsaved"`` (built, but the cache
    directory could not be written: warned, the mesh is still returned).
    ``cache_dir`` naming an existing file is an InputError.
    """
    return cached_artifact(params, cache_dir, refresh, prefix="axisym", key_of=mesh_key, load=load_mesh,
                           build=build_mesh, save=save_mesh)


def cached_artifact(params, cache_dir, refresh, *, prefix, key_of, load, build, save):
    """The cache protocol every mesh kind shares: the artifact for ``params`` (resolved) from
    ``<cache_dir>/<prefix>-<key>.npz`` if present and verified (``load(path, expected=p)``
    raising CacheError otherwise), else ``build(p)`` stored by ``save(obj, path)``; an
    unwritable cache is warned, not fatal. ``obj.info["cache"]``: hit, miss, rebuilt, unsaved."""
    import time

    p = params.resolved()
    key = key_of(p)
    d = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    if d.exists() and not d.is_dir():
        raise InputError(f"cache_dir must be a directory (mesh cache), got the file {str(d)!r}")
    path = d / f"{prefix}-{key[:24]}.npz"
    status = "miss"
    if path.exists() and not refresh:
        try:
            obj = load(path, expected=p)
            if obj.key == key:
                obj.info = dict(obj.info, cache="hit", path=str(path))
                return obj
            status = "rebuilt"
        except CacheError as exc:
            warnings.warn(f"rebuilding mesh: {exc}", RuntimeWarning, stacklevel=3)
            status = "rebuilt"
    t0 = time.perf_counter()
    obj = build(p)
    obj.key = key
    obj.info = {"build_s": time.perf_counter() - t0}
    try:
        save(obj, path)
    except OSError as exc:  # the cache is an optimisation: an unwritable one costs time, not the answer
        warnings.warn(f"mesh cache not written ({exc}); the mesh will be rebuilt next time",
                      RuntimeWarning, stacklevel=3)
        status = "unsaved"
    obj.info = dict(obj.info, cache=status, path=str(path))
    return obj
