"""The builds of the FMU tests and the validation every built FMU passes: ``build_fmu.py`` in a fresh process
(:func:`run_build`), fmpy's ``validate_fmu`` and fmu_manipulation_toolbox's ``fmutool -check`` against the FMU's FMI
version (shared by the FMI 2.0, FMI 3.0 and several-contact tests)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from fmpy.validation import validate_fmu

ROOT = Path(__file__).resolve().parents[1]


def run_build(*args: str, dest: Path, timeout: float = 600) -> str:
    """``python build_fmu.py ARGS --dest DEST`` in a fresh process, as the docs give it; its standard output."""
    done = subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), *args, "--dest", str(dest)], capture_output=True,
                          text=True, timeout=timeout)
    assert done.returncode == 0, f"build_fmu.py {' '.join(args)} failed:\n{done.stdout}\n{done.stderr}"
    return done.stdout


def assert_fmu_is_valid(path: Path, fmi: int) -> None:
    """fmpy validate finds no problem in the FMU at ``path`` and ``fmutool -check`` finds it compliant with FMI
    ``fmi``.0 and without semantic error."""
    problems = validate_fmu(str(path))
    assert problems == [], f"fmpy validate {path.name}: {problems}"
    fmutool = shutil.which("fmutool", path=str(Path(sys.executable).parent)) or shutil.which("fmutool")
    assert fmutool, "fmutool (fmu_manipulation_toolbox) is not installed: pip install -e '.[test]'"
    done = subprocess.run([fmutool, "-input", str(path), "-check"], capture_output=True, text=True, timeout=120)
    log = done.stdout + done.stderr
    assert done.returncode == 0, f"fmutool -check {path.name} failed ({done.returncode}):\n{log}"
    assert f"compliant with FMI-{fmi}.0" in log and f"No semantic error against the FMI-{fmi} standard" in log, log
