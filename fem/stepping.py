"""What the FE contact laws share (``fem.axisym.law.FEContact``, ``fem.solid3d.law.FEContact3D``):
read-only state arrays and the ``run`` of a law that advances one ``step`` at a time.

Assumptions: a law follows the step API of ``mdr.protocol`` with one scene (no batch): ``step``
returns (``mdr.law.StepResult`` of scalars with the slack and slip flags of its stick nodes, new
state) and ``rest_state`` the state at rest; its states are immutable, so their arrays are
frozen (``frozen``) and a caller may keep any of them.
"""
from __future__ import annotations

import numpy as np

from common.errors import InputError
from mdr.law import History
from mdr.protocol import check_loads


def frozen(a):
    """A read-only copy of ``a`` (floating point as float64, any other dtype kept)."""
    a = np.array(a, dtype=float if np.asarray(a).dtype.kind == "f" else np.asarray(a).dtype)
    a.setflags(write=False)
    return a


def step_history(law, n_nodes, *, u=None, F_N=None, d=None, Fx=None, state=None, record_from=None,
                 on_step=None) -> History:
    """The ``run`` of a law that advances one ``step`` at a time (the FE laws): a load history of
    arrays (T,) from ``state`` (default the law's rest state); the slack and slip flags of the
    ``n_nodes`` stick nodes kept from step ``record_from`` on; ``on_step(t, result, state)``
    called after every step. Returns mdr.law.History."""
    check_loads("run", d=d, F_N=F_N, u=u, Fx=Fx, history=True)
    drive = np.atleast_1d(np.asarray(u if u is not None else Fx, dtype=float))
    nT = drive.shape[-1]
    normal = np.broadcast_to(np.asarray(F_N if F_N is not None else d, dtype=float), (nT,))
    state = state if state is not None else law.rest_state()
    out = {k: np.empty(nT) for k in ("u", "Fx", "FN", "d", "a", "c", "work")}
    rec0 = nT if record_from is None else int(record_from)
    if not 0 <= rec0 <= nT:
        raise InputError(f"record_from must be a step index in [0, {nT}], got {record_from!r}")
    rec = {"slack": np.empty((nT - rec0, n_nodes)), "slipping": np.empty((nT - rec0, n_nodes), bool)}
    for t in range(nT):
        kw = {"F_N": normal[t]} if F_N is not None else {"d": normal[t]}
        res, state = law.step(state, **({"u": drive[t]} if u is not None else {"Fx": drive[t]}), **kw)
        for key in out:
            out[key][t] = getattr(res, key)
        if t >= rec0:
            rec["slack"][t - rec0] = res.slack
            rec["slipping"][t - rec0] = res.slipping
        if on_step is not None:
            on_step(t, res, state)
    return History(state=state, **out, **(rec if record_from is not None else {}))
