"""Initialised instances of the FMI 2.0 and FMI 3.0 FMUs built once per test run.

``build_fmu.py --fmi 2,3 --all`` writes both sets into one temporary folder (FMI 3.0 below ``fmi3/``; the
``fmu_folders`` fixture of ``tests/conftest.py``, which the model-description snapshot shares).  Instances
are :class:`rollcontact_cosim.master.Slave` objects: ``slave.fmu`` answers the same (FMI 2.0-named) calls in both
versions, so a test written once runs against both (the ``fmi`` fixture).
"""

from __future__ import annotations

import pytest

VERSIONS = {2: "FMI 2.0", 3: "FMI 3.0"}


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
