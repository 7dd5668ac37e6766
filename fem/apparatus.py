"""The FE contact law in the apparatus: ``python -m mdr apparatus --law fem``.

The command (``studies.cli``, a layer above ``fem``) takes :data:`fem.cli.FE_LAW` (in ``fem.cli``,
so building the parser stays cheap): it adds the FE flags and calls :func:`fem_apparatus_result`
here. The apparatus model itself (``mdr.apparatus``) knows only the contact-law protocol.
"""
from __future__ import annotations

import time


from mdr.apparatus import Apparatus, apparatus_result
from mdr.loading import Loading
from common.errors import InputError, nonnegative

from fem.axisym.law import FEContact
from fem.options import FEOptions
from fem.solvers import blas_threads


def fem_apparatus_law(profile, materials, mu, F_max, options: FEOptions = FEOptions()) -> FEContact:
    """The FE law of the apparatus: the axisymmetric ``fem.axisym.law.FEContact`` of ``options``
    (``fem.options.FEOptions``, checked when it was made) with displacement "contact". Its
    displacement excludes the finite bodies' bulk compliance, so it stands where the half-space law
    stands and the apparatus compliances are not counted twice (see ``fem.axisym.law``). The law is
    pure (explicit state): one law serves every apparatus scene of its geometry, materials, mu and
    F_max."""
    nonnegative("mu", mu)
    if options.model != "axisym":
        raise InputError(f"the apparatus runs the axisymmetric FE model (fem.options.FEOptions.model 'axisym'), got "
                         f"{options.model!r}")
    return options.replace(displacement="contact").law(profile, materials, mu, F_max)


def fem_apparatus_result(profile, materials, app: Apparatus, mu, loading: Loading,
                         options: FEOptions = FEOptions()) -> dict:
    """One apparatus scene with the FE contact law (``python -m mdr apparatus --law fem``).

    The law is :func:`fem_apparatus_law` of ``options`` with ``F_max = F0 + dF`` of ``loading``
    (``Loading.apparatus``). Keys: those of :func:`apparatus_result` (with
    ``contact_radius``/``indentation`` the FE's own at F0) plus ``dofs``, ``mesh``,
    ``solver`` and ``runtime_s`` = {setup, cycles, total} like ``python -m fem contact``.
    The load is checked (a ``Loading``) before the (costly) FE set-up.
    """
    t0 = time.perf_counter()
    with blas_threads(1):  # once for the whole run: the law's steps are many small dense solves
        law = fem_apparatus_law(profile, materials, mu, loading.F_max, options)
        t1 = time.perf_counter()
        out = apparatus_result(law, app, loading)
    t2 = time.perf_counter()
    out.update(law.result_keys(loading.F0, t0, t1, t2))
    out["inputs"]["law"] = law.describe()
    return out
