"""One dispatcher, a registry of methods and the automatic choice (in the manner of scipy's root_scalar)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from rollcontact.result import ContactResult
from rollcontact.scene import Scene

__all__ = ["METHODS", "MethodSpec", "choose_method", "register_method", "solve"]


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
        Rank for the automatic choice: lower is cheaper.
    fallback : bool
        Whether ``auto`` may use it when a cheaper method reports that its assumptions failed.
    """

    name: str
    function: Callable[..., ContactResult]
    inapplicable: Callable[[Scene], str | None]
    cost: int
    fallback: bool = False


METHODS: dict[str, MethodSpec] = {}


def register_method(name: str, function, inapplicable, cost: int, *, fallback: bool = False) -> None:
    """Add (or replace) a method in the registry; one module and one call per fidelity level."""
    METHODS[name] = MethodSpec(name, function, inapplicable, cost, fallback)


def choose_method(scene: Scene) -> str:
    """Name of the cheapest registered method that is exact for the scene."""
    reasons = []
    for spec in sorted(METHODS.values(), key=lambda s: s.cost):
        why = spec.inapplicable(scene)
        if why is None:
            return spec.name
        reasons.append(f"{spec.name}: {why}")
    raise ValueError("no registered method can solve this scene (" + "; ".join(reasons) + ")")


def solve(scene: Scene, method: str = "auto", **options) -> ContactResult:
    """Solve a steady 2D rolling-contact scene.

    Parameters
    ----------
    scene : Scene
        The case.
    method : str
        ``"auto"`` (the cheapest method exact for the scene; when its validity checks fail it falls back to a
        registered fallback method such as ``"discretised"``) or a name in :data:`METHODS`.
    **options
        Passed to the method (see each method's docstring); with ``"auto"`` only options the chosen method
        accepts are passed.

    Returns
    -------
    ContactResult
        ``success`` is False, with a message, when the method's assumptions failed or it did not converge.

    Raises
    ------
    ValueError
        Unknown method name (the message lists the valid ones), or a method that cannot treat the scene.
    """
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a rollcontact.Scene, got {type(scene).__name__}")
    if method != "auto":
        if method not in METHODS:
            raise ValueError(f"unknown method {method!r}; valid methods are {['auto', *sorted(METHODS)]}")
        return METHODS[method].function(scene, **options)
    name = choose_method(scene)
    result = call_with_known_options(METHODS[name], scene, options)
    if result.success:
        return result
    for spec in sorted(METHODS.values(), key=lambda s: s.cost):
        if spec.fallback and spec.cost > METHODS[name].cost and spec.inapplicable(scene) is None:
            backup = call_with_known_options(spec, scene, options)
            info = dict(backup.info, fallback_from=name, fallback_reason=result.message)
            return type(backup)(**{**backup.__dict__, "info": info,
                                   "message": f"{backup.message} (fallback: {name} failed: {result.message})"})
    return result


def call_with_known_options(spec: MethodSpec, scene: Scene, options: dict) -> ContactResult:
    accepted = getattr(spec.function, "options", ())
    return spec.function(scene, **{k: v for k, v in options.items() if k in accepted})
