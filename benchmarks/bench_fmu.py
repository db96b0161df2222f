"""Microseconds per RollingContact2D FMU step through fmpy, against an empty pythonfmu FMU measured in the same run.

One step is what a co-simulation master does per communication point: set the 3 inputs, ``doStep``, get the 10
real and 1 integer outputs (fmpy's ``FMU2Slave``).  The empty FMU has the same inputs and outputs and a
``do_step`` that only returns True: its time is the floor of any pythonfmu FMU.  Cases: the closed form (smooth
surface, Coulomb friction), and the polynomial and discretised methods (corrugated surface) when registered.
Batches of steps of all cases are interleaved and the table shows medians, so that a noisy machine affects every
case alike.  Usage: ``python benchmarks/bench_fmu.py [--rounds N]``.
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
import textwrap
import time
from pathlib import Path

from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "src"))

import rollcontact  # noqa: E402  (after the path set-up, as a script)
from build_fmu import build  # noqa: E402

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

CORRUGATION = {"corrugation_amplitude": 20e-6, "corrugation_wavelength": 0.04}


class Case:
    """One initialised FMU instance stepped with slowly varying inputs."""

    def __init__(self, label: str, unzipped: str, parameters: dict, steps_per_batch: int, velocity: float):
        self.label, self.steps_per_batch, self.velocity = label, steps_per_batch, velocity
        md = read_model_description(unzipped)
        variables = {v.name: v for v in md.modelVariables}
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                             modelIdentifier=md.coSimulation.modelIdentifier, instanceName=label)
        self.fmu.instantiate()
        for name, value in parameters.items():
            (self.fmu.setInteger if variables[name].type == "Integer" else self.fmu.setReal)(
                [variables[name].valueReference], [value])
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

    def batch(self, h: float = 1e-3) -> None:
        """Time ``steps_per_batch`` steps; record microseconds per step."""
        fmu, inputs, reals, integers, v = self.fmu, self.inputs, self.reals, self.integers, self.velocity
        n0 = self.n
        start = time.perf_counter()
        for n in range(n0, n0 + self.steps_per_batch):
            phase = 0.01 * n
            fmu.setReal(inputs, [2e4 * (1.0 + 0.05 * math.sin(phase)), 1e-3 * math.cos(phase), v])
            try:
                fmu.doStep(n * h, h)
            except FMICallException:
                self.discards += 1
            fmu.getReal(reals)
            fmu.getInteger(integers)
        self.times.append((time.perf_counter() - start) / self.steps_per_batch * 1e6)
        self.n = n0 + self.steps_per_batch

    def free(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=30, help="interleaved rounds (default 30)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench_fmu_") as tmp:
        tmp = Path(tmp)
        (tmp / "src").mkdir()
        empty_script = tmp / "src" / "rollcontact_bench_empty_slave.py"
        empty_script.write_text(EMPTY_SLAVE)
        from pythonfmu.builder import FmuBuilder

        empty_fmu = FmuBuilder.build_FMU(empty_script, dest=tmp)
        contact_fmu = build(tmp)
        empty_dir = extract(empty_fmu, unzipdir=tmp / "empty")
        contact_dir = extract(contact_fmu, unzipdir=tmp / "contact")
        cases = [Case("empty pythonfmu", empty_dir, {}, 200, 1.0),
                 Case("closed form", contact_dir, {"method": 1}, 200, 20.0)]
        if "polynomial" in rollcontact.METHODS:
            cases.append(Case("polynomial", contact_dir, {"method": 2, **CORRUGATION}, 10, 1.0))
        if "discretised" in rollcontact.METHODS:
            cases.append(Case("discretised", contact_dir, {"method": 3, **CORRUGATION}, 2, 1.0))
        for case in cases:  # warm-up: imports, caches
            case.batch()
            case.times.clear()
        for _ in range(args.rounds):
            for case in cases:
                case.batch()
        floor = statistics.median(cases[0].times)
        print(f"fmpy {__import__('fmpy').__version__}, Python {sys.version.split()[0]}, {args.rounds} rounds; "
              "one step = setReal(3) + doStep + getReal(10) + getInteger(1)\n")
        print("| case | median us/step | min us/step | ratio to empty (median) | steps | discarded |")
        print("|---|---:|---:|---:|---:|---:|")
        for case in cases:
            median = statistics.median(case.times)
            print(f"| {case.label} | {median:.1f} | {min(case.times):.1f} | {median / floor:.2f} | "
                  f"{case.steps_per_batch * len(case.times)} | {case.discards} |")
        for case in cases:
            case.free()


if __name__ == "__main__":
    main()
