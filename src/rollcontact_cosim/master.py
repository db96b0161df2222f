"""The fixed-step co-simulation master on fmpy's ``FMU2Slave`` (or ``FMU3Slave``), for every scene.

:func:`run_cosimulation` runs a scene (:mod:`rollcontact_cosim.scenes`: its system of a host and a contact FMU,
their parameters and connections) with macro step H from t_0 to t_end = t_0 + N H (communication points
``t_n = t_0 + n H``, never accumulated) and returns a :class:`CosimResult`.  Algorithms (``[run] algorithm``):

* ``"gauss-seidel"`` (default): per macro step the contact is stepped first with the host's outputs at t_n, then
  the host with the contact's fresh forces and their derivatives (creep stiffness, Jacobian), i.e. the host
  integrates with ``F(c(t_n))``.  For a quasi-static contact this is the explicit Euler coupling without extra
  delay: the most accurate ordering, and for explicit coupling stable up to twice the step of Jacobi.
* ``"jacobi"``: both FMUs step from the outputs of t_n; the host's forces are then the ones the contact computed
  in the previous macro step, ``F(c(t_(n-1)))`` (and the contact's start values in the first step).  This is
  libcosim's fixed-step algorithm, used to compare the two masters.

The host's ``force_lag`` follows the algorithm (:meth:`~rollcontact_cosim.scenes.CosimScene.host_parameters`).
Result rows: row k holds ``t_k``, the host's outputs at t_k and the contact's outputs of its step started at t_k
(evaluated with the host's outputs at t_k); the contact is stepped once more at t_N to complete the last row.

The FMUs are taken from ``models/`` (or ``fmu_dir``), each built first when missing or older than its sources
(:func:`~rollcontact_cosim.fmus.ensure_fmus`).  ``fmi_version=3`` runs the FMI 3.0 FMUs of ``models/fmi3/``
through fmpy's ``FMU3Slave`` behind the same calls (:class:`FMU3Calls`): the same results bit for bit.
"""

from __future__ import annotations

import atexit
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.fmi3 import FMU3Slave

from rollcontact_cosim.fmus import FMU_DIR, CosimResult, ensure_fmus, summarise
from rollcontact_cosim.scenes import CosimScene, check_algorithm, check_fmi_version, load_cosim_scene, macro_steps

__all__ = ["FMU_DIR", "MASTERS", "CosimResult", "ensure_fmus", "ensure_scene_fmus", "run_cosimulation", "summarise"]

MASTERS = ("fmpy", "libcosim")
STATUS = {0: "OK", 1: "Warning", 2: "Discard", 3: "Error", 4: "Fatal", 5: "Pending"}
REAL_TYPES = ("Real", "Float64")
INTEGER_TYPES = ("Integer", "Enumeration", "Int32", "Int64")
"""fmpy's variable types (FMI 2.0 and 3.0) read as floats and as integers."""


_extracted: dict[tuple[str, float], str] = {}


def extracted(fmu: Path) -> str:
    """The FMU unzipped in a temporary folder, once per file version and process (removed at exit)."""
    key = (str(fmu.resolve()), fmu.stat().st_mtime)
    if key not in _extracted:
        folder = tempfile.mkdtemp(prefix=f"rollcontact_cosim_{fmu.stem}_")
        atexit.register(shutil.rmtree, folder, ignore_errors=True)
        _extracted[key] = extract(str(fmu), unzipdir=folder)
    return _extracted[key]


class FMU3Calls(FMU3Slave):
    """fmpy's ``FMU3Slave`` answering the ``FMU2Slave`` calls the master makes: Float64 as Real, Int32 and
    Enumeration (Int64) as Integer, ``setupExperiment``'s start time passed on by ``enterInitializationMode``."""

    def __init__(self, description, **kwargs):
        super().__init__(**kwargs)
        self.enumerations = {v.valueReference for v in description.modelVariables if v.type == "Enumeration"}
        self.start_time = 0.0

    setReal, getReal = FMU3Slave.setFloat64, FMU3Slave.getFloat64
    getFMUstate, setFMUstate, freeFMUstate = FMU3Slave.getFMUState, FMU3Slave.setFMUState, FMU3Slave.freeFMUState
    serializeFMUstate, deSerializeFMUstate = FMU3Slave.serializeFMUState, FMU3Slave.deserializeFMUState

    def setInteger(self, vr, values) -> None:
        for ref, value in zip(vr, values, strict=True):
            (self.setInt64 if ref in self.enumerations else self.setInt32)([ref], [value])

    def getInteger(self, vr) -> list[int]:
        if all(ref in self.enumerations for ref in vr):
            return self.getInt64(vr)
        return [(self.getInt64 if ref in self.enumerations else self.getInt32)([ref])[0] for ref in vr]

    def setupExperiment(self, startTime: float = 0.0, **_) -> None:
        self.start_time = startTime

    def enterInitializationMode(self, tolerance=None, startTime=None, stopTime=None):
        return super().enterInitializationMode(tolerance, self.start_time if startTime is None else startTime,
                                               stopTime)


class Slave:
    """One instantiated FMU (FMI 2.0 or 3.0) with name lookup and its log kept (the last messages explain a
    Discard); ``fmu`` answers the ``FMU2Slave`` calls in either version.

    Logging is on for every category: the refusals' ``logStatusDiscard`` and ``logStatusError`` reach :meth:`logger`
    (pythonfmu 0.7 passes nothing without debug logging), and so do pythonfmu's own fmi2Fatal messages, which carry
    no category and which a category list (``fmi2SetDebugLogging``) would drop (docs/fmu.md, "Why a step is
    refused")."""

    def __init__(self, fmu: Path, instance_name: str):
        unzipped = extracted(fmu)
        self.description = read_model_description(unzipped)
        self.variables = {v.name: v for v in self.description.modelVariables}
        self.name = instance_name
        self.log: list[str] = []
        if self.description.fmiVersion.startswith("3"):
            self.fmu = FMU3Calls(self.description, guid=self.description.guid, unzipDirectory=unzipped,
                                 modelIdentifier=self.description.coSimulation.modelIdentifier,
                                 instanceName=instance_name)
            self.fmu.instantiate(loggingOn=True, logMessage=self.logger3)
            return
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.logger = fmi2CallbackLoggerTYPE(self.logger)  # referenced here so ctypes keeps it alive
        self.callbacks.allocateMemory = defaultCallbacks.allocateMemory
        self.callbacks.freeMemory = defaultCallbacks.freeMemory
        self.fmu = FMU2Slave(guid=self.description.guid, unzipDirectory=unzipped,
                             modelIdentifier=self.description.coSimulation.modelIdentifier, instanceName=instance_name)
        self.fmu.instantiate(callbacks=self.callbacks, loggingOn=True)

    def logger(self, environment, instance_name, status, category, message):
        self.log.append(f"{STATUS.get(status, status)}: {message.decode(errors='replace').replace('%%', '%')}")
        del self.log[:-20]

    def logger3(self, environment, status, category, message):
        """FMI 3.0's logger: the message as it is (no printf format)."""
        self.log.append(f"{STATUS.get(status, status)}: {message.decode(errors='replace')}")
        del self.log[:-20]

    def reference(self, name: str, causality: str | None = None) -> int:
        """Value reference of variable ``name`` (with the given causality); KeyError naming the choices."""
        v = self.variables.get(name)
        if v is None or (causality is not None and v.causality != causality):
            choices = [n for n, w in self.variables.items() if causality is None or w.causality == causality]
            raise KeyError(f"{self.name} has no {causality or 'variable'} {name!r} (choices: {', '.join(choices)})")
        return v.valueReference

    def set_start_values(self, values: dict) -> None:
        """Set parameters by name (KeyError naming the parameters for an unknown one)."""
        for name, value in values.items():
            vr = self.reference(name, "parameter")
            kind = self.variables[name].type
            if kind in REAL_TYPES:
                self.fmu.setReal([vr], [float(value)])
            elif kind in INTEGER_TYPES:
                if isinstance(value, bool) or value != int(value):
                    raise ValueError(f"{self.name}.{name} is an Integer parameter, got {value!r}")
                self.fmu.setInteger([vr], [int(value)])
            else:
                self.fmu.setString([vr], [str(value)])

    def initialise(self, start_time: float = 0.0) -> None:
        """setupExperiment at ``start_time`` [s], then enter and exit initialisation mode: ready to step."""
        self.fmu.setupExperiment(startTime=start_time)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def free(self) -> None:
        try:
            self.fmu.terminate()
        except FMICallException:  # a Discarded instance may refuse; it is freed anyway
            pass
        self.fmu.freeInstance()


def run_cosimulation(scene: str | Path | CosimScene, master: str = "fmpy", algorithm: str | None = None,
                     step_size: float | None = None, stop_time: float | None = None, host: dict | None = None,
                     contact: dict | None = None, fmu_dir: Path | str | None = None, fmi_version: int | None = None,
                     build: bool = True) -> CosimResult:
    """Co-simulate a scene with a fixed macro step.

    Parameters
    ----------
    scene : str, Path or CosimScene
        Scene name (``"traction_ramp"``), TOML path or loaded scene.
    master : str
        ``"fmpy"`` (this module) or ``"libcosim"`` (:func:`rollcontact_cosim.osp.run_osp`, same arguments; Jacobi
        only, so ``algorithm`` None means Jacobi there).
    algorithm : str, optional
        ``"gauss-seidel"`` or ``"jacobi"``; the scene's when None.
    step_size, stop_time : float, optional
        Macro step H [s] and end time [s] replacing the scene's; ``(stop_time - start_time) / H`` must be whole.
    host, contact : dict, optional
        Parameter values applied over the scene's host and contact parameters (e.g. ``{"coupling": 0}``).
    fmu_dir : Path, optional
        Folder with (or for) the FMUs; ``models/`` when None.
    fmi_version : int, optional
        2: the FMI 2.0 FMUs of ``fmu_dir``; 3: the FMI 3.0 FMUs of ``fmu_dir/fmi3`` (fmpy master only: libcosim
        loads FMI 2.0 FMUs only); the scene's when None.
    build : bool
        Build the FMUs first where they are missing or stale (:func:`~rollcontact_cosim.fmus.ensure_fmus`); False
        where the caller did (the workers of a sweep).

    Returns
    -------
    CosimResult
        ``success`` is False when an FMU answered a step with Discard (the log message is in ``message``).
    """
    scene = load_cosim_scene(scene)
    if master not in MASTERS:
        raise ValueError(f"master = {master!r} is unknown: use one of {', '.join(MASTERS)}")
    if master == "libcosim":  # Jacobi only, whatever the scene says
        if fmi_version is not None and check_fmi_version(fmi_version) == 3:
            raise ValueError("the libcosim master runs the FMI 2.0 FMUs only (libcosim cannot load FMI 3.0 FMUs): "
                             "use the fmpy master for FMI 3.0")
        from rollcontact_cosim import osp

        return osp.run_osp(scene, step_size, algorithm=algorithm, stop_time=stop_time, host=host, contact=contact,
                           fmu_dir=fmu_dir, build=build)
    algorithm = scene.algorithm if algorithm is None else check_algorithm(algorithm)
    step = scene.step_size if step_size is None else float(step_size)
    stop = scene.stop_time if stop_time is None else float(stop_time)
    steps = macro_steps(scene.start_time, stop, step)
    system = scene.system.variant(fmi_version)
    start_values = {system.host.name: {**scene.host_parameters(algorithm), **(host or {})},
                    system.contact.name: {**scene.contact_parameters(), **(contact or {})}}
    fmu_dir = FMU_DIR if fmu_dir is None else fmu_dir
    paths = ensure_fmus(fmu_dir, system=system) if build else system.fmus(fmu_dir)
    slaves = {}
    try:
        for instance in (system.host, system.contact):
            slaves[instance.name] = Slave(paths[instance.name], instance.name)
            slaves[instance.name].set_start_values(start_values[instance.name])
        for slave in slaves.values():
            slave.initialise(scene.start_time)
        return step_loop(scene, slaves, algorithm, step, steps)
    finally:
        for slave in slaves.values():
            slave.free()


def ensure_scene_fmus(scene: str | Path | CosimScene, master: str = "fmpy", fmu_dir: Path | str | None = None,
                      fmi_version: int | None = None) -> dict[str, Path]:
    """Build the FMUs that runs of ``scene`` through ``master`` take from ``fmu_dir`` (``models/`` when None) where
    they are missing or stale, before runs with ``build=False`` (a sweep's workers); their paths by instance name.
    libcosim takes the FMI 2.0 integer-codes build (:func:`rollcontact_cosim.osp.run_osp`)."""
    variant = {"integer_codes": True, "fmi_version": 2} if master == "libcosim" else {"fmi_version": fmi_version}
    return ensure_fmus(FMU_DIR if fmu_dir is None else fmu_dir, system=load_cosim_scene(scene).system, **variant)


def step_loop(scene: CosimScene, slaves: dict[str, Slave], algorithm: str, step: float, steps: int) -> CosimResult:
    """The macro-step loop of :func:`run_cosimulation` on initialised slaves."""
    host, contact = slaves[scene.system.host.name], slaves[scene.system.contact.name]
    # per FMU one getReal of [connection sources..., recorded reals...] and one getInteger of recorded integers
    wiring = {host.name: ([], []), contact.name: ([], [])}  # instance -> (source vrs, target vrs of the other)
    for source, target in scene.system.connections:
        s_instance, s_name = source.split(".", 1)
        t_instance, t_name = target.split(".", 1)
        wiring[s_instance][0].append(slaves[s_instance].reference(s_name, "output"))
        wiring[s_instance][1].append(slaves[t_instance].reference(t_name, "input"))
    reals = {name: list(sources) for name, (sources, _) in wiring.items()}
    integers: dict[str, list[int]] = {host.name: [], contact.name: []}
    columns = []  # (instance, is_integer, position in that read)
    for name in scene.outputs:
        instance, variable = name.split(".", 1)
        vr = slaves[instance].reference(variable, "output")
        kind = slaves[instance].variables[variable].type
        integer = kind in INTEGER_TYPES
        target = integers[instance] if integer else reals[instance]
        columns.append((instance, integer, len(target)))
        target.append(vr)
    n_host = len(wiring[host.name][0])
    n_contact = len(wiring[contact.name][0])
    to_contact, to_host = wiring[host.name][1], wiring[contact.name][1]
    rows = np.empty((steps + 1, 1 + len(columns)))
    t0 = scene.start_time
    jacobi = algorithm == "jacobi"
    host_reals = host.fmu.getReal(reals[host.name])
    host_integers = host.fmu.getInteger(integers[host.name]) if integers[host.name] else []
    contact_sources = contact.fmu.getReal(wiring[contact.name][0])  # start values: Jacobi's first host step
    message, success, n, stepping, complete = "completed", True, 0, contact, 0
    start = time.perf_counter()
    try:
        for n in range(steps + 1):
            t = t0 + n * step
            contact.fmu.setReal(to_contact, host_reals[:n_host])
            if jacobi:
                host.fmu.setReal(to_host, contact_sources)
            stepping = contact
            contact.fmu.doStep(t, step)
            contact_reals = contact.fmu.getReal(reals[contact.name])
            contact_integers = contact.fmu.getInteger(integers[contact.name]) if integers[contact.name] else []
            record(rows[n], t, columns, {host.name: (host_reals, host_integers),
                                         contact.name: (contact_reals, contact_integers)})
            complete = n + 1
            if n == steps:
                break
            contact_sources = contact_reals[:n_contact]
            if not jacobi:
                host.fmu.setReal(to_host, contact_sources)
            stepping = host
            host.fmu.doStep(t, step)
            host_reals = host.fmu.getReal(reals[host.name])
            if integers[host.name]:
                host_integers = host.fmu.getInteger(integers[host.name])
    except FMICallException as exc:
        success = False
        message = (f"{stepping.name}: {exc.function} failed with status {STATUS.get(exc.status, exc.status)} at "
                   f"t = {t0 + n * step!r} s; its last log message: {stepping.log[-1] if stepping.log else '(none)'}")
    wall = time.perf_counter() - start
    dtype = [("time", float)] + [(name, float) for name in scene.outputs]
    values = np.rec.fromarrays(rows[:complete].T, dtype=dtype).view(np.ndarray) if complete else np.empty(0, dtype)
    return CosimResult(scene.name, "fmpy", algorithm, step, values, n if not success else steps, wall, success,
                       message)


def record(row: np.ndarray, t: float, columns, reads) -> None:
    """Fill ``row`` with t and the recorded values (columns: instance, is_integer, position in that read)."""
    row[0] = t
    for j, (instance, is_integer, position) in enumerate(columns, start=1):
        row[j] = reads[instance][1 if is_integer else 0][position]
