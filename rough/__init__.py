"""Rough surfaces for the half-space contact of the paper's specimens (issue: the paper's real surfaces).

``rough.surfaces``: self-affine, isotropic random height maps generated with tamaas (the rough-contact
library, ``pip install tamaas``) from stated parameters, or a measured topography read from a file
with its pixel size; their radially averaged power spectrum. ``rough.normal``: the frictionless normal
contact of an axisymmetric indenter with such a surface, FFT boundary elements on a periodic grid
(Polonsky & Keer's conjugate gradient; tamaas's solve its witness), with the pixel's and the period's
errors. ``rough.tangential``: the frictional tangential
contact with memory on the same grid (Coulomb cell by cell, Mindlin's traction along x or free to turn,
the cell-integrated Cerruti kernel), under any pressure field: loops and their dissipation. This package
depends on ``common`` and ``mdr`` only.
"""
