"""MDR contact law for axisymmetric fretting contacts and the apparatus model around it.

Public API::

    from mdr import Materials, Sphere, TruncatedSphere, FlatPunch, GeneralProfile, MDRContact

The contact-law protocol every law follows (``MDRContact`` here, ``fem.axisym.law.FEContact``)
is ``mdr.protocol.ContactLaw``. ``mdr`` is physics: it imports only ``common`` (errors, io, the CLI
parser); ``meshes``, ``fem``, ``studies`` (the paper's studies and this package's command) and
``validation`` build on it.
"""
from common.errors import ConvergenceError, InputError
from .law import LawState, MDRContact, StepResult
from .materials import Materials
from .profiles import FlatPunch, GeneralProfile, Sphere, TruncatedSphere, make_profile
from .protocol import ContactLaw

__all__ = ["ContactLaw", "ConvergenceError", "InputError", "LawState", "MDRContact", "StepResult", "Materials",
           "FlatPunch", "GeneralProfile", "Sphere", "TruncatedSphere", "make_profile"]
