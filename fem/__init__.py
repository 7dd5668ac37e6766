"""Finite-element contact of two finite elastic bodies (scikit-fem): an axisymmetric model (Fourier
modes 0 and 1 on one r-z mesh) and a 3D half model, each for what it alone can answer.

Axisymmetric: ``axisym`` (mode-0 weak forms), ``interface`` (small-sliding contact pairs),
``condense`` (interface flexibility), ``model`` (boundary conditions, set-up once per mesh),
``normal`` (penalty / augmented-Lagrangian contact and the half-space-comparable indentation),
``normal_run`` (one normal-contact run, ``python -m fem normal``); tangential loading: ``mode1`` (Fourier
mode-1 weak forms, axis regularity), ``friction`` (Coulomb return map, active-set interface solver,
augmented Lagrangian), ``law`` (``FEContact``, the contact-law protocol of ``mdr.protocol``).

3D half model: ``elastic3d`` (P2 tetrahedra), ``interface3d`` (mortar interface and its
condensation), ``condensed3d`` (the condensed interfaces cached on disk), ``contact3d`` (normal,
tangential and coupled contact solvers), ``law3d`` (``FEContact3D``).

Shared: ``solvers`` (sparse factorisation backends, BLAS threads), ``bulk`` (the finite bodies'
series compliance), ``output`` (fields, VTU), ``contact_run`` (a fretting run of either model,
``python -m fem contact``; the 3D runs until they settle), ``cli`` (``python -m fem``), ``apparatus``
(the FE law in ``python -m mdr apparatus --law fem``: ``studies`` stands on ``fem``).
"""
