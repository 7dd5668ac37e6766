"""The values the MDR contact law (``mdr.law.MDRContact``) hands around: its state, the normal
phase of a step, the result of a step and the history of a run.

Plain data over numpy arrays of a batch shape ``batch`` (per spring cell: batch + (n,); per step
of a run: batch + (T,)). ``LawState``, ``NormalPhase`` and ``StepResult`` are frozen: a step
returns new values and leaves the old ones as they were.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from common.errors import InputError
from .stick import stick_radius


@dataclass(frozen=True)
class LawState:
    """History of the contact: per-cell elastic tangential displacement ``v``,
    in-contact cell length ``ell`` (both batch + (n,)), total tangential relative
    displacement ``u`` and approach ``d`` (batch)."""

    v: np.ndarray
    ell: np.ndarray
    u: np.ndarray
    d: np.ndarray


@dataclass(frozen=True)
class NormalPhase:
    """Normal contact at approach d: contact radius a, per-cell in-contact
    length ell, normal force N (one side, N >= 0) and tangential slip limit vmax."""

    d: np.ndarray
    a: np.ndarray
    ell: np.ndarray
    N: np.ndarray
    vmax: np.ndarray
    FN: np.ndarray


@dataclass(frozen=True)
class StepResult:
    """Outputs of one step (SI): forces, approach, contact and stick radii, the
    tangential relative displacement and the friction work done in the step;
    per node of the law's ``stick_nodes``, the slack to the slip limit and whether
    the node slipped or was out of contact in the step (``mdr.stick``)."""

    Fx: np.ndarray
    FN: np.ndarray
    d: np.ndarray
    a: np.ndarray
    c: np.ndarray
    u: np.ndarray
    work: np.ndarray
    slack: np.ndarray | None = field(default=None, compare=False, repr=False)
    slipping: np.ndarray | None = field(default=None, compare=False, repr=False)


@dataclass
class History:
    """Time series of a run (arrays batch + (T,)) and the final state."""

    u: np.ndarray
    Fx: np.ndarray
    FN: np.ndarray
    d: np.ndarray
    a: np.ndarray
    c: np.ndarray
    work: np.ndarray
    state: LawState = field(repr=False)
    slack: np.ndarray | None = field(default=None, repr=False)
    slipping: np.ndarray | None = field(default=None, repr=False)
    #: what a law records per step beyond the protocol's arrays: {name: sequence over the T steps}
    #: (the 3D FE law's vertex tractions and pressures); None where it records nothing
    fields: dict | None = field(default=None, repr=False)

    def then(self, later: "History") -> "History":
        """This history followed by ``later`` (a run from this one's final state): the arrays joined
        along time, the recorded window and fields too; the final state ``later``'s."""
        def join(a, b, axis):
            return None if a is None or b is None else np.concatenate([a, b], axis=axis)

        fields = None
        if self.fields is not None and later.fields is not None:
            fields = {k: tuple(self.fields[k]) + tuple(later.fields[k]) for k in self.fields}
        return type(later)(state=later.state, **{f: np.concatenate([getattr(self, f), getattr(later, f)], axis=-1)
                                                 for f in ("u", "Fx", "FN", "d", "a", "c", "work")},
                           slack=join(self.slack, later.slack, -2), slipping=join(self.slipping, later.slipping, -2),
                           fields=fields)

    def window_stick_radius(self, law):
        """Stick radius (``mdr.stick``) over the recorded steps (``run(record_from=...)``)."""
        if self.slack is None:
            raise InputError("the history has no recorded slip state: run it with record_from=<first step>")
        T = self.slack.shape[-2]
        return stick_radius(law.stick_nodes, self.slack, self.slipping, self.a[..., -T:], law.stick_onset)
