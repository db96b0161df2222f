"""The elliptic level table :data:`rollcontact.stepping.elliptic.parameters.METHOD_LEVELS` and the codes that follow
from it."""

from rollcontact.elliptic.dispatch import BUILTIN
from rollcontact.stepping.elliptic.parameters import LEVEL_CODES, METHOD_LEVELS, METHOD_NAMES, method_code
from rollcontact.stepping.parameters import AUTO

RECORDED = {1: "linear", 2: "fastsim", 3: "strips", 4: "discretised", 5: "saturated"}
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
    assert LEVEL_CODES == {name: code for code, name in table.items()}, f"LEVEL_CODES {LEVEL_CODES}"


def test_every_builtin_method_has_a_code_of_its_family():
    for spec in BUILTIN:
        code = method_code(spec.name)
        assert code in METHOD_NAMES, f"{spec.name} has no method code in METHOD_LEVELS"
        assert spec.name.startswith(METHOD_NAMES[code]), f"{spec.name} got code {code} ({METHOD_NAMES[code]})"
    assert method_code("no_such_family") == 0, "a method of no family must get code 0"
