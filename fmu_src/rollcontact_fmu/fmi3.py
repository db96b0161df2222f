"""The FMI 3.0 co-simulation binding of the project's slaves (pythonfmu3 0.3.4).

:class:`TableSlave3` puts a shared slave class (a :class:`rollcontact_fmu.slave.TableSlave` with its model glue, e.g.
a variant of ``rollcontact_fmu_contact2d.RollingContact2DShared``, whose FMI 2.0 class is
``rollcontact_fmu.fmi2.fmi2_class``'s) on pythonfmu3: the same variable table (names, value references, units,
ranges, enumerations, descriptions), the same ``do_step``, setters, checks and FMU state, none of it written twice.
The FMI 3.0 entry module names both and ``Fmi3Slave`` (pythonfmu3's builder and binary find the class by a regular
expression over the entry module's lines: the class statement names ``Fmi3Slave`` on one line)::

    class RollingContact2D(TableSlave3, RollingContact2DShared, Fmi3Slave):

:class:`TableSlave3` comes first, so it answers every call pythonfmu3 makes and everything FMI 3.0 words
differently: variables are registered as pythonfmu3's Float64 (Real), Int32 (Integer), Enumeration (an Integer of
the table's ``ENUMERATIONS``; Int64 at the API) and String, plus the independent variable ``time`` that FMI 3.0
requires (value reference after the table's); log messages are pythonfmu3's (literal text, not printf formats,
written in FMI 3.0's words: :attr:`TableSlave3.WORDS`); the model description is FMI 3.0's.  The table's types and
causalities are pythonfmu's (FMI 2.0) classes, so each FMI 3.0 FMU also bundles pythonfmu's Python files (not its
binary).  No FMI 3.0 slave inherits pythonfmu's ``Fmi2Slave`` or the FMI 2.0 binding (``tests/fmu3`` checks it):
:meth:`TableSlave3.__init__` runs ``Fmi3SlaveBase.__init__`` (pythonfmu3's attributes), then the shared slave's
:meth:`~rollcontact_fmu.slave.TableSlave.init_table` (the table, registered through pythonfmu3), then registers
``time``; the calls the shared slave does not answer (``enter_initialization_mode``, ``terminate``, ...) are
pythonfmu3's.

What pythonfmu3 does differently from pythonfmu 0.7, and how this binding copes (docs/fmu-internals.md, "pythonfmu3"):
a message logged with ``debug=False`` reaches the host's logger whether or not debug logging is on (the notices of
status OK are logged with ``debug=True``), passed as it is (no ``%`` escaping); ``fmi3EnterInitializationMode``'s
``startTime`` never reaches Python, so the first ``fmi3DoStep``'s communication point, which FMI 3.0 makes the start
time, sets it (:meth:`TableSlave3.do_step`); the entry module is imported once per process; variables have no
min/max and starts are written with 16 digits (``rollcontact_fmu.description.complete_model_description3`` adds the
bounds, exact starts and the ModelStructure's dependencies).
"""

from __future__ import annotations

import math
from xml.etree.ElementTree import Element

from pythonfmu import Real
from pythonfmu.variables import Boolean as Boolean2
from pythonfmu.variables import Integer as Integer2
from pythonfmu.variables import String as String2
from pythonfmu3 import Fmi3Causality, Fmi3Initial, Fmi3Status, Fmi3Variability
from pythonfmu3.fmi3slave import Fmi3SlaveBase
from pythonfmu3.unit import Unit
from pythonfmu3.variable_types import EnumerationType
from pythonfmu3.variables import Boolean, Enumeration, Float64, Int32, Int64, String, UInt64

from rollcontact_fmu.description import UNITS, complete_model_description3
from rollcontact_fmu.slave import TableSlave

TIME_DESCRIPTION = "Simulation time, the independent variable (FMI 3.0 requires one)"


def fmi3_variable(var, row, enumerations: dict):
    """The pythonfmu3 variable of the shared slave's pythonfmu variable ``var`` (table row ``row``): same name,
    causality, variability, initial, description, getter and setter; Real with its unit; an Integer of
    ``enumerations`` as an Enumeration of its declared type."""
    common = {"causality": Fmi3Causality[var.causality.name], "variability": Fmi3Variability[var.variability.name],
              "initial": None if var.initial is None else Fmi3Initial[var.initial.name],
              "description": var.description, "getter": var.getter, "setter": var.setter}
    if isinstance(var, Real):
        return Float64(var.name, unit=row[4], **common)
    if isinstance(var, Integer2):
        if var.name in enumerations:
            return Enumeration(var.name, declared_type=enumerations[var.name][0], **common)
        return Int32(var.name, **common)
    if isinstance(var, String2):
        return String(var.name, **common)
    if isinstance(var, Boolean2):
        return Boolean(var.name, **common)
    raise TypeError(f"{var.name}: no FMI 3.0 type for {type(var).__name__}")  # a table row of an unknown type


class TableSlave3:
    """The FMI 3.0 side of a :class:`rollcontact_fmu.slave.TableSlave` (module docstring): put it first in the bases,
    the shared slave class next and ``Fmi3Slave`` last."""

    WORDS = {"error": "fmi3Error", "ok": "fmi3OK", "fmi": "FMI 3", "binding": "pythonfmu3", "set_state": "setFMUState"}
    """FMI 3.0's words in the shared slave's messages."""

    def __init__(self, **kwargs):
        Fmi3SlaveBase.__init__(self, **kwargs)  # pythonfmu3's attributes (vars, units, type_definitions, ...)
        self.init_table(**kwargs)  # the shared slave's table, registered through register_variable below
        if len(self.vars) == self.time_reference():  # no row after time
            self.register_time()

    def time_reference(self) -> int:
        """The value reference of ``time``: :attr:`~rollcontact_fmu.slave.TableSlave.TIME_REFERENCE`, or after the
        last row."""
        return len(self.VARIABLES) if self.TIME_REFERENCE is None else self.TIME_REFERENCE

    def reference(self, row: int) -> int:
        """The value reference of table row ``row``: the row, plus one from ``time``'s on."""
        return row if row < self.time_reference() else row + 1

    def register_time(self) -> None:
        """Register the independent variable ``time`` (FMI 3.0 requires one; setting it is refused)."""
        Fmi3SlaveBase.register_variable(self, Float64("time", causality=Fmi3Causality.independent, unit="s",
                                                      variability=Fmi3Variability.continuous,
                                                      description=TIME_DESCRIPTION, getter=self.current_time,
                                                      setter=self.refuse_time))

    def register_variable(self, var, nested: bool = True, var_type=None, has_event_indicator: bool = False):
        """Register ``var``, a pythonfmu3 variable or a pythonfmu variable of the table (converted; ``time`` first
        where its value reference comes, :meth:`time_reference`)."""
        if not isinstance(var, Float64 | Int32 | Int64 | UInt64 | Enumeration | String | Boolean):
            time = self.time_reference()
            if len(self.vars) == time:
                self.register_time()
            row = len(self.vars) - (len(self.vars) > time)  # value reference -> row
            var = fmi3_variable(var, self.VARIABLES[row], self.ENUMERATIONS)
        Fmi3SlaveBase.register_variable(self, var, nested, var_type, has_event_indicator)

    def current_time(self) -> float:
        """The communication point the next step starts from (the start time before the first)."""
        return self.start_time if self.next_time is None else self.next_time

    def refuse_time(self, value) -> None:
        self.refuse(f"set time = {value!r} refused: time is the independent variable")

    # logging: pythonfmu3's messages, FMI 3.0's words ----------------------------------------------------------
    def log(self, msg: str, status=Fmi3Status.ok, category: str | None = None, debug: bool = False) -> None:
        Fmi3SlaveBase.log(self, msg, Fmi3Status(int(status)), category, debug)

    def report(self, message: str, status, reason: str | None = None) -> None:
        """Log ``message`` as it is (FMI 3.0 messages are no printf formats; the shared slave writes them in
        :attr:`WORDS`); status OK only with debug logging, any other status always (the shared slave's ``report``
        escapes ``%`` for FMI 2.0, and echoes refusals the host's logger does not receive: pythonfmu3 passes them on,
        ``reason`` is unused)."""
        status = Fmi3Status(int(status))
        Fmi3SlaveBase.log(self, message, status, debug=status is Fmi3Status.ok)

    # FMI calls --------------------------------------------------------------------------------------------------
    def do_step(self, current_time, step_size):
        """The shared slave's step; the first step of a model sets the start time to its communication point
        (pythonfmu3 does not pass fmi3EnterInitializationMode's startTime)."""
        model = self.model
        if self.next_time == self.start_time != current_time and model is not None and self.error is None and \
                math.isfinite(current_time) and model.state.steps == 0:  # last: several contacts' state is built
            self.start_time = self.next_time = float(current_time)
            model.reset(self.start_time)
            outputs = self.initial_outputs(model)
            if outputs is not None:
                self.outputs = tuple(outputs)
            self.report(f"start time {self.start_time!r} s taken from the first doStep (pythonfmu3 does not pass "
                        "fmi3EnterInitializationMode's startTime)", Fmi3Status.ok)
        return TableSlave.do_step(self, current_time, step_size)

    def set_float64(self, vrs, values):
        self.write_values(vrs, values, Float64, "setFloat64")

    def set_int32(self, vrs, values):
        self.write_values(vrs, values, Int32, "setInt32")

    def set_int64(self, vrs, values):
        self.write_values(vrs, values, Enumeration, "setInt64")

    def set_uint64(self, vrs, values):
        self.write_values(vrs, values, UInt64, "setUInt64")

    def set_boolean(self, vrs, values):
        self.write_values(vrs, values, Boolean, "setBoolean")

    def set_string(self, vrs, values):
        self.write_values(vrs, values, String, "setString")

    def get_float64(self, vrs):
        return self.read_values(vrs, Float64, float, math.nan, "getFloat64")

    def get_int32(self, vrs):
        return self.read_values(vrs, Int32, int, 0, "getInt32")

    def get_int64(self, vrs):
        return self.read_values(vrs, Enumeration, int, 0, "getInt64")

    def get_uint64(self, vrs):
        return self.read_values(vrs, UInt64, int, 0, "getUInt64")

    def get_boolean(self, vrs):
        return self.read_values(vrs, Boolean, bool, False, "getBoolean")

    def get_string(self, vrs):
        return self.read_values(vrs, String, str, "", "getString")

    def to_xml(self, model_options=None) -> Element:
        """pythonfmu3's model description of the table (units and enumeration types registered through pythonfmu3)
        completed by :func:`complete_model_description3`."""
        for attribute in ("author", "description", "license", "version", "copyright", "default_experiment"):
            setattr(self, attribute, getattr(type(self), attribute, None))  # Fmi3SlaveBase.__init__ set them to None
        used = {row[4] for row in self.VARIABLES if row[4] is not None} | {"s"}
        self.register_units([Unit(name, **UNITS[name]) for name in UNITS if name in used])
        for type_name, items in dict(self.ENUMERATIONS.values()).items():
            self.type_definitions[type_name] = enumeration = EnumerationType(type_name, values=())
            for value, item, description in items:
                enumeration.add_value(item, value, description)
        root = Fmi3SlaveBase.to_xml(self, {} if model_options is None else model_options)
        return complete_model_description3(root, self.VARIABLES, self.INITIAL_DEPENDENCIES, self.DIMENSIONS)

