"""The axisymmetric model: Fourier modes 0 and 1 on one r-z mesh (exact for an axisymmetric body under a
tangential load with linear elasticity and Mindlin's uncoupled friction).

``mode0`` (mode-0 weak forms and stresses), ``interface`` (small-sliding contact pairs), ``model``
(boundary conditions, set-up once per mesh), ``normal`` (penalty / augmented-Lagrangian contact and the
half-space-comparable indentation), ``normal_run`` (one normal-contact run, ``python -m fem normal``);
tangential loading: ``mode1`` (Fourier mode-1 weak forms, axis regularity), ``friction`` (Coulomb return
map, active-set interface solver, augmented Lagrangian), ``law`` (``FEContact``, the contact-law protocol
of ``mdr.protocol``); ``output`` (its fields at an instant, VTU).
"""
