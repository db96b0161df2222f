"""The FMI 3.0 FMUs against their FMI 2.0 twins: one contract, tested on both versions (the ``fmi`` fixture).

Both versions are the same slave classes (``fmu_src/rollcontact_fmu/fmi3.py``): the same variables, value references,
units, ranges and enumerations (declared each version's way), the same Discard with a logged reason for a bad input
or parameter, the same refusals where FMI wants an error (logged with status Error, then every step discarded until
a valid state is set), state get/set/serialise, independent instances, and the same outputs bit for bit.  What
differs: FMI 3.0's types (Float64, Int32, Enumeration), the independent variable ``time``, the start time taken
from the first ``fmi3DoStep``, and log messages that reach the host without debug logging.  All four FMUs pass
``fmpy validate`` and ``fmutool -check`` (fmu_manipulation_toolbox).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmu_checks import assert_fmu_is_valid

ROOT = Path(__file__).resolve().parents[2]
VERSIONS = (2, 3)
DISCARD, ERROR, FATAL = 2, 3, 4
H = 1e-3
ROW = (1e5, 1e-3, 20.0)  # normal load [N], creep, speed [m/s]
INPUTS = ("normal_load", "creep", "velocity")
MODELS = ("RollingContact2D", "WheelRig", "Wheelset", "RollingContact3D", "WheelsetContact")


def step(slave, t: float, h: float, *inputs, names=INPUTS) -> list[float]:
    """Set the inputs, step and read every output (integers as floats), in the table's order."""
    slave.fmu.setReal([slave.reference(n) for n in names], list(inputs))
    slave.fmu.doStep(t, h)
    return outputs(slave)


def outputs(slave) -> list[float]:
    values = []
    for v in slave.description.modelVariables:
        if v.causality == "output":
            read = slave.fmu.getReal if v.type in ("Real", "Float64") else slave.fmu.getInteger
            values.append(float(read([v.valueReference])[0]))
    return values


def refused_step(slave, *args, status: int = DISCARD, **kwargs) -> str:
    """Step expecting ``status``; the message logged with it."""
    before = len(slave.log)
    with pytest.raises(FMICallException) as caught:
        step(slave, *args, **kwargs)
    assert caught.value.status == status, f"{args}: status {caught.value.status}, expected {status}"
    logged = slave.log[before:] or slave.log[-1:]
    label = {DISCARD: "Discard", ERROR: "Error"}[status]
    assert logged and logged[-1].startswith(f"{label}: "), f"{args}: the reason must be logged as {label}: {logged}"
    return logged[-1].split(": ", 1)[1]


def errors(slave, since: int) -> list[str]:
    return [m.split(": ", 1)[1] for m in slave.log[since:] if m.startswith("Error: ")]


def saved(slave) -> bytes:
    state = slave.fmu.getFMUstate()
    try:
        return bytes(slave.fmu.serializeFMUstate(state))
    finally:
        slave.fmu.freeFMUstate(state)


def restore(slave, data: bytes) -> None:
    state = slave.fmu.deSerializeFMUstate(data)
    try:
        slave.fmu.setFMUstate(state)
    finally:
        slave.fmu.freeFMUstate(state)


# the model descriptions ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("model", MODELS)
def test_every_fmu_passes_fmpy_validate_and_fmutool_check(fmu_folders, fmi, model):
    assert_fmu_is_valid(fmu_folders[fmi] / f"{model}.fmu", fmi)


@pytest.mark.parametrize("model", MODELS)
def test_fmi3_declares_the_same_variables_the_fmi3_way(fmu_folders, model):
    """Per table row: the same name, causality, variability, description, start, unit and bounds; Real -> Float64,
    Integer -> Int32, an enumeration -> Enumeration of the same type and items; units with the same base units; plus
    one independent variable, ``time``, at the value reference it was released with (``TIME_REFERENCE``: after the
    last row, or before the rows appended since), the rows from it on one value reference further than in FMI 2.0;
    state handling and variable steps declared."""
    two, three = (read_model_description(str(fmu_folders[v] / f"{model}.fmu")) for v in VERSIONS)
    assert (two.fmiVersion, three.fmiVersion) == ("2.0", "3.0")
    variables3 = {v.name: v for v in three.modelVariables}
    independent = [v for v in three.modelVariables if v.causality == "independent"]
    time = {"RollingContact3D": 39, "Wheelset": 56}.get(model, len(two.modelVariables))
    assert [(v.name, v.valueReference, v.unit) for v in independent] == [("time", time, "s")]
    assert len(three.modelVariables) == len(two.modelVariables) + 1
    types2 = {t.name: [(i.name, i.value) for i in t.items] for t in two.typeDefinitions}
    types3 = {t.name: [(i.name, i.value) for i in t.items] for t in three.typeDefinitions}
    assert types3 == types2, "the same enumeration types and items"
    expected_type = {"Real": "Float64", "Integer": "Int32", "Enumeration": "Enumeration", "String": "String"}
    for v2 in two.modelVariables:
        v3 = variables3[v2.name]
        assert v3.type == expected_type[v2.type], f"{v2.name}: {v2.type} became {v3.type}"
        reference = v2.valueReference + (v2.valueReference >= time)
        assert v3.valueReference == reference, f"{v2.name}: value reference {v3.valueReference}, not {reference}"
        for field in ("causality", "variability", "initial", "description", "unit", "min", "max"):
            assert getattr(v3, field) == getattr(v2, field), f"{v2.name}.{field}: {getattr(v3, field)!r}"
        start = float if v2.type == "Real" else (str if v2.type == "String" else int)
        assert start(v3.start) == start(v2.start), f"{v2.name}: start {v3.start!r} against {v2.start!r}"
        if v2.declaredType is not None:
            assert v3.declaredType.name == v2.declaredType.name
    from fmpy.model_description import BaseUnit

    def units(description):  # no BaseUnit (FMI 2.0's "1") is an empty one (FMI 3.0's)
        fields = ("kg", "m", "s", "A", "K", "mol", "cd", "rad", "factor", "offset")
        return {u.name: [getattr(u.baseUnit or BaseUnit(), f) for f in fields] for u in description.unitDefinitions}

    assert {k: v for k, v in units(three).items() if k in units(two)} == units(two), "the same units"
    assert [(u.variable.name, u.dependencies) for u in three.outputs] == \
        [(u.variable.name, u.dependencies) for u in two.outputs], "outputs depend on no input in both"
    caps = three.coSimulation
    assert caps.canGetAndSetFMUstate and caps.canSerializeFMUstate and caps.canHandleVariableCommunicationStepSize


# the same behaviour -------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("inputs, reason", [((-1.0, 1e-3, 20.0), "normal_load = -1.0 N is out of range"),
                                            ((1e5, math.nan, 20.0), "creep = nan is not finite")])
def test_a_bad_input_is_discarded_with_the_reason_and_a_restored_state_steps_on(make, fmi, inputs, reason):
    slave = make(fmi)
    good = saved(slave)
    assert reason in refused_step(slave, 0.0, H, *inputs)
    restore(slave, good)
    assert step(slave, 0.0, H, *ROW) == step(make(fmi), 0.0, H, *ROW), "after the restore it steps normally"


def test_invalid_parameters_are_logged_as_an_error_and_every_step_is_discarded(make, fmi):
    slave = make(fmi, friction_coefficient=-0.1)
    assert any("exitInitializationMode: invalid parameters: friction_coefficient = -0.1" in m
               for m in errors(slave, 0)), slave.log
    for n in range(2):
        assert "friction_coefficient = -0.1" in refused_step(slave, n * H, H, *ROW)


def test_state_get_set_and_serialise_continue_identically_in_another_instance(make, fmi):
    slave = make(fmi, initial_position=0.1)
    rows = [(1e5, 1e-3, 20.0), (1.2e5, 2e-3, 21.0), (9e4, -1e-3, 22.0), (1e5, 5e-4, 19.0)]
    for n, row in enumerate(rows[:2]):
        step(slave, n * H, H, *row)
    data = saved(slave)
    first = [step(slave, (2 + n) * H, H, *row) for n, row in enumerate(rows[2:])]
    restore(slave, data)
    assert [step(slave, (2 + n) * H, H, *row) for n, row in enumerate(rows[2:])] == first, "restore, step again"
    other = make(fmi, radius=0.3)  # other parameters: the state brings its own
    restore(other, data)
    assert [step(other, (2 + n) * H, H, *row) for n, row in enumerate(rows[2:])] == first, "in another instance"


@pytest.mark.parametrize("change, reason", [
    (lambda data: b"", "is not UTF-8 JSON"),
    (lambda data: data[: len(data) // 2], "is not UTF-8 JSON"),
    (lambda data: data.replace(b'"version": 1', b'"version": 9'), "does not match its checksum"),
])
def test_an_invalid_state_is_refused_and_the_instance_keeps_its_state(make, fmi, change, reason):
    slave = make(fmi)
    step(slave, 0.0, H, *ROW)
    good, before = saved(slave), len(slave.log)
    restore(slave, change(good))
    logged = errors(slave, before)
    assert logged and "setFMUstate refused" in logged[0].replace("setFMUState", "setFMUstate") and \
        reason in logged[0], slave.log[before:]
    assert "error state" in refused_step(slave, H, H, *ROW)
    restore(slave, good)
    step(slave, H, H, *ROW)


def test_late_parameters_outputs_and_unknown_references_are_refused(make, fmi):
    slave = make(fmi)
    step(slave, 0.0, H, *ROW)
    before = len(slave.log)
    slave.set_start_values({"radius": 0.2})
    slave.fmu.setReal([slave.reference("tangential_force")], [1.0])
    assert math.isnan(slave.fmu.getReal([10_000])[0]), "an unknown value reference reads NaN"
    logged = errors(slave, before)
    assert len(logged) == 3 and "radius = 0.2 refused" in logged[0] and "is an output" in logged[1], logged
    assert slave.fmu.getReal([slave.reference("radius")]) == [0.46], "the value in force stays"
    assert "radius = 0.2 refused" in refused_step(slave, H, H, *ROW)


def test_two_instances_are_independent_and_both_versions_agree(make, fmi):
    rows = [(1e5, 1e-3, 20.0), (1.1e5, 2e-3, 10.0), (9e4, -1e-3, 15.0)]
    a, b = make(fmi), make(fmi, radius=0.3, friction_coefficient=0.2)
    other = make(3 if fmi == 2 else 2)  # the other version, in the same process
    got_a = [step(a, n * H, H, *row) for n, row in enumerate(rows)]
    got_b = [step(b, n * H, H, *row) for n, row in enumerate(rows)]
    assert got_a != got_b, "the parameters of b are b's"
    assert got_a == [step(other, n * H, H, *row) for n, row in enumerate(rows)], "FMI 2.0 and 3.0 agree exactly"


def test_a_communication_point_inside_the_previous_step_is_discarded(make, fmi):
    slave = make(fmi)
    step(slave, 0.0, 1.0, *ROW)
    assert "t = 0.5 s is not the end of the previous step, 1.0 s" in refused_step(slave, 0.5, 1.0, *ROW)


def test_the_start_time_reaches_the_model_in_both_versions(make, fmi):
    """WheelRig's normal load depends on t: a run started at 0.25 s gives the same outputs in both versions (FMI 3.0
    takes the start time from the first doStep, as pythonfmu3 does not pass it on), and FMI 3.0's ``time`` follows
    the communication points."""
    parameters = {"load_amplitude": 2e4, "load_frequency": 3.0}
    names = ("tangential_force", "creep_stiffness", "external_torque")
    runs = {}
    for version in VERSIONS:
        rig = make(version, "WheelRig", start_time=0.25, **parameters)
        runs[version] = [step(rig, 0.25 + n * H, H, 1e3 * n, 1e7, 0.0, names=names) for n in range(3)]
        if version == 3:
            assert rig.fmu.getReal([rig.reference("time")]) == [0.25 + 3 * H]
    assert runs[2] == runs[3]
    reference = make(2, "WheelRig", start_time=0.0, **parameters)
    assert step(reference, 0.0, H, 0.0, 1e7, 0.0, names=names) != runs[2][0], "the start time matters here"


@pytest.mark.parametrize("inputs, reason", [((math.nan, 0.0, 0.0), "tangential_force = nan N is not finite"),
                                            ((0.0, math.inf, 0.0), "creep_stiffness = inf N is not finite")])
def test_the_host_fmu_discards_bad_inputs_and_repeats_restored_steps(make, fmi, inputs, reason):
    names = ("tangential_force", "creep_stiffness", "external_torque")
    rig = make(fmi, "WheelRig", torque_final=5e3, coupling=1, force_lag=1)
    step(rig, 0.0, H, 9e3, 1.6e7, 0.0, names=names)
    data = saved(rig)
    assert reason in refused_step(rig, H, H, *inputs, names=names)
    restore(rig, data)
    first = [step(rig, (1 + n) * H, H, 1e4 + n, 1.5e7, 0.0, names=names) for n in range(3)]
    restore(rig, data)
    assert [step(rig, (1 + n) * H, H, 1e4 + n, 1.5e7, 0.0, names=names) for n in range(3)] == first


# what FMI 3.0 does better -------------------------------------------------------------------------------------------
def test_fmi3_reasons_reach_the_logger_without_debug_logging_literally_and_in_fmi3_words(fmu_folders, tmp_path):
    """pythonfmu 0.7 drops every message without debug logging (the FMI 2.0 FMU writes its refusals to standard error
    instead); pythonfmu3 passes those of status Warning, Discard and Error regardless, as FMI 3.0 wants, and the
    notices (status OK) only with debug logging.  Messages are literal text (no printf escaping) in FMI 3.0's words."""
    from fmpy.fmi3 import FMU3Slave

    from rollcontact_cosim.master import extracted

    scene = tmp_path / "100%" / "tilted.toml"
    scene.parent.mkdir()
    scene.write_text("[surface]\npolynomial = [0.0, 1e-3]\n[load]\nnormal_load_per_length = 1.0\n")
    unzipped = extracted(fmu_folders[3] / "RollingContact2D.fmu")
    description = read_model_description(unzipped)
    variables = {v.name: v.valueReference for v in description.modelVariables}
    logs = {}
    for debug in (False, True):
        log = logs[debug] = []
        fmu = FMU3Slave(guid=description.guid, unzipDirectory=unzipped, instanceName=f"debug {debug}",
                        modelIdentifier=description.coSimulation.modelIdentifier)
        fmu.instantiate(loggingOn=debug, logMessage=lambda env, status, category, message, log=log: log.append(
            (status, category.decode(), message.decode())))
        try:
            fmu.setString([variables["scene_file"]], [str(scene)])
            fmu.enterInitializationMode(startTime=0.0)
            fmu.exitInitializationMode()
            fmu.setFloat64([variables[n] for n in INPUTS], [-1.0, 0.0, 1.0])
            with pytest.raises(FMICallException):
                fmu.doStep(0.0, H)
            fmu.setFloat64([variables["radius"]], [0.2])
        finally:
            fmu.terminate()
            fmu.freeInstance()
    assert [(s, c) for s, c, _ in logs[False]] == [(DISCARD, "logStatusDiscard"), (ERROR, "logStatusError")], \
        f"Discard and Error reach the logger without debug logging, the notice does not: {logs[False]}"
    assert logs[True][1:] == logs[False] and logs[True][0][:2] == (0, "logAll"), logs[True]
    assert f"scene_file {str(scene)!r} sets material" in logs[True][0][2], "literal text: one '%'"
    assert not any(word in m for _, _, m in logs[True] for word in ("fmi2", "FMI 2", "pythonfmu ")), logs[True]


def fingerprint():
    """``tests/fmu/test_fmu_fingerprint.py``: its cases, signal and recorded outputs."""
    folder = str(ROOT / "tests" / "fmu")
    sys.path.insert(0, folder)
    try:
        import test_fmu_fingerprint
    finally:
        sys.path.remove(folder)
    return test_fmu_fingerprint


def test_fmi3_outputs_equal_fmi2_bit_for_bit_on_the_fingerprint_signal(make):
    """Every case of the FMU fingerprint: FMI 3.0 gives FMI 2.0's outputs bit for bit (same process, same BLAS), and
    the recorded outputs under the fingerprint test's rules (its tolerance per case, 0: bit for bit)."""
    recording = fingerprint()
    recorded = json.loads(recording.DATA.read_text())
    h = recording.H
    for name, (parameters, tolerance) in recording.CASES.items():
        runs = {}
        for version in VERSIONS:
            slave = make(version, **parameters)
            runs[version] = np.array([step(slave, n * h, h, *recording.signal(n)) for n in range(recording.STEPS)])
        assert np.array_equal(runs[3], runs[2]), f"{name}: FMI 3.0 outputs differ from FMI 2.0's"
        want = np.array([[float(v) for v in row] for row in recorded[name]])
        if tolerance == recording.BITS:
            assert np.array_equal(runs[3], want), f"{name}: FMI 3.0 differs from the recorded outputs"
        else:
            scale = np.maximum(np.abs(want).max(axis=0), 1e-300)
            assert np.max(np.abs(runs[3] - want) / scale) <= tolerance, f"{name}: FMI 3.0 against the recording"


RAISING_SLAVE = '''
from pythonfmu3 import Fmi3Causality, Fmi3Initial, Fmi3Slave, Float64


class Raising(Fmi3Slave):
    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.x = 0.0
        self.register_variable(Float64("time", causality=Fmi3Causality.independent))
        self.register_variable(Float64("x", causality=Fmi3Causality.output, initial=Fmi3Initial.exact))

    def do_step(self, current_time, step_size):
        raise ValueError("raised in do_step")
'''

FATAL_PROBE = '''
import os, sys
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave
from pythonfmu3 import FmuBuilder
unzipped = extract(FmuBuilder.build_FMU(sys.argv[1], dest=os.path.dirname(sys.argv[1])))
md = read_model_description(unzipped)
log = []
fmu = FMU3Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName="raising")
fmu.instantiate(logMessage=lambda env, status, category, message: log.append((status, message.decode())))
fmu.enterInitializationMode()
fmu.exitInitializationMode()
try:
    fmu.doStep(0.0, 0.1)
except FMICallException as exc:
    print(exc.status, repr(log[-1]))
sys.stdout.flush()
os._exit(0)  # the instance's Python objects are released: no further call (docs/fmu-internals.md, pythonfmu3)
'''


def test_an_exception_in_a_pythonfmu3_slave_is_fatal(tmp_path):
    """What docs/fmu-internals.md says of pythonfmu3 0.3.4: an exception escaping the slave becomes fmi3Fatal (the
    reason logged), hence the slaves let none escape. Built and run in a subprocess: the instance is unusable
    afterwards, and this process may have imported an FMU's bundled copy of pythonfmu3, which has no binaries to
    build with."""
    script = tmp_path / "raising_slave.py"
    script.write_text(RAISING_SLAVE)
    done = subprocess.run([sys.executable, "-c", FATAL_PROBE, str(script)], capture_output=True, text=True,
                          timeout=120, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.startswith(f"{FATAL} ") and "raised in do_step" in done.stdout, done.stdout


@pytest.mark.parametrize("case", range(4), ids=["negative load", "NaN creep", "friction -0.1", "wavelength 0"])
def test_each_bad_input_is_logged_through_simulate_fmu_without_debug_logging(fmu_folders, case, capfd):
    """The issue's bad inputs and parameters through ``fmpy.simulate_fmu(..., debug_logging=False, logger=...)``:
    the FMI 3.0 FMU hands every Discard and Error reason to the logger (the FMI 2.0 FMU cannot, pythonfmu 0.7: it
    writes them to standard error, ``tests/fmu/test_fmu_hardening.py``)."""
    from fmpy import simulate_fmu

    folder = str(ROOT / "tests" / "fmu")
    sys.path.insert(0, folder)
    try:
        import test_fmu_hardening
    finally:
        sys.path.remove(folder)
    name, keywords, reason = test_fmu_hardening.bad_runs(None)[case]
    log = []
    try:
        simulate_fmu(str(fmu_folders[3] / "RollingContact2D.fmu"), stop_time=1.0, output_interval=0.1,
                     debug_logging=False, logger=lambda *args: log.append(args[-1].decode()), **keywords)
    except Exception:  # noqa: BLE001 - fmpy raises on the Discard
        pass
    assert any(reason in message for message in log), f"{name}: {reason!r} not logged: {log}"
    assert reason not in capfd.readouterr().err, f"{name}: the logger has it, standard error does not (FMI 3.0)"


CONSTRUCTION_PROBE = '''
import importlib, json, sys
sys.path[:0] = json.loads(sys.argv[1])
from pythonfmu import Fmi2Slave
from pythonfmu3 import Fmi3Slave


def refused(self, **kwargs):
    raise AssertionError("Fmi2Slave.__init__ ran in an FMI 3.0 slave")


Fmi2Slave.__init__ = refused
fmi2_methods = {name for klass in Fmi2Slave.__mro__ for name in vars(klass)}
for entry, model in json.loads(sys.argv[2]).items():
    cls = getattr(importlib.import_module(entry), model)
    for name in sorted({name for klass in Fmi3Slave.__mro__ if klass is not object for name in vars(klass)}
                       & fmi2_methods):
        owner = next(klass for klass in cls.__mro__ if name in vars(klass))
        if callable(getattr(cls, name)) and not name.startswith("__") and owner.__module__.startswith("pythonfmu."):
            print(f"{cls.__name__}.{name} resolves to {owner.__module__}.{owner.__name__}")
    if issubclass(cls, Fmi2Slave) or any(klass.__name__ == "TableSlave2" for klass in cls.__mro__):
        print(f"{cls.__name__} inherits pythonfmu's FMI 2.0 binding")
    slave = cls(instance_name="probe")
    names = [var.name for var in slave.vars.values()]
    rows = [row[0] for row in cls.VARIABLES]
    time = len(rows) if cls.TIME_REFERENCE is None else cls.TIME_REFERENCE
    if names != rows[:time] + ["time"] + rows[time:] or not isinstance(slave.units, dict):
        print(f"{cls.__name__}: variables {names[:3]}... not the table with time at {time}")
print("checked")
'''


def test_fmi3_slaves_are_constructed_by_pythonfmu3_and_resolve_no_call_to_pythonfmu(tmp_path):
    """Each FMI 3.0 slave (its entry module as ``build_fmu.py`` writes it) is built by ``Fmi3SlaveBase.__init__`` and
    the shared table, never by pythonfmu's ``Fmi2Slave.__init__`` (made to raise here), inherits neither
    ``Fmi2Slave`` nor the FMI 2.0 binding ``TableSlave2``, and every method both bindings define resolves to the FMI
    3.0 side or the shared slave, not to pythonfmu.  In a subprocess, so that this process imports no slave module an
    FMU instance would share."""
    import build_fmu

    entries = {}
    for model, fmu in build_fmu.FMUS.items():
        entry = build_fmu.tool("entry").write_entry(tmp_path, model, 3, fmu.folder.name, fmu.slave,
                                                    fmu.variant(fmi=3))
        entries[entry.stem] = model
    path = [str(tmp_path), *(str(fmu.folder) for fmu in build_fmu.FMUS.values()), str(build_fmu.FMU_SOURCES),
            str(build_fmu.SOURCES)]
    done = subprocess.run([sys.executable, "-c", CONSTRUCTION_PROBE, json.dumps(path), json.dumps(entries)],
                          capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout == "checked\n", f"FMI 3.0 slaves depending on pythonfmu's Fmi2Slave:\n{done.stdout}"
