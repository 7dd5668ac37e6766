"""The FE options as one checked value (``fem.options.FEOptions``): an option of the other model is an
error naming it, every range is checked once when the value is made, and the law it builds is the
law the direct call builds."""
import pytest

from common.errors import InputError
from fem.options import FEOptions
from meshes.axisym import H_CONTACT_DEFAULT, H_CONTACT_RANGE
from meshes.half3d import H_CONTACT_3D_DEFAULT, H_CONTACT_3D_RANGE, Refinement


@pytest.mark.parametrize("kw, msg", [
    (dict(model="2d"), "model must be one of axisym, 3d"),
    (dict(displacement="plates"), "displacement must be one of contact, plate"),
    (dict(h_contact=H_CONTACT_RANGE[1] * 1.01), "h_contact must be in"),
    (dict(model="3d", h_contact=H_CONTACT_3D_RANGE[1] * 1.01), "h_contact must be in"),
    (dict(contact_extent=1.0), "contact_extent must be > 1 for the axisym model"),
    (dict(model="3d", contact_extent=0.9), "contact_extent must be >= 1 for the 3d model"),
    (dict(block_size=-1.0), "block_size"),
    (dict(penalty=0.0), "penalty"),
    (dict(al_tol=-1e-3), "al_tol"),
    (dict(traction="x"), "traction applies to the 3D model only"),
    (dict(tilt=1e-4), "tilt is a parameter of the 3D model only"),
    (dict(refinement=Refinement(ring=(0.9, 0.18, 0.05))), "refinement (refine, ring, band of the mesh) applies to the 3D"),
    (dict(model="3d", penalty=10.0), "penalty applies to the axisymmetric model only"),
    (dict(model="3d", friction_al_tol=1e-3), "friction_al_tol applies to the axisymmetric model only"),
    (dict(model="3d", traction="y"), "traction must be one of free, x"),
    (dict(model="3d", tilt=0.1), "tilt must be one finite number in"),
    (dict(model="3d", refinement=(0.9, 0.18, 0.05)), "refinement must be a meshes.half3d.Refinement"),
])
def test_bad_options_name_the_parameter(kw, msg):
    with pytest.raises(InputError, match=msg.replace("(", r"\(").replace(")", r"\)")):
        FEOptions(**kw)


def test_refinement_shapes_checked_once():
    with pytest.raises(InputError, match="ring must be None or"):
        Refinement(ring=(0.9, 0.18))
    with pytest.raises(InputError, match="ring or band, not both"):
        Refinement(ring=(0.9, 0.18, 0.05), band=(0.02, 0.06, 0.45))
    r = Refinement(ring=[0.9, 0.18, 0.05])
    assert r.ring == (0.9, 0.18, 0.05) and r.mesh_fields()["band_r"] == 0.9
    assert r.mesh_fields()["band_angle"] == pytest.approx(3.141592653589793)
    assert all(v is None for v in Refinement().mesh_fields().values())


def test_defaults_and_replace():
    assert FEOptions().h == H_CONTACT_DEFAULT and FEOptions(model="3d").h == H_CONTACT_3D_DEFAULT
    o = FEOptions(h_contact=0.05)
    assert o.replace(h_contact=0.1).h == 0.1 and o.h == 0.05
    with pytest.raises(InputError, match="traction applies"):
        o.replace(traction="free")  # a changed value is checked again


def test_options_build_the_direct_law(tmp_path):
    """The law of the options is the law the direct call builds: the same mesh (cache key) and the
    same normal solution."""
    from fem.axisym.law import FEContact
    from mdr.materials import Materials
    from mdr.profiles import Sphere

    prof, mat, F = Sphere(6e-3), Materials(), 0.5
    a = FEOptions(h_contact=0.1, cache_dir=str(tmp_path), displacement="plate").law(prof, mat, 0.2, F)
    b = FEContact(prof, mat, 0.2, F_max=F, h_contact=0.1, cache_dir=str(tmp_path), displacement="plate")
    assert isinstance(a, FEContact) and a.describe() == b.describe()
    assert a.normal(F_N=F).contact_radius == b.normal(F_N=F).contact_radius


def test_cli_rejects_the_other_models_flags(capsys):
    """``python -m fem contact --model 3d --penalty ...`` is bad input (exit 2), not silently ignored."""
    from fem.cli import main

    base = ["contact", "--profile", "sphere", "--R", "6e-3", "--mu", "0.2", "--F0", "0.5", "--fa", "0.05"]
    assert main([*base, "--model", "3d", "--penalty", "10"]) == 2
    assert "--penalty applies to --model axisym only" in capsys.readouterr().err
    assert main([*base, "--tilt", "1e-4"]) == 2
    assert "--tilt applies to --model 3d only" in capsys.readouterr().err
