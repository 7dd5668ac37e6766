"""MDR contact law for axisymmetric fretting contacts and the apparatus model around it.

Public API::

    from mdr import Materials, Sphere, TruncatedSphere, FlatPunch, GeneralProfile, MDRContact
"""
from .errors import ConvergenceError, InputError
from .law import LawState, MDRContact, StepResult
from .materials import Materials
from .profiles import FlatPunch, GeneralProfile, Sphere, TruncatedSphere, make_profile

__all__ = ["ConvergenceError", "InputError", "LawState", "MDRContact", "StepResult", "Materials",
           "FlatPunch", "GeneralProfile", "Sphere", "TruncatedSphere", "make_profile"]
