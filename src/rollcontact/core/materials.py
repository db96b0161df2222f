"""The elastic constants of a pair of quasi-identical bodies: :class:`Material`, shared by every geometry."""

from __future__ import annotations

from dataclasses import dataclass

from rollcontact.core.checks import SceneError, check_real


@dataclass(frozen=True)
class Material:
    """Elastic constants of two quasi-identical bodies.

    Parameters
    ----------
    youngs_modulus : float
        Young's modulus E [Pa] of both bodies.
    poisson_ratio : float
        Poisson's ratio nu [1] of both bodies, 0 <= nu < 0.5.

    Notes
    -----
    The plane-strain contact modulus of two identical bodies is ``E* = E / (2 (1 - nu^2))``
    (``1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2``), so the paper's prefactor ``4 (1-nu^2)/(pi E) = 2/(pi E*)``.
    """

    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.28

    def __post_init__(self):
        object.__setattr__(self, "youngs_modulus",
                           check_real("youngs_modulus", self.youngs_modulus, lower=0.0, lower_open=True))
        object.__setattr__(self, "poisson_ratio",
                           check_real("poisson_ratio", self.poisson_ratio, lower=0.0, upper=0.5,
                                      upper_open=True))

    @property
    def contact_modulus(self) -> float:
        """Plane-strain contact modulus E* = E / (2 (1 - nu^2)) [Pa] of the pair."""
        return self.youngs_modulus / (2.0 * (1.0 - self.poisson_ratio**2))

    @property
    def shear_modulus(self) -> float:
        """Shear modulus G = E / (2 (1 + nu)) [Pa]."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))


def check_material(value) -> Material:
    """``value`` if it is a :class:`Material`, else :class:`~rollcontact.core.checks.SceneError` naming its type."""
    if not isinstance(value, Material):
        raise SceneError(f"material must be a Material, got {type(value).__name__}")
    return value
