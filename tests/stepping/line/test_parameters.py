"""The 2D level table :data:`rollcontact.stepping.line.parameters.METHOD_LEVELS` and the codes that follow from it; the
rail conditions of both contact models' parameters."""

import pytest

from rollcontact import RationalFalling, rail_condition
from rollcontact.line.dispatch import BUILTIN
from rollcontact.stepping import ContactParameters, ModelError
from rollcontact.stepping.elliptic.parameters import EllipticParameters
from rollcontact.stepping.line.parameters import (
    AUTO_CODES,
    INSTATIONARY_CODES,
    METHOD_LEVELS,
    METHOD_NAMES,
    TABLE_CODE,
    method_code,
    registered_methods,
)
from rollcontact.stepping.parameters import AUTO, RAIL_CONDITION_CODES, RAIL_CONDITION_SETS, friction_law

RECORDED = {1: "closed_form", 2: "polynomial", 3: "discretised", 4: "relaxation_lag", 5: "discretised_transient",
            6: "table"}
"""Codes hosts and recorded runs hold (tests/fmu/fingerprints): they never change."""


def test_codes_are_unique_positive_and_keep_the_recorded_ones():
    codes = [level.code for level in METHOD_LEVELS]
    names = [level.name for level in METHOD_LEVELS]
    assert len(set(codes)) == len(codes) and AUTO not in codes and min(codes) > 0, f"codes {codes}"
    assert len(set(names)) == len(names), f"names {names}"
    table = {level.code: level.name for level in METHOD_LEVELS}
    assert {code: table.get(code) for code in RECORDED} == RECORDED, f"recorded codes changed: {table}"
    assert codes == sorted(codes), f"append only: codes {codes} must increase down the table"
    assert all(level.used for level in METHOD_LEVELS), "every level needs a method_used description"


def test_derived_codes_follow_the_table():
    assert METHOD_NAMES == {1: "closed_form", 2: "polynomial", 3: "discretised"}, f"METHOD_NAMES {METHOD_NAMES}"
    assert AUTO_CODES == (2, 3), f"auto families {AUTO_CODES}"
    assert INSTATIONARY_CODES == {"relaxation": 4, "transient": 5}, f"instationary codes {INSTATIONARY_CODES}"
    assert TABLE_CODE == 6, f"table code {TABLE_CODE}"
    assert set(AUTO_CODES) <= set(METHOD_NAMES), "auto tries only families that are choices of method"


def test_every_builtin_method_has_a_code_of_its_family():
    for spec in BUILTIN:
        code = method_code(spec.name)
        assert code in METHOD_NAMES, f"{spec.name} has no method code in METHOD_LEVELS"
        assert spec.name.startswith(METHOD_NAMES[code]), f"{spec.name} got code {code} ({METHOD_NAMES[code]})"
    assert method_code("no_such_family") == 0, "a method of no family must get code 0"
    auto = registered_methods(AUTO_CODES)
    assert auto and [method_code(name) for name in auto] == sorted(method_code(name) for name in auto), \
        f"auto candidates {auto} must come family by family in table order"


@pytest.mark.parametrize("parameters", [ContactParameters, EllipticParameters])
def test_a_rail_condition_replaces_the_friction_parameters_and_a_bad_code_is_named_with_the_rest(parameters):
    for code, name in RAIL_CONDITION_CODES.items():
        law = friction_law(parameters(rail_condition=code, friction_coefficient=0.7, friction_law=2))
        expected = rail_condition(name) if code else RationalFalling(0.7, 0.4 * 0.7, 2.0)
        assert law == expected, f"{parameters.__name__} rail_condition {code} ({name}): {law!r}"
    with pytest.raises(ModelError, match="friction_coefficient = -1.0 .*; rail_condition = 3 is out of range: it must "
                                         "be one of 0 custom, 1 dry, 2 wet"):
        parameters(friction_coefficient=-1.0, rail_condition=3)


def test_the_rail_condition_sets_are_the_named_conditions_of_the_codes():
    """``RAIL_CONDITION_SETS`` (what the FMUs' RailCondition items describe) holds, for every code but custom, the
    named condition whose law :func:`friction_law` steps with."""
    assert set(RAIL_CONDITION_SETS) == set(RAIL_CONDITION_CODES) - {0}
    for code, condition in RAIL_CONDITION_SETS.items():
        assert condition.name == RAIL_CONDITION_CODES[code], f"code {code}: {condition.name}"
        assert friction_law(ContactParameters(rail_condition=code)) == condition.law() == rail_condition(condition.name)
