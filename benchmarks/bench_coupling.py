"""Largest stable macro step per co-simulation scene: explicit vs linearly implicit WheelRig coupling.

For every scene and master algorithm: a fine-step reference run (the scene's step / ``--refine``, linearly
implicit, Gauss-Seidel), then :func:`rollcontact_cosim.stable_step.largest_stable_step` for ``coupling`` = 0
(explicit: the contact force held over the macro step) and 1 (linearly implicit with ``creep_stiffness``).
"Stable" = the run completes and T/N stays within 5 % of max |T/N| of the fine run at every communication point
but the first two (definition in :mod:`rollcontact_cosim.stable_step`).  Prints a markdown table and the deviation
of every tried step.

``--oscillation H`` measures instead what one macro step H (e.g. 1e-3 s) does to the contact force of every scene,
algorithm and coupling: the swing of T over the second half of the run, half the largest change of T from one
communication point to the next (an explicit loop beyond its limit alternates between the saturations, so this is
the amplitude of its limit cycle; a stable run changes T only as its excitation does), and the spread of T over
that half.  It writes ``benchmarks/results/coupling_oscillation.md`` (``--quick``: print only).
Usage: ``python benchmarks/bench_coupling.py [--scenes ...] [--algorithms ...] [--refine 10]
[--oscillation H [--quick]]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile

import common  # (before numpy: limits BLAS to one thread; puts the checkout's src/ on sys.path)
import numpy as np

from rollcontact_cosim.master import ensure_fmus, run_cosimulation
from rollcontact_cosim.scenes import ALGORITHMS, CONTACT, SCENE_NAMES, load_cosim_scene
from rollcontact_cosim.stable_step import largest_stable_step

FORCE = f"{CONTACT}.tangential_force"


def milliseconds(step: float | None) -> str:
    return "none" if step is None else f"{step * 1e3:g}"


def oscillation(scenes: list[str], algorithms: list[str], step: float, quick: bool) -> None:
    """The table of ``--oscillation`` (module docstring) at macro step ``step`` [s]."""
    lines = [f"# Contact force at a macro step of {step * 1e3:g} ms: explicit and linearly implicit coupling", "",
             f"`python benchmarks/bench_coupling.py --oscillation {step:g}`; fmpy master, every scene run over "
             "its own duration at this step. Over the second half of each run: the swing, half the largest change of "
             "the tangential force T between consecutive communication points (the amplitude of an explicit loop's "
             "limit cycle between the saturations), and the range of T.", "",
             "| scene | algorithm | coupling | completed | swing [kN] | T min [kN] | T max [kN] |",
             "|---|---|---|---|---:|---:|---:|"]
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="bench_coupling_") as tmp:
        ensure_fmus(tmp)
        for name in scenes:
            scene = load_cosim_scene(name)
            for algorithm in algorithms:
                for coupling, label in ((0, "explicit"), (1, "linearly implicit")):
                    result = run_cosimulation(scene, algorithm=algorithm, step_size=step, host={"coupling": coupling},
                                              fmu_dir=tmp)
                    force = result.values[FORCE][len(result.values) // 2:] / 1e3
                    swing = float(np.max(np.abs(np.diff(force)))) / 2 if force.size > 1 else float("nan")
                    lines.append(f"| {name} | {algorithm} | {label} | "
                                 f"{'yes' if result.success else 'no: ' + result.message[:60]} | {swing:.3g} | "
                                 f"{force.min():.3g} | {force.max():.3g} |")
                    print(lines[-1], flush=True)
    lines += ["", *common.machine(load)]
    common.publish(lines, "coupling_oscillation.md", quick)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="*", default=list(SCENE_NAMES), help="scenes (default: all)")
    parser.add_argument("--algorithms", nargs="*", default=list(ALGORITHMS), choices=ALGORITHMS)
    parser.add_argument("--refine", type=int, default=10, help="fine step = scene step / refine (default 10)")
    parser.add_argument("--tolerance", type=float, default=0.05, help="band [1 of max |T/N|] (default 0.05)")
    parser.add_argument("--oscillation", type=float, metavar="H",
                        help="only the contact force's swing at macro step H [s] per scene, algorithm and coupling")
    parser.add_argument("--quick", action="store_true", help="with --oscillation: print, do not write the results")
    args = parser.parse_args(argv)
    if args.oscillation is not None:
        oscillation(args.scenes, args.algorithms, args.oscillation, args.quick)
        return
    with tempfile.TemporaryDirectory(prefix="bench_coupling_") as tmp:
        ensure_fmus(tmp)
        rows, details = [], []
        for name in args.scenes:
            scene = load_cosim_scene(name)
            fine = run_cosimulation(scene, algorithm="gauss-seidel", step_size=scene.step_size / args.refine,
                                    host={"coupling": 1}, fmu_dir=tmp)
            if not fine.success:
                print(f"{name}: the fine reference run failed: {fine.message}", file=sys.stderr)
                continue
            at_scene_step = run_cosimulation(scene, fmu_dir=tmp)
            for algorithm in args.algorithms:
                scans = {coupling: largest_stable_step(scene, coupling, fine, algorithm=algorithm,
                                                       tolerance=args.tolerance, fmu_dir=tmp)
                         for coupling in (0, 1)}
                rows.append(f"| {name} | {algorithm} | {milliseconds(fine.step_size)} | "
                            f"{milliseconds(scans[0].largest_stable)} | {milliseconds(scans[1].largest_stable)} | "
                            f"{milliseconds(scene.step_size)} | {at_scene_step.wall_time_per_step * 1e6:.0f} |")
                for coupling, scan in scans.items():
                    tried = ", ".join(f"{h * 1e3:g} ms: {e:.3g}" for h, e in scan.tried)
                    details.append(f"{name} {algorithm} coupling {coupling}: {tried}")
                print(rows[-1], flush=True)
    print(f"\nstable: T/N within {args.tolerance:g} of max |T/N| of the fine run (Gauss-Seidel, linearly implicit, "
          f"scene step / {args.refine}) at every communication point from the third on\n")
    print("| scene | algorithm | fine H [ms] | explicit: largest stable H [ms] | linearly implicit: largest stable "
          "H [ms] | scene H [ms] | us per macro step at the scene H |")
    print("|---|---|---:|---:|---:|---:|---:|")
    print("\n".join(rows))
    print("\ndeviation from the fine run per tried step:")
    print("\n".join(details))


if __name__ == "__main__":
    main()
