"""Microseconds per RollingContact2D FMU step, FMI 3.0 against FMI 2.0, each against its empty FMU, in one run.

One step is what a co-simulation master does per communication point: set the 3 inputs, ``doStep``, get the 10
real and 1 integer outputs, through fmpy's ``FMU2Slave`` (FMI 2.0, pythonfmu) or ``FMU3Slave`` (FMI 3.0,
pythonfmu3, behind the same calls: ``rollcontact_cosim.master.FMU3Calls``).  The empty FMUs have the same inputs
and outputs and a ``do_step`` that only returns True: the floor of any pythonfmu / pythonfmu3 step.  Cases: the
empty FMUs, the closed form (smooth surface, Coulomb friction) and the polynomial method (corrugated surface), when
registered.  Batches of all cases are interleaved and the table shows medians, so that a noisy machine affects
every case alike; one BLAS thread (``common.py``).  Usage: ``python benchmarks/bench_fmi3.py [--rounds N]``.

What it prints goes to ``benchmarks/results/fmi3.md`` with the machine (not after ``--quick``).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import textwrap
from functools import partial
from pathlib import Path

import common  # before numpy: limits BLAS to one thread; puts the checkout on sys.path

import rollcontact
from build_fmu import build

EMPTY_SLAVE3 = textwrap.dedent('''
    """Empty pythonfmu3 slave with RollingContact2D's inputs and outputs: the floor of a pythonfmu3 step."""
    from pythonfmu3 import Fmi3Causality, Fmi3Slave, Fmi3Variability, Float64, Int32


    class EmptyContact3(Fmi3Slave):
        def __init__(self, **kwargs):
            super().__init__(**kwargs)
            self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                           variability=Fmi3Variability.continuous))
            for name in ("normal_load", "creep", "velocity"):
                setattr(self, name, 0.0)
                self.register_variable(Float64(name, causality=Fmi3Causality.input,
                                               variability=Fmi3Variability.continuous))
            for i in range(10):
                setattr(self, f"y{i}", 0.0)
                self.register_variable(Float64(f"y{i}", causality=Fmi3Causality.output,
                                               variability=Fmi3Variability.continuous))
            self.method_used = 0
            self.register_variable(Int32("method_used", causality=Fmi3Causality.output,
                                         variability=Fmi3Variability.discrete))

        def do_step(self, current_time, step_size):
            return True
''')
"""Source of the empty pythonfmu3 slave."""


class Case3(common.Case):
    """:class:`common.Case` on an FMI 3.0 FMU (an ``.fmu`` file): instantiated and initialised through
    ``rollcontact_cosim.master.Slave``, stepped by the same :meth:`common.Case.batch`."""

    def __init__(self, label: str, fmu: Path, parameters: dict, steps_per_batch: int, velocity: float):
        from rollcontact_cosim.master import INTEGER_TYPES, REAL_TYPES, Slave

        self.slave = Slave(fmu, label)
        self.slave.set_start_values(parameters)
        self.slave.fmu.setupExperiment(startTime=0.0)
        self.slave.fmu.enterInitializationMode()
        self.slave.fmu.exitInitializationMode()
        self.fmu = self.slave.fmu
        outputs = [v for v in self.slave.description.modelVariables if v.causality == "output"]
        self.inputs = [v.valueReference for v in self.slave.description.modelVariables if v.causality == "input"]
        self.reals = [v.valueReference for v in outputs if v.type in REAL_TYPES]
        self.integers = [v.valueReference for v in outputs if v.type in INTEGER_TYPES]
        assert len(self.inputs) == 3 and len(self.reals) == 10 and len(self.integers) == 1, label
        self.label, self.steps_per_batch, self.velocity = label, steps_per_batch, velocity
        self.fixed, self.step_size, self.before_step, self.signal = None, 1e-3, None, None
        self.n, self.times, self.discards, self.methods_used = 0, [], 0, set()


def build_fmi3(tmp: Path) -> tuple[Path, Path]:
    """The empty FMI 3.0 FMU and the FMI 3.0 contact FMU, built into ``tmp``."""
    from pythonfmu3 import FmuBuilder

    script = tmp / "src3" / "rollcontact_bench_empty_slave3.py"
    script.parent.mkdir()
    script.write_text(EMPTY_SLAVE3)
    return Path(FmuBuilder.build_FMU(script, dest=tmp / "empty3")), build("RollingContact2D", tmp / "fmi3", fmi=3)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=30, help="interleaved rounds (default 30)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench_fmi3_") as tmp:
        empty2, contact2 = common.build_and_extract(Path(tmp), partial(build, "RollingContact2D"))
        empty3, contact3 = build_fmi3(Path(tmp))
        rows = [("empty FMU", {}, 200, 1.0), ("closed form", {"method": 1}, 200, 20.0)]
        if "polynomial" in rollcontact.METHODS:
            rows.append(("polynomial", {"method": 2, **common.FMU_CORRUGATION}, 10, 1.0))
        cases = {}
        for label, parameters, steps, velocity in rows:
            empty = label == "empty FMU"
            cases[label, 2] = common.Case(f"{label} FMI 2.0", empty2 if empty else contact2, parameters, steps,
                                          velocity)
            cases[label, 3] = Case3(f"{label} FMI 3.0", empty3 if empty else contact3, parameters, steps, velocity)
        common.run_interleaved(list(cases.values()), args.rounds)
        median = {key: statistics.median(case.times) for key, case in cases.items()}
        print(f"fmpy {__import__('fmpy').__version__}, pythonfmu {__import__('pythonfmu').__version__}, pythonfmu3 "
              f"{__import__('pythonfmu3').__version__}, Python {sys.version.split()[0]}, {args.rounds} rounds; one "
              "step = set 3 inputs + doStep + get 10 reals + get 1 integer; medians in us per step\n")
        print("| case | FMI 2.0 | FMI 3.0 | FMI 3.0 / FMI 2.0 | FMI 2.0 above empty | FMI 3.0 above empty | "
              "steps (each) | discarded |")
        print("|---|---:|---:|---:|---:|---:|---:|---:|")
        for label, *_ in rows:
            two, three = median[label, 2], median[label, 3]
            above = ("", "") if label.startswith("empty") else (f"{two - median['empty FMU', 2]:.1f}",
                                                                f"{three - median['empty FMU', 3]:.1f}")
            discarded = cases[label, 2].discards + cases[label, 3].discards
            print(f"| {label} | {two:.1f} | {three:.1f} | {three / two:.2f} | {above[0]} | {above[1]} | "
                  f"{cases[label, 2].steps_per_batch * len(cases[label, 2].times)} | {discarded} |")
        for case in cases.values():
            case.free()


if __name__ == "__main__":
    common.run_and_publish(main, "fmi3.md")
