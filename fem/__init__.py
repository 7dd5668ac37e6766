"""Finite-element contact of two finite elastic bodies (scikit-fem), axisymmetric so far.

One file per assumption: ``axisym`` (mode-0 weak forms), ``interface`` (small-
sliding contact pairs), ``condense`` (interface flexibility), ``solvers``
(sparse factorisation backends, BLAS threads), ``model`` (boundary conditions,
set-up once per mesh), ``normal`` (penalty / augmented-Lagrangian contact and
the half-space-comparable indentation), ``output`` (fields, VTU), ``run`` and
``cli`` (``python -m fem normal``); tangential loading: ``mode1`` (Fourier
mode-1 weak forms, axis regularity), ``friction`` (Coulomb return map, active-set
interface solver, augmented Lagrangian), ``law`` (``FEContact``, the contact-law
protocol of ``mdr.protocol``), ``contact_run`` (``python -m fem contact``), ``apparatus``
(the FE law in ``python -m mdr apparatus --law fem``, reached as an entry-point
plugin: ``mdr`` never imports ``fem``).
"""
