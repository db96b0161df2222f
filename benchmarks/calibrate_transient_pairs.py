"""The extrapolating discretised transient (a pair of nested grids, n/2 and n): error vs elements, time per step.

Run as ``.venv/bin/python benchmarks/calibrate_transient_pairs.py [--crosscheck] [--signals 0,2,...]`` (about 40
minutes; ``--signals`` runs a subset, e.g. to split the run over two processes; ``--crosscheck`` adds the plain
n = 800/1600 Richardson at lambda/a = 5 and 40, about 8 minutes more).  Prints markdown tables; asserts nothing.
One BLAS thread.

Scenario: the instationary study of ``benchmarks/pareto.py`` (its signal and steppers, ``instationary_case.py``):
N' = 1e7 N/m, mu = 0.3, R = 0.46 m, V = 10 m/s, creep control ``xi = (0.5 + 0.3 sin(2 pi sigma/lambda)) mu a/R``, 64
host steps per cycle, lambda/a = 5, 10, 20, 40, at least 40 a rolled before the measured last cycle, every transient
stepped through the FMU's model (``method`` = 3, ``transient`` = 2) from no traction.  Beyond the study's signal
(:data:`SIGNALS`): lambda/a = 1 and 2 (host steps shorter than an element of most grids), and a creep reversal
``0.9 sin`` at lambda/a = 5 and 20, so that the constant is known to hold beyond the study's signal.

The pair: :class:`rollcontact.line.instationary.InstationaryModel` with ``extrapolate=True`` on n elements (swapped into
the FMU's model in place of its plain transient, ``instationary_case.pair_stepper``): the grid of n/2 elements on
the same window, both aligned to the load (``aligned_grid_load`` with ``multiple`` = 2), each committing whole-element
substeps, and ``T' = 2 T'_n - T'_(n/2)``. Reference: the pair 500/1000 (its own error, 6.6/1000^2 = 6.6e-6 mu N' by
the model, is a quarter of what the finest pair measured, 500, is allowed). Error: ``max |T' - T'_ref|``
over the last cycle in units of mu N'. The plain transient on n elements is shown against the same reference.

Tables: (1) per lambda/a and n, the pair's error, ``error n^2`` and time per host step, the plain transient's error and
time; (2) the error model ``error <= C / n^2`` over the measured n: the largest ``error n^2`` and 1.4 times it, against
:data:`rollcontact.stepping.line.transient.EXTRAPOLATED_ERROR_CONSTANT`.  ``--crosscheck``: the reference against the
first-order Richardson extrapolation of plain transients on n = 800/1600 (non-nested grids, an independent route).

What it prints goes to ``benchmarks/results/transient_pairs.md`` with the machine (not after ``--quick``).
"""

from __future__ import annotations

import argparse
import time

import common  # noqa: F401  (before numpy: limits BLAS to one thread)
import numpy as np
from instationary_case import LIMIT, instationary_stepper, pair_stepper, richardson, run_instationary

from rollcontact.stepping.line.transient import EXTRAPOLATED_ERROR_CONSTANT

# (lambda/a, mean, amplitude) of the creep signal (mean + amplitude sin) mu a/R: the Pareto study's, then faster
# oscillations and a creep reversal (the error is not monotone in lambda/a, so the model is checked beyond them)
SIGNALS = ((5.0, 0.5, 0.3), (10.0, 0.5, 0.3), (20.0, 0.5, 0.3), (40.0, 0.5, 0.3), (1.0, 0.5, 0.3), (2.0, 0.5, 0.3),
           (5.0, 0.0, 0.9), (20.0, 0.0, 0.9))
# dense in n, so that no peak of error n^2 between sparse n goes unseen (the error depends on how the host step falls
# on the elements: bench_substep_rule.py)
PAIRS = (50, 64, 100, 128, 140, 156, 200, 300, 400, 440, 460, 480, 490, 500)
REFERENCE = 1000
SAFETY = 1.4  # the model's constant over the largest measured, as for the plain transient's


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--crosscheck", action="store_true", help="also the plain n = 800/1600 Richardson")
    parser.add_argument("--signals", default=",".join(str(i) for i in range(len(SIGNALS))),
                        help="indices into SIGNALS, comma-separated (default all; to split a run over processes)")
    args = parser.parse_args()
    start = time.perf_counter()
    rows, worst, where = [], 0.0, ""
    print("| lambda/a | xi / (mu a/R) | n | pair error [mu N'] | error n^2 | pair ms/step | plain error | "
          "plain ms/step |")
    print("|---|---|---|---|---|---|---|---|")
    for wavelength, mean, amplitude in (SIGNALS[int(i)] for i in args.signals.split(",")):
        signal = f"{mean:g} + {amplitude:g} sin"
        reference, _ = run_instationary(pair_stepper(REFERENCE), wavelength, mean, amplitude)
        for n in PAIRS:
            pair, pair_time = run_instationary(pair_stepper(n), wavelength, mean, amplitude)
            plain, plain_time = run_instationary(instationary_stepper("transient", n), wavelength, mean, amplitude)
            error = float(np.abs(pair - reference).max() / LIMIT)
            if error * n * n > worst:
                worst, where = error * n * n, f"lambda/a = {wavelength:g}, {signal}, n = {n}"
            rows.append((wavelength, n, error))
            print(f"| {wavelength:g} | {signal} | {n} | {error:.2e} | {error * n * n:.3g} | {1e3 * pair_time:.2f} | "
                  f"{np.abs(plain - reference).max() / LIMIT:.2e} | {1e3 * plain_time:.2f} |", flush=True)
        if args.crosscheck and (wavelength, mean, amplitude) in ((5.0, 0.5, 0.3), (40.0, 0.5, 0.3)):
            steppers = {n: instationary_stepper("transient", n) for n in (800, 1600)}
            runs = {n: run_instationary(step, wavelength)[0] for n, step in steppers.items()}
            ratio = (steppers[800].model.instationary.solver.grid.element_width
                     / steppers[1600].model.instationary.solver.grid.element_width)
            plain_ref = richardson(runs[800], runs[1600], ratio)
            print(f"| {wavelength:g} | crosscheck | pair {REFERENCE // 2}/{REFERENCE} vs plain Richardson 800/1600: "
                  f"{np.abs(reference - plain_ref).max() / LIMIT:.2e} | | | | |", flush=True)
    print(f"\nError model error <= C / n^2 over n = {PAIRS[0]}..{PAIRS[-1]}: largest error n^2 {worst:.3g} ({where}), "
          f"x {SAFETY} = {SAFETY * worst:.3g}; the model uses C = {EXTRAPOLATED_ERROR_CONSTANT:g} "
          f"({EXTRAPOLATED_ERROR_CONSTANT / worst:.2f} times the largest)")
    print(f"\n{len(rows)} pairs in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    common.run_and_publish(main, "transient_pairs.md")
