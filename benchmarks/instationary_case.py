"""The instationary scenario of the Pareto study, shared by ``pareto.py`` and the transient and relaxation benchmarks.

N' = 1e7 N/m (:data:`LOAD_I`; the suffix ``_I`` marks the instationary scenario), mu = 0.3, R = 0.46 m, steel,
V = 10 m/s; creep control ``xi = (mean + amplitude sin(2 pi sigma/lambda)) mu a/R`` with :data:`STEPS_PER_CYCLE`
host steps per cycle and at least 40 a rolled before the measured last cycle (:func:`creep_signal`).  Every setting
steps the FMU's stepping model (:func:`model_stepper`), so all pay the same model overhead.
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable

import numpy as np
from common import CONTACT_WIDTH

import rollcontact as rc
from rollcontact.line.hertz import hertz
from rollcontact.line.instationary import (
    LAG_MEMORY,
    InstationaryModel,
    creep_envelope,
    lag_error_bound,
    relaxation_length,
)
from rollcontact.stepping import ContactModel, ContactParameters

ESTAR = rc.Material().contact_modulus  # Pa, steel on steel
LOAD_I = 1e7  # N' [N/m]
MU_I, R_I, SPEED = 0.3, 0.46, 10.0  # friction coefficient [1], radius [m], rolling speed [m/s]
A_I = hertz(LOAD_I, R_I, ESTAR)[0]  # Hertz half-width [m]
SATURATION_I = MU_I * A_I / R_I  # Carter's saturation creep mu a/R [1]
LIMIT = MU_I * LOAD_I  # mu N' [N/m], the unit of the errors in T'
STEPS_PER_CYCLE = 64


def creep_signal(wavelength: float, mean: float = 0.5, amplitude: float = 0.3) -> tuple[np.ndarray, float, int]:
    """The creep per host step of ``(mean + amplitude sin(2 pi sigma/lambda)) mu a/R``.

    Parameters
    ----------
    wavelength
        lambda/a [1].
    mean, amplitude
        Of the creep, in units of :data:`SATURATION_I`.

    Returns
    -------
    tuple
        The creep [1] at each host step (at least 40 a of settling before the last cycle: the lag, ~5 a, has
        decayed), the host step [s], and the index of the first step of the measured (last) cycle.
    """
    cycles = max(1, math.ceil(40.0 / wavelength)) + 1
    k = np.arange(1, cycles * STEPS_PER_CYCLE + 1)
    xi = SATURATION_I * (mean + amplitude * np.sin(2.0 * np.pi * k / STEPS_PER_CYCLE))
    dt = wavelength * A_I / STEPS_PER_CYCLE / SPEED
    return xi, dt, (cycles - 1) * STEPS_PER_CYCLE


def run_instationary(step: Callable[[float, float], float], wavelength: float, mean: float = 0.5,
                     amplitude: float = 0.3) -> tuple[np.ndarray, float]:
    """Step through :func:`creep_signal`, timing every host step.

    Parameters
    ----------
    step
        ``step(xi, dt) -> T'``: creep [1] and host step [s] to tangential force per length [N/m].
    wavelength, mean, amplitude
        Of the signal (:func:`creep_signal`).

    Returns
    -------
    tuple
        T' [N/m] over the measured cycle, and the median time per host step [s].
    """
    xi, dt, first = creep_signal(wavelength, mean, amplitude)
    forces, times = [], []
    for i, value in enumerate(xi):
        t0 = time.perf_counter()
        force = step(value, dt)
        times.append(time.perf_counter() - t0)
        if i >= first:
            forces.append(force)
    return np.array(forces), statistics.median(times)


def model_stepper(**parameters) -> Callable[[float, float], float]:
    """``step(xi, dt) -> T'`` of the FMU's stepping model.

    Parameters
    ----------
    **parameters
        :class:`rollcontact.stepping.ContactParameters` beyond the scenario's radius, width and friction.

    Returns
    -------
    callable
        ``step(xi [1], dt [s]) -> T' [N/m]`` at :data:`LOAD_I` and :data:`SPEED`; ``step.model`` is the
        :class:`rollcontact.stepping.ContactModel`, ``step.used`` the ``method_used`` of every step.
    """
    model = ContactModel(ContactParameters(radius=R_I, contact_width=CONTACT_WIDTH, friction_coefficient=MU_I,
                                           **parameters))
    clock = [0.0]

    def step(xi, dt):
        out = model.step(clock[0], dt, LOAD_I * CONTACT_WIDTH, xi, SPEED)
        clock[0] += dt
        step.used.append(out.method_used)
        return out.tangential_force / CONTACT_WIDTH
    step.model, step.used = model, []
    return step


def instationary_stepper(kind: str, elements: int = 0, tolerance: float = 0.0) -> Callable[[float, float], float]:
    """``step(xi, dt) -> T'`` of the FMU's stepping model running one instationary setting.

    The transient runs on the grid auto's transient builds for the same n (aligned to the load).  Over the measured
    cycle it agrees with auto forced to that n (``elements`` = n) to 1e-7 mu N' (measured for n = 100, 200 at
    lambda/a = 5, 40): auto starts from steady rolling, this from no traction, and the start has decayed.

    Parameters
    ----------
    kind
        "quasi-static" (Carter, ``transient`` = 0), "relaxation" (the lag, ``transient`` = 2), "transient" (the
        discretised transient, ``method`` = 3, ``transient`` = 2), "transient pair" (:func:`pair_stepper`) or
        "auto" (``transient`` = 1).
    elements
        Elements of the transient (0: the model's default, 100).
    tolerance
        auto's tolerance [1 of mu N'].

    Returns
    -------
    callable
        As :func:`model_stepper`.
    """
    if kind == "transient pair":
        return pair_stepper(elements)
    parameters = {"quasi-static": {"transient": 0}, "relaxation": {"transient": 2},
                  "transient": {"method": 3, "transient": 2, "elements": elements},
                  "auto": {"transient": 1, "tolerance": tolerance}}
    return model_stepper(**parameters[kind])


def pair_stepper(elements: int) -> Callable[[float, float], float]:
    """The FMU's model with the extrapolating transient pair in place of its plain transient.

    The model runs ``method`` = 3, ``transient`` = 2, with :class:`rollcontact.line.instationary.InstationaryModel` on
    ``elements``/2 and ``elements`` elements, extrapolated: what auto builds for a tolerance below about 4e-3.

    Parameters
    ----------
    elements
        Elements of the finer grid.

    Returns
    -------
    callable
        As :func:`model_stepper`.
    """
    step = model_stepper(method=3, transient=2, elements=elements)
    model = step.model
    model.instationary = InstationaryModel(model.radius, model.contact_modulus, model.mu, mode="transient",
                                           elements=elements, extrapolate=True)
    return step


def lag_bounds(wavelength: float, mean: float = 0.5, amplitude: float = 0.3) -> np.ndarray:
    """The relaxation lag's error bound at each step of the measured cycle of :func:`creep_signal`.

    As auto's model computes it: :func:`rollcontact.line.instationary.lag_error_bound` of the creep envelope
    (:func:`rollcontact.line.instationary.creep_envelope`) over the host steps.

    Parameters
    ----------
    wavelength, mean, amplitude
        Of the signal (:func:`creep_signal`).

    Returns
    -------
    numpy.ndarray
        The bound [1 of mu N'] at each step of the measured cycle.
    """
    xi, _, first = creep_signal(wavelength, mean, amplitude)
    memory = LAG_MEMORY * relaxation_length(0.0, LOAD_I, R_I, ESTAR, MU_I, R_I)
    step = wavelength * A_I / STEPS_PER_CYCLE / memory
    envelope, bounds = None, []
    for value in xi:
        envelope = creep_envelope(envelope, value / SATURATION_I, step)
        bounds.append(lag_error_bound(envelope))
    return np.array(bounds[first:])


def richardson(coarse: np.ndarray, fine: np.ndarray, refinement: float) -> np.ndarray:
    """T' extrapolated to zero element size from two grids, first order.

    The transient's observed order is 0.97-0.98 at lambda/a = 5..40 (``benchmarks/bench_transient_auto.py``, from
    n, 2n, 4n); the steady discretised T' is first order in the elements across the contact
    (``benchmarks/calibrate_discretised_estimate.py``).

    Parameters
    ----------
    coarse, fine
        T' [N/m] on the coarser and the finer grid.
    refinement
        Element width of the coarser grid over that of the finer [1].

    Returns
    -------
    numpy.ndarray
        The extrapolated T' [N/m].
    """
    return fine + (fine - coarse) / (refinement - 1.0)
