"""Shared fixtures of the wheel/rail tests: the Manchester benchmark's profiles, track and wheelset (the copies in
models/wheelrail/); the positions of its case A-2.2 and the analytic profiles are in ``tests/wheelrail_cases.py``."""

from __future__ import annotations

import pytest
from wheelrail_cases import PROFILES

from rollcontact.wheelrail.geometry import Track, Wheelset
from rollcontact.wheelrail.profiles import read_simpack


@pytest.fixture(scope="session")
def s1002():
    return read_simpack(PROFILES / "MBench_S1002_v3.prw")


@pytest.fixture(scope="session")
def uic60():
    return read_simpack(PROFILES / "MBench_UIC60_v3.prr")


@pytest.fixture(scope="session")
def track(uic60):
    return Track(uic60, gauge=1.435, gauge_height=0.014, inclination=0.0)


@pytest.fixture(scope="session")
def wheelset(s1002):
    return Wheelset(s1002, nominal_radius=0.46, flange_back_spacing=1.360, flange_back_distance=0.070)


@pytest.fixture(scope="session")
def contact_table(track, wheelset):
    """The Manchester pair's contact table over +-8 mm (one yaw node), as the wheelset contact's stepping model builds
    it (its TABLE_STEP)."""
    from rollcontact.stepping.wheelrail.parameters import TABLE_STEP
    from rollcontact.wheelrail.conicity import ContactTable

    return ContactTable.build(track, wheelset, (-0.008, 0.008), TABLE_STEP, yaws=(0.0,))
