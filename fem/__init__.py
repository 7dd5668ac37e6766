"""Finite-element contact of two finite elastic bodies (scikit-fem): an axisymmetric model and a 3D
half model, each for what it alone can answer, and what they share.

- ``fem.axisym``: Fourier modes 0 and 1 on one r-z mesh (``fem.axisym.law.FEContact``);
- ``fem.solid3d``: the 3D half model (``fem.solid3d.law.FEContact3D``);
- shared: ``solvers`` (sparse factorisation backends, BLAS threads), ``condense`` (a body's interface
  flexibility), ``bulk`` (the finite bodies' series compliance: axis probes and the half-space point
  solutions), ``contact_run`` (a fretting run of either model, ``python -m fem contact``; the 3D runs
  until they settle), ``apparatus`` (the FE law in ``python -m mdr apparatus --law fem``: ``studies``
  stands on ``fem``), ``cli`` (``python -m fem``).
"""
