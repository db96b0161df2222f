"""What the stepping models of every geometry share in their parameters: the validated block
:class:`ModelParameters` (material, friction law, rail condition, method, tolerance, step budget), the codes of the
FMUs' integer variables that go with it (:data:`FRICTION_LAW_CODES`, :data:`RAIL_CONDITION_CODES` with the
conditions' parameters :data:`RAIL_CONDITION_SETS`, the :class:`Level` rows of each geometry's method levels) and the
friction law they make (:func:`friction_law`).

Each geometry's parameters (:class:`rollcontact.stepping.line.parameters.ContactParameters`,
:class:`rollcontact.stepping.elliptic.parameters.EllipticParameters`) extend :class:`ModelParameters` with their
own fields and their method levels, and check everything at once: one :class:`~rollcontact.stepping.base.ModelError`
names every invalid value and its limit.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np

from rollcontact.core.checks import SceneError, check_real
from rollcontact.core.friction import (
    RAIL_CONDITIONS,
    Coulomb,
    ExponentialFalling,
    FrictionLaw,
    LinearFalling,
    RationalFalling,
    TabulatedFriction,
)
from rollcontact.stepping.base import ModelError

AUTO = 0
"""``method`` code of the automatic choice (every geometry)."""


class Level(NamedTuple):
    """One row of a geometry's method levels: a code of the FMU's ``method_used`` (and of ``method`` where it is a
    choice).

    Attributes
    ----------
    code : int
        The code (> 0; 0 is auto, resp. no contact).  Never reused or changed: hosts and recorded runs hold it.
    name : str
        The item's name in the FMU's enumerations; for a choice also the family: a registered method belongs to the
        level when its registry name starts with it (e.g. ``"polynomial_friction"`` is a polynomial method).
    choice : str
        Description of the ``method`` item ("": not a value of ``method``, only reported by ``method_used``).
    used : str
        Description of the ``method_used`` item.
    auto : bool
        Whether ``method`` = auto tries the family's registered methods (in table order, by rank within a family)
        where the geometry's stepping model says so.
    """

    code: int
    name: str
    choice: str
    used: str
    auto: bool = False


def level_code(levels: tuple[Level, ...], name: str) -> int:
    """``method_used`` code of a registry name among ``levels``: the choice level whose name starts it (0 for
    none)."""
    return next((level.code for level in levels if level.choice and name.startswith(level.name)), 0)


class FrictionLawCode(NamedTuple):
    """One row of :data:`FRICTION_LAW_CODES`: a ``friction_law`` code, its FMU item, and what it is."""

    code: int
    item: str
    """The item's name in the FMUs' FrictionLaw enumeration."""
    title: str
    """Its name in messages."""
    formula: str
    """mu(v) [1] of the slip velocity v [m/s], with the parameters' letters (the item's description)."""


FRICTION_LAW_CODES = (
    FrictionLawCode(0, "coulomb", "Coulomb", "constant mu"),
    FrictionLawCode(1, "exponential_falling", "exponential falling", "mu [(1 - A) exp(-B v) + A]"),
    FrictionLawCode(2, "rational_falling", "rational falling", "A mu + (1 - A) mu / (1 + v / v_ref)"),
    FrictionLawCode(3, "linear_falling", "linear falling", "max(A mu, mu - c v)"),
    FrictionLawCode(4, "tabulated", "tabulated", "piecewise linear through friction_table"),
)
"""The ``friction_law`` codes: every law of :mod:`rollcontact.core.friction` (:func:`friction_law` builds it), one
table for every geometry and its FMU enumeration."""

FRICTION_LAWS = {row.code: row.title for row in FRICTION_LAW_CODES}
"""``friction_law`` code -> the law's name."""

TABLE_LAW = 4
"""``friction_law`` of the tabulated law, whose points ``friction_table`` gives (:func:`friction_table_points`)."""

RAIL_CONDITION_CODES = {0: "custom", **{k: name for k, name in enumerate(RAIL_CONDITIONS, start=1)}}
"""``rail_condition`` codes: 0 custom (the ``friction_*`` parameters), else a named condition of
:data:`rollcontact.core.friction.RAIL_CONDITIONS` whose law replaces them."""

RAIL_CONDITION_SETS = {code: RAIL_CONDITIONS[name] for code, name in RAIL_CONDITION_CODES.items() if code}
"""``rail_condition`` code (all but 0, custom) -> its named condition, a
:class:`rollcontact.core.friction.RailCondition`: the parameters of its law (``mu_static``, ``kinetic_ratio``,
``decay``) and their ``source`` (what :func:`friction_law` steps with, and what the FMUs' RailCondition items say)."""


new_tuple = tuple.__new__
"""``new_tuple(Outputs, values)`` builds outputs without ``NamedTuple.__new__``'s extra Python frame (the
closed-form steps' hot path)."""


DEFAULT_STEP_BUDGET = 0.05
"""Default ``step_budget`` [s]: a few tens of milliseconds, what a host stepping a few contacts at 1 kHz in a
soft real-time loop can give one contact; ``benchmarks/calibrate_step_budget.py`` measures the steps it bounds."""


@dataclass(frozen=True)
class ModelParameters:
    """The parameters every geometry's stepping model has (the FMU parameters of the same names), checked on
    creation together with the geometry's own (:meth:`problems`).

    Parameters
    ----------
    youngs_modulus : float
        E [Pa] > 0 of both bodies (quasi-identical bodies).
    poisson_ratio : float
        nu [1], 0 <= nu < 0.5.
    friction_coefficient : float
        mu at zero slip velocity [1] > 0.
    friction_law : int
        A code of :data:`FRICTION_LAWS`: 0 Coulomb (mu constant), 1 exponential falling
        ``mu(v) = mu [(1 - A) exp(-B v) + A]``, 2 rational falling ``mu(v) = A mu + (1 - A) mu / (1 + v / v_ref)``,
        3 linear falling ``mu(v) = max(A mu, mu - c v)`` (:mod:`rollcontact.core.friction`; v the slip velocity [m/s],
        mu = ``friction_coefficient``), 4 tabulated: piecewise linear through the points of ``friction_table``
        (``friction_coefficient`` is then unused).
    friction_kinetic_ratio : float
        A [1] in (0, 1]: mu(infinity)/mu of the falling laws (the kinetic coefficient A mu of the rational and
        linear laws).
    friction_decay : float
        B [s/m] >= 0 of the exponential law.
    friction_reference_velocity : float
        v_ref [m/s] > 0 of the rational law.
    friction_slope : float
        c [s/m] >= 0 of the linear law.
    friction_table : str
        Points ``"v mu; v mu; ..."`` (v [m/s] increasing from >= 0, mu [1] > 0) of the tabulated law, e.g.
        ``"0 0.3; 1 0.25; 5 0.12"``; mu is constant beyond the ends.  Read only with ``friction_law`` = 4.
    rail_condition : int
        A code of :data:`RAIL_CONDITION_CODES`: 0 custom (the ``friction_*`` parameters above), 1 dry, 2 wet rail
        (:data:`rollcontact.core.friction.RAIL_CONDITIONS`, Polach's parameter sets of the exponential law), whose
        law replaces ``friction_law``, ``friction_coefficient``, ``friction_kinetic_ratio`` and ``friction_decay``.
    method : int
        0 auto, else the code of a choice of the geometry's method levels (:attr:`LEVELS`).
    tolerance : float
        Requested error [1] >= 0 in the geometry's measure (0: each method's defaults).
    step_budget : float
        Work budget [s] >= 0 of a contact's solve in one step, by the methods' cost models (modelled seconds, no
        clock: the same bound on every machine); 0: no budget, as long as each step takes.
    """

    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.28
    friction_coefficient: float = 0.3
    friction_law: int = 0
    friction_kinetic_ratio: float = 0.4
    friction_decay: float = 0.6
    friction_reference_velocity: float = 2.0
    friction_slope: float = 0.1
    friction_table: str = ""
    rail_condition: int = 0
    method: int = AUTO
    tolerance: float = 0.0
    step_budget: float = DEFAULT_STEP_BUDGET

    LEVELS: ClassVar[tuple[Level, ...]] = ()
    """The geometry's method levels (its ``method`` choices are the rows with a ``choice``)."""

    REALS: ClassVar[tuple] = (
        ("youngs_modulus", 0.0, None, True, False),
        ("poisson_ratio", 0.0, 0.5, False, True),
        ("friction_coefficient", 0.0, None, True, False),
        ("friction_kinetic_ratio", 0.0, 1.0, True, False),
        ("friction_decay", 0.0, None, False, False),
        ("friction_reference_velocity", 0.0, None, True, False),
        ("friction_slope", 0.0, None, False, False),
        ("tolerance", 0.0, None, False, False),
        ("step_budget", 0.0, None, False, False),
    )
    """The real parameters and their limits ``(name, lower, upper, lower_open, upper_open)``; a geometry appends
    its own."""

    def codes(self) -> dict[str, dict]:
        """The integer parameters that take a code and their codes (name -> {code: meaning}); a geometry adds its
        own."""
        return {"friction_law": FRICTION_LAWS, "rail_condition": RAIL_CONDITION_CODES,
                "method": {AUTO: "auto", **{level.code: level.name for level in self.LEVELS if level.choice}}}

    def __post_init__(self):
        """Raise one :class:`~rollcontact.stepping.base.ModelError` naming each invalid value and its limit
        (``"; "``-separated, in the order of :attr:`REALS`, the codes, then the geometry's own checks), so that a
        user corrects them all at once."""
        problems = self.problems()
        if problems:
            raise ModelError("; ".join(problems))

    def problems(self) -> list[str]:
        """Check (and normalise: reals to float, codes to int) every parameter; the problems found."""
        set_ = object.__setattr__
        problems = []
        for name, lower, upper, lower_open, upper_open in self.REALS:
            try:
                set_(self, name, check_real(name, getattr(self, name), lower=lower, upper=upper,
                                            lower_open=lower_open, upper_open=upper_open))
            except SceneError as exc:
                problems.append(str(exc))
        for name, allowed in self.codes().items():
            value = getattr(self, name)
            if isinstance(value, bool) or value not in allowed:
                choices = ", ".join(f"{k} {v}" for k, v in allowed.items())
                problems.append(f"{name} = {value!r} is out of range: it must be one of {choices}")
            else:
                set_(self, name, int(value))
        return problems + friction_table_problems(self.friction_table, self.friction_law)


def whole_number_problems(parameters, names) -> list[str]:
    """Problems of the integer parameters ``names`` of ``parameters`` that must be whole numbers >= 0 (0: the
    method's default), each normalised to int."""
    problems = []
    for name in names:
        value = getattr(parameters, name)
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
            problems.append(f"{name} = {value!r} is out of range: it must be an integer >= 0 (0: the method's default)")
        else:
            object.__setattr__(parameters, name, int(value))
    return problems


def friction_table_problems(table, law: int) -> list[str]:
    """What is wrong with the ``friction_table`` parameter (a string, and with ``friction_law`` = tabulated a
    table :func:`friction_table_points` reads); [] when nothing is."""
    if not isinstance(table, str):
        return [f"friction_table must be a string ('v mu; v mu; ...'), got {table!r}"]
    if law == TABLE_LAW:
        try:
            friction_table_points(table)
        except ValueError as exc:
            return [str(exc)]
    return []


def friction_table_points(text: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Velocities [m/s] and coefficients [1] of a ``friction_table`` ``"v mu; v mu; ..."``, checked as
    :class:`rollcontact.core.friction.TabulatedFriction` checks them.

    Raises
    ------
    ValueError
        The text is no such table; the message shows the form and the first problem.
    """
    form = "write 'v mu' pairs (v [m/s] increasing, mu [1] > 0) separated by ';', e.g. '0 0.3; 1 0.25; 5 0.12'"
    rows = [row.split() for row in text.split(";") if row.strip()]
    if not rows or any(len(row) != 2 for row in rows):
        raise ValueError(f"friction_table = {text[:80]!r} is not a friction table: {form}")
    try:
        law = TabulatedFriction(tuple(float(v) for v, _ in rows), tuple(float(mu) for _, mu in rows))
    except ValueError as exc:
        raise ValueError(f"friction_table = {text[:80]!r}: {exc}; {form}") from None
    return law.velocities, law.coefficients


def friction_law(p: ModelParameters) -> FrictionLaw:
    """The friction law of the parameters ``friction_law`` (a code of :data:`FRICTION_LAWS`),
    ``friction_coefficient``, ``friction_kinetic_ratio``, ``friction_decay``, ``friction_reference_velocity``,
    ``friction_slope`` and ``friction_table``, or the law of its ``rail_condition`` when that is not 0 (custom).

    Raises
    ------
    ValueError
        The values make no valid law (the law's message).
    """
    if p.rail_condition:
        return RAIL_CONDITION_SETS[p.rail_condition].law()
    mu, ratio = p.friction_coefficient, p.friction_kinetic_ratio
    laws = {0: lambda: Coulomb(mu), 1: lambda: ExponentialFalling(mu, ratio, p.friction_decay),
            2: lambda: RationalFalling(mu, ratio * mu, p.friction_reference_velocity),
            3: lambda: LinearFalling(mu, ratio * mu, p.friction_slope),
            4: lambda: TabulatedFriction(*friction_table_points(p.friction_table))}
    return laws[p.friction_law]()
