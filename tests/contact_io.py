"""Inputs, outputs and parameters of a contact FMU of n contacts through fmpy, in either form of its variables:
FMI 2.0's scalars ``name[k]`` or FMI 3.0's arrays (one variable ``name`` of n values, ``<Dimension start="n"/>``).
Values are always given and returned contact by contact, so both forms compare directly."""

from __future__ import annotations

from rollcontact_cosim.master import Slave


def named(name: str, k: int, contacts: int) -> str:
    """FMI 2.0's name of ``name`` for contact ``k`` (from 1): plain with one contact, ``name[k]`` with several."""
    return name if contacts == 1 else f"{name}[{k}]"


def size(slave: Slave, name: str) -> int | None:
    """The number of values of the array variable ``name`` (None: no such array)."""
    variable = slave.variables.get(name)
    return int(variable.dimensions[0].start) if variable is not None and variable.dimensions else None


def set_parameters(slave: Slave, values: dict) -> None:
    """Set parameters by name; in an FMU of arrays, ``name[k]`` sets element k of the array ``name`` (the elements not
    given keep their start values)."""
    elements: dict[str, dict[int, float]] = {}
    scalars = {}
    for name, value in values.items():
        base, _, index = name.partition("[")
        if index and size(slave, base) is not None:
            elements.setdefault(base, {})[int(index.rstrip("]"))] = value
        else:
            scalars[name] = value
    slave.set_start_values(scalars)
    for base, given in elements.items():
        start = [float(v) for v in slave.variables[base].start.split()]
        slave.fmu.setReal([slave.reference(base, "parameter")],
                          [float(given.get(k, start[k - 1])) for k in range(1, size(slave, base) + 1)])


def set_inputs(slave: Slave, names, rows) -> None:
    """Set the inputs ``names`` of every contact, ``rows[k]`` holding contact k's values in the order of ``names``."""
    contacts = len(rows)
    if contacts > 1 and size(slave, names[0]) == contacts:
        slave.fmu.setReal([slave.reference(n) for n in names], [float(row[i]) for i in range(len(names))
                                                                for row in rows])
    else:
        slave.fmu.setReal([slave.reference(named(n, k, contacts)) for k in range(1, contacts + 1) for n in names],
                          [float(v) for row in rows for v in row])


def get_outputs(slave: Slave, names, contacts: int) -> list[float]:
    """The outputs ``names`` of every contact, contact by contact (an Integer or Enumeration as a float)."""
    if contacts > 1 and size(slave, names[0]) == contacts:
        columns = []
        for name in names:
            vr, kind = slave.reference(name), slave.variables[name].type
            read = {"Float64": slave.fmu.getFloat64, "Enumeration": slave.fmu.getInt64}.get(kind, slave.fmu.getInt32)
            columns.append([float(v) for v in read([vr], contacts)])
        return [column[k] for k in range(contacts) for column in columns]
    values = []
    for k in range(1, contacts + 1):
        for name in names:
            v = slave.variables[named(name, k, contacts)]
            read = slave.fmu.getReal if v.type in ("Real", "Float64") else slave.fmu.getInteger
            values.append(float(read([v.valueReference])[0]))
    return values
