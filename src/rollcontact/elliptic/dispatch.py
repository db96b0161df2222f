"""The elliptic dispatcher :func:`solve_elliptic`: the same contract as the 2D :func:`rollcontact.solve`, over its
own registry of 3D methods.

Without a tolerance, ``"auto"`` takes the lowest-ranked registered method that can treat the scene, with its
defaults.  With ``tolerance=t`` it takes, over every applicable method, the cheapest setting whose error estimate
is at most t; a ``budget`` [s] bounds the modelled cost of what starts.  The choice, the escalation of adaptive
methods and the budget are the 2D dispatcher's own functions (:func:`rollcontact.dispatch.cheapest_setting`,
:func:`~rollcontact.dispatch.run_to_tolerance`, :class:`~rollcontact.dispatch.Budget`), run over
:data:`ELLIPTIC_METHODS`; an :class:`~rollcontact.method.AccuracyModel` of a 3D method predicts

* ``error``: the largest of ``|dFx| / (mu Fn)``, ``|dFy| / (mu Fn)`` and ``|dMz| / (mu Fn c)`` [1] against the exact
  (Kalker's) steady solution, c = sqrt(ab);
* ``cost``: the modelled time of one solve [s] (``benchmarks/bench_elliptic_levels.py`` measures them).

Fallback: when the chosen method's answer fails or its error estimate says nothing
(:data:`~rollcontact.method.UNRESOLVED`), ``auto`` runs the cheapest method of higher rank registered as a fallback
(the discretised 3D solver, when registered), and reports ``info["fallback_from"]`` and ``info["fallback_reason"]``.
A named method never falls back.
"""

from __future__ import annotations

from rollcontact.dispatch import (
    Budget,
    OverBudget,
    annotate,
    by_rank,
    call_with_known_options,
    cheapest_setting,
    run_to_tolerance,
    used_options,
    within_budget,
    without_fallback,
)
from rollcontact.elliptic.methods import discretised, fastsim, linear, strips
from rollcontact.elliptic.result import EllipticResult
from rollcontact.elliptic.scene import EllipticScene
from rollcontact.method import AccuracyModel, MethodSpec, check_tolerance, unresolved

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


def choose_elliptic_method(scene: EllipticScene, names=None) -> MethodSpec:
    """The lowest-ranked registered method (among ``names``) that can treat the scene; a ValueError naming every
    method's reason otherwise."""
    reasons = []
    for spec in by_rank(ELLIPTIC_METHODS):
        if names is not None and spec.name not in names:
            continue
        why = spec.inapplicable(scene)
        if why is None:
            return spec
        reasons.append(f"{spec.name}: {why}")
    raise ValueError("no registered elliptic method can solve this scene (" + "; ".join(reasons) + ")")


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
    budget = None if budget is None else Budget(budget)
    if tolerance is None:
        spec = choose_elliptic_method(scene, names)
        result = run_default(spec, scene, options, budget)
    else:
        tolerance = check_tolerance(tolerance)
        try:
            setting = cheapest_setting(scene, tolerance, names, budget, registry=ELLIPTIC_METHODS)
        except OverBudget as exc:
            return EllipticResult.from_scene(scene, "auto", False, str(exc), info={"over_budget": True})
        spec, result = run_to_tolerance(setting, scene, options, tolerance, budget, registry=ELLIPTIC_METHODS)
    reason = result.message if not result.success else unresolved(result)
    if reason is None or not fallback or result.info.get("over_budget"):
        return result
    backups = [s for s in ELLIPTIC_METHODS.values() if s.fallback and s.rank > spec.rank
               and (names is None or s.name in names) and s.inapplicable(scene) is None]
    if not backups:
        return result
    if tolerance is None:
        backup = run_default(min(backups, key=lambda s: s.rank), scene, options, budget)
        if backup.info.get("over_budget"):
            return without_fallback(result, reason, backup.message)
    else:
        try:
            setting = cheapest_setting(scene, tolerance, [s.name for s in backups], budget,
                                       registry=ELLIPTIC_METHODS)
        except OverBudget as exc:
            return without_fallback(result, reason, str(exc))
        backup = run_to_tolerance(setting, scene, options, tolerance, budget, registry=ELLIPTIC_METHODS)[1]
    info = dict(backup.info, fallback_from=spec.name, fallback_reason=reason)
    return type(backup)(**{**backup.__dict__, "info": info,
                           "message": f"{backup.message} (fallback: {spec.name} failed: {reason})"})


def run_default(spec: MethodSpec, scene: EllipticScene, options: dict, budget: Budget | None) -> EllipticResult:
    """The method with its defaults (and the caller's options); with a ``budget`` its modelled cost does not fit,
    the most accurate setting that fits, or, when none does, a refusal (``info["over_budget"]``), as in 2D
    (:func:`rollcontact.dispatch.run_default`)."""
    model = spec.accuracy
    if budget is None or model is None:
        return call_with_known_options(spec, scene, options)
    cost = model.cost(scene, used_options(spec, options))
    if budget.fits(cost):
        budget.charge(cost)
        result = call_with_known_options(spec, scene, options)
        result.info["predicted_cost"] = cost
        return result
    fitting = within_budget(model, spec.name, scene, budget.left())
    if fitting is None:
        return EllipticResult.from_scene(
            scene, spec.name, False, f"{spec.name}'s cheapest setting is modelled at {model.minimum_cost(scene):.3g} "
            f"s, more than the budget of {budget.seconds:.3g} s", info={"over_budget": True})
    budget.charge(fitting.cost)
    result = call_with_known_options(spec, scene, {**fitting.options, **options})
    result.info["predicted_cost"] = fitting.cost
    return type(result)(**{**result.__dict__, "message": f"{result.message} (budget: the default setting is modelled "
                           f"at {cost:.3g} s, more than {budget.seconds:.3g} s; ran {fitting.options}, modelled at "
                           f"{fitting.cost:.3g} s)"})

