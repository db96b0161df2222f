"""Microseconds per RollingContact2D FMU step through fmpy, against an empty pythonfmu FMU measured in the same run.

One step is what a co-simulation master does per communication point: set the 3 inputs, ``doStep``, get the 10
real and 1 integer outputs (fmpy's ``FMU2Slave``).  The empty FMU has the same inputs and outputs and a
``do_step`` that only returns True: its time is the floor of any pythonfmu FMU.  Cases: the closed form (smooth
surface, Coulomb friction), and the polynomial and discretised methods (corrugated surface) when registered.
Batches of steps of all cases are interleaved and the table shows medians, so that a noisy machine affects every
case alike.  One BLAS thread (``common.py``).  Usage: ``python benchmarks/bench_fmu.py [--rounds N]``.

What it prints goes to ``benchmarks/results/fmu_steps.md`` with the machine (not after ``--quick``).
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from functools import partial
from pathlib import Path

import common  # before numpy: limits BLAS to one thread; puts the checkout on sys.path

import rollcontact
from build_fmu import build


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=30, help="interleaved rounds (default 30)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="bench_fmu_") as tmp:
        empty_dir, contact_dir = common.build_and_extract(Path(tmp), partial(build, "RollingContact2D"))
        cases = [common.Case("empty pythonfmu", empty_dir, {}, 200, 1.0),
                 common.Case("closed form", contact_dir, {"method": 1}, 200, 20.0)]
        if "polynomial" in rollcontact.METHODS:
            cases.append(common.Case("polynomial", contact_dir, {"method": 2, **common.FMU_CORRUGATION}, 10, 1.0))
        if "discretised" in rollcontact.METHODS:
            cases.append(common.Case("discretised", contact_dir, {"method": 3, **common.FMU_CORRUGATION}, 2, 1.0))
        common.run_interleaved(cases, args.rounds)
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
    common.run_and_publish(main, "fmu_steps.md")
