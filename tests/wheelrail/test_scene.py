"""The patch scene's checks and its mirror image; the patch result's normalised forces."""

from __future__ import annotations

import math

import numpy as np
import pytest
from wheelrail_gaps import two_wells

from rollcontact import Coulomb
from rollcontact.core.checks import SceneError
from rollcontact.wheelrail.result import PatchResult
from rollcontact.wheelrail.scene import PatchScene


def test_exactly_one_of_load_and_approach():
    with pytest.raises(SceneError, match="exactly one"):
        PatchScene(two_wells())
    with pytest.raises(SceneError, match="exactly one"):
        PatchScene(two_wells(), normal_load=1e4, approach=1e-5)
    with pytest.raises(SceneError, match="normal_load"):
        PatchScene(two_wells(), normal_load=-1.0)
    scene = PatchScene(two_wells(), normal_load=1e4, friction=0.25)
    assert scene.friction == Coulomb(0.25)
    moved = scene.replace(approach=2e-5)
    assert moved.normal_load is None and moved.approach == 2e-5, "replace swaps the load for the approach"


def test_mirrored_scene_reverses_the_lateral_direction():
    scene = PatchScene(two_wells(), normal_load=1e4, longitudinal_creepage=1e-3, lateral_creepage=2e-3,
                       spin_creepage=0.5)
    mirror = scene.mirrored
    assert (mirror.longitudinal_creepage, mirror.lateral_creepage, mirror.spin_creepage) == (1e-3, -2e-3, -0.5)
    s = np.asarray(scene.gap.lateral)
    assert np.array_equal(np.asarray(mirror.gap.lateral), -s[::-1]), "s -> -s"
    assert np.array_equal(np.asarray(mirror.gap.lateral_gap), np.asarray(scene.gap.lateral_gap)[::-1]), "h(-s)"


def test_force_coefficients():
    result = PatchResult("strips", True, "", 1e4, 1e-5, 1e9, 8e-3, 6e-3, 600.0, -300.0, 2.0, 0.0, 0.0, 0.0, 0.3,
                         math.pi * 4e-3 * 3e-3)
    fx, fy, mz = result.force_coefficients
    assert (fx, fy) == (0.2, -0.1)
    assert math.isclose(mz, 2.0 / (3e3 * math.sqrt(12e-6))), "Mz over mu Fn sqrt(area / pi)"
