"""Parameter rows that the elliptic and wheel/rail FMUs share, in their tables' form ``(name, type, unit, min, max,
description)``: the material and the friction law of :class:`rollcontact.stepping.parameters.ModelParameters`."""

from __future__ import annotations

import math

from pythonfmu import Integer, Real, String

from rollcontact_fmu.enumerations import largest
from rollcontact_fmu.slave import POSITIVE


def material_friction_rows(used: dict) -> tuple:
    """Young's modulus, Poisson's ratio and the friction law's parameters; ``friction_law``'s bound from the
    enumerations ``used`` (:func:`rollcontact_fmu.enumerations.largest`)."""
    return (
        ("youngs_modulus", Real, "Pa", POSITIVE, None, "Young's modulus E of wheel and rail, > 0"),
        ("poisson_ratio", Real, "1", 0.0, math.nextafter(0.5, 0.0),
         "Poisson's ratio nu of wheel and rail, 0 <= nu < 0.5"),
        ("friction_coefficient", Real, "1", POSITIVE, None, "Friction coefficient mu at zero slip velocity, > 0"),
        ("friction_law", Integer, None, 0, largest(used["friction_law"][1]), "Friction law (FrictionLaw)"),
        ("friction_kinetic_ratio", Real, "1", POSITIVE, 1.0, "A of the falling laws: mu(infinity)/mu, 0 < A <= 1"),
        ("friction_decay", Real, "s/m", 0.0, None, "B of the exponential law, per slip velocity v, >= 0"),
        ("friction_reference_velocity", Real, "m/s", POSITIVE, None, "v_ref of the rational law, > 0"),
        ("friction_slope", Real, "s/m", 0.0, None, "c of the linear law max(A mu, mu - c v), >= 0"),
        ("friction_table", String, None, None, None,
         "Points 'v mu; v mu; ...' of the tabulated law, v [m/s] increasing"),
    )
