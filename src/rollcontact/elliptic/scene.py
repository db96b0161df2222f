"""Typed, validated description of one steady elliptic (3D) rolling-contact case: :class:`EllipticScene`.

Conventions (docs/physics.md, Elliptic contact): x is the rolling direction, y lateral, z normal; the wheel rolls
towards +x, so material enters the contact at its leading edge ``x = +a(y)``.  The creepages are Kalker's: the rigid
slip of the wheel relative to the rail over the rolling speed V is ``w_x = xi - phi y``, ``w_y = eta + phi x``
(xi longitudinal and eta lateral creepage [1], phi spin creepage [1/m]).  Both bodies are quasi-identical
(:class:`rollcontact.Material`), the normal problem is Hertz's (:mod:`rollcontact.elliptic.hertz`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

from rollcontact.core.checks import SceneError, check_real
from rollcontact.core.friction import Coulomb, FrictionLaw, friction_from_dict, friction_law
from rollcontact.core.materials import Material, check_material
from rollcontact.elliptic.hertz import HertzEllipse, curvatures_from_radii, curvatures_from_semi_axes, hertz_ellipse

__all__ = ["EllipticScene", "scene_from_dict"]


@dataclass(frozen=True)
class EllipticScene:
    """One steady rolling case of an elliptic contact (SI units).

    Parameters
    ----------
    normal_load : float
        Fn [N] >= 0 (0: no contact).
    longitudinal_curvature : float
        A [1/m] > 0 of the undeformed gap ``A x^2 + B y^2``.
    lateral_curvature : float
        B [1/m] > 0.
    longitudinal_creepage : float
        xi [1], either sign; xi > 0 gives a longitudinal force > 0 on the rail.
    lateral_creepage : float
        eta [1], either sign; eta > 0 gives a lateral force > 0 on the rail.
    spin_creepage : float
        phi [1/m], either sign; phi > 0 gives a spin moment > 0 on the rail (and a lateral force > 0).
    material : Material
        Elastic constants of the quasi-identical bodies.
    friction : FrictionLaw
        Friction law (a number is a Coulomb coefficient); velocity-dependent laws take the slip velocity
        ``V |s|`` [m/s].
    rolling_speed : float
        V [m/s] >= 0; enters velocity-dependent friction only.
    name : str
        Free text identifying the scene.

    Raises
    ------
    SceneError
        (a ValueError) naming the field, the value and the limit: a negative load, a curvature <= 0, a NaN
        creepage, ...
    """

    normal_load: float
    longitudinal_curvature: float
    lateral_curvature: float
    longitudinal_creepage: float = 0.0
    lateral_creepage: float = 0.0
    spin_creepage: float = 0.0
    material: Material = field(default_factory=Material)
    friction: FrictionLaw = field(default_factory=lambda: Coulomb(0.3))
    rolling_speed: float = 1.0
    name: str = ""

    def __post_init__(self):
        set_ = object.__setattr__
        set_(self, "normal_load", check_real("normal_load", self.normal_load, lower=0.0, unit="N"))
        set_(self, "longitudinal_curvature", check_real("longitudinal_curvature", self.longitudinal_curvature,
                                                        lower=0.0, lower_open=True, unit="1/m"))
        set_(self, "lateral_curvature", check_real("lateral_curvature", self.lateral_curvature, lower=0.0,
                                                   lower_open=True, unit="1/m"))
        set_(self, "longitudinal_creepage", check_real("longitudinal_creepage", self.longitudinal_creepage))
        set_(self, "lateral_creepage", check_real("lateral_creepage", self.lateral_creepage))
        set_(self, "spin_creepage", check_real("spin_creepage", self.spin_creepage, unit="1/m"))
        set_(self, "rolling_speed", check_real("rolling_speed", self.rolling_speed, lower=0.0, unit="m/s"))
        check_material(self.material)
        set_(self, "friction", friction_law(self.friction))

    @classmethod
    def from_radii(cls, normal_load: float, wheel_rolling_radius: float, wheel_profile_radius: float = math.inf,
                   rail_profile_radius: float = 0.3, rail_longitudinal_radius: float = math.inf,
                   **fields) -> EllipticScene:
        """A scene from the wheel's and rail's principal radii [m] (:func:`~rollcontact.elliptic.hertz.
        curvatures_from_radii`: convex positive, concave negative, straight inf); ``fields`` are the others."""
        A, B = curvatures_from_radii(wheel_rolling_radius, wheel_profile_radius, rail_profile_radius,
                                     rail_longitudinal_radius)
        return cls(normal_load, A, B, **fields)

    @classmethod
    def from_semi_axes(cls, normal_load: float, a: float, b: float, material: Material | None = None,
                       **fields) -> EllipticScene:
        """A scene whose Hertz ellipse under ``normal_load`` [N] > 0 has semi-axes a (along x) and b [m]
        (:func:`~rollcontact.elliptic.hertz.curvatures_from_semi_axes`); ``fields`` are the others."""
        material = Material() if material is None else material
        A, B = curvatures_from_semi_axes(a, b, normal_load, material.contact_modulus)
        return cls(normal_load, A, B, material=material, **fields)

    @cached_property
    def hertz(self) -> HertzEllipse:
        """The Hertz ellipse (a, b, p0, approach, a/b) of the scene (cached: the scene is immutable)."""
        return hertz_ellipse(self.normal_load, self.longitudinal_curvature, self.lateral_curvature,
                             self.material.contact_modulus)

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) [Pa] of the material."""
        return self.material.shear_modulus

    @property
    def friction_coefficient(self) -> float:
        """mu at zero slip velocity [1] (the Coulomb value for a Coulomb law)."""
        return self.friction.static_coefficient

    @property
    def creepages(self) -> tuple[float, float, float]:
        """(xi [1], eta [1], phi [1/m])."""
        return self.longitudinal_creepage, self.lateral_creepage, self.spin_creepage

    def replace(self, **changes) -> EllipticScene:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)


def scene_from_dict(data: dict, *, name: str = "") -> EllipticScene:
    """An EllipticScene from the nested dict of a TOML scene file (``models/README.md``, "Elliptic scenes"):
    ``[scene]`` (``geometry = "elliptic"``, ``name``, ``description``), ``[material]``, ``[ellipse]``
    (``longitudinal_curvature``, ``lateral_curvature`` [1/m], or ``semi_axes = [a, b]`` [m] at the load),
    ``[load]`` (``normal_load`` [N], ``longitudinal_creepage``, ``lateral_creepage``, ``spin_creepage`` [1/m]),
    ``[rolling]`` (``rolling_speed``), ``[friction]`` (a law or a ``rail_condition``).

    Raises
    ------
    SceneError
        An unknown table or key, or an invalid value (named).
    """
    known = {"scene": {"geometry", "name", "description"}, "material": {"youngs_modulus", "poisson_ratio"},
             "ellipse": {"longitudinal_curvature", "lateral_curvature", "semi_axes"},
             "load": {"normal_load", "longitudinal_creepage", "lateral_creepage", "spin_creepage"},
             "rolling": {"rolling_speed"}, "friction": None}
    for table, value in data.items():
        if table not in known:
            raise SceneError(f"unknown table [{table}] in an elliptic scene; valid tables are {sorted(known)}")
        if known[table] is not None and set(value) - known[table]:
            raise SceneError(f"unknown key(s) {sorted(set(value) - known[table])} in [{table}]; valid keys are "
                             f"{sorted(known[table])}")
    material = Material(**data.get("material", {}))
    friction = friction_from_dict(data["friction"]) if "friction" in data else Coulomb(0.3)
    load = dict(data.get("load", {}))
    ellipse = dict(data.get("ellipse", {}))
    fields_ = dict(load, rolling_speed=data.get("rolling", {}).get("rolling_speed", 1.0), friction=friction,
                   name=str(data.get("scene", {}).get("name", name)))
    if "normal_load" not in fields_:
        raise SceneError("[load] needs normal_load [N]")
    normal_load = fields_.pop("normal_load")
    if "semi_axes" in ellipse:
        if set(ellipse) != {"semi_axes"}:
            raise SceneError("[ellipse] takes semi_axes or the two curvatures, not both")
        a, b = ellipse["semi_axes"]
        return EllipticScene.from_semi_axes(normal_load, a, b, material=material, **fields_)
    if set(ellipse) != {"longitudinal_curvature", "lateral_curvature"}:
        raise SceneError("[ellipse] needs longitudinal_curvature and lateral_curvature [1/m] (or semi_axes [m])")
    return EllipticScene(normal_load, material=material, **ellipse, **fields_)
