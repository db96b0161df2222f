"""The FMI 2.0 and FMI 3.0 FMUs built once per test run, and initialised instances of either version.

``build_fmu.py --fmi 2,3 --all`` writes both pairs into one temporary folder (FMI 3.0 below ``fmi3/``).  Instances
are :class:`rollcontact_cosim.master.Slave` objects: ``slave.fmu`` answers the same (FMI 2.0-named) calls in both
versions, so a test written once runs against both (the ``fmi`` fixture).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
VERSIONS = {2: "FMI 2.0", 3: "FMI 3.0"}


@pytest.fixture(scope="session")
def fmu_folders(tmp_path_factory) -> dict[int, Path]:
    """``python build_fmu.py --fmi 2,3 --all --dest <tmp>`` once per test run: version -> folder of both FMUs."""
    dest = tmp_path_factory.mktemp("fmi2_and_fmi3")
    done = subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), "--fmi", "2,3", "--all", "--dest", str(dest)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, f"build_fmu.py --fmi 2,3 --all failed:\n{done.stdout}\n{done.stderr}"
    folders = {2: dest, 3: dest / "fmi3"}
    for folder in folders.values():
        assert {p.name for p in folder.glob("*.fmu")} == {"RollingContact2D.fmu", "WheelRig.fmu", "Wheelset.fmu",
                                                        "RollingContact3D.fmu"}, \
            done.stdout
    return folders


@pytest.fixture(params=list(VERSIONS), ids=list(VERSIONS.values()))
def fmi(request) -> int:
    """The FMI version of the test's FMUs: 2, then 3."""
    return request.param


@pytest.fixture
def make(fmu_folders):
    """``make(version, model="RollingContact2D", start_time=0.0, initialise=True, **parameters)``: an instance
    (``rollcontact_cosim.master.Slave``) with the parameters set and initialised, freed after the test."""
    from rollcontact_cosim.master import Slave

    made = []

    def instance(version: int, model: str = "RollingContact2D", start_time: float = 0.0, initialise: bool = True,
                 **parameters):
        slave = Slave(fmu_folders[version] / f"{model}.fmu", f"{model}_{len(made)}")
        made.append(slave)
        slave.set_start_values(parameters)
        if initialise:
            slave.initialise(start_time)
        return slave

    yield instance
    for slave in made:
        slave.free()
