"""What the project's pythonfmu slaves share (bundled in each FMU's resources): modelDescription completion and
printf-safe log messages.

pythonfmu 0.7 writes no units, bounds, UnitDefinitions or InitialUnknowns (``fmpy validate`` then fails).  A
slave that declares its variables in one table of rows ``(name, type, causality, variability, unit, start, min,
max, description)`` (value references = row order) calls :func:`complete_model_description` from its
``to_xml`` to add them.
"""

from __future__ import annotations

from xml.etree.ElementTree import Element, SubElement

from pythonfmu import Real
from pythonfmu.enums import Fmi2Causality

UNITS = {  # SI base-unit exponents of every unit the project's FMUs use
    "1": {}, "m": {"m": 1}, "m/s": {"m": 1, "s": -1}, "s/m": {"m": -1, "s": 1}, "rad": {"rad": 1},
    "N": {"kg": 1, "m": 1, "s": -2}, "Pa": {"kg": 1, "m": -1, "s": -2}, "W": {"kg": 1, "m": 2, "s": -3},
    "s": {"s": 1}, "Hz": {"s": -1}, "kg": {"kg": 1}, "kg.m2": {"kg": 1, "m": 2}, "rad/s": {"rad": 1, "s": -1},
    "N.m": {"kg": 1, "m": 2, "s": -2}, "N.s/m": {"kg": 1, "s": -1}, "N.s2/m2": {"kg": 1, "m": -1},
}


def printf_safe(message: str) -> str:
    """The message as a literal printf format (pythonfmu's C side formats log messages)."""
    return message.replace("%", "%%")


def complete_model_description(root: Element, variables, initial_dependencies: str | None = "") -> Element:
    """Add units, min/max, UnitDefinitions and a complete ModelStructure to pythonfmu's ``root`` (returned).

    Parameters
    ----------
    root : Element
        ``Fmi2Slave.to_xml()`` of the slave.
    variables : sequence of tuple
        The slave's variable table (rows as in the module docstring, in registration order).
    initial_dependencies : str or None
        ``dependencies`` of every output in InitialUnknowns: ``""`` when the initial outputs are the start values
        (they depend on no known), None to omit the attribute (they depend on the parameters).

    Outputs are computed in ``do_step`` only, so in ``Outputs`` they depend on no input (``dependencies=""``).
    """
    rows = {row[0]: row for row in variables}
    used = []
    for variable in root.iter("ScalarVariable"):
        _, kind, _, _, unit, _, lower, upper, _ = rows[variable.get("name")]
        element = variable[0]
        if unit is not None:
            element.set("unit", unit)
            if unit not in used:
                used.append(unit)
        for attribute, bound in (("min", lower), ("max", upper)):
            if bound is not None:
                element.set(attribute, f"{bound:.16g}" if kind is Real else str(bound))
    units = Element("UnitDefinitions")
    for name in sorted(used, key=list(UNITS).index):
        unit = SubElement(units, "Unit", name=name)
        if UNITS[name]:
            SubElement(unit, "BaseUnit", {k: str(v) for k, v in UNITS[name].items()})
    root.insert(list(root).index(root.find("CoSimulation")) + 1, units)
    root.remove(root.find("ModelStructure"))
    structure = SubElement(root, "ModelStructure")
    outputs = SubElement(structure, "Outputs")
    initial_unknowns = SubElement(structure, "InitialUnknowns")
    for index, row in enumerate(variables, start=1):
        if row[2] is Fmi2Causality.output:
            SubElement(outputs, "Unknown", index=str(index), dependencies="")
            unknown = SubElement(initial_unknowns, "Unknown", index=str(index))
            if initial_dependencies is not None:
                unknown.set("dependencies", initial_dependencies)
    return root
