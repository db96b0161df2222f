"""The hunting scene as a co-simulation through fmpy: the Wheelset host FMU and one RollingContact3D FMU with two
contacts (``build_fmu.py --contacts 2``), coupled by :data:`rollcontact_cosim.wheelset.CONNECTIONS` and the
Jacobians.

Each macro step is Gauss-Seidel with the contact first, the sequence :func:`rollcontact_cosim.wheelset.simulate`
runs in process: the host's creepages, loads and speeds at t_n go to the contact FMU, which steps; its forces,
moments and Jacobians (``dFx_dxi[k]`` ... ``dMz_dphi[k]``) go to the host, which steps with the linearly implicit
integrator of :class:`~rollcontact_cosim.wheelset.WheelsetModel`.  Both contacts use the wheel's axes (the host's
convention) and the gap curvatures ``A = 1/(2 r0)``, ``B = 1/(2 R_rail)`` (:func:`contact_parameters`).

:class:`LibraryContactLaw` is the contact FMU's model in process (the same
:class:`rollcontact.stepping.EllipticModel`): ``simulate`` with it is the co-simulation bit for bit,
which ``tests/cosim/wheelset/test_cosim.py`` checks.  :func:`cosim_hunting_sweep` is the speed sweep of
:func:`rollcontact_cosim.wheelset.study.hunting_sweep` co-simulated (one task per speed, on dask or in process),
against the eigenvalues of the wheelset linearised with the contact FMU's own Jacobian at zero creepage.
:func:`cosimulate_libcosim` runs the same system with libcosim's fixed-step (Jacobi) algorithm, and the sweep runs
through either master (:data:`MASTERS`), each with its reference results (:data:`REFERENCES`).
"""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import numpy as np

from rollcontact.stepping import EllipticModel, EllipticParameters
from rollcontact_cosim.fmus import ROOT
from rollcontact_cosim.master import Slave
from rollcontact_cosim.scenes import COSIM_DIR
from rollcontact_cosim.wheelset.model import HOST, ContactForces, WheelsetParameters
from rollcontact_cosim.wheelset.stability import critical_speed, klingel_wavelength, least_damped, linearised
from rollcontact_cosim.wheelset.study import SPEEDS, HuntingSweep, SpeedRun, decay_rate, plot_hunting, zero_crossing

__all__ = ["CONTACT_MODEL", "MASTERS", "REFERENCES", "LibraryContactLaw", "contact_parameters", "cosim_hunting_sweep",
           "cosimulate", "cosimulate_libcosim", "ensure_wheelset_fmus", "write_cosim_reference"]


CONTACT_MODEL = "RollingContact3D_2"
"""The contact FMU of the scene: the elliptic contact with two contacts (``build_fmu.py --contacts 2``)."""

INPUTS = ("normal_load", "longitudinal_creep", "lateral_creep", "spin", "velocity")
FORCES = ("longitudinal_force", "lateral_force", "spin_moment")
JACOBIAN = tuple(f"d{force}_d{symbol}" for force in ("Fx", "Fy", "Mz") for symbol in ("xi", "eta", "phi"))
STATES = ("lateral_displacement", "yaw_angle", "lateral_velocity", "yaw_rate")


def contact_parameters(parameters: WheelsetParameters, *, rail_profile_radius: float = 0.3,
                       youngs_modulus: float = 210e9, poisson_ratio: float = 0.25, friction_coefficient: float = 0.3,
                       method: int = 1) -> dict:
    """The contact FMU's parameters for the wheelset: one material and law, both contacts with the curvatures
    ``A = 1/(2 r0)`` (rolling radius) and ``B = 1/(2 R_rail)`` (straight cone on a rail head of profile radius
    ``rail_profile_radius`` [m]); ``method`` a code of :data:`rollcontact.stepping.elliptic.parameters.METHOD_LEVELS`
    (default 1, the linear theory)."""
    curvatures = (0.5 / parameters.rolling_radius, 0.5 / rail_profile_radius)
    return {"youngs_modulus": youngs_modulus, "poisson_ratio": poisson_ratio,
            "friction_coefficient": friction_coefficient, "method": method,
            **{f"{name}[{k}]": value for k in (1, 2)
               for name, value in zip(("curvature_longitudinal", "curvature_lateral"), curvatures, strict=True)}}


class LibraryContactLaw:
    """The contact FMU's model in process, as a creep-force law of :func:`rollcontact_cosim.wheelset.simulate`:
    one contact of an :class:`EllipticModel` with the FMU's parameters (both contacts have the same curvatures)."""

    def __init__(self, contact: dict):
        shared = {k: v for k, v in contact.items() if "[" not in k}
        self.model = EllipticModel(EllipticParameters(
            **shared, curvature_longitudinal=(contact["curvature_longitudinal[1]"],),
            curvature_lateral=(contact["curvature_lateral[1]"],)))

    def outputs(self, normal_load, xi, eta, phi, velocity):
        return self.model.contact_step(0, float(normal_load), float(xi), float(eta), float(phi), float(velocity))

    def __call__(self, normal_load, xi, eta, phi, velocity) -> ContactForces:
        return ContactForces(*self.outputs(normal_load, xi, eta, phi, velocity)[:3])

    def jacobian(self, normal_load, xi, eta, phi, velocity) -> np.ndarray:
        return np.reshape(self.outputs(normal_load, xi, eta, phi, velocity)[8:17], (3, 3))


def cosimulate(parameters: WheelsetParameters, stop_time: float, step_size: float, fmu_dir: Path | str,
               contact: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Co-simulate the wheelset with the contact FMU; times [s] and host states (rows ``y, psi, y', psi'``), as
    :func:`~rollcontact_cosim.wheelset.simulate` returns them.

    ``fmu_dir`` holds ``Wheelset.fmu`` and ``RollingContact3D_2.fmu``; ``contact``: the contact FMU's parameters
    (default :func:`contact_parameters`).  A step the contact or the host discards raises (fmpy's
    FMICallException), with the reason in the slaves' logs.
    """
    n = int(round(stop_time / step_size))
    if n < 1 or abs(n * step_size - stop_time) > 1e-9 * stop_time:
        raise ValueError(f"stop_time = {stop_time!r} s is not a positive multiple of step_size = {step_size!r} s")
    folder = Path(fmu_dir)
    host = Slave(folder / f"{HOST}.fmu", HOST)
    wheels = Slave(folder / f"{CONTACT_MODEL}.fmu", CONTACT_MODEL)
    try:
        host.set_start_values({f.name: getattr(parameters, f.name) for f in dataclasses.fields(parameters)})
        wheels.set_start_values(contact_parameters(parameters) if contact is None else contact)
        for slave in (host, wheels):
            slave.initialise()
        sent = [f"{name}[{k}]" for k in (1, 2) for name in INPUTS]
        returned = [f"{name}[{k}]" for k in (1, 2) for name in FORCES + JACOBIAN]
        read_host = [host.reference(name) for name in sent]
        write_contact = [wheels.reference(name) for name in sent]
        read_contact = [wheels.reference(name) for name in returned]
        write_host = [host.reference(name) for name in returned]
        states_refs = [host.reference(name) for name in STATES]
        states = np.empty((n + 1, 4))
        states[0] = host.fmu.getReal(states_refs)
        for i in range(n):
            t = i * step_size
            wheels.fmu.setReal(write_contact, host.fmu.getReal(read_host))
            wheels.fmu.doStep(t, step_size)
            host.fmu.setReal(write_host, wheels.fmu.getReal(read_contact))
            host.fmu.doStep(t, step_size)
            states[i + 1] = host.fmu.getReal(states_refs)
        return np.arange(n + 1) * step_size, states
    finally:
        host.free()
        wheels.free()


def ensure_wheelset_fmus(fmu_dir: Path | str, master: str = "fmpy") -> Path:
    """The folder of ``Wheelset.fmu`` and ``RollingContact3D_2.fmu`` for ``master``, built by ``build_fmu.py`` when
    missing: ``fmu_dir`` for fmpy, its ``integer_codes/`` folder for libcosim (the integer-codes build: libcosim lists
    no FMI enumerations, as :func:`rollcontact_cosim.fmus.ensure_fmus` arranges for the other scenes)."""
    codes = ["--integer-codes"] if master == "libcosim" else []
    folder = Path(fmu_dir) / "integer_codes" if codes else Path(fmu_dir)
    for model, args in ((HOST, ["--only", HOST, *codes]), (CONTACT_MODEL, ["--contacts", "2", *codes])):
        if not (folder / f"{model}.fmu").is_file():
            done = subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), *args, "--dest", str(folder)],
                                  capture_output=True, text=True, timeout=600)
            if done.returncode != 0:
                raise RuntimeError(f"build_fmu.py {' '.join(args)} failed:\n{done.stdout}\n{done.stderr}")
    return folder


def cosim_speed(parameters: WheelsetParameters, speed: float, fmu_dir: str, contact: dict, periods: int = 12,
                steps_per_period: int = 200, settle: int = 2, amplitude_limit: float = 0.01,
                master: str = "fmpy") -> SpeedRun:
    """:func:`rollcontact_cosim.wheelset.study.run_speed` co-simulated through ``master`` (:data:`MASTERS`; the FMUs
    in ``fmu_dir`` suit it): the decay rate of y at ``speed`` over ``periods`` kinematic periods (after ``settle``,
    while |y| <= ``amplitude_limit`` [m]) against the eigenvalues of the wheelset linearised with the contact's
    Jacobian at zero creepage."""
    p = dataclasses.replace(parameters, speed=float(speed))
    period = klingel_wavelength(p) / speed
    step = period / steps_per_period
    if master == "libcosim":  # its clock counts whole nanoseconds
        step = round(step * 1e9) / 1e9
    times, states = MASTERS[master](p, step * steps_per_period * periods, step, fmu_dir, contact)
    rate, peaks = decay_rate(times, states[:, 0], start=settle * period, limit=amplitude_limit)
    mode = least_damped(p, linearised(LibraryContactLaw(contact), p))
    return SpeedRun(float(speed), rate, mode.real, peaks, mode.imag / (2.0 * math.pi))


def cosim_hunting_sweep(speeds, fmu_dir: Path | str, parameters: WheelsetParameters | None = None,
                        contact: dict | None = None, *, periods: int = 12, steps_per_period: int = 200, client=None,
                        scheduler: str | None = None, n_workers: int = 2, master: str = "fmpy") -> HuntingSweep:
    """The decay rate at each speed co-simulated through ``master`` (one task each: ``client``/``scheduler``/
    ``n_workers`` as in :func:`rollcontact_cosim.sweep.run_sweep`, ``n_workers=0`` in process), the critical speed of
    their zero crossing and the eigenvalues' with the contact FMU's Jacobian at zero creepage
    (:class:`LibraryContactLaw`); the FMUs are those of :func:`ensure_wheelset_fmus` for ``master``."""
    from rollcontact_cosim.sweep import submit

    if master not in MASTERS:
        raise ValueError(f"master = {master!r}: the wheelset runs through {' or '.join(MASTERS)}")
    p = WheelsetParameters() if parameters is None else parameters
    contact = contact_parameters(p) if contact is None else contact
    folder = str(ensure_wheelset_fmus(fmu_dir, master).resolve())
    speeds = sorted(float(v) for v in speeds)
    arguments = [(p, v, folder, contact, periods, steps_per_period, 2, 0.01, master) for v in speeds]
    if client is None and scheduler is None and n_workers == 0:
        runs = [cosim_speed(*args) for args in arguments]
    else:
        runs = submit(cosim_speed, arguments, client, scheduler, n_workers, fmus=False)
    return HuntingSweep(tuple(runs), critical_speed(p, linearised(LibraryContactLaw(contact), p)),
                        zero_crossing(speeds, [run.simulated for run in runs]))


REFERENCES = {"fmpy": COSIM_DIR / "wheelset_hunting_cosim.md", "libcosim": COSIM_DIR / "wheelset_hunting_libcosim.md"}
"""Reference results of the co-simulated sweep through each master (:func:`write_cosim_reference`)."""

COUPLING = {"fmpy": "through fmpy (Gauss-Seidel, the contact first)",
            "libcosim": "through libcosim (fixed step, Jacobi: the host's forces lag one step, force_lag = 1)"}
"""How each master couples the two FMUs, as the reference results say it."""


def write_cosim_reference(fmu_dir: Path | str, path: Path | str | None = None, plot: Path | str | None = None,
                          speeds=SPEEDS, master: str = "fmpy", **sweep_options) -> Path:
    """Run the co-simulated sweep of the default wheelset through ``master`` over ``speeds`` (serial unless
    ``sweep_options`` say otherwise) and write its table and critical speeds to ``path`` (default: the master's
    :data:`REFERENCES`; and the figure to ``plot``)."""
    p = WheelsetParameters()
    contact = contact_parameters(p)
    sweep = cosim_hunting_sweep(speeds, fmu_dir, p, contact, **{"n_workers": 0, "master": master, **sweep_options})
    if plot is not None:
        plot_hunting(sweep, plot, p, linearised(LibraryContactLaw(contact), p))
    path = REFERENCES[master] if path is None else path
    lines = [f"# wheelset_hunting: reference results co-simulated through {master}", "",
             *textwrap.wrap(f"Written by `rollcontact_cosim.wheelset.cosim.write_cosim_reference(master={master!r})`:"
                            " the default wheelset of `rollcontact_cosim.wheelset` co-simulated "
                            f"{COUPLING[master]} with `RollingContact3D_2` (linear theory, `contact_parameters`), 200 "
                            "steps per kinematic period; the eigenvalues with the contact FMU's Jacobian at zero "
                            "creepage. Every figure is a function of the parameters only.", 115), "",
             "| V [m/s] | co-simulated decay rate [1/s] | eigenvalue Re [1/s] | frequency [Hz] | peaks |",
             "|---|---|---|---|---|"]
    lines += [f"| {r.speed:g} | {r.simulated:+.4f} | {r.predicted:+.4f} | {r.frequency:.3f} | {r.peaks} |"
              for r in sweep.runs]
    simulated = ("none in the sweep" if sweep.simulated_critical_speed is None
                 else f"{sweep.simulated_critical_speed:.2f} m/s ({100 * sweep.error:+.2f} %)")
    lines += ["", f"critical speed: eigenvalues {sweep.predicted_critical_speed:.2f} m/s, co-simulation {simulated}"]
    Path(path).write_text("\n".join(lines) + "\n")
    return Path(path)


def cosimulate_libcosim(parameters: WheelsetParameters, stop_time: float, step_size: float, fmu_dir: Path | str,
                        contact: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The co-simulation through libcosim's fixed-step (Jacobi) algorithm: times [s] and host states as
    :func:`cosimulate`; the host runs with ``force_lag = 1`` (its forces belong to the creepages of the previous
    communication point, about which it linearises them).

    ``fmu_dir`` holds ``Wheelset.fmu`` and the integer-codes build of ``RollingContact3D_2.fmu`` (``build_fmu.py
    --contacts 2 --integer-codes``: libcosim lists no enumeration variables).  The system structure is written for
    the run (instances ``Wheelset`` and ``RollingContact3D``, the connections
    :data:`rollcontact_cosim.wheelset.CONNECTIONS` and the Jacobians); the parameters are set as initial values.
    """
    from libcosimpy.CosimEnums import CosimVariableCausality, CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    from rollcontact_cosim.osp import NAMESPACE, NS_PER_S, lookup, samples, set_start_values
    from rollcontact_cosim.wheelset.model import CONNECTIONS, CONTACT

    n = int(round(stop_time / step_size))
    step_ns = round(step_size * NS_PER_S)
    if n < 1 or abs(n * step_size - stop_time) > 1e-9 * stop_time or abs(step_size * NS_PER_S - step_ns) > 1e-6:
        raise ValueError(f"stop_time = {stop_time!r} s must be a positive multiple of step_size = {step_size!r} s, "
                         "a whole number of nanoseconds")
    folder = Path(fmu_dir).resolve()
    links = [*CONNECTIONS, *((f"{CONTACT}.{name}[{k}]", f"{HOST}.{name}[{k}]") for k in (1, 2) for name in JACOBIAN)]
    connections = "".join(
        "<VariableConnection>" + "".join(f'<Variable simulator="{end.split(".", 1)[0]}" name="{end.split(".", 1)[1]}"/>'
                                         for end in link) + "</VariableConnection>" for link in links)
    system = (f'<?xml version="1.0" encoding="utf-8"?><OspSystemStructure xmlns="{NAMESPACE}" version="0.1">'
              f"<StartTime>0.0</StartTime><BaseStepSize>{float(step_size)!r}</BaseStepSize>"
              "<Algorithm>fixedStep</Algorithm><Simulators>"
              f'<Simulator name="{HOST}" source="{(folder / f"{HOST}.fmu").as_uri()}"/>'
              f'<Simulator name="{CONTACT}" source="{(folder / f"{CONTACT_MODEL}.fmu").as_uri()}"/>'
              f"</Simulators><Connections>{connections}</Connections></OspSystemStructure>")
    start_values = {HOST: {**{f.name: getattr(parameters, f.name) for f in dataclasses.fields(parameters)},
                           "force_lag": 1},
                    CONTACT: contact_parameters(parameters) if contact is None else contact}
    log_output_level(CosimLogLevel.WARNING)
    with tempfile.TemporaryDirectory(prefix="rollcontact_wheelset_osp_") as tmp:
        config = Path(tmp, "OspSystemStructure.xml")
        config.write_text(system)
        execution = CosimExecution.from_osp_config_file(str(config))
    try:
        index, variables = set_start_values(execution, start_values)
        observer = CosimObserver.create_time_series()
        execution.add_observer(observer)
        observed = [lookup(variables[HOST], HOST, name, CosimVariableCausality.OUTPUT) for name in STATES]
        for v in observed:
            observer.start_time_series(index[HOST], v.reference, CosimVariableType(v.type))
        if not execution.step(n):
            raise RuntimeError(f"libcosim stopped before {n} steps (an FMU refused a step: rerun with the fmpy "
                               "master, cosimulate, for its reason)")
        states = np.column_stack([samples(observer, index[HOST], v, n + 1) for v in observed])
        return np.arange(n + 1) * step_size, states
    finally:
        del execution


MASTERS = {"fmpy": cosimulate, "libcosim": cosimulate_libcosim}
"""The co-simulation of the wheelset through each master: ``(parameters, stop_time, step_size, fmu_dir, contact) ->
(times, states)``."""
