"""What the line contact's accuracy models share: the Hertz half-width of a scene and the sharpness of its friction
law over the slip velocities of the patch."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from rollcontact.line.hertz import hertz
from rollcontact.line.scene import Scene


def hertz_half_width(scene) -> float:
    """Hertz half-width a [m] of the scene's load and radius."""
    return hertz(scene.normal_load_per_length, scene.radius, scene.material.contact_modulus)[0]


def friction_sharpness(scene: Scene) -> float:
    """``beta = max|dmu/dv| v_max / mu_s`` [1] over slip velocities ``0..v_max``, ``v_max = V max(|xi|, mu a/R)``.

    How much mu changes across the slip velocities of the patch: it sets the error of the slip iteration.
    """
    mu = scene.friction_coefficient
    return sharpness(scene.friction, scene.rolling_speed * max(abs(scene.creep), mu * hertz_half_width(scene)
                                                               / scene.radius))


SHARPNESS_SAMPLES = np.linspace(0.0, 1.0, 9)
"""Where :func:`sharpness` samples dmu/dv, in units of v_max."""


@lru_cache(maxsize=64)
def sharpness(friction, v_max: float) -> float:
    # cached: every setting of a ladder asks for the same scene's value
    slopes = np.abs(friction.derivative(v_max * SHARPNESS_SAMPLES))
    return float(np.max(slopes)) * v_max / friction.static_coefficient
