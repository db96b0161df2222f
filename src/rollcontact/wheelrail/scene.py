"""The wheel/rail contact's cases: a wheelset on its track (:class:`WheelRailScene`, what the wheel/rail levels
solve) and one patch's rolling-contact case (:class:`PatchScene`: its gap, its normal load or approach, the creepages
at its rigid contact point, the friction law, the rolling speed and the material, what a patch level solves).

Creepages (docs/physics.md, Elliptic contact): the rigid slip of the wheel relative to the rail over V in the
patch's contact plane is ``w_x = xi - phi s``, ``w_y = eta + phi x``, x along the track (the wheel rolls towards +x)
and s across the patch from its rigid contact point.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property

from rollcontact.core.checks import SceneError, check_real
from rollcontact.core.friction import Coulomb, FrictionLaw
from rollcontact.core.materials import Material
from rollcontact.wheelrail.geometry import Pose, Track, Velocities, Wheelset
from rollcontact.wheelrail.normal import WheelLoad, loaded_position, solve_normal
from rollcontact.wheelrail.patch import PatchGap
from rollcontact.wheelrail.search import WheelContact, search_wheel

__all__ = ["SIDES", "PatchScene", "WheelRailScene"]


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



@dataclass(frozen=True)
class WheelRailScene:
    """One wheelset on its track: the contact of both wheels on their rails (SI units; track axes of docs/physics.md,
    Wheel/rail geometry: x along the track, y to the right, z downward).

    Parameters
    ----------
    track : Track
        Rail profile, gauge, inclination.
    wheelset : Wheelset
        Wheel profile, nominal rolling radius, flange-back spacing.
    lateral_shift : float
        y [m] of the wheelset, towards the right rail positive.
    yaw : float
        psi [rad], the front turned to the right positive.
    roll : float or None
        phi [rad] (positive lowers the right wheel); None: the roll at which the rigid wheelset carries both loads
        with Hertz's normal contact (:func:`~rollcontact.wheelrail.normal.loaded_position`).
    vertical_load_left, vertical_load_right : float
        Q [N] >= 0: the vertical force each wheel exerts on its rail (the z component of its contact forces, the
        tangential forces' included); each wheel is pressed down from the pose until it carries its load.
        0: the wheel carries nothing (no contact, zero forces).
    forward_speed : float
        V [m/s] > 0.
    lateral_velocity : float
        dy/dt [m/s].
    yaw_rate : float
        dpsi/dt [rad/s].
    pitch_rate : float or None
        The wheelset's angular velocity about its axle [rad/s], negative for forward rolling; None: ``-V / r0``.
    material : Material
        Elastic constants of wheel and rail (quasi-identical bodies).
    friction : FrictionLaw
        A number is a Coulomb coefficient; velocity-dependent laws take the slip velocity ``V |s|``.
    name : str
        Free text.
    """

    track: Track
    wheelset: Wheelset
    lateral_shift: float = 0.0
    yaw: float = 0.0
    roll: float | None = None
    vertical_load_left: float = 1e5
    vertical_load_right: float = 1e5
    forward_speed: float = 1.0
    lateral_velocity: float = 0.0
    yaw_rate: float = 0.0
    pitch_rate: float | None = None
    material: Material = field(default_factory=Material)
    friction: FrictionLaw = field(default_factory=lambda: Coulomb(0.3))
    name: str = ""

    def __post_init__(self):
        set_ = object.__setattr__
        if not isinstance(self.track, Track):
            raise SceneError(f"track must be a Track, got {type(self.track).__name__}")
        if not isinstance(self.wheelset, Wheelset):
            raise SceneError(f"wheelset must be a Wheelset, got {type(self.wheelset).__name__}")
        for name in ("vertical_load_left", "vertical_load_right"):
            set_(self, name, check_real(name, getattr(self, name), lower=0.0, unit="N"))
        set_(self, "forward_speed", check_real("forward_speed", self.forward_speed, lower=0.0, lower_open=True,
                                                unit="m/s"))
        for name, unit in (("lateral_velocity", "m/s"), ("yaw_rate", "rad/s")):
            set_(self, name, check_real(name, getattr(self, name), unit=unit))
        if not isinstance(self.material, Material):
            raise SceneError(f"material must be a Material, got {type(self.material).__name__}")
        if isinstance(self.friction, (int, float)) and not isinstance(self.friction, bool):
            set_(self, "friction", Coulomb(self.friction))
        if not isinstance(self.friction, FrictionLaw):
            raise SceneError(f"friction must be a FrictionLaw or a number, got {self.friction!r}")
        Pose(self.lateral_shift, self.yaw, 0.0 if self.roll is None else self.roll)  # checks the pose's values
        Velocities(self.forward_speed, self.lateral_velocity, self.yaw_rate, self.pitch_rate)

    @cached_property
    def pose(self) -> Pose:
        """The wheelset's pose: the given roll, or the rigid wheelset's for the loads (Hertz); vertical 0 (each
        wheel is pressed down from it to its load)."""
        if self.roll is not None:
            return Pose(self.lateral_shift, self.yaw, self.roll)
        left, right = self.vertical_load_left, self.vertical_load_right
        if left > 0.0 and right > 0.0:
            pose, _, _ = loaded_position(self.track, self.wheelset, self.lateral_shift, self.yaw, left, right,
                                         self.material)
            return Pose(self.lateral_shift, self.yaw, pose.roll)
        return Pose(self.lateral_shift, self.yaw, 0.0)

    @cached_property
    def velocities(self) -> Velocities:
        """The wheelset's velocities."""
        return Velocities(self.forward_speed, self.lateral_velocity, self.yaw_rate, self.pitch_rate)

    @cached_property
    def contacts(self) -> tuple[WheelContact, WheelContact]:
        """The (left, right) wheels' contact geometry at the pose (:func:`~rollcontact.wheelrail.search.
        search_wheel`; cached: the scene is immutable)."""
        return tuple(search_wheel(self.track, self.wheelset, self.pose, side) for side in SIDES)

    def load(self, side: str) -> float:
        """Q [N] of the wheel on ``side``."""
        return self.vertical_load_left if side == "left" else self.vertical_load_right

    @cached_property
    def hertz(self) -> tuple[WheelLoad, WheelLoad]:
        """Each wheel's normal contact by Hertz at its vertical load (:func:`~rollcontact.wheelrail.normal.
        solve_normal`): the classical answer and the start of the other levels' normal problems."""
        return tuple(solve_normal(contact, self.load(contact.side), self.material) for contact in self.contacts)

    @property
    def friction_coefficient(self) -> float:
        """mu at zero slip velocity [1]."""
        return self.friction.static_coefficient

    def replace(self, **changes) -> WheelRailScene:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)


SIDES = ("left", "right")
"""The wheels in the order of :attr:`WheelRailScene.contacts` and of the result's ``wheels``."""
