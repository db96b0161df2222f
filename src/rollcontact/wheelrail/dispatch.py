"""The wheel/rail contact's dispatcher: its method table, registry and :func:`solve`, on the shared engine
(:class:`rollcontact.core.dispatch.Dispatcher`, whose docstring states the rules of ``auto``, tolerance, budget and
fallback).

Without a tolerance ``auto`` takes the fast non-Hertzian strips, then Hertz's ellipses with the elliptic levels,
with the discretised patches as the reference and fallback.  An accuracy model of a wheel/rail level predicts the
largest error of its patches' forces (Fx, Fy over mu Fn, Mz over mu Fn c, c = sqrt(area / pi)) against the exact
(discretised) solution of the same planar patches.
"""

from __future__ import annotations

from rollcontact.core.dispatch import Dispatcher
from rollcontact.core.method import MethodSpec
from rollcontact.wheelrail.methods import discretised, hertz, strips
from rollcontact.wheelrail.result import WheelRailResult
from rollcontact.wheelrail.scene import WheelRailScene

__all__ = ["BUILTIN", "DISPATCHER", "METHODS", "choose_method", "choose_setting", "register_method", "setting_for",
           "solve"]

BUILTIN: tuple[MethodSpec, ...] = (strips.METHOD, hertz.METHOD, discretised.METHOD)
"""The wheel/rail method table: the strips (10), Hertz's ellipses (20), the discretised patches (100, the
fallback)."""


def refused(scene: WheelRailScene, name: str, message: str, over_budget: bool = True) -> WheelRailResult:
    """An unsuccessful result of nothing solved, with the reason."""
    return WheelRailResult(name, False, message, (), {"over_budget": over_budget})


DISPATCHER = Dispatcher("wheel/rail", WheelRailScene, BUILTIN, refused)

METHODS = DISPATCHER.methods
"""The registry :func:`solve` dispatches over: :data:`BUILTIN` and what :func:`register_method` added."""

register_method = DISPATCHER.register
choose_method = DISPATCHER.choose_method
choose_setting = DISPATCHER.choose_setting
setting_for = DISPATCHER.setting_for


def solve(scene: WheelRailScene, method: str = "auto", *, tolerance: float | None = None, methods=None,
          estimate: str = "full", budget: float | None = None, **options) -> WheelRailResult:
    """Solve a wheelset on its track: both wheels' patches, their normal and creep forces.

    Parameters
    ----------
    scene : WheelRailScene
        The case.
    method : str
        ``"auto"`` or a name in :data:`METHODS` (``"strips"``, ``"hertz"``, ``"discretised"`` and what is
        registered).  ``"auto"`` without a tolerance: the lowest-ranked level that applies; with a tolerance the
        cheapest setting of any applicable level whose error estimate meets it.
    tolerance : float, optional
        Requested error [1] of each patch's Fx and Fy over mu Fn and Mz over mu Fn c, > 0.
    methods : iterable of str, optional
        ``auto`` chooses and falls back only among these names.
    estimate : {"full", "free"}
        The error estimate reported without a tolerance.
    budget : float, optional
        The work [s] the solve may do, in the accuracy models' modelled seconds (no clock is read).
    **options
        Passed to the level (``elliptic`` for ``"hertz"``; the patch level's options for the others, and ``starts``:
        a result of the same level on the same geometry whose normal solutions this solve's start from,
        :func:`~rollcontact.wheelrail.wheels.solve_wheels`).

    Returns
    -------
    WheelRailResult
        ``info["error_estimate"]`` the largest of the patches'; with a tolerance also ``tolerance``,
        ``tolerance_met`` and ``setting``; after a fallback ``fallback_from`` and ``fallback_reason``.

    Raises
    ------
    ValueError
        An unknown method, a named method that cannot treat the scene, or an invalid tolerance or budget.
    """
    return DISPATCHER.solve(scene, method, tolerance=tolerance, methods=methods, estimate=estimate, budget=budget,
                            **options)
