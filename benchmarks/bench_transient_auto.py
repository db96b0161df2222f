"""Discretised transient behind ``transient`` = 1 (auto) at tight tolerances: error vs elements, time per step.

Run as ``.venv/bin/python benchmarks/bench_transient_auto.py [--quick | --order-check]`` (full: about 3
minutes; ``--quick``: lambda/a = 10 only, reference from n = 200/400).  Prints markdown tables; asserts nothing.
One BLAS thread.

Scenario: the instationary study of ``benchmarks/pareto.py`` (its signal and steppers, ``instationary_case.py``, so both
measure the same thing): N' = 1e7 N/m, mu = 0.3, R = 0.46 m, V = 10 m/s, creep control ``xi = (0.5 + 0.3 sin(2 pi
sigma/lambda)) mu a/R``, 64 host steps per cycle, lambda/a = 5, 10, 20, 40, at least 40 a rolled before the measured
last cycle.  The transient runs on the grid the FMU's model builds
(:data:`rollcontact.stepping.line.transient.GRID_LOAD_FACTOR`: window +-1.25 a(2 N'), n elements) and starts from steady
rolling at the first creep (:meth:`rollcontact.line.instationary.InstationaryModel.steady_state`, as the model does when
it switches the transient in).

Reference: first-order Richardson extrapolation of n = 400/800, ``T'_ref = 2 T'_800 - T'_400``.  The order is
observed from three grids n, 2n, 4n as ``log2(max|T'_2n - T'_n| / max|T'_4n - T'_2n|)`` (:func:`observed_order`),
printed for n = 200/400/800 (0.97-0.98 in ``benchmarks/results/transient_auto.md``).  Error:
``max |T'_n - T'_ref|`` over the last cycle in units of mu N'; the n = 800 row is part of the extrapolation and left
out of the fit.

Tables: (1) error, elements rolled and median time per host step for each lambda/a and n; (2) steady rolling on the grid
against Carter, the force jump when the model switches the transient in or hands back; (3) the error model ``error(n) <=
C / n^p``: p fitted by least squares to log(max over lambda/a of the error) for n <= 400, C the largest ``error n^p``,
against the constants the model uses (:data:`rollcontact.stepping.line.transient.TRANSIENT_ERROR_CONSTANT`,
:data:`rollcontact.stepping.line.transient.TRANSIENT_ERROR_ORDER`);
(4) what ``transient`` = 1 chooses at tolerance 1e-2, 1e-3, 1e-4, its error and time per host step.

What it prints goes to ``benchmarks/results/transient_auto.md`` with the machine (not after ``--quick``).
"""

from __future__ import annotations

import argparse

import common  # before numpy: limits BLAS to one thread
import numpy as np
from instationary_case import (
    A_I,
    ESTAR,
    LIMIT,
    LOAD_I,
    MU_I,
    R_I,
    SATURATION_I,
    SPEED,
    STEPS_PER_CYCLE,
    instationary_stepper,
    richardson,
    run_instationary,
)
from pareto_cases import TOLERANCES

from rollcontact.line.carter import carter
from rollcontact.line.instationary import InstationaryModel, aligned_grid_load
from rollcontact.stepping import ContactModel, ContactParameters
from rollcontact.stepping.line.transient import GRID_LOAD_FACTOR, TRANSIENT_ERROR_CONSTANT, TRANSIENT_ERROR_ORDER


def grid_model(elements: int) -> InstationaryModel:
    """The transient on the grid the FMU's model builds for N' (:func:`aligned_grid_load`)."""
    return InstationaryModel(R_I, ESTAR, MU_I, mode="transient", elements=elements,
                             max_normal_load_per_length=aligned_grid_load(LOAD_I, elements, GRID_LOAD_FACTOR))


def transient_stepper(elements: int):
    """``step(xi, dt) -> T'`` of the transient on the model's grid, started from steady rolling at the first xi."""
    model = grid_model(elements)
    state = [None]

    def step(xi, dt):
        if state[0] is None:
            state[0] = model.steady_state(LOAD_I, xi)
        state[0], result = model.step(state[0], LOAD_I, xi, SPEED, dt)
        return result.tangential_force_per_length
    return step


def elements_per_step(elements: int, wavelength: float) -> float:
    """Elements rolled per host step, ``V dt / h`` (the model commits whole-element substeps)."""
    return wavelength * A_I / STEPS_PER_CYCLE / grid_model(elements).solver.grid.element_width


def steady_jump(elements: int) -> float:
    """max |T'_steady(n) - T'_Carter| / (mu N') over xi = (0.2, 0.5, 0.8) mu a/R."""
    model = grid_model(elements)
    worst = 0.0
    for fraction in (0.2, 0.5, 0.8):
        xi = fraction * SATURATION_I
        steady = model.steady_state(LOAD_I, xi).tangential_force_per_length
        worst = max(worst, abs(steady - carter(LOAD_I, xi, R_I, ESTAR, MU_I)[0]) / LIMIT)
    return worst


def observed_order(forces: dict[int, np.ndarray]) -> float:
    """Convergence order from three grids n, 2n, 4n: ``log2(max|T'_2n - T'_n| / max|T'_4n - T'_2n|)``, clipped
    to [0.5, 2]."""
    n1, n2, n3 = sorted(forces)
    ratio = np.abs(forces[n2] - forces[n1]).max() / max(np.abs(forces[n3] - forces[n2]).max(), 1e-300)
    return float(np.clip(np.log(ratio) / np.log(n3 / n2), 0.5, 2.0))


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="lambda/a = 10 only, reference n = 100/200/400")
    parser.add_argument("--order-check", action="store_true",
                        help="only the observed order at lambda/a = 5 from n = 400/800/1600 (about 15 minutes)")
    args = parser.parse_args(argv)
    if args.order_check:
        runs = {n: run_instationary(transient_stepper(n), 5.0)[0] for n in (400, 800, 1600)}
        print(f"lambda/a = 5, observed order from n = 400/800/1600: {observed_order(runs):.2f}")
        return
    wavelengths = (10.0,) if args.quick else (5.0, 10.0, 20.0, 40.0)
    elements = (50, 100, 200, 400) if args.quick else (50, 100, 200, 400, 600, 800)
    fine = elements[-1]
    fitted = [n for n in elements if n < fine]

    print("### (1) Discretised transient on the model's grid vs the Richardson reference\n")
    print("| lambda/a | n | elements per step | error [mu N'] | time per step [ms] |")
    print("|---|---|---|---|---|")
    errors, references, orders = {}, {}, []
    for wavelength in wavelengths:
        runs = {n: run_instationary(transient_stepper(n), wavelength) for n in elements}
        order = observed_order({n: runs[n][0] for n in (fine // 4, fine // 2, fine)})
        orders.append(f"lambda/a = {wavelength:g}: {order:.2f}")
        ref = references[wavelength] = richardson(runs[fine // 2][0], runs[fine][0], 2.0)
        for n in elements:
            forces, seconds = runs[n]
            errors[wavelength, n] = float(np.abs(forces - ref).max() / LIMIT)
            note = " (in the extrapolation)" if n == fine else ""
            print(f"| {wavelength:g} | {n} | {elements_per_step(n, wavelength):.3f} | "
                  f"{errors[wavelength, n]:.2e}{note} | {1e3 * seconds:.3g} |")
    print(f"\nObserved orders from n = {fine // 4}/{fine // 2}/{fine} (observed_order): " + "; ".join(orders))

    print("\n### (2) Steady rolling on the grid vs Carter (jump at switch-in and hand-back)\n")
    print("| n | max |T'_steady - T'_Carter| [mu N'] |")
    print("|---|---|")
    for n in elements:
        print(f"| {n} | {steady_jump(n):.2e} |")

    print("\n### (3) Error model error(n) <= C / n^p\n")
    worst = np.array([max(errors[w, n] for w in wavelengths) for n in fitted])
    slope = np.polyfit(np.log(fitted), np.log(worst), 1)[0]
    print(f"least-squares order over n = {fitted}: p = {-slope:.2f}; "
          f"C = max error n^p: {max(worst * np.array(fitted) ** -slope):.3g} (p fitted), "
          f"{max(worst * np.array(fitted) ** TRANSIENT_ERROR_ORDER):.3g} (p = {TRANSIENT_ERROR_ORDER:g})")
    print(f"model: C = {TRANSIENT_ERROR_CONSTANT:g}, p = {TRANSIENT_ERROR_ORDER:g}\n")
    print("| n | max error [mu N'] | model bound | bound / error |")
    print("|---|---|---|---|")
    for n, error in zip(fitted, worst, strict=True):
        bound = TRANSIENT_ERROR_CONSTANT / n ** TRANSIENT_ERROR_ORDER
        print(f"| {n} | {error:.2e} | {bound:.2e} | {bound / error:.2f} |")

    print("\n### (4) transient = 1 (auto), method 0: choice, error vs the reference, time per host step\n")
    print("| lambda/a | tolerance | choice | steps (last cycle) | error [mu N'] | met | time per step [ms] |")
    print("|---|---|---|---|---|---|---|")
    names = {1: "quasi-static", 4: "relaxation", 5: "transient"}
    for wavelength in wavelengths:
        ref = references[wavelength]
        for tolerance in TOLERANCES:
            model = ContactModel(ContactParameters(radius=R_I, contact_width=common.CONTACT_WIDTH,
                                                   friction_coefficient=MU_I, transient=1, tolerance=tolerance))
            n = model.instationary.elements
            choice = ("relaxation" if model.instationary.mode != "transient" else
                      f"transient pair n = {n // 2}/{n}" if model.instationary.extrapolate else f"transient n = {n}")
            stepper = instationary_stepper("auto", tolerance=tolerance)
            forces, seconds = run_instationary(stepper, wavelength)
            last = stepper.used[-STEPS_PER_CYCLE:]
            shares = ", ".join(f"{last.count(c) / len(last):.0%} {name}" for c, name in names.items() if c in last)
            error = float(np.abs(forces - ref).max() / LIMIT)
            print(f"| {wavelength:g} | {tolerance:g} | {choice} | {shares} | {error:.2e} | "
                  f"{'yes' if error <= tolerance else 'no'} | {1e3 * seconds:.3g} |")


if __name__ == "__main__":
    common.run_and_publish(main, "transient_auto.md")
