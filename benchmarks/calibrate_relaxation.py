"""How accurate the relaxation lag is, and the calibration of its error bound for a creep swing.

Run as ``.venv/bin/python benchmarks/calibrate_relaxation.py`` (about 10 minutes, most of it in the reference at
lambda/a >= 80).  Prints a markdown table; asserts nothing.  One BLAS thread.

Scenario: the instationary study of ``benchmarks/pareto.py`` (``instationary_case.py``: N' = 1e7 N/m, mu = 0.3,
R = 0.46 m, V = 10 m/s, 64 host steps per cycle, at least 40 a rolled before the measured last cycle) under creep
control ``xi = (mean + amplitude sin(2 pi sigma/lambda)) mu a/R`` for lambda/a = 2..40 and swings from
``0.2 + 0.1 sin`` to creep reversals far beyond saturation (``10 sin``), near saturation and wholly in full slip
(``2 + 0.5 sin``); slow swings (lambda/a = 80..320) near zero creep and near saturation.  Each setting steps the
FMU's model: the lag (``transient`` = 2), quasi-static Carter (``transient`` = 0).  Reference: the extrapolating
transient pair 200/400 (error <= 16/400^2 = 1e-4 mu N', ``benchmarks/calibrate_transient_pairs.py``).  Error:
``|T' - T'_ref|`` in units of mu N' at each step of the last cycle.

Calibration of :func:`rollcontact.line.instationary.lag_error_bound`: at each step the creep envelope of the FMU's
model (:func:`rollcontact.line.instationary.creep_envelope`, memory :data:`~rollcontact.line.instationary.LAG_MEMORY`
relaxation lengths) gives ``w = (high - low)/2 (1 - d)_+``; 'ratio' is the largest ``(error - e_0)_+ / w`` over the
cycle (``e_0`` = :data:`~rollcontact.line.instationary.LAG_ERROR_FLOOR`, the reference's own bound), and
:data:`~rollcontact.line.instationary.LAG_ERROR_COEFFICIENT` is 1.4 times the largest ratio.  'margin': the smallest
``bound / error`` over the cycle.

What it shows (564 s, the run behind the constants): the lag's error is linear in the swing, 0.7-2.6 % of the
amplitude in saturation creeps, most where the swing passes zero creep (2.5 % at lambda/a = 5), 0.2-0.5 % near
saturation, none wholly in full slip; 2.9-3.4e-3 mu N' on the Pareto study's ``0.5 + 0.3 sin`` (4.3e-4 at lambda/a
= 320), 1.3-2.3e-2 for a reversal ``0.9 sin``, up to 0.15 mu N' (lambda/a = 2, ``10 sin``).  The largest ratio is
0.027 (``3 sin`` at lambda/a = 5), so C = 0.038, and the bound is at least 1.41 times the error at every one of the
72 x 64 measured steps.  A memory of 4 relaxation lengths would need 0.031 for slow swings near saturation (their
stiff part is forgotten while its error persists).  At lambda/a = 320 every swing touching saturation is 7.5e-5 off
the reference: that is the floor.

What it prints goes to ``benchmarks/results/relaxation.md`` with the machine (not after ``--quick``).
"""

from __future__ import annotations

import time

import common  # noqa: F401  (before numpy: limits BLAS to one thread)
import numpy as np
from instationary_case import LIMIT, instationary_stepper, lag_bounds, pair_stepper, run_instationary

from rollcontact.line.instationary import LAG_ERROR_COEFFICIENT, LAG_ERROR_FLOOR, LAG_MEMORY

SWINGS = ((0.5, 0.3), (0.0, 0.3), (0.2, 0.1), (0.7, 0.3), (0.8, 0.15), (0.9, 0.3), (0.95, 0.1), (1.2, 0.3),
          (2.0, 0.5), (0.0, 0.9), (0.0, 3.0), (0.0, 10.0))  # (mean, amplitude) / (mu a/R)
SIGNALS = ([(w, *s) for w in (2.0, 5.0, 10.0, 20.0, 40.0) for s in SWINGS]
           + [(w, *s) for w in (80.0, 160.0, 320.0) for s in ((0.5, 0.3), (0.8, 0.15), (0.95, 0.1), (1.2, 0.3))])
REFERENCE = 400
SAFETY = 1.4


def envelope_widths(wavelength: float, mean: float, amplitude: float) -> np.ndarray:
    """``(high - low)/2 (1 - d)_+`` of the model's creep envelope at each step of the measured cycle."""
    return (lag_bounds(wavelength, mean, amplitude) - LAG_ERROR_FLOOR) / LAG_ERROR_COEFFICIENT


def main() -> None:
    start = time.perf_counter()
    worst, where, tightest = 0.0, "", np.inf
    print("| lambda/a | xi / (mu a/R) | lag error [mu N'] | error / amplitude | ratio | margin | quasi-static error |")
    print("|---|---|---|---|---|---|---|")
    for signal in SIGNALS:
        wavelength, mean, amplitude = signal
        reference, _ = run_instationary(pair_stepper(REFERENCE), *signal)
        lag, _ = run_instationary(instationary_stepper("relaxation"), *signal)
        quasi, _ = run_instationary(instationary_stepper("quasi-static"), *signal)
        errors = np.abs(lag - reference) / LIMIT
        widths = envelope_widths(*signal)
        excess = np.maximum(0.0, errors - LAG_ERROR_FLOOR)
        ratio = float(np.max(np.where(excess > 0.0, excess / np.where(widths > 0.0, widths, np.nan), 0.0)))
        bounds = LAG_ERROR_COEFFICIENT * widths + LAG_ERROR_FLOOR
        margin = float(np.min(bounds[errors > 0.0] / errors[errors > 0.0])) if np.any(errors > 0.0) else np.inf
        tightest = min(tightest, margin)
        if not ratio <= worst:
            worst, where = ratio, f"lambda/a = {wavelength:g}, {mean:g} + {amplitude:g} sin"
        print(f"| {wavelength:g} | {mean:g} + {amplitude:g} sin | {errors.max():.2e} | "
              f"{errors.max() / amplitude:.4f} | {ratio:.4f} | {margin:.2f} | "
              f"{np.abs(quasi - reference).max() / LIMIT:.2e} |", flush=True)
    print(f"\nLargest ratio {worst:.4g} ({where}), x {SAFETY} = {SAFETY * worst:.3g}; LAG_ERROR_COEFFICIENT = "
          f"{LAG_ERROR_COEFFICIENT:g} (memory {LAG_MEMORY:g} relaxation lengths, floor {LAG_ERROR_FLOOR:g}); "
          f"the bound is >= {tightest:.2f} times the error at every measured step")
    print(f"{len(SIGNALS)} signals in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    common.run_and_publish(main, "relaxation.md")
