"""Parameter sweeps and regression suites of co-simulations on dask.distributed (a local cluster by default).

One co-simulation is one task: a :class:`Case` (scene plus overrides) goes to a worker process, which runs
:func:`rollcontact_cosim.master.run_cosimulation` and sends back a small :class:`CaseResult` (the run's summary,
success and message, and the time histories only when asked for).  Cases are independent, so the sweep scales
with the workers; a pythonfmu FMU runs Python inside the worker, hence one thread per worker process.

* ``run_sweep(cases)`` starts a ``LocalCluster`` (``n_workers`` processes, one thread each) and closes it after;
  ``run_sweep(cases, scheduler="tcp://host:8786")`` uses an existing cluster, ``client=`` an existing Client.
  Workers elsewhere need the same installation (``pip install -e .`` of this repository, so that ``models/``
  and ``build_fmu.py`` are where :mod:`rollcontact_cosim.master` looks); the FMUs are built once in the calling
  process before any task starts, so that workers never build concurrently.
* ``run_regression()`` checks every scene with every master against its reference (``models/cosim/*_ref.csv``)
  as one task each.

Command line::

    python -m rollcontact_cosim.sweep --regression [--scheduler tcp://host:8786]
    python -m rollcontact_cosim.sweep traction_ramp --contact friction_coefficient=0.25,0.3,0.35
"""

from __future__ import annotations

import argparse
import itertools
import sys
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rollcontact_cosim.cli import Progress, run
from rollcontact_cosim.master import MASTERS, ensure_scene_fmus, run_cosimulation, summarise
from rollcontact_cosim.scenes import SCENE_NAMES

__all__ = ["Case", "CaseResult", "run_case", "run_regression", "run_sweep"]


@dataclass(frozen=True)
class Case:
    """One co-simulation of a sweep: :func:`~rollcontact_cosim.master.run_cosimulation`'s arguments.

    Attributes
    ----------
    scene : str
        Scene name or TOML path.
    master : str
        ``"fmpy"`` or ``"libcosim"``.
    algorithm : str or None
        ``"gauss-seidel"`` or ``"jacobi"``; the scene's when None.
    step_size, stop_time : float or None
        Macro step [s] and end time [s] replacing the scene's.
    host, contact : Mapping
        Parameter overrides of the WheelRig and RollingContact2D FMUs.
    keep_values : bool
        Send the time histories back (they can be large); otherwise only the summary.
    """

    scene: str
    master: str = "fmpy"
    algorithm: str | None = None
    step_size: float | None = None
    stop_time: float | None = None
    host: Mapping = field(default_factory=dict)
    contact: Mapping = field(default_factory=dict)
    keep_values: bool = False


@dataclass(frozen=True)
class CaseResult:
    """What a worker sends back for a :class:`Case`.

    Attributes
    ----------
    case : Case
    success : bool
        False when an FMU refused a step or the run raised (``message`` says why); a failed case does not stop
        the sweep.
    message : str
    summary : dict
        :func:`rollcontact_cosim.master.summarise` of the run (empty when it raised).
    values : numpy.ndarray or None
        Time histories when ``case.keep_values``.
    """

    case: Case
    success: bool
    message: str
    summary: dict
    values: np.ndarray | None = None


def run_case(case: Case) -> CaseResult:
    """Run one case (in a worker, its FMUs built already); exceptions become an unsuccessful :class:`CaseResult`
    naming them."""
    try:
        result = run_cosimulation(case.scene, master=case.master, algorithm=case.algorithm,
                                  step_size=case.step_size, stop_time=case.stop_time, host=dict(case.host),
                                  contact=dict(case.contact), build=False)
    except Exception as exc:  # noqa: BLE001 - one bad case must not lose the sweep's other results
        return CaseResult(case, False, f"{type(exc).__name__}: {exc}", {})
    return CaseResult(case, result.success, result.message, summarise(result),
                      result.values if case.keep_values else None)


def check_case(scene: str, master: str) -> tuple[str, str, list[str]]:
    """``(scene, master, problems)`` of one scene's run against its reference (in a worker, its FMUs built
    already)."""
    from rollcontact_cosim.reference import check

    try:
        return scene, master, check(scene, master=master, build=False)
    except Exception as exc:  # noqa: BLE001 - reported as the case's problem
        return scene, master, [f"{type(exc).__name__}: {exc}"]


def run_sweep(cases: Iterable[Case], *, client=None, scheduler: str | None = None,
              n_workers: int = 2) -> list[CaseResult]:
    """Run the cases on dask.distributed; results in the order of ``cases``.

    Parameters
    ----------
    cases : iterable of Case
    client : dask.distributed.Client, optional
        An existing client (left open).
    scheduler : str, optional
        Address of an existing scheduler (``"tcp://host:8786"``) when no client is given.
    n_workers : int
        Worker processes of the local cluster started when neither is given (one thread each).
    """
    cases = list(cases)
    for scene, master in dict.fromkeys((case.scene, case.master) for case in cases):
        ensure_scene_fmus(scene, master)
    return submit(run_case, [(case,) for case in cases], client, scheduler, n_workers)


def run_regression(scenes: Iterable[str] = SCENE_NAMES, masters: Iterable[str] = MASTERS, *, client=None,
                   scheduler: str | None = None, n_workers: int = 2) -> list[tuple[str, str, list[str]]]:
    """Every scene with every master against its reference result: ``(scene, master, problems)`` per pair."""
    pairs = list(itertools.product(scenes, masters))
    for scene, master in pairs:
        ensure_scene_fmus(scene, master)  # a misspelt scene fails here, not in a worker
    return submit(check_case, pairs, client, scheduler, n_workers)


def submit(function, arguments: list[tuple], client, scheduler: str | None, n_workers: int) -> list:
    """``function(*args)`` for each tuple of ``arguments`` on the given, addressed or a new local cluster (the
    callers build the FMUs the tasks need before: workers never build)."""
    from dask.distributed import Client

    if client is not None:
        return gather(client, function, arguments)
    if scheduler is not None:
        with Client(scheduler) as own:
            return gather(own, function, arguments)
    with local_cluster(n_workers) as cluster, Client(cluster) as own:
        return gather(own, function, arguments)


def local_cluster(n_workers: int):
    """A LocalCluster of ``n_workers`` processes with one thread each, whose workers import this repository's code.

    Worker processes are spawned with the parent's ``sys.path``; a pythonfmu FMU loaded in the parent has put its
    ``resources`` folder there, whose bundled copy of ``rollcontact_cosim`` does not know where ``models/`` is.  The
    workers start without those folders.
    """
    from dask.distributed import LocalCluster

    saved = sys.path[:]
    sys.path[:] = [p for p in saved if not is_fmu_resources(p)]
    try:
        return LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True, dashboard_address=None)
    finally:
        sys.path[:] = saved


def is_fmu_resources(path: str) -> bool:
    """Whether ``path`` is the ``resources`` folder of an unpacked FMU."""
    folder = Path(path)
    return folder.name == "resources" and (folder.parent / "modelDescription.xml").is_file()


def gather(client, function, arguments: list[tuple]) -> list:
    """The results of ``function(*args)`` on the cluster, in the order of ``arguments``, with a progress bar on a
    terminal."""
    from dask.distributed import as_completed

    # pure=False: equal arguments are still separate runs (wall times are part of the result)
    futures = [client.submit(function, *args, pure=False) for args in arguments]
    with Progress(len(futures), f"{function.__name__} runs") as progress:
        for _ in as_completed(futures):
            progress.advance()
    return client.gather(futures)


def parse_overrides(items: list[str], what: str) -> dict[str, list]:
    """``["name=v1,v2", ...]`` -> ``{name: [v1, v2]}`` with ints and floats parsed."""
    values = {}
    for item in items:
        name, sep, text = item.partition("=")
        if not sep or not text:
            raise ValueError(f"--{what} {item!r}: expected name=value[,value...]")
        values[name] = [int(v) if v.lstrip("+-").isdigit() else float(v) for v in text.split(",")]
    return values


def main(argv: list[str] | None = None) -> int:
    """The sweep or regression command (module docstring); a bad scene or value, or dask missing, is one line and
    exit code 2."""
    return run("python -m rollcontact_cosim.sweep", lambda: command(argv))


def command(argv: list[str] | None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rollcontact_cosim.sweep", description=__doc__.splitlines()[0])
    parser.add_argument("scene", nargs="?", default="traction_ramp", help="scene of the sweep (default traction_ramp)")
    parser.add_argument("--regression", action="store_true", help="check every scene and master against its reference")
    parser.add_argument("--host", action="append", default=[], help="host parameter values: name=v1,v2,...")
    parser.add_argument("--contact", action="append", default=[], help="contact parameter values: name=v1,v2,...")
    parser.add_argument("--master", default="fmpy", choices=MASTERS)
    parser.add_argument("--scheduler", help="address of an existing dask scheduler (default: a local cluster)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes of the local cluster")
    args = parser.parse_args(argv)
    if args.regression:
        failed = 0
        for scene, master, problems in run_regression(scheduler=args.scheduler, n_workers=args.workers):
            failed += bool(problems)
            print(f"{scene:20s} {master:9s} " + ("ok" if not problems else "FAILED: " + "; ".join(problems)))
        return 1 if failed else 0
    grids = [("host", k, v) for k, v in parse_overrides(args.host, "host").items()] + \
            [("contact", k, v) for k, v in parse_overrides(args.contact, "contact").items()]
    cases = []
    for combination in itertools.product(*(values for _, _, values in grids)):
        overrides = {"host": {}, "contact": {}}
        for (where, name, _), value in zip(grids, combination, strict=True):
            overrides[where][name] = value
        cases.append(Case(args.scene, master=args.master, **overrides))
    print(f"{'case':50s} {'peak T/N':>9s} {'creep at peak':>14s} {'us/step':>8s}  status")
    for res in run_sweep(cases, scheduler=args.scheduler, n_workers=args.workers):
        label = ", ".join(f"{k}={v}" for k, v in {**res.case.host, **res.case.contact}.items()) or res.case.scene
        s = res.summary
        print(f"{label:50s} {s.get('peak_traction_coefficient', float('nan')):9.4f} "
              f"{s.get('creep_at_peak', float('nan')):14.4g} {s.get('wall_time_per_step_us', float('nan')):8.1f}  "
              + ("ok" if res.success else res.message))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
