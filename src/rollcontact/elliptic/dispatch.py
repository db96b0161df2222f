"""The elliptic contact's dispatcher: its method table, registry and :func:`solve`, on the shared engine
(:class:`rollcontact.core.dispatch.Dispatcher`, whose docstring states the rules of ``auto``, tolerance, budget and
fallback).

Without a tolerance, ``"auto"`` takes the lowest-ranked registered method that can treat the scene, with its
defaults; the discretised 3D solver is the fallback.  An :class:`~rollcontact.core.method.AccuracyModel` of an
elliptic method predicts

* ``error``: the largest of ``|dFx| / (mu Fn)``, ``|dFy| / (mu Fn)`` and ``|dMz| / (mu Fn c)`` [1] against the exact
  (Kalker's) steady solution, c = sqrt(ab);
* ``cost``: the modelled time of one solve [s] (``benchmarks/calibrate_elliptic_levels.py`` measures them).
"""

from __future__ import annotations

from rollcontact.core.dispatch import Dispatcher
from rollcontact.core.method import MethodSpec
from rollcontact.elliptic.methods import discretised, fastsim, linear, saturated, strips
from rollcontact.elliptic.result import EllipticResult
from rollcontact.elliptic.scene import EllipticScene

__all__ = ["BUILTIN", "DISPATCHER", "METHODS", "choose_method", "choose_setting", "register_method", "setting_for",
           "solve"]

BUILTIN: tuple[MethodSpec, ...] = (strips.METHOD, fastsim.METHOD, saturated.METHOD, linear.METHOD, discretised.METHOD)
"""The elliptic method table: the levels shipped with the package, one line each.  Their ranks order ``auto``
without a tolerance by expected accuracy: strips (10), FASTSIM (20), the saturated linear theory (25), the linear
theory (30); the discretised solver (100) is the fallback, above them."""


def refused(scene: EllipticScene, name: str, message: str, over_budget: bool = True) -> EllipticResult:
    """An unsuccessful result of nothing solved, with the reason."""
    return EllipticResult.from_scene(scene, name, False, message, info={"over_budget": over_budget})


DISPATCHER = Dispatcher("elliptic", EllipticScene, BUILTIN, refused)

METHODS = DISPATCHER.methods
"""The registry :func:`solve` dispatches over: :data:`BUILTIN` and what :func:`register_method` added."""

register_method = DISPATCHER.register
choose_method = DISPATCHER.choose_method
choose_setting = DISPATCHER.choose_setting
setting_for = DISPATCHER.setting_for


def solve(scene: EllipticScene, method: str = "auto", *, tolerance: float | None = None, methods=None,
          estimate: str = "full", budget: float | None = None, **options) -> EllipticResult:
    """Solve a steady elliptic rolling-contact scene: Fx, Fy [N] and Mz [N m] on the rail.

    Parameters
    ----------
    scene : EllipticScene
        The case.
    method : str
        ``"auto"`` or a name in :data:`METHODS` (``"linear"``, ``"fastsim"``, ``"strips"``, ``"discretised"`` and
        what is registered).  ``"auto"`` without a tolerance: the lowest-ranked applicable method with its defaults;
        with a tolerance the cheapest setting of any applicable method whose error estimate meets it.
    tolerance : float, optional
        Requested error [1] of Fx and Fy over mu Fn and of Mz over mu Fn c, > 0.  With a named method: its
        cheapest setting that meets it, without fallback.
    methods : iterable of str, optional
        ``auto`` chooses and falls back only among these names.
    estimate : {"full", "free"}
        The error estimate reported without a tolerance: the method's full one, or the part that costs nothing
        beyond the solve.
    budget : float, optional
        The work [s] the solve may do, in the accuracy models' modelled seconds (no clock is read): a setting starts
        only while its cost fits what is left after the settings already run; when none fits, an unsuccessful
        result says why and nothing is solved.
    **options
        Passed to the method (each method's docstring); with ``"auto"`` only those the chosen method accepts.

    Returns
    -------
    EllipticResult
        ``info["error_estimate"]`` holds the method's estimate; with a tolerance also ``tolerance``,
        ``tolerance_met`` and ``setting``; after a fallback ``fallback_from`` and ``fallback_reason``.

    Raises
    ------
    ValueError
        An unknown method (the message lists the valid ones), a named method that cannot treat the scene, no method
        that can (each one's reason, e.g. a/b outside a level's range), or an invalid tolerance or budget.
    """
    return DISPATCHER.solve(scene, method, tolerance=tolerance, methods=methods, estimate=estimate, budget=budget,
                            **options)
