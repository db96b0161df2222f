"""Fixed parameters of the elliptic contact's stepping model, the outputs of a step and the codes of the FMU's
integer variables.

* :class:`EllipticParameters` holds the fixed parameters (FMU parameters of the same names: the shared block of
  :class:`~rollcontact.stepping.parameters.ModelParameters` and the elliptic contact's own, the curvatures one per
  contact) and checks them all at once;
* :class:`EllipticOutputs` is what one contact's step returns (SI units; forces and moment of the wheel on the rail);
* :data:`METHOD_LEVELS` declares the FMU's ``method`` / ``method_used`` codes once.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, NamedTuple

from rollcontact.core.checks import SceneError, check_real
from rollcontact.stepping.parameters import Level, ModelParameters, level_code

METHOD_LEVELS = (
    Level(1, "linear", "Kalker's linear theory, no friction limit", "Kalker's linear theory, no friction limit"),
    Level(2, "fastsim", "FASTSIM, Kalker's simplified theory", "FASTSIM, Kalker's simplified theory"),
    Level(3, "strips", "strip theory with FaStrip's slip directions", "strip theory with FaStrip's slip directions"),
    Level(4, "discretised", "the discretised 3D steady-rolling solver", "the discretised 3D steady-rolling solver"),
    Level(5, "saturated", "linear theory saturated at mu Fn (Shen, Hedrick, Elkins)",
          "linear theory saturated at mu Fn (Shen, Hedrick, Elkins)"),
    Level(6, "table", "", "the certified table of the strips"),
)
"""The elliptic fidelity levels as the FMU numbers them: the ``method`` choices, the ``method_used`` codes, the FMU's
``Method3D`` and ``MethodUsed3D`` enumerations and their documented table all follow from it.  Append only (a new
level takes the next code); ``tests/stepping/elliptic/test_parameters.py`` checks that every built-in method has a
code."""

LEVEL_CODES = {level.name: level.code for level in METHOD_LEVELS}
"""Level name -> code."""

METHOD_NAMES = {level.code: level.name for level in METHOD_LEVELS if level.choice}
"""``method`` codes and the levels they stand for (0 is auto)."""

JACOBIAN_MODES = {0: "linear", 1: "difference"}
"""``jacobian``: the linear theory's slopes, or forward differences of the step's method (a step answered from the
certified table: the table's own derivatives) (:mod:`rollcontact.stepping.elliptic.model`)."""

TABLE_MODES = {0: "auto", 1: "off", 2: "on"}
"""``table``: the certified table of the strips (:mod:`rollcontact.stepping.elliptic.table_use`) built when the run pays
for it (auto), never, or at initialisation (on)."""

TABLE_OFF = 1
"""``table`` = off."""

NO_STICK = -1.0
"""``stick_fraction`` of a level that does not compute one (linear, strips)."""

DEFAULT_CURVATURES = tuple(float(f"{1.0 / (2.0 * radius):.16g}") for radius in (0.46, 0.3))
"""Default (A, B) [1/m]: a conical wheel of rolling radius 0.46 m on a rail head of crown radius 0.3 m,
A = 1/(2 r0), B = 1/(2 R_rail), to 16 significant digits (as an FMI 2.0 model description writes a start)."""


def method_code(name: str) -> int:
    """``method_used`` code of a registry name: the level whose name starts it (0 for none)."""
    return level_code(METHOD_LEVELS, name)


class EllipticOutputs(NamedTuple):
    """Outputs of one contact in one step (SI units; forces and moment of the wheel on the rail)."""

    longitudinal_force: float
    lateral_force: float
    spin_moment: float
    semi_axis_longitudinal: float
    semi_axis_lateral: float
    max_pressure: float
    stick_fraction: float
    frictional_power: float
    dFx_dxi: float
    dFx_deta: float
    dFx_dphi: float
    dFy_dxi: float
    dFy_deta: float
    dFy_dphi: float
    dMz_dxi: float
    dMz_deta: float
    dMz_dphi: float
    method_used: int


ZERO = EllipticOutputs(*(0.0,) * 17, 0)
"""The outputs without load (no contact)."""


@dataclass(frozen=True)
class EllipticParameters(ModelParameters):
    """Fixed parameters of an :class:`~rollcontact.stepping.elliptic.model.EllipticModel`, checked on creation
    (every invalid value at once): the shared block (:class:`~rollcontact.stepping.parameters.ModelParameters`:
    material, friction law, rail condition, ``method``, ``tolerance``, ``step_budget``) and the elliptic contact's
    own.

    Parameters
    ----------
    curvature_longitudinal, curvature_lateral : tuple of float
        A and B [1/m] > 0 of the gap ``A x^2 + B y^2``, one per contact (the same count).
    jacobian : int
        A code of :data:`JACOBIAN_MODES`.
    table : int
        A code of :data:`TABLE_MODES`: with Coulomb friction and ``method`` auto or strips, the steps answer from
        the certified table of the strips once it is built, where ``tolerance`` is 0 or at least its bound plus the
        strips' largest error (:mod:`rollcontact.stepping.elliptic.table_use`).

    Notes
    -----
    The shared parameters take these meanings here: ``method`` 0 auto, else the code of a level of
    :data:`METHOD_LEVELS`; ``tolerance`` the requested error [1] of Fx, Fy over mu Fn and of Mz over mu Fn c;
    ``step_budget`` bounds each contact's solve in a step; the slip velocity of a falling law is ``V |s|``.
    """

    curvature_longitudinal: tuple = (DEFAULT_CURVATURES[0],)
    curvature_lateral: tuple = (DEFAULT_CURVATURES[1],)
    jacobian: int = 0
    table: int = 0

    LEVELS: ClassVar[tuple[Level, ...]] = METHOD_LEVELS

    def codes(self) -> dict[str, dict]:
        return {**super().codes(), "jacobian": JACOBIAN_MODES, "table": TABLE_MODES}

    def problems(self) -> list[str]:
        """The shared checks, then the curvatures': a per-contact value is named ``curvature_longitudinal[k]``
        (k from 1) when there are several."""
        problems = super().problems()
        counts = []
        for name in ("curvature_longitudinal", "curvature_lateral"):
            values = getattr(self, name)
            if isinstance(values, (int, float)) and not isinstance(values, bool):
                values = (values,)
            if not isinstance(values, (tuple, list)) or not values:
                problems.append(f"{name} must be a non-empty sequence of curvatures [1/m], one per contact, got "
                                f"{values!r}")
                continue
            checked = []
            for k, value in enumerate(values, start=1):
                label = name if len(values) == 1 else f"{name}[{k}]"
                try:
                    checked.append(check_real(label, value, lower=0.0, lower_open=True, unit="1/m"))
                except SceneError as exc:
                    problems.append(str(exc))
            object.__setattr__(self, name, tuple(checked) if len(checked) == len(values) else tuple(values))
            counts.append(len(values))
        if len(counts) == 2 and counts[0] != counts[1]:
            problems.append(f"curvature_longitudinal has {counts[0]} contacts, curvature_lateral {counts[1]}: one "
                            "curvature of each per contact")
        return problems

    @property
    def contacts(self) -> int:
        """Number of contacts n."""
        return len(self.curvature_longitudinal)


INPUTS = (("normal_load", "N", 0.0), ("longitudinal_creep", "", None), ("lateral_creep", "", None),
          ("spin", "1/m", None), ("velocity", "m/s", 0.0), ("gap_curvature_longitudinal", "1/m", 0.0),
          ("gap_curvature_lateral", "1/m", 0.0))
"""The inputs of a contact (name, unit, lower bound) in :meth:`EllipticModel.step`'s order; the last two, the gap's
curvatures A and B of the step (0: the parameters ``curvature_longitudinal`` and ``curvature_lateral``), may be left
out of a row."""

LOAD_INPUTS = 5
"""Inputs of a row without the gap's curvatures (:data:`INPUTS`)."""
