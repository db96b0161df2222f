"""Profiles and positions the wheel/rail tests share: the Manchester case's positions (``models/wheelrail``), a cone
and a circular rail head made in the test."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from rollcontact.wheelrail.geometry import Pose
from rollcontact.wheelrail.profiles import Profile

ROOT = Path(__file__).resolve().parents[1]
PROFILES = ROOT / "models" / "wheelrail" / "profiles"
CASES = ROOT / "models" / "wheelrail" / "manchester_a22.csv"



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
