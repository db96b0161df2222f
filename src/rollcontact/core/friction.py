"""Friction laws mu(v) of the slip velocity v = V |s| [m/s] (docs/physics.md, Velocity-dependent friction).

Every law is a small frozen dataclass with ``coefficient(slip_velocity)`` (vectorised) and
``static_coefficient`` (mu at v = 0).  ``is_constant`` tells solvers when the Coulomb closed forms apply.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollcontact.core.checks import SceneError, positive


class FrictionLaw:
    """Interface: mu as a function of slip velocity v [m/s] >= 0."""

    is_constant = False

    @property
    def static_coefficient(self) -> float:
        """mu(0) [1]."""
        return float(self.coefficient(0.0))

    @property
    def maximum_coefficient(self) -> float:
        """sup mu(v) [1] over v >= 0: the bound of ``|q| <= mu p`` and ``|T'| <= mu N'``; mu(0) for a law that
        does not rise (a law that rises overrides it)."""
        return self.static_coefficient

    def coefficient(self, slip_velocity):  # pragma: no cover - interface
        raise NotImplementedError

    def describe(self) -> str:  # pragma: no cover - interface
        """The law's name, formula and values with their units, in one line (figure titles, summaries)."""
        raise NotImplementedError

    def derivative(self, slip_velocity):
        """dmu/dv [s/m], by central differences unless a law overrides it."""
        v = np.asarray(slip_velocity, dtype=float)
        h = 1e-7 * np.maximum(1.0, v)
        return (self.coefficient(v + h) - self.coefficient(np.maximum(v - h, 0.0))) / (h + np.minimum(v, h))


@dataclass(frozen=True)
class Coulomb(FrictionLaw):
    """Constant friction coefficient mu [1] (Coulomb's law)."""

    mu: float
    is_constant = True

    def __post_init__(self):
        object.__setattr__(self, "mu", positive("friction coefficient mu", self.mu))

    @property
    def static_coefficient(self) -> float:
        return self.mu

    def describe(self) -> str:
        return f"Coulomb, mu = {self.mu:g}"

    def coefficient(self, slip_velocity):
        return self.mu + 0.0 * np.asarray(slip_velocity, dtype=float)

    def derivative(self, slip_velocity):
        return 0.0 * np.asarray(slip_velocity, dtype=float)


@dataclass(frozen=True)
class ExponentialFalling(FrictionLaw):
    """Exponential falling friction mu(v) = mu_s [(1 - A) exp(-B v) + A] (Polach).

    Parameters
    ----------
    mu_static : float
        mu_s = mu(0) [1].
    kinetic_ratio : float
        A = mu(inf)/mu_s [1], 0 < A <= 1.
    decay : float
        B [s/m] >= 0.
    """

    mu_static: float
    kinetic_ratio: float = 0.4
    decay: float = 0.6

    def __post_init__(self):
        from rollcontact.core.checks import check_real

        object.__setattr__(self, "mu_static", positive("friction mu_static", self.mu_static))
        object.__setattr__(self, "kinetic_ratio",
                           check_real("friction kinetic_ratio", self.kinetic_ratio, lower=0.0, upper=1.0,
                                      lower_open=True))
        object.__setattr__(self, "decay", positive("friction decay", self.decay, allow_zero=True))

    @property
    def is_constant(self) -> bool:
        return self.kinetic_ratio == 1.0 or self.decay == 0.0

    @property
    def static_coefficient(self) -> float:
        return self.mu_static

    def coefficient(self, slip_velocity):
        v = np.asarray(slip_velocity, dtype=float)
        return self.mu_static * ((1.0 - self.kinetic_ratio) * np.exp(-self.decay * v) + self.kinetic_ratio)

    def describe(self) -> str:
        return (f"exponential falling mu(v) = mu_s [(1 - A) exp(-B v) + A], mu_s = {self.mu_static:g}, "
                f"A = {self.kinetic_ratio:g}, B = {self.decay:g} s/m")

    def derivative(self, slip_velocity):
        v = np.asarray(slip_velocity, dtype=float)
        return -self.mu_static * (1.0 - self.kinetic_ratio) * self.decay * np.exp(-self.decay * v)


@dataclass(frozen=True)
class RationalFalling(FrictionLaw):
    """Rational falling friction mu(v) = mu_k + (mu_s - mu_k) / (1 + v / v_ref)."""

    mu_static: float
    mu_kinetic: float
    reference_velocity: float

    def __post_init__(self):
        object.__setattr__(self, "mu_static", positive("friction mu_static", self.mu_static))
        object.__setattr__(self, "mu_kinetic", positive("friction mu_kinetic", self.mu_kinetic))
        object.__setattr__(self, "reference_velocity",
                           positive("friction reference_velocity", self.reference_velocity))

    @property
    def is_constant(self) -> bool:
        return self.mu_static == self.mu_kinetic

    @property
    def static_coefficient(self) -> float:
        return self.mu_static

    @property
    def maximum_coefficient(self) -> float:
        return max(self.mu_static, self.mu_kinetic)

    def coefficient(self, slip_velocity):
        v = np.asarray(slip_velocity, dtype=float)
        return self.mu_kinetic + (self.mu_static - self.mu_kinetic) / (1.0 + v / self.reference_velocity)

    def describe(self) -> str:
        return (f"rational falling mu(v) = mu_k + (mu_s - mu_k) / (1 + v / v_ref), mu_s = {self.mu_static:g}, "
                f"mu_k = {self.mu_kinetic:g}, v_ref = {self.reference_velocity:g} m/s")

    def derivative(self, slip_velocity):
        v = np.asarray(slip_velocity, dtype=float)
        return -(self.mu_static - self.mu_kinetic) / self.reference_velocity / (1.0 + v / self.reference_velocity) ** 2


@dataclass(frozen=True)
class LinearFalling(FrictionLaw):
    """Linear falling friction mu(v) = max(mu_k, mu_s - slope v), slope [s/m] >= 0."""

    mu_static: float
    mu_kinetic: float
    slope: float

    def __post_init__(self):
        object.__setattr__(self, "mu_static", positive("friction mu_static", self.mu_static))
        object.__setattr__(self, "mu_kinetic", positive("friction mu_kinetic", self.mu_kinetic))
        object.__setattr__(self, "slope", positive("friction slope", self.slope, allow_zero=True))

    @property
    def is_constant(self) -> bool:
        return self.slope == 0.0 or self.mu_static == self.mu_kinetic

    @property
    def static_coefficient(self) -> float:
        return self.mu_static

    @property
    def maximum_coefficient(self) -> float:
        return max(self.mu_static, self.mu_kinetic)

    def coefficient(self, slip_velocity):
        v = np.asarray(slip_velocity, dtype=float)
        return np.maximum(self.mu_kinetic, self.mu_static - self.slope * v)

    def describe(self) -> str:
        return (f"linear falling mu(v) = max(mu_k, mu_s - c v), mu_s = {self.mu_static:g}, "
                f"mu_k = {self.mu_kinetic:g}, c = {self.slope:g} s/m")


@dataclass(frozen=True)
class TabulatedFriction(FrictionLaw):
    """User table mu(v): piecewise-linear through (velocities, coefficients), constant beyond the ends."""

    velocities: tuple[float, ...]
    coefficients: tuple[float, ...]

    def __post_init__(self):
        v = tuple(positive("friction table velocity", x, allow_zero=True) for x in self.velocities)
        m = tuple(positive("friction table coefficient", x) for x in self.coefficients)
        if len(v) != len(m) or len(v) < 1:
            raise ValueError(f"friction table needs equally many velocities and coefficients (>= 1), "
                             f"got {len(v)} and {len(m)}")
        if any(b <= a for a, b in zip(v, v[1:], strict=False)):
            raise ValueError(f"friction table velocities must increase strictly, got {v}")
        object.__setattr__(self, "velocities", v)
        object.__setattr__(self, "coefficients", m)

    @property
    def is_constant(self) -> bool:
        return len(set(self.coefficients)) == 1

    @property
    def maximum_coefficient(self) -> float:
        return max(self.coefficients)

    def coefficient(self, slip_velocity):
        return np.interp(np.asarray(slip_velocity, dtype=float), self.velocities, self.coefficients)

    def describe(self) -> str:
        return (f"tabulated mu(v) through {len(self.velocities)} points, mu = {self.coefficients[0]:g} at "
                f"v = {self.velocities[0]:g} m/s to {self.coefficients[-1]:g} at {self.velocities[-1]:g} m/s")


POLACH_2005 = ("O. Polach, Creep forces in simulations of traction vehicles running on adhesion limit, Wear 258 "
               "(2005) 992-1000, Table 2")
"""Source of the dry and wet rail conditions (:data:`RAIL_CONDITIONS`)."""


@dataclass(frozen=True)
class RailCondition:
    """A named rail condition: the published parameters of the exponential law
    ``mu(v) = mu_0 [(1 - A) exp(-B v) + A]`` (:class:`ExponentialFalling`) and their source.

    Polach fitted ``mu_0``, ``A`` and ``B`` together with two reduction factors of Kalker's initial creep slope
    (``kA`` in the adhesion area, ``kS`` in the slip area) to measured traction curves.  rollcontact computes the
    creep slope from the contact mechanics, so a condition carries the friction law only; the slope it gives is
    the dry, clean contact's (docs/physics.md, Velocity-dependent friction).
    """

    name: str
    mu_static: float
    kinetic_ratio: float
    decay: float
    source: str

    def law(self) -> ExponentialFalling:
        """The condition's friction law."""
        return ExponentialFalling(self.mu_static, self.kinetic_ratio, self.decay)


RAIL_CONDITIONS = {
    "dry": RailCondition("dry", 0.55, 0.40, 0.60, POLACH_2005),
    "wet": RailCondition("wet", 0.30, 0.40, 0.20, POLACH_2005),
}
"""Named rail conditions: mu_0 [1], A [1], B [s/m] of Polach's dry and wet parameter sets."""


def rail_condition(name: str) -> ExponentialFalling:
    """The friction law of a named rail condition of :data:`RAIL_CONDITIONS` (``"dry"``, ``"wet"``).

    Raises
    ------
    ValueError
        ``name`` is not a condition; the message lists them.
    """
    key = str(name).lower()
    if key not in RAIL_CONDITIONS:
        raise ValueError(f"unknown rail condition {name!r}; valid conditions are {sorted(RAIL_CONDITIONS)}")
    return RAIL_CONDITIONS[key].law()


LAWS = {
    "coulomb": Coulomb,
    "exponential": ExponentialFalling,
    "rational": RationalFalling,
    "linear": LinearFalling,
    "table": TabulatedFriction,
}


def friction_from_dict(data: dict) -> FrictionLaw:
    """Build a law from a TOML table: ``law = "<name>"`` plus the law's fields (e.g. ``mu = 0.3``), or
    ``rail_condition = "<name>"`` alone (:data:`RAIL_CONDITIONS`)."""
    data = dict(data)
    if "rail_condition" in data:
        condition = data.pop("rail_condition")
        if data:
            raise ValueError(f"friction: rail_condition = {condition!r} sets the whole law; remove "
                             f"{', '.join(sorted(data))} or the rail_condition")
        return rail_condition(condition)
    law = str(data.pop("law", "coulomb")).lower()
    if law not in LAWS:
        raise ValueError(f"unknown friction law {law!r}; valid laws are {sorted(LAWS)}")
    try:
        return LAWS[law](**data)
    except TypeError as exc:
        raise ValueError(f"friction law {law!r}: {exc}") from None


def friction_law(value) -> FrictionLaw:
    """The friction law a scene's ``friction`` stands for: a :class:`FrictionLaw` as it is, a number mu as
    ``Coulomb(mu)``; anything else :class:`~rollcontact.core.checks.SceneError` naming the value."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return Coulomb(value)
    if not isinstance(value, FrictionLaw):
        raise SceneError(f"friction must be a FrictionLaw or a number, got {value!r}")
    return value
