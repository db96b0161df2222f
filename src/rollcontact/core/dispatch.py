"""The dispatch engine every geometry shares: a method table, a registry and the automatic choice, in the manner of
scipy's ``root_scalar`` (:class:`Dispatcher`).

Each geometry (:mod:`rollcontact.line.dispatch`, :mod:`rollcontact.elliptic.dispatch`, ...) makes one
:class:`Dispatcher` of its scene type, its method table and its refusal, and exposes its ``solve``, ``METHODS`` and
``register_method``; the rules below are the same for all of them.

Without a tolerance
-------------------
``solve(scene)`` (method ``"auto"``) takes the lowest-ranked registered method that can treat the scene, with its
defaults.

Tolerance-aware choice
----------------------
``solve(scene, tolerance=t)`` takes, over every method that can treat the scene, the cheapest *setting* whose error
estimate is at most t (:meth:`Dispatcher.choose_setting`).  Each registered method may carry an
:class:`~rollcontact.core.method.AccuracyModel` that lists its settings for a scene (option sets such as a
polynomial truncation, a node count or an element count) and gives, for each, the predicted error (in the
geometry's measure) and a modelled cost; only the ranking of the costs matters.  The models and their calibrations
live with their methods.  Where a method's result carries an a-posteriori estimate that misses t, ``auto`` runs
the finer settings its model names until one meets t (:meth:`Dispatcher.run_to_tolerance`).

The result reports ``info["error_estimate"]`` (the method's estimate for the options actually used, a posteriori
where the method returns one), and with a tolerance also ``info["tolerance"]``, ``info["tolerance_met"]`` and
``info["setting"]`` (the options run; also with a budget), ``info["predicted_cost"]`` (the modelled cost of the
setting that gave the result) and ``info["modelled_cost"]`` (with a budget: the modelled cost of everything the solve
ran, failures and fallbacks included).  When no setting meets the tolerance, the most accurate one is used and the
message says so.

Budget
------
``budget=`` bounds the work in the accuracy models' modelled seconds (:class:`Budget`): a setting starts only while
its modelled cost fits what is left; no clock is read, so the same scene and budget run the same settings on any
machine.

Fallback
--------
When the chosen method's answer fails (its validity checks, its convergence, an arithmetic error) or its error
estimate says nothing (:data:`~rollcontact.core.method.UNRESOLVED`), ``auto`` runs the cheapest method of higher
rank registered as a fallback, with a tolerance at its cheapest setting that meets it, and reports
``info["fallback_from"]`` and ``info["fallback_reason"]``.  A named method never falls back.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace

from rollcontact.core.checks import check_real, error_text
from rollcontact.core.method import AccuracyModel, MethodSpec, Setting, check_tolerance, nan_last, unresolved

__all__ = ["Budget", "Dispatcher", "OverBudget", "annotate", "used_options"]


class OverBudget(ValueError):
    """No setting of the methods that can treat the scene fits the caller's budget; the message names their
    cheapest modelled costs."""


class Budget:
    """The work a solve may do, in modelled seconds: a setting starts only while its modelled cost fits what is left.

    The modelled cost is the accuracy models' (seconds on the machine of their calibration); what is left is
    ``seconds`` less the modelled cost of the settings already run (:meth:`charge`).  No clock is read: the same
    scene and budget run the same settings on any machine, however fast or loaded.
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


class Dispatcher:
    """One geometry's dispatcher: its method table and registry, the automatic choice, escalation, budget and
    fallback (module docstring).

    Parameters
    ----------
    geometry : str
        What it solves, for messages (``"line"``, ``"elliptic"``, ...).
    scene_type : type
        The scene class :meth:`solve` accepts.
    builtin : tuple of MethodSpec
        The method table: the fidelity levels shipped with the package, one line each (a method module exports its
        :class:`~rollcontact.core.method.MethodSpec` as ``METHOD``).
    refuse : callable
        ``refuse(scene, name, message, over_budget) -> result``: the geometry's unsuccessful result of nothing
        solved, with the reason (``info["over_budget"]`` says whether the budget refused it).
    """

    def __init__(self, geometry: str, scene_type: type, builtin: tuple[MethodSpec, ...],
                 refuse: Callable[..., object]):
        self.geometry = geometry
        self.scene_type = scene_type
        self.builtin = builtin
        self.methods: dict[str, MethodSpec] = {spec.name: spec for spec in builtin}
        """The registry :meth:`solve` dispatches over: :attr:`builtin` and whatever :meth:`register` added."""
        self.refuse = refuse
        self.ranked_cache: tuple[tuple[MethodSpec, ...], list[MethodSpec]] | None = None

    def register(self, name: str, function, inapplicable, rank: int, *, fallback: bool = False,
                 accuracy: AccuracyModel | None = None) -> None:
        """Add (or replace) a method in :attr:`methods`: the extension point for a fidelity level outside the package.

        Parameters
        ----------
        name : str
            Registry key, the ``method`` argument of :meth:`solve`.
        function : callable
            ``function(scene, **options) -> result``; its attribute ``options`` (a tuple of names) lists the options
            ``auto`` may pass on.
        inapplicable : callable
            ``inapplicable(scene) -> str | None``: why the method cannot treat the scene, or None.
        rank : int
            Order of preference of ``auto`` without a tolerance: lower is tried first.
        fallback : bool
            Whether ``auto`` may use it when a method of lower rank fails.
        accuracy : AccuracyModel, optional
            Settings, error and cost model for ``auto`` with a tolerance.
        """
        self.methods[name] = MethodSpec(name, function, inapplicable, rank, fallback, accuracy)

    def ranked(self) -> list[MethodSpec]:
        """The registered methods, lowest rank first (sorted once per registry content: auto asks per solve)."""
        specs = tuple(self.methods.values())
        if self.ranked_cache is None or self.ranked_cache[0] != specs:
            self.ranked_cache = (specs, sorted(specs, key=lambda s: s.rank))
        return self.ranked_cache[1]

    # choice ---------------------------------------------------------------------------------------------------------
    def choose_method(self, scene, tolerance: float | None = None, names=None) -> str:
        """Name of the lowest-ranked registered method (among ``names``, default all) that can treat the scene (or,
        with a tolerance, of the method of :meth:`choose_setting`)."""
        if tolerance is not None:
            return self.cheapest_setting(scene, check_tolerance(tolerance), names).method
        reasons = []
        for spec in self.ranked():
            if names is not None and spec.name not in names:
                continue
            why = spec.inapplicable(scene)
            if why is None:
                return spec.name
            reasons.append(f"{spec.name}: {why}")
        raise ValueError("no registered method can solve this scene (" + "; ".join(reasons) + ")")

    def choose_setting(self, scene, tolerance: float, names=None, budget: float | None = None) -> Setting:
        """The cheapest setting, over the applicable methods, whose error estimate is at most ``tolerance``.

        Parameters
        ----------
        scene
            The case (of the dispatcher's scene type).
        tolerance : float
            Requested error [1] (the geometry's measure), > 0.
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
        return self.cheapest_setting(scene, check_tolerance(tolerance), names,
                                     None if budget is None else Budget(budget))

    def cheapest_setting(self, scene, tolerance: float, names=None, budget: Budget | None = None) -> Setting:
        """:meth:`choose_setting` for a tolerance already checked (``solve`` checks it once per call); with a
        ``budget``, only settings whose modelled cost fits what is left of it (:func:`within_budget`)."""
        allowed = None if names is None else set(names)
        best = closest = None
        unmodelled = []
        over = []
        reasons = []
        for spec in self.ranked():
            if allowed is not None and spec.name not in allowed:
                continue
            model = spec.accuracy
            # a method whose cheapest setting costs more than the best found cannot win: skip its checks
            if best is not None and (model is None or model.floor >= best.cost
                                     or model.minimum_cost(scene) >= best.cost):
                continue
            why = spec.inapplicable(scene)
            if why is not None:
                reasons.append(f"{spec.name}: {why}")
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
                         + (f" among {sorted(allowed)}" if allowed is not None else "")
                         + (f" ({'; '.join(reasons)})" if reasons else ""))

    def setting_for(self, name: str, scene, tolerance: float) -> Setting:
        """The cheapest setting of method ``name`` whose error estimate meets ``tolerance`` (else its most accurate).

        For callers that run a fixed list of methods themselves (a stepping model); a method without an accuracy
        model gets its defaults (NaN estimates).
        """
        tolerance = check_tolerance(tolerance)
        model = self.methods[name].accuracy
        if model is None:
            return Setting(name, {}, math.nan, math.nan)
        return model.setting_for(name, scene, tolerance)

    # solving --------------------------------------------------------------------------------------------------------
    def solve(self, scene, method: str = "auto", *, tolerance: float | None = None, methods=None,
              estimate: str = "full", budget: float | None = None, **options):
        """Solve a steady scene of the dispatcher's geometry (each geometry's ``solve`` documents its parameters).

        ``method`` is ``"auto"`` or a registered name (a named method refuses a scene it cannot treat with a
        ValueError); ``tolerance``, ``methods``, ``budget`` as in the module docstring; ``estimate`` ``"full"`` (the
        method's full error estimate) or ``"free"`` (only the part that costs nothing beyond the solve,
        :meth:`~rollcontact.core.method.AccuracyModel.free_estimate`, what a stepping model checks every step);
        ``options`` go to the method (with ``"auto"`` or a tolerance, only those the chosen method accepts).

        Raises
        ------
        TypeError
            A scene of another type.
        ValueError
            An unknown method (the message lists the valid ones), a named method that cannot treat the scene, no
            method that can, or an invalid tolerance, budget or ``estimate``.
        """
        if not isinstance(scene, self.scene_type):
            raise TypeError(f"scene must be a rollcontact.{self.scene_type.__name__}, got {type(scene).__name__}")
        if estimate not in ("full", "free"):
            raise ValueError(f"estimate = {estimate!r} is not one of 'full', 'free'")
        if method != "auto":
            spec = self.methods.get(method)
            if spec is None:
                raise ValueError(f"unknown {self.geometry} method {method!r}; valid methods are "
                                 f"{['auto', *sorted(self.methods)]}")
            if tolerance is None and budget is None:
                why = spec.inapplicable(scene)
                if why is not None:
                    raise ValueError(f"method {method!r} cannot solve this scene: {why}")
                return annotate(spec, scene, options, spec.function(scene, **options), estimate=estimate)
            names, fallback = (method,), False
        else:
            names, fallback = (None if methods is None else tuple(methods)), True
        budget = None if budget is None else Budget(budget)
        result = self.choose_and_run(scene, tolerance, names, fallback, budget, options, estimate)
        if budget is not None:
            result.info["modelled_cost"] = budget.spent
        return result

    def choose_and_run(self, scene, tolerance: float | None, names: tuple[str, ...] | None, fallback: bool,
                       budget: Budget | None, options: dict, estimate: str = "full"):
        """What :meth:`solve` does once the method's candidates are known: choose, run, escalate and fall back, all
        within ``budget`` (each setting run is charged to it)."""
        if tolerance is None:
            spec = self.methods[self.choose_method(scene, names=names)]
            result = attempt(fallback, lambda: self.run_default(spec, scene, options, estimate, budget),
                             lambda message: self.refuse(scene, spec.name, message, False))
        else:
            tolerance = check_tolerance(tolerance)
            try:
                setting = self.cheapest_setting(scene, tolerance, names, budget)
            except OverBudget as exc:
                return self.refuse(scene, "auto", str(exc), True)
            spec = self.methods[setting.method]
            result = attempt(fallback,
                             lambda: self.run_to_tolerance(setting, scene, options, tolerance, budget)[1],
                             lambda message: self.refuse(scene, spec.name, message, False))
        reason = result.message if not result.success else unresolved(result)
        if reason is None or not fallback or result.info.get("over_budget"):
            return result
        backups = [s for s in self.methods.values()
                   if s.fallback and s.rank > spec.rank and (names is None or s.name in names)
                   and (tolerance is not None or s.inapplicable(scene) is None)]
        if not backups:
            return result
        if tolerance is None:
            backup_spec = min(backups, key=lambda s: s.rank)
            backup = self.run_default(backup_spec, scene, options, estimate, budget)
            if backup.info.get("over_budget"):
                return without_fallback(result, reason, backup.message)
        else:
            try:
                setting = self.cheapest_setting(scene, tolerance, [s.name for s in backups], budget)
            except OverBudget as exc:
                return without_fallback(result, reason, str(exc))
            except ValueError:  # no fallback method can treat the scene either
                return result
            backup_spec, backup = self.run_to_tolerance(setting, scene, options, tolerance, budget)
        info = dict(backup.info, fallback_from=spec.name, fallback_reason=reason)
        return type(backup)(**{**backup.__dict__, "info": info,
                               "message": f"{backup.message} (fallback: {spec.name} failed: {reason})"})

    def run_default(self, spec: MethodSpec, scene, options: dict, estimate: str, budget: Budget | None):
        """The method with its default setting (and the caller's options); with a ``budget`` that its modelled cost
        does not fit, the most accurate setting that fits (:func:`within_budget`), or, when none does, nothing: a
        refusal (``info["over_budget"]``)."""
        model = spec.accuracy
        if budget is None or model is None:  # a method without a cost model runs as it is: no budget can bound it
            return call_with_known_options(spec, scene, options, estimate)
        used = used_options(spec, options)
        cost = model.cost(scene, used)
        if budget.fits(cost):
            budget.charge(cost)
            result = call_with_known_options(spec, scene, options, estimate)
            result.info.update(predicted_cost=cost, setting=used)
            return result
        fitting = within_budget(model, spec.name, scene, budget.left())
        if fitting is None:
            cheapest = model.minimum_cost(scene)
            return self.refuse(scene, spec.name, f"{spec.name}'s cheapest setting is modelled at {cheapest:.3g} s, "
                               f"more than the budget of {budget.seconds:.3g} s", True)
        budget.charge(fitting.cost)
        result = call_with_known_options(spec, scene, {**fitting.options, **options}, estimate)
        result.info.update(predicted_cost=fitting.cost, setting=used_options(spec, {**fitting.options, **options}))
        return type(result)(**{**result.__dict__, "message": f"{result.message} (budget: the default setting is "
                               f"modelled at {cost:.3g} s, more than {budget.seconds:.3g} s; ran {fitting.options}, "
                               f"modelled at {fitting.cost:.3g} s)"})

    def run_to_tolerance(self, setting: Setting, scene, options: dict, tolerance: float,
                         budget: Budget | None = None) -> tuple[MethodSpec, object]:
        """:meth:`run_setting`, then, while the result's a-posteriori estimate misses the tolerance, the settings the
        method's :meth:`AccuracyModel.escalation` names, and after a failure those its :meth:`AccuracyModel.retry`
        names (each finer than the last, so the loop ends).  User options that fix the escalated option stop it, and
        so does a ``budget`` that the next setting's modelled cost does not fit (the message says so)."""
        if budget is not None:
            budget.charge(setting.cost)
        spec, result = self.run_setting(setting, scene, options, tolerance)
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
                note = (f" (budget: {following} is modelled at {cost:.3g} s, more than the "
                        f"{max(budget.left(), 0.0):.3g} s left of {budget.seconds:.3g} s)")
                break
            if not result.success:
                failures.append(f"{used}: {result.message}")
            if budget is not None:
                budget.charge(cost)
            spec, result = self.run_setting(Setting(spec.name, following, math.nan, cost), scene, options, tolerance)
            result.info["predicted_cost"] = cost
        if failures or note:
            message = result.message + note
            if failures:
                message += " (after failing with " + "; ".join(failures) + ")"
            result = type(result)(**{**result.__dict__, "message": message})
        return spec, result

    def run_setting(self, setting: Setting, scene, options: dict, tolerance: float) -> tuple[MethodSpec, object]:
        """Run a chosen setting (user options override it) and record the tolerance outcome in the result."""
        spec = self.methods[setting.method]
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


def within_budget(model: AccuracyModel, name: str, scene, left: float) -> Setting | None:
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


def without_fallback(result, reason: str, why: str):
    """The failed (or unresolved) ``result`` as a failure whose message says why no fallback ran (the budget)."""
    return type(result)(**{**result.__dict__, "success": False, "message": f"{reason} (no fallback: {why})"})


def attempt(fallback: bool, run, fail):
    """``run()``; where a fallback may follow, an ArithmeticError it raises (a numerical breakdown, e.g. a division
    by a load that underflows) becomes ``fail(message)``, an unsuccessful result that says so, so the fallback
    runs."""
    if not fallback:
        return run()
    try:
        return run()
    except ArithmeticError as exc:
        return fail(f"raised {error_text(exc)}")


def call_with_known_options(spec: MethodSpec, scene, options: dict, estimate: str = "full"):
    """Call the method with the options it accepts, and annotate the result with its error estimate."""
    used = used_options(spec, options)
    return annotate(spec, scene, used, spec.function(scene, **used), estimate=estimate)


def used_options(spec: MethodSpec, options: dict) -> dict:
    """The ``options`` that the method lists in its function's ``options`` attribute."""
    accepted = getattr(spec.function, "options", ())
    return {k: v for k, v in options.items() if k in accepted}


def annotate(spec: MethodSpec, scene, options: dict, result, tolerance: float | None = None, estimate: str = "full"):
    """Put the method's error estimate for the options used into ``result.info`` (a fresh dict per result); with
    a ``tolerance``, one that need only tell whether the result meets it (:meth:`AccuracyModel.achieved`); with
    ``estimate="free"`` and no tolerance, only the part that costs nothing (:meth:`AccuracyModel.free_estimate`).
    ``result.method`` is the registry name (a function registered under another name reports this one).  Any
    result dataclass with ``method`` and ``info`` is annotated; anything else passes unchanged."""
    if not hasattr(result, "info"):
        return result
    if result.method != spec.name:
        result = replace(result, method=spec.name)
    if spec.accuracy is not None:
        result.info["error_estimate"] = (spec.accuracy.free_estimate(result) if estimate == "free" and tolerance is None
                                         else spec.accuracy.achieved(scene, options, result, tolerance))
    return result
