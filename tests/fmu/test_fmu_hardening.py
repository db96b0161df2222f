"""The RollingContact2D FMU against hosts that misbehave (issue: corrupt states, late parameters, devices as scene
files, communication points inside a step, memory per instance, log messages without debug logging).

What pythonfmu 0.7 lets a slave do shapes the expectations (``docs/fmu-internals.md``, "Known limits of pythonfmu"):
only ``doStep`` has a status of its own (fmi2Discard); every other call returns fmi2OK unless the slave raises,
which pythonfmu turns into fmi2Fatal and a broken instance. So where FMI 2 wants fmi2Error the FMU *emulates* it:
the call returns fmi2OK, the reason is logged with status Error (3), nothing changes, and every ``doStep`` is
discarded with the reason until a valid state is set or the instance is reset. Cases that could crash or hang the
test process run in a subprocess.
"""

from __future__ import annotations

import gc
import hashlib
import json
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException
from fmu_host import DISCARD, H, Instance, discarded, model_outputs

ERROR = 3
ROW = (1e5, 1e-3, 20.0)  # normal load [N], creep, speed [m/s]


def serialise(state: dict) -> bytes:
    """Bytes of an FMU state as the FMU serialises them: JSON (sorted keys) with a SHA-256 checksum, computed here
    independently of the slave's code."""
    text = json.dumps(state, sort_keys=True)
    return json.dumps({**state, "sha256": hashlib.sha256(text.encode()).hexdigest()}, sort_keys=True).encode()


def errors(fmu: Instance, since: int) -> list[str]:
    """Messages logged with status Error since log entry ``since`` (printf-unescaped)."""
    return [m.replace("%%", "%") for s, _, m in fmu.log[since:] if s == ERROR]


def saved_state(fmu: Instance) -> bytes:
    """The instance's state, serialised."""
    state = fmu.fmu.getFMUstate()
    try:
        return bytes(fmu.fmu.serializeFMUstate(state))
    finally:
        fmu.fmu.freeFMUstate(state)


def set_serialised(fmu: Instance, data: bytes) -> None:
    state = fmu.fmu.deSerializeFMUstate(data)
    try:
        fmu.fmu.setFMUstate(state)
    finally:
        fmu.fmu.freeFMUstate(state)


# 1. corrupt or crafted FMU states -----------------------------------------------------------------------------------
def flipped(data: bytes) -> bytes:
    """The first digit of the model's time changed: still valid JSON of the right shape, caught by the checksum."""
    at = data.index(b'"time": ') + len(b'"time": ')
    return data[:at] + bytes([ord("7") if data[at] != ord("7") else ord("8")]) + data[at + 1:]


def crafted(change):
    """Bytes of the saved state after ``change(state_dict)``, with a valid checksum."""
    def make(data: bytes) -> bytes:
        state = json.loads(data)
        del state["sha256"]
        change(state)
        return serialise(state)
    return make


def replaced(value):
    return lambda data: serialise(value)


BAD_STATES = {  # name: (bytes from the saved bytes, what the logged reason says)
    "truncated": (lambda d: d[: len(d) // 2], "is not UTF-8 JSON"),
    "flipped digit": (flipped, "does not match its checksum"),
    "non-UTF-8": (lambda d: b"\xff\xfe" + d[2:], "is not UTF-8 JSON"),
    "no checksum": (lambda d: json.dumps({k: v for k, v in json.loads(d).items() if k != "sha256"}).encode(),
                    "no JSON object with a checksum"),
    "empty object": (replaced({}), "not an FMU state of this FMU"),
    "null": (lambda d: b"null", "no JSON object with a checksum"),
    "no model key": (crafted(lambda s: s.pop("model")), "missing key(s) ['model']"),
    "version 99": (crafted(lambda s: s.update(version=99)), "FMU state version 99 is not supported"),
    "other FMU": (crafted(lambda s: s.update(fmu="WheelRig")), "belongs to the FMU 'WheelRig'"),
    "variable 'log'": (crafted(lambda s: s["variables"].update(log=1)), "unknown ['log']"),
    "variable 'step_model'": (crafted(lambda s: s["variables"].update(step_model=None)), "unknown ['step_model']"),
    "radius a string": (crafted(lambda s: s["variables"].update(radius="0.2")), "radius = '0.2' is not of type Real"),
    "method a float": (crafted(lambda s: s["variables"].update(method=1.0)), "method = 1.0 is not of type Integer"),
    "NaN output": (crafted(lambda s: s["outputs"].__setitem__(0, math.nan)), "tangential_force = nan"),
    "infinite model time": (crafted(lambda s: s["model"].update(time=math.inf)), "model state time = inf"),
    "model steps a bool": (crafted(lambda s: s["model"].update(steps=True)), "steps = True"),
    "bad base64": (crafted(lambda s: s["model"].update(instationary="not base64!")), "model state instationary"),
    "model version 99": (crafted(lambda s: s["model"].update(version=99)), "model state version 99"),
    "no model state": (crafted(lambda s: s.update(model=None)), "must hold the model's state"),
    "scene file /dev/zero": (crafted(lambda s: s["variables"].update(scene_file="/dev/zero")),
                             "is a character device"),
    "a table that splits": (crafted(lambda s: (s["variables"].update(corrugation_amplitude=20e-6,
                                                                     corrugation_wavelength=0.01, table=2),
                                               s["model"].update(table_domain=[1e5, 2e5]))),
                            "its table cannot be built"),
    "a table of another family": (crafted(lambda s: (s["variables"].update(friction_law=1),
                                                     s["model"].update(table_domain=[1e5, 2e5]))),
                                  "is not a domain of this model's table"),
}


@pytest.mark.parametrize("name", list(BAD_STATES))
def test_an_invalid_state_is_refused_and_the_instance_keeps_its_state(instance, name):
    make, reason = BAD_STATES[name]
    fmu = instance()
    fmu.step(0.0, H, *ROW)
    good = saved_state(fmu)
    before_outputs, before = fmu.outputs(), len(fmu.log)
    set_serialised(fmu, make(good))  # fmi2OK (fmpy would raise otherwise): pythonfmu has no other status here
    logged = errors(fmu, before)
    assert logged and reason in logged[0] and "setFMUstate refused" in logged[0], \
        f"{name}: the reason must be logged with status Error, got {logged or fmu.log[before:]}"
    assert fmu.outputs() == before_outputs, "the outputs stay those of the previous state"
    message = discarded(fmu, H, H, *ROW)
    assert "error state" in message and reason in message, f"the next step is discarded with the reason: {message}"
    set_serialised(fmu, good)  # a valid state ends the error state
    assert fmu.step(H, H, *ROW) == model_outputs({}, [ROW, ROW])[1], "and the instance steps on from it"


def test_a_state_with_the_old_keys_cannot_write_attributes_of_the_slave(instance):
    """A crafted key ``log`` once replaced the slave's log method (the next bad step became fmi2Fatal)."""
    fmu = instance()
    state = json.loads(saved_state(fmu))
    del state["sha256"]
    state["variables"]["log"] = 0
    set_serialised(fmu, serialise(state))
    set_serialised(fmu, saved_state(fmu))  # the current state: ends the error state
    assert "normal_load = -1.0 N is out of range" in discarded(fmu, 0.0, H, -1.0, 0.0, 1.0), \
        "a bad step after the refused state is an ordinary Discard"


def test_states_saved_before_initialisation_or_with_invalid_parameters_are_valid(instance, unzipped, description):
    from fmpy.fmi2 import FMU2Slave

    raw = FMU2Slave(guid=description.guid, unzipDirectory=str(unzipped),
                    modelIdentifier=description.coSimulation.modelIdentifier, instanceName="raw")
    raw.instantiate()
    state = raw.getFMUstate()
    uninitialised = bytes(raw.serializeFMUstate(state))
    raw.freeFMUstate(state)
    raw.fmi2FreeInstance(raw.component)  # not freeInstance: fmpy would unload the library the others use
    invalid = saved_state(instance(friction_coefficient=-0.1))
    fmu = instance()
    before = len(fmu.log)
    set_serialised(fmu, invalid)
    assert "invalid parameters: friction_coefficient = -0.1" in discarded(fmu, 0.0, H, *ROW)
    set_serialised(fmu, uninitialised)
    assert "the FMU is not initialised" in discarded(fmu, 0.0, H, *ROW)
    assert not errors(fmu, before), "both are states an instance can be in: none is refused"


ZERO_LENGTH = """
import sys
sys.path.insert(0, {tests!r})
from fmpy import read_model_description
from fmu_host import Instance, H
fmu = Instance({unzipped!r}, read_model_description({unzipped!r}))
good = fmu.fmu.getFMUstate()
for data in (b"", b"", b"\\x00", b"{{"):  # twice: the second call after a Fatal crashed pythonfmu 0.7 hosts
    state = fmu.fmu.deSerializeFMUstate(data)
    fmu.fmu.setFMUstate(state)
    fmu.fmu.freeFMUstate(state)
fmu.fmu.setFMUstate(good)
fmu.fmu.freeFMUstate(good)
out = fmu.step(0.0, H, 1e5, 1e-3, 20.0)
fmu.free()
print("errors", sum(1 for s, _, m in fmu.log if s == 3 and "setFMUstate refused" in m), "force", out.tangential_force)
"""


def test_zero_length_and_garbage_bytes_neither_crash_nor_fatal(unzipped):
    """fmpy's ``deSerializeFMUstate(b"")`` once ended in fmi2Fatal, after which pythonfmu 0.7 leaves dangling
    pointers (docs/fmu-internals.md): the next call on the instance was a use after free (SIGSEGV). Now every such
    state is an ordinary refused state, in a subprocess that must exit normally."""
    script = ZERO_LENGTH.format(tests=str(Path(__file__).parents[1]), unzipped=str(unzipped))
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, f"exit {done.returncode} (signal {-done.returncode} if < 0):\n{done.stderr[-3000:]}"
    assert "errors 4 force" in done.stdout, f"four refused states expected:\n{done.stdout}\n{done.stderr[-2000:]}"


# 2. parameters after initialisation ---------------------------------------------------------------------------------
def test_a_fixed_parameter_set_after_initialisation_is_refused_and_never_applied(instance):
    fmu = instance()
    fmu.step(0.0, H, *ROW)
    before = len(fmu.log)
    fmu.set(radius=0.2)
    logged = errors(fmu, before)
    assert logged and "radius = 0.2 refused" in logged[0] and "value in force stays 0.46" in logged[0], logged
    assert fmu.fmu.getReal([fmu.variables["radius"].valueReference]) == [0.46], "the value in force is reported"
    assert "radius = 0.2 refused" in discarded(fmu, H, H, *ROW), "steps are discarded (emulated fmi2Error)"
    state = fmu.fmu.getFMUstate()  # a round trip does not apply the refused value
    fmu.fmu.setFMUstate(state)
    fmu.fmu.freeFMUstate(state)
    assert fmu.step(H, H, *ROW) == model_outputs({}, [ROW, ROW])[1], "the default radius stays in force"
    before = len(fmu.log)
    fmu.set(radius=0.46, method=0, scene_file="")  # the values in force: no change, no error
    assert not errors(fmu, before), "re-setting the values in force is no error"
    fmu.step(2 * H, H, *ROW)


def test_outputs_and_wrong_value_references_are_refused_without_fatal(instance):
    fmu = instance()
    before = len(fmu.log)
    fmu.fmu.setReal([fmu.variables["tangential_force"].valueReference], [1.0])
    fmu.fmu.setReal([fmu.variables["method"].valueReference], [1.0])  # an Integer
    fmu.fmu.setReal([10_000], [1.0])
    assert np.isnan(fmu.fmu.getReal([10_000])[0]), "an unknown value reference reads NaN"
    logged = errors(fmu, before)
    assert len(logged) == 4 and "is an output" in logged[0] and "method, not a Real" in logged[1], logged
    assert "error state" in discarded(fmu, 0.0, H, *ROW)


def test_invalid_parameters_at_initialisation_are_an_error_and_a_reset_recovers(instance):
    fmu = instance(friction_coefficient=-0.1)
    logged = errors(fmu, 0)
    assert logged and "exitInitializationMode: invalid parameters: friction_coefficient = -0.1" in logged[0], fmu.log
    assert "friction_coefficient = -0.1" in discarded(fmu, 0.0, H, *ROW)
    fmu.fmu.reset()  # back to instantiated: parameters can be set again
    fmu.set(friction_coefficient=0.25)
    fmu.fmu.setupExperiment(startTime=0.0)
    fmu.fmu.enterInitializationMode()
    fmu.fmu.exitInitializationMode()
    assert fmu.step(0.0, H, *ROW) == model_outputs({"friction_coefficient": 0.25}, [ROW])[0]


# 3. scene files that are no scenes ----------------------------------------------------------------------------------
SCENE_PROBE = """
import json, sys
sys.path.insert(0, {tests!r})
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmu_host import Instance, H
results = {{}}
for path in {paths!r}:
    fmu = Instance({unzipped!r}, read_model_description({unzipped!r}), scene_file=path)
    try:
        fmu.step(0.0, H, 1e5, 1e-3, 20.0)
        status = 0
    except FMICallException as exc:
        status = exc.status
    results[path] = [status, [m for _, _, m in fmu.log]]
    fmu.free()
print(json.dumps(results))
"""


def test_devices_fifos_big_and_foreign_files_are_refused_unread_without_echoing_them(unzipped, tmp_path):
    """Each is refused for what it is (a device, a FIFO, too big) before it is read: reading /dev/zero or a FIFO
    without a writer never ends, which the probe's time-out would report."""
    fifo = tmp_path / "fifo.toml"
    os.mkfifo(fifo)
    big = tmp_path / "big.toml"
    big.write_text("# " + "x" * (1 << 20) + "\n")
    foreign = tmp_path / "secrets.toml"
    foreign.write_text('secret_token = "hunter2"\n')
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"\xffhunter2\x00")
    text = tmp_path / "passwd"
    text.write_text("root:x:0:0:hunter2:/root:/bin/sh\n")
    expected = {"/dev/zero": "is a character device", str(fifo): "is a FIFO", str(tmp_path): "is a directory",
                str(big): "more than a scene's limit of 1048576 bytes", str(foreign): "is not a scene",
                str(binary): "it is not UTF-8 text", str(text): "is not a scene: a TOML syntax error (at line 1"}
    script = SCENE_PROBE.format(tests=str(Path(__file__).parents[1]), unzipped=str(unzipped), paths=list(expected))
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-3000:]
    results = json.loads(done.stdout.splitlines()[-1])
    for path, reason in expected.items():
        status, log = results[path]
        assert status == DISCARD, f"{path}: the step must be discarded, got status {status}"
        assert any(reason in m for m in log), f"{path}: expected {reason!r} in the log {log}"
        assert not any("hunter2" in m or "secret_token" in m for m in log), f"{path}: the log echoes content: {log}"


# 4. communication points ---------------------------------------------------------------------------------------------
def test_a_communication_point_inside_the_previous_step_is_discarded(instance):
    fmu = instance()
    fmu.step(0.0, 1.0, 1e5, 1e-3, 10.0)
    message = discarded(fmu, 0.5, 1.0, 1e5, 1e-3, 10.0)
    assert "t = 0.5 s is not the end of the previous step, 1.0 s" in message, message
    assert fmu.outputs().axis_position == 0.0, "the axis did not move"
    assert fmu.step(1.0, 1.0, 1e5, 1e-3, 10.0).axis_position == 10.0, "X(1 s) = 10 m"
    assert "is not the end of the previous step, 2.0 s" in discarded(fmu, 5.0, 1.0, 1e5, 1e-3, 10.0), "nor a jump"


def test_communication_points_are_accepted_within_rounding_and_from_a_restored_state(instance):
    fmu = instance(start_time=2.0)
    assert "is not the end of the previous step, 2.0 s" in discarded(fmu, 0.0, 0.1, *ROW), "the first at the start"
    for n in range(30):  # 2 + n * 0.1 differs from the running sum by a few ulps
        fmu.step(2.0 + n * 0.1, 0.1, *ROW)
    state = fmu.fmu.getFMUstate()
    fmu.step(5.0, 0.1, *ROW)
    fmu.fmu.setFMUstate(state)  # back to t = 5.0
    fmu.fmu.freeFMUstate(state)
    fmu.step(5.0, 0.1, *ROW)
    assert "is not the end of the previous step" in discarded(fmu, 5.1 + 1e-6, 0.1, *ROW)


# 5. memory per instance ----------------------------------------------------------------------------------------------
MEMORY_PROBE = """
import gc, sys
from fmpy import read_model_description
from fmpy.fmi2 import FMU2Slave
unzipped = {unzipped!r}
md = read_model_description(unzipped)
fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, modelIdentifier=md.coSimulation.modelIdentifier,
                instanceName="memory")

def cycle():
    fmu.instantiate(loggingOn=False)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 1e-3)
    fmu.terminate()
    fmu.fmi2FreeInstance(fmu.component)

for _ in range(30):
    cycle()
gc.collect()
with open(unzipped + "/resources/slavemodule.txt") as named:  # the entry module pythonfmu re-executes
    module = sys.modules[named.read().strip()]
refs, paths, blocks = sys.getrefcount(module.__dict__), len(sys.path), sys.getallocatedblocks()
for _ in range({cycles}):
    cycle()
gc.collect()
print((sys.getallocatedblocks() - blocks) / {cycles}, sys.getrefcount(module.__dict__) - refs, len(sys.path) - paths)
"""


def test_instantiate_free_cycles_leave_little_behind(unzipped):
    """Measured (benchmarks/results/fuzz.md, docs/fmu-internals.md): 150 Python blocks per cycle before (the slave class
    re-created by pythonfmu on each instantiation), about 15 now, pythonfmu's own findClass leaks."""
    cycles = 200
    script = MEMORY_PROBE.format(unzipped=str(unzipped), cycles=cycles)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    blocks, refs, paths = (float(v) for v in done.stdout.split())
    assert blocks < 30, f"{blocks:.1f} Python memory blocks left per instantiate/free cycle"
    assert refs == 0, f"the entry module's namespace gained {refs:.0f} references (its refcount must balance)"
    assert paths == 0, f"sys.path grew by {paths:.0f} entries"


def test_the_entry_module_balances_its_references_without_ctypes(instance, unzipped, monkeypatch):
    """The fallback when ctypes cannot reach the C API: a class whose method holds the reference."""
    import ctypes

    monkeypatch.setattr(ctypes, "pythonapi", None)
    instance()  # the entry module is loaded, its fallback taken once
    module = sys.modules[(unzipped / "resources" / "slavemodule.txt").read_text().strip()]
    gc.collect()  # the frames of the caught AttributeErrors
    before = sys.getrefcount(module.__dict__)
    for _ in range(5):
        instance()
    gc.collect()
    after = sys.getrefcount(module.__dict__)  # not inside the assert: its rewriting holds a reference
    assert after == before, "findClass's extra Py_DECREF must be balanced"


# 6. log messages -----------------------------------------------------------------------------------------------------
def bad_runs(unzipped):
    """``(name, simulate_fmu keywords, expected reason)`` of the issue's bad inputs and parameters."""
    t = np.linspace(0.0, 1.0, 11)
    load = np.where(t < 0.5, 1e5, -1e3)
    negative = np.array(list(zip(t, load, np.full_like(t, 1e-3), np.full_like(t, 20.0), strict=True)),
                        dtype=[("time", float), ("normal_load", float), ("creep", float), ("velocity", float)])
    nan_creep = negative.copy()
    nan_creep["normal_load"], nan_creep["creep"] = 1e5, np.nan
    steady = negative.copy()
    steady["normal_load"] = 1e5
    return [("negative load from t = 0.5 s", {"input": negative}, "normal_load = -1000.0 N is out of range"),
            ("NaN creep", {"input": nan_creep}, "creep = nan is not finite"),
            ("friction_coefficient = -0.1", {"input": steady, "start_values": {"friction_coefficient": -0.1}},
             "friction_coefficient = -0.1"),
            ("corrugation_wavelength = 0", {"input": steady, "start_values": {"corrugation_wavelength": 0.0}},
             "corrugation_wavelength = 0.0")]


def simulate_logged(unzipped, debug_logging: bool, keywords: dict) -> list[tuple[int, str, str]]:
    log = []

    def logger(component, instance_name, status, category, message):
        log.append((status, (category or b"").decode(), message.decode()))

    try:
        simulate_fmu(str(unzipped), validate=False, stop_time=1.0, output_interval=0.1, debug_logging=debug_logging,
                     logger=logger, **keywords)
    except Exception:  # noqa: BLE001 - fmpy raises on the Discard
        pass
    return log


@pytest.mark.parametrize("case", range(4), ids=["negative load", "NaN creep", "friction -0.1", "wavelength 0"])
def test_discard_and_error_reasons_reach_the_logger_with_status_categories(unzipped, case, capfd):
    name, keywords, reason = bad_runs(unzipped)[case]
    log = simulate_logged(unzipped, True, keywords)
    hits = [(s, c) for s, c, m in log if reason in m]
    assert hits, f"{name}: {reason!r} not logged: {log}"
    assert all((s, c) in {(DISCARD, "logStatusDiscard"), (ERROR, "logStatusError")} for s, c in hits), \
        f"{name}: Discard/Error reasons carry the declared categories logStatusDiscard/logStatusError: {hits}"
    err = capfd.readouterr().err
    assert reason not in err, f"{name}: the logger received the reason, so it is not repeated on stderr:\n{err}"


@pytest.mark.parametrize("case", range(4), ids=["negative load", "NaN creep", "friction -0.1", "wavelength 0"])
def test_discard_and_error_reasons_reach_stderr_once_without_debug_logging(unzipped, case, capfd):
    """pythonfmu 0.7 hands no message to the logger while loggingOn is fmi2False (``PyLogger::log`` in
    ``Logger.hpp``: docs/fmu-internals.md, Known limits of pythonfmu, 3); the refusal is then written to standard
    error, once (an invalid parameter's Error at initialisation and the Discard of the step it refuses are one
    reason)."""
    name, keywords, reason = bad_runs(unzipped)[case]
    log = simulate_logged(unzipped, False, keywords)
    assert log == [], f"{name}: pythonfmu 0.7 passes nothing to the logger without debug logging: {log}"
    err = capfd.readouterr().err
    lines = [line for line in err.splitlines() if reason in line]
    assert len(lines) == 1, f"{name}: {reason!r} exactly once on standard error:\n{err}"
    assert lines[0].startswith("RollingContact2D (instance ") and ("Discard: " in lines[0] or "Error: " in lines[0]), \
        f"{name}: the line names the FMU, the instance and the status: {lines[0]!r}"
    assert len(err.splitlines()) == 1, f"{name}: one reason, one line:\n{err}"


# the WheelRig FMU shares the slave base ------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def wheel_rig(tmp_path_factory):
    """The WheelRig FMU (``build_fmu.py --all``), unzipped, and its model description."""
    from fmpy import extract, read_model_description

    dest = tmp_path_factory.mktemp("wheel_rig")
    done = subprocess.run([sys.executable, str(Path(__file__).resolve().parents[2] / "build_fmu.py"), "--all",
                           "--dest", str(dest)], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    unzipped = extract(str(dest / "WheelRig.fmu"), unzipdir=str(dest / "unzipped"))
    return unzipped, read_model_description(unzipped)


def test_the_wheel_rig_refuses_bad_states_late_parameters_and_wrong_times(wheel_rig):
    from fmpy.fmi2 import FMU2Slave, defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE

    unzipped, description = wheel_rig
    vr = {v.name: v.valueReference for v in description.modelVariables}
    log = []
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = fmi2CallbackLoggerTYPE(lambda env, name, status, cat, msg: log.append((status, msg.decode())))
    callbacks.allocateMemory, callbacks.freeMemory = defaultCallbacks.allocateMemory, defaultCallbacks.freeMemory
    rig = FMU2Slave(guid=description.guid, unzipDirectory=unzipped, instanceName="rig",
                    modelIdentifier=description.coSimulation.modelIdentifier)
    rig.instantiate(callbacks=callbacks, loggingOn=True)
    rig.setupExperiment(startTime=0.0)
    rig.enterInitializationMode()
    rig.exitInitializationMode()

    def step(t, h=1e-3):
        rig.setReal([vr["tangential_force"], vr["creep_stiffness"], vr["external_torque"]], [1e3, 1e7, 0.0])
        try:
            rig.doStep(t, h)
        except FMICallException as exc:
            return exc.status, log[-1][1]
        return 0, rig.getReal([vr["velocity"], vr["wheel_speed"]])

    try:
        assert step(0.0)[0] == 0
        state = rig.getFMUstate()
        good = bytes(rig.serializeFMUstate(state))
        first = step(1e-3)
        crafted_state = json.loads(good)
        del crafted_state["sha256"]
        crafted_state["model"]["velocity"] = math.nan
        bad = rig.deSerializeFMUstate(serialise(crafted_state))
        rig.setFMUstate(bad)
        rig.freeFMUstate(bad)
        assert any(s == ERROR and "velocity = nan" in m for s, m in log), log[-2:]
        status, message = step(2e-3)
        assert status == DISCARD and "error state" in message, message
        rig.setFMUstate(state)
        assert step(1e-3) == first, "the valid state restores the rig exactly"
        rig.setReal([vr["vehicle_mass"]], [1.0])
        assert any(s == ERROR and "vehicle_mass = 1.0 refused" in m for s, m in log), log[-2:]
        rig.setFMUstate(state)
        rig.freeFMUstate(state)
        status, message = step(0.5e-3)
        assert status == DISCARD and "is not the end of the previous step" in message, message
    finally:
        rig.terminate()
        rig.fmi2FreeInstance(rig.component)
