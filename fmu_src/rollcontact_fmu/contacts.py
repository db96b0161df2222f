"""Several contacts in one slave, and the variant classes of a contact FMU.

A contact FMU of n contacts declares each per-contact variable once per contact, ``name[1]`` ... ``name[n]`` (FMI
2.0's array convention, :func:`named`), or, in FMI 3.0, as one array variable ``name`` of n values (the slave's
``DIMENSIONS``); the shared parameters stay scalars.  A slave module gives its declaration for every variant
(contacts, integer codes, arrays) and builds the variant's class with :func:`variant_class`; its step gathers the
inputs and spreads the outputs with :func:`contacts_step`, its parameters with :func:`contact_values`.
"""

from __future__ import annotations

from itertools import chain
from operator import attrgetter

from pythonfmu.enums import Fmi2Causality


def named(name: str, k: int, contacts: int) -> str:
    """The variable name of ``name`` for contact ``k`` (from 1): plain with one contact, ``name[k]`` with several."""
    return name if contacts == 1 else f"{name}[{k}]"


def variant_name(model: str, contacts: int) -> str:
    """The model name of the contact FMU ``model`` with ``contacts`` contacts: ``model``, else ``model_n``."""
    return model if contacts == 1 else f"{model}_{contacts}"


def contact_text(description: str, k: int | None) -> str:
    """``description`` with ``, contact k`` (``k`` None: ``, one per contact``) before its parenthesised part, if
    any."""
    head, sep, tail = description.partition(" (")
    return f"{head}, {'one per contact' if k is None else f'contact {k}'}{sep}{tail}"


def contact_values(values: dict, name: str, contacts: int, dimensions: dict) -> tuple:
    """The per-contact values of parameter ``name`` among ``values`` (name -> value): the FMI 3.0 array ``name``
    (in ``dimensions``), the scalar ``name`` of a single contact, else ``name[1]`` ... ``name[contacts]``."""
    if name in dimensions:
        return tuple(values[name])
    return (values[name],) if contacts == 1 else tuple(values[f"{name}[{k}]"] for k in range(1, contacts + 1))


def contacts_step(step, current_time: float, step_size: float, values, width: int, arrays: bool,
                  appended: int = 0) -> tuple:
    """The outputs of a several-contact slave in its table's order (a tuple: the slave's outputs as they are) from
    ``step(current_time, step_size, rows)`` (one output tuple per contact) and its input values: one array per input
    (``arrays``, FMI 3.0: rows are their columns, outputs go output by output) or ``width`` inputs per contact in turn
    (FMI 2.0: contact by contact), followed by ``appended`` inputs per contact in turn (inputs declared after the
    others: each contact's row ends with its own)."""
    if arrays:
        return tuple(chain.from_iterable(zip(*step(current_time, step_size, list(zip(*values, strict=True))),
                                             strict=True)))
    if appended:
        n = len(values) // (width + appended)
        split = n * width
        return tuple(chain.from_iterable(step(current_time, step_size, [
            values[i * width:(i + 1) * width] + values[split + i * appended:split + (i + 1) * appended]
            for i in range(n)])))
    return tuple(chain.from_iterable(step(current_time, step_size,
                                          [values[i:i + width] for i in range(0, len(values), width)])))


def variant_class(base: type, model: str, contacts: int, declaration: tuple, dimensions: dict) -> type:
    """The shared slave class (no FMI binding) of a contact FMU's variant: ``base`` with the variant's table.

    Parameters
    ----------
    base : type
        The slave logic (a :class:`~rollcontact_fmu.slave.TableSlave`).
    model : str
        The variant's model name (:func:`variant_name`): pythonfmu names the model, its files and binaries after the
        class.
    contacts : int
        Its number of contacts (``CONTACTS``).
    declaration : tuple
        Its variable table and enumerations (``VARIABLES``, ``ENUMERATIONS``).
    dimensions : dict
        Its array variables (``DIMENSIONS``; none in FMI 2.0).

    The class also gets ``INPUT_NAMES``, the input variables in table order, and ``read_inputs(slave)``, their values
    in one C call.  A slave module keeps one class per variant and process (a host may load several variants).
    """
    variables, enumerations = declaration
    names = tuple(row[0] for row in variables if row[2] is Fmi2Causality.input)
    return type(model, (base,), {
        "__doc__": f"{model}: {base.__name__} with {contacts} contact{'s' if contacts > 1 else ''}.",
        "__module__": base.__module__, "VARIABLES": variables, "ENUMERATIONS": enumerations, "CONTACTS": contacts,
        "INPUT_NAMES": names, "read_inputs": attrgetter(*names), "DIMENSIONS": dimensions})
