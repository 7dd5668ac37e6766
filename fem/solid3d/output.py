"""The 3D model's contact fields as a VTU file (ParaView): ``python -m fem contact --model 3d --vtu``.

The contact disk of the full body: the half model's contact facets (y >= 0) and their mirror image
(y -> -y, the traction's y component and the y slip change sign), linear triangles on the P1
traction vertices, with the point data a contact user expects at one state of a run
(``fem.solid3d.law.FE3DState``): ``contact_pressure`` (Pa), ``shear_traction_x``,
``shear_traction_y`` and ``shear_traction`` (its magnitude) (Pa), ``contact_status`` (0 no contact,
1 stick, 2 slip: ``fem.solid3d.estimators.slip_state``) and ``slip_x``, ``slip_y`` (m: the
accumulated weighted slip P_j over the vertex area A_j). Coordinates in m, z = 0 (the contact plane).
The bodies' volume fields (displacements, stresses) are not written: the 3D model keeps only the
condensed interface, not the bodies' factorisations.
"""
from __future__ import annotations

import numpy as np

from common.io import write_vtu_atomic

from fem.solid3d.estimators import slip_state

#: ``contact_status`` values, as in the axisymmetric model's VTU (``fem.axisym.output.STATUS``)
STATUS = {"none": 0, "stick": 1, "slip": 2}


def contact_fields(law, state) -> dict:
    """The point data of the module docstring on the half model's vertices (n,)."""
    mi = law.model.mi
    q, p, P = np.asarray(state.q), np.asarray(state.p), np.asarray(state.P)
    g = law.mu * p
    _, slipping = slip_state(g, q)
    status = np.where(g > 0, np.where(slipping, STATUS["slip"], STATUS["stick"]), STATUS["none"])
    return {"contact_pressure": p, "shear_traction_x": q[:, 0], "shear_traction_y": q[:, 1],
            "shear_traction": np.hypot(q[:, 0], q[:, 1]), "contact_status": status.astype(float),
            "slip_x": P[:, 0] / mi.A, "slip_y": P[:, 1] / mi.A}


def write_contact_vtu(law, state, path) -> str:
    """Write the contact disk of ``state`` to ``path`` (.vtu, atomically); returns the path."""
    import meshio

    m = law.model
    mi, mesh = m.mi, m.hmesh.mesh
    tri = np.searchsorted(mi.vertices, mesh.facets[:, mesh.boundaries["contact"]]).T  # (k, 3) vertex positions
    pts = np.column_stack([mi.x, mi.y, np.zeros(mi.n)])
    mirror = pts * np.array([1.0, -1.0, 1.0])
    fields = contact_fields(law, state)
    odd = {"shear_traction_y", "slip_y"}  # change sign in the mirror image
    data = {k: np.concatenate([v, -v if k in odd else v]) for k, v in fields.items()}
    out = meshio.Mesh(np.vstack([pts, mirror]), [("triangle", np.vstack([tri, tri[:, ::-1] + mi.n]))],
                      point_data=data)
    return write_vtu_atomic(out, path)
