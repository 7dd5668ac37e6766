"""The 3D half model with a flat face: the truncated sphere's edge as a circle of the mesh, the
flat punch and the tilted flat face (fem.solid3d.law).

Closed forms (half-space, identical steel bodies): the truncated sphere's normal contact is exact
in the MDR (mdr.normal; Ciavarella, Hills & Monno 1998, Proc. IMechE C 212, 319); the flat punch
of radius b: Boussinesq's pressure p = F / (2 pi b sqrt(b^2 - r^2)), and tilted by theta about y
(theta > 0 lifts the +x side) at a central force F

    p sqrt(b^2 - r^2) = F / (2 pi b) - (2 E* / pi) theta x,   moment M_y = int p x dA = -(4/3) E* theta b^3,

in full contact while theta <= theta_c = F / (4 E* b^2) (Johnson 1985, Contact Mechanics, sec. 5.2).
The finite bodies' compliance changes the approach (never compared here) but neither the force
nor, to O((b/L)^2) for a block of size L = 20 b, the pressure at a given force: every check is at
the force. Under a tangential force Q < mu F the flat punch sticks completely (q/p = Q/F wherever
the Cattaneo-Mindlin assumptions hold; the MDR law gives c = b) and slides as a whole at mu F.

Over 500 lines for a stated reason: its tests share the module's 3D models (``truncated``, ``punch``,
``refined``: meshes and condensed interfaces set up once); split, each part would set them up again.
"""
import numpy as np
import pytest

from fem.solid3d import estimators as est
from fem.solid3d.law import FEContact3D
from mdr import normal as mn
from mdr import reference as ref
from common.errors import InputError
from mdr.materials import Materials
from mdr.profiles import FlatPunch, TruncatedSphere
from mdr.loading import Loading

MAT = Materials()
ES = MAT.E_star
F, MU = 0.5, 0.2
R, B_T = 6e-3, 20e-6  # truncated sphere (Table 2 loading F0 = 0.5 N)
B_F = 100e-6  # flat punch
THC = F / (4 * ES * B_F**2)  # 1.14e-4 rad


def _lattice(n=16):
    """Barycentric points of the n^2 sub-triangles' centroids (equal weights): a composite rule that
    tolerates the log and inverse-square-root singularities of the exact pressures."""
    pts = [((i + 1 / 3) / n, (j + 1 / 3) / n) for i in range(n) for j in range(n - i)]
    pts += [((i + 2 / 3) / n, (j + 2 / 3) / n) for i in range(n) for j in range(n - i) if i + j < n - 1]
    L = np.array(pts)
    return np.column_stack([L, 1 - L.sum(1)])


def _quadrature(law, p):
    """Points (r), weights and the P1 pressure field there, over the contact half disk."""
    mi, m = law.model.mi, law.model.hmesh.mesh
    tri = m.facets[:, m.boundaries["contact"]].T
    X = m.p[:2, tri]
    lam = _lattice()
    area = 0.5 * np.abs((X[0, :, 1] - X[0, :, 0]) * (X[1, :, 2] - X[1, :, 0])
                        - (X[0, :, 2] - X[0, :, 0]) * (X[1, :, 1] - X[1, :, 0]))
    xq = np.einsum("qv,ckv->ckq", lam, X)
    ph = np.einsum("qv,kv->kq", lam, p[np.searchsorted(mi.vertices, tri)])
    return np.hypot(xq[0], xq[1]), area[:, None] / lam.shape[0], ph


# ------------------------------------------------------------------ truncated sphere: the edge in the mesh


@pytest.fixture(scope="module")
def truncated(tmp_path_factory):
    cache = tmp_path_factory.mktemp("m3d-trunc")
    return {h: FEContact3D(TruncatedSphere(R, B_T), MAT, MU, F_max=F, h_contact=h, cache_dir=cache)
            for h in (0.3, 0.2)}


def test_truncated_sphere_edge_is_a_mesh_circle(truncated):
    a_ref = ref.truncated_contact_radius(F, R, B_T, ES)
    for law in truncated.values():
        assert law.model.hmesh.params.edge == pytest.approx(B_T / a_ref, rel=1e-12)
        on_edge = np.abs(law.model.mi.r - B_T) < 1e-9 * B_T
        assert on_edge.sum() >= 8 and np.sum(on_edge & law.model.mi.on_plane) == 2  # (+-b, 0) and the arc
    # meshes without an edge keep their parameters, hence their cache keys
    from meshes.half3d import Half3DMeshParams

    assert "edge" not in Half3DMeshParams(a_ref=1.0).resolved().as_dict()


def test_truncated_sphere_against_mdr(truncated):
    """Contact radius and pressure at F = 0.5 N against the exact axisymmetric solution (MDR).
    Measured (h = a/3.3, a/5): contact radius -2.6 %, -3.4 % (without the edge circle -5.0 %,
    -3.9 %); relative L1 error of the pressure over the half disk 0.227, 0.133 (a/6.7: 0.105,
    a/10: 0.079)."""
    prof = TruncatedSphere(R, B_T)
    a_ex = ref.truncated_contact_radius(F, R, B_T, ES)
    d_ex = float(mn.approach_from_force(prof, MAT, F))
    err = {}
    for h, law in truncated.items():
        nr = law.normal(F_N=F)
        assert abs(nr.contact_radius / a_ex - 1) < 0.07
        r, w, ph = _quadrature(law, nr.p)
        pe = mn.pressure(prof, MAT, d_ex, r.ravel()).reshape(r.shape)
        err[h] = float(np.sum(w * np.abs(ph - pe)) / np.sum(w * pe))
    assert err[0.2] < err[0.3] < 0.45 and err[0.2] < 0.27


# ------------------------------------------------------------------ flat punch


@pytest.fixture(scope="module")
def punch(tmp_path_factory):
    cache = tmp_path_factory.mktemp("m3d-flat")
    return {h: FEContact3D(FlatPunch(B_F), MAT, MU, h_contact=h, cache_dir=cache) for h in (0.3, 0.2)}


def test_flat_punch_mesh_and_input(punch):
    law = punch[0.2]
    p = law.model.hmesh.params
    assert p.a_ref == B_F and p.contact_extent == 1.0
    assert np.max(law.model.mi.r) == pytest.approx(B_F, rel=1e-9)
    assert np.all(law.gap0 == 0)
    with pytest.raises(InputError, match="contact_extent"):
        FEContact3D(FlatPunch(B_F), MAT, MU, contact_extent=1.25)
    for bad in (0.02, np.nan, np.inf, [1e-4]):
        with pytest.raises(InputError, match="tilt must be"):
            law.assuming(tilt=bad)


def test_flat_punch_boussinesq_pressure(punch):
    """The share of F carried within r <= rho, 1 - sqrt(1 - rho^2/b^2) for Boussinesq: measured
    within 5.1 % at b/5 for rho <= 0.8 b (b/10: 2.4 %). The approach is not compared (finite
    bodies: -5.2 % against the half-space)."""
    law = punch[0.2]
    nr = law.normal(F_N=F)
    assert nr.force == pytest.approx(F, rel=1e-12) and nr.contact_radius == B_F
    assert law.tilt_keys(F)["contact_area_fraction"] == 1.0
    r, w, ph = _quadrature(law, nr.p)
    for rho in (0.3, 0.5, 0.7, 0.8):
        share = 2 * float(np.sum(w * ph * (r <= rho * B_F))) / F
        assert abs(share / (1 - np.sqrt(1 - rho**2)) - 1) < 0.12, rho


def test_flat_punch_sticks_until_gross_slip(punch):
    """Q < mu F: complete stick along +x (c = b, as the MDR law gives) at Q = 0.5 and 0.9 mu F; the
    P1 tractions oscillate next to the edge like the pressure, so a few vertices there reach their
    limit (area share measured 11 % at 0.5 mu F, b/5). Beyond gross slip every vertex slides and
    F_x -> mu F."""
    from mdr.law import MDRContact

    mdr_law = MDRContact(FlatPunch(B_F), MAT, MU, F_max=F)
    res_mdr, _ = mdr_law.step(mdr_law.rest_state(), Fx=0.5 * MU * F, F_N=F)
    assert res_mdr.c == pytest.approx(B_F, rel=1e-12)
    law = punch[0.2]
    for Q in (0.5, 0.9):
        res, st = law.step(law.rest_state(), Fx=Q * MU * F, F_N=F)
        assert res.c == pytest.approx(B_F, rel=1e-12)
    res, st = law.step(law.rest_state(), Fx=0.5 * MU * F, F_N=F)
    g = MU * np.asarray(st.p)
    qn = np.hypot(st.q[:, 0], st.q[:, 1])
    at_limit = (g > 0) & (qn >= g * (1 - 1e-6))
    assert law.model.mi.A[at_limit].sum() / law.model.mi.A.sum() < 0.25
    us = 20 * MU * ref.flat_punch_approach(F, B_F, ES) * ES / MAT.G_star  # far beyond the gross-slip u
    res, st = law.step(law.rest_state(), u=us, F_N=F)
    g = MU * np.asarray(st.p)
    qn = np.hypot(st.q[:, 0], st.q[:, 1])
    assert np.allclose(qn[g > 0], g[g > 0], rtol=1e-9) and abs(res.Fx / (MU * F) - 1) < 1e-6
    with pytest.raises(InputError, match="friction limit"):
        law.step(law.rest_state(), Fx=MU * F, F_N=F)


# ------------------------------------------------------------------ the tilted flat punch


def _moment(law, p):
    """M_y = int p x dA of the full body, exact for the P1 pressure field: over a triangle
    int p x = area / 12 (sum_i p_i x_i + sum_i p_i sum_j x_j)."""
    mi, m = law.model.mi, law.model.hmesh.mesh
    tri = m.facets[:, m.boundaries["contact"]].T
    X = m.p[:2, tri]
    area = 0.5 * np.abs((X[0, :, 1] - X[0, :, 0]) * (X[1, :, 2] - X[1, :, 0])
                        - (X[0, :, 2] - X[0, :, 0]) * (X[1, :, 1] - X[1, :, 0]))
    pv = p[np.searchsorted(mi.vertices, tri)]
    return 2.0 * float(np.sum(area / 12 * (np.sum(pv * X[0], axis=1) + pv.sum(1) * X[0].sum(1))))


def _m_halfspace(theta):
    return -4.0 / 3.0 * ES * theta * B_F**3


def test_tilted_punch_full_contact_below_theta_c(punch):
    """theta <= theta_c: contact everywhere, the moment and the linear part of p sqrt(b^2 - r^2)
    against the half-space (neither depends on the approach, so the finite block drops out).
    Measured at 0.8 theta_c: M / M_hs - 1 = 2.5 %, 2.7 % (b/3.3, b/5; b/10: 1.8 %, b/14: 1.3 %);
    least-squares line of p sqrt(b^2 - r^2) over r <= 0.7 b at b/5: intercept / (F / 2 pi b)
    1.008, slope / (-2 E* theta / pi) 1.13."""
    err = {}
    for h, law in punch.items():
        for frac in (0.5, 0.8):
            tl = law.assuming(tilt=frac * THC)
            nr = tl.normal(F_N=F)
            keys = tl.tilt_keys(F)
            assert keys["tilt"] == frac * THC and keys["contact_area_fraction"] == 1.0
            assert keys["contact_x_min"] == pytest.approx(-B_F, rel=1e-9)
            assert keys["contact_x_max"] == pytest.approx(B_F, rel=1e-9)
        err[h] = _moment(tl, nr.p) / _m_halfspace(0.8 * THC) - 1
    assert all(0 < e < 0.06 for e in err.values()), err
    tl = punch[0.2].assuming(tilt=0.8 * THC)
    nr = tl.normal(F_N=F)
    mi = tl.model.mi
    sel = mi.r <= 0.7 * B_F
    c0, c1 = np.linalg.lstsq(np.column_stack([np.ones(sel.sum()), mi.x[sel]]),
                             nr.p[sel] * np.sqrt(B_F**2 - mi.r[sel] ** 2), rcond=None)[0]
    assert abs(c0 / (F / (2 * np.pi * B_F)) - 1) < 0.05
    assert abs(c1 / (-2 * ES * 0.8 * THC / np.pi) - 1) < 0.3


def test_tilted_punch_loses_the_trailing_edge(punch):
    """theta > theta_c: the +x side (lifted) separates, the -x rim stays loaded; the contact area
    fraction and the trailing extent fall monotonically with the tilt. Measured at b/5:
    fraction 0.90, 0.76, 0.60, 0.35, 0.23, 0.13 at 1.2, 1.5, 2, 3, 4, 6 theta_c; x_max
    0.60 b at 1.2 theta_c (b/3.3: 0.61 b)."""
    for law in punch.values():
        fr, xm = [], []
        for k in (1.25, 1.5, 2.0, 3.0, 4.0, 6.0):
            keys = law.assuming(tilt=k * THC).tilt_keys(F)
            assert keys["contact_x_min"] == pytest.approx(-B_F, rel=1e-9)
            fr.append(keys["contact_area_fraction"])
            xm.append(keys["contact_x_max"])
        assert xm[0] < 0.9 * B_F and fr[0] < 1.0
        assert np.all(np.diff(fr) < 0) and np.all(np.diff(xm) <= 0), (fr, xm)
    # the sign convention: theta < 0 lifts the -x side, the mirror image
    a = punch[0.2].assuming(tilt=2 * THC).tilt_keys(F)
    b = punch[0.2].assuming(tilt=-2 * THC).tilt_keys(F)
    assert b["contact_x_max"] == pytest.approx(B_F, rel=1e-9)
    assert abs(b["contact_area_fraction"] - a["contact_area_fraction"]) < 0.05


# the Table 2 force loading of the tilt family: F_N = F0 + dF sin, F_x = fa sin (in phase)
F0_T, DF_T, FA_T = 0.5, 0.1, 0.06


def _theta_stick():
    """Closed form: the tilted punch sticks completely while theta <= theta_s. Its full-stick traction
    q = F_x / (2 pi b sqrt(b^2 - r^2)) (exact for the half-space, Mindlin 1949) against the tilted
    pressure, p sqrt(b^2 - r^2) = F_N / (2 pi b) - (2 E* / pi) theta x, needs |F_x| <= mu (F_N - 4 E*
    theta b^2) at the lifted edge x = b at every instant: theta_s = min_t (F_N - |F_x| / mu) / (4 E* b^2)
    (here 0.1 N / (4 E* b^2) = 0.2 theta_c)."""
    s = np.sin(np.linspace(0, 2 * np.pi, 2001))
    return float(np.min(F0_T + DF_T * s - np.abs(FA_T * s) / MU)) / (4 * ES * B_F**2)


def _tilt_run(law, theta, steps=20):
    import warnings

    from fem.contact_run import drive_3d

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a sticking punch's cycles are "not stationary" at 1e-26 J
        out = drive_3d(law.assuming(tilt=theta), Loading.of(F0_T, dF=DF_T, alpha=0.0, fa=FA_T, cycles=3, steps=steps))
    return out["dissipation"] / (4 * MU * F0_T * out["displacement_amplitude"]), out


def test_tilted_punch_sticks_below_the_closed_form_bound(punch):
    """Under the Table 2 force loading the tilted punch dissipates nothing while theta <= theta_s
    (``_theta_stick``, 0.2 theta_c) and starts to slip at its lifted edge beyond it: slip index
    W / (4 mu F0 u_A) below 1e-4 at 0.5 theta_s (measured 1.2e-6, 1.9e-5 at b/3.3, b/5) and above 1e-3
    at 2.5 theta_s (measured 2.7e-3 at both). Above theta_c the dissipation grows monotonically with the
    tilt (1, 2, 4 theta_c at b/5; measured 3.0, 4.7, 5.8e-11 J) while the contact shrinks."""
    ts = _theta_stick()
    assert ts == pytest.approx(0.2 * THC, rel=1e-6)
    for law in punch.values():
        assert _tilt_run(law, 0.5 * ts)[0] < 1e-4
        assert _tilt_run(law, 2.5 * ts)[0] > 1e-3
    W = [_tilt_run(punch[0.2], k * THC)[1]["dissipation"] for k in (1.0, 2.0, 4.0)]
    assert np.all(np.diff(W) > 0), W


def test_tilt_zero_is_the_aligned_punch(punch):
    """Tilt 0 is the aligned model: a law tilted and set back to 0 gives the aligned law's steps to
    the bit (the same path). Against the axisymmetric model (``fem.axisym.law.FEContact``, h = b/20; both in
    the contact measure) under the Table 2 force loading: both stick completely (slip index below
    1e-4; measured 2e-17 in 3D, 1e-11 axisymmetric) and the displacement amplitude agrees within 3 %
    (measured -1.3 %: the 3D contact measure's tangential stiffness is ~2 % above the half-space's,
    see tests/test_contact3d.py, not a tilt effect)."""
    import warnings

    from fem.axisym.law import FEContact
    from mdr.drive import run_contact

    law = punch[0.3]
    back = law.assuming(tilt=2 * THC).assuming(tilt=0.0)
    assert back.tilt == 0.0 and np.array_equal(back.gap0, law.gap0)
    s1 = s2 = law.rest_state()
    for fn, fx in ((0.5, 0.0), (0.6, 0.05), (0.4, -0.05)):
        r1, s1 = law.step(s1, Fx=fx, F_N=fn)
        r2, s2 = back.step(s2, Fx=fx, F_N=fn)
        assert r1.Fx == r2.Fx and r1.u == r2.u and np.array_equal(s1.q, s2.q)
    l3 = FEContact3D(FlatPunch(B_F), MAT, MU, h_contact=0.3, displacement="contact")
    d3, o3 = _tilt_run(l3, 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        ax = run_contact(FEContact(FlatPunch(B_F), MAT, MU, h_contact=1 / 20, displacement="contact"), Loading.of(F0_T, dF=DF_T, alpha=0.0, fa=FA_T, cycles=3, steps=20))
    assert d3 < 1e-4 and ax["dissipation"] / (4 * MU * F0_T * ax["displacement_amplitude"]) < 1e-4
    assert abs(o3["displacement_amplitude"] / ax["displacement_amplitude"] - 1) < 0.03


@pytest.mark.slow
def test_tilted_punch_mesh_convergence(tmp_path):
    """One tilted case at two mesh levels (b/5, b/10): the contact area fraction at 2 theta_c
    (measured 0.603, 0.616; b/14: 0.619) and the moment at 0.5 theta_c (M / M_hs - 1: 2.48 %,
    1.80 %; b/14: 1.25 %)."""
    out = {}
    for h in (0.2, 0.1):
        law = FEContact3D(FlatPunch(B_F), MAT, MU, h_contact=h, cache_dir=tmp_path)
        half = law.assuming(tilt=0.5 * THC)
        out[h] = (law.assuming(tilt=2 * THC).tilt_keys(F)["contact_area_fraction"],
                  _moment(half, half.normal(F_N=F).p) / _m_halfspace(0.5 * THC) - 1)
    assert abs(out[0.1][0] - out[0.2][0]) < 0.04
    assert 0.4 < out[0.1][0] < 0.8
    assert 0 < out[0.1][1] < out[0.2][1] and out[0.1][1] < 0.04


# ------------------------------------------------------------------ the loaded edge refined

#: the paper's bound on the flat faces' tilt (rad), 7.6 theta_c of this punch at F
TILT_PAPER = np.pi / 3600
#: a refined ball at the loaded edge (-b, 0) of the punch tilted by theta > 0: (x, h, radius) / b (the
#: cheap one: at pi/3600 a radius of 0.8 b covers the whole edge crescent, see the slow test below)
REFINE = (-1.0, 0.1, 0.5)


@pytest.fixture(scope="module")
def refined(tmp_path_factory):
    return FEContact3D(FlatPunch(B_F), MAT, MU, h_contact=0.3, refine=REFINE,
                       cache_dir=tmp_path_factory.mktemp("m3d-refined"))


def test_refine_mesh_params_and_input(refined):
    """The refinement is a ball of the mesh: edges within it are about refine_h long (vertex
    spacing on the contact face near (-b, 0) at most 1.5 h_r, away from it about h_contact);
    meshes without it keep their cache keys; bad input names the parameter."""
    from meshes.half3d import Half3DMeshParams

    assert not {"refine_x", "refine_h", "refine_radius"} & set(Half3DMeshParams(a_ref=1.0).resolved().as_dict())
    p = refined.model.hmesh.params
    assert (p.refine_x, p.refine_h, p.refine_radius) == REFINE
    m, mi = refined.model.hmesh.mesh, refined.model.mi
    tri = m.facets[:, m.boundaries["contact"]]
    e = np.concatenate([tri[[0, 1]], tri[[1, 2]], tri[[2, 0]]], axis=1)
    mid = 0.5 * (m.p[:2, e[0]] + m.p[:2, e[1]])
    le = np.linalg.norm(m.p[:, e[0]] - m.p[:, e[1]], axis=0)
    near = np.hypot(mid[0] + B_F, mid[1]) < 0.3 * B_F
    far = np.hypot(mid[0] - 0.5 * B_F, mid[1]) < 0.3 * B_F
    assert np.median(le[near]) < 1.5 * REFINE[1] * B_F < np.median(le[far]) and np.median(le[far]) > 0.2 * B_F
    for kw, name in ((dict(refine_x=-1.0), "go together"), (dict(refine_x=-1.5, refine_h=0.1, refine_radius=0.5),
                                                             "refine_x must be"),
                     (dict(refine_x=-1.0, refine_h=0.5, refine_radius=0.5), "refine_h must be"),
                     (dict(refine_x=-1.0, refine_h=0.1, refine_radius=0.0), "refine_radius must be"),
                     (dict(refine_x=np.nan, refine_h=0.1, refine_radius=0.5), "refine_x must be")):
        with pytest.raises(InputError, match=name):
            Half3DMeshParams(a_ref=1.0, h_contact=0.3, contact_extent=1.0, **kw)
    with pytest.raises(InputError, match="refine must be"):
        FEContact3D(FlatPunch(B_F), MAT, MU, h_contact=0.3, refine=(-1.0, 0.1))


def test_refined_edge_moment_and_paper_tilt(refined, punch):
    """Below theta_c the refinement at the loaded edge does not worsen the moment against
    -(4/3) E* theta b^3 (measured at 0.8 theta_c: M / M_hs - 1 = +0.34 % against +2.5 % without,
    b/3.3). At the paper's bound pi/3600 = 7.6 theta_c the edge contact, fewer than 10 vertices
    without the refinement (measured 4 at b/3.3, 8 at b/5), covers 35 with it (b/10 in the ball);
    x_min stays the loaded rim and the contact shrinks with the tilt beyond theta_c (area fraction
    0.60, 0.26, 0.15 at 2, 4, 7.6 theta_c)."""
    e = {}
    for name, law in (("plain", punch[0.3]), ("refined", refined)):
        tl = law.assuming(tilt=0.8 * THC)
        e[name] = _moment(tl, tl.normal(F_N=F).p) / _m_halfspace(0.8 * THC) - 1
    assert abs(e["refined"]) <= abs(e["plain"]) and abs(e["refined"]) < 0.01, e
    tl = refined.assuming(tilt=TILT_PAPER)
    nc = int(est.contact_mask(tl.model, tl.normal(F_N=F).p).sum())
    assert nc >= 10, nc
    fr = [refined.assuming(tilt=k * THC).tilt_keys(F) for k in (2.0, 4.0, TILT_PAPER / THC)]
    assert all(k["contact_x_min"] == pytest.approx(-B_F, rel=1e-9) for k in fr)
    assert np.all(np.diff([k["contact_area_fraction"] for k in fr]) < 0)


@pytest.mark.slow
def test_refined_edge_converges_at_the_paper_tilt(tmp_path):
    """The flat punch at pi/3600 (7.6 theta_c) with the loaded edge refined (h_contact = b/3.3), the
    refined ball's size h_r and radius rho varied: (h_r, rho) = (b/10, 0.8 b), (b/14, 0.8 b),
    (b/10, b): contact area fraction measured 0.168, 0.179, 0.175, x_max -0.589 b, -0.575 b,
    -0.594 b. A ball of 0.5 b leaves the crescent's tips on the coarse mesh and undercounts them
    (0.148 at b/10, 0.160 at b/20); without the refinement 0.078 (b/3.3), 0.093 (b/5)."""
    out = []
    for hr, rho in ((0.1, 0.8), (0.07, 0.8), (0.1, 1.0)):
        law = FEContact3D(FlatPunch(B_F), MAT, MU, h_contact=0.3, refine=(-1.0, hr, rho), cache_dir=tmp_path)
        k = law.assuming(tilt=TILT_PAPER).tilt_keys(F)
        out.append((k["contact_area_fraction"], k["contact_x_max"] / B_F))
    fr, xm = np.array(out).T
    assert np.ptp(fr) < 0.03 and np.all((0.12 < fr) & (fr < 0.25)), out
    assert np.ptp(xm) < 0.05 and np.all((-0.7 < xm) & (xm < -0.45)), out


# ------------------------------------------------------------------ a band along the loaded rim arc

#: the truncated sphere of the paper's experiments (Figs. 6, 7): b = 0.6 mm, R = 6 mm; at the Table 2
#: force F its theta_c is 3.2e-6 rad and the paper's bound pi/3600 is 274 theta_c
B_P = 0.6e-3
#: the band along its loaded edge: (h, width, angle, growth), h and width / b; the edge crescent at
#: pi/3600 reaches r = 0.96 b and |phi - pi| = 0.35 rad (measured), inside width 0.06 b and 0.45 rad
BAND = (0.02, 0.06, 0.45, 1.0)


def test_band_mesh_params_and_input(tmp_path):
    """The band is a strip of the mesh along the arc |phi - pi| <= band_angle of the edge circle:
    contact-face edges within it are about band_h long (median at most 1.5 band_h), on the same
    circle outside the arc and away from it about h_contact; meshes without a band keep their cache
    keys; bad input names the parameter."""
    from meshes.half3d import Half3DMeshParams, cached_mesh3d, mesh3d_key

    base = dict(a_ref=1.0, h_contact=0.3, contact_extent=1.25, size=20.0, height=20.0, edge=1.0)
    assert not {"band_h", "band_width", "band_angle", "band_growth"} & set(Half3DMeshParams(**base).resolved().as_dict())
    p = Half3DMeshParams(**base, band_h=BAND[0], band_width=BAND[1], band_angle=BAND[2], band_growth=BAND[3])
    assert mesh3d_key(p) != mesh3d_key(Half3DMeshParams(**base))
    m = cached_mesh3d(p, tmp_path).mesh
    tri = m.facets[:, m.boundaries["contact"]]
    e = np.concatenate([tri[[0, 1]], tri[[1, 2]], tri[[2, 0]]], axis=1)
    mid = 0.5 * (m.p[:2, e[0]] + m.p[:2, e[1]])
    le = np.linalg.norm(m.p[:, e[0]] - m.p[:, e[1]], axis=0)
    r, phi = np.hypot(mid[0], mid[1]), np.arctan2(mid[1], mid[0])
    inside = (np.abs(r - 1) < 0.5 * BAND[1]) & (np.abs(phi - np.pi) < 0.8 * BAND[2])
    beyond = (np.abs(r - 1) < 0.1) & (np.abs(phi - np.pi / 2) < 0.3)  # on the circle, outside the arc
    centre = r < 0.4
    assert np.median(le[inside]) < 1.5 * BAND[0], np.median(le[inside])
    assert np.median(le[beyond]) > 0.5 * base["h_contact"] and np.median(le[centre]) > 0.5 * base["h_contact"]
    for kw, name in ((dict(band_h=0.02), "go together"), (dict(band_h=0.5, band_width=0.06, band_angle=0.4),
                                                         "band_h must be"),
                     (dict(band_h=0.02, band_width=0.0, band_angle=0.4), "band_width must be"),
                     (dict(band_h=0.02, band_width=0.06, band_angle=4.0), "band_angle must be"),
                     (dict(band_h=0.02, band_width=0.06, band_angle=np.nan), "band_angle must be"),
                     (dict(band_h=0.02, band_width=0.06, band_angle=0.4, band_growth=2.0), "band_growth must be"),
                     (dict(band_growth=0.5), "band_growth needs a band")):
        with pytest.raises(InputError, match=name):
            Half3DMeshParams(**base, **kw)
    with pytest.raises(InputError, match="band must be"):
        FEContact3D(TruncatedSphere(R, B_P), MAT, MU, F_max=F, h_contact=0.3, band=(0.02, 0.06))


@pytest.mark.slow
def test_band_converges_at_the_paper_tilt(tmp_path):
    """The truncated sphere b = 0.6 mm at pi/3600 (274 theta_c), its loaded rim arc banded
    (``BAND`` with band_h = b/50 and b/70; h_contact = 0.3 b elsewhere): the edge crescent covers
    0.0046-0.0050 of the aligned contact (measured 0.00456, 0.00502 on 20 and 43 vertices; on the
    meshes of F_max = 0.6 N, the benchmark's, 0.00462 and 0.00462; band_h = b/33: 0.0062), reaches
    inwards to r = 0.961 b, 0.962 b (radial width 0.039 b, 0.038 b) and along the arc to
    |phi - pi| = 0.344, 0.352 rad. Without the band it is one vertex (the scene's meshes: 0.038 and
    0.019)."""
    out = []
    for bh in (0.02, 0.014):
        law = FEContact3D(TruncatedSphere(R, B_P), MAT, MU, F_max=F, h_contact=0.3, band=(bh, *BAND[1:]),
                          cache_dir=tmp_path)
        tl = law.assuming(tilt=TILT_PAPER)
        c = est.contact_mask(tl.model, tl.normal(F_N=F).p)
        mi = tl.model.mi
        k = tl.tilt_keys(F)
        out.append((k["contact_area_fraction"], 1 - mi.r[c].min() / B_P,
                    np.abs(np.arctan2(mi.y[c], mi.x[c]) - np.pi).max(), int(c.sum())))
    (f1, w1, a1, n1), (f2, w2, a2, n2) = out
    assert n1 >= 10 and n2 >= 10, out
    assert abs(f2 / f1 - 1) < 0.25 and 0.002 < f2 < 0.01, out  # measured 0.10 (b/33 against b/70: 0.34)
    assert abs(w2 - w1) < 0.01 and 0.02 < w2 < 0.06, out  # half an element of the coarser band
    assert abs(a2 - a1) < 0.03 and 0.2 < a2 < 0.45, out


# ------------------------------------------------------------------ the command


def test_cli_tilted_flat_punch(tmp_path, capsys):
    import json

    from fem.cli import main

    js = tmp_path / "out.json"
    argv = ["contact", "--model", "3d", "--profile", "flat", "--b", str(B_F), "--mu", "0.2", "--F0", "0.5",
            "--fa", "0.02", "--cycles", "3", "--steps", "8", "--h-contact", "0.3", "--tilt", str(2 * THC),
            "--cache-dir", str(tmp_path), "--json", str(js)]
    assert main(argv) == 0
    out = json.loads(js.read_text())
    assert out["tilt"] == pytest.approx(2 * THC, rel=1e-12)
    assert 0.3 < out["contact_area_fraction"] < 0.9
    assert out["contact_x_min"] == pytest.approx(-B_F, rel=1e-9) and out["contact_x_max"] < 0.5 * B_F
    assert out["contact_radius"] == pytest.approx(0.5 * (out["contact_x_max"] - out["contact_x_min"]), rel=1e-12)


@pytest.mark.parametrize("flags,msg", [
    (["--model", "3d", "--tilt", "0.1"], "tilt must be"),
    (["--model", "3d", "--tilt", "nan"], "tilt must be"),
    (["--tilt", "1e-4"], "--tilt applies to --model 3d"),
    (["--model", "3d", "--contact-extent", "1.25"], "contact_extent"),
])
def test_cli_tilt_bad_input(flags, msg, capsys):
    from fem.cli import main

    argv = ["contact", "--profile", "flat", "--b", "1e-4", "--mu", "0.2", "--F0", "0.5", "--fa", "0.05", *flags]
    assert main(argv) == 2
    assert msg in capsys.readouterr().err


def test_tilted_sphere_is_a_shifted_sphere(shared_mesh_cache):
    """A sphere tilted by theta is the same sphere moved by -R theta along x (r^2/2R + theta x =
    ((x + R theta)^2 + y^2)/2R - R theta^2/2): the Hertz contact, centred at x = -R theta.
    Measured at a/4, theta = 5e-4 (shift 0.109 a): pressure centroid within 0.7 % of the shift;
    the contact's x extent only to one element (vertex resolution)."""
    from mdr.profiles import Sphere

    law = FEContact3D(Sphere(R), MAT, MU, F_max=F, h_contact=0.25, cache_dir=shared_mesh_cache)
    a = ref.hertz(F, R, ES)["a"]
    t = law.assuming(tilt=5e-4)
    nr = t.normal(F_N=F)
    w = t.model.mi.A * nr.p
    shift = -R * 5e-4
    assert abs((w @ t.model.mi.x) / w.sum() / shift - 1) < 0.02
    keys = t.tilt_keys(F)
    h = 0.25 * a
    assert abs(keys["contact_x_min"] - (shift - a)) < h and abs(keys["contact_x_max"] - (shift + a)) < h
    # a tilt that moves the contact off the meshed disk is refused, never truncated
    from common.errors import ConvergenceError

    with pytest.raises(ConvergenceError, match="rim"):
        law.assuming(tilt=1e-3).normal(F_N=F)


@pytest.mark.slow
def test_tilted_face_in_the_apparatus_fig6():
    """The experiment of Fig. 6 (``studies.study.LOOP_CASES``: b = 0.6 mm, F0 = 0.31 N, dF = 0.2 F0,
    u_A = 90 nm, mu1 = 0.2, mu2 = 0.1, k_x = 1.9 N/um; 3 cycles of 80 steps) in the apparatus with the
    3D law through its trial steps, aligned and tilted on the same mesh (h = 0.3, 0.2 b;
    benchmarks/bench_tilt_apparatus.py prints the table). Aligned, the slip index is the MDR law's within
    0.2 % (measured 0.53074, 0.53094 against 0.53137); tilted by theta_c = 2.0e-6 rad it falls by
    0.14-0.15 %, by 3 theta_c 0.67-0.70 % (the two levels within 0.05 %), still within the catalogue's
    slip-index tolerance 0.005 (absolute)."""
    import warnings

    from mdr.apparatus import Apparatus, run_apparatus
    from mdr.law import MDRContact
    from studies.study import LOOP_CASES, R_IND, TABLE1_B, TABLE1_KX
    from validation.scenes import tilt_critical

    _, F0, ua, mu1, mu2 = LOOP_CASES["fig6"]
    prof, app = TruncatedSphere(R_IND, TABLE1_B), Apparatus(kx=TABLE1_KX, mu2=mu2)
    kw = dict(dF=0.2 * F0, alpha=0.0, ua=ua, cycles=3, steps=80)
    thc = tilt_critical(F0, TABLE1_B, ES)
    d_md = float(run_apparatus(MDRContact(prof, MAT, mu1, F_max=1.2 * F0, F_min=0.8 * F0, n=400), app, Loading.apparatus(F0, **kw))["slip_index"])
    eff = {}
    for h in (0.3, 0.2):
        law = FEContact3D(prof, MAT, mu1, F_max=1.2 * F0, h_contact=h, displacement="contact")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            d = [float(run_apparatus(law.assuming(tilt=k * thc), app, Loading.apparatus(F0, **kw))["slip_index"]) for k in (0.0, 1.0, 3.0)]
        assert abs(d[0] / d_md - 1) < 2e-3
        eff[h] = np.array(d[1:]) / d[0] - 1
    for e in eff.values():
        assert -4e-3 < e[0] < 0 and -0.015 < e[1] < -0.003 and abs(e[1] * d[0]) < 0.005
    assert np.all(np.abs(eff[0.3] - eff[0.2]) < 5e-4)


@pytest.mark.slow
def test_banded_face_in_the_apparatus_fig6_at_the_paper_tilt():
    """The experiment of Fig. 6 at the paper's bound pi/3600 (443 theta_c at F0 = 0.31 N) on the mesh
    banded along the loaded rim arc (``BAND``, band_h = b/50; 3 cycles of 40 steps, half the benchmark's):
    the edge crescent is resolved (16 vertices at F0) and the slip index falls by about a tenth
    (benchmarks/bench_tilt_apparatus.py --band, 80 steps: -10.3 % at b/50, -10.7 % at b/70), ten times
    the catalogue's slip-index tolerance 0.005: at the paper's bound the aligned answer does not hold."""
    import warnings

    from mdr.apparatus import Apparatus, run_apparatus
    from studies.study import LOOP_CASES, R_IND, TABLE1_B, TABLE1_KX

    _, F0, ua, mu1, mu2 = LOOP_CASES["fig6"]
    prof, app = TruncatedSphere(R_IND, TABLE1_B), Apparatus(kx=TABLE1_KX, mu2=mu2)
    kw = dict(dF=0.2 * F0, alpha=0.0, ua=ua, cycles=3, steps=40)
    law = FEContact3D(prof, MAT, mu1, F_max=1.2 * F0, h_contact=0.3, displacement="contact", band=BAND)
    tl = law.assuming(tilt=TILT_PAPER)
    assert int(est.contact_mask(tl.model, tl.normal(F_N=F0).p).sum()) >= 10
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        d0, d1 = (float(run_apparatus(x, app, Loading.apparatus(F0, **kw))["slip_index"]) for x in (law, tl))
    assert -0.2 < d1 / d0 - 1 < -0.05, (d0, d1)
    assert d0 - d1 > 0.02, (d0, d1)
