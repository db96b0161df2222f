"""The two FMUs a co-simulation needs, built when missing or stale, and what a co-simulation returns.

Shared by the masters (:mod:`rollcontact_cosim.master` on fmpy, :mod:`rollcontact_cosim.osp` on libcosim).
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rollcontact_cosim.scenes import CONTACT, HOST

ROOT = Path(__file__).resolve().parents[2]
FMU_DIR = ROOT / "models"
"""Default folder of ``RollingContact2D.fmu`` and ``WheelRig.fmu``."""


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


FMI_VERSIONS = (2, 3)
"""FMI versions of the FMUs: 2 (FMI 2.0, pythonfmu; the default) or 3 (FMI 3.0, pythonfmu3)."""


def check_fmi_version(fmi_version) -> int:
    """``fmi_version`` if it is 2 or 3, else ValueError."""
    if isinstance(fmi_version, bool) or fmi_version not in FMI_VERSIONS:
        raise ValueError(f"fmi_version = {fmi_version!r} is unknown: use 2 (FMI 2.0) or 3 (FMI 3.0)")
    return int(fmi_version)


def ensure_fmus(fmu_dir: Path | str = FMU_DIR, integer_codes: bool = False, fmi_version: int = 2) -> dict[str, Path]:
    """Paths of both FMUs in ``fmu_dir``, built by ``build_fmu.py --all --if-stale`` when missing or stale; with
    ``integer_codes`` the build for hosts without FMI enumerations (``build_fmu.py --integer-codes``), in the
    folder ``integer_codes/`` below ``fmu_dir``; with ``fmi_version`` 3 the FMI 3.0 FMUs (``build_fmu.py --fmi
    3``), in the folder ``fmi3/`` below ``fmu_dir``."""
    fmi_version = check_fmi_version(fmi_version)
    if integer_codes and fmi_version == 3:
        raise ValueError("the integer-codes build (for libcosim) is an FMI 2.0 build: use fmi_version = 2")
    fmu_dir = Path(fmu_dir) / "integer_codes" if integer_codes else Path(fmu_dir)
    spec = importlib.util.spec_from_file_location("rollcontact_build_fmu", ROOT / "build_fmu.py")
    builder = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(builder)  # only for is_stale: the build itself runs in a subprocess
    folder = builder.fmi_dest(fmu_dir, fmi_version)
    if any(builder.is_stale(name, folder, fmi_version) for name in builder.FMUS):
        done = subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), "--all", "--if-stale", "--dest",
                               str(fmu_dir), "--fmi", str(fmi_version),
                               *(["--integer-codes"] if integer_codes else [])],
                              capture_output=True, text=True, timeout=600)
        if done.returncode != 0:
            raise RuntimeError(f"build_fmu.py --all failed:\n{done.stdout}\n{done.stderr}")
    return {name: folder / f"{name}.fmu" for name in (HOST, CONTACT)}




