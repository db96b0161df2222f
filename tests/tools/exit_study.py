"""Exit codes of Python host processes that drive the FMUs and exit normally (docs/fmu.md, "Exit").

Usage::

    python tests/tools/exit_study.py [--processes 200] [--unfixed 40] [--workers 2] [--seed 1]
    python tests/tools/exit_study.py --quick        # 8 processes

``benchmarks/bench_exit.py`` runs the study with the same options and writes ``benchmarks/results/exit.md``.

Every process is a fresh Python (``subprocess``) running one workload of this file (``--host``) on FMUs built by
``build_fmu.py --fmi 2,3 --all``, then exiting through ``sys.exit(0)`` like any script: interpreter finalisation,
``exit()``'s handlers and the libraries' destructors all run.  Workloads (parameters drawn from
``numpy.random.default_rng([seed, process])``):

* ``simulate2`` / ``simulate3``: ``fmpy.simulate_fmu`` of RollingContact2D (FMI 2.0 / 3.0) over an input table,
  Coulomb or falling friction (``friction_law = 1``, ``table`` auto, off or on);
* ``slave2`` / ``slave3``: 1-3 instances (``FMU2Slave`` / ``FMU3Slave``) stepped alternately, with get/set and
  serialise/deserialise state round trips;
* ``wheelrig``: the WheelRig FMU (FMI 2.0) stepped beside a RollingContact2D instance.

A process counts as clean when it exits with 0 and printed its results line.  ``--unfixed N`` runs N more processes
(the same workloads in turn, spread evenly among the others) on copies of the FMUs whose Linux binaries are
replaced by the installed pythonfmu libraries, without the exit fix, for comparison.

``--c-host N`` (needs gcc and a shared libpython) runs the C host of ``tests/fmu_host.py``, which returns from
``main`` (``exit()``, static destructors, ``Py_Finalize`` of the interpreter pythonfmu started), N times per
variant: fixed and unfixed (both FMUs hold scipy's ``_uarray`` exception type, docs/fmu.md "Exit").  A
``sitecustomize`` on ``PYTHONPATH`` registers a Python ``atexit`` handler that writes a marker file: clean means exit
code 0, one output line per step and the marker written (the embedded interpreter was finalised).
``--valgrind N`` (needs valgrind) runs N more processes per variant (workloads ``slave2`` and ``slave3`` in turn)
under memcheck with ``PYTHONMALLOC=malloc`` and counts their invalid accesses: those in
``finalizePythonInterpreter`` (the double release) and any others, leaving out the dynamic loader's word-wise
``strncmp`` reads in ``dl-load.c`` (reads within the words of valid strings, reported by memcheck whatever the
FMU).  Whether the double release aborts a process depends on the heap layout; memcheck sees it in every process.
With ``--c-host``, it also runs the fixed C host N times under memcheck.  The exit status is 1 when a process on the
fixed FMUs does not exit cleanly.
"""

from __future__ import annotations

import argparse
import collections
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import zipfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # one BLAS thread in every host process, as the tests
os.environ.setdefault("OMP_NUM_THREADS", "1")

ROOT = Path(__file__).resolve().parents[2]
WORKLOADS = ("simulate2", "simulate3", "slave2", "slave3", "wheelrig")
TIMEOUT = 300.0
"""Longest a host process may run [s] before it counts as hung."""
INPUTS = ("normal_load", "creep", "velocity")


# ------------------------------------------------------------------------------------------------ host processes
def draw_parameters(rng) -> dict:
    """RollingContact2D parameters of one instance: Coulomb or falling friction, table auto, off or on."""
    p: dict = {"table": int(rng.integers(0, 3))}
    if rng.random() < 0.6:
        p.update(
            friction_law=1,
            friction_kinetic_ratio=float(rng.uniform(0.3, 0.9)),
            friction_decay=float(rng.uniform(0.5, 5.0)),
        )
    if rng.random() < 0.3:
        p.update(corrugation_amplitude=float(rng.uniform(1e-6, 2e-5)), corrugation_wavelength=0.04)
    return p


def signal(rng, steps: int):
    """Inputs per step: normal load [N], creep [1], velocity [m/s]."""
    load = rng.uniform(5e4, 1.5e5) * (1.0 + 0.2 * rng.standard_normal(steps)).clip(0.2, 2.0)
    creep = rng.uniform(-3e-3, 3e-3, steps)
    return [(float(n), float(c), 20.0) for n, c in zip(load, creep, strict=True)]


def host_simulate(folder: Path, rng) -> str:
    """``fmpy.simulate_fmu`` of RollingContact2D over an input table; the last tangential force."""
    import numpy as np
    from fmpy import simulate_fmu

    steps, h = int(rng.integers(5, 20)), 1e-3
    rows = [(k * h, *u) for k, u in enumerate(signal(rng, steps))]
    table = np.array(rows, dtype=[("time", np.float64), *((name, np.float64) for name in INPUTS)])
    result = simulate_fmu(
        str(folder / "RollingContact2D.fmu"),
        start_values=draw_parameters(rng),
        input=table,
        stop_time=(steps - 1) * h,
        output_interval=h,
        output=["tangential_force"],
    )
    return f"{result['tangential_force'][-1]:.6g}"


def host_slaves(folder: Path, rng) -> str:
    """1-3 RollingContact2D instances stepped alternately, with state round trips; the forces of the last step."""
    from rollcontact_cosim.master import Slave

    slaves = [Slave(folder / "RollingContact2D.fmu", f"contact_{i}") for i in range(int(rng.integers(1, 4)))]
    for slave in slaves:
        slave.set_start_values(draw_parameters(rng))
        slave.fmu.setupExperiment(startTime=0.0)
        slave.fmu.enterInitializationMode()
        slave.fmu.exitInitializationMode()
    h, forces = 1e-3, []
    for k, u in enumerate(signal(rng, int(rng.integers(5, 15)))):
        for slave in slaves:
            slave.fmu.setReal([slave.reference(name, "input") for name in INPUTS], list(u))
            slave.fmu.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
            if rng.random() < 0.3:
                state = slave.fmu.getFMUstate()
                data = slave.fmu.serializeFMUstate(state)
                slave.fmu.freeFMUstate(state)
                restored = slave.fmu.deSerializeFMUstate(data)
                slave.fmu.setFMUstate(restored)
                slave.fmu.freeFMUstate(restored)
    for slave in slaves:
        forces.append(slave.fmu.getReal([slave.reference("tangential_force")])[0])
        slave.free()
    return " ".join(f"{f:.6g}" for f in forces)


def host_wheelrig(folder: Path, rng) -> str:
    """The WheelRig FMU stepped beside a RollingContact2D instance (two binaries, one interpreter)."""
    from rollcontact_cosim.master import Slave

    rig, contact = Slave(folder / "WheelRig.fmu", "rig"), Slave(folder / "RollingContact2D.fmu", "contact")
    contact.set_start_values(draw_parameters(rng))
    for slave in (rig, contact):
        slave.fmu.setupExperiment(startTime=0.0)
        slave.fmu.enterInitializationMode()
        slave.fmu.exitInitializationMode()
    h = 1e-3
    for k, u in enumerate(signal(rng, int(rng.integers(5, 15)))):
        contact.fmu.setReal([contact.reference(name, "input") for name in INPUTS], list(u))
        for slave in (rig, contact):
            slave.fmu.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
    force = contact.fmu.getReal([contact.reference("tangential_force")])[0]
    rig.free()
    contact.free()
    return f"{force:.6g}"


def host(workload: str, folders: dict[int, Path], seed: int, process: int) -> None:
    """Run one workload in this process and print its results line (then the caller exits normally)."""
    import numpy as np
    from fmpy.fmi1 import FMICallException

    rng = np.random.default_rng([seed, process])
    try:
        if workload.startswith("simulate"):
            out = host_simulate(folders[int(workload[-1])], rng)
        elif workload.startswith("slave"):
            out = host_slaves(folders[int(workload[-1])], rng)
        else:
            out = host_wheelrig(folders[2], rng)
    except FMICallException as exc:  # a discarded step ends the workload; the process still exits normally
        out = f"stopped: {exc}"
    print(f"results {workload} {out}", flush=True)


# ------------------------------------------------------------------------------------------------------- the study
def build(dest: Path) -> dict[str, dict[int, Path]]:
    """Fixed FMUs (``build_fmu.py --fmi 2,3 --all``) and unfixed copies: variant -> FMI version -> folder."""
    done = subprocess.run(
        [sys.executable, str(ROOT / "build_fmu.py"), "--fmi", "2,3", "--all", "--dest", str(dest / "fixed")],
        capture_output=True,
        text=True,
        timeout=600,
    )
    if done.returncode != 0:
        raise RuntimeError(f"build_fmu.py failed:\n{done.stdout}\n{done.stderr}")
    import importlib.metadata

    def installed(package: str, folder: str) -> Path:  # the installed distribution's file
        return Path(
            importlib.metadata.distribution(package).locate_file(Path(package, "resources", "binaries", folder))
        )

    originals = {
        "binaries/linux64/": installed("pythonfmu", "linux64"),
        "binaries/x86_64-linux/": installed("pythonfmu3", "x86_64-linux"),
    }
    for fmu in (dest / "fixed").rglob("*.fmu"):
        copy = dest / "unfixed" / fmu.relative_to(dest / "fixed")
        copy.parent.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(fmu) as source, zipfile.ZipFile(copy, "w") as target:
            for info in source.infolist():
                folder = next((f for f in originals if info.filename.startswith(f)), None)
                data = source.read(info)
                if folder and info.filename.endswith(".so"):
                    data = (originals[folder] / "libpythonfmu-export.so").read_bytes()
                target.writestr(info, data)
    return {variant: {2: dest / variant, 3: dest / variant / "fmi3"} for variant in ("fixed", "unfixed")}


def run_one(
    variant: str, folders: dict[int, Path], workload: str, seed: int, process: int, valgrind: bool = False
) -> dict:
    command = [
        sys.executable,
        str(Path(__file__).resolve()),
        "--host",
        workload,
        "--fmi2",
        str(folders[2]),
        "--fmi3",
        str(folders[3]),
        "--seed",
        str(seed),
        "--process",
        str(process),
    ]
    env = dict(os.environ)
    if valgrind:
        command = ["valgrind", "--num-callers=12", *command]
        env["PYTHONMALLOC"] = "malloc"  # every Python object a malloc block memcheck watches
    t0 = time.perf_counter()
    try:
        done = subprocess.run(
            command, capture_output=True, text=True, timeout=TIMEOUT * (10 if valgrind else 1), env=env
        )
        code, out, err = done.returncode, done.stdout, done.stderr
    except subprocess.TimeoutExpired:
        code, out, err = "hung", "", ""
    seconds = time.perf_counter() - t0
    printed = f"results {workload}" in out
    tail = err.strip().splitlines()[-1][:160] if err.strip() else ""
    run = {
        "variant": f"{variant} (memcheck)" if valgrind else variant,
        "workload": workload,
        "process": process,
        "code": code,
        "printed": printed,
        "seconds": seconds,
        "tail": tail,
    }
    if valgrind:
        run["invalid"] = invalid_accesses(err)
    return run


def invalid_accesses(log: str) -> collections.Counter:
    """memcheck's invalid accesses in ``log`` by kind: ``finalizer`` (in ``finalizePythonInterpreter``),
    ``uarray`` (of a block scipy's ``_uarray`` freed, ``globals_free``) or ``other``; the dynamic loader's
    ``strncmp`` word reads (``dl-load.c``) are left out (module docstring)."""
    kinds: collections.Counter = collections.Counter()
    blocks = log.split("== \n")
    for block in blocks:
        if "== Invalid " not in block:
            continue
        head = block[block.index("== Invalid ") :]
        if "finalizePythonInterpreter" in head:
            kinds["finalizer"] += 1
        elif "globals_free" in head and "_uarray" in head:
            kinds["uarray"] += 1
        elif not ("strncmp" in head and "dl-load.c" in head):
            kinds["other"] += 1
    return kinds


def study(args) -> list[dict]:
    with tempfile.TemporaryDirectory(prefix="rollcontact_exit_") as tmp:
        variants = build(Path(tmp))
        # the unfixed processes spread evenly among the fixed ones, so that both see the same machine load
        jobs = sorted(
            [("fixed", p, p / args.processes) for p in range(args.processes)]
            + [("unfixed", p, (p + 0.5) / args.unfixed) for p in range(args.unfixed)],
            key=lambda j: j[2],
        )
        with ThreadPoolExecutor(args.workers) as pool:
            runs = list(
                pool.map(
                    lambda job: run_one(
                        job[0], variants[job[0]], WORKLOADS[job[1] % len(WORKLOADS)], args.seed, job[1]
                    ),
                    jobs,
                )
            )
            if args.valgrind > 0 and shutil.which("valgrind"):
                memcheck = [(variant, p) for p in range(args.valgrind) for variant in ("fixed", "unfixed")]
                runs += list(
                    pool.map(
                        lambda job: run_one(
                            job[0], variants[job[0]], ("slave2", "slave3")[job[1] % 2], args.seed, job[1], valgrind=True
                        ),
                        memcheck,
                    )
                )
        return runs + c_host_runs(args, Path(tmp), variants)


SITECUSTOMIZE = """import atexit, os
if os.environ.get("EXIT_MARKER"):
    atexit.register(lambda: open(os.environ["EXIT_MARKER"], "w").write("finalised"))
"""
C_ROWS = ((1e5, 1e-3, 20.0), (2e5, -1e-3, 20.0), (1.5e5, 3e-3, 25.0))


def c_host_runs(args, tmp: Path, variants: dict[str, dict[int, Path]]) -> list[dict]:
    """``args.c_host`` runs of the C host per variant (module docstring); [] without gcc or a shared libpython."""
    import sysconfig

    from fmpy import extract, read_model_description

    libpython = Path(sysconfig.get_config_var("LIBDIR") or "", sysconfig.get_config_var("LDLIBRARY") or "")
    if args.c_host <= 0 or shutil.which("gcc") is None or not libpython.is_file():
        return []
    sys.path.insert(0, str(ROOT / "tests"))
    from fmu_host import C_HOST  # one C host for the test and this study

    (tmp / "host.c").write_text(C_HOST)
    subprocess.run(["gcc", "-std=c99", "-o", str(tmp / "host"), str(tmp / "host.c"), "-ldl"], check=True)
    cases = {}
    for name in ("fixed", "unfixed"):
        variant = folder = name  # no space or comma in the extraction path (docs/fmu.md)
        unzipped = Path(extract(str(variants[variant][2] / "RollingContact2D.fmu"), unzipdir=tmp / f"u_{folder}"))
        site = tmp / f"site_{folder}"
        site.mkdir()
        (site / "sitecustomize.py").write_text(SITECUSTOMIZE)
        md = read_model_description(str(unzipped))
        refs = {v.name: v.valueReference for v in md.modelVariables}
        cases[name] = (
            [
                str(tmp / "host"),
                str(next((unzipped / "binaries" / "linux64").glob("*.so"))),
                md.guid,
                (unzipped / "resources").as_uri(),
                "0.001",
                *(str(refs[n]) for n in INPUTS),
                str(refs["method_used"]),
                str(refs["tangential_force"]),
            ],
            site,
        )
    env = {
        "PATH": "/usr/bin:/bin",
        "LD_PRELOAD": str(libpython),
        "PYTHONHOME": sys.base_prefix,
        "OPENBLAS_NUM_THREADS": "1",
    }

    def one(job):
        name, i, valgrind = job
        command, site = cases[name]
        marker = tmp / f"marker_{site.name}_{i}_{valgrind}"
        extra = {"PYTHONMALLOC": "malloc"} if valgrind else {}
        t0 = time.perf_counter()
        done = subprocess.run(
            ["valgrind", "--num-callers=12", *command] if valgrind else command,
            input="".join(f"{n!r} {c!r} {v!r}\n" for n, c, v in C_ROWS),
            capture_output=True,
            text=True,
            timeout=TIMEOUT * (10 if valgrind else 1),
            env={
                **env,
                **extra,
                "EXIT_MARKER": str(marker),
                "PYTHONPATH": f"{site}:{sysconfig.get_paths()['purelib']}",
            },
        )
        printed = (
            len([line for line in done.stdout.splitlines() if line[:1].isdigit()]) == len(C_ROWS) and marker.is_file()
        )
        tail = done.stderr.strip().splitlines()[-1][:160] if done.stderr.strip() else ""
        run = {
            "variant": f"C host, {name}" + (" (memcheck)" if valgrind else ""),
            "workload": "c_host",
            "process": i,
            "code": done.returncode,
            "printed": printed,
            "seconds": time.perf_counter() - t0,
            "tail": tail,
        }
        if valgrind:
            run["invalid"] = invalid_accesses(done.stderr)
        return run

    jobs = [(name, i, False) for i in range(args.c_host) for name in cases]
    if args.valgrind > 0 and shutil.which("valgrind"):
        jobs += [(name, i, True) for i in range(args.valgrind) for name in ("fixed",)]
    with ThreadPoolExecutor(args.workers) as pool:
        return list(pool.map(one, jobs))


def report(runs: list[dict], args, seconds: float, machine: list[str] = ()) -> list[str]:
    """The markdown report of the ``runs``; ``machine``: the lines describing the machine (none: left out)."""
    lines = [
        "# Exit codes of host processes",
        "",
        "`python benchmarks/bench_exit.py"
        + (" --quick" if args.quick else f" --processes {args.processes} --unfixed {args.unfixed}")
        + "`: "
        "each row counts fresh Python processes that ran one workload on the FMUs and exited normally "
        '(docs/fmu.md, "Exit"); *fixed*: the FMUs as `build_fmu.py` builds them, *unfixed*: the same FMUs '
        "with the installed pythonfmu libraries as their Linux binaries.  Clean: exit code 0 and the results "
        "line printed.",
        "",
        *machine,
        f"- {len(runs)} processes, {args.workers} at a time, seed {args.seed}, {seconds:.0f} s in all",
        "",
        "| FMUs | workload | processes | clean | exit codes | median process time |",
        "|---|---|---:|---:|---|---:|",
    ]
    groups = collections.defaultdict(list)
    for run in runs:
        groups[(run["variant"], run["workload"])].append(run)
    for variant in dict.fromkeys(r["variant"] for r in runs):
        rows = [r for r in runs if r["variant"] == variant]
        for workload in (*WORKLOADS, "c_host", "all"):
            if workload == "all" and rows[0]["workload"] == "c_host":
                continue
            group = rows if workload == "all" else groups[(variant, workload)]
            if not group:
                continue
            codes = collections.Counter(str(r["code"]) for r in group)
            clean = sum(r["code"] == 0 and r["printed"] for r in group)
            text = ", ".join(f"{code}: {n}" for code, n in sorted(codes.items()))
            name = f"**{workload}**" if workload == "all" else workload
            lines.append(
                f"| {variant} | {name} | {len(group)} | {clean} | {text} | "
                f"{statistics.median(r['seconds'] for r in group):.1f} s |"
            )
    checked = [r for r in runs if "invalid" in r]
    if checked:
        lines += [
            "",
            "Under memcheck (`PYTHONMALLOC=malloc`): invalid accesses per process, in "
            "`finalizePythonInterpreter`, of a block scipy's `_uarray` freed (`globals_free`), and elsewhere "
            "(the dynamic loader's `strncmp` word reads left out).",
            "",
            "| FMUs | workload | process | exit code | in finalizePythonInterpreter | freed by _uarray | elsewhere |",
            "|---|---|---:|---:|---:|---:|---:|",
        ]
        lines += [
            f"| {r['variant']} | {r['workload']} | {r['process']} | {r['code']} | {r['invalid']['finalizer']} | "
            f"{r['invalid']['uarray']} | {r['invalid']['other']} |"
            for r in checked
        ]
    failed = [r for r in runs if not (r["code"] == 0 and r["printed"])]
    if failed:
        lines += ["", "Processes that did not exit cleanly (last line of stderr):", ""]
        lines += [
            f"- {r['variant']} {r['workload']} process {r['process']}: exit {r['code']}, `{r['tail'] or '(no stderr)'}`"
            for r in failed[:40]
        ]
    return lines


def parser() -> argparse.ArgumentParser:
    """The study's options (also ``benchmarks/bench_exit.py``'s)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], add_help=False)
    parser.add_argument("--processes", type=int, default=200, help="host processes on the fixed FMUs")
    parser.add_argument("--unfixed", type=int, default=40, help="host processes on the unfixed FMUs")
    parser.add_argument("--c-host", type=int, default=40, help="C host processes per variant (0: none)")
    parser.add_argument("--valgrind", type=int, default=2, help="processes per variant under memcheck (0: none)")
    parser.add_argument("--workers", type=int, default=2, help="processes run at a time")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--quick", action="store_true", help="8 processes, 4 unfixed, 2 C hosts, no memcheck")
    return parser


def run(args, machine: list[str] = ()) -> tuple[list[str], int]:
    """The study of ``args``: the report's lines and the exit status (1: a process on the fixed FMUs did not exit
    cleanly)."""
    if args.quick:
        args.processes, args.unfixed, args.c_host, args.valgrind = 8, 4, 2, 0
    t0 = time.perf_counter()
    runs = study(args)
    status = int(any(r["variant"] == "fixed" and not (r["code"] == 0 and r["printed"]) for r in runs))
    return report(runs, args, time.perf_counter() - t0, machine), status


def main(argv: list[str] | None = None) -> int:
    full = argparse.ArgumentParser(description=__doc__.splitlines()[0], parents=[parser()])
    full.add_argument("--host", choices=WORKLOADS, help=argparse.SUPPRESS)  # run one workload in this process
    full.add_argument("--fmi2", type=Path, help=argparse.SUPPRESS)
    full.add_argument("--fmi3", type=Path, help=argparse.SUPPRESS)
    full.add_argument("--process", type=int, default=0, help=argparse.SUPPRESS)
    args = full.parse_args(argv)
    if args.host:
        host(args.host, {2: args.fmi2, 3: args.fmi3}, args.seed, args.process)
        return 0
    lines, status = run(args)
    print("\n".join(lines))
    return status


if __name__ == "__main__":
    sys.exit(main())
