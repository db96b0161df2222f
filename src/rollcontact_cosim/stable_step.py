"""Largest stable macro step of a scene's creep-force coupling (explicit or linearly implicit host).

Definition
----------
A run with macro step H is **stable** when it completes (no FMU refuses a step) and its traction coefficient
T/N stays within ``tolerance`` (default 0.05) of the largest |T/N| of a fine-step reference run of the same scene
at every communication point from the third on (the reference interpolated linearly in time).  The first two are
left out because a Jacobi master's first host step sees the contact's start values (T = k = 0): the free wheel
spins up for one step, a start-up kick of order ``M(t_1) H / J`` that a stable coupling damps in the next step.
Beyond its stability limit an explicitly coupled loop oscillates with growing amplitude until the creep
saturates, so T/N swings by about +-mu and misses this band by far; below the limit the coupling error is first
order in H and stays small.  A step too coarse to resolve the scene's excitation (e.g. the 200 Hz torque ripple)
fails the same band, so the result is the largest *usable* step, which for the linearly implicit coupling is set
by accuracy, not stability.

:func:`largest_stable_step` tries the steps of :data:`CANDIDATE_STEPS` that divide the run, from small to large,
and returns the largest one below the first unstable step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rollcontact_cosim.master import CosimResult, run_cosimulation
from rollcontact_cosim.scenes import CONTACT, CosimScene, CosimSceneError, load_cosim_scene, macro_steps

__all__ = ["CANDIDATE_STEPS", "TRACTION", "StepScan", "deviation", "is_stable", "largest_stable_step"]

TRACTION = f"{CONTACT}.traction_coefficient"
CANDIDATE_STEPS = tuple(m * 10.0 ** e for e in range(-6, 0) for m in (1, 2, 5))
"""Macro steps tried [s]: 1, 2 and 5 times 1e-6 ... 1e-1."""
MIN_STEPS = 10
"""Fewest macro steps of a tried run (a run of a few steps says nothing about stability)."""


@dataclass
class StepScan:
    """Outcome of :func:`largest_stable_step`.

    Attributes
    ----------
    largest_stable : float or None
        Largest stable step [s] (None: even the smallest tried step is unstable).
    tried : list of (float, float)
        (H [s], deviation [1]) of every run, inf for a run an FMU refused.
    """

    largest_stable: float | None
    tried: list[tuple[float, float]]


def deviation(result: CosimResult, fine: CosimResult, variable: str = TRACTION, skip: int = 2) -> float:
    """max_k |y(t_k) - y_fine(t_k)| / max |y_fine| over the run's rows from ``skip`` on (inf when it failed)."""
    if not result.success:
        return float("inf")
    values = result.values[skip:]
    y_fine = np.interp(values["time"], fine.values["time"], fine.values[variable])
    scale = float(np.max(np.abs(fine.values[variable])))
    if scale == 0.0:
        raise ValueError(f"{variable} of the fine reference is 0 throughout: no scale for the deviation")
    return float(np.max(np.abs(values[variable] - y_fine))) / scale


def is_stable(result: CosimResult, fine: CosimResult, tolerance: float = 0.05, variable: str = TRACTION) -> bool:
    """True when ``result`` completed and stays within ``tolerance`` of ``fine`` (module docstring)."""
    return deviation(result, fine, variable) <= tolerance


def largest_stable_step(scene: str | CosimScene, coupling: int, fine: CosimResult, algorithm: str | None = None,
                        tolerance: float = 0.05, stop_time: float | None = None, steps=CANDIDATE_STEPS,
                        **run_options) -> StepScan:
    """Largest stable macro step of ``scene`` with the host's ``coupling`` (0 explicit, 1 linearly implicit).

    Parameters
    ----------
    scene : str or CosimScene
        The scene.
    coupling : int
        WheelRig ``coupling``.
    fine : CosimResult
        Fine-step reference run of the scene (same stop time).
    algorithm : str, optional
        Master algorithm (the scene's when None).
    tolerance : float
        Band of :func:`is_stable` [1 of max |T/N|].
    stop_time : float, optional
        End time [s] replacing the scene's (the fine run must cover it).
    steps : sequence of float
        Candidate steps [s]; those finer than the fine run's, not dividing the run or giving fewer than
        :data:`MIN_STEPS` macro steps are skipped.
    **run_options
        Passed to :func:`rollcontact_cosim.master.run_cosimulation` (e.g. ``fmu_dir``, ``host``).
    """
    scene = load_cosim_scene(scene)
    stop = scene.stop_time if stop_time is None else stop_time
    host = {**run_options.pop("host", {}), "coupling": coupling}
    tried: list[tuple[float, float]] = []
    largest = None
    for step in sorted(steps):
        if step <= fine.step_size:
            continue
        try:
            if macro_steps(scene.start_time, stop, step) < MIN_STEPS:
                continue
        except CosimSceneError:
            continue
        result = run_cosimulation(scene, algorithm=algorithm, step_size=step, stop_time=stop, host=host,
                                  **run_options)
        error = deviation(result, fine)
        tried.append((step, error))
        if error > tolerance:
            break
        largest = step
    return StepScan(largest, tried)
