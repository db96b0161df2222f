"""The shared checks of a step's arguments (``rollcontact.stepping.base``): the messages the FMUs' refusals carry."""

from __future__ import annotations

import math

from rollcontact.stepping.base import argument_problems, time_problems


def test_a_step_argument_is_named_with_its_value_and_a_bound_with_its_unit():
    rows = (("normal_load", math.nan, "N", 0.0, False), ("creep", -math.inf, "", None, False),
            ("velocity", -0.5, "m/s", 0.0, False), ("spin", "x", "1/m", None, False), ("load", 2.0, "N", 0.0, False))
    assert argument_problems(rows, "contact 2: ") == [
        "contact 2: normal_load = nan is not finite", "contact 2: creep = -inf is not finite",
        "contact 2: velocity = -0.5 m/s is out of range: it must be >= 0.0",
        "contact 2: spin must be a real number, got 'x'"]
    assert time_problems(0.0, 0.0) == ["step_size = 0.0 s is out of range: it must be > 0.0"]
    assert time_problems(math.inf, 1e-3) == ["current_time = inf is not finite"]
