"""Meshes: geometry and boundary tags, the line3 boundary handling, cache, VTU export."""
from __future__ import annotations

import math
import os

import meshio
import numpy as np
import pytest

from common.errors import InputError
from meshes import AxisymMeshParams, build_mesh, cached_mesh, export_vtu, from_meshio, generate_meshio, load_mesh
from meshes.cache import CacheError, mesh_key

A = 27.4e-6
R = 6e-3


def coarse(profile="sphere", b=0.0, **kw):
    kw.setdefault("h_contact", 0.1)
    kw.setdefault("block_radius", 60 * A)
    kw.setdefault("growth", 0.5)
    return AxisymMeshParams(profile, None if profile == "flat" else R, b, A, **kw)


@pytest.fixture(scope="module")
def sphere_meshio():
    return generate_meshio(coarse())


def facet_mid(mesh, name):
    f = mesh.boundaries[name]
    return 0.5 * (mesh.p[:, mesh.facets[0, f]] + mesh.p[:, mesh.facets[1, f]])


def test_skfem_reader_drops_line3_boundaries_and_ours_keeps_them(sphere_meshio):
    """gmsh order-2 meshes carry boundaries as line3; scikit-fem's reader ignores them."""
    import skfem.io.meshio as skio

    m = sphere_meshio
    assert "line3" in m.cells_dict and "triangle6" in m.cells_dict
    plain = skio.from_meshio(m)
    plain_names = set(plain.boundaries or {})
    assert not any(n.endswith(":contact") for n in plain_names)  # the problem this module solves
    body = from_meshio(m, "block")
    n_line3 = {k: len(v["line3"]) for k, v in m.cell_sets_dict.items() if k.startswith("block:") and "line3" in v}
    for name, count in n_line3.items():
        assert len(body.boundaries[name.split(":")[1]]) == count


@pytest.mark.parametrize("profile,b", [("sphere", 0.0), ("truncated", 20e-6), ("flat", 25e-6)])
def test_boundary_tags_lie_on_their_geometry(profile, b):
    p = coarse(profile, b).resolved()
    am = build_mesh(p)
    ind, blk = am.indenter, am.block
    L, H, H1, rc = p.block_radius, p.block_height, p.indenter_height, p.r_contact
    tol = 1e-9 * L
    assert np.allclose(facet_mid(ind, "axis")[0], 0.0, atol=tol)
    assert np.allclose(facet_mid(blk, "axis")[0], 0.0, atol=tol)
    assert np.allclose(facet_mid(ind, "top")[1], H1, atol=tol)
    assert np.allclose(facet_mid(blk, "bottom")[1], -H, atol=tol)
    cb = facet_mid(blk, "contact")
    assert np.allclose(cb[1], 0.0, atol=tol) and cb[0].max() <= rc + tol
    ci = facet_mid(ind, "contact")
    assert ci[0].max() <= rc + tol
    # the contact segments are uniformly meshed with h_min and cover [0, rc]
    for mesh in (ind, blk):
        f = mesh.boundaries["contact"]
        ends = mesh.p[:, mesh.facets[:, f]]
        lengths = np.hypot(*(ends[:, 1] - ends[:, 0]))
        assert lengths.max() <= p.h_min * 1.02
        assert np.isclose(lengths.sum(), rc, rtol=1e-3)
    # node at the kink / punch edge on both bodies
    if b > 0:
        for mesh in (ind, blk):
            assert np.min(np.abs(mesh.p[0] - b) + np.abs(mesh.p[1])) < tol
    # indenter surface is the exact cap (sphere/truncated) or flat
    if profile != "flat":
        zc = math.sqrt(R**2 - b**2)
        r, z = ind.p[:, np.unique(ind.facets[:, ind.boundaries["contact"]])]
        out = r > b
        assert np.allclose(np.hypot(r[out], z[out] - zc), R, rtol=1e-12)
    # grading: coarse far away, fine near the contact
    for mesh in (ind, blk):
        e = mesh.p[:, mesh.facets]
        lengths = np.hypot(*(e[:, 1] - e[:, 0]))
        assert lengths.max() > 20 * p.h_min
    # the areas of the section are right (no missing or overlapping elements)
    assert np.isclose(blk_area(blk), L * H, rtol=1e-9)


def blk_area(mesh):
    p, t = mesh.p, mesh.t
    a = p[:, t[1]] - p[:, t[0]]
    b = p[:, t[2]] - p[:, t[0]]
    return float(np.sum(0.5 * np.abs(a[0] * b[1] - a[1] * b[0])))


def test_cache_hit_verify_and_rebuild(tmp_path):
    p = coarse()
    m1 = cached_mesh(p, tmp_path)
    assert m1.info["cache"] == "miss"
    files = list(tmp_path.glob("axisym-*.npz"))
    assert len(files) == 1 and not list(tmp_path.glob(".*tmp"))
    m2 = cached_mesh(p, tmp_path)
    assert m2.info["cache"] == "hit"
    for b in ("indenter", "block"):
        assert np.array_equal(m1.bodies[b].p, m2.bodies[b].p)
        assert np.array_equal(m1.bodies[b].t, m2.bodies[b].t)
        for k, v in m1.bodies[b].boundaries.items():
            assert np.array_equal(np.asarray(v), np.asarray(m2.bodies[b].boundaries[k]))
    # a different parameter is a different key
    assert mesh_key(coarse(h_contact=0.05)) != mesh_key(p)
    # equal after default resolution -> same key
    assert mesh_key(p) == mesh_key(p.resolved())
    # corrupt the file: verification fails, the cache rebuilds it
    path = files[0]
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))
    with pytest.raises(CacheError):
        load_mesh(path, expected=p)
    with pytest.warns(RuntimeWarning):
        m3 = cached_mesh(p, tmp_path)
    assert m3.info["cache"] == "rebuilt"
    assert load_mesh(path, expected=p).key == m1.key


def test_cache_dir_from_environment(tmp_path, monkeypatch):
    from meshes.cache import default_cache_dir

    monkeypatch.setenv("FRETTING_MESH_CACHE", str(tmp_path / "c"))
    assert default_cache_dir() == tmp_path / "c"


#: a worker process: build the mesh of coarse() into the cache dir argv[1], but write it only
#: when both workers have built theirs (ready files), so the two writers of one file race
_RACER = """
import sys, time
from pathlib import Path
import meshes.cache as c
from meshes import AxisymMeshParams
d, me, other = Path(sys.argv[1]), sys.argv[2], sys.argv[3]
save = c.save_mesh
def racing_save(obj, path):
    (d.parent / f"ready-{me}").touch()
    t0 = time.monotonic()
    while not (d.parent / f"ready-{other}").exists():
        assert time.monotonic() - t0 < 120, "the other worker never built its mesh"
        time.sleep(0.005)
    return save(obj, path)
c.save_mesh = racing_save
m = c.cached_mesh(AxisymMeshParams("sphere", %r, 0.0, %r, h_contact=0.1, block_radius=%r, growth=0.5), d)
print(m.info["cache"], c._digest(c._arrays(m)))
"""


def test_two_workers_building_the_same_mesh_at_once(tmp_path):
    """Two processes (as two Dask workers on a shared FRETTING_MESH_CACHE) miss the same
    empty cache and write the same file at the same moment: both get the mesh, the stored
    file is complete and verifies, and it equals what each built (atomic replace: the last
    writer wins with identical bytes, no reader sees half a file)."""
    import subprocess
    import sys
    from pathlib import Path as P

    d = tmp_path / "cache"
    code = _RACER % (R, A, 60 * A)
    env = dict(os.environ, PYTHONPATH=str(P(__file__).resolve().parent.parent))
    procs = [subprocess.Popen([sys.executable, "-c", code, str(d), me, other], stdout=subprocess.PIPE, text=True,
                              env=env) for me, other in (("a", "b"), ("b", "a"))]
    outs = [p.communicate(timeout=300)[0].split() for p in procs]
    assert [p.returncode for p in procs] == [0, 0]
    assert [o[0] for o in outs] == ["miss", "miss"]  # both built and wrote it
    assert outs[0][1] == outs[1][1]  # the same mesh
    files = list(d.iterdir())
    assert len(files) == 1 and files[0].suffix == ".npz"  # no temporary file left
    from meshes.cache import _arrays, _digest

    assert _digest(_arrays(load_mesh(files[0], expected=coarse()))) == outs[0][1]
    assert cached_mesh(coarse(), d).info["cache"] == "hit"


def test_vtu_export_roundtrip(tmp_path):
    am = build_mesh(coarse())
    from skfem import Basis, ElementTriP2

    data = {}
    for b in ("indenter", "block"):
        xy = Basis(am.bodies[b], ElementTriP2(), intorder=1).doflocs
        data[b] = xy[0] ** 2 + xy[1]
    path = export_vtu(am, tmp_path / "m.vtu", point_data={"f": data})
    m = meshio.read(path)
    assert "triangle6" in m.cells_dict
    assert np.allclose(m.point_data["f"], m.points[:, 0] ** 2 + m.points[:, 1])
    ntri = sum(am.bodies[b].t.shape[1] for b in ("indenter", "block"))
    assert len(m.cells_dict["triangle6"]) == ntri
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".")]


@pytest.mark.parametrize("umask,mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
def test_vtu_export_follows_the_umask(tmp_path, umask, mode):
    """fields.vtu had mode 0600 (tempfile.mkstemp) while every other output followed the
    umask; a VTU gets the mode open() gives, also in a parent directory it creates."""
    am = build_mesh(coarse())
    old = os.umask(umask)
    try:
        path = export_vtu(am, tmp_path / "new" / "dir" / "fields.vtu")
    finally:
        os.umask(old)
    assert os.stat(path).st_mode & 0o777 == mode
    assert not [f for f in os.listdir(tmp_path / "new" / "dir") if f.startswith(".")]


def test_vtu_export_names_a_bad_path(tmp_path):
    am = build_mesh(coarse())
    (tmp_path / "file").write_text("x")
    for bad in (tmp_path, tmp_path / "file" / "f.vtu"):
        with pytest.raises(InputError, match="VTU path"):
            export_vtu(am, bad)


@pytest.mark.parametrize("kw,name", [
    (dict(profile="truncated", b=R), "b"),
    (dict(profile="sphere", b=0.0, h_contact=0.5), "h_contact"),
    (dict(profile="sphere", b=0.0, h_contact=-0.01), "h_contact"),
    (dict(profile="sphere", b=0.0, block_radius=-1.0), "block_radius"),
    (dict(profile="sphere", b=0.0, block_radius=A), "block_radius"),
    (dict(profile="flat", b=0.0), "b"),
    (dict(profile="cone", b=0.0), "profile"),
])
def test_bad_mesh_parameters(kw, name):
    profile = kw.pop("profile")
    b = kw.pop("b")
    with pytest.raises(InputError, match=name):
        AxisymMeshParams(profile, R, b, A, **kw).resolved()
