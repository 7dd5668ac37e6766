"""The contact-law protocol: what the drivers, the apparatus and the validation need of a law.

Both laws of the project satisfy it: ``mdr.law.MDRContact`` (half-space, MDR)
and ``fem.axisym.law.FEContact`` (finite bodies, FE). A law is a pure step function
over an explicit, immutable state: the caller keeps the state, can try a step
and throw it away, and reads the state at any instant by keeping it (``run``
returns the final one in its History; ``mdr.drive.run_contact`` and
``mdr.apparatus.run_apparatus`` take ``state_at=k`` for the state after step k).

Normal load: ``d`` (approach) or ``F_N`` (normal force, >= 0; 0 = contact lost).
Tangential load: ``u`` (total relative displacement) or ``Fx`` (force, |Fx| < mu F_N).
``prepare`` is mandatory: the apparatus solves its equilibrium with the
trials' force and slope (there is no step-only fallback).

Also here: :class:`LawPlugin`, what a package registers under the entry-point
group ``fretting.contact_laws`` (``common.plugins``) to offer its law to
``python -m mdr apparatus --law NAME`` (the MDR and FE laws are built in).
"""
from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np


@runtime_checkable
class ContactTrial(Protocol):
    """The normal part of one step done, for many trial tangential displacements."""

    def force(self, u) -> tuple[Any, Any]:
        """(F_x, dF_x/du) at total tangential displacement u, nothing committed."""

    def commit(self, u) -> tuple[Any, Any]:
        """(``mdr.law.StepResult``, new state) of the step to u; equals ``step(state, u, ...)``."""


@runtime_checkable
class ContactLaw(Protocol):
    """A frictional contact law (see the module docstring)."""

    #: coefficient of friction (scalar or an array of the batch shape)
    mu: Any
    #: batch shape of the scenes the law runs at once (() for one scene)
    batch: tuple
    #: exponent of the slack's fall towards a stick edge (``mdr.stick``)
    stick_onset: float

    @property
    def stick_nodes(self) -> np.ndarray:
        """Radii of the nodes the stick radius is resolved on (``mdr.stick``)."""

    def describe(self) -> dict:
        """Plain-data description (the ``inputs.law`` key of results)."""

    def rest_state(self) -> Any:
        """The state with the bodies apart and no tangential history."""

    def contact_at(self, F_N) -> dict:
        """The law's own normal contact at the normal force ``F_N`` without tangential traction:
        ``contact_radius`` and ``indentation`` (m, half-space comparable), the keys every result
        of a run of the law reports (``mdr.drive.run_contact``, ``mdr.apparatus.apparatus_result``):
        a law's result never carries another model's numbers."""

    def normal_load(self, F_N) -> dict:
        """The keyword arguments of ``prepare``/``step`` that impose the normal forces
        ``F_N`` (an array of any shape batch + (T,)): ``{"d": ...}`` for a law that turns
        forces into approaches at once for a history, ``{"F_N": ...}`` for one that takes
        the force at each step. Slice the arrays at a step before use."""

    def step(self, state, u=None, *, d=None, F_N=None, Fx=None) -> tuple[Any, Any]:
        """(``mdr.law.StepResult``, new state) of one step; ``state`` is not modified."""

    def prepare(self, state, *, d=None, F_N=None) -> ContactTrial:
        """The normal part of a step (see :class:`ContactTrial`)."""

    def run(self, u=None, *, F_N=None, d=None, Fx=None, state=None, record_from: int | None = None) -> Any:
        """A whole load history from ``state`` (default at rest): ``mdr.law.History`` with the
        final state; ``record_from``: keep the per-node slip state from that step on."""


@runtime_checkable
class LawPlugin(Protocol):
    """A contact law offered to ``python -m mdr apparatus --law NAME`` and
    ``python -m mdr study fig8|fig9 --law NAME`` (``common.plugins``)."""

    help: str

    def add_arguments(self, parser) -> None:
        """Add the law's own flags to the apparatus and study commands' parsers."""

    def apparatus_result(self, profile, materials, app, mu, loading, args) -> dict:
        """The result dict of the apparatus command with this law under ``loading``
        (``mdr.loading.Loading.apparatus``; ``args``: the parsed flags)."""

    def make_law(self, profile, materials, mu, F_max, args, coarsen: float = 1.0) -> ContactLaw:
        """The law (one scene, reusable from its ``rest_state``) for the apparatus, as
        ``apparatus_result`` builds it, with its discretisation coarsened by the factor
        ``coarsen`` (1: as the flags say; 2: twice the element size), for the own error of
        a study from a ladder of ``coarsen`` = 2^(L-1) .. 2, 1."""

    def session(self):
        """A context manager that many runs of the law's ``make_law`` laws go inside (e.g.
        limiting the BLAS thread pools once instead of at every step)."""


#: the load arguments of the protocol's calls, as errors name them
_LOADS = {"d": ("d", "approach"), "F_N": ("F_N", "normal force"), "u": ("u", "tangential displacement"),
          "Fx": ("Fx", "tangential force")}
_NOT_ASKED = object()


def check_loads(call: str, *, d, F_N, u=_NOT_ASKED, Fx=_NOT_ASKED, history: bool = False) -> None:
    """The one rule of every law's ``step``, ``prepare`` and ``run``: exactly one of d / F_N, and where
    the call takes a tangential load, exactly one of u / Fx (``history``: the arguments are histories).
    InputError naming the call and the pair otherwise."""
    from common.errors import InputError

    pairs = [(("d", d), ("F_N", F_N))]
    if u is not _NOT_ASKED or Fx is not _NOT_ASKED:
        pairs.append((("u", None if u is _NOT_ASKED else u), ("Fx", None if Fx is _NOT_ASKED else Fx)))
    for (a, va), (b, vb) in pairs:
        if (va is None) == (vb is None):
            what = [f"{_LOADS[k][0]} ({_LOADS[k][1]}{' history' if history else ''})" for k in (a, b)]
            raise InputError(f"{call} needs exactly one of {what[0]} or {what[1]}")
