"""The line contact's dispatcher: its method table, registry and :func:`solve`, on the shared engine
(:class:`rollcontact.core.dispatch.Dispatcher`, whose docstring states the rules of ``auto``, tolerance, budget and
fallback).

Without a tolerance ``auto`` takes the cheapest exact method that can treat the scene: the closed forms, then the
polynomial method, then the discretised one (the fallback).  An accuracy model of a line method predicts the larger
relative error of T' and of the peak pressure p0 (:mod:`rollcontact.line.methods.polynomial.accuracy`,
:mod:`rollcontact.line.methods.discretised.accuracy`, :mod:`rollcontact.line.methods.closed_form`).
"""

from __future__ import annotations

import math

from rollcontact.core.dispatch import Dispatcher
from rollcontact.core.method import MethodSpec
from rollcontact.line.methods import closed_form, discretised, polynomial
from rollcontact.line.result import ContactResult
from rollcontact.line.scene import Scene

__all__ = ["BUILTIN", "DISPATCHER", "METHODS", "choose_method", "choose_setting", "register_method", "setting_for",
           "solve"]

BUILTIN: tuple[MethodSpec, ...] = (
    closed_form.METHOD,
    polynomial.METHOD,
    discretised.METHOD,
)
"""The method table: the line contact's fidelity levels shipped with the package, one line each."""


def refused(scene: Scene, name: str, message: str, over_budget: bool = True) -> ContactResult:
    """An unsuccessful result of nothing solved, with the reason."""
    nan = math.nan
    return ContactResult(name, False, message, scene.normal_load_per_length, nan, scene.creep, nan, nan, nan, nan,
                         info={"over_budget": over_budget})


DISPATCHER = Dispatcher("line", Scene, BUILTIN, refused)

METHODS = DISPATCHER.methods
"""The registry :func:`solve` dispatches over: :data:`BUILTIN` and whatever :func:`register_method` added."""

register_method = DISPATCHER.register
choose_method = DISPATCHER.choose_method
choose_setting = DISPATCHER.choose_setting
setting_for = DISPATCHER.setting_for


def solve(scene: Scene, method: str = "auto", *, tolerance: float | None = None, methods=None,
          estimate: str = "full", budget: float | None = None, **options) -> ContactResult:
    """Solve a steady line-contact scene.

    Parameters
    ----------
    scene : Scene
        The case.
    method : str
        ``"auto"`` or a name in :data:`METHODS`.  ``"auto"`` without a tolerance takes the lowest-ranked method
        that can treat the scene, with its defaults; with ``tolerance`` the cheapest setting of any applicable
        method whose error estimate meets it.  When the answer fails (its validity checks, its convergence, an
        arithmetic error) or its error estimate says nothing (:data:`~rollcontact.core.method.UNRESOLVED`),
        ``auto`` falls back to the cheapest method of higher rank registered as a fallback (``"discretised"``).
    tolerance : float, optional
        Requested relative error [1] of T' and p0, > 0.  With a named method: that method's cheapest setting whose
        error estimate meets it, without fallback.
    methods : iterable of str, optional
        ``auto`` chooses and falls back only among these registered names (default: all).
    estimate : {"full", "free"}
        Without a tolerance, ``info["error_estimate"]`` is the method's full estimate (``"full"``), or only the part
        that costs nothing beyond the solve (``"free"``: a lower bound, NaN where none is known), which is what
        ``auto`` then checks against :data:`~rollcontact.core.method.UNRESOLVED`.  The stepping model asks for
        ``"free"``.
    budget : float, optional
        The work [s] the solve may do, in the accuracy models' modelled seconds (calibrated by
        ``benchmarks/pareto.py``; no clock is read): a setting starts only while its modelled cost fits what is left
        after the settings already run.  With a tolerance: the cheapest setting that meets it within the budget,
        else the most accurate that fits (the message says so); without: the method's default setting when it fits,
        else the most accurate that does.  When none fits, an unsuccessful result says why, and nothing is solved.
        A method without an accuracy model has no cost model: it runs unbounded.  :func:`choose_setting` gives the
        setting and its modelled cost before solving; the result reports it as ``info["predicted_cost"]``, and the
        modelled cost of everything the solve ran as ``info["modelled_cost"]``.
    **options
        Passed to the method (see each method's docstring).  With ``"auto"``, or with a tolerance, they override
        the chosen setting's and only those the chosen method accepts are passed.

    Returns
    -------
    ContactResult
        ``success`` is False, with a message, when the method's assumptions failed or it did not converge.
        ``info["error_estimate"]`` holds the estimated relative error of T' and p0 when the method has an
        accuracy model; with a tolerance also ``tolerance``, ``tolerance_met`` and ``setting`` (options used).
        After a fallback ``info["fallback_from"]`` and ``info["fallback_reason"]`` name the method that failed.

    Raises
    ------
    ValueError
        Unknown method name (the message lists the valid ones), a named method that cannot treat the scene, no
        method that can, or an invalid tolerance or ``estimate``.
    """
    return DISPATCHER.solve(scene, method, tolerance=tolerance, methods=methods, estimate=estimate, budget=budget,
                            **options)
