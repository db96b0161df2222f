"""The wheel/rail contact's cases: a wheelset on its track (:class:`WheelRailScene`, what the wheel/rail levels
solve) and one patch's rolling-contact case (:class:`PatchScene`: its gap, its normal load or approach, the creepages
at its rigid contact point, the friction law, the rolling speed and the material, what a patch level solves).

Creepages (docs/physics.md, Elliptic contact): the rigid slip of the wheel relative to the rail over V in the
patch's contact plane is ``w_x = xi - phi s``, ``w_y = eta + phi x``, x along the track (the wheel rolls towards +x)
and s across the patch from its rigid contact point.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path

from rollcontact.core.checks import SceneError, check_real
from rollcontact.core.friction import Coulomb, FrictionLaw, friction_from_dict, friction_law
from rollcontact.core.materials import Material, check_material
from rollcontact.wheelrail.geometry import Pose, Track, Velocities, Wheelset
from rollcontact.wheelrail.normal import WheelLoad, loaded_position, solve_normal
from rollcontact.wheelrail.patch import PatchGap
from rollcontact.wheelrail.profiles import read_profile
from rollcontact.wheelrail.search import WheelContact, search_wheel

__all__ = ["POSITION_COLUMNS", "SIDES", "VELOCITY_FIELDS", "PatchScene", "WheelRailScene", "cases_from_dict",
           "read_positions"]


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
        check_material(self.material)
        set_(self, "friction", friction_law(self.friction))

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) [Pa] of the material."""
        return self.material.shear_modulus

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
        check_material(self.material)
        set_(self, "friction", friction_law(self.friction))
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

    def with_contacts(self, contacts) -> WheelRailScene:
        """A copy whose wheels' contact geometry is given rather than searched: ``(left, right)``, what
        :func:`~rollcontact.wheelrail.search.search_wheel` finds at :attr:`pose` on this track and wheelset with the
        default depth (the rigid wheelset's, :func:`~rollcontact.wheelrail.normal.rigid_contacts`); SceneError where
        they are not the left and right wheels' at :attr:`pose`."""
        contacts = tuple(contacts)
        if len(contacts) != 2 or not all(isinstance(c, WheelContact) for c in contacts) or \
                tuple(c.side for c in contacts) != SIDES:
            raise SceneError(f"contacts must be the (left, right) wheels' WheelContact, got {contacts!r}")
        for c in contacts:
            if c.pose != self.pose:
                raise SceneError(f"the {c.side} wheel's contact was found at {c.pose!r}, not at the scene's pose "
                                 f"{self.pose!r}")
            if c.scan is not None and (c.scan.track is not self.track or c.scan.wheelset is not self.wheelset):
                raise SceneError(f"the {c.side} wheel's contact was found on another track or wheelset")
        scene = replace(self)
        scene.__dict__["contacts"] = contacts  # the cached_property's value, as searching would give it
        return scene

    def with_velocities(self, **velocities) -> WheelRailScene:
        """A copy with other velocities (``forward_speed``, ``lateral_velocity``, ``yaw_rate``, ``pitch_rate``,
        validated again) that shares this scene's geometry: its pose, contacts and Hertz's normal contact, which do
        not depend on them (where this scene has computed them)."""
        unknown = set(velocities) - set(VELOCITY_FIELDS)
        if unknown:
            raise SceneError(f"with_velocities changes only {list(VELOCITY_FIELDS)}, not {sorted(unknown)}")
        scene = replace(self, **velocities)
        for name in ("pose", "contacts", "hertz"):
            if name in self.__dict__:
                scene.__dict__[name] = self.__dict__[name]
        return scene


VELOCITY_FIELDS = ("forward_speed", "lateral_velocity", "yaw_rate", "pitch_rate")
"""The fields of a :class:`WheelRailScene` its geometry does not depend on (:meth:`WheelRailScene.with_velocities`)."""

SIDES = ("left", "right")
"""The wheels in the order of :attr:`WheelRailScene.contacts` and of the result's ``wheels``."""


POSITION_COLUMNS = ("case", "lateral_shift_mm", "yaw_rad", "roll_rad", "vertical_load_per_wheel_N",
                    "forward_speed_m_s", "pitch_rate_rad_s")
"""Columns of a positions file (``[positions] file``): the Manchester benchmark's CSV of case A-2.2."""


def cases_from_dict(data: dict, folder: Path, *, name: str = "") -> list[tuple[dict, WheelRailScene]]:
    """The cases of a wheel/rail TOML scene file (``models/wheelrail/README.md``): ``(fields, scene)`` pairs, the
    fields ``case``, ``lateral_shift`` [m] and ``yaw`` [rad] that name each case.

    Tables: ``[scene]`` (``geometry = "wheelrail"``, ``name``, ``description``); ``[track]`` (``rail_profile``, a
    path relative to the file, ``gauge``, ``gauge_height``, ``inclination``); ``[wheelset]`` (``wheel_profile``,
    ``nominal_radius``, ``flange_back_spacing``, ``flange_back_distance``); ``[material]``; ``[friction]`` (a law
    or a ``rail_condition``); and either ``[positions]`` (``file``: a CSV of :data:`POSITION_COLUMNS`, relative to
    the file; ``forward_speed`` [m/s] optional, replacing the file's and scaling its pitch rates alike) or
    ``[pose]`` (the :class:`WheelRailScene` fields ``lateral_shift`` ... ``pitch_rate`` of one case).

    Raises
    ------
    SceneError
        An unknown table or key, a missing field, an invalid value (named), a profile or positions file that cannot
        be read.
    """
    known = {"scene": {"geometry", "name", "description"},
             "track": {"rail_profile", "gauge", "gauge_height", "inclination"},
             "wheelset": {"wheel_profile", "nominal_radius", "flange_back_spacing", "flange_back_distance"},
             "material": {"youngs_modulus", "poisson_ratio"}, "friction": None,
             "positions": {"file", "forward_speed"},
             "pose": {"lateral_shift", "yaw", "roll", "vertical_load_left", "vertical_load_right", "forward_speed",
                      "lateral_velocity", "yaw_rate", "pitch_rate"}}
    for table, value in data.items():
        if table not in known:
            raise SceneError(f"unknown table [{table}] in a wheel/rail scene; valid tables are {sorted(known)}")
        if known[table] is not None and set(value) - known[table]:
            raise SceneError(f"unknown key(s) {sorted(set(value) - known[table])} in [{table}]; valid keys are "
                             f"{sorted(known[table])}")
    if ("positions" in data) == ("pose" in data):
        raise SceneError("a wheel/rail scene needs one of [positions] (a file of cases) and [pose] (one case)")
    track_data, wheel_data = dict(data.get("track", {})), dict(data.get("wheelset", {}))
    for table, key in ((track_data, "rail_profile"), (wheel_data, "wheel_profile")):
        if key not in table:
            raise SceneError(f"[{'track' if key == 'rail_profile' else 'wheelset'}] needs {key} (a profile file)")
    rail = read_profile(folder / track_data.pop("rail_profile"))
    wheel = read_profile(folder / wheel_data.pop("wheel_profile"))
    track, wheelset = Track(rail, **track_data), Wheelset(wheel, **wheel_data)
    common = {"material": Material(**data.get("material", {})),
              "friction": friction_from_dict(data["friction"]) if "friction" in data else Coulomb(0.3),
              "name": str(data.get("scene", {}).get("name", name))}
    if "pose" in data:
        scene = WheelRailScene(track, wheelset, **data["pose"], **common)
        return [({"case": 1, "lateral_shift": scene.lateral_shift, "yaw": scene.yaw}, scene)]
    positions = dict(data["positions"])
    if "file" not in positions:
        raise SceneError("[positions] needs file (a CSV of cases)")
    out = []
    for row in read_positions(folder / positions["file"]):
        speed = row["forward_speed_m_s"]
        scale = positions.get("forward_speed", speed) / speed
        scene = WheelRailScene(track, wheelset, row["lateral_shift_mm"] * 1e-3, row["yaw_rad"], row["roll_rad"],
                               row["vertical_load_per_wheel_N"], row["vertical_load_per_wheel_N"], speed * scale,
                               pitch_rate=row["pitch_rate_rad_s"] * scale, **common)
        out.append(({"case": int(row["case"]), "lateral_shift": scene.lateral_shift, "yaw": scene.yaw}, scene))
    return out


def read_positions(path: Path) -> list[dict]:
    """The rows of a positions file (:data:`POSITION_COLUMNS`, numbers); SceneError naming the file and the line
    otherwise."""
    try:
        with open(path, newline="") as fh:
            rows = list(csv.DictReader(fh))
    except OSError as exc:
        raise SceneError(f"cannot read the positions file {str(path)!r}: {exc}") from None
    out = []
    for line, row in enumerate(rows, start=2):
        missing = [c for c in POSITION_COLUMNS if c not in row]
        if missing:
            raise SceneError(f"{path.name}: the columns {missing} are missing (needed: {list(POSITION_COLUMNS)})")
        try:
            out.append({c: float(row[c]) for c in POSITION_COLUMNS})
        except (TypeError, ValueError):
            raise SceneError(f"{path.name}, line {line}: a value is not a number: {row}") from None
    if not out:
        raise SceneError(f"{path.name}: no positions")
    return out
