"""Fixed parameters of the wheelset's contact stepping model, the outputs of a step and the codes of the FMU's
integer variables.

* :class:`WheelsetContactParameters` holds the fixed parameters (FMU parameters of the same names: the shared block
  of :class:`~rollcontact.stepping.parameters.ModelParameters`, the track and wheelset, the elliptic level of the
  ``hertz`` level, the geometry table) and checks them all at once;
* :class:`WheelsetContactOutputs` is what a step returns (SI units, track axes; loads of the rails on the wheelset);
* :data:`METHOD_LEVELS` declares the FMU's ``method`` / ``method_used`` codes once.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, NamedTuple, get_type_hints

from rollcontact.stepping.elliptic.parameters import METHOD_LEVELS as ELLIPTIC_LEVELS
from rollcontact.stepping.parameters import AUTO, Level, ModelParameters, level_code
from rollcontact.wheelrail.loads import WheelsetLoads

METHOD_LEVELS = (
    Level(1, "hertz", "Hertz's ellipse per contact point, forces by the elliptic level elliptic_method",
          "Hertz's ellipse per contact point with an elliptic level"),
    Level(2, "strips", "the non-Hertzian strips on each patch's gap", "the non-Hertzian strips on each patch's gap"),
    Level(3, "discretised", "the discretised half-space on each patch's gap",
          "the discretised half-space on each patch's gap"),
)
"""The wheel/rail levels as the FMU numbers them (:data:`rollcontact.wheelrail.dispatch.BUILTIN`): the ``method``
choices, the ``method_used`` codes and the FMU's ``MethodWheelRail`` / ``MethodUsedWheelRail`` enumerations follow
from it.  Append only."""

LEVEL_CODES = {level.name: level.code for level in METHOD_LEVELS}
METHOD_NAMES = {level.code: level.name for level in METHOD_LEVELS if level.choice}
ELLIPTIC_NAMES = {level.code: level.name for level in ELLIPTIC_LEVELS if level.choice}
"""``elliptic_method`` codes (0 auto): the elliptic levels of :data:`rollcontact.stepping.elliptic.parameters.
METHOD_LEVELS`."""

TABULATED_LAWS = ("linear", "saturated")
"""The elliptic levels that the ``hertz`` level answers through the geometry table in float arithmetic
(:class:`rollcontact.wheelrail.tabulated.TabulatedWheelset`)."""

GEOMETRY_TABLE_MODES = {0: "off", 1: "on"}
"""``geometry_table``: 0 a contact search at every step, 1 the contact geometry tabulated over the lateral shift at
initialisation."""

JACOBIAN_MODES = {0: "difference", 1: "none"}
"""``jacobian``: forward differences of the step's own evaluation (four more), or none (the derivatives read 0)."""

CARRIED_PROFILES = Path(__file__).resolve().parents[4] / "models" / "wheelrail" / "profiles"
"""Where the library finds the default profiles (the repository's ``models/wheelrail/profiles``; an FMU passes its
resources folder instead)."""

DEFAULT_WHEEL = "MBench_S1002_v3.prw"
DEFAULT_RAIL = "MBench_UIC60_v3.prr"
"""The default profiles (an empty ``wheel_profile`` / ``rail_profile``): the Manchester benchmark's S1002 and UIC60
1:40 (``models/wheelrail/profiles/README.md``, Apache-2.0)."""

TABLE_STEP = 2.0e-4
"""Spacing [m] of the geometry table's lateral shifts before its refinement
(:meth:`rollcontact.wheelrail.conicity.ContactTable.build`: jumps resolved, intervals halved to its tolerances)."""


def method_code(name: str) -> int:
    """``method_used`` code of a wheel/rail registry name (0 for none)."""
    return level_code(METHOD_LEVELS, name)


DERIVED = ("lateral_shift", "yaw", "lateral_velocity", "yaw_rate")
"""The inputs the derivative outputs differentiate by."""

WheelsetContactOutputs = NamedTuple("WheelsetContactOutputs", [
    *get_type_hints(WheelsetLoads).items(), ("roll", float), ("vertical_position", float),
    *((f"d{load}_d{by}", float) for load in ("force_y", "moment_yaw") for by in DERIVED), ("method_used", int)])
WheelsetContactOutputs.__doc__ = """Outputs of one step (SI units, track axes: x forward, y to the right, z down): the
loads of the rails on the wheelset (the fields of :class:`rollcontact.wheelrail.loads.WheelsetLoads`), its ``roll``
[rad] and ``vertical_position`` [m] (``Pose.vertical``, downward), the derivatives ``dforce_y_d...`` [N per unit] and
``dmoment_yaw_d...`` [N m per unit] in each of :data:`DERIVED` (lateral shift [m], yaw [rad], lateral velocity [m/s],
yaw rate [rad/s]), and the level's code ``method_used``."""

INPUTS = (("lateral_shift", "m", None), ("yaw", "rad", None), ("lateral_velocity", "m/s", None),
          ("yaw_rate", "rad/s", None), ("forward_speed", "m/s", 0.0), ("pitch_rate", "rad/s", None),
          ("vertical_load_left", "N", 0.0), ("vertical_load_right", "N", 0.0))
"""The inputs (name, unit, lower bound) in :meth:`WheelsetContactModel.step`'s order."""


@dataclass(frozen=True)
class WheelsetContactParameters(ModelParameters):
    """Fixed parameters of a :class:`~rollcontact.stepping.wheelrail.model.WheelsetContactModel`, checked on
    creation (every invalid value at once): the shared block (:class:`~rollcontact.stepping.parameters.
    ModelParameters`: material, friction law, rail condition, ``method``, ``tolerance``, ``step_budget``) and the
    wheelset's own.

    Parameters
    ----------
    wheel_profile, rail_profile : str
        Profile files (SIMPACK ``.prw``/``.prr``, Miniprof ``.whl``/``.ban``; :func:`rollcontact.wheelrail.
        profiles.read_profile`) of the right wheel and rail; "" the carried S1002 and UIC60 1:40
        (:data:`DEFAULT_WHEEL`, :data:`DEFAULT_RAIL`).
    gauge, gauge_height : float
        Track gauge [m] measured ``gauge_height`` [m] below the rail tops (:class:`rollcontact.wheelrail.geometry.
        Track`).
    rail_inclination : float
        Cant of each rail towards the track centre [rad] (0 for a profile already canted, as the carried UIC60).
    flange_back_spacing, flange_back_distance : float
        [m] between the flange backs, and from each wheel's taping line to its flange back.
    nominal_radius : float
        r0 [m] at the taping line.
    elliptic_method : int
        The elliptic level of the ``hertz`` level: 0 auto, else a code of :data:`ELLIPTIC_NAMES` (default 5, the
        saturated linear theory).
    geometry_table : int
        A code of :data:`GEOMETRY_TABLE_MODES` (default 1: tabulated at initialisation).
    table_range : float
        The table's half range of lateral shifts [m], (0, 0.05].
    jacobian : int
        A code of :data:`JACOBIAN_MODES`.

    Notes
    -----
    The shared parameters take these meanings here: ``method`` a code of :data:`METHOD_LEVELS` (default 1, hertz) or
    0 auto (:func:`rollcontact.wheelrail.dispatch.solve`'s choice); ``tolerance`` the requested error [1] of each
    patch's Fx, Fy over mu Fn and Mz over mu Fn c; ``step_budget`` bounds each solve of a step, in modelled seconds.
    """

    wheel_profile: str = ""
    rail_profile: str = ""
    gauge: float = 1.435
    gauge_height: float = 0.014
    rail_inclination: float = 0.0
    flange_back_spacing: float = 1.36
    flange_back_distance: float = 0.07
    nominal_radius: float = 0.46
    elliptic_method: int = 5
    geometry_table: int = 1
    table_range: float = 0.012
    jacobian: int = 0
    method: int = 1

    LEVELS: ClassVar[tuple[Level, ...]] = METHOD_LEVELS

    REALS: ClassVar[tuple] = (
        *ModelParameters.REALS,
        ("gauge", 0.5, 3.0, False, False),
        ("gauge_height", 0.0, 0.05, False, False),
        ("rail_inclination", -0.2, 0.2, False, False),
        ("flange_back_spacing", 0.3, 3.0, False, False),
        ("flange_back_distance", 0.0, 0.2, False, False),
        ("nominal_radius", 0.05, 5.0, False, False),
        ("table_range", 0.0, 0.05, True, False),
    )

    def codes(self) -> dict[str, dict]:
        return {**super().codes(), "elliptic_method": {AUTO: "auto", **ELLIPTIC_NAMES},
                "geometry_table": GEOMETRY_TABLE_MODES, "jacobian": JACOBIAN_MODES}

    def problems(self) -> list[str]:
        """The shared checks, then the profile paths' (strings)."""
        problems = super().problems()
        for name in ("wheel_profile", "rail_profile"):
            if not isinstance(getattr(self, name), str):
                problems.append(f"{name} must be a string (a profile file, or '' for the carried one), got "
                                f"{getattr(self, name)!r}")
        return problems
