"""A refused step or call of the FMI 2.0 FMU is visible by default (docs/fmu.md, "Why a step is refused").

pythonfmu 0.7 hands a message to the host's logger only for the categories the host switched on
(``fmi2SetDebugLogging``); a refusal (status Discard or Error) the host's logger does not receive goes to standard
error instead, once per reason and instance, and one the logger receives does not (no double messages).  ``capfd``
captures both Python's ``sys.stderr`` (what an fmpy host's FMU writes to) and file descriptor 2 (a C host's).
"""

from __future__ import annotations

import math
import re
import shutil
import subprocess
import sys
import sysconfig

import pytest
from fmpy import instantiate_fmu, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmu_host import C_HOST, DISCARD, H, model_outputs, shared_libpython

ERROR = 3
ROW = (1e5, 1e-3, 20.0)  # normal load [N], creep, speed [m/s]
NAN_CREEP = "creep = nan is not finite"
NEGATIVE_LOAD = "normal_load = -1.0 N is out of range"
FIXED = "friction_coefficient is a fixed parameter and cannot change after initialisation"
SHOWN = re.compile(r"^RollingContact2D \(instance '([^']*)'\): (Discard|Error): (.*)$", re.M)
"""A refusal written to standard error: FMU, instance name, status, message."""


class Host:
    """An fmpy host of one initialised instance with the debug logging it asks for: ``categories`` None leaves
    logging off (``loggingOn = fmi2False``), ``()`` switches every category on, else just those."""

    def __init__(self, unzipped, description, categories, name="refusals"):
        self.variables = {v.name: v.valueReference for v in description.modelVariables}
        self.log: list[tuple[int, str, str]] = []
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.logger = fmi2CallbackLoggerTYPE(self.logger)
        self.callbacks.allocateMemory = defaultCallbacks.allocateMemory
        self.callbacks.freeMemory = defaultCallbacks.freeMemory
        self.fmu = FMU2Slave(guid=description.guid, unzipDirectory=str(unzipped), instanceName=name,
                             modelIdentifier=description.coSimulation.modelIdentifier)
        self.fmu.instantiate(callbacks=self.callbacks, loggingOn=categories is not None)
        if categories:
            self.fmu.setDebugLogging(True, list(categories))
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()

    def logger(self, environment, instance_name, status, category, message):
        self.log.append((status, (category or b"").decode(), message.decode().replace("%%", "%")))

    def step(self, t, normal_load, creep, velocity) -> int:
        """Set the inputs and step; the status (0 OK, 2 Discard)."""
        names = ("normal_load", "creep", "velocity")
        self.fmu.setReal([self.variables[n] for n in names], [normal_load, creep, velocity])
        try:
            self.fmu.doStep(t, H)
        except FMICallException as exc:
            return exc.status
        return 0

    def tangential_force(self) -> float:
        return self.fmu.getReal([self.variables["tangential_force"]])[0]

    def free(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()


@pytest.fixture
def host(unzipped, description):
    """A factory of :class:`Host` instances, freed after the test."""
    made = []

    def make(categories, name="refusals") -> Host:
        made.append(Host(unzipped, description, categories, name))
        return made[-1]

    yield make
    for h in made:
        h.free()


def shown(err: str) -> list[tuple[str, str, str]]:
    """The refusals written to standard error: (instance, status, message)."""
    return SHOWN.findall(err)


def test_each_distinct_reason_is_shown_once_and_the_instance_stays_usable(host, capfd):
    fmu = host(None, name="wheel 1")
    statuses = [fmu.step(0.0, 1e5, math.nan, 20.0) for _ in range(3)]  # a Discard leaves the time at 0
    statuses += [fmu.step(0.0, -1.0, 1e-3, 20.0) for _ in range(2)]
    statuses.append(fmu.step(0.0, 1e5, math.nan, 20.0))
    assert statuses == [DISCARD] * 6, f"every bad step is discarded: {statuses}"
    assert fmu.step(0.0, *ROW) == 0, "after the refusals the instance steps"
    expected = model_outputs({}, [ROW])[0].tangential_force
    assert fmu.tangential_force() == expected, "after the refusals the step is the model's"
    assert fmu.log == [], f"with logging off pythonfmu hands nothing to the host's logger: {fmu.log}"
    out, err = capfd.readouterr()
    lines = shown(err)
    assert [(instance, status) for instance, status, _ in lines] == [("wheel 1", "Discard")] * 2, \
        f"two distinct reasons, each shown once with the FMU and instance name:\n{err}"
    assert NAN_CREEP in lines[0][2] and NEGATIVE_LOAD in lines[1][2], f"the reasons, in order:\n{err}"
    assert "do_step at t = 0.0 s" in lines[0][2], f"the message says when:\n{err}"
    assert out == "", f"nothing on standard output: {out!r}"


@pytest.mark.parametrize(("categories", "to_logger", "to_stderr"), [
    (None, set(), {NAN_CREEP, FIXED}),
    ((), {NAN_CREEP, FIXED, "error state"}, set()),
    (("logStatusDiscard", "logStatusError"), {NAN_CREEP, FIXED, "error state"}, set()),
    (("logStatusError",), {FIXED}, {NAN_CREEP}),
    (("logStatusDiscard",), {NAN_CREEP, "error state"}, {FIXED}),
], ids=["logging off", "every category", "discard and error", "error only", "discard only"])
def test_a_refusal_goes_to_the_host_logger_or_to_stderr_never_both(host, capfd, categories, to_logger, to_stderr):
    """A NaN creep (Discard), a fixed parameter set after initialisation (emulated Error) and the step it makes
    discarded (Discard, the Error's reason): each reason reaches the user once, through the categories the host
    switched on, else on standard error; the Discard that follows an Error the host received is not shown again."""
    fmu = host(categories)
    assert fmu.step(0.0, 1e5, math.nan, 20.0) == DISCARD
    assert fmu.step(0.0, *ROW) == 0
    fmu.fmu.setReal([fmu.variables["friction_coefficient"]], [0.5])
    assert fmu.step(H, *ROW) == DISCARD, "the emulated error state discards the next step"
    keys = ((NAN_CREEP, DISCARD, "logStatusDiscard"), (FIXED, ERROR, "logStatusError"),
            ("error state", DISCARD, "logStatusDiscard"))
    logged = {key for key, status, category in keys if any(key in m and (s, c) == (status, category)
                                                           for s, c, m in fmu.log)}
    assert logged == to_logger, f"the host's logger received {fmu.log}"
    assert len(fmu.log) == len(to_logger), f"each once, nothing else: {fmu.log}"
    lines = shown(capfd.readouterr().err)
    assert len(lines) == len(to_stderr), f"{sorted(to_stderr)} on standard error, once each: {lines}"
    for key in to_stderr:
        assert sum(key in message for _, _, message in lines) == 1, f"{key!r} shown once: {lines}"


def test_simulate_fmu_with_categories_through_fmu_instance(unzipped, description, capfd):
    """docs/fmu.md's recipe for the reasons alone in fmpy: instantiate with debug logging and a logger, switch on
    the Discard and Error categories, hand the instance to ``simulate_fmu``; the logger receives the reason once and
    nothing is repeated on standard error.  (The logger is given explicitly: fmpy's printf proxy keeps the last
    logger given to it process-wide, so the default callbacks may call a logger of an earlier run.)"""
    import numpy as np

    t = np.linspace(0.0, 1.0, 11)
    signals = np.array([(x, 1e5, math.nan if x >= 0.5 else 1e-3, 20.0) for x in t],
                       dtype=[("time", float), ("normal_load", float), ("creep", float), ("velocity", float)])
    log = []
    fmu = instantiate_fmu(str(unzipped), description, fmi_type="CoSimulation", debug_logging=True,
                          logger=lambda component, name, status, category, message: log.append((status, message)))
    fmu.setDebugLogging(True, ["logStatusDiscard", "logStatusError"])
    try:
        result = simulate_fmu(str(unzipped), stop_time=1.0, output_interval=0.1, input=signals, fmu_instance=fmu)
    finally:
        fmu.freeInstance()
    assert result["time"][-1] == pytest.approx(0.5), "fmpy stops at the Discard (the issue's truncated result)"
    assert [s for s, m in log if NAN_CREEP in m.decode()] == [DISCARD], f"the reason reaches the logger once: {log}"
    assert shown(capfd.readouterr().err) == [], "nothing repeated on standard error"


def test_more_distinct_reasons_than_the_limit_end_with_one_line_saying_so(host, capfd):
    fmu = host(None)
    for n in range(25):
        assert fmu.step(0.0, -1.0 - n, 1e-3, 20.0) == DISCARD
    err = capfd.readouterr().err
    assert len(shown(err)) == 20, f"at most 20 reasons per instance:\n{err}"
    assert err.count("more than 20 distinct refusals") == 1, f"then one line that says so:\n{err}"
    assert "normal_load = -20.0 N" in err and "normal_load = -21.0 N" not in err, err


def test_a_c_host_without_logging_sees_the_reason_on_its_standard_error(unzipped, description, tmp_path):
    """A C host has no Python-level streams: the embedded interpreter's ``sys.stderr`` is file descriptor 2."""
    gcc, libpython = shutil.which("gcc"), shared_libpython()
    if gcc is None or libpython is None:
        pytest.skip("needs gcc and a shared libpython (tests/fmu/test_fmu.py, the C host)")
    source, program = tmp_path / "host.c", tmp_path / "host"
    call = '&callbacks, 0, 1);'
    assert C_HOST.count(call) == 1, "the C host's fmi2Instantiate call (visible = 0, loggingOn = 1)"
    source.write_text(C_HOST.replace(call, '&callbacks, 0, 0);'))  # loggingOn = fmi2False
    built = subprocess.run([gcc, "-std=c99", "-Wall", "-Werror", "-o", str(program), str(source), "-ldl"],
                           capture_output=True, text=True)
    assert built.returncode == 0, built.stderr
    variables = {v.name: v.valueReference for v in description.modelVariables}
    binary = next((unzipped / "binaries" / "linux64").glob("*.so"))
    args = [str(program), str(binary), description.guid, (unzipped / "resources").as_uri(), repr(H),
            *(str(variables[n]) for n in ("normal_load", "creep", "velocity")), str(variables["method_used"]),
            str(variables["tangential_force"])]
    env = {"PATH": "/usr/bin:/bin", "LD_PRELOAD": str(libpython), "PYTHONHOME": sys.base_prefix,
           "PYTHONPATH": sysconfig.get_paths()["purelib"]}
    ran = subprocess.run(args, input=f"{ROW[0]!r} {ROW[1]!r} {ROW[2]!r}\n-1.0 0.001 20.0\n", capture_output=True,
                         text=True, env=env, cwd=tmp_path, timeout=120)
    assert ran.returncode == 0, ran.stderr
    assert [line.split()[0] for line in ran.stdout.splitlines()] == ["0", str(DISCARD)], ran.stdout
    lines = shown(ran.stderr)
    assert [(i, s) for i, s, _ in lines] == [("c_host", "Discard")] and NEGATIVE_LOAD in lines[0][2], ran.stderr
    assert "[c_host|" not in ran.stderr, f"the host's logger (logging off) receives nothing:\n{ran.stderr}"


# the reading of pythonfmu's logger object, on a block laid out as the GNU C++ library lays it out -----------------
def slave_base():
    """``fmu_src/rollcontact_fmu/workarounds.py`` under a name of its own (the FMUs of this process keep theirs)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "fmu_src" / "rollcontact_fmu" / "workarounds.py"
    spec = importlib.util.spec_from_file_location("rollcontact_fmu_workarounds_under_test", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class FakeLogger:
    """A ``PyLogger`` as bytes: flag at 8, ``std::string`` name at 16, ``std::vector<std::string>`` at 48."""

    def __init__(self, name: bytes, flag: int, categories: tuple[bytes, ...]):
        import ctypes

        self.block = ctypes.create_string_buffer(80)
        self.strings = ctypes.create_string_buffer(32 * max(len(categories), 1))
        self.heap = [ctypes.create_string_buffer(text) for text in (name, *categories)]  # long strings' storage
        self.address = ctypes.addressof(self.block)
        ctypes.c_uint8.from_address(self.address + 8).value = flag
        self.write_string(self.address + 16, name, self.heap[0])
        first = ctypes.addressof(self.strings)
        for k, text in enumerate(categories):
            self.write_string(first + 32 * k, text, self.heap[1 + k])
        for offset, value in ((48, first), (56, first + 32 * len(categories)), (64, first + 32 * len(categories))):
            ctypes.c_size_t.from_address(self.address + offset).value = value if categories else 0

    @staticmethod
    def write_string(address: int, text: bytes, storage) -> None:
        import ctypes

        local = len(text) <= 15
        data = address + 16 if local else ctypes.addressof(storage)
        ctypes.c_size_t.from_address(address).value = data
        ctypes.c_size_t.from_address(address + 8).value = len(text)
        if local:
            ctypes.memmove(address + 16, text, len(text))
        else:
            ctypes.c_size_t.from_address(address + 16).value = len(text)  # capacity


@pytest.mark.skipif(sys.platform != "linux", reason="the layout is read on 64-bit Linux only")
@pytest.mark.parametrize(("name", "flag", "categories", "expected"), [
    (b"rc", 0, (), None),
    (b"rc", 1, (), ()),
    (b"an instance name longer than fifteen bytes", 1, (b"logStatusError",), ("logStatusError",)),
    (b"rc", 1, (b"logStatusDiscard", b"logStatusError"), ("logStatusDiscard", "logStatusError")),
])
def test_the_logger_object_is_read_as_pythonfmu_lays_it_out(name, flag, categories, expected):
    fake = FakeLogger(name, flag, categories)
    assert slave_base().logger_categories(fake.address, name.decode()) == expected


@pytest.mark.skipif(sys.platform != "linux", reason="the layout is read on 64-bit Linux only")
@pytest.mark.parametrize("case", ["another name", "flag 2", "vector ends before it begins", "no address"])
def test_a_logger_object_of_another_layout_is_refused(case):
    import ctypes

    fake = FakeLogger(b"rc", 1, (b"logStatusError",))
    name = "rc"
    if case == "another name":
        name = "rd"
    elif case == "flag 2":
        ctypes.c_uint8.from_address(fake.address + 8).value = 2
    elif case == "vector ends before it begins":
        ctypes.c_size_t.from_address(fake.address + 56).value -= 64
    address = 0 if case == "no address" else fake.address
    with pytest.raises(ValueError, match="layout"):
        slave_base().logger_categories(address, name)
