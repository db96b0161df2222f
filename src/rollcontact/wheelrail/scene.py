"""One patch's rolling-contact case: its gap, its normal load or approach, the creepages at its rigid contact point,
the friction law, the rolling speed and the material (:class:`PatchScene`).

Creepages (docs/physics.md, Elliptic contact): the rigid slip of the wheel relative to the rail over V in the
patch's contact plane is ``w_x = xi - phi s``, ``w_y = eta + phi x``, x along the track (the wheel rolls towards +x)
and s across the patch from its rigid contact point.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from rollcontact.core.checks import SceneError, check_real
from rollcontact.core.friction import Coulomb, FrictionLaw
from rollcontact.core.materials import Material
from rollcontact.wheelrail.patch import PatchGap

__all__ = ["PatchScene"]


@dataclass(frozen=True)
class PatchScene:
    """One patch's case (SI units).

    Parameters
    ----------
    gap : PatchGap
        The undeformed gap ``h(s) + A(s) x^2`` in the patch's tangent plane.
    normal_load : float, optional
        Fn [N] >= 0.
    approach : float, optional
        delta [m] >= 0, the rigid interpenetration at the rigid contact point; exactly one of ``normal_load`` and
        ``approach``.
    longitudinal_creepage, lateral_creepage : float
        xi, eta [1] at the rigid contact point.
    spin_creepage : float
        phi [1/m].
    material : Material
        Elastic constants of the quasi-identical bodies.
    friction : FrictionLaw
        A number is a Coulomb coefficient; velocity-dependent laws take the slip velocity ``V |s|`` [m/s].
    rolling_speed : float
        V [m/s] >= 0.
    name : str
        Free text.
    """

    gap: PatchGap
    normal_load: float | None = None
    approach: float | None = None
    longitudinal_creepage: float = 0.0
    lateral_creepage: float = 0.0
    spin_creepage: float = 0.0
    material: Material = field(default_factory=Material)
    friction: FrictionLaw = field(default_factory=lambda: Coulomb(0.3))
    rolling_speed: float = 1.0
    name: str = ""

    def __post_init__(self):
        set_ = object.__setattr__
        if not isinstance(self.gap, PatchGap):
            raise SceneError(f"gap must be a PatchGap, got {type(self.gap).__name__}")
        if (self.normal_load is None) == (self.approach is None):
            raise SceneError("give exactly one of normal_load and approach")
        if self.normal_load is not None:
            set_(self, "normal_load", check_real("normal_load", self.normal_load, lower=0.0, unit="N"))
        else:
            set_(self, "approach", check_real("approach", self.approach, lower=0.0, unit="m"))
        for name in ("longitudinal_creepage", "lateral_creepage"):
            set_(self, name, check_real(name, getattr(self, name)))
        set_(self, "spin_creepage", check_real("spin_creepage", self.spin_creepage, unit="1/m"))
        set_(self, "rolling_speed", check_real("rolling_speed", self.rolling_speed, lower=0.0, unit="m/s"))
        if not isinstance(self.material, Material):
            raise SceneError(f"material must be a Material, got {type(self.material).__name__}")
        if isinstance(self.friction, (int, float)) and not isinstance(self.friction, bool):
            set_(self, "friction", Coulomb(self.friction))
        if not isinstance(self.friction, FrictionLaw):
            raise SceneError(f"friction must be a FrictionLaw or a number, got {self.friction!r}")

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) [Pa]."""
        return self.material.youngs_modulus / (2.0 * (1.0 + self.material.poisson_ratio))

    @property
    def friction_coefficient(self) -> float:
        """mu at zero slip velocity [1]."""
        return self.friction.static_coefficient

    @property
    def creepages(self) -> tuple[float, float, float]:
        """(xi [1], eta [1], phi [1/m])."""
        return self.longitudinal_creepage, self.lateral_creepage, self.spin_creepage

    @property
    def mirrored(self) -> PatchScene:
        """The scene mirrored across the rolling direction (``s -> -s``): ``h(-s)``, ``A(-s)``, eta and phi
        reversed; its Fy and Mz are the negatives of this scene's and its Fx the same."""
        import numpy as np

        gap = PatchGap(-np.asarray(self.gap.lateral)[::-1], np.asarray(self.gap.lateral_gap)[::-1],
                       np.asarray(self.gap.longitudinal_curvature)[::-1])
        return replace(self, gap=gap, lateral_creepage=-self.lateral_creepage, spin_creepage=-self.spin_creepage)

    def replace(self, **changes) -> PatchScene:
        """A copy with some fields changed (validated again); giving ``normal_load`` drops the approach and the
        other way round."""
        if "normal_load" in changes and "approach" not in changes:
            changes["approach"] = None
        if "approach" in changes and "normal_load" not in changes:
            changes["normal_load"] = None
        return replace(self, **changes)

