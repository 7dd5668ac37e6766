"""Offscreen pyvista field plots of an FE scene (no display needed).

One PNG with three panels (pyvista renders each panel without labels; matplotlib
composes them with axes in um, colour bars, titles and a stick/slip legend):

1. the x-z section near the contact (the r-z mesh at theta = 0 and, mirrored, at
   theta = pi), both bodies, coloured by the von Mises stress at the peak of the
   last tangential cycle (modes 0 + 1 superposed, ``fem.axisym.output.fretting_fields``,
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

from common.io import write_bytes_atomic

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
    returns (mesh, scale, tangential, the undeformed mesh's edges). With the fields of
    ``fem.axisym.output.fretting_fields``
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
    if clip.n_points:
        # the picture moved as one rigid body so that the block's surface point on the axis stays put:
        # near the contact the bodies' rigid shifts (the plates' ~100 nm) would hide the dimple and
        # the shear, which are what the window shows; a common translation changes no shape
        pts = np.asarray(clip.points)
        blk = np.flatnonzero(pts[:, 1] <= 0.0)
        k = blk[np.argmin(np.hypot(pts[blk, 0], pts[blk, 1]))] if blk.size else 0
        clip.point_data["u"] = clip.point_data["u"] - clip.point_data["u"][k]
    umax = float(np.max(np.linalg.norm(clip.point_data["u"], axis=1))) if clip.n_points else 0.0
    # the largest displacement drawn as a quarter of the contact radius: the dimple and the shear of
    # ~100 nm show on a window of a few contact radii (at 0.06 a they were below a pixel)
    scale = 0.25 * a / umax if umax > 0 else 1.0
    clip.point_data["mises_MPa"] = clip.point_data["mises"] / 1e6
    warped = clip.warp_by_vector("u", factor=scale)
    # the undeformed shape's edges (the bodies' faces and the window's cut), drawn over the deformed one
    outline = clip.extract_feature_edges(boundary_edges=True, feature_edges=False, manifold_edges=False,
                                         non_manifold_edges=False) if clip.n_points else None
    return warped, scale, tangential, outline


def _render(pv, meshes, centre, half_h, size):
    """Render ``meshes`` ([(mesh, add_mesh kwargs)]) offscreen in parallel projection, the view
    centred on ``centre`` (x, y) with ``half_h`` world units from the centre to the top edge;
    returns the RGB image and its extent (xmin, xmax, ymin, ymax) in world units, so a plot
    can put length axes on it."""
    try:
        pl = pv.Plotter(off_screen=True, window_size=list(size), border=False)
    except Exception as e:  # pragma: no cover - depends on the OpenGL stack
        raise RenderError(f"cannot open an offscreen render window ({e}); on Debian install libegl1 and "
                          f"libgl1-mesa-dri") from e
    try:
        pl.set_background("white")
        for mesh, kw in meshes:
            pl.add_mesh(mesh, show_scalar_bar=False, lighting=False, **kw)  # colours = the bar's
        cx, cy = centre
        pl.camera_position = [(cx, cy, 10.0 * half_h), (cx, cy, 0.0), (0.0, 1.0, 0.0)]
        pl.enable_parallel_projection()
        pl.camera.parallel_scale = half_h
        img = pl.screenshot(return_img=True)
    finally:
        pl.close()
    if img is None or image_is_blank(img):
        raise RenderError("offscreen rendering produced a blank image (check Mesa's EGL: libegl1, libgl1-mesa-dri)")
    half_w = half_h * size[0] / size[1]
    return np.ascontiguousarray(img[..., :3]), (cx - half_w, cx + half_w, cy - half_h, cy + half_h)


def _colorbar(fig, ax, cmap, vmin, vmax, label, extend="neither", ticklabels=None):
    """A horizontal colour bar under ``ax``; ``ticklabels``: one label per colour of a
    categorical map (ticks at the colours' centres)."""
    import matplotlib as mpl

    if ticklabels is None:
        sm = mpl.cm.ScalarMappable(norm=mpl.colors.Normalize(vmin, vmax), cmap=cmap)
    else:
        n = len(ticklabels)
        sm = mpl.cm.ScalarMappable(norm=mpl.colors.BoundaryNorm(np.arange(n + 1) - 0.5, n),
                                   cmap=mpl.colors.ListedColormap(cmap))
    cb = fig.colorbar(sm, ax=ax, orientation="horizontal", label=label, shrink=0.85, pad=0.16, extend=extend)
    if ticklabels is not None:
        cb.set_ticks(np.arange(len(ticklabels)), labels=list(ticklabels))


def field_figure(vtu_path, field: dict, result: dict, png_path) -> str:
    """Render the three panels to ``png_path`` (atomically); returns the file name.

    Each panel is rendered by pyvista without labels (parallel projection, so a pixel is a
    known length) and composed with matplotlib: axes in um (the length scale), colour bars
    and titles laid out by matplotlib so no label sits on another."""
    pv = _pyvista()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    a = float(result["fem"]["contact_radius"]) or float(result["errors"]["a_ref"])
    r = np.asarray(field["r"], float)
    p = np.asarray(field["p"], float) / 1e6
    state = np.where(~np.asarray(field["contact"]), 0.0, np.where(np.asarray(field["slip"]), 2.0, 1.0))
    if r.size and r[0] > 0.0:  # the first pair sits off the axis: close the disk (no hole at its centre)
        r, p, state = np.r_[0.0, r], np.r_[p[0], p], np.r_[state[0], state]
    sec, scale, tangential, outline = section(pv, vtu_path, a)
    mises = np.asarray(sec.point_data["mises_MPa"], float)
    # a flat punch's stress is singular at its edge: colour to the 99.5th percentile (the bar
    # shows the clipping), which keeps the field readable
    m_lo, m_hi = float(np.min(mises)), float(np.percentile(mises, 99.5))
    m_ext = "max" if np.max(mises) > 1.01 * m_hi else "neither"
    # and so is its pressure: colour to the 98th percentile of the pairs in contact
    pc = p[state > 0] if np.any(state > 0) else p
    p_hi = float(np.percentile(pc, 98)) if pc.size else 1.0
    p_hi = p_hi if p_hi > 0 else max(float(np.max(p)), 1.0)
    p_ext = "max" if np.max(p) > 1.001 * p_hi else "neither"
    rmax = float(r.max()) if r.size else a
    size = (560, 520)
    img0, ext0 = _render(pv, [(sec, dict(scalars="mises_MPa", cmap="viridis", clim=[m_lo, m_hi]))]
                         + ([(outline, dict(color="white", line_width=1.5))] if outline is not None else []),
                         (0.0, -0.25 * a), 2.7 * a, size)
    img1, ext1 = _render(pv, [(_disk(pv, r, p), dict(scalars="v", cmap="plasma", clim=[0.0, p_hi]))],
                         (0.0, 0.0), 1.08 * rmax, size)
    colours = ["#d9d9d9", "#1f77b4", "#d62728"]
    img2, ext2 = _render(pv, [(_disk(pv, r, state), dict(scalars="v", cmap=colours, clim=[0, 2], n_colors=3))],
                         (0.0, 0.0), 1.08 * rmax, size)

    fig, axes = plt.subplots(1, 3, figsize=(15, 5.6))
    um = lambda e: [1e6 * v for v in e]  # noqa: E731
    for ax, img, ext in zip(axes, (img0, img1, img2), (ext0, ext1, ext2)):
        ax.imshow(img, extent=um(ext), interpolation="antialiased")
        ax.set_xlabel("x (um)")
    axes[0].set_ylabel("z (um)")
    axes[1].set_ylabel("y (um)")
    axes[2].set_ylabel("y (um)")
    axes[0].set_title(("x-z section at the peak of F_x (F_x along +x)" if tangential else "r-z section at F0")
                      + f"\ndeformed (displacements x{scale:.3g}, relative to the block's surface on the axis);"
                      "\nwhite: the undeformed shape", fontsize=10)
    axes[1].set_title("contact pressure at F0", fontsize=11)
    axes[2].set_title("stick and slip at the peak of F_x", fontsize=11)
    _colorbar(fig, axes[0], "viridis", m_lo, m_hi, "von Mises stress (MPa)", extend=m_ext)
    _colorbar(fig, axes[1], "plasma", 0.0, p_hi, "pressure (MPa)", extend=p_ext)
    _colorbar(fig, axes[2], colours, 0, 2, "state of the contact pairs",
              ticklabels=("out of contact", "stick", "slip"))
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    plt.close(fig)
    write_bytes_atomic(png_path, buf.getvalue())
    return Path(png_path).name
