"""Shared fixtures of the wheel/rail tests: the Manchester benchmark's profiles, track and wheelset (the copies in
models/wheelrail/), the positions of its case A-2.2, and analytic profiles (a cone, a cylinder, a circular rail
head) written as points."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from rollcontact.wheelrail.geometry import Pose, Track, Wheelset
from rollcontact.wheelrail.profiles import Profile, read_simpack

ROOT = Path(__file__).resolve().parents[2]
PROFILES = ROOT / "models" / "wheelrail" / "profiles"
CASES = ROOT / "models" / "wheelrail" / "manchester_a22.csv"


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


def manchester_rows() -> list[dict]:
    with open(CASES) as fh:
        return list(csv.DictReader(fh))


def manchester_pose(row: dict) -> Pose:
    return Pose(float(row["lateral_shift_mm"]) * 1e-3, float(row["yaw_rad"]), float(row["roll_rad"]))


def cone(conicity: float, half_width: float = 0.07, step: float = 2e-4) -> Profile:
    """A conical wheel: z = -lambda y (the radius grows towards the flange side, negative y), no smoothing."""
    y = np.arange(-half_width, half_width + step / 2, step)
    return Profile(y, -conicity * y, smoothing=0.0, kind="wheel", source="cone")


def circular_head(radius: float, half_angle: float = 1.2, points: int = 401, sample_step: float = 1e-4) -> Profile:
    """A rail head of one circle of ``radius`` [m] (top at the origin, z downward) over +-half_angle [rad]."""
    t = np.linspace(-half_angle, half_angle, points)
    return Profile(radius * np.sin(t), radius * (1.0 - np.cos(t)), smoothing=0.0, kind="rail", source="circle",
                   sample_step=sample_step)
