"""Benchmark of instationary rolling: cost per step and accuracy of the cheap models against the transient.

Run as ``python benchmarks/bench_instationary.py``.  Prints markdown tables; asserts nothing.  One BLAS thread
(set before numpy loads), medians of repeated timings.

1. Time per step of :class:`InstationaryModel` in relaxation and transient mode (n = 100, 200), creep control,
   one step = one element width of rolling (transient steps of more than one element are split into substeps).
2. Creep control, ``xi = (m + A sin(2 pi sigma/lambda)) mu a/R`` for (m, A) in (0.3, 0.2), (0.5, 0.3),
   (0.6, 0.6) (the last one saturates), default datum L = R: max |T' - T'_transient| / (mu N') over the third
   cycle for the relaxation model and for quasi-static Carter, median and max over the three cases, reference
   the transient with 200 elements.
3. Force control, ``T' = (0.4 + 0.2 sin) mu N'``: L2 deviation of the oscillating part of q from quasi-steady
   Carter, paper's route and discretised transient (200 elements), against the rule 2.5 a / lambda.

What it prints goes to ``benchmarks/results/instationary.md`` with the machine (not after ``--quick``).
"""

import math
import statistics
import time

import common  # before numpy: limits BLAS to one thread
import numpy as np

import rollcontact as rc
from rollcontact.line.carter import carter
from rollcontact.line.hertz import hertz
from rollcontact.line.instationary import (
    InstationaryModel,
    OscillatingForce,
    oscillating_force_chebyshev,
    oscillating_force_discretised,
    quasi_steady_deviation,
)

LOAD = 1e7  # N' [N/m]
MU = 0.3
R = 0.46
ESTAR = rc.Material().contact_modulus
A, P0 = hertz(LOAD, R, ESTAR)
SATURATION = MU * A / R
LIMIT = MU * LOAD
SPEED = 10.0  # m/s
WAVELENGTHS = (5, 10, 20, 50)
CREEP_CASES = ((0.3, 0.2), (0.5, 0.3), (0.6, 0.6))
KW = {"radius": R, "contact_modulus": ESTAR, "mu": MU}


def step_time(mode, elements):
    """Median wall time [s] of one creep-controlled step of one element width, near a periodic state."""
    model = InstationaryModel(R, ESTAR, MU, mode=mode, max_normal_load_per_length=LOAD, elements=elements)
    dt = 2.5 * A / elements / SPEED
    state = model.initial_state()
    for k in range(2 * elements):
        state, _ = model.step(state, LOAD, SATURATION * (0.4 + 0.2 * math.sin(0.05 * k)), SPEED, dt)
    k = 0

    def step():
        nonlocal state, k
        k += 1
        state, _ = model.step(state, LOAD, SATURATION * (0.4 + 0.2 * math.sin(0.05 * k)), SPEED, dt)
    return common.median_time(step, min_repeats=50, min_seconds=0.5, warmups=0)


def creep_run(mode, mean, amplitude, wavelength, elements=200):
    """T' over the third cycle and the creeps, one step per element width of the 200-element grid."""
    model = InstationaryModel(R, ESTAR, MU, mode=mode, max_normal_load_per_length=LOAD, elements=elements)
    steps = round(wavelength / (2.5 / elements))
    dt = wavelength * A / steps / SPEED
    state = model.initial_state()
    state, _ = model.step(state, LOAD, mean * SATURATION, SPEED, dt)
    forces, creeps = [], []
    for k in range(3 * steps):
        xi = SATURATION * (mean + amplitude * math.sin(2 * math.pi * (k + 1) / steps))
        state, res = model.step(state, LOAD, xi, SPEED, dt)
        if k >= 2 * steps:
            forces.append(res.tangential_force_per_length)
            creeps.append(xi)
    return np.array(forces), np.array(creeps)


def main():
    print("### Time per step (creep control, one element width of rolling, one BLAS thread)\n")
    print("| mode | n | median time per step [ms] |")
    print("|---|---|---|")
    print(f"| relaxation | - | {1e3 * step_time('relaxation', 100):.4f} |")
    for n in (100, 200):
        print(f"| transient | {n} | {1e3 * step_time('transient', n):.3f} |")

    print("\n### Creep control: error in T' vs the transient (n = 200), default datum L = R, units of mu N'\n")
    print("| lambda/a | relaxation median | relaxation max | quasi-static median | quasi-static max |")
    print("|---|---|---|---|---|")
    for wavelength in WAVELENGTHS:
        relax, quasi = [], []
        for mean, amplitude in CREEP_CASES:
            reference, creeps = creep_run("transient", mean, amplitude, wavelength)
            relaxed, _ = creep_run("relaxation", mean, amplitude, wavelength)
            carter_forces = np.array([carter(LOAD, xi, R, ESTAR, MU)[0] for xi in creeps])
            relax.append(np.abs(relaxed - reference).max() / LIMIT)
            quasi.append(np.abs(carter_forces - reference).max() / LIMIT)
        print(f"| {wavelength} | {statistics.median(relax):.4f} | {max(relax):.4f} | {statistics.median(quasi):.3f} "
              f"| {max(quasi):.3f} |")

    print("\n### Force control: L2 deviation of the oscillating part of q from quasi-steady Carter\n")
    print("| lambda/a | 2.5 a/lambda | paper's route | discretised (n = 200) | route vs discretised RMS [mu p0] | "
          "route [s] | discretised [s] |")
    print("|---|---|---|---|---|---|---|")
    x = np.linspace(-A, A, 801)
    for wavelength in WAVELENGTHS:
        force = OscillatingForce(0.4 * LIMIT, 0.2 * LIMIT, wavelength * A)
        t0 = time.perf_counter()
        paper = oscillating_force_chebyshev(LOAD, force, **KW)
        t1 = time.perf_counter()
        discretised = oscillating_force_discretised(LOAD, force, **KW, elements=200)
        t2 = time.perf_counter()
        rms = math.sqrt(np.mean([np.mean((p.traction(x) - d.traction(x)) ** 2)
                                 for p, d in zip(paper, discretised, strict=True)])) / (MU * P0)
        ok = "" if all(r.success for r in paper) else " (route failed)"
        print(f"| {wavelength} | {2.5 / wavelength:.3f} | {quasi_steady_deviation(paper, force.mean, **KW):.3f}{ok} | "
              f"{quasi_steady_deviation(discretised, force.mean, **KW):.3f} | {rms:.4f} | {t1 - t0:.2f} | "
              f"{t2 - t1:.2f} |")


if __name__ == "__main__":
    common.run_and_publish(main, "instationary.md")
