"""Rough surfaces for the half-space contact of the paper's specimens (issue: the paper's real surfaces).

``rough.surfaces``: self-affine, isotropic random height maps generated with tamaas (the rough-contact
library, ``pip install tamaas``) from stated parameters, or a measured topography read from a file
with its pixel size; their radially averaged power spectrum. The contact engine on these surfaces
comes next; this package depends on ``mdr`` only.
"""
