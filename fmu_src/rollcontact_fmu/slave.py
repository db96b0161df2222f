"""The slave base of every FMU of the project: :class:`TableSlave`, a slave's variables from one table, its life
cycle, ``do_step`` and its refusals, in either FMI version.

A slave declares its variables in one table of rows ``(name, type, causality, variability, unit, start, min, max,
description)``, the types and causalities pythonfmu's (FMI 2.0) classes (:data:`INPUT` ... :data:`FIXED`); the value
reference of a variable is its row number (append, never reorder).  Its binding registers the table with pythonfmu
(``rollcontact_fmu.fmi2``) or pythonfmu3 (``rollcontact_fmu.fmi3``) and completes the model description from it
(``rollcontact_fmu.description``).

What pythonfmu's C++ layer does with a slave shapes what :class:`TableSlave` does (docs/fmu-internals.md):

* Any exception escaping a slave method becomes fmi2Fatal (fmi3Fatal), after which every call on the instance is a
  use after free.  So nothing raises into pythonfmu: not the setters, getters, state methods or ``do_step``.
* Only ``do_step`` has a status (False: fmi2Discard); every other call returns fmi2OK.  A call FMI answers with
  fmi2Error (a fixed parameter set after initialisation, an invalid FMU state, invalid parameters at
  exitInitializationMode, an unknown value reference) is therefore logged with status Error and puts the instance
  into an *emulated error state*: it keeps its previous values, and every ``do_step`` is discarded with the reason
  until a valid state is set or the instance is reset.
* pythonfmu 0.7 hands a message to the host's logger only while debug logging is on for its category: a message of
  status Discard or Error that the host's logger does not receive is written to the process's standard error
  instead, once per distinct reason and instance (:meth:`TableSlave.echo`).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable
from operator import itemgetter

from pythonfmu.enums import Fmi2Causality, Fmi2Initial, Fmi2Status, Fmi2Variability

from rollcontact_fmu.state import NOT_INITIALISED, FmuState, clip, same_value, short
from rollcontact_fmu.workarounds import drop_repeated_path, logger_categories, printf_safe

INPUT, OUTPUT, PARAMETER = Fmi2Causality.input, Fmi2Causality.output, Fmi2Causality.parameter
CONTINUOUS, DISCRETE, FIXED = Fmi2Variability.continuous, Fmi2Variability.discrete, Fmi2Variability.fixed
"""The causalities and variabilities of a variable table's rows."""

POSITIVE = math.nextafter(0.0, 1.0)
"""``min`` of a parameter that must be > 0: FMI bounds are inclusive, and the smallest positive double is the first
value above 0."""

REFUSAL_CATEGORIES = {Fmi2Status.discard: "logStatusDiscard", Fmi2Status.error: "logStatusError"}
"""Status of a refusal -> the log category pythonfmu gives it; such a message the host's logger does not receive is
written to standard error (:meth:`TableSlave.echo`)."""

ECHO_LIMIT = 20
"""Distinct refusal reasons one instance writes to standard error at most (then one line says the rest is not)."""

TOLD_LIMIT = 256
"""Refusal reasons one instance remembers as told (a host stepping on after refusals does not grow memory)."""

PLAN_LIMIT = 64
"""Lists of input value references one instance remembers as checked (a host sets the same few every step)."""


class TableSlave(FmuState):
    """What every slave does around its library model, in either FMI version: variables from one table, do_step,
    state, refusals.

    It is no pythonfmu slave itself: a binding constructs it and answers the FMI calls in its version's names,
    :class:`rollcontact_fmu.fmi2.TableSlave2` on pythonfmu's ``Fmi2Slave`` (the FMI 2.0 slave class names the shared
    class first, then the binding: :func:`rollcontact_fmu.fmi2.fmi2_class`) and
    :class:`rollcontact_fmu.fmi3.TableSlave3` on pythonfmu3 (first, then the shared class, then ``Fmi3Slave``).  The
    binding gives ``log``, ``register_variable``, ``vars``, ``instance_name``, ``resources``, ``modelName`` and
    :attr:`WORDS`, and calls :meth:`init_table` after its base constructor.  The FMU state's methods are
    :class:`~rollcontact_fmu.state.FmuState`'s.

    A subclass sets :attr:`VARIABLES` (rows as in the module docstring), :attr:`ENUMERATIONS` (variable -> its
    enumeration, :mod:`rollcontact_fmu.enumerations`) and :attr:`INITIAL_DEPENDENCIES`, and gives
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

    author = "rollcontact"
    license = "MIT"
    """The model description's author and license (a slave gives its ``description``, ``version`` and
    ``default_experiment``)."""

    VARIABLES: tuple = ()
    ENUMERATIONS: dict = {}
    DIMENSIONS: dict = {}
    """Array variables (FMI 3.0's ``<Dimension>``) -> their number of values: such a variable holds a list, its
    value reference gets and sets that many values (the others one each)."""
    INITIAL_DEPENDENCIES: str | None = ""
    TIME_REFERENCE: int | None = None
    """FMI 3.0's value reference of ``time`` where rows were appended to the table after it was released: the rows
    from this one on come after ``time``, each at its row plus one, so every released value reference stays (None:
    ``time`` after the last row).  FMI 2.0 has no ``time``: there every row is its value reference."""

    def reference(self, row: int) -> int:
        """The value reference of table row ``row``: the row itself in FMI 2.0 (FMI 3.0:
        :meth:`rollcontact_fmu.fmi3.TableSlave3.reference`)."""
        return row

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
        self.input_names = {self.reference(row): variable[0] for row, variable in enumerate(self.VARIABLES)
                            if variable[2] is Fmi2Causality.input}
        outputs = []
        for row, (name, kind, causality, variability, _unit, start, _lo, _hi, description) in enumerate(self.VARIABLES):
            size = self.DIMENSIONS.get(name)
            if causality is Fmi2Causality.output:
                positions = tuple(range(len(outputs), len(outputs) + (size or 1)))
                self.output_index[self.reference(row)] = positions
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

    def output_reader(self, index):
        """Getter of output ``index`` of the last step (the outputs follow the table); of an array output (a tuple of
        positions) the list of its values."""
        if isinstance(index, tuple):
            return lambda: [self.outputs[i] for i in index]
        return lambda: self.outputs[index]


class HostSlave(TableSlave):
    """A slave whose model is ``MODEL(PARAMETERS(**values), start_time=...)`` with ``outputs()`` in the table's order
    (the co-simulation hosts of ``rollcontact_cosim``): its outputs follow the model from initialisation on, and
    after a restored state."""

    MODEL: type
    PARAMETERS: type
    INITIAL_DEPENDENCIES = None  # the initial outputs are computed from the parameters

    def new_model(self, values: dict):
        """The model at the start time (no notices)."""
        return self.MODEL(self.PARAMETERS(**values), start_time=self.start_time), ()

    def initial_outputs(self, model):
        return model.outputs()

    def restored_outputs(self, saved):
        return self.model.outputs()
