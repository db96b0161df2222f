"""The hunting study of the wheelset, in process: Klingel's wavelength and the critical speed from time simulations.

Runs the model of :mod:`rollcontact_cosim.wheelset` with a creep-force law evaluated in process (Kalker's linear
law by default) by :func:`rollcontact_cosim.wheelset.simulate`, the step sequence of a Gauss-Seidel master, and
compares what the time histories show with :mod:`rollcontact_cosim.wheelset.stability`:

* :func:`klingel_study`: the wavelength of the lateral oscillation, from the upward zero crossings of y over
  several periods (:func:`wavelength`), against Klingel's ``2 pi sqrt(r0 e / lambda)``, with the suspension scaled
  by the factors given (Klingel's limit is the free wheelset at low speed: the suspension's stiffness adds to the
  creep forces' kinematic coupling at every speed, the inertia's share grows as V^2).
* :func:`hunting_sweep`: the decay rate of y (a least-squares line through the logarithms of the peaks of |y|,
  the log decrement per second, :func:`decay_rate`) at each speed, one task per speed on dask.distributed (a local
  cluster as :mod:`rollcontact_cosim.sweep` starts, or serial in process with ``n_workers=0``); the simulated
  critical speed is the zero crossing of the decay rate, interpolated linearly between the bracketing speeds,
  against the eigenvalues' :func:`~rollcontact_cosim.wheelset.stability.critical_speed`.
* :func:`plot_hunting`: the figure (decay rate against speed, eigenvalue prediction overlaid, critical speeds
  marked); :func:`run_hunting_study` runs both studies and writes the figure (the entry of the
  ``wheelset_hunting`` scene's in-process mode).

Step size: ``steps_per_period`` steps of the kinematic period ``L / V`` (default 200).  The linearly implicit
trapezoidal rule's phase error is ``(h omega)^2 / 12`` (2e-4 at 200 steps) and it adds no damping to an undamped
mode (:mod:`rollcontact_cosim.wheelset`), so neither the wavelength nor the zero crossing of the decay rate
depends on the step beyond that.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rollcontact_cosim.scenes import COSIM_DIR
from rollcontact_cosim.wheelset.model import (
    CreepForceLaw,
    KalkerLinearLaw,
    WheelsetError,
    WheelsetParameters,
    linear_law,
    simulate,
)
from rollcontact_cosim.wheelset.stability import critical_speed, klingel_wavelength, least_damped, linearised

__all__ = ["REFERENCE", "SPEEDS", "HuntingSweep", "KlingelPoint", "SpeedRun", "decay_rate", "hunting_sweep",
           "klingel_study", "plot_hunting", "report", "run_hunting_study", "run_speed", "wavelength",
           "write_reference"]


def upward_crossings(times: np.ndarray, signal: np.ndarray) -> np.ndarray:
    """Times [s] where ``signal`` crosses zero upwards, interpolated linearly between samples."""
    k = np.nonzero((signal[:-1] < 0.0) & (signal[1:] >= 0.0))[0]
    return times[k] - signal[k] * (times[k + 1] - times[k]) / (signal[k + 1] - signal[k])


def wavelength(times: np.ndarray, lateral: np.ndarray, speed: float, skip: int = 1) -> float:
    """Mean wavelength [m] ``V (t_last - t_first) / periods`` between upward zero crossings of y, after ``skip``.

    Raises WheelsetError when fewer than two crossings remain.
    """
    crossings = upward_crossings(np.asarray(times), np.asarray(lateral))[skip:]
    if crossings.size < 2:
        raise WheelsetError(f"{crossings.size} upward zero crossings of y after skipping {skip}: the run shows no "
                            "period; run longer")
    return speed * (crossings[-1] - crossings[0]) / (crossings.size - 1)


def decay_rate(times: np.ndarray, lateral: np.ndarray, start: float = 0.0,
               limit: float = math.inf) -> tuple[float, int]:
    """Decay rate sigma [1/s] of y (negative when it decays) and the number of peaks it is fitted to.

    The peaks are the local extrema of |y| after ``start`` [s] and before |y| first exceeds ``limit`` [m], each
    refined by the parabola through its three samples; sigma is the slope of the least-squares line through
    ``(t_k, ln |y_k|)``, so that ``|y| ~ exp(sigma t)``: the real part of the dominant eigenvalue.  Raises
    WheelsetError with fewer than 3 peaks.
    """
    t, y = np.asarray(times), np.abs(np.asarray(lateral))
    beyond = np.nonzero(y > limit)[0]
    if beyond.size:
        t, y = t[:beyond[0]], y[:beyond[0]]
    inner = (y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:]) & (t[1:-1] >= start)
    k = np.nonzero(inner)[0] + 1
    if k.size < 3:
        raise WheelsetError(f"{k.size} peaks of |y| after t = {start!r} s with |y| <= {limit!r} m: too few for a "
                            "decay rate; run longer, or start smaller when it grows")
    left, mid, right = y[k - 1], y[k], y[k + 1]
    curvature = left - 2.0 * mid + right
    shift = np.where(curvature != 0.0, 0.5 * (left - right) / np.where(curvature != 0.0, curvature, 1.0), 0.0)
    peak_time = t[k] + shift * (t[k + 1] - t[k])
    peak = mid - 0.25 * (left - right) * shift
    slope = np.polyfit(peak_time, np.log(peak), 1)[0]
    return float(slope), int(k.size)


@dataclass(frozen=True)
class KlingelPoint:
    """Wavelength of one run (:func:`klingel_study`): parameters, measured and Klingel's [m], eigenvalues' [m]."""

    speed: float
    suspension_scale: float
    measured: float
    klingel: float
    eigenvalue: float

    @property
    def error(self) -> float:
        """``measured / klingel - 1`` [1]."""
        return self.measured / self.klingel - 1.0


def klingel_study(parameters: WheelsetParameters | None = None, law: KalkerLinearLaw | None = None,
                  speeds=(2.0, 5.0, 10.0), suspension_scales=(1.0, 0.1, 0.01, 0.0), periods: int = 6,
                  steps_per_period: int = 200) -> list[KlingelPoint]:
    """Wavelength of y at each speed and scale of both suspension stiffnesses, against Klingel's and the
    eigenvalues' ``2 pi V / Im(lambda)``.

    The runs start on the kinematic motion (``y0``, ``psi' = -V lambda y0 / (e r0)``: xi = eta = 0), so that the
    stiff creep modes are not excited; the first crossing is skipped.
    """
    p0 = WheelsetParameters() if parameters is None else parameters
    law = linear_law(p0) if law is None else law
    length = klingel_wavelength(p0)
    out = []
    for speed in speeds:
        for scale in suspension_scales:
            p = dataclasses.replace(
                p0, speed=speed, lateral_stiffness=scale * p0.lateral_stiffness,
                yaw_stiffness=scale * p0.yaw_stiffness, initial_yaw_angle=0.0, initial_lateral_velocity=0.0,
                initial_yaw_rate=-speed * p0.conicity * p0.initial_lateral_displacement
                / (p0.contact_half_distance * p0.rolling_radius))
            period = length / speed
            step = period / steps_per_period
            times, states = simulate(p, law, step * steps_per_period * periods, step)
            mode = least_damped(p, law)
            out.append(KlingelPoint(speed, scale, wavelength(times, states[:, 0], speed), length,
                                    2.0 * math.pi * speed / mode.imag))
    return out


@dataclass(frozen=True)
class SpeedRun:
    """Decay rate of one speed (:func:`run_speed`): simulated and the least-damped eigenvalue's real part [1/s]."""

    speed: float
    simulated: float
    predicted: float
    peaks: int
    frequency: float


def run_speed(parameters: WheelsetParameters, speed: float, law: CreepForceLaw, periods: int = 12,
              steps_per_period: int = 200, settle: int = 2, amplitude_limit: float = 0.01) -> SpeedRun:
    """Simulate at ``speed`` for ``periods`` kinematic periods ``L / V``; the decay rate of y after ``settle``
    periods (the stiff and the fast-decaying modes are gone by then) and while |y| <= ``amplitude_limit`` [m]
    (default 10 mm, the order of the flange clearance, beyond which flangeless cones no longer model the wheelset)
    against the eigenvalues' (with the law's Jacobian at zero creepage as the linear law)."""
    p = dataclasses.replace(parameters, speed=float(speed))
    period = klingel_wavelength(p) / speed
    step = period / steps_per_period
    times, states = simulate(p, law, step * steps_per_period * periods, step)
    rate, peaks = decay_rate(times, states[:, 0], start=settle * period, limit=amplitude_limit)
    mode = least_damped(p, linearised(law, p))
    return SpeedRun(float(speed), rate, mode.real, peaks, mode.imag / (2.0 * math.pi))


@dataclass(frozen=True)
class HuntingSweep:
    """Result of :func:`hunting_sweep`.

    Attributes
    ----------
    runs : tuple of SpeedRun
        One per speed, by increasing speed.
    predicted_critical_speed : float
        Eigenvalues' critical speed [m/s].
    simulated_critical_speed : float or None
        Zero crossing of the simulated decay rates [m/s] (None: no sign change among the speeds).
    """

    runs: tuple[SpeedRun, ...]
    predicted_critical_speed: float
    simulated_critical_speed: float | None

    @property
    def error(self) -> float:
        """``simulated / predicted - 1`` [1] (NaN without a simulated crossing)."""
        if self.simulated_critical_speed is None:
            return math.nan
        return self.simulated_critical_speed / self.predicted_critical_speed - 1.0


def zero_crossing(speeds, rates) -> float | None:
    """First speed where ``rates`` goes from < 0 to >= 0, linear between the bracketing samples."""
    for k in range(len(speeds) - 1):
        if rates[k] < 0.0 <= rates[k + 1]:
            return float(speeds[k] - rates[k] * (speeds[k + 1] - speeds[k]) / (rates[k + 1] - rates[k]))
    return None


def hunting_sweep(speeds, parameters: WheelsetParameters | None = None, law: CreepForceLaw | None = None, *,
                  periods: int = 12, steps_per_period: int = 200, client=None, scheduler: str | None = None,
                  n_workers: int = 2) -> HuntingSweep:
    """Decay rate of y at each speed (one task each) and the simulated critical speed.

    ``client``/``scheduler``/``n_workers`` as in :func:`rollcontact_cosim.sweep.run_sweep`; ``n_workers=0``
    without a client or scheduler runs the speeds one after the other in process.
    """
    from rollcontact_cosim.sweep import submit

    p = WheelsetParameters() if parameters is None else parameters
    law = linear_law(p) if law is None else law
    speeds = sorted(float(v) for v in speeds)
    arguments = [(p, v, law, periods, steps_per_period) for v in speeds]
    if client is None and scheduler is None and n_workers == 0:
        runs = [run_speed(*args) for args in arguments]
    else:
        runs = submit(run_speed, arguments, client, scheduler, n_workers)
    return HuntingSweep(tuple(runs), critical_speed(p, linearised(law, p)),
                        zero_crossing(speeds, [run.simulated for run in runs]))


def plot_hunting(sweep: HuntingSweep, path: Path | str, parameters: WheelsetParameters | None = None,
                 law: KalkerLinearLaw | None = None) -> Path:
    """PNG: simulated decay rates against speed, the least-damped eigenvalue's real part over the same range
    (``parameters``, ``law``: of the sweep, defaults as there), both critical speeds marked."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rollcontact_cosim.wheelset.stability import eigenvalues

    p = WheelsetParameters() if parameters is None else parameters
    law = linear_law(p) if law is None else law
    speeds = np.array([run.speed for run in sweep.runs])
    fine = np.linspace(speeds[0], speeds[-1], 200)
    real = [eigenvalues(dataclasses.replace(p, speed=float(v)), law)[0].real for v in fine]
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.plot(fine, real, "-", color="C0", label="least-damped eigenvalue, Re [1/s]")
    ax.plot(speeds, [run.simulated for run in sweep.runs], "o", color="C3", label="simulated decay rate of y [1/s]")
    ax.axvline(sweep.predicted_critical_speed, color="C0", ls="--", lw=0.9,
               label=f"eigenvalues: V_c = {sweep.predicted_critical_speed:.2f} m/s")
    if sweep.simulated_critical_speed is not None:
        ax.axvline(sweep.simulated_critical_speed, color="C3", ls=":", lw=1.2,
                   label=f"simulation: V_c = {sweep.simulated_critical_speed:.2f} m/s ({100 * sweep.error:+.2f} %)")
    ax.set_xlabel("speed V [m/s]")
    ax.set_ylabel("decay rate sigma [1/s] (> 0: hunting grows)")
    ax.set_title(f"Wheelset hunting: lambda = {p.conicity:g}, k_y = {p.lateral_stiffness:.3g} N/m, "
                 f"k_psi = {p.yaw_stiffness:.3g} N m/rad", fontsize=9)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


REFERENCE = COSIM_DIR / "wheelset_hunting_inprocess.md"
"""Reference results of the in-process study (:func:`write_reference`)."""
REFERENCE_HEADER = """# wheelset_hunting: in-process reference results

Written by `rollcontact_cosim.wheelset.study.write_reference()` (the study of `python -m rollcontact_cosim --scene
wheelset_hunting`: default parameters of `rollcontact_cosim.wheelset`, Kalker's linear creep forces, 200 steps per
kinematic period); every figure is a function of the parameters only.

"""
SPEEDS = tuple(float(v) for v in range(30, 101, 10))
"""Speeds [m/s] of the default sweep: 30 ... 100 m/s, independent of the prediction."""


def run_hunting_study(plot: Path | str | None = "cosim_wheelset_hunting.png", parameters=None, law=None,
                      speeds=SPEEDS, **sweep_options) -> tuple[HuntingSweep, list[KlingelPoint]]:
    """Both studies (the sweep over ``speeds`` with ``sweep_options`` of :func:`hunting_sweep`, Klingel's at its
    defaults), the figure written to ``plot`` (None: none); the in-process mode of the ``wheelset_hunting``
    scene."""
    p = WheelsetParameters() if parameters is None else parameters
    law = linear_law(p) if law is None else law
    sweep = hunting_sweep(speeds, p, law, **sweep_options)
    klingel = klingel_study(p, linearised(law, p))
    if plot is not None:
        plot_hunting(sweep, plot, p, linearised(law, p))
    return sweep, klingel


def report(sweep: HuntingSweep, klingel: list[KlingelPoint]) -> str:
    """The studies' results as markdown tables (decay rates per speed, critical speeds, Klingel's wavelengths)."""
    lines = ["| V [m/s] | simulated decay rate [1/s] | eigenvalue Re [1/s] | frequency [Hz] | peaks |",
             "|---|---|---|---|---|"]
    lines += [f"| {r.speed:g} | {r.simulated:+.4f} | {r.predicted:+.4f} | {r.frequency:.3f} | {r.peaks} |"
              for r in sweep.runs]
    simulated = ("none in the sweep" if sweep.simulated_critical_speed is None
                 else f"{sweep.simulated_critical_speed:.2f} m/s ({100 * sweep.error:+.2f} %)")
    lines += ["", f"critical speed: eigenvalues {sweep.predicted_critical_speed:.2f} m/s, simulation {simulated}",
              "", "| V [m/s] | suspension scale | wavelength [m] | Klingel [m] | error | eigenvalues' [m] |",
              "|---|---|---|---|---|---|"]
    lines += [f"| {k.speed:g} | {k.suspension_scale:g} | {k.measured:.4f} | {k.klingel:.4f} | {100 * k.error:+.3f} % "
              f"| {k.eigenvalue:.4f} |" for k in klingel]
    return "\n".join(lines)


def write_reference(path: Path | str = REFERENCE, **sweep_options) -> Path:
    """Run the default study (serial unless ``sweep_options`` say otherwise) and write its :func:`report` to
    ``path`` below :data:`REFERENCE_HEADER`."""
    sweep, klingel = run_hunting_study(None, **{"n_workers": 0, **sweep_options})
    Path(path).write_text(REFERENCE_HEADER + report(sweep, klingel) + "\n")
    return Path(path)
