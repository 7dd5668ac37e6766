"""The names of modelling assumptions that several models share, in one home (the 3D FE law,
``fem.solid3d.law``, and the rough half-space, ``rough.tangential``, read them)."""
from .errors import InputError

#: the tangential traction: "free" (two components, its direction free to turn with the slip) or "x"
#: (q_y = 0 everywhere: Mindlin's assumption, as in the axisymmetric model and MDR; on the same
#: discretisation the pair of the two isolates the effect of the direction from the discretisation error)
TRACTIONS = ("free", "x")


def check_traction(traction) -> str:
    """``traction`` if it is one of ``TRACTIONS``; else an InputError naming them."""
    if traction not in TRACTIONS:
        raise InputError(f"traction must be one of {', '.join(TRACTIONS)}, got {traction!r}")
    return traction
