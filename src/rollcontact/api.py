"""One dispatcher, a registry of methods and the automatic choice (in the manner of scipy's root_scalar).

Tolerance-aware choice
----------------------
``solve(scene, tolerance=t)`` (method ``"auto"``) takes, over every method that can treat the scene, the cheapest
*setting* whose error estimate is at most t.  Each registered method may carry an :class:`AccuracyModel` that
lists its settings for a scene (option sets such as a polynomial tolerance, a node count or an element count) and
gives, for each, the predicted error and a modelled cost:

* error: the larger of the relative errors of T' and of the peak pressure p0, from measured convergence
  (the discretised T' is first order in the elements across the contact, the polynomial method's truncation is
  controlled by its coefficient decay, its slip iteration is bounded a priori by beta/N^2 in the node count N
  and, after the solve, by its own a-posteriori estimate, from which ``auto`` escalates the node count until the
  tolerance is met (:func:`run_to_tolerance`, ``benchmarks/bench_slip_nodes.py``);
* cost: modelled seconds per solve from operation counts (n^3 for a dense factorisation, nodes^2 per slip
  iteration, iteration counts growing with the friction law's sharpness), with constants measured by
  ``benchmarks/pareto.py``, which also checks the model against measured times.  Only the ranking matters.

The result reports ``info["error_estimate"]`` (the method's estimate for the options actually used, a posteriori
where the method returns one, e.g. the polynomial truncation residual or the discretised grid), and with a
tolerance also ``info["tolerance"]``, ``info["tolerance_met"]`` and ``info["setting"]``.  When no setting meets
the tolerance, the most accurate one is used and the message says so.  Without a tolerance ``auto`` behaves as
before: the cheapest exact method with its defaults.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from rollcontact.result import ContactResult
from rollcontact.scene import Scene, check_real

__all__ = ["METHODS", "AccuracyModel", "MethodSpec", "Setting", "choose_method", "choose_setting", "register_method",
           "setting_for", "solve"]

ROUND_OFF = 1e-14
"""Relative error reported for results exact up to floating-point round-off."""

UNRESOLVED = 1.0
"""A result whose error estimate (relative, T' and p0) is at least this says nothing reliable, not even the size of
T' or p0: ``solve`` with ``"auto"`` treats it as a failure and falls back like one (a corrugation of k a = 293 on
order 170 once reported success with an estimate of 49 and |q| above mu p by 1.4 % of mu p0;
``tests/test_api.py``)."""


class Setting(NamedTuple):
    """One way to run a method on a scene, with what it is predicted to achieve and to cost.

    Immutable; a named tuple rather than a frozen dataclass because ``auto`` builds one per solve and a frozen
    dataclass costs ~2 us to construct, a quarter of a closed-form solve.

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

    def ladder(self, scene: Scene) -> tuple[dict, ...]:  # pragma: no cover - interface
        """Option sets worth considering for the scene, from the cheapest to the most accurate."""
        raise NotImplementedError

    def cost(self, scene: Scene, options: dict) -> float:  # pragma: no cover - interface
        """Modelled time per solve [s] with these options."""
        raise NotImplementedError

    def error(self, scene: Scene, options: dict) -> float:  # pragma: no cover - interface
        """Predicted relative error [1] of T' and p0 with these options (before solving)."""
        raise NotImplementedError

    def achieved(self, scene: Scene, options: dict, result: ContactResult, tolerance: float | None = None) -> float:
        """Error estimate [1] of a result obtained with these options; by default the prediction.

        With a ``tolerance`` the estimate only has to tell whether the result meets it: a model may then return a
        cheaper, larger bound that already does, rather than compute its best estimate."""
        return self.error(scene, options)

    def free_estimate(self, result: ContactResult) -> float:
        """A lower bound [1] of :meth:`achieved` that costs nothing beyond the solve (the FMU's model checks it
        every step without a tolerance, :func:`unresolved`); NaN (the default): none is known."""
        return math.nan

    def escalation(self, scene: Scene, options: dict, estimate: float, tolerance: float) -> dict | None:
        """Options to run next when a result obtained with ``options`` has the a-posteriori error ``estimate``
        above ``tolerance`` (an adaptive method); None (the default): nothing finer to try."""
        return None

    def retry(self, scene: Scene, options: dict, result: ContactResult) -> dict | None:
        """Options to run next when the result obtained with ``options`` failed, where a finer setting may
        succeed; None (the default): the failure stands."""
        return None

    def minimum_cost(self, scene: Scene) -> float:
        """Cost of the cheapest setting [s] (lets ``auto`` skip a method that cannot beat its best so far); the
        first of the ladder unless a subclass knows better without building it."""
        return self.cost(scene, self.ladder(scene)[0])

    def merged(self, options: dict, user: dict) -> dict:
        """The options to run: a chosen setting's ``options`` overridden by the caller's ``user`` options."""
        return {**options, **user}

    def setting_for(self, name: str, scene: Scene, tolerance: float) -> Setting:
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
    cost : int
        Rank for the automatic choice without a tolerance: lower is cheaper.
    fallback : bool
        Whether ``auto`` may use it when a cheaper method reports that its assumptions failed.
    accuracy : AccuracyModel or None
        Settings, error and cost model for the tolerance-aware choice; None: the method is used by ``auto``
        with a tolerance only when no modelled method applies.
    """

    name: str
    function: Callable[..., ContactResult]
    inapplicable: Callable[[Scene], str | None]
    cost: int
    fallback: bool = False
    accuracy: AccuracyModel | None = None


METHODS: dict[str, MethodSpec] = {}


def register_method(name: str, function, inapplicable, cost: int, *, fallback: bool = False,
                    accuracy: AccuracyModel | None = None) -> None:
    """Add (or replace) a method in the registry; one module and one call per fidelity level.

    ``accuracy`` defaults to this module's model for the built-in methods of the same name
    (:data:`BUILTIN_ACCURACY`).
    """
    if accuracy is None:
        accuracy = BUILTIN_ACCURACY.get(name)
    METHODS[name] = MethodSpec(name, function, inapplicable, cost, fallback, accuracy)


def by_rank() -> list[MethodSpec]:
    """The registered methods, cheapest rank first (sorted once per registry content: auto asks per solve)."""
    specs = tuple(METHODS.values())
    if RANKED[0] != specs:
        RANKED[:] = [specs, sorted(specs, key=lambda s: s.cost)]
    return RANKED[1]


RANKED: list = [None, []]  # (registry content it was sorted from, sorted specs)


def choose_method(scene: Scene, tolerance: float | None = None) -> str:
    """Name of the cheapest registered method that is exact for the scene (or, with a tolerance, of the method
    of :func:`choose_setting`)."""
    if tolerance is not None:
        return choose_setting(scene, tolerance).method
    reasons = []
    for spec in by_rank():
        why = spec.inapplicable(scene)
        if why is None:
            return spec.name
        reasons.append(f"{spec.name}: {why}")
    raise ValueError("no registered method can solve this scene (" + "; ".join(reasons) + ")")


def choose_setting(scene: Scene, tolerance: float, names=None) -> Setting:
    """The cheapest setting, over the applicable methods, whose error estimate is at most ``tolerance``.

    Parameters
    ----------
    scene : Scene
        The case.
    tolerance : float
        Requested relative error of T' and p0, > 0.
    names : iterable of str, optional
        Consider only these methods (default: all registered).

    Returns
    -------
    Setting
        When no setting meets the tolerance, the most accurate one (``error_estimate > tolerance``); when no
        method with an accuracy model applies, the cheapest exact method by rank with its defaults (NaN
        estimates).

    Raises
    ------
    ValueError
        Invalid tolerance, or no considered method can treat the scene.
    """
    return cheapest_setting(scene, check_tolerance(tolerance), names)


def cheapest_setting(scene: Scene, tolerance: float, names=None) -> Setting:
    """:func:`choose_setting` for a tolerance already checked (``solve`` checks it once per call)."""
    allowed = None if names is None else set(names)
    best = closest = None
    unmodelled = []
    for spec in by_rank():
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
        if setting.error_estimate <= tolerance:
            if best is None or setting.cost < best.cost:
                best = setting
        elif closest is None or nan_last(setting.error_estimate) < nan_last(closest.error_estimate):
            closest = setting
    if best is not None or closest is not None:
        return best if best is not None else closest
    if unmodelled:
        return Setting(unmodelled[0], {}, math.nan, math.nan)
    raise ValueError("no registered method can solve this scene"
                     + (f" among {sorted(allowed)}" if allowed is not None else ""))


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


def solve(scene: Scene, method: str = "auto", **options) -> ContactResult:
    """Solve a steady 2D rolling-contact scene.

    Parameters
    ----------
    scene : Scene
        The case.
    method : str
        ``"auto"`` or a name in :data:`METHODS`.  ``"auto"`` without a tolerance takes the cheapest method exact
        for the scene with its defaults; with ``tolerance`` the cheapest setting of any applicable method whose
        error estimate meets it (module docstring).  When the chosen method's validity checks fail, ``auto``
        falls back to a registered fallback method such as ``"discretised"``.
    **options
        Passed to the method (see each method's docstring).  With ``"auto"``: ``tolerance`` [1] is the requested
        relative error of T' and p0 (not passed on as such); other options override the chosen setting's and
        only those the chosen method accepts are passed.

    Returns
    -------
    ContactResult
        ``success`` is False, with a message, when the method's assumptions failed or it did not converge.
        ``info["error_estimate"]`` holds the estimated relative error of T' and p0 when the method has an
        accuracy model; with a tolerance also ``tolerance``, ``tolerance_met`` and ``setting`` (options used).

    Raises
    ------
    ValueError
        Unknown method name (the message lists the valid ones), a method that cannot treat the scene, or an
        invalid tolerance.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a rollcontact.Scene, got {type(scene).__name__}")
    if method != "auto":
        if method not in METHODS:
            raise ValueError(f"unknown method {method!r}; valid methods are {['auto', *sorted(METHODS)]}")
        spec = METHODS[method]
        return annotate(spec, scene, options, spec.function(scene, **options))
    tolerance = options.pop("tolerance", None)
    if tolerance is None:
        spec = METHODS[choose_method(scene)]
        result = call_with_known_options(spec, scene, options)
    else:
        tolerance = check_tolerance(tolerance)
        spec, result = run_to_tolerance(cheapest_setting(scene, tolerance), scene, options, tolerance)
    reason = result.message if not result.success else unresolved(result)
    if reason is None:
        return result
    name = spec.name
    backups = [s for s in METHODS.values()
               if s.fallback and s.cost > spec.cost and (tolerance is not None or s.inapplicable(scene) is None)]
    if not backups:
        return result
    if tolerance is None:
        backup_spec = min(backups, key=lambda s: s.cost)
        backup = call_with_known_options(backup_spec, scene, options)
    else:
        try:
            setting = cheapest_setting(scene, tolerance, names=[s.name for s in backups])
        except ValueError:  # no fallback method can treat the scene either
            return result
        backup_spec, backup = run_to_tolerance(setting, scene, options, tolerance)
    info = dict(backup.info, fallback_from=name, fallback_reason=reason)
    return type(backup)(**{**backup.__dict__, "info": info,
                           "message": f"{backup.message} (fallback: {name} failed: {reason})"})


def unresolved(result: ContactResult, estimate: float | None = None) -> str | None:
    """Why a successful ``result`` still says nothing reliable (its error ``estimate``, by default
    ``info["error_estimate"]``, is at least :data:`UNRESOLVED`), or None (also without an estimate: then the
    method's success stands)."""
    if estimate is None:
        estimate = result.info.get("error_estimate", math.nan)
    if not estimate >= UNRESOLVED:
        return None
    return f"its error estimate {estimate:.3g} is at least {UNRESOLVED:g}: the scene is beyond what it resolves"


def run_to_tolerance(setting: Setting, scene: Scene, options: dict, tolerance: float) -> tuple[MethodSpec,
                                                                                               ContactResult]:
    """:func:`run_setting`, then, while the result's a-posteriori estimate misses the tolerance, the settings the
    method's :meth:`AccuracyModel.escalation` names, and after a failure those its :meth:`AccuracyModel.retry`
    names (each finer than the last, so the loop ends).  User options that fix the escalated option stop it."""
    spec, result = run_setting(setting, scene, options, tolerance)
    failures = []
    while spec.accuracy is not None:
        used = result.info["setting"]
        following = (spec.accuracy.escalation(scene, used, result.info["error_estimate"], tolerance)
                     if result.success else spec.accuracy.retry(scene, used, result))
        if following is None or any(key in options for key in following):
            break
        if not result.success:
            failures.append(f"{used}: {result.message}")
        spec, result = run_setting(Setting(spec.name, following, math.nan, math.nan), scene, options, tolerance)
    if failures:
        result = type(result)(**{**result.__dict__, "message": f"{result.message} (after failing with "
                                                                  + "; ".join(failures) + ")"})
    return spec, result


def run_setting(setting: Setting, scene: Scene, options: dict, tolerance: float) -> tuple[MethodSpec, ContactResult]:
    """Run a chosen setting (user options override it) and record the tolerance outcome in the result."""
    spec = METHODS[setting.method]
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


def call_with_known_options(spec: MethodSpec, scene: Scene, options: dict) -> ContactResult:
    """Call the method with the options it accepts, and annotate the result with its error estimate."""
    used = used_options(spec, options)
    return annotate(spec, scene, used, spec.function(scene, **used))


def used_options(spec: MethodSpec, options: dict) -> dict:
    accepted = getattr(spec.function, "options", ())
    return {k: v for k, v in options.items() if k in accepted}


def annotate(spec: MethodSpec, scene: Scene, options: dict, result: ContactResult,
             tolerance: float | None = None) -> ContactResult:
    """Put the method's error estimate for the options used into ``result.info`` (a fresh dict per result); with
    a ``tolerance``, one that need only tell whether the result meets it (:meth:`AccuracyModel.achieved`)."""
    if spec.accuracy is not None and isinstance(result, ContactResult):
        result.info["error_estimate"] = spec.accuracy.achieved(scene, options, result, tolerance)
    return result


def check_tolerance(tolerance) -> float:
    """A requested relative error: finite and > 0 (a ValueError naming the value otherwise)."""
    return check_real("tolerance", tolerance, lower=0.0, lower_open=True, unit="1")


def nan_last(value: float) -> float:
    return math.inf if math.isnan(value) else value


# ----------------------------------------------------------------------------- accuracy models of the methods
# Constants measured by benchmarks/pareto.py (which prints fitted values and checks model against measurement):
# times on one core of the 2.5 GHz Xeon of benchmarks/results/pareto.md; errors as bounds over its cases.
CLOSED_FORM_COST = 8.8e-6  # s, Hertz + Carter through solve()
POLYNOMIAL_COST = 7.5e-5  # s, normal Newton, tangential root and validity checks (order-independent to ~10 %)
POLYNOMIAL_HARMONIC_COST = 7.5e-5  # s per surface harmonic
# slip iteration (benchmarks/bench_slip_nodes.py, table E): Newton steps ~ 3 + 6.8 beta (beta: friction_sharpness);
# s per step with N nodes a + b N^2 + c N^3 (dense node tables; a also carries the a-posteriori estimate's share)
SLIP_ITERATIONS = (3.0, 6.8)
SLIP_COST = (5.2e-4, 8.6e-8, 5.7e-10)
DIRECT_COST = (1.7e-3, 2.8e-8, 0.0)  # s: discretised Coulomb, a + b n^2 + c n^3 (c fits 0 up to n = 1600)
STRUCTURED_ITERATIONS = (20.0, 85.0)  # Newton iterations of the discretised velocity-dependent solve ~ 20 + 85 beta
STRUCTURED_COST = (1.5e-4, 9.6e-9, 8.9e-12)  # s per such Newton iteration, a + b n^2 + c n^3

POLYNOMIAL_TOLERANCES = tuple(10.0**-k for k in range(2, 13))
SLIP_NODES = (8, 16, 32, 64, 128, 256, 512)  # requested; the ladder offers the distinct counts that run
# Slip-iteration T' error against the nodes N that run (benchmarks/bench_slip_nodes.py, 1024-node references):
SLIP_NODE_ERROR = 1.5  # relative T' error <= SLIP_NODE_ERROR * sharpness / N^2 (largest measured 0.96)
SLIP_CONVERGENCE = 2.0  # escalation aims at N (estimate / t)^(1/2): the estimate's typical decay
DISCRETISED_ELEMENTS = (50, 100, 200, 400, 800, 1600)
# relative T' error <= 4.0 w/n (w = window over the Hertz width 2a): the largest coefficient measured by
# benchmarks/bench_discretised_estimate.py is 3.0 (the split contact at 1e-3 of the saturation creep, n = 800; at
# creeps near saturation it stays below 1.7)
DISCRETISED_FORCE_ERROR = 4.0
DISCRETISED_PRESSURE_ERROR = 3.0  # relative p0 error <= 3 (w/n)^2
# The extrapolated setting (solve_discretised(extrapolate=m)): T' from n and 2n elements, each level the mean over m
# grid placements.  Relative T' error <= 3.2 w/(m n) (n the coarser level): the placement mean leaves a first-order
# residue that falls like 1/m (benchmarks/bench_discretised_estimate.py, table C: m c = err m n / w at most 2.12,
# on the split contact near full stick, the worst case, scanned at n = 50..400; m = 2, 4, 8, 16 alike; the bound on
# the automatic window is >= 2.03 times every one of 450 errors); p0 is the finer level's, <= 3 (w/2n)^2.
# Calibrated for m in [2, 16]; auto offers m = 8 and 16
EXTRAPOLATION_PLACEMENTS = (8, 16)
EXTRAPOLATED_FORCE_ERROR = 3.2
EXTRAPOLATION_CALIBRATED = (2, 16)  # the range of m the bound was measured for


class ClosedFormAccuracy(AccuracyModel):
    """Hertz + Carter: exact (round-off) wherever applicable, one setting."""

    floor = CLOSED_FORM_COST

    def ladder(self, scene):
        return ({},)

    def cost(self, scene, options):
        return CLOSED_FORM_COST

    def error(self, scene, options):
        return ROUND_OFF

    def minimum_cost(self, scene):
        return CLOSED_FORM_COST

    def setting_for(self, name, scene, tolerance):
        # the one setting, without the ladder walk: auto asks on every solve of a Hertzian scene
        return Setting(name, {}, ROUND_OFF, CLOSED_FORM_COST)


class PolynomialAccuracy(AccuracyModel):
    """Polynomial method: T', a, Delta and a* are exact (Bessel moments); the order limits p(x) and p0.

    Settings: the truncation ``tolerance`` (the method picks the order whose neglected coefficients stay below
    it relative to the Hertz slope; the p0 error follows) and, for velocity-dependent friction, the slip
    iteration's ``nodes``.  Counts are the nodes N that run (:func:`slip_nodes`: requests below the law's and the
    pressure's floor run the floor, so the ladder offers each count once).  A priori the T' error is below
    ``SLIP_NODE_ERROR * beta / N^2`` with the law's sharpness ``beta`` (:func:`friction_sharpness`), a bound over
    ``benchmarks/bench_slip_nodes.py``'s cases but mostly 10-100 times pessimistic; a result carries the slip
    iteration's a-posteriori estimate (:func:`rollcontact.velocity_friction.force_error_estimate`), which
    :meth:`achieved` reports.  So :meth:`setting_for` starts at the cheapest count and :meth:`escalation` names
    the count to run next while the estimate misses the tolerance.  An explicit ``order`` has no prediction
    (NaN); the result's truncation residual then gives the estimate.
    """

    floor = POLYNOMIAL_COST

    def ladder(self, scene):
        if scene.friction.is_constant:
            return tuple({"tolerance": t} for t in POLYNOMIAL_TOLERANCES)
        floor = slip_floor(scene)  # slip_nodes per rung, without hashing the scene for each
        return tuple({"nodes": n} for n in sorted({max(n, floor) for n in SLIP_NODES}))

    def cost(self, scene, options):
        base = POLYNOMIAL_COST + POLYNOMIAL_HARMONIC_COST * len(scene.surface.harmonics)
        if scene.friction.is_constant:
            return base
        nodes = slip_nodes(scene, options.get("nodes", default_option("polynomial", "nodes")))
        iterations = SLIP_ITERATIONS[0] + SLIP_ITERATIONS[1] * friction_sharpness(scene)
        a, b, c = SLIP_COST
        return base + iterations * (a + b * nodes * nodes + c * nodes**3)

    def minimum_cost(self, scene):
        # with constant friction every setting costs the same: no ladder to build
        return self.cost(scene, {}) if scene.friction.is_constant else super().minimum_cost(scene)

    def error(self, scene, options):
        if options.get("order") is not None:
            return math.nan
        truncation = options.get("tolerance", default_option("polynomial", "tolerance"))
        return max(truncation, SLIP_NODE_ERROR * self.slip_scale(scene, options))

    def achieved(self, scene, options, result, tolerance=None):
        """The truncation residual and, for the slip iteration, its a-posteriori estimate (a Newton step's cost,
        :func:`slip_estimate`); with a ``tolerance`` that the a-priori bound ``SLIP_NODE_ERROR beta/N^2`` of the
        nodes that ran already meets (a converged result), that bound instead: as certain as the estimate (both
        are calibrated on ``benchmarks/bench_slip_nodes.py``'s cases, the discretised method is certified by its
        bound alone) and free, where the estimate is ~20 % of the solve (:func:`ran_slip_bound`)."""
        # residual: the first neglected coefficients relative to the leading one (inf when the solve failed)
        if not math.isfinite(result.residual):
            return math.nan
        floor = max(result.residual, ROUND_OFF)
        if tolerance is not None and result.success:
            bound = max(floor, ran_slip_bound(scene, result))
            if bound <= tolerance:
                return bound
        slip = slip_estimate(result)
        return math.nan if math.isnan(slip) else max(floor, slip)

    def free_estimate(self, result):
        """The truncation residual (the slip iteration's estimate, the rest of :meth:`achieved`, costs a Newton
        step)."""
        return result.residual if math.isfinite(result.residual) else math.nan

    def setting_for(self, name, scene, tolerance):
        """For velocity-dependent friction the cheapest count, the start of the adaptive path (:meth:`escalation`
        moves up while the result's estimate misses the tolerance), with the bound of the largest count, which the
        path can reach, as its error; otherwise the cheapest setting whose bound meets the tolerance.

        Starting at the floor rather than where the bound meets t is cheaper: the bound is 10-100 times pessimistic
        for most laws, and escalation from the floor costs 1.0-1.4 times the cheapest count whose estimate meets t
        on average (``benchmarks/bench_slip_nodes.py``, table C).
        """
        if scene.friction.is_constant:
            # every truncation tolerance costs the same and bounds the error by itself: the loosest one <= t (the
            # ladder walk's answer without its 22 model calls, ~25 us per auto solve)
            loosest = next((t for t in POLYNOMIAL_TOLERANCES if t <= tolerance), POLYNOMIAL_TOLERANCES[-1])
            options = {"tolerance": loosest}
            return Setting(name, options, self.error(scene, options), self.cost(scene, options))
        ladder = self.ladder(scene)
        return Setting(name, ladder[0], self.error(scene, ladder[-1]), self.cost(scene, ladder[0]))

    def escalation(self, scene, options, estimate, tolerance) -> dict | None:
        """Options to run next when a result run with ``options`` has error ``estimate`` above ``tolerance``.

        For velocity-dependent friction, the rung expected to meet it: the slip estimate ``E`` at N nodes typically
        falls like ``N^-SLIP_CONVERGENCE`` (``benchmarks/bench_slip_nodes.py``, table C), so the first count
        ``>= N (E/t)^(1/SLIP_CONVERGENCE)``, else the largest.  None when the estimate meets the tolerance (or is
        NaN), for Coulomb friction, or when no count of the ladder exceeds N: every call moves up, so escalating
        until None ends.
        """
        if scene.friction.is_constant or not estimate > tolerance:
            return None
        nodes = slip_nodes(scene, options.get("nodes", default_option("polynomial", "nodes")))
        larger = [o for o in self.ladder(scene) if o["nodes"] > nodes]
        if not larger:
            return None
        target = nodes * (estimate / tolerance) ** (1.0 / SLIP_CONVERGENCE)
        return next((o for o in larger if o["nodes"] >= target), larger[-1])

    @staticmethod
    def slip_scale(scene, options) -> float:
        """``beta / N^2`` of the nodes N that run (0 when the slip iteration does not)."""
        if scene.friction.is_constant or scene.creep == 0.0:
            return 0.0
        nodes = slip_nodes(scene, options.get("nodes", default_option("polynomial", "nodes")))
        return friction_sharpness(scene) / (nodes * nodes)


def slip_estimate(result) -> float:
    """The slip iteration's a-posteriori relative T' error of a polynomial result (NaN when it did not converge;
    0 when it did not run: Coulomb friction, zero creep, or the polynomial method's Coulomb reduction; and 0 on
    several patches, whose estimate is the result's residual, :mod:`rollcontact.split_friction`)."""
    from rollcontact.velocity_friction import VelocityFrictionDistributions

    dist = result.distributions
    return dist.force_error if isinstance(dist, VelocityFrictionDistributions) else 0.0


def ran_slip_bound(scene, result) -> float:
    """The a-priori T' error bound ``SLIP_NODE_ERROR beta/N^2`` of the N nodes the slip iteration of a polynomial
    result ran (0 where it did not run, as :func:`slip_estimate`)."""
    from rollcontact.velocity_friction import VelocityFrictionDistributions

    dist = result.distributions
    if not isinstance(dist, VelocityFrictionDistributions):
        return 0.0
    return SLIP_NODE_ERROR * friction_sharpness(scene) / dist.nodes**2


def slip_nodes(scene, nodes: int) -> int:
    """Nodes the slip iteration runs for ``nodes`` requested: at least :func:`slip_floor`."""
    return max(int(nodes), slip_floor(scene))


@lru_cache(maxsize=64)
def slip_floor(scene) -> int:
    """Fewest nodes the slip iteration runs for the scene (:func:`rollcontact.velocity_friction.effective_nodes`
    with the scene's pressure; 0 without a polynomial normal solution).  Cached: every rung of a ladder asks."""
    from rollcontact.velocity_friction import effective_nodes

    pressure = normal_pressure(scene.normal_load_per_length, scene.radius, scene.material, scene.surface,
                               scene.axis_position)
    if pressure is None:  # no load, or the normal problem failed: nothing to raise against
        return 0
    return effective_nodes(0, pressure, scene.material.contact_modulus, scene.friction, scene.rolling_speed)


@lru_cache(maxsize=32)
def normal_pressure(load, radius, material, surface, axis_position) -> np.ndarray | None:
    """Sine coefficients of p from the polynomial method's normal problem at its default tolerance, or None.

    Cached on the geometry alone (creep, friction and speed do not enter): every rung of a ladder asks for it.  A
    flat surface has Hertz's ``p = p0 sin(theta)`` (eq 9): no normal solve, which the FMU's model would otherwise
    repeat at every step whose load changed.
    """
    from rollcontact.closed_form import hertz
    from rollcontact.polynomial import solve_polynomial

    if surface.is_flat:
        return None if load == 0.0 else np.array([0.0, hertz(load, radius, material.contact_modulus)[1]])
    normal = solve_polynomial(Scene(load, radius=radius, material=material, surface=surface,
                                    axis_position=axis_position), check=False)
    return normal.info.get("pressure_coefficients")


class DiscretisedAccuracy(AccuracyModel):
    """Discretised method: T' first order and p0 second order in the elements across the contact.

    The bound ``max(4.0 w/n, 3 (w/n)^2)`` (w the grid length over the Hertz width 2a, n the elements) holds
    for every case of ``benchmarks/bench_discretised_estimate.py`` (Hertz/Carter at three loads on a fixed window
    and six creeps of both signs, corrugations up to a split contact at four creeps, a quartic profile,
    falling friction).  The first-order coefficient varies 0-3 with where the patch edges fall on the grid and
    with the creep (largest on the split contact at small creep), so the bound is several times pessimistic in
    the median.  The bound uses the Hertz width 2a and holds where the patches are about as wide; a result's
    estimate (:meth:`achieved`) puts in its patches' widths where they are narrower (:func:`patch_widths`): on short
    corrugations with small satellite patches the Hertz-width bound was exceeded by T' (up to 2.9 times for one
    grid, 5 times for the extrapolated pair; measured against the polynomial method's several patches on 64 scenes
    of 4-10 mm / 10-40 um corrugation, ``benchmarks/bench_multipatch.py``), the estimate is not (at most 0.58), and
    ``auto`` escalates while it misses the tolerance (:meth:`escalation`).  No estimate from the solution's
    convergence replaces the bound:
    the answer at n itself moves by up to the error when the grid moves by half an element, and the two-grid
    estimate (3 times the largest difference to two solves of n/2 elements at different placements) bounds the
    error but is larger than this bound in the median (same benchmark).  Element counts below the automatic
    grid's resolution of the shortest surface wavelength are not offered.

    The extrapolated setting ``{"elements": n, "extrapolate": m}`` averages that placement-dependent part over m
    placements and removes the smooth first-order part by Richardson extrapolation from n and 2n elements: its
    bound is ``max(3.2 w/(m n), 3 (w/2n)^2)`` (:data:`EXTRAPOLATED_FORCE_ERROR`), w from the automatic window,
    which is at least as long as the fitted window it runs on; m outside :data:`EXTRAPOLATION_CALIBRATED` has no
    calibrated bound (NaN).  It costs ``m`` solves at n and at 2n, and pays where a single grid would need more
    than ~3 times 2n elements: tolerances below ~1e-2 on a scene only this method treats (a split contact).
    Offered with m = :data:`EXTRAPOLATION_PLACEMENTS`, its finer level at most the largest single grid offered,
    for constant friction (with velocity-dependent friction each of the 2m structured solves costs ~20-100 Newton
    iterations).
    """

    floor = DIRECT_COST[0]  # the structured (velocity-dependent) solve's ~20 iterations cost more

    def ladder(self, scene):
        needed = self.resolution(scene)
        rungs = tuple({"elements": n} for n in DISCRETISED_ELEMENTS if n >= needed)
        pairs = tuple({"elements": n, "extrapolate": m} for m in EXTRAPOLATION_PLACEMENTS for n in DISCRETISED_ELEMENTS
                      if n >= needed and 2 * n <= DISCRETISED_ELEMENTS[-1]) if scene.friction.is_constant else ()
        return (rungs + pairs) or ({},)  # the automatic grid resolves the shortest wavelength

    def cost(self, scene, options):
        placements = options.get("extrapolate", 0)
        if placements:
            n = self.pair_elements(options)
            # plus the normal solve on the automatic grid that fits the window, costed as a whole solve
            return (placements * (self.solve_cost(scene, n) + self.solve_cost(scene, 2 * n))
                    + self.solve_cost(scene, automatic_grid(scene).elements))
        return self.solve_cost(scene, options.get("elements") or automatic_grid(scene).elements)

    @staticmethod
    def pair_elements(options) -> int:
        """The coarser level's elements of an extrapolated pair (``solve_discretised``'s default when unset)."""
        from rollcontact.discretised import DEFAULT_ELEMENTS

        return options.get("elements") or DEFAULT_ELEMENTS

    @staticmethod
    def solve_cost(scene, n: int) -> float:
        """Modelled time [s] of one solve on n elements."""
        if scene.friction.is_constant:
            a, b, c = DIRECT_COST
            return a + b * n * n + c * n**3
        a, b, c = STRUCTURED_COST
        iterations = STRUCTURED_ITERATIONS[0] + STRUCTURED_ITERATIONS[1] * friction_sharpness(scene)
        return iterations * (a + b * n * n + c * n**3)

    def minimum_cost(self, scene):
        return self.cost(scene, {"elements": DISCRETISED_ELEMENTS[0]})

    def merged(self, options, user):
        """A caller's ``elements`` fixes one grid of that many elements: the extrapolated pair is then dropped
        unless the caller asks for it too."""
        if "elements" in user and "extrapolate" not in user:
            options = {k: v for k, v in options.items() if k != "extrapolate"}
        return {**options, **user}

    def setting_for(self, name, scene, tolerance):
        """The cheapest of the fewest single-grid elements and, for each m offered, the fewest extrapolated pair
        whose bounds meet the tolerance, any count from the ladder's first to its last (at least the surface
        resolution); when none does, the most accurate of them at their largest counts, with its bound.

        Not only the ladder's rungs: the bounds are within 1.35-2 times the worst measured error, so the next rung
        up, up to twice the elements needed, would cost up to 4-8 times (n^2 to n^3).
        """
        if scene.normal_load_per_length == 0.0:
            return super().setting_for(name, scene, tolerance)
        ratio = automatic_length(scene) / (2.0 * hertz_half_width(scene))  # n times w/n of the bound
        floor = max(self.resolution(scene), DISCRETISED_ELEMENTS[0])
        largest = DISCRETISED_ELEMENTS[-1]
        single = self.fewest({}, ratio * max(DISCRETISED_FORCE_ERROR / tolerance,
                                             math.sqrt(DISCRETISED_PRESSURE_ERROR / tolerance)),
                             floor, largest, scene, tolerance)
        candidates = [single]
        if floor <= largest // 2 and scene.friction.is_constant:
            candidates += [self.fewest({"extrapolate": m},
                                       ratio * max(EXTRAPOLATED_FORCE_ERROR / (m * tolerance),
                                                   0.5 * math.sqrt(DISCRETISED_PRESSURE_ERROR / tolerance)),
                                       floor, largest // 2, scene, tolerance) for m in EXTRAPOLATION_PLACEMENTS]
        meeting = [s for s in candidates if s.error_estimate <= tolerance]
        if meeting:
            return Setting(name, *min(meeting, key=lambda s: s.cost)[1:])
        return Setting(name, *min(candidates, key=lambda s: s.error_estimate)[1:])

    def fewest(self, extra: dict, needed: float, floor: int, top: int, scene, tolerance) -> Setting:
        """The setting ``{"elements": n, **extra}`` with the fewest n in [floor, top] whose bound meets the
        tolerance (``needed``: the real n the bound asks for), else n = top."""
        n = min(max(math.ceil(min(needed, top)), floor), top)
        options = {"elements": n, **extra}
        while n < top and self.error(scene, options) > tolerance:  # rounding of the ceil
            n += 1
            options = {"elements": n, **extra}
        return Setting("", options, self.error(scene, options), self.cost(scene, options))

    def error(self, scene, options):
        if scene.normal_load_per_length == 0.0:
            return 0.0
        placements = options.get("extrapolate", 0)
        if placements:
            return self.extrapolated_bound(scene, automatic_length(scene), self.pair_elements(options), placements)
        window = options.get("window")
        length = automatic_length(scene) if window is None else float(window[1]) - float(window[0])
        elements = options.get("elements") or automatic_grid(scene, None, window).elements
        return self.bound(scene, length, elements)

    def achieved(self, scene, options, result, tolerance=None):
        """The bound with the result's patches: the Hertz width 2a in it replaced by :func:`patch_widths`' widths
        where the patches are narrower (short corrugations), so never below the a-priori :meth:`error` (as cheap
        with a tolerance as without)."""
        grid = result.info.get("grid")
        if grid is None:  # no load: no grid, nothing to get wrong
            return 0.0
        widths = patch_widths(result, 2.0 * hertz_half_width(scene))
        placements = options.get("extrapolate", 0)
        if placements:  # the grid is the finer level's, on the fitted window
            return self.extrapolated_bound(scene, grid.length, grid.elements // 2, placements, widths)
        return self.bound(scene, grid.length, grid.elements, widths)

    def escalation(self, scene, options, estimate, tolerance) -> dict | None:
        """Options to run next when the result's patch-aware estimate (:meth:`achieved`) misses the tolerance
        that the a-priori bound (Hertz width) promised: :meth:`setting_for` with the tolerance tightened by the
        factor the patches cost, ``t error/estimate`` (one grid or the pair, whichever is then cheaper).  None
        when the estimate meets the tolerance (or is NaN), or that setting's bound is not below the one run:
        every call lowers the bound, so escalating until None ends.
        """
        if not estimate > tolerance or "elements" not in options:
            return None
        predicted = self.error(scene, options)
        if not predicted > 0.0:  # NaN (an uncalibrated m) or no load: nothing to scale
            return None
        following = self.setting_for("discretised", scene, tolerance * predicted / estimate).options
        return following if self.error(scene, following) < predicted else None

    def retry(self, scene, options, result) -> dict | None:
        """After a failed slip iteration (velocity-dependent friction) on a single grid, twice the elements, up to
        the largest offered: the failure is mostly a slip zone shorter than an element at a patch end (see
        :func:`rollcontact.discretised.solve_discretised`, which does the same on its automatic grid)."""
        elements = options.get("elements")
        if scene.friction.is_constant or not elements or options.get("extrapolate") \
                or 2 * elements > DISCRETISED_ELEMENTS[-1]:
            return None
        return {"elements": 2 * elements}

    @staticmethod
    def resolution(scene) -> int:
        """Elements the automatic grid needs for the shortest surface wavelength (0 without harmonics)."""
        from rollcontact.discretised import ELEMENTS_PER_WAVELENGTH

        waves = [2.0 * math.pi / h.wavenumber for h in scene.surface.harmonics if h.amplitude > 0.0]
        if not waves or scene.normal_load_per_length == 0.0:
            return 0
        return math.ceil(ELEMENTS_PER_WAVELENGTH * automatic_length(scene) / min(waves))

    @staticmethod
    def bound(scene, length: float, elements: int, widths: PatchWidths | None = None) -> float:
        """``max(4.0 h/W_T, 3 (h/W_p)^2)``, h = length/elements; the widths W [m] default to the Hertz width 2a
        (then h/2a = w/n)."""
        force, pressure = widths or PatchWidths.hertz(scene)
        h = length / elements
        return max(DISCRETISED_FORCE_ERROR * h / force, DISCRETISED_PRESSURE_ERROR * (h / pressure) ** 2)

    @staticmethod
    def extrapolated_bound(scene, length: float, elements: int, placements: int,
                           widths: PatchWidths | None = None) -> float:
        """``max(3.2 h/(m W_T), 3 (h/(2 W_p))^2)`` for the coarser level's n (h = length/n) and m placements, the
        widths as in :meth:`bound`; NaN for an m outside :data:`EXTRAPOLATION_CALIBRATED`."""
        low, high = EXTRAPOLATION_CALIBRATED
        if not low <= placements <= high:
            return math.nan
        force, pressure = widths or PatchWidths.hertz(scene)
        h = length / elements
        return max(EXTRAPOLATED_FORCE_ERROR * h / (placements * force),
                   DISCRETISED_PRESSURE_ERROR * (0.5 * h / pressure) ** 2)


def default_option(name: str, option: str):
    """Default of the keyword-only ``option`` of registered method ``name`` (one source of truth: the method)."""
    return METHODS[name].function.__kwdefaults__[option]


# the method modules import this one, so theirs are imported when first needed
def automatic_grid(scene, elements=None, window=None):
    """:func:`rollcontact.discretised.automatic_grid`."""
    from rollcontact.discretised import automatic_grid as grid_for

    return grid_for(scene, elements, window)


@lru_cache(maxsize=32)
def automatic_length(scene) -> float:
    """Length [m] of the automatic grid's window (cached: each setting of the ladder asks for it)."""
    return automatic_grid(scene).length


class PatchWidths(NamedTuple):
    """Widths [m] that scale the discretised error bounds: T' error ~ h/force, p0 error ~ (h/pressure)^2."""

    force: float
    pressure: float

    @classmethod
    def hertz(cls, scene) -> PatchWidths:
        """Both the Hertz width 2a: the a-priori bounds, before the patches are known."""
        width = 2.0 * hertz_half_width(scene)
        return cls(width, width)


def patch_widths(result: ContactResult, hertz_width: float) -> PatchWidths:
    """The widths of a discretised result's patches in its error bounds, at most the Hertz width ``hertz_width``.

    T': every patch k (width ``w_k``, force ``T'_k``, from the tabulated fields) errs by about ``h/w_k |T'_k|`` to
    first order, its edges and its stick zone lying anywhere within their elements, so relative to T' the error is
    ~ ``h/W_T`` with ``1/W_T = sum_k |T'_k| / (w_k |T'|)``.  A small satellite patch beside the main one weighs by
    its force: at small creep it slips fully while |T'| is small.  p0 (second order): the width of the patch that
    holds the largest pressure.  ``benchmarks/bench_multipatch.py`` (table B) measures the T' coefficient
    ``error W_T/h`` against the polynomial method's several patches: at most 1.3 for one grid, 1.9/m for the pair
    over m placements, under the bounds' 4.0 and 3.2/m (the Hertz width alone let the error reach 2.9 and 5
    times the bound); the p0 errors stay below 0.03 of the estimate.  Without traction (zero creep, a failed
    solve) W_T is the Hertz width.
    """
    fields = result.distributions
    x, p, q = np.asarray(fields.x), np.asarray(fields.p), np.asarray(fields.q)
    patches = result.info.get("patches") or []
    if x.size < 2 or not patches:
        return PatchWidths(hertz_width, hertz_width)
    h = x[1] - x[0]
    # element centres lie half an element inside the patch edges
    forces = [(h * float(q[(x > lo) & (x < hi)].sum()), hi - lo) for lo, hi in patches]
    total = abs(sum(force for force, _ in forces))
    weighted = sum(abs(force) / width for force, width in forces) / total if total > 0.0 else 0.0
    peak = x[int(np.argmax(p))]
    holding = next((hi - lo for lo, hi in patches if lo <= peak <= hi), hertz_width)
    return PatchWidths(min(hertz_width, 1.0 / weighted) if weighted > 0.0 else hertz_width,
                       min(hertz_width, holding))


def hertz_half_width(scene) -> float:
    """Hertz half-width a [m] of the scene's load and radius."""
    from rollcontact.closed_form import hertz

    return hertz(scene.normal_load_per_length, scene.radius, scene.material.contact_modulus)[0]


def friction_sharpness(scene: Scene) -> float:
    """``beta = max|dmu/dv| v_max / mu_s`` [1] over slip velocities ``0..v_max``, ``v_max = V max(|xi|, mu a/R)``.

    How much mu changes across the slip velocities of the patch: it sets the error of the slip iteration.
    """
    mu = scene.friction_coefficient
    return sharpness(scene.friction, scene.rolling_speed * max(abs(scene.creep), mu * hertz_half_width(scene)
                                                               / scene.radius))


SHARPNESS_SAMPLES = np.linspace(0.0, 1.0, 9)
"""Where :func:`sharpness` samples dmu/dv, in units of v_max."""


@lru_cache(maxsize=64)
def sharpness(friction, v_max: float) -> float:
    # cached: every setting of a ladder asks for the same scene's value
    slopes = np.abs(friction.derivative(v_max * SHARPNESS_SAMPLES))
    return float(np.max(slopes)) * v_max / friction.static_coefficient


BUILTIN_ACCURACY: dict[str, AccuracyModel] = {"closed_form": ClosedFormAccuracy(),
                                              "polynomial": PolynomialAccuracy(),
                                              "discretised": DiscretisedAccuracy()}
"""Accuracy models of the methods shipped with the package, by registry name (see :func:`register_method`)."""
