"""The fixture of the RollingContact2D FMU's tests: initialised instances of the test run's build (``fmu_path``,
``tests/conftest.py``) through :class:`fmu_host.Instance`."""

from __future__ import annotations

import pytest
from fmu_host import Instance


@pytest.fixture
def instance(unzipped, description):
    """A factory of initialised instances, freed after the test."""
    made = []

    def make(**kwargs) -> Instance:
        made.append(Instance(unzipped, description, name=f"rc{len(made)}", **kwargs))
        return made[-1]

    yield make
    for inst in made:
        inst.free()
