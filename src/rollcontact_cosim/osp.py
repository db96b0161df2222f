"""The libcosim master (Open Simulation Platform, through ``libcosimpy``), for every scene.

:func:`run_osp` runs a scene (:mod:`rollcontact_cosim.scenes`) with libcosim's fixed-step algorithm and returns
the fmpy master's :class:`~rollcontact_cosim.fmus.CosimResult` (``master = "libcosim"``, ``algorithm =
"jacobi"``); ``run_cosimulation(scene, master="libcosim")`` of :mod:`rollcontact_cosim.master` calls it.

System
    :func:`system_structure` writes the scene's system as an ``OspSystemStructure.xml``: both FMUs of the
    integer-codes build (libcosim lists no FMI enumeration variables) by their absolute paths under their instance
    names, every connection of the description, the run's ``BaseStepSize`` and ``StartTime`` (libcosimpy takes
    the step size and the start time only from such a file).  Each run loads one written to a temporary folder.
    The parameters are set with ``CosimExecution.*_initial_value`` (typed by the FMU's variable) before the first
    step, when libcosim applies start values; the host's ``force_lag`` is 1 (Jacobi).
    ``models/cosim/OspSystemStructure.xml`` is the wheel rig's system for libcosim's own tools (sources relative to
    that folder, ``force_lag = 1`` as an initial value).
Algorithm
    Jacobi only: per macro step libcosim steps every FMU from the inputs transferred after the previous step, then
    transfers every connection (it also propagates values in initialisation mode, as many rounds as there are
    FMUs, and once more after leaving it).  The FMU calls run on libcosim's worker threads (hardware threads - 1
    of them, none on one core); pythonfmu takes the GIL in every call, and ctypes releases it while libcosim runs,
    so this works in-process.  The results equal the fmpy master's ``"jacobi"`` up to the time grid: libcosim
    counts integer nanoseconds, so the FMUs see ``t_k = (t0_ns + k H_ns) / 1e9``, which can differ from fmpy's
    ``t_0 + k H`` in the last bit.
Rows
    The time-series observer samples both FMUs after initialisation (step 0) and after every step, so the contact's
    outputs of its step started at t_k are its sample k + 1.  The run takes N + 1 steps and the contact's columns
    are shifted back one row: the row convention of every master (``models/cosim/README.md``).
Pitfalls
    libcosim's log level is process-wide and its default (debug) floods stderr; :func:`run_osp` sets
    ``log_level``.  libcosim instantiates the FMUs with logging on and prints an FMU's Error message (an invalid
    parameter, an emulated fmi2Error) at its error level, shown at the default WARNING; a Discard stops the execution
    with only "<instance>: Step not complete" and the FMU's own message at DEBUG level, so the result's message
    says how to get it (docs/fmu.md, "Why a step is refused").
"""

from __future__ import annotations

import tempfile
import time
import xml.etree.ElementTree as ET
from ctypes import POINTER, c_double, c_int, c_int64, c_size_t, c_uint32
from pathlib import Path

import numpy as np
from libcosimpy._internal import get_last_error_message, libcosimc, wrap_function  # libcosimc's functions
from libcosimpy.CosimEnums import CosimVariableCausality, CosimVariableType
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
from libcosimpy.CosimObserver import CosimObserver

from rollcontact_cosim.fmus import FMU_DIR, CosimResult, ensure_fmus
from rollcontact_cosim.scenes import COSIM_DIR, CosimScene, System, check_algorithm, load_cosim_scene, macro_steps

__all__ = ["OSP_CONFIG", "run_osp", "system_structure"]

OSP_CONFIG = COSIM_DIR / "OspSystemStructure.xml"
"""The wheel rig's system for libcosim's own tools (:func:`system_structure` of the wheel rig scenes)."""
NAMESPACE = "http://opensimulationplatform.com/MSMI/OSPSystemStructure"
NS_PER_S = 1_000_000_000
INITIAL_VALUE = {  # FMU variable type -> CosimExecution setter, Python type
    CosimVariableType.REAL: ("real_initial_value", float),
    CosimVariableType.INTEGER: ("integer_initial_value", int),
    CosimVariableType.BOOLEAN: ("boolean_initial_value", bool),
    CosimVariableType.STRING: ("string_initial_value", str),
}


def run_osp(scene: str | Path | CosimScene, step_size: float | None = None, *, algorithm: str | None = None,
            stop_time: float | None = None, host: dict | None = None, contact: dict | None = None,
            fmu_dir: Path | str | None = None, build: bool = True,
            log_level: CosimLogLevel = CosimLogLevel.WARNING) -> CosimResult:
    """Co-simulate a scene with libcosim's fixed-step (Jacobi) algorithm.

    Parameters
    ----------
    scene : str, Path or CosimScene
        Scene name (``"traction_ramp"``), TOML path or loaded scene.
    step_size, stop_time : float, optional
        Macro step H [s] (a whole number of nanoseconds) and end time [s] replacing the scene's.
    algorithm : str, optional
        None or ``"jacobi"`` (the scene's algorithm does not apply: libcosim's fixed-step algorithm is Jacobi).
    host, contact : dict, optional
        Parameter values applied over :meth:`CosimScene.host_parameters` for Jacobi (``force_lag = 1``) and
        :meth:`CosimScene.contact_parameters`.
    fmu_dir : Path, optional
        Folder whose ``integer_codes/`` folder holds (or gets) the FMUs; ``models/`` when None.
    build : bool
        Build the FMUs first where they are missing or stale; False where the caller did.
    log_level : CosimLogLevel
        libcosim's log level, set for the whole process.

    Returns
    -------
    CosimResult
        ``values`` follows the fmpy master's row convention; ``wall_time`` is the stepping (N + 1 libcosim steps,
        observer included); ``success`` is False when an FMU refused a step (``values`` then ends at the last
        complete row).

    Raises
    ------
    ValueError
        Gauss-Seidel requested, or a step that is not a whole number of nanoseconds.
    KeyError
        A parameter or recorded output the FMUs do not have (the message lists the choices).
    RuntimeError
        libcosim cannot load the system or refuses a parameter value.
    """
    scene = load_cosim_scene(scene)
    if algorithm is not None and check_algorithm(algorithm) != "jacobi":
        raise ValueError(f"algorithm = {algorithm!r}: libcosim's fixed-step algorithm is Jacobi; use 'jacobi' "
                         f"(or the fmpy master for Gauss-Seidel)")
    step = scene.step_size if step_size is None else float(step_size)
    stop = scene.stop_time if stop_time is None else float(stop_time)
    steps = macro_steps(scene.start_time, stop, step)
    step_ns = round(step * NS_PER_S)
    if abs(step * NS_PER_S - step_ns) > 1e-6 * step_ns:
        raise ValueError(f"step_size = {step!r} s is not a whole number of nanoseconds (libcosim's time unit)")
    system = scene.system.variant(fmi_version=2, integer_codes=True)  # libcosim lists no FMI enumerations
    start_values = {system.host.name: {**scene.host_parameters("jacobi"), **(host or {})},
                    system.contact.name: {**scene.contact_parameters(), **(contact or {})}}
    fmu_dir = FMU_DIR if fmu_dir is None else fmu_dir
    fmus = ensure_fmus(fmu_dir, system=system) if build else system.fmus(fmu_dir)
    log_output_level(log_level)
    with tempfile.TemporaryDirectory(prefix="rollcontact_osp_") as folder:
        config = Path(folder) / "OspSystemStructure.xml"
        system_structure(system, {name: path.resolve().as_uri() for name, path in fmus.items()}, scene.start_time,
                         step).write(config, encoding="utf-8", xml_declaration=True)
        try:
            execution = CosimExecution.from_osp_config_file(str(config))
        except AssertionError as exc:  # libcosimpy's way of reporting a failed load
            raise RuntimeError(f"libcosim cannot load the system of {scene.name} (FMUs {fmus}): {exc}") from None
    try:
        return simulate(execution, scene, start_values, step, step_ns, steps)
    finally:
        del execution  # frees the FMU instances and libcosim's worker threads now, not at garbage collection


def system_structure(system: System, sources: dict[str, str], start_time: float, step: float,
                     initial_values: dict[str, dict[str, int]] | None = None) -> ET.ElementTree:
    """The ``OspSystemStructure.xml`` of ``system``: its instances with their FMUs' ``sources`` (instance name ->
    URI or path relative to the file), every connection, ``StartTime`` ``start_time`` [s], ``BaseStepSize`` ``step``
    [s], libcosim's fixed-step algorithm, and Integer ``initial_values`` (instance -> variable -> value)."""
    ET.register_namespace("", NAMESPACE)
    root = ET.Element(f"{{{NAMESPACE}}}OspSystemStructure", version="0.1")
    for tag, text in (("StartTime", repr(float(start_time))), ("BaseStepSize", repr(float(step))),
                      ("Algorithm", "fixedStep")):
        ET.SubElement(root, f"{{{NAMESPACE}}}{tag}").text = text
    simulators = ET.SubElement(root, f"{{{NAMESPACE}}}Simulators")
    for instance in (system.host, system.contact):
        simulator = ET.SubElement(simulators, f"{{{NAMESPACE}}}Simulator", name=instance.name,
                                  source=sources[instance.name])
        values = (initial_values or {}).get(instance.name, {})
        if values:
            initial = ET.SubElement(simulator, f"{{{NAMESPACE}}}InitialValues")
            for variable, value in values.items():
                element = ET.SubElement(initial, f"{{{NAMESPACE}}}InitialValue", variable=variable)
                ET.SubElement(element, f"{{{NAMESPACE}}}Integer", value=str(int(value)))
    connections = ET.SubElement(root, f"{{{NAMESPACE}}}Connections")
    for link in system.connections:
        connection = ET.SubElement(connections, f"{{{NAMESPACE}}}VariableConnection")
        for end in link:
            instance, variable = end.split(".", 1)
            ET.SubElement(connection, f"{{{NAMESPACE}}}Variable", simulator=instance, name=variable)
    ET.indent(root, space="    ")
    return ET.ElementTree(root)


def set_start_values(execution: CosimExecution, start_values: dict[str, dict]) -> tuple[dict, dict]:
    """Set each instance's start values by variable name (``{instance: {variable: value}}``); returns the slave
    index of each instance and its variables by name.  RuntimeError naming what libcosim refused."""
    index = {name: execution.slave_index_from_instance_name(name) for name in start_values}
    variables = {name: {v.name.decode(): v for v in execution.slave_variables(i)} for name, i in index.items()}
    for name, values in start_values.items():
        for variable, value in values.items():
            v = lookup(variables[name], name, variable, CosimVariableCausality.PARAMETER)
            setter, kind = INITIAL_VALUE[CosimVariableType(v.type)]
            if not getattr(execution, setter)(index[name], v.reference, kind(value)):
                raise RuntimeError(f"libcosim refused {name}.{variable} = {value!r}: {get_last_error_message()}")
    return index, variables


def simulate(execution: CosimExecution, scene: CosimScene, start_values: dict[str, dict], step: float, step_ns: int,
             steps: int) -> CosimResult:
    """Set the start values, record, take N + 1 steps and assemble the result rows (see the module docstring)."""
    index, variables = set_start_values(execution, start_values)
    observer = CosimObserver.create_time_series(buffer_size=steps + 2)  # every sample: the default keeps 10000
    execution.add_observer(observer)
    recorded = []  # (column, instance, variable description)
    for output in scene.outputs:
        name, variable = output.split(".", 1)
        v = lookup(variables[name], name, variable, CosimVariableCausality.OUTPUT)
        observer.start_time_series(index[name], v.reference, CosimVariableType(v.type))
        recorded.append((output, name, v))

    start = time.perf_counter()
    success = execution.step(steps + 1)
    wall = time.perf_counter() - start
    start_ns = round(scene.start_time * NS_PER_S)
    done, late = divmod(execution.status().current_time - start_ns, step_ns)  # macro steps completed
    if late or done > steps + 1 or success != (done == steps + 1):
        raise RuntimeError(f"libcosim reached t = {execution.status().current_time} ns after {steps + 1} steps of "
                           f"{step_ns} ns from {start_ns} ns (success: {success})")
    message = "completed"
    if not success:
        message = (f"{get_last_error_message().strip()} in the macro step from t = {scene.start_time + done * step!r}"
                   f" s (libcosim logs the FMU's reason at DEBUG level: rerun with "
                   f"log_level=CosimLogLevel.DEBUG, or with the fmpy master)")
    rows = done  # row k needs the host's sample k and the contact's sample k + 1
    values = np.empty(rows, dtype=[("time", float)] + [(output, float) for output in scene.outputs])
    values["time"] = scene.start_time + np.arange(rows) * step  # as the fmpy master
    for output, name, v in recorded:
        shift = 1 if name == scene.system.contact.name else 0
        values[output] = samples(observer, index[name], v, rows + shift)[shift:]
    return CosimResult(scene.name, "libcosim", "jacobi", step, values, steps if success else rows, wall, success,
                       message)


def lookup(variables: dict, instance: str, name: str, causality: CosimVariableCausality):
    """The variable description of ``instance.name`` with ``causality``; KeyError listing the choices."""
    v = variables.get(name)
    if v is None or v.causality != causality.value:
        choices = [n for n, w in variables.items() if w.causality == causality.value]
        raise KeyError(f"{instance} has no {causality.name.lower()} {name!r} (choices: {', '.join(choices)})")
    return v


def samples(observer: CosimObserver, index: int, variable, count: int) -> np.ndarray:
    """Observed values of steps 0 .. count - 1 of one variable.

    libcosimc is called directly: libcosimpy's ``time_series_*_samples`` trims its arrays at the number of step
    numbers that are not 0, which drops the last sample of any read that includes step 0.
    """
    kind = c_int if variable.type == CosimVariableType.INTEGER.value else c_double
    read = wrap_function(libcosimc(), f"cosim_observer_slave_get_{'integer' if kind is c_int else 'real'}_samples",
                         restype=c_int64, argtypes=[POINTER(CosimObserver), c_int, c_uint32, c_int64, c_size_t,
                                                    POINTER(kind), POINTER(c_int64), POINTER(c_int64)])
    values, steps, times = (kind * count)(), (c_int64 * count)(), (c_int64 * count)()
    got = read(observer.ptr(), index, variable.reference, 0, count, values, steps, times)
    if got != count or list(steps) != list(range(count)):
        raise RuntimeError(f"libcosim's observer returned {got} samples of steps {list(steps[:max(got, 0)])} for "
                           f"{variable.name.decode()}, expected steps 0..{count - 1}: {get_last_error_message()}")
    return np.array(values, dtype=float)
