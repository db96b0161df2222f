"""One dispatcher, a registry of methods and the automatic choice (in the manner of scipy's root_scalar).

Without a tolerance
-------------------
``solve(scene)`` (method ``"auto"``) takes the lowest-ranked registered method that can treat the scene, with its
defaults: the cheapest exact method (closed form, then the polynomial method, then the discretised one).

Tolerance-aware choice
----------------------
``solve(scene, tolerance=t)`` takes, over every method that can treat the scene, the cheapest *setting* whose error
estimate is at most t (:func:`choose_setting`).  Each registered method may carry an
:class:`~rollcontact.method.AccuracyModel` that lists its settings for a scene (option sets such as a polynomial
truncation, a node count or an element count) and gives, for each, the predicted relative error of T' and p0 and a
modelled cost; only the ranking of the costs matters.  The models and their calibrations live with their methods
(:mod:`rollcontact.methods.polynomial.accuracy`, :mod:`rollcontact.methods.discretised.accuracy`,
:mod:`rollcontact.methods.closed_form`).  Where a method's result carries an a-posteriori estimate that misses t,
``auto`` runs the finer settings its model names until one meets t (:func:`run_to_tolerance`).

The result reports ``info["error_estimate"]`` (the method's estimate for the options actually used, a posteriori
where the method returns one), and with a tolerance also ``info["tolerance"]``, ``info["tolerance_met"]`` and
``info["setting"]``.  When no setting meets the tolerance, the most accurate one is used and the message says so.

Fallback
--------
When the chosen method's answer fails (its validity checks, its convergence, an arithmetic error) or its error
estimate says nothing (:data:`~rollcontact.method.UNRESOLVED`), ``auto`` runs the cheapest method of higher rank
registered as a fallback (``"discretised"``), with a tolerance at its cheapest setting that meets it, and reports
``info["fallback_from"]`` and ``info["fallback_reason"]``.  A named method never falls back.
"""

from __future__ import annotations

import math
from dataclasses import replace

from rollcontact.checks import check_real
from rollcontact.method import AccuracyModel, MethodSpec, Setting, check_tolerance, nan_last, unresolved
from rollcontact.methods import closed_form, discretised, polynomial
from rollcontact.result import ContactResult
from rollcontact.scene import Scene

BUILTIN: tuple[MethodSpec, ...] = (
    closed_form.METHOD,
    polynomial.METHOD,
    discretised.METHOD,
)
"""The method table: the fidelity levels shipped with the package, one line each (a method module exports its
:class:`~rollcontact.method.MethodSpec` as ``METHOD``)."""

METHODS: dict[str, MethodSpec] = {spec.name: spec for spec in BUILTIN}
"""The registry ``solve`` dispatches over: :data:`BUILTIN` and whatever :func:`register_method` added."""


def register_method(name: str, function, inapplicable, rank: int, *, fallback: bool = False,
                    accuracy: AccuracyModel | None = None) -> None:
    """Add (or replace) a method in :data:`METHODS`: the extension point for a fidelity level outside the package.

    Parameters
    ----------
    name : str
        Registry key, the ``method`` argument of :func:`solve`.
    function : callable
        ``function(scene, **options) -> ContactResult``; its attribute ``options`` (a tuple of names) lists the
        options ``auto`` may pass on.
    inapplicable : callable
        ``inapplicable(scene) -> str | None``: why the method cannot treat the scene, or None.
    rank : int
        Order of preference of ``auto`` without a tolerance: lower is tried first.
    fallback : bool
        Whether ``auto`` may use it when a method of lower rank fails.
    accuracy : AccuracyModel, optional
        Settings, error and cost model for ``auto`` with a tolerance.
    """
    METHODS[name] = MethodSpec(name, function, inapplicable, rank, fallback, accuracy)


def by_rank(registry: dict[str, MethodSpec] | None = None) -> list[MethodSpec]:
    """The methods of ``registry`` (default :data:`METHODS`), lowest rank first (sorted once per registry content:
    auto asks per solve)."""
    registry = METHODS if registry is None else registry
    specs = tuple(registry.values())
    cached = RANKED.get(id(registry))
    if cached is None or cached[0] != specs:
        cached = RANKED[id(registry)] = (specs, sorted(specs, key=lambda s: s.rank))
    return cached[1]


RANKED: dict[int, tuple] = {}  # id of a registry: (its content the order is sorted from, the sorted specs)


def choose_method(scene: Scene, tolerance: float | None = None, names=None, registry=None) -> str:
    """Name of the lowest-ranked registered method (among ``names``, default all) that can treat the scene (or,
    with a tolerance, of the method of :func:`choose_setting`); ``registry`` defaults to :data:`METHODS`."""
    if tolerance is not None:
        return cheapest_setting(scene, check_tolerance(tolerance), names, registry=registry).method
    reasons = []
    for spec in by_rank(registry):
        if names is not None and spec.name not in names:
            continue
        why = spec.inapplicable(scene)
        if why is None:
            return spec.name
        reasons.append(f"{spec.name}: {why}")
    raise ValueError("no registered method can solve this scene (" + "; ".join(reasons) + ")")


def choose_setting(scene: Scene, tolerance: float, names=None, budget: float | None = None) -> Setting:
    """The cheapest setting, over the applicable methods, whose error estimate is at most ``tolerance``.

    Parameters
    ----------
    scene : Scene
        The case.
    tolerance : float
        Requested relative error of T' and p0, > 0.
    names : iterable of str, optional
        Consider only these methods (default: all registered).
    budget : float, optional
        Consider only settings whose modelled cost [s] is at most this.

    Returns
    -------
    Setting
        Its ``cost`` is the modelled time [s] of the solve, known before it starts.  When no setting meets the
        tolerance, the most accurate one (``error_estimate > tolerance``); when no method with an accuracy model
        applies, the cheapest exact method by rank with its defaults (NaN estimates).

    Raises
    ------
    ValueError
        Invalid tolerance or budget, no considered method can treat the scene, or (:class:`OverBudget`) none
        within the budget.
    """
    return cheapest_setting(scene, check_tolerance(tolerance), names, None if budget is None else Budget(budget))


def cheapest_setting(scene: Scene, tolerance: float, names=None, budget: Budget | None = None,
                     registry: dict[str, MethodSpec] | None = None) -> Setting:
    """:func:`choose_setting` for a tolerance already checked (``solve`` checks it once per call); with a
    ``budget``, only settings whose modelled cost fits what is left of it (:func:`within_budget`); over the methods
    of ``registry`` (default :data:`METHODS`; the elliptic dispatcher passes its own)."""
    allowed = None if names is None else set(names)
    best = closest = None
    unmodelled = []
    over = []
    for spec in by_rank(registry):
        if allowed is not None and spec.name not in allowed:
            continue
        model = spec.accuracy
        # a method whose cheapest setting costs more than the best found cannot win: skip its checks
        if best is not None and (model is None or model.floor >= best.cost or model.minimum_cost(scene) >= best.cost):
            continue
        if spec.inapplicable(scene) is not None:
            continue
        if model is None:
            unmodelled.append(spec.name)
            continue
        setting = model.setting_for(spec.name, scene, tolerance)
        if budget is not None and not budget.fits(setting.cost):
            fitting = within_budget(model, spec.name, scene, budget.left())
            if fitting is None:
                over.append(f"{spec.name} (its cheapest setting is modelled at {model.minimum_cost(scene):.3g} s)")
                continue
            setting = fitting
        if setting.error_estimate <= tolerance:
            if best is None or setting.cost < best.cost:
                best = setting
        elif closest is None or nan_last(setting.error_estimate) < nan_last(closest.error_estimate):
            closest = setting
    if best is not None or closest is not None:
        return best if best is not None else closest
    if unmodelled:  # no cost model: nothing bounds its work, a budget included
        return Setting(unmodelled[0], {}, math.nan, math.nan)
    if over:
        raise OverBudget(f"no setting fits the budget of {budget.seconds:.3g} s: " + "; ".join(over))
    raise ValueError("no registered method can solve this scene"
                     + (f" among {sorted(allowed)}" if allowed is not None else ""))


def within_budget(model: AccuracyModel, name: str, scene: Scene, left: float) -> Setting | None:
    """The most accurate setting of the model's ladder whose modelled cost is at most ``left`` [s] (the cheaper of
    equally accurate ones), or None when none is."""
    best = None
    for options in model.ladder(scene):
        cost = model.cost(scene, options)
        if cost <= left:
            key = (nan_last(model.error(scene, options)), cost)
            if best is None or key < best[0]:
                best = (key, options)
    if best is None:
        return None
    (error, cost), options = best
    return Setting(name, options, error, cost)


class OverBudget(ValueError):
    """No setting of the methods that can treat the scene fits the caller's budget; the message names their
    cheapest modelled costs."""


class Budget:
    """The work a solve may do, in modelled seconds: a setting starts only while its modelled cost fits what is left.

    The modelled cost is the accuracy models' (seconds on the machine of their calibration, ``benchmarks/pareto.py``);
    what is left is ``seconds`` less the modelled cost of the settings already run (:meth:`charge`).  No clock is
    read: the same scene and budget run the same settings on any machine, however fast or loaded.
    """

    def __init__(self, seconds: float):
        self.seconds = check_real("budget", seconds, lower=0.0, lower_open=True, unit="s")
        self.spent = 0.0
        """Modelled seconds [s] of the settings run so far."""

    def left(self) -> float:
        """Modelled seconds [s] left."""
        return self.seconds - self.spent

    def fits(self, cost: float) -> bool:
        """Whether a setting of modelled ``cost`` [s] may start (a NaN cost never does)."""
        return cost <= self.left()

    def charge(self, cost: float) -> None:
        """Count a setting of modelled ``cost`` [s] that ran (a NaN cost, of a method without a cost model, counts
        nothing: no model bounds it)."""
        if cost == cost:
            self.spent += cost


def setting_for(name: str, scene: Scene, tolerance: float) -> Setting:
    """The cheapest setting of method ``name`` whose error estimate meets ``tolerance`` (else its most accurate).

    For callers that run a fixed list of methods themselves (the FMU's stepping model); a method without an
    accuracy model gets its defaults (NaN estimates).
    """
    tolerance = check_tolerance(tolerance)
    model = METHODS[name].accuracy
    if model is None:
        return Setting(name, {}, math.nan, math.nan)
    return model.setting_for(name, scene, tolerance)


def solve(scene: Scene, method: str = "auto", *, tolerance: float | None = None, methods=None,
          estimate: str = "full", budget: float | None = None, **options) -> ContactResult:
    """Solve a steady 2D rolling-contact scene.

    Parameters
    ----------
    scene : Scene
        The case.
    method : str
        ``"auto"`` or a name in :data:`METHODS`.  ``"auto"`` without a tolerance takes the lowest-ranked method
        that can treat the scene, with its defaults; with ``tolerance`` the cheapest setting of any applicable
        method whose error estimate meets it (module docstring).  When the answer fails (its validity checks, its
        convergence, an arithmetic error) or its error estimate says nothing (:data:`~rollcontact.method.UNRESOLVED`),
        ``auto`` falls back to the cheapest method of higher rank registered as a fallback (``"discretised"``).
    tolerance : float, optional
        Requested relative error [1] of T' and p0, > 0.  With a named method: that method's cheapest setting whose
        error estimate meets it, without fallback.
    methods : iterable of str, optional
        ``auto`` chooses and falls back only among these registered names (default: all).
    budget : float, optional
        The work [s] the solve may do, in the accuracy models' modelled seconds (calibrated by
        ``benchmarks/pareto.py``): a setting starts only while its modelled cost fits what is left of the budget
        after the modelled costs of the settings already run, so ``auto`` chooses, escalates and falls back within
        it, the same way on every machine (no clock is read).  With a tolerance: the
        cheapest setting that meets it within the budget, else the most accurate that fits (the message says so);
        without: the method's default setting when it fits, else the most accurate that does.  When none fits, an
        unsuccessful result says why, and nothing is solved.  A method without an accuracy model has no cost
        model: it runs unbounded.  :func:`choose_setting` gives the setting and its
        modelled cost before solving; the result reports it as ``info["predicted_cost"]``, and the modelled cost
        of everything the solve ran as ``info["modelled_cost"]``.
    estimate : {"full", "free"}
        Without a tolerance, ``info["error_estimate"]`` is the method's full estimate (``"full"``), or only the part
        that costs nothing beyond the solve (``"free"``, :meth:`~rollcontact.method.AccuracyModel.free_estimate`: a
        lower bound, NaN where none is known), which is what ``auto`` then checks against
        :data:`~rollcontact.method.UNRESOLVED`.  The FMU's stepping model asks for ``"free"``.
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
        Unknown method name (the message lists the valid ones), no method that can treat the scene, or an
        invalid tolerance or ``estimate``.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a rollcontact.Scene, got {type(scene).__name__}")
    if estimate not in ("full", "free"):
        raise ValueError(f"estimate = {estimate!r} is not one of 'full', 'free'")
    if method != "auto":
        if method not in METHODS:
            raise ValueError(f"unknown method {method!r}; valid methods are {['auto', *sorted(METHODS)]}")
        if tolerance is None and budget is None:
            spec = METHODS[method]
            return annotate(spec, scene, options, spec.function(scene, **options), estimate=estimate)
        methods, fallback = (method,), False
    else:
        fallback = True
    return within(scene, tolerance, None if methods is None else tuple(methods), fallback, budget, options, estimate)


def within(scene, tolerance: float | None, names: tuple[str, ...] | None, fallback: bool, budget: float | None,
           options: dict, estimate: str = "full", registry: dict[str, MethodSpec] | None = None, refuse=None):
    """:func:`choose_and_run` within ``budget`` [s] of modelled work (None: no bound), the modelled cost of what ran
    reported as ``info["modelled_cost"]``: the common path of :func:`solve` and of
    :func:`rollcontact.elliptic.solve_elliptic` once the candidates are known."""
    budget = None if budget is None else Budget(budget)
    result = choose_and_run(scene, tolerance, names, fallback, budget, options, estimate, registry, refuse)
    if budget is not None:
        result.info["modelled_cost"] = budget.spent
    return result


def choose_and_run(scene, tolerance: float | None, names: tuple[str, ...] | None, fallback: bool,
                   budget: Budget | None, options: dict, estimate: str = "full",
                   registry: dict[str, MethodSpec] | None = None, refuse=None):
    """What :func:`solve` does once the method's candidates are known: choose, run, escalate and fall back, all
    within ``budget`` (each setting run is charged to it).  Over ``registry`` (default :data:`METHODS`), with
    ``refuse(scene, name, message, over_budget)`` making the result of nothing solved (default :func:`refused`): the
    elliptic dispatcher runs the same rules over its own methods and result type."""
    registry = METHODS if registry is None else registry
    refuse = refused if refuse is None else refuse
    if tolerance is None:
        spec = registry[choose_method(scene, names=names, registry=registry)]
        result = attempt(fallback, lambda: run_default(spec, scene, options, estimate, budget, refuse),
                         lambda message: refuse(scene, spec.name, message, False))
    else:
        tolerance = check_tolerance(tolerance)
        try:
            setting = cheapest_setting(scene, tolerance, names, budget, registry)
        except OverBudget as exc:
            return refuse(scene, "auto", str(exc), True)
        spec = registry[setting.method]
        result = attempt(fallback, lambda: run_to_tolerance(setting, scene, options, tolerance, budget, registry)[1],
                         lambda message: refuse(scene, spec.name, message, False))
    reason = result.message if not result.success else unresolved(result)
    if reason is None or not fallback or result.info.get("over_budget"):
        return result
    backups = [s for s in registry.values()
               if s.fallback and s.rank > spec.rank and (names is None or s.name in names)
               and (tolerance is not None or s.inapplicable(scene) is None)]
    if not backups:
        return result
    if tolerance is None:
        backup_spec = min(backups, key=lambda s: s.rank)
        backup = run_default(backup_spec, scene, options, estimate, budget, refuse)
        if backup.info.get("over_budget"):
            return without_fallback(result, reason, backup.message)
    else:
        try:
            setting = cheapest_setting(scene, tolerance, [s.name for s in backups], budget, registry)
        except OverBudget as exc:
            return without_fallback(result, reason, str(exc))
        except ValueError:  # no fallback method can treat the scene either
            return result
        backup_spec, backup = run_to_tolerance(setting, scene, options, tolerance, budget, registry)
    info = dict(backup.info, fallback_from=spec.name, fallback_reason=reason)
    return type(backup)(**{**backup.__dict__, "info": info,
                           "message": f"{backup.message} (fallback: {spec.name} failed: {reason})"})


def run_default(spec: MethodSpec, scene, options: dict, estimate: str, budget: Budget | None, refuse=None):
    """The method with its default setting (and the caller's options); with a ``budget`` that its modelled cost
    does not fit, the most accurate setting that fits (:func:`within_budget`), or, when none does, nothing: a
    refusal (``info["over_budget"]``, made by ``refuse``, default :func:`refused`)."""
    model = spec.accuracy
    if budget is None or model is None:  # a method without a cost model runs as it is: no budget can bound it
        return call_with_known_options(spec, scene, options, estimate)
    used = used_options(spec, options)
    cost = model.cost(scene, used)
    if budget.fits(cost):
        budget.charge(cost)
        result = call_with_known_options(spec, scene, options, estimate)
        result.info["predicted_cost"] = cost
        return result
    fitting = within_budget(model, spec.name, scene, budget.left())
    if fitting is None:
        cheapest = model.minimum_cost(scene)
        return (refused if refuse is None else refuse)(
            scene, spec.name, f"{spec.name}'s cheapest setting is modelled at {cheapest:.3g} s, more than the budget "
            f"of {budget.seconds:.3g} s", True)
    budget.charge(fitting.cost)
    result = call_with_known_options(spec, scene, {**fitting.options, **options}, estimate)
    result.info["predicted_cost"] = fitting.cost
    return type(result)(**{**result.__dict__, "message": f"{result.message} (budget: the default setting is modelled "
                           f"at {cost:.3g} s, more than {budget.seconds:.3g} s; ran {fitting.options}, modelled at "
                           f"{fitting.cost:.3g} s)"})


def without_fallback(result: ContactResult, reason: str, why: str) -> ContactResult:
    """The failed (or unresolved) ``result`` as a failure whose message says why no fallback ran (the budget)."""
    return type(result)(**{**result.__dict__, "success": False, "message": f"{reason} (no fallback: {why})"})


def refused(scene: Scene, name: str, message: str, over_budget: bool = True) -> ContactResult:
    """An unsuccessful result of nothing solved, with the reason."""
    nan = math.nan
    return ContactResult(name, False, message, scene.normal_load_per_length, nan, scene.creep, nan, nan, nan, nan,
                         info={"over_budget": over_budget})


def attempt(fallback: bool, run, fail):
    """``run()``; where a fallback may follow, an ArithmeticError it raises (a numerical breakdown, e.g. a division
    by a load that underflows) becomes ``fail(message)``, an unsuccessful result that says so, so the fallback
    runs."""
    if not fallback:
        return run()
    try:
        return run()
    except ArithmeticError as exc:
        return fail(f"raised {type(exc).__name__}: {exc}")


def run_to_tolerance(setting: Setting, scene: Scene, options: dict, tolerance: float,
                     budget: Budget | None = None, registry: dict[str, MethodSpec] | None = None
                     ) -> tuple[MethodSpec, ContactResult]:
    """:func:`run_setting`, then, while the result's a-posteriori estimate misses the tolerance, the settings the
    method's :meth:`AccuracyModel.escalation` names, and after a failure those its :meth:`AccuracyModel.retry`
    names (each finer than the last, so the loop ends).  User options that fix the escalated option stop it, and so
    does a ``budget`` that the next setting's modelled cost does not fit (the message says so).  ``registry``
    defaults to :data:`METHODS`."""
    if budget is not None:
        budget.charge(setting.cost)
    spec, result = run_setting(setting, scene, options, tolerance, registry)
    result.info["predicted_cost"] = setting.cost
    failures = []
    note = ""
    while spec.accuracy is not None:
        used = result.info["setting"]
        following = (spec.accuracy.escalation(scene, used, result.info["error_estimate"], tolerance)
                     if result.success else spec.accuracy.retry(scene, used, result))
        if following is None or any(key in options for key in following):
            break
        cost = spec.accuracy.cost(scene, following)
        if budget is not None and not budget.fits(cost):
            note = (f" (budget: {following} is modelled at {cost:.3g} s, more than the {max(budget.left(), 0.0):.3g} s "
                    f"left of {budget.seconds:.3g} s)")
            break
        if not result.success:
            failures.append(f"{used}: {result.message}")
        if budget is not None:
            budget.charge(cost)
        spec, result = run_setting(Setting(spec.name, following, math.nan, cost), scene, options, tolerance, registry)
        result.info["predicted_cost"] = cost
    if failures or note:
        message = result.message + note
        if failures:
            message += " (after failing with " + "; ".join(failures) + ")"
        result = type(result)(**{**result.__dict__, "message": message})
    return spec, result


def run_setting(setting: Setting, scene: Scene, options: dict, tolerance: float,
                registry: dict[str, MethodSpec] | None = None) -> tuple[MethodSpec, ContactResult]:
    """Run a chosen setting (user options override it) and record the tolerance outcome in the result;
    ``registry`` defaults to :data:`METHODS`."""
    spec = (METHODS if registry is None else registry)[setting.method]
    merged = (spec.accuracy.merged(setting.options, options) if spec.accuracy is not None
              else {**setting.options, **options}) if options else setting.options
    used = used_options(spec, merged)
    result = annotate(spec, scene, used, spec.function(scene, **used), tolerance)
    estimate = result.info.get("error_estimate", math.nan)
    met = bool(estimate <= tolerance)
    result.info.update(tolerance=tolerance, tolerance_met=met, setting=used)
    if met or not result.success:
        return spec, result
    note = (f" (tolerance {tolerance:.3g} not reached: error estimate {estimate:.3g})" if math.isfinite(estimate)
            else f" (tolerance {tolerance:.3g} not checked: the method gives no error estimate)")
    return spec, type(result)(**{**result.__dict__, "message": result.message + note})


def call_with_known_options(spec: MethodSpec, scene: Scene, options: dict, estimate: str = "full") -> ContactResult:
    """Call the method with the options it accepts, and annotate the result with its error estimate."""
    used = used_options(spec, options)
    return annotate(spec, scene, used, spec.function(scene, **used), estimate=estimate)


def used_options(spec: MethodSpec, options: dict) -> dict:
    """The ``options`` that the method lists in its function's ``options`` attribute."""
    accepted = getattr(spec.function, "options", ())
    return {k: v for k, v in options.items() if k in accepted}


def annotate(spec: MethodSpec, scene: Scene, options: dict, result: ContactResult,
             tolerance: float | None = None, estimate: str = "full") -> ContactResult:
    """Put the method's error estimate for the options used into ``result.info`` (a fresh dict per result); with
    a ``tolerance``, one that need only tell whether the result meets it (:meth:`AccuracyModel.achieved`); with
    ``estimate="free"`` and no tolerance, only the part that costs nothing (:meth:`AccuracyModel.free_estimate`).
    ``result.method`` is the registry name (a function registered under another name reports this one).  Any
    result dataclass with ``method`` and ``info`` (the 2D :class:`ContactResult`, the elliptic result) is
    annotated; anything else passes unchanged."""
    if not hasattr(result, "info"):
        return result
    if result.method != spec.name:
        result = replace(result, method=spec.name)
    if spec.accuracy is not None:
        result.info["error_estimate"] = (spec.accuracy.free_estimate(result) if estimate == "free" and tolerance is None
                                         else spec.accuracy.achieved(scene, options, result, tolerance))
    return result
