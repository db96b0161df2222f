"""Nonlinear hunting of a wheelset on real profiles: the scene ``wheelset_hunting_profiles`` (the Wheelset host on
profiles and the WheelsetContact FMU) run over a speed sweep from a small and a large start, its bifurcation diagram
against the equivalent linearisation of the profiles (docs/physics.md, "Wheelset hunting on profiles").

* :func:`profile_run`: one co-simulation (fmpy or libcosim, :func:`rollcontact_cosim.master.run_cosimulation`) of
  :data:`TRAVEL` seconds at a speed from a start y0 (host axes); the limit cycle's amplitude is the largest |y| over the
  last :data:`WINDOW` seconds (0 where the motion has died out: below :data:`SETTLED`), its frequency from the upward
  zero crossings there, and the initial growth rate of |y| (:func:`rollcontact_cosim.wheelset.study.decay_rate` over
  the first :data:`GROWTH_WINDOW` seconds) that locates the onset from small perturbations;
* :func:`hunting_diagram`: every (speed, start) pair as one task on dask.distributed (a local cluster by default, as
  :mod:`rollcontact_cosim.sweep`), the FMUs built once before;
* :class:`Linearisation`: the wheelset as the cone of the equivalent conicity at an amplitude A, ``lambda_e(A)``
  (harmonic linearisation of Delta r, EN 15302's principle), with the lateral stiffness of the contact angles'
  change ``k_g(A) = (Q - f23 / r0) DF(tan(delta_R) - tan(delta_L))`` added to the suspension's (the normal forces'
  lateral components less the spin creep forces they bring, the gravitational stiffness of Wickens' wheelset) and
  Kalker's coefficients of the centred contacts: its eigenvalues' critical speed ``V_c(A)``
  (:func:`rollcontact_cosim.wheelset.stability.critical_speed`), the linear critical speed at the small start's
  amplitude, and the curve ``A -> V_c(A)``, the limit cycles the equivalent linearisation predicts;
* :func:`klingel_check`: the free wheelset (no suspension) started on its kinematic motion at a low speed: the
  wavelength of y against Klingel's ``2 pi sqrt(r0 e / lambda_e)`` with the equivalent conicity of EN 15302's Annex B
  at that amplitude;
* :func:`plot_profiles`, :func:`report`, :func:`write_reference`: the figure (the bifurcation diagram beside the
  equivalent conicity against the amplitude) and the reference results, a function of the parameters only.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rollcontact.stepping import WheelsetContactModel, WheelsetContactParameters
from rollcontact_cosim.master import MASTERS, ensure_scene_fmus, run_cosimulation
from rollcontact_cosim.scenes import COSIM_DIR, load_cosim_scene
from rollcontact_cosim.wheelset.model import KalkerLinearLaw, WheelsetError, WheelsetParameters, simulate_profiles
from rollcontact_cosim.wheelset.stability import critical_speed
from rollcontact_cosim.wheelset.study import decay_rate, upward_crossings, wavelength, zero_crossing

__all__ = ["AMPLITUDES", "SCENE", "SPEEDS", "STARTS", "STEPS", "Linearisation", "ProfileRun", "ProfilesStudy",
           "hunting_diagram", "klingel_check", "plot_profiles", "profile_run", "report", "write_reference"]

SCENE = "wheelset_hunting_profiles"
"""The scene the study runs: ``models/cosim/wheelset_hunting_profiles.toml``."""

SPEEDS = tuple(float(v) for v in range(20, 78, 3))
"""The sweep's speeds [m/s]: 20 ... 77 m/s, 20 of them."""

STARTS = (5e-4, 8e-3)
"""The starts y0 [m]: 0.5 mm (a small perturbation) and 8 mm (on the flange)."""

TRAVEL = 10.0
"""Simulated time [s] of each run."""

STEPS = {"fmpy": None, "libcosim": 5e-4}
"""Each master's communication step [s] (None: the scene's, 1 ms).  libcosim's fixed-step algorithm is Jacobi (the
host steps on the contact's loads of the step before, with their derivatives): at 1 ms that lag grows in flange
contact at 74 m/s from the 8 mm start until the wheelset leaves the geometry table's range, where at 0.5 ms it
settles on the limit cycle the fmpy master's Gauss-Seidel run finds (6.35 against 6.33 mm)."""

WINDOW = 2.0
"""The last seconds of a run over which the limit cycle's amplitude and frequency are read."""

GROWTH_WINDOW = 3.0
"""The first seconds of a run over which the growth rate of |y| is fitted (while |y| stays below twice the start)."""

SETTLED = 2e-5
"""[m]: a run whose largest |y| over the last :data:`WINDOW` seconds is below this has no limit cycle (amplitude 0)."""

DECAYING = 0.97
"""A run whose largest |y| over each of the last two :data:`WINDOW` s falls below this share of the one before is
still decaying (more than about 1.5 % per second, twice running; an irregular limit cycle on the flange does not keep
falling): no limit cycle (amplitude 0)."""

FLANGE_ANGLE = 0.5
"""[rad]: a run whose largest contact angle over the last :data:`WINDOW` exceeds this rides on the flange."""

AMPLITUDES = tuple(float(a) for a in np.round(np.concatenate([np.arange(0.3, 1.0, 0.1), np.arange(1.0, 10.01, 0.25)])
                                              * 1e-3, 9))
"""Amplitudes [m] of the conicity panel: 0.3 ... 10 mm."""

TREAD = 6e-3
"""[m]: the equivalent linearisation's curve is drawn up to this amplitude (the tread and the flange root; on the
flange its one set of creep coefficients, the centred contacts', and its small-slope cone no longer describe the
wheelset)."""

KLINGEL_SPEED = 20.0
"""[m/s]: the low speed of :func:`klingel_check` (well below the onset; the free wheelset keeps its amplitude)."""


@dataclass(frozen=True)
class ProfileRun:
    """One run of the sweep (:func:`profile_run`).

    Attributes
    ----------
    speed : float
        V [m/s].
    start : float
        y0 [m].
    amplitude : float
        The limit cycle's amplitude [m]: the largest |y| over the last :data:`WINDOW`, 0 below :data:`SETTLED` or
        where it still decays (:data:`DECAYING`).
    final : float
        The largest |y| [m] over the last :data:`WINDOW`, whatever the run does.
    frequency : float
        [Hz] of y over the last :data:`WINDOW` (0 without two upward zero crossings).
    growth : float
        Growth rate [1/s] of |y| over the first :data:`GROWTH_WINDOW` (NaN with fewer than three peaks).
    flange : bool
        Whether the limit cycle rides on the flange (a contact angle above :data:`FLANGE_ANGLE`).
    wall_time : float
        Seconds the co-simulation's step loop took (not part of the reference results).
    cpu_time : float
        Processor seconds of the run in its process, the FMUs' Python included (not part of the reference results).
    """

    speed: float
    start: float
    amplitude: float
    final: float
    frequency: float
    growth: float
    flange: bool
    wall_time: float = 0.0
    cpu_time: float = 0.0


def analyse(speed: float, start: float, times: np.ndarray, lateral: np.ndarray, angles: np.ndarray | None = None,
            wall_time: float = 0.0) -> ProfileRun:
    """The :class:`ProfileRun` of the time history y(t) [m] (host axes) and the largest contact angle [rad] per
    sample (None: not recorded)."""
    window = times >= times[-1] - WINDOW
    peaks = []
    for k in (1, 2, 3):  # the largest |y| over the last window, the one before and the one before that
        span = (times >= times[-1] - k * WINDOW) & (times < times[-1] - (k - 1) * WINDOW if k > 1 else True)
        peaks.append(float(np.max(np.abs(lateral[span]))) if span.any() else peaks[-1])
    peak = peaks[0]
    decaying = peaks[0] < DECAYING * peaks[1] and peaks[1] < DECAYING * peaks[2]
    amplitude = peak if peak >= SETTLED and not decaying else 0.0
    crossings = upward_crossings(times[window], lateral[window])
    frequency = (crossings.size - 1) / (crossings[-1] - crossings[0]) if crossings.size >= 2 and amplitude else 0.0
    early = times <= GROWTH_WINDOW
    try:
        growth, _ = decay_rate(times[early], lateral[early], start=0.2, limit=2.0 * start)
    except WheelsetError:
        growth = math.nan
    flange = bool(angles is not None and amplitude and np.max(angles[window]) > FLANGE_ANGLE)
    return ProfileRun(float(speed), float(start), amplitude, peak, float(frequency), float(growth), flange, wall_time)


def profile_run(speed: float, start: float, fmu_dir: Path | str | None = None, master: str = "fmpy",
                stop_time: float = TRAVEL, step_size: float | None = None, contact: dict | None = None,
                build: bool = False) -> ProfileRun:
    """Co-simulate the scene at ``speed`` [m/s] from y0 = ``start`` [m] through ``master`` for ``stop_time`` [s]
    (the scene's step unless ``step_size``; ``contact`` overrides the WheelsetContact's parameters); the FMUs in
    ``fmu_dir`` (built there first with ``build``).

    Raises
    ------
    RuntimeError
        An FMU refused a step (the message says which, and why).
    """
    clock = time.process_time()
    result = run_cosimulation(SCENE, master=master, step_size=step_size, stop_time=stop_time,
                              host={"speed": float(speed), "initial_lateral_displacement": float(start)},
                              contact=contact, fmu_dir=fmu_dir, build=build)
    if not result.success:
        raise RuntimeError(f"the profile hunting run at {speed} m/s from {start} m through {master} stopped: "
                           f"{result.message}")
    values = result.values
    angles = np.maximum(values["WheelsetContact.contact_angle_left"], values["WheelsetContact.contact_angle_right"])
    run = analyse(speed, start, values["time"], values["Wheelset.lateral_displacement"], angles, result.wall_time)
    return dataclasses.replace(run, cpu_time=time.process_time() - clock)


# the equivalent linearisation -----------------------------------------------------------------------------------
class Linearisation:
    """The wheelset of the scene linearised at an amplitude A (module docstring): the cone of the equivalent
    conicity ``lambda_e(A)`` with the lateral stiffness ``k_y + k_g(A)`` and Kalker's coefficients of the centred
    contacts, in :mod:`rollcontact_cosim.wheelset.stability`'s equations.

    Parameters
    ----------
    host : WheelsetParameters
        The host's parameters (mass, inertia, suspension, load per wheel, speed).
    contact : WheelsetContactModel
        The contact's model (its geometry table).
    """

    def __init__(self, host: WheelsetParameters, contact: WheelsetContactModel):
        self.host, self.contact = host, contact
        load = host.normal_load
        (f11, f22, f23, f33), _ = contact.creep_coefficients(0.0, load)
        self.law = KalkerLinearLaw(f11, f22, f23, f33)
        functions = contact.contact_functions()
        centre = float(np.interp(0.0, functions.shift, functions["left_wheel_lateral"]))
        self.contact_half_distance = contact.wheelset.taping_line + centre
        self.contact_angle = float(np.interp(0.0, functions.shift, functions["left_contact_angle"]))
        self.rolling_radius = contact.wheelset.nominal_radius

    def conicity(self, amplitude: float, method: str = "harmonic") -> float:
        """lambda_e [1] at the amplitude [m] (:meth:`rollcontact.stepping.WheelsetContactModel.
        equivalent_conicity`)."""
        return self.contact.equivalent_conicity(amplitude, method)

    def gravitational_stiffness(self, amplitude: float) -> float:
        """k_g [N/m] at the amplitude [m] (module docstring; :meth:`rollcontact.stepping.WheelsetContactModel.
        gravitational_stiffness`)."""
        return self.contact.gravitational_stiffness(amplitude, self.host.normal_load)

    def parameters(self, amplitude: float) -> WheelsetParameters:
        """The cone wheelset equivalent at the amplitude [m]."""
        return dataclasses.replace(self.host, conicity=self.conicity(amplitude), contact_angle=self.contact_angle,
                                   rolling_radius=self.rolling_radius,
                                   contact_half_distance=self.contact_half_distance,
                                   lateral_stiffness=self.host.lateral_stiffness
                                   + self.gravitational_stiffness(amplitude), contact_model=0)

    def critical_speed(self, amplitude: float) -> float:
        """V_c [m/s] of the equivalent wheelset at the amplitude [m]."""
        return critical_speed(self.parameters(amplitude), self.law)

    def wavelength(self, amplitude: float) -> float:
        """Klingel's wavelength ``2 pi sqrt(r0 e / lambda_e)`` [m] with EN 15302 Annex B's conicity (the nonlinear
        kinematic oscillation's) at the amplitude [m]."""
        return 2.0 * math.pi * math.sqrt(self.rolling_radius * self.contact_half_distance
                                         / self.conicity(amplitude, "klingel"))


def scene_models(contact: dict | None = None) -> tuple[WheelsetParameters, WheelsetContactModel]:
    """The scene's host parameters and the WheelsetContact's model (its ``[contact]`` table, with ``contact``
    over it), in process."""
    scene = load_cosim_scene(SCENE)
    host = WheelsetParameters(**scene.host_parameters("gauss-seidel"))
    values = {**scene.contact_parameters(), **(contact or {})}
    return host, WheelsetContactModel(WheelsetContactParameters(**values))


@dataclass(frozen=True)
class KlingelPoint:
    """:func:`klingel_check` at one amplitude: the start [m], the largest |y| after the first period [m], the
    simulated wavelength and Klingel's at the start's equivalent conicity [m]."""

    start: float
    amplitude: float
    measured: float
    klingel: float

    @property
    def error(self) -> float:
        return self.measured / self.klingel - 1.0


def klingel_check(amplitudes=(5e-4, 1e-3, 2e-3, 3e-3), speed: float = KLINGEL_SPEED, periods: int = 4,
                  step_size: float = 1e-3) -> list[KlingelPoint]:
    """The free wheelset of the scene (no suspension) on profiles, in process (:func:`rollcontact_cosim.wheelset.
    model.simulate_profiles` with the WheelsetContact's model), started at each amplitude on its kinematic motion
    (``psi' = -V lambda_e y0 / (e r0)``: no longitudinal creepage): its wavelength over ``periods`` periods after the
    first against Klingel's with the equivalent conicity of EN 15302 Annex B at the start."""
    host, contact = scene_models()
    linear = Linearisation(host, contact)
    out = []
    for start in amplitudes:
        klingel = linear.wavelength(start)
        lam = linear.conicity(start, "klingel")
        p = dataclasses.replace(host, speed=float(speed), lateral_stiffness=0.0, yaw_stiffness=0.0,
                                initial_lateral_displacement=float(start), initial_yaw_angle=0.0,
                                initial_lateral_velocity=0.0,
                                initial_yaw_rate=-speed * lam * start / (linear.contact_half_distance
                                                                          * linear.rolling_radius))
        contact.reset(0.0)
        steps = round((periods + 1) * klingel / speed / step_size)
        times, states = simulate_profiles(p, contact, steps * step_size, step_size)
        after = times >= klingel / speed
        out.append(KlingelPoint(float(start), float(np.max(np.abs(states[after, 0]))),
                                wavelength(times, states[:, 0], speed), klingel))
    return out


# the sweep --------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ProfilesStudy:
    """Result of :func:`hunting_diagram`.

    Attributes
    ----------
    runs : tuple of ProfileRun
        By speed, then start.
    master : str
        The master that ran them.
    wall_time : float
        Seconds the sweep took (FMU builds and cluster start included; not part of the reference results).
    """

    runs: tuple[ProfileRun, ...]
    master: str
    wall_time: float = 0.0

    def of(self, start: float) -> list[ProfileRun]:
        """The runs from ``start`` [m], by speed."""
        return [run for run in self.runs if run.start == start]

    @property
    def onset(self) -> float | None:
        """The speed [m/s] where the small start's growth rate crosses zero (linear between the swept speeds;
        None without a crossing)."""
        small = [run for run in self.of(min(STARTS)) if math.isfinite(run.growth)]
        return zero_crossing([run.speed for run in small], [run.growth for run in small])

    @property
    def nonlinear_critical_speed(self) -> float | None:
        """The lowest swept speed [m/s] at which a run from either start ends on a limit cycle (None: none)."""
        return min((run.speed for run in self.runs if run.amplitude > 0.0), default=None)


def hunting_diagram(speeds=SPEEDS, starts=STARTS, fmu_dir: Path | str | None = None, master: str = "fmpy", *,
                    stop_time: float = TRAVEL, client=None, scheduler: str | None = None,
                    n_workers: int = 2) -> ProfilesStudy:
    """Every (speed [m/s], start [m]) pair co-simulated through ``master`` at its step (:data:`STEPS`; one task
    each: ``client``/``scheduler``/``n_workers`` as in :func:`rollcontact_cosim.sweep.run_sweep`, ``n_workers=0`` in
    process), the scene's FMUs in
    ``fmu_dir`` (``models/`` when None; libcosim's in its ``integer_codes/`` folder), built first where missing or
    stale."""
    from rollcontact_cosim.master import FMU_DIR
    from rollcontact_cosim.sweep import submit

    if master not in MASTERS:
        raise ValueError(f"master = {master!r}: the wheelset runs through {' or '.join(MASTERS)}")
    clock = time.perf_counter()
    folder = str(Path(FMU_DIR if fmu_dir is None else fmu_dir).resolve())
    ensure_scene_fmus(SCENE, master, folder)
    arguments = [(float(v), float(s), folder, master, float(stop_time), STEPS[master]) for v in sorted(speeds)
                 for s in starts]
    if client is None and scheduler is None and n_workers == 0:
        runs = [profile_run(*args) for args in arguments]
    else:
        runs = submit(profile_run, arguments, client, scheduler, n_workers)
    return ProfilesStudy(tuple(runs), master, time.perf_counter() - clock)


# figure and reference ---------------------------------------------------------------------------------------------
def plot_profiles(study: ProfilesStudy, linear: Linearisation, path: Path | str) -> Path:
    """PNG: the bifurcation diagram (limit-cycle amplitude of y against speed from both starts, the equivalent
    linearisation's curve, the linear and nonlinear critical speeds, the flange marked) beside the equivalent
    conicity against the amplitude."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, cx) = plt.subplots(1, 2, figsize=(12.5, 5.4), gridspec_kw={"width_ratios": (1.6, 1)},
                                 layout="constrained")
    curve = [(linear.critical_speed(a), a) for a in AMPLITUDES if a <= TREAD]
    ax.plot([v for v, _ in curve], [1e3 * a for _, a in curve], "--", color="0.45", lw=1.0,
            label="equivalent linearisation V_c(lambda_e(A), k_g(A)), tread and flange root")
    styles = {min(STARTS): ("o", "C0"), max(STARTS): ("s", "C3")}
    for start in STARTS:
        runs = study.of(start)
        marker, colour = styles[start]
        ax.plot([r.speed for r in runs], [1e3 * r.amplitude for r in runs], marker, color=colour, mfc="none",
                ms=7 if start == max(STARTS) else 5, label=f"limit cycle from y0 = {1e3 * start:g} mm")
        flange = [r for r in runs if r.flange]
        ax.plot([r.speed for r in flange], [1e3 * r.amplitude for r in flange], marker, color=colour,
                ms=7 if start == max(STARTS) else 5)
    vc = linear.critical_speed(min(STARTS))
    ax.axvline(vc, color="C0", ls=":", lw=1.2, label=f"linear critical speed (A = {1e3 * min(STARTS):g} mm): "
                                                     f"{vc:.1f} m/s")
    if study.nonlinear_critical_speed is not None:
        ax.axvline(study.nonlinear_critical_speed, color="C3", ls="-.", lw=1.2,
                   label=f"nonlinear critical speed: {study.nonlinear_critical_speed:.0f} m/s")
    if study.onset is not None:
        ax.axvline(study.onset, color="C2", ls=":", lw=1.0, label=f"onset from {1e3 * min(STARTS):g} mm: "
                                                                 f"{study.onset:.1f} m/s")
    ax.axhline(1e3 * 6.25, color="0.7", lw=0.8)
    ax.text(min(SPEEDS), 1e3 * 6.25, " flange contact (6.25 mm)", fontsize=7, va="bottom", color="0.4")
    ax.set_xlim(min(SPEEDS) - 2, max(SPEEDS) + 2)
    ax.set_ylim(0.0, 1e3 * max(max(r.amplitude for r in study.runs), 8e-3) * 1.1)
    ax.set_xlabel("speed V [m/s]")
    ax.set_ylabel("limit-cycle amplitude of y [mm] (filled: on the flange)")
    p = linear.host
    ax.set_title(f"bifurcation diagram, S1002 / UIC60 1:40 ({study.master}): m = {p.mass:g} kg, k_y = "
                 f"{p.lateral_stiffness:.3g} N/m, k_psi = {p.yaw_stiffness:.3g} N m/rad, "
                 f"Q = {p.normal_load / 1e3:g} kN", fontsize=9)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7, loc="upper left")
    amplitudes = np.array(AMPLITUDES)
    cx.plot(1e3 * amplitudes, [linear.conicity(a) for a in amplitudes], "-", color="C0",
            label="harmonic linearisation of Delta r")
    cx.plot(1e3 * amplitudes, [linear.conicity(a, "klingel") for a in amplitudes], "--", color="C1",
            label="Klingel (EN 15302 Annex B)")
    cx.set_xlabel("amplitude y^ [mm]")
    cx.set_ylabel("equivalent conicity lambda_e [1]")
    cx.set_title("equivalent conicity", fontsize=9)
    cx.set_ylim(0.0, None)
    cx.grid(True, lw=0.3)
    cx.legend(fontsize=7)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def report(study: ProfilesStudy, linear: Linearisation, klingel: list[KlingelPoint]) -> str:
    """The study's results as markdown (a function of the parameters only: no wall times)."""
    lines = ["| V [m/s] | " + " | ".join(f"A from {1e3 * s:g} mm [mm] | final [mm] | f [Hz] | flange"
                                         for s in STARTS) + f" | growth from {1e3 * min(STARTS):g} mm [1/s] |",
             "|---|" + "---|---|---|---|" * len(STARTS) + "---|"]
    by = {(r.speed, r.start): r for r in study.runs}
    for speed in sorted({r.speed for r in study.runs}):
        cells = []
        for start in STARTS:
            r = by[speed, start]
            cells += [f"{1e3 * r.amplitude:.3f}", f"{1e3 * r.final:.3f}", f"{r.frequency:.2f}",
                      "yes" if r.flange else ""]
        small = by[speed, min(STARTS)]
        growth = f"{small.growth:+.3f}" if math.isfinite(small.growth) else "past 2 y0 in < 3 peaks"
        lines.append(f"| {speed:g} | " + " | ".join(cells) + f" | {growth} |")
    vc = linear.critical_speed(min(STARTS))
    onset = study.onset
    lines += ["", f"linear critical speed (eigenvalues at lambda_e({1e3 * min(STARTS):g} mm) = "
              f"{linear.conicity(min(STARTS)):.4f}, k_g = {linear.gravitational_stiffness(min(STARTS)):.4g} N/m): "
              f"{vc:.2f} m/s",
              "onset from the small start (zero crossing of its growth rate): "
              + ("none in the sweep" if onset is None else f"{onset:.2f} m/s ({100 * (onset / vc - 1):+.1f} % of the "
                                                            "linear critical speed)"),
              "nonlinear critical speed (lowest swept speed with a limit cycle): "
              + ("none" if study.nonlinear_critical_speed is None else f"{study.nonlinear_critical_speed:g} m/s"),
              "", "| amplitude [mm] | lambda_e harmonic | lambda_e Klingel | k_g [N/m] | V_c [m/s] |",
              "|---|---|---|---|---|"]
    for a in (5e-4, 1e-3, 2e-3, 3e-3, 4e-3, 5e-3, 6e-3, 7e-3, 8e-3):
        lines.append(f"| {1e3 * a:g} | {linear.conicity(a):.4f} | {linear.conicity(a, 'klingel'):.4f} | "
                     f"{linear.gravitational_stiffness(a):.4g} | {linear.critical_speed(a):.2f} |")
    lines += ["", f"Kinematic oscillation of the free wheelset at {KLINGEL_SPEED:g} m/s (no suspension, started on "
              "its kinematic motion) against Klingel's wavelength with EN 15302 Annex B's conicity at the start:",
              "", "| start [mm] | largest y after a period [mm] | wavelength [m] | Klingel [m] | error |",
              "|---|---|---|---|---|"]
    lines += [f"| {1e3 * k.start:g} | {1e3 * k.amplitude:.3f} | {k.measured:.4f} | {k.klingel:.4f} | "
              f"{100 * k.error:+.2f} % |" for k in klingel]
    return "\n".join(lines)


REFERENCES = {"fmpy": COSIM_DIR / "wheelset_hunting_profiles_fmpy.md",
              "libcosim": COSIM_DIR / "wheelset_hunting_profiles_libcosim.md"}
"""Reference results of the study through each master (:func:`write_reference`)."""


def write_reference(study: ProfilesStudy, linear: Linearisation, klingel: list[KlingelPoint],
                    path: Path | str | None = None) -> Path:
    """Write :func:`report` of a study of the scene's defaults (the speeds :data:`SPEEDS`, starts :data:`STARTS`,
    :data:`TRAVEL` seconds each) to ``path`` (default: the master's :data:`REFERENCES`)."""
    path = REFERENCES[study.master] if path is None else Path(path)
    header = [f"# {SCENE}: reference results through {study.master}", "",
              f"Written by `python benchmarks/wheelset_hunting_profiles.py --master {study.master}`: the scene's "
              f"wheelset at {len({r.speed for r in study.runs})} speeds from y0 = "
              + " and ".join(f"{1e3 * s:g} mm" for s in STARTS) + f", {TRAVEL:g} s each at "
              + ("the scene's step" if STEPS[study.master] is None else f"a step of {1e3 * STEPS[study.master]:g} ms "
                 "(Jacobi: rollcontact_cosim.wheelset.profiles.STEPS)") + "; the "
              f"limit cycle's amplitude is the largest |y| over the last {WINDOW:g} s ('final'; 0 below "
              f"{1e3 * SETTLED:g} mm or where it still decays), "
              f"its growth rate fitted over the first {GROWTH_WINDOW:g} s. Every figure is a function of the "
              "parameters only.", ""]
    path.write_text("\n".join(header) + report(study, linear, klingel) + "\n")
    return path
