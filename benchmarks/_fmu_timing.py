"""Shared FMU step timing through fmpy: an empty pythonfmu FMU (the floor of any pythonfmu step) and stepped cases.

One step is what a co-simulation master does per communication point: set the 3 inputs, ``doStep``, get the 10
real and 1 integer outputs (fmpy's ``FMU2Slave``).  The empty FMU has the same inputs and outputs and a
``do_step`` that only returns True.  Used by ``bench_fmu.py`` and ``pareto.py``.
"""

from __future__ import annotations

import math
import statistics
import textwrap
import time
from pathlib import Path

from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave

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


def build_and_extract(tmp: Path, build_contact) -> tuple[str, str]:
    """Build the empty FMU and (with ``build_contact(dest) -> path``) the contact FMU in ``tmp``; unzip both.

    Returns the two unzip directories ``(empty, contact)``.
    """
    from pythonfmu.builder import FmuBuilder

    (tmp / "src").mkdir(exist_ok=True)
    empty_script = tmp / "src" / "rollcontact_bench_empty_slave.py"
    empty_script.write_text(EMPTY_SLAVE)
    empty_fmu = FmuBuilder.build_FMU(empty_script, dest=tmp)
    contact_fmu = build_contact(tmp)
    return extract(empty_fmu, unzipdir=tmp / "empty"), extract(contact_fmu, unzipdir=tmp / "contact")


class Case:
    """One initialised FMU instance stepped with slowly varying inputs (load 20 kN +-5 %, creep +-1e-3), or with the
    constant inputs ``fixed = (normal_load [N], creep [1])``, by communication steps of ``step_size`` [s];
    ``before_step()``, if given, runs before each step (inside the timing)."""

    def __init__(self, label: str, unzipped: str, parameters: dict, steps_per_batch: int, velocity: float,
                 fixed: tuple[float, float] | None = None, step_size: float = 1e-3, before_step=None):
        self.label, self.steps_per_batch, self.velocity = label, steps_per_batch, velocity
        self.fixed, self.step_size, self.before_step = fixed, step_size, before_step
        md = read_model_description(unzipped)
        variables = {v.name: v for v in md.modelVariables}
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=label)
        self.fmu.instantiate()
        setters = {"Integer": self.fmu.setInteger, "Real": self.fmu.setReal, "String": self.fmu.setString}
        for name, value in parameters.items():
            setters[variables[name].type]([variables[name].valueReference], [value])
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.inputs = [v.valueReference for v in md.modelVariables if v.causality == "input"]
        self.reals = [v.valueReference for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
        self.integers = [v.valueReference for v in md.modelVariables
                         if v.causality == "output" and v.type == "Integer"]
        assert len(self.inputs) == 3 and len(self.reals) == 10 and len(self.integers) == 1, label
        self.n = 0
        self.times: list[float] = []
        self.discards = 0
        self.methods_used: set[int] = set()

    def batch(self) -> None:
        """Time ``steps_per_batch`` steps; record microseconds per step."""
        fmu, inputs, reals, integers, v = self.fmu, self.inputs, self.reals, self.integers, self.velocity
        h, fixed, before = self.step_size, self.fixed, self.before_step
        n0 = self.n
        used = []
        start = time.perf_counter()
        for n in range(n0, n0 + self.steps_per_batch):
            if fixed is None:
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
        self.fmu.terminate()
        self.fmu.freeInstance()


def run_interleaved(cases: list[Case], rounds: int) -> None:
    """Warm every case up (imports, caches), then time ``rounds`` rounds of one batch per case, interleaved so
    that a noisy machine affects every case alike."""
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
                     budget: float, min_batches: int = 3, before_step=None) -> tuple[float, int]:
    """Median microseconds per fmpy step of a fresh instance with ``parameters``, stepped with the constant
    ``inputs = (normal_load [N], creep [1])`` at ``velocity`` [m/s] by :data:`STEADY_STEP`: batches of at least
    ~2 ms (at least ``min_batches``, up to ``budget`` [s] of them) after one step of warm-up (imports, caches), with
    ``before_step`` run before each step (:class:`Case`).  Also the number of discarded steps."""
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
    """``scene`` as the TOML text of a scene file for the contact FMU's ``scene_file`` parameter.

    The FMU reads the file's surface in its own frame and solves the mirrored scene with the axis at ``-X``
    (:mod:`rollcontact.model`), so the file holds the mirror of the scene's surface
    (:func:`rollcontact.model.mirrored` is its own inverse); start the FMU at ``initial_position =
    -scene.axis_position``.  The load, creep, axis and speed in the file are placeholders: the FMU's inputs replace
    them.
    """
    import rollcontact as rc
    from rollcontact.model import mirrored

    return rc.scene_toml(scene.replace(surface=mirrored(scene.surface)))
