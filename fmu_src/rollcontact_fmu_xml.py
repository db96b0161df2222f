"""What the project's pythonfmu slaves share (bundled in each FMU's resources): the :class:`TableSlave` base
(variables from one table, do_step, state), modelDescription completion and printf-safe log messages.

pythonfmu 0.7 writes no units, bounds, UnitDefinitions or InitialUnknowns (``fmpy validate`` then fails).  A
slave that declares its variables in one table of rows ``(name, type, causality, variability, unit, start, min,
max, description)`` (value references = row order) calls :func:`complete_model_description` from its
``to_xml`` to add them.
"""

from __future__ import annotations

from xml.etree.ElementTree import Element, SubElement

from pythonfmu import Fmi2Slave, Real
from pythonfmu.enums import Fmi2Causality, Fmi2Initial, Fmi2Status

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


class TableSlave(Fmi2Slave):
    """What both slaves do around their library model: variables from one table, do_step, state, XML.

    A subclass sets :attr:`VARIABLES` (rows as in the module docstring) and :attr:`INITIAL_DEPENDENCIES`, and gives
    :meth:`new_model` (parameter values -> model and notices to log), :meth:`step_model` and
    :meth:`restore_model`.  Bad parameters leave ``problem`` set: every ``do_step`` is then discarded with it; any
    exception of the model becomes a logged Discard, never an escaping exception (pythonfmu would turn it into
    fmi2Fatal).  The FMU state holds the non-output variables, the outputs and the model's state dict.
    """

    VARIABLES: tuple = ()
    INITIAL_DEPENDENCIES: str | None = ""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        outputs = []
        for name, kind, causality, variability, _unit, start, _lo, _hi, description in self.VARIABLES:
            if causality is Fmi2Causality.output:
                getter = self.output_reader(len(outputs))
                outputs.append(start)
                initial = Fmi2Initial.approx
            else:
                setattr(self, name, start)
                getter = initial = None
            self.register_variable(kind(name, causality=causality, variability=variability, initial=initial,
                                        description=description, getter=getter))
        self.outputs = tuple(outputs)
        self.start_time = 0.0
        self.model = None
        self.problem: str | None = "the FMU is not initialised: exit initialisation mode before stepping"

    # hooks ------------------------------------------------------------------------------------------------------
    def new_model(self, values: dict, fresh: bool):
        """``(model, notices)`` for the parameter values; may keep ``self.model`` when not ``fresh``."""
        raise NotImplementedError

    def step_model(self, current_time: float, step_size: float) -> tuple:
        """The model's outputs after one step (table order); may raise."""
        raise NotImplementedError

    def restore_model(self, data: dict) -> None:
        """Set the model's state from its dict."""
        raise NotImplementedError

    # FMI calls --------------------------------------------------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        self.start_time = float(start_time)

    def exit_initialization_mode(self):
        self.build_model(fresh=True)

    def do_step(self, current_time, step_size):
        if self.problem is not None:
            self.log(printf_safe(f"do_step at t = {current_time!r} s discarded: {self.problem}"), Fmi2Status.discard)
            return False
        try:
            outputs = self.step_model(current_time, step_size)
        except Exception as exc:  # noqa: BLE001 - an escaping exception would be fmi2Fatal
            self.log(printf_safe(f"do_step at t = {current_time!r} s, h = {step_size!r} s discarded: {exc}"),
                     Fmi2Status.discard)
            return False
        self.outputs = outputs
        return True

    def output_reader(self, index):
        """Getter of output ``index`` of the last step (the outputs follow the table)."""
        return lambda: self.outputs[index]

    def _get_fmu_state(self):
        return {"variables": {row[0]: getattr(self, row[0]) for row in self.VARIABLES
                              if row[2] is not Fmi2Causality.output},
                "outputs": list(self.outputs), "start_time": self.start_time, "problem": self.problem,
                "model": None if self.model is None else self.model.state.to_dict()}

    def _set_fmu_state(self, state):
        try:
            for name, value in state["variables"].items():
                setattr(self, name, value)
            self.outputs = tuple(state["outputs"])
            self.start_time = state["start_time"]
            if state["model"] is None:  # saved before initialisation or with invalid parameters
                self.model = None
                self.problem = state["problem"]
                return
            self.build_model(fresh=False)
            if self.model is not None:
                self.restore_model(state["model"])
        except Exception as exc:  # noqa: BLE001 - an escaping exception would be fmi2Fatal
            self.problem = f"the FMU state could not be restored: {exc}"
            self.log(printf_safe(self.problem), Fmi2Status.error)

    # helpers ----------------------------------------------------------------------------------------------------
    def build_model(self, fresh: bool) -> None:
        """(Re)build the model from the parameter variables; keep the problem for do_step when they are invalid."""
        values = {row[0]: getattr(self, row[0]) for row in self.VARIABLES if row[2] is Fmi2Causality.parameter}
        try:
            self.model, notices = self.new_model(values, fresh)
        except Exception as exc:  # noqa: BLE001 - an escaping exception would be fmi2Fatal
            self.model = None
            self.problem = f"invalid parameters: {exc}"
            self.log(printf_safe(f"{self.problem}; every do_step will be discarded"), Fmi2Status.warning)
            return
        self.problem = None
        for notice in notices:
            self.log(printf_safe(notice), Fmi2Status.ok)

    def to_xml(self, model_options=None) -> Element:
        """pythonfmu's model description plus units, bounds, UnitDefinitions and a complete ModelStructure."""
        root = super().to_xml({} if model_options is None else model_options)
        return complete_model_description(root, self.VARIABLES, self.INITIAL_DEPENDENCIES)
