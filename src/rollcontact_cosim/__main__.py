"""Main job: ``python -m rollcontact_cosim [scene] [--plot out.png] [--algorithm A] [--step-size H] [--fmu-dir D]``.

Builds the FMUs if needed, co-simulates the scene (default ``traction_ramp``) with the fmpy master, prints a
summary (peak adhesion and the creep where it occurs, macro steps, wall time per step) and writes a PNG of the
recorded time histories (default ``cosim_<scene>.png`` in the current folder).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from rollcontact_cosim.master import CosimResult, run_cosimulation, summarise
from rollcontact_cosim.scenes import ALGORITHMS, DEFAULT_SCENE

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
    "RollingContact2D.creep_stiffness": "dT/dxi [N]",
    "RollingContact2D.contact_half_width": "a [m]",
    "RollingContact2D.stick_half_width": "a* [m]",
    "RollingContact2D.stationarity": "lambda/a [1]",
    "RollingContact2D.method_used": "method used",
    "RollingContact2D.axis_position": "axis position [m]",
}


def plot(result: CosimResult, path: Path | str) -> Path:
    """PNG of every recorded variable against time (matplotlib, Agg backend)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = result.values.dtype.names[1:]
    columns = 2
    rows = (len(names) + columns - 1) // columns
    fig, axes = plt.subplots(rows, columns, figsize=(11, 2.2 * rows), sharex=True, squeeze=False)
    time = result.values["time"]
    for ax, name in zip(axes.flat[:len(names)], names, strict=True):
        ax.plot(time, result.values[name], lw=1.0)
        ax.set_ylabel(LABELS.get(name, name), fontsize=8)
        ax.grid(True, lw=0.3)
        if name == "RollingContact2D.stationarity":
            ax.set_yscale("log")
    for ax in axes.flat[len(names):]:
        ax.set_visible(False)
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    fig.suptitle(f"{result.scene}: {result.master} master, {result.algorithm}, H = {result.step_size:g} s")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rollcontact_cosim", description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default=DEFAULT_SCENE,
                        help=f"scene name in models/cosim or a TOML path (default {DEFAULT_SCENE})")
    parser.add_argument("--plot", help="PNG to write (default cosim_<scene>.png in the current folder)")
    parser.add_argument("--algorithm", choices=ALGORITHMS, help="master algorithm (default: the scene's)")
    parser.add_argument("--step-size", type=float, help="macro step [s] (default: the scene's)")
    parser.add_argument("--master", default="fmpy", choices=("fmpy", "libcosim"), help="co-simulation master")
    parser.add_argument("--fmu-dir", help="folder of the FMUs, built there if missing or stale (default: models/)")
    args = parser.parse_args(argv)
    result = run_cosimulation(args.scene, master=args.master, algorithm=args.algorithm, step_size=args.step_size,
                              fmu_dir=args.fmu_dir)
    s = summarise(result)
    print(f"scene {result.scene}: {result.master} master, {result.algorithm}, H = {result.step_size:g} s, "
          f"{s['steps']} macro steps, {s['wall_time']:.3g} s wall, {s['wall_time_per_step_us']:.0f} us per step")
    if "peak_traction_coefficient" in s:
        print(f"peak adhesion T/N = {s['peak_traction_coefficient']:.4f} at creep {s['creep_at_peak']:.4g} "
              f"(t = {s['time_at_peak']:.4g} s)")
    if not result.success:
        print(f"stopped early: {result.message}", file=sys.stderr)
    path = plot(result, args.plot or f"cosim_{result.scene}.png")
    print(f"plot: {path}")
    return 0 if result.success else 1


if __name__ == "__main__":
    sys.exit(main())
