"""Shared set-up and timing of the benchmark scripts: environment, median times, cold solves, FMU steps through fmpy.

Import it in a script as ``import common``, before numpy, scipy or rollcontact (among the third-party imports a
straight import sorts first, so ruff's isort keeps it there).  Importing it

* limits BLAS to one thread (``OPENBLAS_NUM_THREADS`` and ``OMP_NUM_THREADS`` = 1 unless already set): OpenBLAS reads
  them once, when numpy is first imported, so the limit only holds if this module is imported before numpy.  One
  thread: the solvers' matrices are small, threads only add overhead on the shared 2-core machines, and the times
  compare with CONTACT's single-core figures;
* puts the checkout's ``src/`` (the ``rollcontact`` package of this checkout, not an installed one) and its root
  (``build_fmu.py``) at the front of ``sys.path``.

FMU timing: one step is what a co-simulation master does per communication point: set the 3 inputs, ``doStep``, get
the 10 real and 1 integer outputs (fmpy's ``FMU2Slave``).  An empty pythonfmu FMU with the same inputs and outputs
and a ``do_step`` that only returns True gives the floor of any pythonfmu step.  fmpy and pythonfmu are imported only
by the FMU helpers.
"""

from __future__ import annotations

import os
import sys

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import math  # noqa: E402  (after the thread limits, as everything below)
import statistics  # noqa: E402
import textwrap  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
"""The checkout's root directory."""
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "src"))

RESULTS = ROOT / "benchmarks" / "results"
"""Directory of the results files the benchmarks write."""

CONTACT_WIDTH = 0.02
"""Lateral contact width [m]: the FMU's default ``contact_width``, also used to turn loads per length into loads."""

FMU_CORRUGATION = {"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.04}
"""FMU parameters of the corrugated rail of the FMU step cases: 20 um amplitude [m], 40 mm wavelength [m]."""


# ------------------------------------------------------------------------------------------------------ timing
def median_time(function: Callable[[], object], min_repeats: int = 5, min_seconds: float = 0.3, warmups: int = 1,
                batch_seconds: float = 0.0, max_repeats: float = math.inf) -> float:
    """Median wall time of one call of ``function``.

    Parameters
    ----------
    function
        Called without arguments; its result is ignored.
    min_repeats
        Least number of timed samples.
    min_seconds
        Samples are taken for at least this long [s] (after ``min_repeats``, up to ``max_repeats``).
    warmups
        Untimed calls first (imports, size-keyed caches); at least 1 when ``batch_seconds`` > 0.
    batch_seconds
        0: a sample is one call.  Otherwise a sample is a batch of calls lasting about this long [s] (timeit style:
        the number of calls from the time of the last warm-up call, at least 1), and its time is divided by the
        number of calls.
    max_repeats
        Most samples taken once ``min_repeats`` are in.

    Returns
    -------
    float
        Median time per call [s].
    """
    if batch_seconds > 0.0 and warmups < 1:
        raise ValueError("batch_seconds needs a warm-up call to size the batches")
    single = 0.0
    for _ in range(warmups):
        t0 = time.perf_counter()
        function()
        single = max(time.perf_counter() - t0, 1e-7)
    number = max(1, int(batch_seconds / single)) if batch_seconds > 0.0 else 1
    samples = []
    start = time.perf_counter()
    while len(samples) < min_repeats or (time.perf_counter() - start < min_seconds and len(samples) < max_repeats):
        if number == 1:
            t0 = time.perf_counter()
            function()
            samples.append(time.perf_counter() - t0)
        else:
            t0 = time.perf_counter()
            for _ in range(number):
                function()
            samples.append((time.perf_counter() - t0) / number)
    return statistics.median(samples)


def influence_cache_clear() -> Callable[[], None]:
    """The function that empties rollcontact's cache of influence matrices and their factorisations.

    Returns
    -------
    callable
        ``rollcontact.core.halfspace.elements.operators_for.cache_clear``: after it, a discretised solve builds its
        matrices again, as the first solve on a grid does.
    """
    from rollcontact.core.halfspace.elements import operators_for

    return operators_for.cache_clear


def cold(function: Callable[[], object], method: str = "discretised") -> Callable[[], object]:
    """``function`` timed as a first solve on its grid.

    Parameters
    ----------
    function
        A solve, called without arguments.
    method
        The method ``function`` runs.  Only the discretised solver caches per grid.

    Returns
    -------
    callable
        For ``method`` = "discretised": a function that empties the cache of influence matrices
        (:func:`influence_cache_clear`) and then returns ``function()``.  For any other method: ``function`` itself.
    """
    if method != "discretised":
        return function
    clear = influence_cache_clear()

    def run():
        clear()
        return function()
    return run


# --------------------------------------------------------------------------------------------------- FMU steps
EMPTY_SLAVE = textwrap.dedent('''
    """Empty pythonfmu slave with RollingContact2D's inputs and outputs: the floor of a pythonfmu step."""
    from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Integer, Real


    class EmptyContact2D(Fmi2Slave):
        def __init__(self, **kwargs):
            super().__init__(**kwargs)
            for name in ("normal_load", "creep", "velocity"):
                setattr(self, name, 0.0)
                self.register_variable(Real(name, causality=Fmi2Causality.input,
                                            variability=Fmi2Variability.continuous))
            for i in range(10):
                setattr(self, f"y{i}", 0.0)
                self.register_variable(Real(f"y{i}", causality=Fmi2Causality.output,
                                            variability=Fmi2Variability.continuous))
            self.method_used = 0
            self.register_variable(Integer("method_used", causality=Fmi2Causality.output,
                                           variability=Fmi2Variability.discrete))

        def do_step(self, current_time, step_size):
            return True
''')
"""Source of the empty pythonfmu slave (:func:`build_and_extract`)."""


def build_and_extract(tmp: Path, build_contact: Callable[[Path], Path]) -> tuple[str, str]:
    """Build the empty FMU and the contact FMU and unzip both.

    Parameters
    ----------
    tmp
        Directory for the sources, the FMUs and the unzipped files.
    build_contact
        ``build_contact(dest) -> path`` builds the contact FMU into ``dest`` (``partial(build_fmu.build,
        "RollingContact2D")``).

    Returns
    -------
    tuple of str
        The unzip directories ``(empty, contact)``.
    """
    from fmpy import extract
    from pythonfmu.builder import FmuBuilder

    (tmp / "src").mkdir(exist_ok=True)
    empty_script = tmp / "src" / "rollcontact_bench_empty_slave.py"
    empty_script.write_text(EMPTY_SLAVE)
    empty_fmu = FmuBuilder.build_FMU(empty_script, dest=tmp)
    contact_fmu = build_contact(tmp)
    return extract(empty_fmu, unzipdir=tmp / "empty"), extract(contact_fmu, unzipdir=tmp / "contact")


class Case:
    """One initialised FMU instance, stepped and timed in batches of steps.

    Inputs: slowly varying (normal load 20 kN +-5 %, creep +-1e-3) or, with ``fixed``, constant.

    Parameters
    ----------
    label
        Name of the case (and of the FMU instance).
    unzipped
        Unzip directory of the FMU.
    parameters
        FMU parameters by name, set before initialisation.
    steps_per_batch
        Steps timed together in :meth:`batch`.
    velocity
        Rolling speed input [m/s].
    fixed
        Constant inputs ``(normal_load [N], creep [1])``; None: the varying ones.
    step_size
        Communication step [s].
    before_step
        Called before each step, inside the timing; None: nothing.
    signal
        ``signal(n) -> (normal_load [N], creep [1])`` of step n, replacing the default varying inputs.
    """

    def __init__(self, label: str, unzipped: str, parameters: dict, steps_per_batch: int, velocity: float,
                 fixed: tuple[float, float] | None = None, step_size: float = 1e-3,
                 before_step: Callable[[], object] | None = None,
                 signal: Callable[[int], tuple[float, float]] | None = None):
        from fmpy import read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.label, self.steps_per_batch, self.velocity = label, steps_per_batch, velocity
        self.fixed, self.step_size, self.before_step, self.signal = fixed, step_size, before_step, signal
        md = read_model_description(unzipped)
        variables = {v.name: v for v in md.modelVariables}
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=label)
        self.fmu.instantiate()
        setters = {"Integer": self.fmu.setInteger, "Enumeration": self.fmu.setInteger, "Real": self.fmu.setReal,
                   "String": self.fmu.setString}
        for name, value in parameters.items():
            setters[variables[name].type]([variables[name].valueReference], [value])
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.inputs = [v.valueReference for v in md.modelVariables if v.causality == "input"]
        self.reals = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
        self.integers = [v.valueReference for v in md.modelVariables
                         if v.causality == "output" and v.type in ("Integer", "Enumeration")]
        assert len(self.inputs) == 3 and len(self.reals) == 10 and len(self.integers) == 1, label
        self.n = 0
        self.times: list[float] = []  # microseconds per step of each timed batch
        self.discards = 0  # steps the FMU discarded
        self.methods_used: set[int] = set()  # the method_used outputs seen

    def batch(self) -> None:
        """Time ``steps_per_batch`` steps; append the microseconds per step to :attr:`times`."""
        from fmpy.fmi1 import FMICallException

        fmu, inputs, reals, integers, v = self.fmu, self.inputs, self.reals, self.integers, self.velocity
        h, fixed, before = self.step_size, self.fixed, self.before_step
        n0 = self.n
        used = []
        start = time.perf_counter()
        signal = self.signal
        for n in range(n0, n0 + self.steps_per_batch):
            if signal is not None:
                load, creep = signal(n)
                fmu.setReal(inputs, [load, creep, v])
            elif fixed is None:
                phase = 0.01 * n
                fmu.setReal(inputs, [2e4 * (1.0 + 0.05 * math.sin(phase)), 1e-3 * math.cos(phase), v])
            else:
                fmu.setReal(inputs, [fixed[0], fixed[1], v])
            if before is not None:
                before()
            try:
                fmu.doStep(n * h, h)
            except FMICallException:
                self.discards += 1
            fmu.getReal(reals)
            used.append(fmu.getInteger(integers)[0])
        self.times.append((time.perf_counter() - start) / self.steps_per_batch * 1e6)
        self.methods_used.update(used)
        self.n = n0 + self.steps_per_batch

    def free(self) -> None:
        """Terminate and free the FMU instance."""
        self.fmu.terminate()
        self.fmu.freeInstance()


def run_interleaved(cases: list[Case], rounds: int) -> None:
    """Time ``rounds`` rounds of one batch per case, interleaved so that a noisy machine affects every case alike.

    Parameters
    ----------
    cases
        The cases; each is first warmed up by one untimed batch (imports, caches).
    rounds
        Timed batches per case.
    """
    for case in cases:
        case.batch()
        case.times.clear()
    for _ in range(rounds):
        for case in cases:
            case.batch()


STEADY_STEP = 1e-9
"""Communication step [s] of :func:`steady_step_time`: the axis rolls ``V h`` (20 nm at 20 m/s) per step, so a few
thousand steps see the scene of the case, not a different place on a corrugation."""


def steady_step_time(unzipped: str, parameters: dict, inputs: tuple[float, float], velocity: float,
                     budget: float, min_batches: int = 3,
                     before_step: Callable[[], object] | None = None) -> tuple[float, int]:
    """Time per fmpy step of a fresh FMU instance with constant inputs, stepped by :data:`STEADY_STEP`.

    After one step of warm-up (imports, caches), batches of at least ~2 ms are timed.

    Parameters
    ----------
    unzipped
        Unzip directory of the FMU.
    parameters
        FMU parameters by name.
    inputs
        ``(normal_load [N], creep [1])``.
    velocity
        Rolling speed [m/s].
    budget
        Time [s] for the batches: at least ``min_batches``, then more while within it (at most 200).
    min_batches
        Least number of batches.
    before_step
        Called before each step, inside the timing (:class:`Case`).

    Returns
    -------
    tuple
        Median microseconds per step, and the number of discarded steps.
    """
    case = Case("steady", unzipped, parameters, 1, velocity, fixed=inputs, step_size=STEADY_STEP,
                before_step=before_step)
    try:
        case.batch()
        case.steps_per_batch = max(1, int(2e3 / max(case.times[0], 1e-3)))
        case.times.clear()
        start = time.perf_counter()
        while len(case.times) < min_batches or (time.perf_counter() - start < budget and len(case.times) < 200):
            case.batch()
        return statistics.median(case.times), case.discards
    finally:
        case.free()


def scene_toml(scene) -> str:
    """A scene as the TOML text of a scene file for the contact FMU's ``scene_file`` parameter.

    The FMU reads the file's surface in its own frame and solves the mirrored scene with the axis at ``-X``
    (:mod:`rollcontact.stepping`), so the file holds the mirror of the scene's surface
    (:func:`rollcontact.stepping.line.model.mirrored` is its own inverse); start the FMU at ``initial_position =
    -scene.axis_position``.  The load, creep, axis and speed in the file are placeholders: the FMU's inputs replace
    them.

    Parameters
    ----------
    scene : rollcontact.Scene
        The scene.

    Returns
    -------
    str
        The file's text.
    """
    import rollcontact as rc
    from rollcontact.stepping.line.model import mirrored

    return rc.scene_toml(scene.replace(surface=mirrored(scene.surface)))


def machine(load: float) -> list[str]:
    """The machine's description, markdown list lines; ``load``: the 1-minute load average read before the study
    started (read at the end it would count the study's own process)."""
    import platform

    import numpy as np
    import scipy

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            cpu = next(line.split(":", 1)[1].strip() for line in fh if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    blas = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
    return [f"- CPU: {cpu}, {os.cpu_count()} logical cores (shared with other jobs; load average at start "
            f"{load:.2f})",
            f"- Python {platform.python_version()} ({platform.python_implementation()}), numpy {np.__version__}, "
            f"scipy {scipy.__version__}, {blas.get('name', '?')} {blas.get('version', '')}",
            f"- BLAS threads: OPENBLAS_NUM_THREADS = {os.environ.get('OPENBLAS_NUM_THREADS')}, "
            f"OMP_NUM_THREADS = {os.environ.get('OMP_NUM_THREADS')}",
            f"- {platform.platform()}"]


class Tee:
    """A text stream writing to each of ``streams``."""

    def __init__(self, *streams):
        self.streams = streams

    def write(self, text: str) -> int:
        for stream in self.streams:
            stream.write(text)
        return len(text)

    def flush(self) -> None:
        for stream in self.streams:
            stream.flush()


def run_and_publish(main: Callable[[], object], name: str) -> None:
    """Run the study ``main`` (a script that prints its markdown tables) and write what it printed to
    ``RESULTS / name``, followed by the command that ran it and the machine (:func:`machine`, with the load average
    read before the study).  Nothing is written after ``--quick`` or ``--help``, nor when the study fails."""
    import contextlib
    import io

    load = os.getloadavg()[0]
    printed = io.StringIO()
    with contextlib.redirect_stdout(Tee(sys.stdout, printed)):
        main()
    if any(arg in ("--quick", "-h", "--help") for arg in sys.argv[1:]):
        return
    command = " ".join(["python", f"benchmarks/{Path(sys.argv[0]).name}", *sys.argv[1:]])
    RESULTS.mkdir(parents=True, exist_ok=True)
    (RESULTS / name).write_text(f"{printed.getvalue().rstrip()}\n\nRun by `{command}` on:\n\n"
                                + "\n".join(machine(load)) + "\n")
    print(f"wrote {RESULTS / name}")


def publish(lines: list[str], name: str, quick: bool) -> None:
    """Print a benchmark's markdown ``lines`` and, unless ``quick``, write them to ``RESULTS / name``."""
    text = "\n".join(lines) + "\n"
    print(text)
    if not quick:
        (RESULTS / name).write_text(text)
