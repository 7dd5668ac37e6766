"""Atomic file output: a reader never sees half a file.

Shared by every package of the project (``common`` is the ground floor of the
layers ``common`` -> ``mdr`` -> ``meshes`` -> ``fem`` -> ``studies`` -> ``validation``, so this is its one home)."""
from __future__ import annotations

import json
import os
import secrets
import sys
import tempfile
from pathlib import Path

import numpy as np

from .errors import InputError


def _to_jsonable(obj):
    if isinstance(obj, dict):
        return {str(k): _to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _to_jsonable(obj.tolist())
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, float) and not np.isfinite(obj):
        return None
    return obj


def _umask() -> int:
    old = os.umask(0o022)
    os.umask(old)
    return old


_MODE = 0o666 & ~_umask()  # the mode open() would give a new file (mkstemp gives 0600)
DIR_MODE = 0o777 & ~_umask()  # the mode mkdir() would give a new directory (mkdtemp gives 0700)


def check_output_path(path, name="output path") -> Path:
    """Raise InputError (naming ``name``) unless ``path`` can be written as a file: it must not
    be a directory, no parent may be an existing file, and its nearest existing folder must take
    a new file (probed by creating and removing one: permissions, a read-only or immutable folder).
    Call it before a costly run."""
    path = Path(path)
    if path.is_dir():
        raise InputError(f"{name} {str(path)!r} is a directory; give a file name")
    _check_folder(path, name, path)
    return path


def check_output_dir(path, name="output folder") -> Path:
    """Raise InputError (naming ``name``) unless ``path`` is, or can be made, a folder that takes new
    files (see :func:`check_output_path`). Call it before a costly run."""
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise InputError(f"{name} {str(path)!r} is a file, not a folder")
    _check_folder(path / ".probe", name, path)
    return path


def _check_folder(path: Path, name: str, shown: Path) -> None:
    """Raise InputError unless a file ``path`` can be created: its nearest existing ancestor is a folder
    that takes a new file (probed), and ``path`` itself, if it exists, is writable; ``shown`` is the
    path the message names."""
    for parent in path.parents:
        if parent.exists():
            if not parent.is_dir():
                raise InputError(f"{name} {str(shown)!r}: {str(parent)!r} is a file, not a directory")
            try:
                fd, probe = tempfile.mkstemp(dir=parent, prefix=".write-probe.")
                os.close(fd)
                os.unlink(probe)
            except OSError as e:
                raise InputError(f"{name} {str(shown)!r} cannot be written: "
                                 f"{str(parent)!r} takes no new file ({e.strerror or e})") from None
            if path.exists() and not os.access(path, os.W_OK):
                raise InputError(f"{name} {str(path)!r} cannot be written (no write permission)")
            return


def write_bytes_atomic(path, data: bytes) -> Path:
    """Write ``data`` to ``path`` through a temporary file and ``os.replace`` (:func:`write_files_atomic`
    of one file; InputError if ``path`` cannot be a file, see :func:`check_output_path`)."""
    write_files_atomic({path: data})
    return Path(path)


def write_files_atomic(files: dict) -> None:
    """Write several files as one: each ``{path: bytes}`` goes to a temporary file beside its target
    first, and only when all are written are they renamed into place (``os.replace``), so a failure
    while writing leaves every previous file as it was."""
    staged = []
    try:
        for path, data in files.items():
            path = check_output_path(path)
            path.parent.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
            staged.append((tmp, path))
            with os.fdopen(fd, "wb") as fh:
                fh.write(data)
                fh.flush()
                os.fsync(fh.fileno())
            os.chmod(tmp, _MODE)
        for tmp, path in staged:
            os.replace(tmp, path)
    except BaseException:
        for tmp, _ in staged:
            try:
                os.unlink(tmp)
            except FileNotFoundError:
                pass
        raise


def json_bytes(obj) -> bytes:
    """The bytes ``write_json`` writes for ``obj``."""
    return (dumps_json(obj) + "\n").encode()


def dumps_json(obj) -> str:
    """JSON text of ``obj`` (numpy arrays and scalars converted, NaN -> null)."""
    return json.dumps(_to_jsonable(obj), indent=1, allow_nan=False)


def write_json(path, obj) -> None:
    """Write ``obj`` as JSON to ``path`` atomically; ``path == '-'`` means stdout."""
    data = json_bytes(obj)
    if str(path) == "-":
        sys.stdout.write(data.decode())
        sys.stdout.flush()
    else:
        write_bytes_atomic(path, data)


def write_vtu_atomic(out, path) -> str:
    """Write the ``meshio.Mesh`` ``out`` to ``path`` (.vtu) atomically: a failed write leaves any
    earlier file intact; returns the path."""
    import meshio

    path = os.fspath(check_output_path(path, "VTU path"))  # InputError if it cannot be a file
    d = os.path.dirname(os.path.abspath(path))
    os.makedirs(d, exist_ok=True)
    # a fresh name opened by meshio with open(): the file gets the umask's mode like every
    # other file the project writes (tempfile.mkstemp would leave it 0600)
    tmp = os.path.join(d, f".{os.path.basename(path)}.{os.getpid()}.{secrets.token_hex(6)}.vtu")
    try:
        meshio.write(tmp, out, file_format="vtu")
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path
