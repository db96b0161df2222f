"""The hunting scene co-simulated: the Wheelset host FMU and one RollingContact3D FMU with two contacts
(``build_fmu.py --contacts 2``), the system of ``models/cosim/wheelset_hunting.toml`` (:data:`SCENE`), run by
either master of :mod:`rollcontact_cosim.master` from that description.

Through fmpy each macro step is Gauss-Seidel with the contact first, the sequence
:func:`rollcontact_cosim.wheelset.model.simulate` runs in process: the host's creepages, loads and speeds at t_n go
to the contact FMU, which steps; its forces, moments and Jacobians (``dFx_dxi[k]`` ... ``dMz_dphi[k]``) go to the
host, which steps with the linearly implicit integrator of :class:`~rollcontact_cosim.wheelset.model.WheelsetModel`.
Through libcosim (fixed step, Jacobi) the host's forces lag one step and the host runs with ``force_lag = 1``.  Both
contacts use the wheel's axes (the host's convention) and the gap curvatures ``A = 1/(2 r0)``, ``B = 1/(2 R_rail)``
(:func:`contact_parameters`).

:class:`LibraryContactLaw` is the contact FMU's model in process (the same :class:`rollcontact.stepping.EllipticModel`):
``simulate`` with it is the co-simulation bit for bit, which ``tests/cosim/wheelset/test_cosim.py`` checks.
:func:`cosim_hunting_sweep` is the speed sweep of :func:`rollcontact_cosim.wheelset.study.hunting_sweep`
co-simulated (one task per speed, on dask or in process) through either master (:data:`MASTERS`), against the
eigenvalues of the wheelset linearised with the contact FMU's own Jacobian at zero creepage, each master with its
reference results (:data:`REFERENCES`).
"""

from __future__ import annotations

import dataclasses
import math
import textwrap
from pathlib import Path

import numpy as np

from rollcontact.stepping import EllipticModel, EllipticParameters
from rollcontact_cosim.master import MASTERS, ensure_scene_fmus, run_cosimulation
from rollcontact_cosim.scenes import COSIM_DIR
from rollcontact_cosim.wheelset.model import STATES, ContactForces, WheelsetParameters
from rollcontact_cosim.wheelset.stability import critical_speed, klingel_wavelength, least_damped, linearised
from rollcontact_cosim.wheelset.study import SPEEDS, HuntingSweep, SpeedRun, decay_rate, plot_hunting, zero_crossing

__all__ = ["MASTERS", "REFERENCES", "SCENE", "LibraryContactLaw", "contact_parameters", "cosim_hunting_sweep",
           "cosimulate", "host_parameters", "write_cosim_reference"]

SCENE = "wheelset_hunting"
"""The scene whose system the co-simulations run: ``models/cosim/wheelset_hunting.toml``."""


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


def host_parameters(parameters: WheelsetParameters) -> dict:
    """The host FMU's parameters of ``parameters``, every field but ``force_lag`` (the master's algorithm sets it:
    :meth:`rollcontact_cosim.scenes.CosimScene.host_parameters`)."""
    return {f.name: getattr(parameters, f.name) for f in dataclasses.fields(parameters) if f.name != "force_lag"}


def cosimulate(parameters: WheelsetParameters, stop_time: float, step_size: float, fmu_dir: Path | str | None = None,
               contact: dict | None = None, *, master: str = "fmpy", build: bool = True
               ) -> tuple[np.ndarray, np.ndarray]:
    """Co-simulate the wheelset with the contact FMU through ``master``; times [s] and host states (rows
    ``y, psi, y', psi'``), as :func:`~rollcontact_cosim.wheelset.model.simulate` returns them.

    Parameters
    ----------
    parameters : WheelsetParameters
        The host's parameters (``force_lag`` follows the master: 0 through fmpy, 1 through libcosim).
    stop_time, step_size : float
        t_end and the macro step H [s] (through libcosim a whole number of nanoseconds).
    fmu_dir : Path, optional
        The folder of the FMUs (``models/`` when None), built there when missing or stale unless ``build`` is
        False; libcosim's in its ``integer_codes/`` folder.
    contact : dict, optional
        The contact FMU's parameters (default :func:`contact_parameters`).
    master : str
        ``"fmpy"`` (Gauss-Seidel, the contact first) or ``"libcosim"`` (Jacobi).

    Raises
    ------
    RuntimeError
        An FMU refused a step (the message says which, and why).
    """
    result = run_cosimulation(SCENE, master=master, step_size=step_size, stop_time=stop_time,
                              host=host_parameters(parameters),
                              contact=contact_parameters(parameters) if contact is None else contact,
                              fmu_dir=fmu_dir, build=build)
    if not result.success:
        raise RuntimeError(f"the wheelset co-simulation through {master} stopped: {result.message}")
    return result.values["time"], np.column_stack([result.values[f"Wheelset.{name}"] for name in STATES])


def cosim_speed(parameters: WheelsetParameters, speed: float, fmu_dir: str, contact: dict, periods: int = 12,
                steps_per_period: int = 200, settle: int = 2, amplitude_limit: float = 0.01,
                master: str = "fmpy") -> SpeedRun:
    """:func:`rollcontact_cosim.wheelset.study.run_speed` co-simulated through ``master`` (:data:`MASTERS`; the
    FMUs in ``fmu_dir`` are built already): the decay rate of y at ``speed`` over ``periods`` kinematic periods
    (after ``settle``, while |y| <= ``amplitude_limit`` [m]) against the eigenvalues of the wheelset linearised
    with the contact's Jacobian at zero creepage."""
    p = dataclasses.replace(parameters, speed=float(speed))
    period = klingel_wavelength(p) / speed
    step = period / steps_per_period
    if master == "libcosim":  # its clock counts whole nanoseconds
        step = round(step * 1e9) / 1e9
    times, states = cosimulate(p, step * steps_per_period * periods, step, fmu_dir, contact, master=master,
                               build=False)
    rate, peaks = decay_rate(times, states[:, 0], start=settle * period, limit=amplitude_limit)
    mode = least_damped(p, linearised(LibraryContactLaw(contact), p))
    return SpeedRun(float(speed), rate, mode.real, peaks, mode.imag / (2.0 * math.pi))


def cosim_hunting_sweep(speeds, fmu_dir: Path | str, parameters: WheelsetParameters | None = None,
                        contact: dict | None = None, *, periods: int = 12, steps_per_period: int = 200, client=None,
                        scheduler: str | None = None, n_workers: int = 2, master: str = "fmpy") -> HuntingSweep:
    """The decay rate at each speed co-simulated through ``master`` (one task each: ``client``/``scheduler``/
    ``n_workers`` as in :func:`rollcontact_cosim.sweep.run_sweep`, ``n_workers=0`` in process), the critical speed of
    their zero crossing and the eigenvalues' with the contact FMU's Jacobian at zero creepage
    (:class:`LibraryContactLaw`); the scene's FMUs in ``fmu_dir`` (libcosim's in its ``integer_codes/`` folder),
    built first where missing or stale."""
    from rollcontact_cosim.sweep import submit

    if master not in MASTERS:
        raise ValueError(f"master = {master!r}: the wheelset runs through {' or '.join(MASTERS)}")
    p = WheelsetParameters() if parameters is None else parameters
    contact = contact_parameters(p) if contact is None else contact
    ensure_scene_fmus(SCENE, master, fmu_dir)
    folder = str(Path(fmu_dir).resolve())
    speeds = sorted(float(v) for v in speeds)
    arguments = [(p, v, folder, contact, periods, steps_per_period, 2, 0.01, master) for v in speeds]
    if client is None and scheduler is None and n_workers == 0:
        runs = [cosim_speed(*args) for args in arguments]
    else:
        runs = submit(cosim_speed, arguments, client, scheduler, n_workers)
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
