"""What the elliptic methods share: the scene's creepage coefficients, the applicability of the table's range of
a/b, the no-load answer, and the normalised creepage and Poisson's ratio that the accuracy models use."""

from __future__ import annotations

import math

from rollcontact.elliptic.creep_coefficients import CreepageCoefficients, aspect_ratio_range, creepage_coefficients
from rollcontact.elliptic.result import EllipticResult
from rollcontact.elliptic.scene import EllipticScene


def coefficients(scene: EllipticScene) -> CreepageCoefficients:
    """Kalker's C11, C22, C23, C33 at the scene's a/b and nu (a ValueError outside the table's a/b)."""
    return creepage_coefficients(scene.hertz.aspect_ratio, scene.material.poisson_ratio)


def outside_table(scene: EllipticScene) -> str | None:
    """Why the scene's a/b is outside the creepage-coefficient table's range, or None."""
    low, high = aspect_ratio_range()
    g = scene.hertz.aspect_ratio
    if not low <= g <= high:
        return f"a/b = {g:.4g} is outside the creepage-coefficient table's range [{low:g}, {high:g}]"
    return None


def no_load(scene: EllipticScene, method: str) -> EllipticResult:
    """The answer at Fn = 0: no contact, no forces."""
    return EllipticResult.from_scene(scene, method, True, "no load: no contact", (0.0, 0.0, 0.0))


def linear_forces(scene: EllipticScene, c: CreepageCoefficients) -> tuple[float, float, float]:
    """Kalker's linear theory, forces on the rail: ``Fx = G c^2 C11 xi``, ``Fy = G c^2 (C22 eta + c C23 phi)``,
    ``Mz = G c^3 (-C23 eta + c C33 phi)`` [N, N, N m] (Kalker 1967; 1990, section 2.3; docs/physics.md).  The spin
    term of Mz is omitted (0) at phi = 0 so that a table without C33 serves every case without spin."""
    xi, eta, phi = scene.creepages
    g = scene.shear_modulus
    length = scene.hertz.c
    area = length * length
    fx = g * area * c.c11 * xi
    fy = g * area * (c.c22 * eta + length * c.c23 * phi)
    mz = g * area * length * (-c.c23 * eta + (length * c.c33 * phi if phi != 0.0 else 0.0))
    return fx, fy, mz


def linear_ratio(scene: EllipticScene, c: CreepageCoefficients) -> float:
    """``tau = (|(Fx, Fy)| + G c^3 C23 |phi|) / (mu Fn)`` [1] of the linear theory: the creepages in units of
    saturation, what the accuracy models scale with (the spin counted by its lateral force even where it cancels
    that of eta, since it also drives the moment)."""
    fx, fy, _ = linear_forces(scene, c._replace(c33=0.0))
    scale = scene.friction_coefficient * scene.normal_load
    spin = scene.shear_modulus * scene.hertz.c**3 * c.c23 * abs(scene.spin_creepage)
    return (math.hypot(fx, fy) + spin) / scale if scale > 0.0 else 0.0


MEASURED_POISSON_RATIO = 0.28
"""Poisson's ratio [1] of steel, at which the accuracy models' main constants are measured; their errors grow with
nu above it (``benchmarks/calibrate_elliptic_levels.py``, table B3)."""


def poisson_excess(scene: EllipticScene) -> float:
    """``max(0, nu - MEASURED_POISSON_RATIO)`` [1]: how far the scene's Poisson's ratio lies above steel's."""
    return max(0.0, scene.material.poisson_ratio - MEASURED_POISSON_RATIO)
