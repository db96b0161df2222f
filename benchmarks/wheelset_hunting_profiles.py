"""The nonlinear hunting study of the S1002/UIC60 wheelset: the scene ``wheelset_hunting_profiles`` (the Wheelset host
on profiles and the WheelsetContact FMU) at 20 speeds from 0.5 mm and from 8 mm, 10 s each, one dask task per run on
a local cluster of two workers, through fmpy or libcosim (``rollcontact_cosim.wheelset.profiles``).

Writes the bifurcation diagram beside the equivalent conicity (``results/wheelset_hunting_profiles_<master>.png``),
the reference results (``models/cosim/wheelset_hunting_profiles_<master>.md``: a function of the parameters only) and
this study's results with its wall time and the machine (``results/wheelset_hunting_profiles_<master>.md``).
``--quick``: four speeds, 3 s each, into a temporary folder, nothing written.

Usage: ``python benchmarks/wheelset_hunting_profiles.py [--master fmpy|libcosim] [--workers 2] [--quick]``.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

import common  # before numpy: limits BLAS to one thread; puts the checkout on sys.path

from rollcontact_cosim.wheelset.profiles import (
    SPEEDS,
    Linearisation,
    hunting_diagram,
    klingel_check,
    plot_profiles,
    report,
    scene_models,
    write_reference,
)

FILES = {"fmpy": (common.RESULTS / "wheelset_hunting_profiles_fmpy.md",
                  common.RESULTS / "wheelset_hunting_profiles_fmpy.png"),
         "libcosim": (common.RESULTS / "wheelset_hunting_profiles_libcosim.md",
                      common.RESULTS / "wheelset_hunting_profiles_libcosim.png")}
"""The results file and the figure of each master."""


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--master", default="fmpy", choices=("fmpy", "libcosim"))
    parser.add_argument("--workers", type=int, default=2, help="dask workers (default 2)")
    parser.add_argument("--quick", action="store_true", help="4 speeds, 3 s each, nothing written")
    args = parser.parse_args()
    load = os.getloadavg()[0]
    clock = time.perf_counter()
    speeds = SPEEDS[::6] if args.quick else SPEEDS
    with tempfile.TemporaryDirectory(prefix="wheelset_hunting_profiles_") as tmp:
        study = hunting_diagram(speeds, fmu_dir=tmp if args.quick else None, master=args.master,
                                stop_time=3.0 if args.quick else 10.0, n_workers=args.workers)
    linear = Linearisation(*scene_models())
    klingel = klingel_check()
    total = time.perf_counter() - clock
    text = report(study, linear, klingel)
    runs = sorted(study.runs, key=lambda r: -r.wall_time)
    cpu = sum(r.cpu_time for r in study.runs)
    timing = [f"{len(study.runs)} runs through {study.master} on {args.workers} dask workers: the sweep "
              f"{study.wall_time:.0f} s of wall time (FMUs built when stale, cluster started, every run), the whole "
              f"study {total:.0f} s; the runs' step loops {sum(r.wall_time for r in study.runs):.0f} s in all (the "
              f"longest {runs[0].wall_time:.1f} s, {runs[0].speed:g} m/s from {1e3 * runs[0].start:g} mm); the runs "
              f"took {cpu:.0f} processor seconds in their workers (geometry tables and FMU instantiations included), "
              f"{cpu / args.workers:.0f} s on {args.workers} cores of their own"]
    print(text + "\n\n" + timing[0])
    if args.quick:
        return
    results, figure = FILES[study.master]
    plot_profiles(study, linear, figure)
    reference = write_reference(study, linear, klingel)
    command = f"python benchmarks/wheelset_hunting_profiles.py --master {study.master} --workers {args.workers}"
    results.write_text(
        f"# {results.stem}\n\n{text}\n\n{timing[0]}\n\nFigure: [{figure.name}]({figure.name}); reference results: "
        f"models/cosim/{reference.name}.\n\nRun by `{command}` on:\n\n" + "\n".join(common.machine(load)) + "\n")
    print(f"wrote {figure}, {reference}, {results}")


if __name__ == "__main__":
    main()
