"""What the project's pythonfmu slaves share (bundled in each FMU's resources): the :class:`TableSlave` base
(variables from one table, do_step, state), modelDescription completion and printf-safe log messages.

pythonfmu 0.7 writes no units, bounds, UnitDefinitions or InitialUnknowns (``fmpy validate`` then fails).  A
slave declares its variables in one table of rows ``(name, type, causality, variability, unit, start, min, max,
description)`` (value references = row order); its FMI 2.0 binding (``fmi2_table_slave.TableSlave2``) calls
:func:`complete_model_description` from ``to_xml`` to add them.

What pythonfmu 0.7's C++ layer (``PySlaveInstance.cpp``, ``fmi2.cpp``) does with the slave, and how
:class:`TableSlave` copes (``docs/fmu.md``, "Known limits of pythonfmu"):

* Any exception escaping a slave method becomes fmi2Fatal, and ``handle_py_exception`` then releases the instance's
  Python objects without forgetting them: every later call on the instance, ``fmi2FreeInstance`` included, is a
  use after free (SIGSEGV).  So nothing may raise into pythonfmu: not the setters, getters, state methods or
  ``do_step``.
* Apart from that, only ``do_step`` has a status (False: fmi2Discard); every other call returns fmi2OK.  A call
  FMI 2 answers with fmi2Error (a fixed parameter set after initialisation, an invalid FMU state, invalid
  parameters at exitInitializationMode, an unknown value reference) is therefore logged with status Error and
  puts the instance into an *emulated error state*: it keeps its previous values, and every ``do_step`` is
  discarded with the reason until a valid state is set (``fmi2SetFMUstate``) or the instance is reset.
* pythonfmu 0.7 hands a message to the host's logger only while debug logging is on for its category
  (``Logger.hpp``): without it a refusal would be silent.  A message of status Discard or Error that the host's
  logger does not receive is written to the process's standard error instead (Python's ``sys.stderr``: fd 2 in a C
  host, what the user sees in a Python host), once per distinct reason and instance (:meth:`TableSlave.echo`).
  Whether the host receives it is read from pythonfmu's logger object (:func:`logger_categories`).
* The FMU state object is the Python dict of ``_get_fmu_state``; ``_fmu_state_to_bytes`` and
  ``_fmu_state_from_bytes`` (static, called on the class) serialise it as UTF-8 JSON with a SHA-256 checksum
  (:func:`serialise_state`).  Bytes that are no such state (not UTF-8, not JSON, no or a wrong checksum) become a
  marker dict that ``_set_fmu_state`` refuses, and a state is checked completely before anything is changed.
"""

from __future__ import annotations

import ctypes
import hashlib
import json
import math
import sys
from collections.abc import Callable
from itertools import chain
from operator import itemgetter
from xml.etree.ElementTree import Element, SubElement

from pythonfmu import Real
from pythonfmu.enums import Fmi2Causality, Fmi2Initial, Fmi2Status, Fmi2Variability
from pythonfmu.variables import Integer, String

from rollcontact.core.friction import RAIL_CONDITIONS
from rollcontact.stepping.parameters import RAIL_CONDITION_CODES

UNITS = {  # SI base-unit exponents of every unit the project's FMUs use
    "1": {}, "m": {"m": 1}, "m/s": {"m": 1, "s": -1}, "s/m": {"m": -1, "s": 1}, "rad": {"rad": 1},
    "N": {"kg": 1, "m": 1, "s": -2}, "Pa": {"kg": 1, "m": -1, "s": -2}, "W": {"kg": 1, "m": 2, "s": -3},
    "s": {"s": 1}, "Hz": {"s": -1}, "kg": {"kg": 1}, "kg.m2": {"kg": 1, "m": 2}, "rad/s": {"rad": 1, "s": -1},
    "N.m": {"kg": 1, "m": 2, "s": -2}, "N.s/m": {"kg": 1, "s": -1}, "N.s2/m2": {"kg": 1, "m": -1},
    "1/m": {"m": -1}, "N/m": {"kg": 1, "s": -2}, "N.m2": {"kg": 1, "m": 3, "s": -2},
    "N.m/rad": {"kg": 1, "m": 2, "s": -2, "rad": -1}, "N.m.s/rad": {"kg": 1, "m": 2, "s": -1, "rad": -1},
}


STATE_FORMAT = "rollcontact TableSlave FMU state"
"""``format`` of every FMU state of a :class:`TableSlave`."""

STATE_VERSION = 1
"""Layout version of the FMU state (``version``); states of another version are refused."""

UNDECODABLE = "undecodable FMU state"
"""Key of the marker dict ``_fmu_state_from_bytes`` returns for bytes that are no serialised state."""

CHECKSUM = "sha256"
"""Key of the serialised state's checksum: SHA-256 of :func:`canonical_json` of the state without it."""

NOT_INITIALISED = "the FMU is not initialised: exit initialisation mode before stepping"

REFUSAL_CATEGORIES = {Fmi2Status.discard: "logStatusDiscard", Fmi2Status.error: "logStatusError"}
"""Status of a refusal -> the log category pythonfmu gives it; such a message the host's logger does not receive is
written to standard error (:meth:`TableSlave.echo`)."""

ECHO_LIMIT = 20
"""Distinct refusal reasons one instance writes to standard error at most (then one line says the rest is not)."""

TOLD_LIMIT = 256
"""Refusal reasons one instance remembers as told (a host stepping on after refusals does not grow memory)."""

INT32 = (-(2**31), 2**31 - 1)

PLAN_LIMIT = 64
"""Lists of input value references one instance remembers as checked (a host sets the same few every step)."""


FRICTION_LAW_ITEMS = ((0, "coulomb", "constant mu"),
                      (1, "exponential_falling", "mu [(1 - A) exp(-B v) + A]"),
                      (2, "rational_falling", "A mu + (1 - A) mu / (1 + v / v_ref)"),
                      (3, "linear_falling", "max(A mu, mu - c v)"),
                      (4, "tabulated", "piecewise linear through friction_table"))
"""Items of the contact FMUs' FrictionLaw enumeration: the codes of ``rollcontact.stepping.parameters.FRICTION_LAWS``
(one law of the same codes in the 2D and the elliptic contact)."""


RAIL_CONDITION_ITEMS = ((0, "custom", "the friction_* parameters"),
                        *((code, name, f"{name} rail, Polach 2005: exponential law with mu {c.mu_static:g}, "
                                       f"A {c.kinetic_ratio:g}, B {c.decay:g} s/m")
                          for code, name in RAIL_CONDITION_CODES.items() if code
                          for c in (RAIL_CONDITIONS[name],)))
"""Items of the contact FMUs' RailCondition enumeration: ``rollcontact.stepping.parameters.RAIL_CONDITION_CODES``
with the values of ``rollcontact.core.friction.RAIL_CONDITIONS``."""

RAIL_CONDITION_TEXT = "Rail condition replacing the friction_* parameters unless custom (RailCondition)"
"""Description of the contact FMUs' ``rail_condition`` parameter."""


def integer_coded(variables, enumerations: dict) -> tuple:
    """The variable table with each enumeration's variable as a plain Integer whose description lists its codes
    (``build_fmu.py --integer-codes``, for hosts without FMI enumerations such as libcosim)."""
    return tuple((*row[:8], f"{row[8].split(' (')[0]}: " + ", ".join(f"{v} {item}"
                                                                       for v, item, _ in enumerations[row[0]][1]))
                 if row[0] in enumerations else row for row in variables)


def contact_values(values: dict, name: str, contacts: int, dimensions: dict) -> tuple:
    """The per-contact values of parameter ``name`` among ``values`` (name -> value): the FMI 3.0 array ``name``
    (in ``dimensions``), the scalar ``name`` of a single contact, else ``name[1]`` ... ``name[contacts]``."""
    if name in dimensions:
        return tuple(values[name])
    return (values[name],) if contacts == 1 else tuple(values[f"{name}[{k}]"] for k in range(1, contacts + 1))


def contacts_step(step, current_time: float, step_size: float, values, width: int, arrays: bool) -> tuple:
    """The outputs of a several-contact slave in its table's order (a tuple: the slave's outputs as they are) from
    ``step(current_time, step_size, rows)`` (one output tuple per contact) and its input values: one array per input
    (``arrays``, FMI 3.0: rows are their columns, outputs go output by output) or ``width`` inputs per contact in turn
    (FMI 2.0: contact by contact)."""
    if arrays:
        return tuple(chain.from_iterable(zip(*step(current_time, step_size, list(zip(*values, strict=True))),
                                             strict=True)))
    return tuple(chain.from_iterable(step(current_time, step_size,
                                          [values[i:i + width] for i in range(0, len(values), width)])))


def printf_safe(message: str) -> str:
    """The message as a literal printf format (pythonfmu's C side formats log messages)."""
    return message.replace("%", "%%")


def short(value, limit: int = 80) -> str:
    """``repr(value)`` cut to ``limit`` characters: a log message never carries a whole crafted state."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def canonical_json(value) -> str:
    """The JSON text a state is serialised and checksummed as (sorted keys: the same text after a round trip)."""
    return json.dumps(value, sort_keys=True)


def serialise_state(state) -> bytes:
    """UTF-8 JSON of the FMU state ``state`` (a dict) with its checksum added."""
    return canonical_json({**state, CHECKSUM: hashlib.sha256(canonical_json(state).encode()).hexdigest()}).encode()


def deserialise_state(data: bytes):
    """The FMU state of :func:`serialise_state`'s bytes; ValueError (saying why) for anything else.

    The checksum catches accidental corruption (a flipped digit still parses); the state's content is checked when
    it is set, since anyone can compute a checksum.
    """
    try:
        state = json.loads(bytes(data).decode("utf-8"))
    except Exception as exc:  # noqa: BLE001 - UnicodeDecodeError, JSONDecodeError, RecursionError, ...
        raise ValueError(f"the serialised FMU state ({len(data)} bytes) is not UTF-8 JSON: "
                         f"{type(exc).__name__}: {clip(str(exc))}") from None
    if not isinstance(state, dict) or not isinstance(state.get(CHECKSUM), str):
        raise ValueError(f"the serialised FMU state ({len(data)} bytes) is no JSON object with a checksum")
    digest = state.pop(CHECKSUM)
    if hashlib.sha256(canonical_json(state).encode()).hexdigest() != digest:
        raise ValueError(f"the serialised FMU state ({len(data)} bytes) does not match its checksum: it is corrupt")
    return state


def clip(text: str, limit: int = 200) -> str:
    """``text`` cut to ``limit`` characters."""
    return text if len(text) <= limit else text[:limit - 3] + "..."


def same_value(a, b) -> bool:
    """Equal numbers (both NaN included), equal strings or arrays of such values: a host re-setting the value in
    force changes nothing."""
    if isinstance(a, list | tuple) and isinstance(b, list | tuple):
        return len(a) == len(b) and all(map(same_value, a, b))
    if is_real(a) and is_real(b):
        return a == b or (a != a and b != b)
    return type(a) is type(b) and a == b


def is_real(value) -> bool:
    """An int or float, not a bool (JSON numbers)."""
    return type(value) in (int, float)


def hold_uarray_error_type() -> None:
    """Give scipy's ``_uarray.BackendNotImplementedError`` type one reference that is never released.

    In an interpreter that pythonfmu's binary started (a C host), ``Py_Finalize`` frees ``_uarray``'s module state
    (its ``globals_free``) and afterwards a dictionary still reads that exception type: memcheck shows the read of
    the freed type, and it crashes the host at exit now and then (``benchmarks/results/exit.md``; docs/fmu.md, "Exit").
    One more reference keeps the type alive through finalisation; in a Python host it costs nothing.  Called once,
    when this module is first imported (pythonfmu re-runs the entry module at every instantiation, not this one).
    """
    try:
        from scipy._lib._uarray._uarray import BackendNotImplementedError
    except ImportError:  # a scipy without _uarray has nothing to hold
        return
    ctypes.pythonapi.Py_IncRef(ctypes.py_object(BackendNotImplementedError))


hold_uarray_error_type()


def drop_repeated_path(entry: str) -> None:
    """Remove all but the first occurrence of ``entry`` from ``sys.path`` (the same list object).

    pythonfmu's instance constructor inserts the resources folder at ``sys.path[0]`` on every instantiation and
    never removes it: without this, ``sys.path`` grows by one entry per instance.
    """
    if entry in sys.path:
        first = sys.path.index(entry)
        sys.path[first + 1:] = [path for path in sys.path[first + 1:] if path != entry]


def logger_categories(address: int, instance_name: str):
    """What pythonfmu 0.7's logger object at ``address`` hands to the host's logger callback: None while debug
    logging is off, ``()`` for every category, else the tuple of categories of ``fmi2SetDebugLogging``.

    The object is a ``pythonfmu::PyLogger`` (``Logger.hpp``; ``fmi2.cpp``'s ``Fmi2Logger`` adds the callbacks
    pointer), whose address pythonfmu passes to the slave as the keyword ``logger``.  With the GNU C++ library on a
    64-bit platform its members lie at: 8 ``bool debugLogging_``, 16 ``std::string instanceName_`` (data pointer,
    size, then the local buffer of short strings or the capacity), 48 ``std::vector<std::string> categories_``
    (begin, end, end of storage; 32 bytes per string).  The layout is accepted only when the instance name read
    there is ``instance_name``, the flag is 0 or 1 and the vector is well formed; raises ValueError otherwise (another
    platform, compiler or pythonfmu version).
    """
    if sys.platform != "linux" or ctypes.sizeof(ctypes.c_void_p) != 8:
        raise ValueError(f"the layout of pythonfmu's logger is known for 64-bit Linux only (this is {sys.platform})")
    if not address:
        raise ValueError("no logger object (address 0): unknown layout")
    name = instance_name.encode()
    if ctypes.c_size_t.from_address(address + 24).value != len(name) or string_at(address + 16) != name:
        # the size first: a pointer is followed only where the object already looks like the expected one
        raise ValueError("the instance name in pythonfmu's logger object does not match: unknown layout")
    flag = ctypes.c_uint8.from_address(address + 8).value
    begin, end, storage = (ctypes.c_size_t.from_address(address + offset).value for offset in (48, 56, 64))
    if flag > 1 or not begin <= end <= storage or (end - begin) % 32 or (end - begin) // 32 > 64 or \
            (end > begin and not begin):
        raise ValueError("the debug flag or the categories in pythonfmu's logger object are malformed: unknown layout")
    if not flag:
        return None
    return tuple(string_at(element).decode(errors="replace") for element in range(begin, end, 32))


def string_at(address: int, limit: int = 1024) -> bytes:
    """The bytes of the GNU C++ library's ``std::string`` at ``address`` (ValueError when it is none: a short string
    not in its local buffer, a long one in it, or longer than ``limit``)."""
    data, size, capacity = (ctypes.c_size_t.from_address(address + offset).value for offset in (0, 8, 16))
    local = address + 16
    if size > limit or (size <= 15) != (data == local) or (data != local and capacity < size):
        raise ValueError(f"no std::string at {address:#x}")
    return ctypes.string_at(data, size)


class StateRefused(ValueError):
    """An FMU state that cannot be set; the message says why."""


def checked_value(name: str, value, kind):
    """A state's value of the variable ``name`` of type ``kind`` (Real as float); StateRefused for another type."""
    if kind is Real and is_real(value):
        return float(value)
    if (kind is Integer and type(value) is int and INT32[0] <= value <= INT32[1]) or (
            kind is String and type(value) is str):
        return value
    raise StateRefused(f"variables: {name} = {short(value)} is not of type {kind.__name__}")


def complete_model_description(root: Element, variables, initial_dependencies: str | None = "",
                               enumerations: dict | None = None) -> Element:
    """Add units, min/max, UnitDefinitions, TypeDefinitions of the enumerations and a complete ModelStructure to
    pythonfmu's ``root`` (returned).

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

    Outputs are computed in ``do_step`` only, so in ``Outputs`` they depend on no input (``dependencies=""``).
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
                element.set(attribute, repr(float(bound)) if kind is Real else str(bound))  # exact round trip
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


class TableSlave:
    """What every slave does around its library model, in either FMI version: variables from one table, do_step,
    state, refusals.

    It is no pythonfmu slave itself: a binding constructs it and answers the FMI calls in its version's names,
    :class:`fmi2_table_slave.TableSlave2` on pythonfmu's ``Fmi2Slave`` (the FMI 2.0 slave class names the shared
    class first, then the binding) and :class:`fmi3_table_slave.TableSlave3` on pythonfmu3 (first, then the shared
    class, then ``Fmi3Slave``).  The binding gives ``log``, ``register_variable``, ``vars``, ``instance_name``,
    ``resources``, ``modelName`` and :attr:`WORDS`, and calls :meth:`init_table` after its base constructor.

    A subclass sets :attr:`VARIABLES` (rows as in the module docstring) and :attr:`INITIAL_DEPENDENCIES`, and gives
    :meth:`new_model` (parameter values -> model and notices to log, without side effects), :meth:`step_model`,
    :meth:`parse_model_state` (a model state dict -> the model's state object, checked completely) and
    :meth:`restore_model`; :meth:`initial_outputs` and :meth:`restored_outputs` when the outputs follow the model.

    Life cycle: parameters are set before ``exit_initialization_mode``, which builds the model (invalid parameters
    leave ``problem`` set: every ``do_step`` is then discarded with it).  After it the parameters are fixed: a set
    that changes one is refused (emulated fmi2Error, module docstring).  ``do_step`` accepts only the communication
    point ``t_(n+1) = t_n + h_n`` (or the start time, or the time of a restored state), within rounding.  Any
    exception of the model becomes a logged Discard, never an escaping exception.  The FMU state holds the
    non-output variables, the outputs, the life-cycle fields and the model's state dict.
    """

    VARIABLES: tuple = ()
    ENUMERATIONS: dict = {}
    DIMENSIONS: dict = {}
    """Array variables (FMI 3.0's ``<Dimension>``) -> their number of values: such a variable holds a list, its
    value reference gets and sets that many values (the others one each)."""
    INITIAL_DEPENDENCIES: str | None = ""

    def init_table(self, **kwargs) -> None:
        """Set up what the slave adds to its binding's constructor: the table's variables (registered through
        ``self.register_variable``, so the binding's own), their start values, the outputs and the life-cycle
        fields.  Called by the constructor of each binding after that binding's base constructor."""
        if "logger" in kwargs and self.resources:  # instantiated by pythonfmu's binary (not by the builder)
            drop_repeated_path(self.resources)
        self.logger_address = kwargs.get("logger")  # pythonfmu's C++ logger object (logger_categories)
        self.told: set[str] = set()  # refusal reasons the host's logger received or standard error showed
        self.echoes = 0  # lines written to standard error
        self.output_names: list[str] = []  # per output value: its name (name[k] in an array)
        self.output_kinds: list[type] = []  # per output value: its type
        self.output_index: dict[int, tuple[int, ...]] = {}  # value reference -> its positions in the outputs
        self.output_plans: dict[tuple, Callable] = {}  # (type, value references) read before -> gather
        self.input_plans: dict[tuple, tuple] = {}  # (type, value references) of inputs set before -> (names, spans)
        self.input_names = {vr: row[0] for vr, row in enumerate(self.VARIABLES) if row[2] is Fmi2Causality.input}
        outputs = []
        for vr, (name, kind, causality, variability, _unit, start, _lo, _hi, description) in enumerate(self.VARIABLES):
            size = self.DIMENSIONS.get(name)
            if causality is Fmi2Causality.output:
                positions = tuple(range(len(outputs), len(outputs) + (size or 1)))
                self.output_index[vr] = positions
                getter = self.output_reader(positions[0] if size is None else positions)
                outputs += [start] * len(positions)
                self.output_names += [name] if size is None else [f"{name}[{k}]" for k in range(1, size + 1)]
                self.output_kinds += [kind] * len(positions)
                initial = Fmi2Initial.approx
            else:
                setattr(self, name, start if size is None else [start] * size)
                getter = initial = None
            self.register_variable(kind(name, causality=causality, variability=variability, initial=initial,
                                        description=description, getter=getter,
                                        setter=self.variable_writer(name, kind, causality, variability)))
        self.outputs = tuple(outputs)
        self.kinds = {row[0]: row[1] for row in self.VARIABLES}
        self.state_variables = tuple(row[0] for row in self.VARIABLES if row[2] is not Fmi2Causality.output)
        self.parameter_names = tuple(row[0] for row in self.VARIABLES if row[2] is Fmi2Causality.parameter)
        self.start_time = 0.0
        self.stop_time = None  # the run's end from setupExperiment (None: not defined)
        self.initialised = False
        self.next_time: float | None = None
        self.model = None
        self.model_values: dict | None = None
        self.problem: str | None = NOT_INITIALISED
        self.error: str | None = None

    # hooks ------------------------------------------------------------------------------------------------------
    def new_model(self, values: dict):
        """``(model, notices)`` for the parameter values (raises for invalid ones); no side effects."""
        raise NotImplementedError

    def step_model(self, current_time: float, step_size: float) -> tuple:
        """The model's outputs after one step (table order); may raise."""
        raise NotImplementedError

    def parse_model_state(self, data):
        """The model's state object from its dict, every field checked (raises ValueError); no side effects."""
        raise NotImplementedError

    def restore_model(self, model, state) -> None:
        """Set ``model``'s state to the object of :meth:`parse_model_state`; may raise (e.g. a certified table the
        state refers to cannot be built), leaving ``model`` as it was."""
        model.set_state(state)

    def step_messages(self) -> list[str]:
        """Messages of the model's last step attempt, logged with status Warning (default: none)."""
        return []

    def initial_outputs(self, model) -> tuple | None:
        """The outputs after initialisation with ``model`` (None: keep the start values)."""
        return None

    def restored_outputs(self, saved: tuple) -> tuple:
        """The outputs after a state was restored into ``self.model`` (default: the saved ones)."""
        return saved

    # FMI calls --------------------------------------------------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        if not self.initialised:
            self.start_time = float(start_time)
            self.stop_time = None if stop_time is None else float(stop_time)

    def exit_initialization_mode(self):
        if self.initialised:  # a state saved after initialisation was set in initialisation mode
            return
        self.initialised = True
        self.next_time = self.start_time
        values = self.parameter_values()
        try:
            model, notices = self.new_model(dict(values))
        except Exception as exc:  # noqa: BLE001 - an escaping exception would be fmi2Fatal
            self.problem = f"invalid parameters: {exc}"
            w = self.WORDS
            self.report(f"exitInitializationMode: {self.problem}; every do_step will be discarded ({w['binding']} "
                        f"cannot return {w['error']} here): reset the instance and set valid parameters",
                        Fmi2Status.error, self.problem)
            return
        self.model, self.model_values, self.problem = model, values, None
        outputs = self.initial_outputs(model)
        if outputs is not None:
            self.outputs = tuple(outputs)
        for notice in notices:
            self.report(notice, Fmi2Status.ok)

    def do_step(self, current_time, step_size):
        if self.error is not None:
            return self.discard(current_time, None, f"the instance is in error state since: {self.error}; set "
                                f"a valid saved state ({self.WORDS['set_state']}) or reset the instance", self.error)
        if self.problem is not None:
            return self.discard(current_time, None, self.problem)
        late = self.time_problem(current_time, step_size)
        if late is not None:
            return self.discard(current_time, step_size, late)
        try:
            outputs = self.step_model(current_time, step_size)
        except Exception as exc:  # noqa: BLE001 - an escaping exception would be fmi2Fatal
            self.report_step_messages()
            return self.discard(current_time, step_size, str(exc))
        self.report_step_messages()
        self.outputs = tuple(outputs)
        self.next_time = current_time + step_size
        return True

    def _get_fmu_state(self):
        return {"format": STATE_FORMAT, "version": STATE_VERSION, "fmu": self.modelName,
                "variables": {name: getattr(self, name) for name in self.state_variables},
                "outputs": list(self.outputs), "start_time": self.start_time, "initialised": self.initialised,
                "next_time": self.next_time, "model": None if self.model is None else self.model.state.to_dict()}

    def _set_fmu_state(self, state):
        try:
            checked = self.check_state(state)
            if checked["model"] is not None:  # before anything changes: a refused model state changes nothing
                self.restore_model(checked["model"], checked["model_state"])
        except Exception as exc:  # noqa: BLE001 - StateRefused, or anything unforeseen: never fmi2Fatal
            reason = str(exc) if isinstance(exc, StateRefused) else f"{type(exc).__name__}: {clip(str(exc), 200)}"
            self.refuse(f"{self.WORDS['set_state']} refused, the instance keeps its previous state: {reason}")
            return
        for name, value in checked["variables"].items():
            setattr(self, name, value)
        self.start_time, self.initialised, self.next_time = (checked[k] for k in ("start_time", "initialised",
                                                                                    "next_time"))
        self.model, self.model_values, self.problem = checked["model"], checked["values"], checked["problem"]
        self.outputs = checked["outputs"]
        if self.model is not None:
            self.outputs = tuple(self.restored_outputs(self.outputs))
        self.error = None

    @staticmethod
    def _fmu_state_to_bytes(state) -> bytes:
        try:
            return serialise_state(state)
        except Exception as exc:  # noqa: BLE001 - never fmi2Fatal: the bytes are refused when set
            return f"the FMU state could not be serialised: {clip(str(exc))}".encode()

    @staticmethod
    def _fmu_state_from_bytes(state):
        try:
            return deserialise_state(state)
        except Exception as exc:  # noqa: BLE001 - never fmi2Fatal: the marker is refused when set
            return {UNDECODABLE: str(exc)}

    # helpers ----------------------------------------------------------------------------------------------------
    def report(self, message: str, status: Fmi2Status, reason: str | None = None) -> None:
        """Log ``message`` (printf-safe) with ``status`` (its category: logStatusError etc., else logAll); a refusal
        (status Discard or Error) is also echoed (:meth:`echo`) under ``reason`` (default: the message)."""
        self.log(printf_safe(message), status)
        if status in REFUSAL_CATEGORIES:
            self.echo(message, status, message if reason is None else reason)

    def echo(self, message: str, status: Fmi2Status, reason: str) -> None:
        """Write the refusal ``message`` to standard error unless the host's logger receives its category (module
        docstring), once per ``reason`` and instance: a reason already told, through the host's logger or here, is not
        repeated (the same reason at another time, or as the Discard that follows an Error).  At most
        :data:`ECHO_LIMIT` lines, then one that says so; :data:`TOLD_LIMIT` reasons are remembered.  Never raises.

        Not under pythonfmu's binary (no logger object: the builder, a Python caller reading the log queue) nothing
        is written.  A logger object of an unknown layout counts as not receiving: a refusal may then be shown twice,
        but never not at all.
        """
        if self.logger_address is None or reason in self.told or self.echoes > ECHO_LIMIT:
            return
        category = REFUSAL_CATEGORIES[status]
        try:
            categories = logger_categories(self.logger_address, self.instance_name)
        except Exception:  # noqa: BLE001 - unknown layout: echo
            categories = None
        if len(self.told) < TOLD_LIMIT:
            self.told.add(reason)
        if categories is not None and (not categories or category in categories):
            return
        self.echoes += 1
        line = (f"{self.modelName} (instance {self.instance_name!r}): {status.name.capitalize()}: {message} "
                f"[on standard error because the host's logger does not receive {category}; once per reason]")
        if self.echoes > ECHO_LIMIT:
            line = (f"{self.modelName} (instance {self.instance_name!r}): more than {ECHO_LIMIT} distinct refusals: "
                    "the others are not shown (enable the categories logStatusDiscard and logStatusError)")
        try:
            sys.stderr.write(line + "\n")
            sys.stderr.flush()
        except Exception:  # noqa: BLE001 - no standard error (None, closed): never fmi2Fatal
            pass

    def refuse(self, reason: str) -> None:
        """Emulate fmi2Error (pythonfmu cannot return it): log the reason, enter the error state."""
        w = self.WORDS
        self.report(f"{reason} [emulated {w['error']}: {w['binding']} returns {w['ok']} here; every do_step is "
                    "discarded until a valid state is set or the instance is reset]", Fmi2Status.error, reason)
        if self.error is None:
            self.error = reason

    def report_step_messages(self) -> None:
        try:
            for message in self.step_messages():
                self.report(message, Fmi2Status.warning)
        except Exception as exc:  # noqa: BLE001 - never fmi2Fatal
            self.report(f"the model's messages could not be read: {clip(str(exc))}", Fmi2Status.warning)

    def discard(self, current_time, step_size, reason: str, cause: str | None = None) -> bool:
        """Log why the step is discarded (status Discard) and return False (fmi2Discard); ``cause`` (default: the
        reason) is what :meth:`echo` shows once."""
        h = "" if step_size is None else f", h = {step_size!r} s"
        self.report(f"do_step at t = {current_time!r} s{h} discarded: {reason}", Fmi2Status.discard,
                    reason if cause is None else cause)
        return False

    def time_problem(self, current_time: float, step_size: float) -> str | None:
        """Why ``current_time`` is not the next communication point (None when it is, within rounding)."""
        expected = self.next_time
        if current_time == expected or not (math.isfinite(current_time) and math.isfinite(step_size)):
            return None  # non-finite times and steps are the model's to report
        tolerance = max(1e-9 * abs(step_size), 8.0 * math.ulp(max(abs(current_time), abs(expected))))
        if abs(current_time - expected) <= tolerance:
            return None
        return (f"the communication point t = {current_time!r} s is not the end of the previous step, "
                f"{expected!r} s: {self.WORDS['fmi']} co-simulation steps from t_(n+1) = t_n + h_n (the start time "
                f"first); set a saved state ({self.WORDS['set_state']}) to step from another time")

    def parameter_values(self) -> dict:
        return {name: getattr(self, name) for name in self.parameter_names}

    def variable_writer(self, name: str, kind, causality, variability):
        """The setter of variable ``name``: refuses outputs, and fixed parameters once initialised."""
        if causality is Fmi2Causality.output:
            return lambda value: self.refuse(f"set {name} = {short(value)} refused: {name} is an output")

        def write(value):
            if self.initialised and causality is Fmi2Causality.parameter and \
                    variability in (Fmi2Variability.fixed, Fmi2Variability.constant):
                current = getattr(self, name)
                if not same_value(value, current):
                    self.refuse(f"set {name} = {short(value)} refused: {name} is a fixed parameter and cannot change "
                                f"after initialisation (the value in force stays {current!r})")
                return
            setattr(self, name, value)

        return write

    def write_values(self, vrs, values, kind, call: str) -> None:
        # the inputs a host sets every step: once checked, straight to their attributes (an input's setter only
        # stores the value; an array input takes its slice of the values)
        key = (kind, *vrs)
        plan = self.input_plans.get(key)
        if plan is not None:
            names, spans = plan
            if spans is None:  # scalar inputs: plain instance attributes, stored in one call
                self.__dict__.update(zip(names, values, strict=False))
                return
            if len(values) == spans[-1][1]:
                for name, (lo, hi) in zip(names, spans, strict=True):
                    setattr(self, name, list(values[lo:hi]))
                return
        sizes = [self.DIMENSIONS.get(var.name, 1) if isinstance(var := self.vars.get(vr), kind) else 1 for vr in vrs]
        if len(values) != sum(sizes):
            self.refuse(f"{call} of {len(values)} values for the value references {short(list(vrs))} refused: they "
                        f"take {sum(sizes)} values")
            return
        if plan is None and vrs and len(self.input_plans) < PLAN_LIMIT and all(
                isinstance(self.vars.get(vr), kind) and vr in self.input_names for vr in vrs):
            ends = [sum(sizes[:i + 1]) for i in range(len(sizes))]
            self.input_plans[key] = ([self.input_names[vr] for vr in vrs], None if not self.DIMENSIONS else
                                     [(end - size, end) for end, size in zip(ends, sizes, strict=True)])
        position = 0
        for vr, size in zip(vrs, sizes, strict=True):
            var = self.vars.get(vr)
            value = values[position] if var is None or var.name not in self.DIMENSIONS else \
                list(values[position:position + size])
            position += size
            if not isinstance(var, kind):
                what = "no variable" if var is None else f"{var.name}, not a {kind.__name__}"
                self.refuse(f"{call} of value reference {vr!r} refused: it is {what}")
                continue
            var.setter(value)

    def read_values(self, vrs, kind, convert, placeholder, call: str) -> list:
        # the outputs a host reads every step: once checked, gathered from the last step's outputs in one call (the
        # Real outputs are floats already: only the other types are converted)
        key = (kind, *vrs)
        plan = self.output_plans.get(key)
        if plan is not None:
            values = plan(self.outputs)
            return list(values) if convert is float else [convert(v) for v in values]
        if vrs and all(isinstance(self.vars.get(vr), kind) and vr in self.output_index for vr in vrs):
            positions = [i for vr in vrs for i in self.output_index[vr]]
            self.output_plans[key] = itemgetter(*positions) if len(positions) > 1 else \
                (lambda outputs, i=positions[0]: (outputs[i],))
        values = []
        for vr in vrs:
            var = self.vars.get(vr)
            if not isinstance(var, kind):
                what = "no variable" if var is None else f"{var.name}, not a {kind.__name__}"
                self.refuse(f"{call} of value reference {vr!r}: it is {what} (returned {placeholder!r})")
                values.append(placeholder)
                continue
            try:
                if var.name in self.DIMENSIONS:
                    values += [convert(value) for value in var.getter()]
                    continue
                values.append(convert(var.getter()))
            except Exception as exc:  # noqa: BLE001 - never fmi2Fatal
                self.refuse(f"{call} of {var.name} failed: {clip(str(exc), 200)}")
                values.append(placeholder)
        return values

    def check_state(self, state):
        """Everything ``_set_fmu_state`` needs from ``state`` as a dict, checked completely; raises StateRefused
        and changes nothing (a new model may be built, but is not installed)."""
        if isinstance(state, dict) and set(state) == {UNDECODABLE}:
            raise StateRefused(str(state[UNDECODABLE]))
        if not isinstance(state, dict):
            raise StateRefused(f"an FMU state is a JSON object, got {type(state).__name__} {short(state)}")
        keys = {"format", "version", "fmu", "variables", "outputs", "start_time", "initialised", "next_time", "model"}
        if state.get("format") != STATE_FORMAT:
            raise StateRefused(f"not an FMU state of this FMU (format {short(state.get('format'))})")
        version = state.get("version")
        if type(version) is not int or version != STATE_VERSION:
            raise StateRefused(f"FMU state version {short(version)} is not supported (this FMU reads version "
                               f"{STATE_VERSION})")
        if set(state) != keys:
            unknown, missing = sorted(map(str, set(state) - keys)), sorted(keys - set(state))
            raise StateRefused(f"unknown key(s) {short(unknown)}, missing key(s) {missing}")
        if state["fmu"] != self.modelName:
            raise StateRefused(f"the state belongs to the FMU {short(state['fmu'])}, not {self.modelName}")
        variables = self.check_variables(state["variables"])
        outputs = self.check_outputs(state["outputs"])
        start_time, initialised, next_time = state["start_time"], state["initialised"], state["next_time"]
        if not is_real(start_time) or not math.isfinite(start_time):
            raise StateRefused(f"start_time = {short(start_time)} must be a finite real number")
        if type(initialised) is not bool:
            raise StateRefused(f"initialised = {short(initialised)} must be true or false")
        if initialised != (next_time is not None) or (
                next_time is not None and (not is_real(next_time) or not math.isfinite(next_time))):
            raise StateRefused(f"next_time = {short(next_time)} must be a finite real number once initialised, "
                               f"else null (initialised = {initialised})")
        data = state["model"]
        if data is not None and not isinstance(data, dict):
            raise StateRefused(f"model must be null or an object, got {type(data).__name__}")
        values = {name: variables[name] for name in self.parameter_names}
        checked = {"variables": variables, "outputs": outputs, "start_time": float(start_time),
                   "initialised": initialised, "next_time": None if next_time is None else float(next_time),
                   "model": None, "model_state": None, "values": None, "problem": NOT_INITIALISED}
        if not initialised:
            if data is not None:
                raise StateRefused("a state saved before initialisation holds no model state")
            return checked
        if self.model is not None and self.model_values is not None and all(
                same_value(values[k], self.model_values[k]) for k in values):
            model = self.model  # same parameters: the model is kept (only its state is set)
        else:
            try:
                model, _ = self.new_model(dict(values))
            except Exception as exc:  # noqa: BLE001 - the state's own parameters are invalid
                if data is not None:
                    raise StateRefused(f"its parameters are invalid ({clip(str(exc), 200)}) but it holds a model "
                                       "state") from None
                return {**checked, "values": values, "problem": f"invalid parameters: {exc}"}
        if data is None:
            raise StateRefused("an initialised state with valid parameters must hold the model's state")
        try:
            model_state = self.parse_model_state(data)
        except Exception as exc:  # noqa: BLE001
            raise StateRefused(clip(str(exc), 300)) from None
        return {**checked, "model": model, "model_state": model_state, "values": values, "problem": None}

    def check_variables(self, variables) -> dict:
        """The state's variables: exactly the non-output variables, each of its type."""
        if not isinstance(variables, dict):
            raise StateRefused(f"variables must be an object, got {type(variables).__name__}")
        unknown = [k for k in variables if k not in self.state_variables]
        missing = [k for k in self.state_variables if k not in variables]
        if unknown or missing:
            raise StateRefused(f"variables: unknown {short(sorted(map(str, unknown)))}, missing {short(missing)} "
                               "(a state holds exactly the FMU's input and parameter variables)")
        checked = {}
        for name in self.state_variables:
            value, kind, size = variables[name], self.kinds[name], self.DIMENSIONS.get(name)
            if size is None:
                checked[name] = checked_value(name, value, kind)
            elif type(value) is list and len(value) == size:
                checked[name] = [checked_value(name, element, kind) for element in value]
            else:
                raise StateRefused(f"variables: {name} = {short(value)} is not a list of {size} values")
        return checked

    def check_outputs(self, outputs) -> tuple:
        """The state's outputs: one finite value of its type per output."""
        if not isinstance(outputs, list) or len(outputs) != len(self.output_names):
            raise StateRefused(f"outputs must be a list of {len(self.output_names)} values, got {short(outputs)}")
        for name, kind, value in zip(self.output_names, self.output_kinds, outputs, strict=True):
            ok = (is_real(value) and math.isfinite(value)) if kind is Real else \
                (type(value) is int and INT32[0] <= value <= INT32[1])
            if not ok:
                raise StateRefused(f"outputs: {name} = {short(value)} is not a finite value of type {kind.__name__}")
        return tuple(float(v) if kind is Real else v for kind, v in zip(self.output_kinds, outputs, strict=True))

    def output_reader(self, index):
        """Getter of output ``index`` of the last step (the outputs follow the table); of an array output (a tuple of
        positions) the list of its values."""
        if isinstance(index, tuple):
            return lambda: [self.outputs[i] for i in index]
        return lambda: self.outputs[index]
