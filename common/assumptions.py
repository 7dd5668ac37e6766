"""The names of modelling assumptions that several models share, in one home (the 3D FE law,
``fem.solid3d.law``, and the rough half-space, ``rough.tangential``, read them)."""
from .errors import InputError

#: the tangential traction: "free" (two components, its direction free to turn with the slip) or "x"
#: (q_y = 0 everywhere: Mindlin's assumption; on the same discretisation the pair of the two isolates the
#: effect of the direction from the discretisation error). Where each model makes it:
#: - MDR: "x" by construction (one tangential spring per cell, along x: ``mdr.law``, ``mdr.law_traction``);
#: - the axisymmetric FE model: "x" by construction (one tangential force per contact pair: the
#:   assumptions of ``fem.axisym.friction``);
#: - the 3D FE model: either, default "free" (``fem.solid3d.law.FEContact3D(traction=...)``, ``.assuming``;
#:   ``python -m fem contact --model 3d --traction``);
#: - the rough half-space: either, default "x" (``rough.tangential.TangentialContact(traction=...)``).
TRACTIONS = ("free", "x")


def check_traction(traction) -> str:
    """``traction`` if it is one of ``TRACTIONS``; else an InputError naming them."""
    if traction not in TRACTIONS:
        raise InputError(f"traction must be one of {', '.join(TRACTIONS)}, got {traction!r}")
    return traction
