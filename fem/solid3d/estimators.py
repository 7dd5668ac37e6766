"""What the 3D model's vertex fields say about the contact: pure functions of a built model
(``fem.solid3d.model.Model3D``) and the pressures p (n,) and tractions q (n, 2) at its vertices.

Each estimator states the form of the fields it assumes (a smooth edge where p^2 is linear, one
interval of contact along the symmetry plane, a circular contact, Cattaneo-Mindlin's slack).
Lengths in m, the half model's fields (y >= 0) counted for the full body.
"""
from __future__ import annotations

import numpy as np

from mdr.normal import moment_radius
from mdr.stick import at_limit, per_step

from fem.solid3d.contact import WHOLE
from fem.solid3d.model import Model3D

#: the slack fraction at which a vertex counts as sticking (``mdr.stick``: 1/2 as for any traction)
STICK_ONSET = 0.5


def contact_mask(model: Model3D, p) -> np.ndarray:
    """The vertices in contact: the loaded ones (p > 0) and the free ones enclosed by them, i.e.
    the connected sets of free vertices (along the contact facets' edges) that reach no vertex
    of the candidate disk's rim. The filling is for the flat punch: its P1 pressure oscillates
    next to the singular edge, and the Signorini solution leaves a few vertices of the ring
    next to the rim at zero pressure (with a weighted gap below 0.5 % of d A_j at b/5) inside
    a contact that the theory has complete."""
    from scipy.sparse.csgraph import connected_components

    free = ~(p > 0)
    if not np.any(free):
        return ~free
    idx = np.flatnonzero(free)
    _, lab = connected_components(model.adj[idx][:, idx], directed=False)
    open_ = np.unique(lab[model.rim[idx]])
    mask = ~free
    mask[idx[~np.isin(lab, open_)]] = True
    return mask


def contact_area(model: Model3D, p) -> float:
    """Contact area of the full body (m^2): twice the sum of the vertex areas A_j (the integrals of
    the P1 hats) of the vertices in contact (:func:`contact_mask`), i.e. the contact edge half way
    between a loaded and a free vertex (first order in the element size)."""
    return WHOLE * float(model.mi.A[contact_mask(model, p)].sum())


def contact_extent_x(model: Model3D, p) -> tuple:
    """(x_min, x_max) of the contact along the symmetry plane (m): the outermost loaded vertices
    on y = 0, each moved towards the free vertex beyond it to the zero of p^2 extrapolated
    linearly from the last two loaded vertices (p ~ sqrt of the distance to a smooth edge,
    as in :func:`edge_radius`), clipped to that interval; at the rim of the candidate disk
    the rim. Assumes the loaded vertices on the plane form one interval."""
    pl = model.plane
    x, pp = model.mi.x[pl], p[pl]
    k = np.flatnonzero(contact_mask(model, p)[pl])
    if k.size == 0:
        return 0.0, 0.0
    ends = []
    for j, step in ((k[0], -1), (k[-1], 1)):
        xe = float(x[j])
        if 0 <= j + step < x.size and 0 <= j - step < x.size and pp[j - step] > 0:
            w1, w2 = pp[j] ** 2, pp[j - step] ** 2
            if w2 > w1:
                xr = x[j] + w1 * (x[j] - x[j - step]) / (w2 - w1)
                lo, hi = sorted((float(x[j]), float(x[j + step])))
                xe = float(np.clip(xr, lo, hi))
        ends.append(xe)
    return ends[0], ends[1]


def edge_radius(model: Model3D, p) -> float:
    """Contact radius from the vertex pressures: near a smooth edge p^2 is linear in r^2 (exact
    for Hertz, first order for the truncated sphere), so a least-squares line through
    (r^2, p^2) of the loaded vertices within 2 h of the outermost one is extrapolated to
    p = 0, clipped to [outermost loaded vertex, innermost free vertex beyond it]. All angles
    together: assumes a circular contact (the aligned sphere and truncated sphere)."""
    mi = model.mi
    loaded = p > 0
    if not np.any(loaded):
        return 0.0
    h = model.hmesh.params.h_min
    r1 = float(mi.r[loaded].max())
    sel = loaded & (mi.r >= r1 - 2.0 * h)
    if sel.sum() < 3:
        return r1
    k, c0 = np.polyfit(mi.r[sel] ** 2, p[sel] ** 2, 1)
    a = np.sqrt(-c0 / k) if k < 0 and c0 > 0 else r1
    beyond = mi.r[~loaded & (mi.r > r1)]
    return float(np.clip(a, r1, beyond.min() if beyond.size else r1 + h))


def contact_radius(model: Model3D, p, aligned: bool) -> float:
    """The contact radius: of the aligned flat punch its radius b (once in contact), of an aligned
    sphere or truncated sphere :func:`edge_radius`; of a tilted contact the half-width of its
    extent along x (:func:`contact_extent_x`)."""
    if not np.any(p > 0):
        return 0.0
    if aligned and model.flat:
        return float(model.profile.b)
    if aligned:
        return edge_radius(model, p)
    x0, x1 = contact_extent_x(model, p)
    return 0.5 * (x1 - x0)


def pressure_radius(model: Model3D, p) -> float:
    """The pressure's second-moment radius (m, ``mdr.normal.moment_radius``) about the load axis,
    of the P1 pressure field sum_j p_j phi_j integrated exactly (``Model3D.r2_hat``). Unlike
    :func:`edge_radius` it needs no edge located between vertices: a vertex whose hat straddles
    the edge has a positive weighted gap and carries no pressure, which puts the read edge inside
    by a fraction of an element (the sphere: 0.4-1.7 % of a on meshes of h = a/5 ... a/14, graded
    or not), while this integral is within 0.25 % of MDR's on the same meshes, 0.15 % from a/7 on
    (``tests/test_contact3d.py``). NaN without contact."""
    return moment_radius(WHOLE * float(model.mi.A @ p), WHOLE * float(model.r2_hat @ p))


def ray_caps(model: Model3D, p, a, tilted: bool) -> dict:
    """The contact's extent along each stick ray (m), the cap of its stick extent: ``a`` for every
    ray of an aligned contact; of a tilted one x_max, -x_min (:func:`contact_extent_x`) and the
    outermost loaded vertex within ``SECTOR`` of the y axis."""
    if not tilted:
        return {"+x": a, "-x": a, "y": a}
    x0, x1 = contact_extent_x(model, p)
    ly = model.ys[contact_mask(model, p)[model.ys]]
    return {"+x": max(x1, 0.0), "-x": max(-x0, 0.0), "y": float(model.mi.r[ly].max()) if ly.size else 0.0}


def slip_state(g, q) -> tuple:
    """(slack, slipping) of tractions q (n, 2) under slip limits g = mu p (n,): slack g - |q| in
    contact (0 outside), slipping where outside contact or at the limit (``mdr.stick.at_limit``)."""
    qn = np.hypot(q[:, 0], q[:, 1])
    contact = g > 0
    slack = np.where(contact, g - qn, 0.0)
    return slack, ~contact | at_limit(slack, g)


def stick_radius_x(model: Model3D, slack, slipping, p, a, tilted: bool) -> float:
    """The stick extent along +x (m, ``mdr.stick.per_step`` on the +x ray), the protocol's stick radius."""
    ray = model.rays["+x"]
    a_x = ray_caps(model, p, a, tilted)["+x"]
    return float(per_step(model.mi.x[ray], slack[ray], slipping[ray], a_x, STICK_ONSET))


def stick_zone(model: Model3D, mu, q, p, a, tilted: bool) -> dict:
    """Stick extents of one instant (m): ``stick_radius_x`` (mean of +x and -x),
    ``stick_center_x`` (their half difference), ``stick_radius_y``, each from the vertices of
    one ray (``mdr.stick``: resolved to a fraction of the element); ``stick_axis_x``,
    ``stick_axis_y``, the semi-axes of the ellipse with the stick set's area and second moments
    (every vertex that sticks, weighted by its area A_j: a = sqrt(4 I_x / area), so a change of
    the stick set by one vertex moves them by ~A_j / area, far less than an element);
    ``stick_axis_quantum`` (m), their resolution: the change of an axis when one vertex of median
    area joins the stick set, axis * A_median / (2 area);
    ``stick_fit_x``, ``stick_fit_y``, ``stick_fit_center_x`` (m): the stick ellipse fitted to the
    slack s = mu p - |q| of the sticking vertices, s^2 = A0 - B (x - x0)^2 - C y^2
    (:func:`stick_ellipse_fit`; semi-axes sqrt(A0 / B), sqrt(A0 / C), centre x0; NaN where it
    cannot be fitted): exact for Cattaneo-Mindlin, whose slack is (mu p0 / a) sqrt(c^2 - r^2)
    (Hertz pressure, traction along x), an approximation elsewhere. It uses every sticking
    vertex, so it moves almost continuously with the solution (a small jump when a vertex of
    near-zero slack joins the stick set) instead of by one vertex at a time. It assumes that
    form: at a constant normal force the traction of free direction stays close to it (the fit
    converges, ``tests/test_contact3d.py``); under a varying normal force the stick zone's slack
    carries its history and the fit is no estimate (the assumptions-3d scene's Table 2 loading:
    the fitted axes of the sphere's free-direction run and of its twin along x on one mesh
    differed by 1.5-15 % of a, where the two stick sets were identical);
    ``traction_angle_max``, the largest |q_y|/|q| over the vertices in contact that slip;
    ``pressure_center_x``, the x of the pressure's centroid (m). ``tilted``: the face is tilted
    (the rays are capped by the contact's own extent, :func:`ray_caps`)."""
    mi = model.mi
    g = mu * p
    qn = np.hypot(q[:, 0], q[:, 1])
    contact = g > 0
    slack, slipping = slip_state(g, q)
    ext = {}
    caps = ray_caps(model, p, a, tilted)
    for name, ray in model.rays.items():
        r = np.abs(mi.x[ray]) if name != "y" else mi.r[ray]
        ext[name] = float(per_step(r, slack[ray], slipping[ray], caps[name], STICK_ONSET))
    slip = contact & slipping
    ang = float(np.max(np.abs(q[slip, 1]) / qn[slip])) if np.any(slip) else 0.0
    w = mi.A * p
    st = contact & ~slipping
    area = float(mi.A[st].sum())
    if area > 0:
        xc = float(mi.A[st] @ mi.x[st]) / area
        axes = (np.sqrt(4.0 * float(mi.A[st] @ (mi.x[st] - xc) ** 2) / area),
                np.sqrt(4.0 * float(mi.A[st] @ mi.y[st] ** 2) / area))
        quantum = 0.5 * max(axes) * float(np.median(mi.A[st])) / area
    else:
        axes, quantum = (0.0, 0.0), 0.0
    fit = stick_ellipse_fit(mi.x[st], mi.y[st], slack[st], mi.A[st])
    return {"stick_radius_x": 0.5 * (ext["+x"] + ext["-x"]), "stick_center_x": 0.5 * (ext["+x"] - ext["-x"]),
            "stick_fit_x": fit[0], "stick_fit_y": fit[1], "stick_fit_center_x": fit[2],
            "stick_radius_y": ext["y"], "stick_axis_x": float(axes[0]), "stick_axis_y": float(axes[1]),
            "stick_axis_quantum": quantum, "traction_angle_max": ang,
            "pressure_center_x": float(w @ mi.x / w.sum()) if w.sum() > 0 else 0.0}


def stick_ellipse_fit(x, y, slack, w) -> tuple:
    """(semi-axis x, semi-axis y, centre x) (m) of the ellipse where the fitted squared slack of the
    sticking vertices vanishes: weighted least squares (weights ``w``, the vertex areas) of
    s^2 = A + D x - B x^2 - C y^2 (the half model, symmetric in y), i.e. A0 - B (x - x0)^2 - C y^2
    with x0 = D / (2 B), A0 = A + B x0^2. Exact for a Cattaneo-Mindlin stick zone (slack
    proportional to sqrt(c^2 - r^2)); NaNs with fewer than 5 vertices or B, C or A0 <= 0."""
    nan = (float("nan"),) * 3
    if np.size(x) < 5:
        return nan
    sw = np.sqrt(np.asarray(w, dtype=float))
    M = np.column_stack([np.ones(np.size(x)), -np.square(x), -np.square(y), x]) * sw[:, None]
    (A, B, C, D), *_ = np.linalg.lstsq(M, np.square(slack) * sw, rcond=None)
    if not (B > 0 and C > 0):
        return nan
    x0 = D / (2.0 * B)
    A0 = A + B * x0 ** 2  # s^2 = A0 - B (x - x0)^2 - C y^2
    if not A0 > 0:
        return nan
    return float(np.sqrt(A0 / B)), float(np.sqrt(A0 / C)), float(x0)
