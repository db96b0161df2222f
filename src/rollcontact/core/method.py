"""What a method is, for every geometry: the registry entry :class:`MethodSpec`, the accuracy-model interface
:class:`AccuracyModel` and the :class:`Setting` it proposes.

A module of its own so that the method modules of each geometry and the dispatch engine
(:mod:`rollcontact.core.dispatch`) both depend on it and not on each other.  A scene and a result are whatever the
geometry defines (the line contact's :class:`~rollcontact.line.scene.Scene` and
:class:`~rollcontact.line.result.ContactResult`, the elliptic contact's, ...); a result has ``method``, ``success``,
``message`` and an ``info`` dict.  An accuracy model predicts the error of a setting in its geometry's measure (the
line contact: the larger relative error of T' and p0; the elliptic contact: the largest of the forces' errors over
mu Fn) and its modelled cost; :data:`UNRESOLVED` is the estimate from which a result counts as saying nothing.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

from rollcontact.core.checks import check_real

ROUND_OFF = 1e-14
"""Relative error reported for results exact up to floating-point round-off."""


UNRESOLVED = 1.0
"""A result whose error estimate (in its geometry's measure, e.g. relative, of T' and p0) is at least this says
nothing reliable, not even the size of the answer: ``solve`` with ``"auto"`` treats it as a failure and falls back like
one (an error of the order of the answer itself leaves no digit to trust, whatever the method's own checks say;
``tests/dispatch/test_dispatch.py::test_auto_falls_back_where_the_error_estimate_says_nothing``)."""


class Setting(NamedTuple):
    """One way to run a method on a scene, with what it is predicted to achieve and to cost.

    Immutable; a named tuple rather than a frozen dataclass because ``auto`` builds one per solve and a frozen
    dataclass costs more to construct, a noticeable part of a closed-form solve.

    Attributes
    ----------
    method : str
        Registry name.
    options : dict
        Keyword options for the method.
    error_estimate : float
        Predicted relative error [1] of T' and p0 (the larger); NaN when the method has no accuracy model.
    cost : float
        Modelled time per solve [s]; NaN when the method has no accuracy model.
    """

    method: str
    options: dict
    error_estimate: float
    cost: float


class AccuracyModel:
    """How the error and the cost of a method depend on its options; what the tolerance-aware ``auto`` needs.

    Subclasses give :meth:`ladder` (option sets, cheapest first), :meth:`cost` and :meth:`error`;
    :meth:`achieved` may refine the error from a result, :meth:`escalation` and :meth:`retry` name finer settings
    after a result that misses the tolerance or fails, and :attr:`floor` is a lower bound of :meth:`cost`.
    """

    floor: float = 0.0
    """A lower bound [s] of :meth:`cost` over every scene and setting: ``auto`` skips the method without asking
    its scene-dependent :meth:`minimum_cost` once a setting at most this cheap is found."""

    def ladder(self, scene) -> tuple[dict, ...]:  # pragma: no cover - interface
        """Option sets worth considering for the scene, from the cheapest to the most accurate."""
        raise NotImplementedError

    def cost(self, scene, options: dict) -> float:  # pragma: no cover - interface
        """Modelled time per solve [s] with these options."""
        raise NotImplementedError

    def error(self, scene, options: dict) -> float:  # pragma: no cover - interface
        """Predicted relative error [1] of T' and p0 with these options (before solving)."""
        raise NotImplementedError

    def achieved(self, scene, options: dict, result, tolerance: float | None = None) -> float:
        """Error estimate [1] of a result obtained with these options; by default the prediction.

        With a ``tolerance`` the estimate only has to tell whether the result meets it: a model may then return a
        cheaper, larger bound that already does, rather than compute its best estimate."""
        return self.error(scene, options)

    def free_estimate(self, result) -> float:
        """A lower bound [1] of :meth:`achieved` that costs nothing beyond the solve (the FMU's model checks it
        every step without a tolerance, :func:`unresolved`); NaN (the default): none is known."""
        return math.nan

    def escalation(self, scene, options: dict, estimate: float, tolerance: float) -> dict | None:
        """Options to run next when a result obtained with ``options`` has the a-posteriori error ``estimate``
        above ``tolerance`` (an adaptive method); None (the default): nothing finer to try."""
        return None

    def retry(self, scene, options: dict, result) -> dict | None:
        """Options to run next when the result obtained with ``options`` failed, where a finer setting may
        succeed; None (the default): the failure stands."""
        return None

    def minimum_cost(self, scene) -> float:
        """Cost of the cheapest setting [s] (lets ``auto`` skip a method that cannot beat its best so far); the
        first of the ladder unless a subclass knows better without building it."""
        return self.cost(scene, self.ladder(scene)[0])

    def merged(self, options: dict, user: dict) -> dict:
        """The options to run: a chosen setting's ``options`` overridden by the caller's ``user`` options."""
        return {**options, **user}

    def setting_for(self, name: str, scene, tolerance: float) -> Setting:
        """The cheapest setting whose predicted error is at most ``tolerance``, else the most accurate one."""
        # plain tuples, one Setting at the end: auto runs this per solve, for every applicable method
        best = closest = None
        for options in self.ladder(scene):
            error = self.error(scene, options)
            if error <= tolerance:
                key = (self.cost(scene, options), -error)
                if best is None or key < best[0]:
                    best = (key, options)
            elif best is None:
                key = (nan_last(error), self.cost(scene, options))
                if closest is None or key < closest[0]:
                    closest = (key, options, error)
        if best is not None:
            (cost, error), options = best
            return Setting(name, options, -error, cost)
        (_, cost), options, error = closest
        return Setting(name, options, error, cost)


@dataclass(frozen=True)
class MethodSpec:
    """A registered method.

    Attributes
    ----------
    name : str
        Registry key.
    function : callable
        ``function(scene, **options) -> ContactResult``.
    inapplicable : callable
        ``inapplicable(scene) -> str | None``: why the method cannot give the exact answer for the scene, or
        None when it can (up to its own discretisation error).
    rank : int
        Order of preference of ``auto`` without a tolerance (lower is tried first; cheaper methods rank lower).
    fallback : bool
        Whether ``auto`` may use it when a cheaper method reports that its assumptions failed.
    accuracy : AccuracyModel or None
        Settings, error and cost model for the tolerance-aware choice; None: the method is used by ``auto``
        with a tolerance only when no modelled method applies.
    """

    name: str
    function: Callable[..., object]
    inapplicable: Callable[[object], str | None]
    rank: int
    fallback: bool = False
    accuracy: AccuracyModel | None = None


def unresolved(result, estimate: float | None = None) -> str | None:
    """Why a successful ``result`` still says nothing reliable (its error ``estimate``, by default
    ``info["error_estimate"]``, is at least :data:`UNRESOLVED`), or None (also without an estimate: then the
    method's success stands)."""
    if estimate is None:
        estimate = result.info.get("error_estimate", math.nan)
    if not estimate >= UNRESOLVED:
        return None
    return f"its error estimate {estimate:.3g} is at least {UNRESOLVED:g}: the scene is beyond what it resolves"


def check_tolerance(tolerance) -> float:
    """A requested relative error: finite and > 0 (a ValueError naming the value otherwise)."""
    return check_real("tolerance", tolerance, lower=0.0, lower_open=True, unit="1")


def nan_last(value: float) -> float:
    """``value``, with NaN as infinity (sorts last)."""
    return math.inf if math.isnan(value) else value
