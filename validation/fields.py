"""Offscreen pyvista field plots of an FE scene (no display needed).

One PNG with three panels:

1. the x-z section near the contact (the r-z mesh at theta = 0 and, mirrored, at
   theta = pi), both bodies, coloured by the von Mises stress at the peak of the
   last tangential cycle (modes 0 + 1 superposed, ``fem.output.fretting_fields``,
   from the scene's VTU), on the deformed shape (displacements scaled up, factor
   shown);
2. the contact disk coloured by the contact pressure at F0;
3. the contact disk at the peak of the last tangential cycle: stick (pairs that
   did not slip), slip, and out of contact.

Rendering: ``pyvista.Plotter(off_screen=True)`` on Mesa's EGL
(``VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow``, set here if unset, so VTK
does not try X first). A rendered image with no contrast (a silent failure of
the OpenGL stack) raises :class:`RenderError`, as does a missing system library
(the message names the Debian package).
"""
from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np

from mdr.io import write_bytes_atomic

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

MIN_PIXEL_STD = 2.0  # a rendered panel with contrast has a pixel std of tens (0-255 scale)


class RenderError(RuntimeError):
    """Offscreen rendering failed or produced a blank image."""


def _pyvista():
    try:
        import pyvista as pv
    except (ImportError, OSError) as e:  # pragma: no cover - depends on the machine image
        raise RenderError(f"pyvista/VTK cannot load ({e}); on Debian install libegl1 and libgl1-mesa-dri "
                          f"(apt-get install libegl1 libgl1-mesa-dri)") from e
    pv.OFF_SCREEN = True
    return pv


def image_is_blank(img) -> bool:
    """True if an RGB(A) image has (almost) no contrast: a blank render."""
    rgb = np.asarray(img)[..., :3].astype(float)
    return float(rgb.std()) < MIN_PIXEL_STD


def _disk(pv, r, values, n_theta=96):
    rr = np.asarray(r, float)
    th = np.linspace(0.0, 2.0 * np.pi, n_theta)
    R, TH = np.meshgrid(rr, th, indexing="ij")
    grid = pv.StructuredGrid(R * np.cos(TH), R * np.sin(TH), np.zeros_like(R))
    grid.point_data["v"] = np.tile(np.asarray(values, float), n_theta)  # pyvista orders points r-fastest
    return grid


def section(pv, vtu_path, a):
    """The x-z section (r-z mesh mirrored to -r), clipped near the contact and warped;
    returns (mesh, scale, tangential). With the fields of ``fem.output.fretting_fields``
    (``u_x0``/``mises_x0`` for theta = 0, ``u_x180``/``mises_x180`` for theta = pi) the two
    halves show modes 0 + 1 at the peak of F_x; else the mode-0 ``u``/``mises`` on both."""
    m = pv.read(str(vtu_path))
    tangential = {"u_x0", "u_x180", "mises_x0", "mises_x180"} <= set(m.point_data)
    if not tangential and ("mises" not in m.point_data or "u" not in m.point_data):
        raise RenderError(f"{vtu_path} lacks the 'mises' or 'u' point data")
    mirror = m.copy()
    if tangential:
        m.point_data["u"] = m.point_data["u_x0"]
        m.point_data["mises"] = m.point_data["mises_x0"]
        mirror.point_data["u"] = mirror.point_data["u_x180"]
        mirror.point_data["mises"] = mirror.point_data["mises_x180"]
    mirror.points[:, 0] *= -1.0
    u = mirror.point_data["u"].copy()
    u[:, 0] *= -1.0
    mirror.point_data["u"] = u
    both = m.merge(mirror)
    box = (-3.0 * a, 3.0 * a, -3.0 * a, 2.5 * a, -1.0, 1.0)
    clip = both.clip_box(box, invert=False)
    umax = float(np.max(np.linalg.norm(clip.point_data["u"], axis=1))) if clip.n_points else 0.0
    scale = 0.06 * a / umax if umax > 0 else 1.0
    clip.point_data["mises_MPa"] = clip.point_data["mises"] / 1e6
    warped = clip.warp_by_vector("u", factor=scale)
    return warped, scale, tangential


def field_figure(vtu_path, field: dict, result: dict, png_path, window=(1650, 560)) -> str:
    """Render the three panels to ``png_path`` (atomically); returns the file name."""
    pv = _pyvista()
    a = float(result["fem"]["contact_radius"]) or float(result["errors"]["a_ref"])
    r = np.asarray(field["r"], float)
    p = np.asarray(field["p"], float) / 1e6
    state = np.where(~np.asarray(field["contact"]), 0.0, np.where(np.asarray(field["slip"]), 2.0, 1.0))
    sec, scale, tangential = section(pv, vtu_path, a)
    try:
        pl = pv.Plotter(off_screen=True, shape=(1, 3), window_size=list(window), border=False)
    except Exception as e:  # pragma: no cover - depends on the OpenGL stack
        raise RenderError(f"cannot open an offscreen render window ({e}); on Debian install libegl1 and "
                          f"libgl1-mesa-dri") from e
    try:
        pl.subplot(0, 0)
        pl.add_mesh(sec, scalars="mises_MPa", cmap="viridis", show_edges=False,
                    scalar_bar_args={"title": "von Mises (MPa)", "vertical": False, "fmt": "%.3g"})
        pl.add_text(("x-z section at the peak of F_x (F_x to +x)" if tangential else "r-z section at F0")
                    + f", displacement x{scale:.3g}", font_size=9)
        pl.view_xy()
        pl.camera.zoom(1.25)
        pl.subplot(0, 1)
        pl.add_mesh(_disk(pv, r, p), scalars="v", cmap="plasma",
                    scalar_bar_args={"title": "pressure (MPa)", "vertical": False, "fmt": "%.3g"})
        pl.add_text("contact pressure at F0", font_size=9)
        pl.view_xy()
        pl.subplot(0, 2)
        cmap = ["#d9d9d9", "#1f77b4", "#d62728"]
        pl.add_mesh(_disk(pv, r, state), scalars="v", cmap=cmap, clim=[0, 2], n_colors=3,
                    scalar_bar_args={"title": "out / stick / slip", "vertical": False, "n_labels": 3, "fmt": "%.3g"})
        pl.add_text("stick (blue) / slip (red) at the peak of F_x", font_size=9)
        pl.view_xy()
        img = pl.screenshot(return_img=True)
    finally:
        pl.close()
    if img is None or image_is_blank(img):
        raise RenderError("offscreen rendering produced a blank image (check Mesa's EGL: libegl1, libgl1-mesa-dri)")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    plt.imsave(buf, np.ascontiguousarray(img[..., :3]), format="png")
    write_bytes_atomic(png_path, buf.getvalue())
    return Path(png_path).name
