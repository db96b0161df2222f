"""Speed-accuracy Pareto study: every method and setting on every scene family, error vs time, and auto's choices.

Run ``.venv/bin/python benchmarks/pareto.py [--quick] [--no-fmu]``: writes ``benchmarks/results/pareto.md``
(tables, headline ratios, machine) and ``benchmarks/results/pareto.png`` (error vs time per family, the Pareto front
of each case, auto's choice at each requested tolerance).  ``--quick`` is a smoke test (< 60 s: one case per family,
few settings, small references); the full study takes several minutes.  One BLAS thread.

Modules: ``pareto_cases.py`` (configurations, scene families, settings, references, records),
``instationary_case.py`` (the instationary scenario, shared with the transient benchmarks), ``pareto_elliptic.py``
(the elliptic family: every 3D level against the discretised 3D reference), ``pareto_measure.py``
(the measurements), ``pareto_analysis.py`` (fronts, equal-accuracy ratios, cost-model fit), ``pareto_report.py``
(markdown and figure), ``common.py`` (timing, FMU steps).

Error. Steady scenes: the larger relative error of T' and of the peak pressure p0 against a converged reference (the
contract of ``solve(scene, tolerance=t)``); for discretised settings the largest over four grid placements (the window
shifted by 0, 1/4, 1/2, 3/4 of an element, :data:`pareto_cases.PLACEMENTS`): where the patch edges fall in their
elements moves the answer by about its error, and in use that placement is arbitrary. References: the closed form where
exact (Hertz/Carter); otherwise the polynomial method at truncation tolerance 1e-12 (1024 slip nodes for
velocity-dependent friction), cross-checked against the Richardson-extrapolated discretised solver (n = 800/1600 on a
window of +-1.25 a about the patch, whose edges then fall on element boundaries, as in ``tests/test_cross_methods.py``);
for a split contact (several patches, ``rollcontact.line.methods.polynomial.patches``) against the first-order
Richardson extrapolation of the discretised T' from n = 2000/4000, each level the mean over 8 grid placements on a
window fitted to the patches; a contact the polynomial method cannot treat would take that extrapolation as its
reference (:func:`pareto_cases.split_reference`), its uncertainty shown as the change from n = 1000/2000. The
extrapolated discretised settings (``extrapolate`` = m = 8, 16: n/2n, each level the mean over m placements) average
over placements themselves and are measured as they run. Instationary rolling (creep control, ``xi = (0.5 + 0.3 sin(2 pi
sigma/lambda)) mu a/R`` at lambda/a = 5..40, and a creep reversal ``0.9 sin`` at lambda/a = 5, where the relaxation lag
errs most; 64 host steps per cycle): max |T' - T'_ref| over the last cycle in units of mu N', reference the
extrapolating transient pair n = 500/1000 (nested grids, second order: ``calibrate_transient_pairs.py``; the plain
transient's on the same finest grid shown). Every instationary setting, the transients in the rows and the reference
included, steps the FMU's model (quasi-static: ``transient`` = 0; relaxation: 2; transient: ``method`` = 3,
``transient`` = 2, ``elements`` = n; pair: that model with the extrapolating transient swapped in,
:func:`instationary_case.pair_stepper`): the grids auto's transient runs on (window about +-1.77 a, the Hertz patch
edges on element boundaries, ``ContactModel.prepare_grid``) and the model's overhead, so auto and the rows compare like
for like.

Time. Median over repeated calls (timeit-style batches, at least 3 samples); discretised solves with the caches of
influence matrices emptied first (a first solve on a new grid, as for a moving axis); instationary: median per host
step. FMU: microseconds per fmpy step (set inputs, doStep, get outputs) against an empty pythonfmu FMU built in the
same run (``common.py``): for every steady setting that an FMU parameter selects (closed form: ``method`` = 1;
polynomial: 2 with its ``tolerance`` or ``polynomial_order``; discretised: 3 with ``elements``) and for auto
(``method`` = 0, ``tolerance`` = t), a fresh contact FMU reading the case's scene from a scene file
(``common.scene_toml``; its model solves exactly the case's scene) with the case's load, creep and speed as
constant inputs, stepped by 1 ns so the axis stays where the case puts it (``common.steady_step_time``: caches warm
after a first step, as along a run); and a few cases with varying inputs against the empty FMU
(``pareto_measure.fmu_study``).  The machine is shared and noisy: compare ratios measured in the same run, not
absolute times across runs.
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile
import time
from pathlib import Path

import common  # before numpy: limits BLAS to one thread
from pareto_cases import FULL, QUICK, Reference, steady_cases
from pareto_elliptic import elliptic_study
from pareto_measure import FmuBench, fmu_study, instationary_study, measure_case
from pareto_report import plot, report

from rollcontact_cosim.cli import Progress

RESULTS = common.RESULTS


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="smoke test (< 60 s)")
    parser.add_argument("--no-fmu", action="store_true", help="skip the FMU step timing")
    args = parser.parse_args(argv)
    config = QUICK if args.quick else FULL
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else math.nan
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="pareto_fmu_") as tmp:
        bench = None
        if not args.no_fmu:
            from functools import partial

            from build_fmu import build

            print("building the FMUs", flush=True)
            bench = FmuBench(*common.build_and_extract(Path(tmp), partial(build, "RollingContact2D")), Path(tmp))
        rows, choices, references = [], [], {}
        cases = [(family, label, scene) for family, listed in steady_cases(config).items() for label, scene in listed]
        with Progress(len(cases) + 2 + (bench is not None), "cases") as progress:
            for family, label, scene in cases:
                progress.advance(0, f"{family}: {label}")
                case_rows, case_choices, ref = measure_case(family, label, scene, config, bench)
                rows += case_rows
                choices += case_choices
                references[(family, label)] = ref
                progress.advance()
            progress.advance(0, "instationary")
            inst_rows, inst_choices, inst_refs = instationary_study(config)
            rows += inst_rows
            choices += inst_choices
            progress.advance()
            progress.advance(0, "elliptic (3D)")
            ell_rows, ell_choices, ell_refs = elliptic_study(config.quick)
            rows += ell_rows
            choices += ell_choices
            references.update({(row.family, case): Reference(None, how) for row in ell_rows[:1]
                               for case, how in ell_refs})
            progress.advance()
            fmu = []
            if bench is not None:
                progress.advance(0, "FMU steps")
                fmu = fmu_study(config, bench)
                progress.advance()
    RESULTS.mkdir(parents=True, exist_ok=True)
    plot(rows, choices, RESULTS / "pareto.png")
    report(config, rows, choices, references, inst_refs, fmu, time.perf_counter() - start, load,
           RESULTS / "pareto.md")
    print(f"wrote {RESULTS / 'pareto.md'} and {RESULTS / 'pareto.png'} in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
