"""The modelDescription completion: what pythonfmu 0.7 and pythonfmu3 0.3.4 leave out of a slave's description.

pythonfmu 0.7 writes no units, bounds, UnitDefinitions, enumerations or InitialUnknowns (``fmpy validate`` then
fails); pythonfmu3 writes no bounds and starts with 16 digits only.  A slave declares its variables in one table of
rows ``(name, type, causality, variability, unit, start, min, max, description)`` (value reference = row number,
:mod:`rollcontact_fmu.slave`); its binding completes the description from that table:
:func:`complete_model_description` for FMI 2.0 (``rollcontact_fmu.fmi2``), :func:`complete_model_description3` for
FMI 3.0 (``rollcontact_fmu.fmi3``, which registers the units and enumeration types through pythonfmu3 first).

Outputs are computed in ``do_step`` only, so as outputs they depend on no variable (``dependencies=""``).
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
    "1/m": {"m": -1}, "N/m": {"kg": 1, "s": -2}, "N.m2": {"kg": 1, "m": 3, "s": -2},
    "N.m/rad": {"kg": 1, "m": 2, "s": -2, "rad": -1}, "N.m.s/rad": {"kg": 1, "m": 2, "s": -1, "rad": -1},
    "N/rad": {"kg": 1, "m": 1, "s": -2, "rad": -1}, "N.s/rad": {"kg": 1, "m": 1, "s": -1, "rad": -1},
    "N.m/m": {"kg": 1, "m": 1, "s": -2}, "N.s": {"kg": 1, "m": 1, "s": -1},
}


def exact(kind):
    """How a value of the table's type ``kind`` is written: a Real's ``repr`` (an exact round trip), else ``str``."""
    return (lambda value: repr(float(value))) if kind is Real else str


def complete_model_description(root: Element, variables, initial_dependencies: str | None = "",
                               enumerations: dict | None = None) -> Element:
    """Add units, min/max, UnitDefinitions, TypeDefinitions of the enumerations and a complete ModelStructure to
    pythonfmu's FMI 2.0 ``root`` (returned).

    Parameters
    ----------
    root : Element
        ``Fmi2Slave.to_xml()`` of the slave.
    variables : sequence of tuple
        The slave's variable table (rows as in the module docstring, in registration order).
    initial_dependencies : str or None
        ``dependencies`` of every output in InitialUnknowns: ``""`` when the initial outputs are the start values
        (they depend on no known), None to omit the attribute (they depend on the parameters).
    enumerations : dict, optional
        Variable name -> ``(type name, ((value, item name, description), ...))``: the Integer variable becomes an
        Enumeration of that declared type (pythonfmu 0.7 has no Enumeration variable; an FMI 2 host sets and gets
        it with fmi2SetInteger/fmi2GetInteger as the slave's Integer).
    """
    rows = {row[0]: row for row in variables}
    enumerations = enumerations or {}
    used = []
    for variable in root.iter("ScalarVariable"):
        name = variable.get("name")
        _, kind, _, _, unit, _, lower, upper, _ = rows[name]
        element = variable[0]
        if name in enumerations:
            element.tag = "Enumeration"
            element.set("declaredType", enumerations[name][0])
        if unit is not None:
            element.set("unit", unit)
            if unit not in used:
                used.append(unit)
        for attribute, bound in (("min", lower), ("max", upper)):
            if bound is not None:
                element.set(attribute, exact(kind)(bound))
    units = Element("UnitDefinitions")
    for name in sorted(used, key=list(UNITS).index):
        unit = SubElement(units, "Unit", name=name)
        if UNITS[name]:
            SubElement(unit, "BaseUnit", {k: str(v) for k, v in UNITS[name].items()})
    root.insert(list(root).index(root.find("CoSimulation")) + 1, units)
    if enumerations:
        types = Element("TypeDefinitions")
        for type_name, items in dict(enumerations.values()).items():
            enumeration = SubElement(SubElement(types, "SimpleType", name=type_name), "Enumeration")
            for value, item, description in items:
                SubElement(enumeration, "Item", name=item, value=str(value), description=description)
        root.insert(list(root).index(units) + 1, types)
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


def complete_model_description3(root: Element, variables, initial_dependencies: str | None = "",
                                dimensions: dict | None = None) -> Element:
    """Add min/max, exact starts, the arrays' dimensions and the dependencies of the ModelStructure to pythonfmu3's
    ``root`` (returned).

    Parameters
    ----------
    root : Element
        ``Fmi3SlaveBase.to_xml()`` of the slave (units and type definitions registered through pythonfmu3).
    variables : sequence of tuple
        The slave's variable table (value reference = row number).
    initial_dependencies : str or None
        ``dependencies`` of every output among the InitialUnknowns: ``""`` when the initial outputs are the start
        values, None to omit the attribute (they depend on the parameters).
    dimensions : dict, optional
        Array variables -> their number of values: each gets ``<Dimension start="n"/>`` and its start value n
        times (the slave's :attr:`~rollcontact_fmu.slave.TableSlave.DIMENSIONS`).
    """
    rows = {row[0]: row for row in variables}
    dimensions = dimensions or {}
    for element in root.find("ModelVariables"):
        row = rows.get(element.get("name"))
        if row is None:  # time
            continue
        kind, start, lower, upper = row[1], row[5], row[6], row[7]
        write = exact(kind)
        for attribute, value in (("min", lower), ("max", upper)):
            if value is not None:
                element.set(attribute, write(value))
        size = dimensions.get(row[0])
        if element.get("start") is not None and (kind is Real or size is not None):
            element.set("start", " ".join([write(start)] * (size or 1)))
        if size is not None:
            element.append(Element("Dimension", start=str(size)))
    for entry in root.find("ModelStructure"):
        if entry.tag == "Output":
            entry.set("dependencies", "")
        elif entry.tag == "InitialUnknown" and initial_dependencies is not None:
            entry.set("dependencies", initial_dependencies)
    return root
