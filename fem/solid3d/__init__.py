"""The 3D half model (y >= 0): only for what the axisymmetric model assumes (the traction's direction,
normal-tangential coupling of a dissimilar pair) or cannot hold (a tilted face).

``elastic`` (P2 tetrahedra), ``interface`` (mortar interface and its condensation), ``condensed`` (the
condensed interfaces cached on disk), ``contact`` (normal, tangential and coupled contact solvers),
``law`` (``FEContact3D``).
"""
