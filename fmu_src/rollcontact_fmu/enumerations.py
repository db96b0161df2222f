"""The contact FMUs' enumerations, derived from the solver's tables (written nowhere else), and the integer-codes
variant of a variable table.

An enumeration of a slave is ``variable name -> (type name, items)``, each item ``(value, name, description)``:

* FrictionLaw from :data:`rollcontact.stepping.parameters.FRICTION_LAW_CODES` (:func:`friction_law_items`);
* RailCondition from :data:`rollcontact.stepping.parameters.RAIL_CONDITION_CODES` and the conditions' parameters,
  :data:`rollcontact.stepping.parameters.RAIL_CONDITION_SETS` (:func:`rail_condition_items`);
* a geometry's method choice and the method used from its ``METHOD_LEVELS`` (:func:`method_items`,
  :func:`method_used_items`): one :class:`rollcontact.stepping.parameters.Level` line adds an item to both.

These functions read the tables when called, so a slave's declaration follows the tables in force.
"""

from __future__ import annotations

import re

import rollcontact.stepping.parameters as shared

RAIL_CONDITION_TEXT = "Rail condition replacing the friction_* parameters unless custom (RailCondition)"
"""Description of the contact FMUs' ``rail_condition`` parameter."""


def friction_law_items() -> tuple:
    """The FrictionLaw items: each ``friction_law`` code, its item name and its law mu(v)."""
    return tuple((row.code, row.item, row.formula) for row in shared.FRICTION_LAW_CODES)


def cited(source: str) -> str:
    """The short citation ``"Surname year"`` of a reference ``"I. Surname, title, ... (year) ..."``."""
    year = re.search(r"\((\d{4})\)", source)
    return f"{source.split(',')[0].split()[-1]} {year.group(1) if year else ''}".strip()


def rail_condition_items() -> tuple:
    """The RailCondition items: 0 custom, then each named condition with its law's parameters and its source."""
    return ((0, shared.RAIL_CONDITION_CODES[0], "the friction_* parameters"),
            *((code, c.name, f"{c.name} rail, {cited(c.source)}: exponential law with mu {c.mu_static:g}, "
                             f"A {c.kinetic_ratio:g}, B {c.decay:g} s/m")
              for code, c in shared.RAIL_CONDITION_SETS.items()))


def method_items(levels, auto: str) -> tuple:
    """The items of a geometry's ``method`` (its choice): 0 ``auto`` (described by ``auto``), then every level of
    ``levels`` that is a choice, described by :attr:`~rollcontact.stepping.parameters.Level.choice`."""
    return ((shared.AUTO, "auto", auto), *((level.code, level.name, level.choice) for level in levels if level.choice))


def method_used_items(levels) -> tuple:
    """The items of a geometry's ``method_used``: 0 ``none`` (no contact), then every level of ``levels``, described
    by :attr:`~rollcontact.stepping.parameters.Level.used`."""
    return ((0, "none", "no contact"), *((level.code, level.name, level.used) for level in levels))


def largest(items) -> int:
    """The largest value among enumeration ``items`` (the variable's declared max)."""
    return max(value for value, *_ in items)


def integer_coded(variables, enumerations: dict) -> tuple:
    """The variable table with each enumeration's variable as a plain Integer whose description lists its codes
    (``build_fmu.py --integer-codes``, for hosts without FMI enumerations such as libcosim)."""
    return tuple((*row[:8], f"{row[8].split(' (')[0]}: " + ", ".join(f"{v} {item}"
                                                                       for v, item, _ in enumerations[row[0]][1]))
                 if row[0] in enumerations else row for row in variables)
