"""Largest stable macro step per co-simulation scene: explicit vs linearly implicit WheelRig coupling.

For every scene and master algorithm: a fine-step reference run (the scene's step / ``--refine``, linearly
implicit, Gauss-Seidel), then :func:`rollcontact_cosim.stability.largest_stable_step` for ``coupling`` = 0
(explicit: the contact force held over the macro step) and 1 (linearly implicit with ``creep_stiffness``).
"Stable" = the run completes and T/N stays within 5 % of max |T/N| of the fine run at every communication point
but the first two (definition in :mod:`rollcontact_cosim.stability`).  Prints a markdown table and the deviation
of every tried step.
Usage: ``python benchmarks/bench_coupling.py [--scenes ...] [--algorithms ...] [--refine 10]``.
"""

from __future__ import annotations

import argparse
import sys
import tempfile

import common  # noqa: F401  (before numpy: limits BLAS to one thread; puts the checkout's src/ on sys.path)

from rollcontact_cosim.master import ensure_fmus, run_cosimulation
from rollcontact_cosim.scenes import ALGORITHMS, SCENE_NAMES, load_cosim_scene
from rollcontact_cosim.stability import largest_stable_step


def milliseconds(step: float | None) -> str:
    return "none" if step is None else f"{step * 1e3:g}"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="*", default=list(SCENE_NAMES), help="scenes (default: all)")
    parser.add_argument("--algorithms", nargs="*", default=list(ALGORITHMS), choices=ALGORITHMS)
    parser.add_argument("--refine", type=int, default=10, help="fine step = scene step / refine (default 10)")
    parser.add_argument("--tolerance", type=float, default=0.05, help="band [1 of max |T/N|] (default 0.05)")
    args = parser.parse_args(argv)
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
