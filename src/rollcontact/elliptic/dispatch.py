"""The elliptic dispatcher :func:`solve_elliptic`: the same contract as the 2D :func:`rollcontact.solve`, over its
own registry of 3D methods.

Without a tolerance, ``"auto"`` takes the lowest-ranked registered method that can treat the scene, with its
defaults.  With ``tolerance=t`` it takes, over every applicable method, the cheapest setting whose error estimate
is at most t; a ``budget`` [s] bounds the modelled cost of what starts.  The choice, the escalation of adaptive
methods, the budget and the fallback are the 2D dispatcher's own (:func:`rollcontact.dispatch.within`), run over
:data:`ELLIPTIC_METHODS` with :class:`EllipticResult` for what is refused; an
:class:`~rollcontact.method.AccuracyModel` of a 3D method predicts

* ``error``: the largest of ``|dFx| / (mu Fn)``, ``|dFy| / (mu Fn)`` and ``|dMz| / (mu Fn c)`` [1] against the exact
  (Kalker's) steady solution, c = sqrt(ab);
* ``cost``: the modelled time of one solve [s] (``benchmarks/bench_elliptic_levels.py`` measures them).

Fallback: when the chosen method's answer fails or its error estimate says nothing
(:data:`~rollcontact.method.UNRESOLVED`), ``auto`` runs the cheapest method of higher rank registered as a fallback
(the discretised 3D solver, when registered), and reports ``info["fallback_from"]`` and ``info["fallback_reason"]``.
A named method never falls back.
"""

from __future__ import annotations

from rollcontact.dispatch import Budget, annotate, cheapest_setting, within
from rollcontact.elliptic.methods import discretised, fastsim, linear, strips
from rollcontact.elliptic.result import EllipticResult
from rollcontact.elliptic.scene import EllipticScene
from rollcontact.method import AccuracyModel, MethodSpec, check_tolerance

__all__ = ["BUILTIN", "ELLIPTIC_METHODS", "choose_elliptic_setting", "register_elliptic_method", "solve_elliptic"]

BUILTIN: tuple[MethodSpec, ...] = (strips.METHOD, fastsim.METHOD, linear.METHOD, discretised.METHOD)
"""The elliptic method table: the levels shipped with the package, one line each.  Their ranks order ``auto``
without a tolerance by expected accuracy: strips (10), FASTSIM (20), the linear theory (30); the discretised
solver (100) is the fallback, above them."""

ELLIPTIC_METHODS: dict[str, MethodSpec] = {spec.name: spec for spec in BUILTIN}
"""The registry :func:`solve_elliptic` dispatches over: :data:`BUILTIN` and what :func:`register_elliptic_method`
added."""


def register_elliptic_method(name: str, function, inapplicable, rank: int, *, fallback: bool = False,
                             accuracy: AccuracyModel | None = None) -> None:
    """Add (or replace) a 3D method in :data:`ELLIPTIC_METHODS` (the arguments of
    :func:`rollcontact.register_method`; ``function(scene, **options) -> EllipticResult``)."""
    ELLIPTIC_METHODS[name] = MethodSpec(name, function, inapplicable, rank, fallback, accuracy)


def choose_elliptic_setting(scene: EllipticScene, tolerance: float, names=None, budget: float | None = None):
    """The cheapest setting (method, options, error estimate, modelled cost [s]) over the applicable 3D methods
    whose error estimate is at most ``tolerance`` (else the most accurate); see
    :func:`rollcontact.dispatch.choose_setting`."""
    return cheapest_setting(scene, check_tolerance(tolerance), names, None if budget is None else Budget(budget),
                            registry=ELLIPTIC_METHODS)


def solve_elliptic(scene: EllipticScene, method: str = "auto", *, tolerance: float | None = None, methods=None,
                   budget: float | None = None, **options) -> EllipticResult:
    """Solve a steady elliptic rolling-contact scene: Fx, Fy [N] and Mz [N m] on the rail.

    Parameters
    ----------
    scene : EllipticScene
        The case.
    method : str
        ``"auto"`` or a name in :data:`ELLIPTIC_METHODS` (``"linear"``, ``"fastsim"``, ``"strips"``, and what is
        registered).  ``"auto"`` without a tolerance: the lowest-ranked applicable method with its defaults; with a
        tolerance the cheapest setting of any applicable method whose error estimate meets it (module docstring).
    tolerance : float, optional
        Requested error [1] of Fx and Fy over mu Fn and of Mz over mu Fn c, > 0.  With a named method: its
        cheapest setting that meets it, without fallback.
    methods : iterable of str, optional
        ``auto`` chooses and falls back only among these names.
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
        An unknown method (the message lists the valid ones), no method that can treat the scene (each one's
        reason, e.g. a/b outside a level's range), or an invalid tolerance or budget.
    """
    if not isinstance(scene, EllipticScene):
        raise TypeError(f"scene must be a rollcontact.EllipticScene, got {type(scene).__name__}")
    if method != "auto":
        if method not in ELLIPTIC_METHODS:
            raise ValueError(f"unknown elliptic method {method!r}; valid methods are "
                             f"{['auto', *sorted(ELLIPTIC_METHODS)]}")
        spec = ELLIPTIC_METHODS[method]
        if tolerance is None and budget is None:
            why = spec.inapplicable(scene)
            if why is not None:
                raise ValueError(f"method {method!r} cannot solve this scene: {why}")
            return annotate(spec, scene, options, spec.function(scene, **options))
        names, fallback = (method,), False
    else:
        names, fallback = (None if methods is None else tuple(methods)), True
    return within(scene, tolerance, names, fallback, budget, options, registry=ELLIPTIC_METHODS, refuse=refused)


def refused(scene: EllipticScene, name: str, message: str, over_budget: bool = True) -> EllipticResult:
    """An unsuccessful result of nothing solved, with the reason (the elliptic counterpart of
    :func:`rollcontact.dispatch.refused`)."""
    return EllipticResult.from_scene(scene, name, False, message, info={"over_budget": over_budget})
