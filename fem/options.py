"""The FE model's options as one value, checked once where they enter (``FEOptions``): the command
line (``fem.cli``), the apparatus (``fem.apparatus``) and a script alike. Which model, its mesh size,
its bodies' size, the displacement measure, the solver; the axisymmetric model's penalty and
augmented-Lagrangian tolerances; the 3D model's traction direction, tilt and mesh refinements.
An option of the other model is an error naming it, never silently ignored.
"""
from __future__ import annotations

from dataclasses import dataclass, field, fields
from pathlib import Path

import numpy as np

from common.errors import InputError, in_range, nonnegative, positive
from meshes.axisym import CONTACT_EXTENT_DEFAULT, H_CONTACT_DEFAULT, H_CONTACT_RANGE
from meshes.half3d import H_CONTACT_3D_DEFAULT, H_CONTACT_3D_RANGE, Refinement

#: the FE models: Fourier modes 0 + 1 on an r-z mesh (``fem.axisym``), the 3D half model (``fem.solid3d``)
MODELS = ("axisym", "3d")
#: the displacement measures (``fem.axisym.law``): half-space comparable, or the plates'
DISPLACEMENTS = ("contact", "plate")
#: options of one model only
AXISYM_ONLY = ("penalty", "al_tol", "friction_al_tol")
SOLID3D_ONLY = ("traction", "tilt", "refinement")


@dataclass(frozen=True)
class FEOptions:
    """How the FE side is built (SI; mesh sizes / a_ref).

    ``model`` (``MODELS``); ``h_contact`` element size on the contact zone / a_ref (None: the model's
    default, ``meshes.axisym.H_CONTACT_DEFAULT`` or ``meshes.half3d.H_CONTACT_3D_DEFAULT``, in the
    model's range); ``contact_extent`` candidate contact radius / a_ref (None: 1.25; the 3D flat punch
    takes its face); ``block_size`` (m; None: the model's default); ``displacement``
    (``DISPLACEMENTS``); ``cache_dir`` of meshes and condensed interfaces; ``backend`` the sparse
    solver (None: the best installed). Axisymmetric only: ``penalty``, ``al_tol``,
    ``friction_al_tol`` (None: the law's defaults). 3D only: ``traction`` ("free" or "x"; None:
    "free"), ``tilt`` (rad), ``refinement`` (``meshes.half3d.Refinement``)."""

    model: str = "axisym"
    h_contact: float | None = None
    contact_extent: float | None = None
    block_size: float | None = None
    displacement: str = "contact"
    cache_dir: str | None = None
    backend: str | None = None
    penalty: float | None = None
    al_tol: float | None = None
    friction_al_tol: float | None = None
    traction: str | None = None
    tilt: float = 0.0
    refinement: Refinement = field(default_factory=Refinement)

    def __post_init__(self):
        if self.model not in MODELS:
            raise InputError(f"model must be one of {', '.join(MODELS)}, got {self.model!r}")
        if self.displacement not in DISPLACEMENTS:
            raise InputError(f"displacement must be one of {', '.join(DISPLACEMENTS)}, got {self.displacement!r}")
        lo, hi = H_CONTACT_RANGE if self.model == "axisym" else H_CONTACT_3D_RANGE
        if self.h_contact is not None:
            object.__setattr__(self, "h_contact", in_range("h_contact", self.h_contact, lo, hi))
        ce, lowest = self.contact_extent, (1.0, "> 1") if self.model == "axisym" else (1.0, ">= 1")
        if ce is not None and not (np.ndim(ce) == 0 and np.isfinite(ce) and (ce > 1 or (ce == 1 and self.model == "3d"))):
            raise InputError(f"contact_extent must be {lowest[1]} for the {self.model} model (candidate contact radius "
                             f"/ a_ref, finite), got {ce!r}")
        if self.block_size is not None:
            positive("block_size", self.block_size)
        if self.cache_dir is not None and Path(self.cache_dir).exists() and not Path(self.cache_dir).is_dir():
            raise InputError(f"cache_dir must be a directory (mesh cache), got the file {str(self.cache_dir)!r}")
        if not isinstance(self.refinement, Refinement):
            raise InputError(f"refinement must be a meshes.half3d.Refinement, got {self.refinement!r}")
        if self.model == "axisym":
            self._only_3d()
            for name in AXISYM_ONLY:
                v = getattr(self, name)
                if v is not None:
                    (positive if name == "penalty" else nonnegative)(name, v)
        else:
            for name in AXISYM_ONLY:
                if getattr(self, name) is not None:
                    raise InputError(f"{name} applies to the axisymmetric model only (the 3D model's contact "
                                     "constraints are exact)")
            from fem.solid3d.law import check_assumptions, check_tilt

            if self.traction is not None:
                check_assumptions(self.traction, True)
            check_tilt(self.tilt)

    def _only_3d(self):
        if self.traction is not None:
            raise InputError("traction applies to the 3D model only (the axisymmetric model's traction is along x)")
        if self.tilt != 0:
            raise InputError(f"tilt is a parameter of the 3D model only (model '3d'), got tilt={self.tilt!r}")
        if self.refinement != Refinement():
            raise InputError("refinement (refine, ring, band of the mesh) applies to the 3D model only")

    @property
    def h(self) -> float:
        """The element size / a_ref in use (the model's default where none is given)."""
        if self.h_contact is not None:
            return self.h_contact
        return H_CONTACT_DEFAULT if self.model == "axisym" else H_CONTACT_3D_DEFAULT

    def replace(self, **changes) -> "FEOptions":
        """These options with ``changes``, checked again."""
        return FEOptions(**{**{f.name: getattr(self, f.name) for f in fields(self)}, **changes})

    def law(self, profile, materials, mu, F_max):
        """The FE law of these options for ``profile`` on ``materials`` with friction ``mu``, its mesh
        sized for the largest normal force ``F_max`` (N): ``fem.axisym.law.FEContact`` or
        ``fem.solid3d.law.FEContact3D``."""
        common = dict(F_max=F_max, h_contact=self.h, block_size=self.block_size, cache_dir=self.cache_dir,
                      backend=self.backend, displacement=self.displacement)
        if self.model == "3d":
            from fem.solid3d.law import FEContact3D

            r = self.refinement
            return FEContact3D(profile, materials, mu, contact_extent=self.contact_extent, traction=self.traction or "free",
                               tilt=self.tilt, refine=r.refine, ring=r.ring, band=r.band, **common)
        from fem.axisym.law import FEContact

        tuning = {k: getattr(self, k) for k in AXISYM_ONLY if getattr(self, k) is not None}
        ce = CONTACT_EXTENT_DEFAULT if self.contact_extent is None else self.contact_extent
        return FEContact(profile, materials, mu, contact_extent=ce, **tuning, **common)
