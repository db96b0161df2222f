"""The FMUs a co-simulation needs, built when missing or stale, and what a co-simulation returns.

Shared by the masters (:mod:`rollcontact_cosim.master` on fmpy, :mod:`rollcontact_cosim.osp` on libcosim).
:func:`ensure_fmus` asks ``build_fmu.py`` (in a subprocess: the builder imports the slaves) for each FMU of a
scene's system with ``--if-stale``, which builds only what is missing or older than its sources: ``--only MODEL``
or ``--contacts N``, ``--fmi 2|3``, ``--integer-codes`` as the system's variant says, into ``--dest``.
"""

from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rollcontact_cosim.scenes import CONTACT, HOST, WHEEL_RIG, Instance, System

ROOT = Path(__file__).resolve().parents[2]
FMU_DIR = ROOT / "models"
"""Default folder of the FMUs (``build_fmu.py``'s default ``--dest``)."""
BUILD_FMU = ROOT / "build_fmu.py"


@dataclass
class CosimResult:
    """Time histories and bookkeeping of one co-simulation run.

    Attributes
    ----------
    scene : str
        Scene name.
    master : str
        ``"fmpy"`` or ``"libcosim"``.
    algorithm : str
        ``"gauss-seidel"`` or ``"jacobi"``.
    step_size : float
        Macro step H [s].
    values : numpy.ndarray
        Structured array: ``time`` [s] and the recorded variables (``"Instance.output"``, SI units), one row per
        communication point reached (module docstring).
    steps : int
        Macro steps completed.
    wall_time : float
        Wall-clock time [s] of the stepping loop (without loading and initialising the FMUs).
    success : bool
        False when an FMU refused a step; ``values`` then ends at the last complete row.
    message : str
        Why the run stopped early (with the FMU's log message), or ``"completed"``.
    """

    scene: str
    master: str
    algorithm: str
    step_size: float
    values: np.ndarray
    steps: int
    wall_time: float
    success: bool
    message: str

    def __getitem__(self, name: str) -> np.ndarray:
        return self.values[name]

    @property
    def wall_time_per_step(self) -> float:
        """Wall-clock time per macro step [s]."""
        return self.wall_time / max(self.steps, 1)


def summarise(result: CosimResult) -> dict[str, float]:
    """Peak adhesion and cost of a run.

    Returns
    -------
    dict
        ``peak_traction_coefficient`` (largest |T/N|, with its sign), ``creep_at_peak`` and ``time_at_peak``
        (the host's creep at that row) when ``RollingContact2D.traction_coefficient`` and ``WheelRig.creep`` are
        recorded; ``steps``, ``wall_time`` [s] and ``wall_time_per_step_us`` [us] always.
    """
    out: dict[str, float] = {}
    names = result.values.dtype.names
    traction, creep = f"{CONTACT}.traction_coefficient", f"{HOST}.creep"
    if traction in names and creep in names and result.values.size:
        k = int(np.argmax(np.abs(result.values[traction])))
        out.update(peak_traction_coefficient=float(result.values[traction][k]),
                   creep_at_peak=float(result.values[creep][k]), time_at_peak=float(result.values["time"][k]))
    out.update(steps=result.steps, wall_time=result.wall_time, wall_time_per_step_us=1e6 * result.wall_time_per_step)
    return out


_checked: set[tuple[str, ...]] = set()
"""The build commands this process has run (the staleness check runs once per process, folder and FMU)."""


def ensure_fmus(fmu_dir: Path | str = FMU_DIR, integer_codes: bool | None = None, fmi_version: int | None = None,
                system: System | None = None) -> dict[str, Path]:
    """The system's FMUs in ``fmu_dir`` (instance name -> path), each built first when missing or stale.

    Parameters
    ----------
    fmu_dir : Path
        The folder ``build_fmu.py --dest`` builds into; the FMI 3.0 FMUs are in its ``fmi3/`` folder, the
        integer-codes build (for hosts without FMI enumerations: libcosim) in its ``integer_codes/`` folder.
    integer_codes : bool, optional
        The integer-codes build (``build_fmu.py --integer-codes``, FMI 2.0 only); the system's when None.
    fmi_version : int, optional
        2 (FMI 2.0) or 3 (FMI 3.0); the system's when None.
    system : System, optional
        The scene's system (:attr:`rollcontact_cosim.scenes.CosimScene.system`); the wheel rig's when None.

    Raises
    ------
    ValueError
        A variant that does not exist (FMI 3.0 with integer codes, an unknown FMI version).
    RuntimeError
        ``build_fmu.py`` failed (its output in the message).
    """
    system = (WHEEL_RIG if system is None else system).variant(fmi_version, integer_codes)
    paths = system.fmus(fmu_dir)
    for instance in system.instances:
        build(instance, system, fmu_dir, paths[instance.name])
    return paths


def build(instance: Instance, system: System, fmu_dir: Path | str, path: Path) -> None:
    """``build_fmu.py --only MODEL|--contacts N --if-stale --fmi V [--integer-codes] --dest DIR`` for the instance
    in the system's variant, unless this process ran that command already and ``path`` is there."""
    dest = Path(fmu_dir).resolve() / "integer_codes" if system.integer_codes else Path(fmu_dir).resolve()
    command = (sys.executable, str(BUILD_FMU), *instance.build_selection, "--if-stale", "--fmi",
               str(system.fmi_version), *(("--integer-codes",) if system.integer_codes else ()), "--dest", str(dest))
    if command in _checked and path.is_file():
        return
    done = subprocess.run(command, capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        raise RuntimeError(f"build_fmu.py {' '.join(command[2:])} failed:\n{done.stdout}\n{done.stderr}")
    _checked.add(command)
