"""The values of the paper this project checks, in one place (SI): Willert, "Fretting in a
quasi-static apparatus", Machines 11 (2023) 484. Its steel (``mdr.materials``: E = 200 GPa,
nu = 0.29) is ``STEEL_E``, ``STEEL_NU`` there; everything else the paper fixes is here. Where a value
is a default of a function elsewhere (``mdr.loading.Loading.apparatus``, ``mdr.apparatus.Apparatus``,
the scenes of ``validation.scenes``), it is read from here.
"""
from __future__ import annotations

from .materials import STEEL_E, STEEL_NU

__all__ = ["B_TABLE1", "DF_OVER_F0", "KX_TABLE1", "MU2", "R_INDENTER", "STEEL_E", "STEEL_NU", "TABLE2", "UA_TABLE2"]

#: radius of the indenter's spherical cap (m), Section 2
R_INDENTER = 6e-3
#: Table 1: the truncated indenter's flat-face radius (m) and the normal axis's tangential stiffness (N/m)
B_TABLE1, KX_TABLE1 = 0.6e-3, 1.9e6
#: Table 2: normal force F0 and its amplitude dF (N), friction of the contact (mu1) and of the
#: bedding (mu2), piezo amplitude u_A (m)
TABLE2 = dict(F0=0.5, dF=0.1, mu1=0.2, mu2=0.1, ua=150e-9)
#: Table 2's piezo amplitude (m) and bedding friction, by name
UA_TABLE2, MU2 = TABLE2["ua"], TABLE2["mu2"]
#: the normal force's amplitude over its mean in the experiments of Figs. 4-7: Table 2's dF / F0
DF_OVER_F0 = TABLE2["dF"] / TABLE2["F0"]
