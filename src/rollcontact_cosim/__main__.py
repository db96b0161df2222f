"""The main job, ``python -m rollcontact_cosim``: co-simulates a scene of ``models/cosim`` (default
``traction_ramp``, the WheelRig and RollingContact2D FMUs, built first when missing or stale), prints a summary
(peak adhesion and the creep where it occurs, macro steps, wall time per step), writes a PNG of the adhesion curve
and the recorded time histories, whose title names the friction law and its values (:func:`figure`), and with
``--csv PATH`` the recorded time histories as CSV with their units in the header (:func:`write_csv`).
``--fmi 3`` runs the FMI 3.0 FMUs (``models/fmi3/``, fmpy master) instead of the FMI 2.0 ones.

``--scene NAME`` is the same as the positional scene.  The scene ``wheelset_hunting_profiles`` runs its study
(:mod:`rollcontact_cosim.wheelset.profiles`: the speed sweep from a small and a large start co-simulated through
``--master`` on dask, the bifurcation diagram to ``--plot``).  The scene ``wheelset_hunting`` runs in process
(:func:`rollcontact_cosim.wheelset.study.run_hunting_study`: the wheelset with Kalker's linear creep forces, a
speed sweep on a local dask cluster against the linear stability analysis, Klingel's wavelength), prints its
tables and writes its figure; with ``--fmu-dir`` or ``--master libcosim`` its speed sweep is co-simulated through
that master (fmpy by default) with the scene's system, the Wheelset and RollingContact3D_2 FMUs
(:mod:`rollcontact_cosim.wheelset.cosim`); the other co-simulation options do not apply.
"""

from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

import numpy as np

from rollcontact_cosim.cli import run
from rollcontact_cosim.master import FMU_DIR, CosimResult, ensure_scene_fmus, run_cosimulation, summarise
from rollcontact_cosim.scenes import ALGORITHMS, CONTACT, DEFAULT_SCENE, load_cosim_scene

LABELS = {  # variable -> axis label
    "WheelRig.creep": "creep xi [1]",
    "WheelRig.velocity": "velocity v [m/s]",
    "WheelRig.wheel_speed": "wheel speed [rad/s]",
    "WheelRig.normal_load": "normal load N [N]",
    "WheelRig.motor_torque": "motor torque [N m]",
    "WheelRig.slip_velocity": "slip velocity [m/s]",
    "WheelRig.distance": "distance [m]",
    "RollingContact2D.tangential_force": "tangential force T [N]",
    "RollingContact2D.traction_coefficient": "traction T/N [1]",
    "RollingContact2D.creep_stiffness": "creep stiffness dT/dxi [N]",
    "RollingContact2D.contact_half_width": "contact half-width a [m]",
    "RollingContact2D.stick_half_width": "stick-zone half-width a* [m]",
    "RollingContact2D.stationarity": "stationarity lambda/a [1]",
    "RollingContact2D.method_used": "method used",
    "RollingContact2D.axis_position": "axis position [m]",
}


METHOD_LABELS = {0: "none", 1: "closed form", 2: "polynomial", 3: "discretised", 4: "relaxation lag",
                 5: "transient"}
"""``method_used`` codes (the FMU's enumeration) and their names on the plot's axis."""

STARTUP = 0.05
"""Fraction of the run at its start that the time histories mark as start-up: their y-axes are scaled to the rest,
so a start-up spike neither hides the run nor is hidden (it is clipped and the span shaded)."""


def friction_title(contact: dict) -> str:
    """The friction law and its values of the RollingContact2D parameters ``contact`` (the scene's ``[contact]``
    table over the FMU's defaults; a ``scene_file`` there is read), e.g. ``"friction: exponential falling mu(v) =
    mu_s [(1 - A) exp(-B v) + A], mu_s = 0.35, A = 0.4, B = 0.6 s/m"``; a ``rail_condition`` is named before its
    law (``"friction: wet rail (Polach 2005), exponential falling ..."``)."""
    from rollcontact.stepping import ContactModel, ContactParameters

    parameters = ContactParameters(**contact)
    friction = ContactModel(parameters).friction
    condition = (f"{parameters.codes()['rail_condition'][parameters.rail_condition]} rail (Polach 2005), "
                 if parameters.rail_condition and not parameters.scene_file else "")
    return f"friction: {condition}{friction.describe()}"


def figure(result: CosimResult, friction: str = ""):
    """The figure of the run (matplotlib, Agg backend): the adhesion curve T/N against the creep on linear axes
    (Carter's straight initial slope stays straight) above the same curve on a log creep axis (the small creeps
    resolved), beside the time histories of every recorded variable; the title names the scene, the master and
    ``friction`` (:func:`friction_title`).

    Time histories: integer outputs as steps with named levels, no offset on any axis, a constant drawn with zero
    on its axis, the creep on a log (or symmetric log) axis, and the start-up (:data:`STARTUP`) shaded, the
    y-axes scaled to the rest of the run.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    values = result.values
    names = values.dtype.names[1:]
    time = values["time"]
    columns = 2
    rows = max(2, (len(names) + columns - 1) // columns)
    fig = plt.figure(figsize=(15, max(7.0, 2.0 * rows)))
    grid = fig.add_gridspec(rows, 3, width_ratios=(1.25, 1, 1))
    split = (rows + 1) // 2
    adhesion_curve(fig.add_subplot(grid[:split, 0]), values, log=False)
    adhesion_curve(fig.add_subplot(grid[split:, 0]), values, log=True)
    start = time[0] + STARTUP * (time[-1] - time[0]) if time.size else 0.0
    for k, name in enumerate(names):
        ax = fig.add_subplot(grid[k // columns, 1 + k % columns])
        time_history(ax, time, values[name], name, start)
        if k // columns == rows - 1 or k + columns >= len(names):
            ax.set_xlabel("time [s]")
    title = f"{result.scene}: {result.master} master, {result.algorithm}, H = {result.step_size:g} s"
    fig.suptitle(f"{title}\n{friction}" if friction else title)
    fig.tight_layout()
    return fig


def plot(result: CosimResult, path: Path | str, friction: str = "") -> Path:
    """PNG of :func:`figure` at ``path``."""
    import matplotlib.pyplot as plt

    fig = figure(result, friction)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


LINEAR_SPAN = 4.0
"""The linear adhesion curve shows |creep| up to this many times the creep of the peak (where the initial slope and
the peak are; the log panel shows the whole run)."""


def adhesion_curve(ax, values, log: bool) -> None:
    """T/N against |creep|, on linear axes up to :data:`LINEAR_SPAN` times the peak's creep or (``log``) on a log
    creep axis over the run: traction (creep > 0, T/N) and braking (creep < 0, -T/N) apart, the peak of |T/N|
    marked with its value and creep."""
    creep = values["WheelRig.creep"] if "WheelRig.creep" in values.dtype.names else None
    traction = (values["RollingContact2D.traction_coefficient"]
                if "RollingContact2D.traction_coefficient" in values.dtype.names else None)
    ax.set_title("adhesion curve, log creep axis" if log else "adhesion curve")
    if creep is None or traction is None or not np.any(creep != 0.0):
        ax.text(0.5, 0.5, "no creep and traction recorded", ha="center", va="center", transform=ax.transAxes)
        return
    for sign, label in ((1.0, "traction (creep xi > 0): T/N"), (-1.0, "braking (creep xi < 0): -T/N")):
        mask = sign * creep > 0.0
        if mask.any():
            order = np.argsort(sign * creep[mask])
            ax.plot((sign * creep[mask])[order], (sign * traction[mask])[order], ".", ms=2.5, label=label)
    peak = int(np.argmax(np.abs(traction) * (creep != 0.0)))
    ax.plot(abs(creep[peak]), abs(traction[peak]), "o", mfc="none", mec="C3", ms=9)
    ax.annotate(f"peak T/N = {abs(traction[peak]):.4f}\nat creep {abs(creep[peak]):.3g}",
                (abs(creep[peak]), abs(traction[peak])), textcoords="offset points", xytext=(-14 if log else 14, 6),
                ha="right" if log else "left", color="C3",
                bbox={"boxstyle": "round", "fc": "white", "ec": "C3", "lw": 0.5})
    span = min(float(np.max(np.abs(creep))), LINEAR_SPAN * abs(creep[peak]))
    if log:
        ax.set_xscale("log")
        ax.set_xlabel("|creep| xi [1] (log axis)")
    else:
        ax.set_xlim(0.0, span)
        shown = "" if span >= float(np.max(np.abs(creep))) else f" up to {LINEAR_SPAN:g} x the peak's (all: below)"
        ax.set_xlabel(f"|creep| xi [1]{shown}")
    ax.set_ylabel("traction coefficient T/N [1]")
    ax.set_ylim(0.0, 1.3 * abs(traction[peak]) or 1.0)  # room above the peak for its label
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8, loc="upper left" if log else "best")


def time_history(ax, time, series, name: str, start: float) -> None:
    """One recorded variable against time, drawn as :func:`plot` describes."""
    series = np.asarray(series, dtype=float)
    if name.endswith("method_used"):
        ax.step(time, series, where="post", lw=1.0)
        levels = sorted({int(v) for v in series})
        ax.set_yticks(levels, [METHOD_LABELS.get(v, str(v)) for v in levels], fontsize=7)
        ax.set_ylim(min(levels) - 0.5, max(levels) + 0.5)
    else:
        ax.plot(time, series, lw=1.0)
        ax.ticklabel_format(axis="y", useOffset=False)
        steady = series[time >= start] if np.any(time >= start) else series
        low, high = float(np.min(steady)), float(np.max(steady))
        if name.endswith("creep") and np.all(series >= 0.0) and np.any(series > 0.0):
            ax.set_yscale("log")
        elif name.endswith("creep") and np.any(series < 0.0) and np.any(series > 0.0):
            ax.set_yscale("symlog", linthresh=max(1e-6, 0.01 * np.max(np.abs(series))))
        elif name.endswith("stationarity"):
            ax.set_yscale("log")
            if low > 0.0:
                ax.set_ylim(low / 2.0, high * 2.0)
                if np.max(series) > 2.0 * high:
                    ax.axvspan(time[0], start, color="0.85", lw=0)
                    ax.text(time[0], high * 2.0, " start-up (clipped)", fontsize=6, va="top")
        elif high - low <= 1e-9 * max(abs(high), abs(low), 1e-300):  # constant: its value against zero
            ax.set_ylim(min(0.0, 1.2 * low), max(0.0, 1.2 * high) or 1.0)
        else:
            margin = 0.08 * (high - low)
            ax.set_ylim(low - margin, high + margin)
            if np.min(series) < low - margin or np.max(series) > high + margin:
                ax.axvspan(time[0], start, color="0.85", lw=0)
                ax.text(time[0], high + margin, " start-up (clipped)", fontsize=6, va="top")
    ax.set_ylabel(LABELS.get(name, name), fontsize=8)
    ax.grid(True, lw=0.3)


def wheelset_hunting(args) -> int:
    """The ``wheelset_hunting`` scene in process: the tables on stdout, the figure to ``--plot``; with ``--fmu-dir``
    or ``--master libcosim`` the speed sweep co-simulated through ``--master`` with the Wheelset and
    RollingContact3D_2 FMUs of ``--fmu-dir`` (default models/; built there when missing or stale, libcosim's in its
    ``integer_codes/`` folder): :func:`rollcontact_cosim.wheelset.cosim.write_cosim_reference`'s table."""
    from rollcontact_cosim.wheelset.study import report, run_hunting_study

    if args.fmi is not None or args.algorithm or args.step_size or args.csv:
        raise ValueError("the wheelset_hunting scene runs in process, or co-simulated with --fmu-dir or --master: "
                         "--fmi, --algorithm, --step-size and --csv do not apply")
    path = args.plot or "cosim_wheelset_hunting.png"
    if args.fmu_dir or args.master != "fmpy":
        import tempfile

        from rollcontact_cosim.wheelset.cosim import write_cosim_reference

        with tempfile.TemporaryDirectory(prefix="wheelset_hunting_") as tmp:
            table = write_cosim_reference(args.fmu_dir or FMU_DIR, Path(tmp, "report.md"), path, master=args.master,
                                          n_workers=2)
            print(table.read_text())
    else:
        sweep, klingel = run_hunting_study(path)
        print(report(sweep, klingel))
    print(f"plot: {path}")
    return 0


def wheelset_hunting_profiles(args) -> int:
    """The ``wheelset_hunting_profiles`` scene's study: the speed sweep from both starts co-simulated through
    ``--master`` (fmpy by default) on two dask workers, the FMUs of ``--fmu-dir`` (default models/; built there when
    missing or stale); its tables on stdout, the bifurcation diagram to ``--plot``."""
    from rollcontact_cosim.wheelset.profiles import (
        Linearisation,
        hunting_diagram,
        klingel_check,
        plot_profiles,
        report,
        scene_models,
    )

    if args.fmi is not None or args.algorithm or args.step_size or args.csv:
        raise ValueError("the wheelset_hunting_profiles study runs the scene's system at every speed: --fmi, "
                         "--algorithm, --step-size and --csv do not apply")
    study = hunting_diagram(fmu_dir=args.fmu_dir, master=args.master)
    linear = Linearisation(*scene_models())
    path = plot_profiles(study, linear, args.plot or "cosim_wheelset_hunting_profiles.png")
    print(report(study, linear, klingel_check()))
    print(f"\n{len(study.runs)} runs through {study.master} in {study.wall_time:.0f} s\nplot: {path}")
    return 0


IN_PROCESS = {"wheelset_hunting": wheelset_hunting, "wheelset_hunting_profiles": wheelset_hunting_profiles}
"""Scenes run in process (no FMU), by name: a function of the parsed arguments returning the exit code."""


def recorded_units(names, scene, fmu_dir=None, master: str = "fmpy", fmi_version: int | None = None
                   ) -> dict[str, str]:
    """The unit of each recorded ``"Instance.variable"`` of ``names`` as the FMUs declare it (``"1"`` for a
    variable without unit: the integer codes), read from the modelDescription of the FMUs the run of ``scene`` used
    (through ``master``, from ``fmu_dir``, in ``fmi_version``)."""
    from fmpy import read_model_description

    paths = ensure_scene_fmus(scene, master, fmu_dir, fmi_version)
    declared = {f"{instance}.{v.name}": v.unit for instance, path in paths.items()
                for v in read_model_description(str(path)).modelVariables}
    return {name: declared.get(name) or "1" for name in names}


def write_csv(result: CosimResult, path: Path | str, units: dict[str, str]) -> Path:
    """The recorded time histories of ``result`` as CSV at ``path``: a header ``time [s]``, ``Instance.variable
    [unit]`` (``units``, :func:`recorded_units`), then one row per communication point, every digit of each value
    (``repr``: they read back as the same floats)."""
    names = result.values.dtype.names
    with open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow(["time [s]", *(f"{name} [{units[name]}]" for name in names[1:])])
        writer.writerows([repr(float(row[name])) for name in names] for row in result.values)
    return Path(path)


DESCRIPTION = "Co-simulate a wheel rig with a rolling contact (two FMUs), print the peak adhesion, plot the run."

EPILOG = f"""\
Scenes are TOML files of models/cosim (their format: models/cosim/README.md). The summary gives the
peak traction coefficient T/N [1], the creep xi [1] and time [s] where it occurs, and the wall time per
macro step [us]. The figure shows the adhesion curve (linear and log creep axes) and every recorded
variable against time [s]; its title names the friction law and its values.

The scene wheelset_hunting runs in process: a hunting wheelset's speed sweep against its linear
stability analysis, and Klingel's wavelength; with --fmu-dir DIR (or --master libcosim) the sweep is
co-simulated through the master with the Wheelset and RollingContact3D_2 FMUs of DIR (default models/;
built there when missing or stale). The scene wheelset_hunting_profiles runs its study: the wheelset on
S1002/UIC60 profiles (the Wheelset and WheelsetContact FMUs) at 20 speeds from 0.5 mm and 8 mm, 10 s
each, on two dask workers through --master; the bifurcation diagram goes to --plot.

examples:
  python -m rollcontact_cosim
  python -m rollcontact_cosim --scene wheelset_hunting
  python -m rollcontact_cosim --scene wheelset_hunting --fmu-dir models
  python -m rollcontact_cosim --scene wheelset_hunting --master libcosim
  python -m rollcontact_cosim --scene wheelset_hunting_profiles [--master libcosim]
  python -m rollcontact_cosim {DEFAULT_SCENE} --step-size 2e-3 --plot ramp.png --csv ramp.csv
"""


def parser() -> argparse.ArgumentParser:
    """The main job's options (``--help`` shows them with their units and examples)."""
    p = argparse.ArgumentParser(prog="python -m rollcontact_cosim", description=DESCRIPTION, epilog=EPILOG,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene", nargs="?", default=DEFAULT_SCENE,
                   help=f"scene name in models/cosim or a TOML path (default {DEFAULT_SCENE})")
    p.add_argument("--scene", dest="scene_option", metavar="SCENE",
                   help=f"the scene, as the positional argument; {', '.join(IN_PROCESS)} runs in process")
    p.add_argument("--plot", metavar="PNG", help="figure to write (default cosim_<scene>.png in the current folder)")
    p.add_argument("--csv", metavar="PATH",
                   help="also write the recorded time histories as CSV, units in the header (e.g. 'time [s]', "
                        "'RollingContact2D.tangential_force [N]')")
    p.add_argument("--algorithm", choices=ALGORITHMS, help="master algorithm (default: the scene's)")
    p.add_argument("--step-size", type=float, metavar="H", help="macro step H [s] (default: the scene's)")
    p.add_argument("--master", default="fmpy", choices=("fmpy", "libcosim"),
                   help="co-simulation master (default fmpy; libcosim needs libcosimpy)")
    p.add_argument("--fmu-dir", metavar="DIR",
                   help="folder of the FMUs, built there if missing or stale (default: models/)")
    p.add_argument("--fmi", type=int, choices=(2, 3),
                   help="FMI version of the FMUs: 2 or 3 (FMI 3.0, in <fmu-dir>/fmi3; fmpy master); default: the "
                        "scene's (2)")
    return p


def main(argv: list[str] | None = None) -> int:
    """The main job (module docstring); a bad scene or a missing optional dependency is one line and exit code 2."""
    return run("python -m rollcontact_cosim", lambda: job(argv))


def job(argv: list[str] | None) -> int:
    args = parser().parse_args(argv)
    scene = args.scene_option or args.scene
    if scene in IN_PROCESS:
        return IN_PROCESS[scene](args)
    scene = load_cosim_scene(scene)
    result = run_cosimulation(scene, master=args.master, algorithm=args.algorithm, step_size=args.step_size,
                              fmu_dir=args.fmu_dir, fmi_version=args.fmi)
    s = summarise(result)
    version = " (FMI 3.0)" if (args.fmi or scene.system.fmi_version) == 3 else ""
    print(f"scene {result.scene}: {result.master} master{version}, {result.algorithm}, H = {result.step_size:g} s, "
          f"{s['steps']} macro steps, {s['wall_time']:.3g} s wall, {s['wall_time_per_step_us']:.0f} us per step")
    if "peak_traction_coefficient" in s:
        print(f"peak adhesion T/N = {s['peak_traction_coefficient']:.4f} at creep {s['creep_at_peak']:.4g} "
              f"(t = {s['time_at_peak']:.4g} s)")
    if not result.success:
        print(f"stopped early: {result.message}", file=sys.stderr)
    friction = friction_title(scene.contact_parameters()) if scene.system.contact.model == CONTACT else ""
    path = plot(result, args.plot or f"cosim_{result.scene}.png", friction)
    print(f"plot: {path}")
    if args.csv:
        units = recorded_units(result.values.dtype.names[1:], scene, args.fmu_dir, args.master, args.fmi)
        print(f"csv: {write_csv(result, args.csv, units)}")
    return 0 if result.success else 1


if __name__ == "__main__":
    sys.exit(main())
