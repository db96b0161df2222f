"""Numerical stability at the extremes through the built FMU (issue 7): property-based tests driven by fmpy.

The FMU is built once per test run by ``build_fmu.py`` (the fixtures of ``conftest.py``) and stepped through
fmpy's ``FMU2Slave`` with its logger captured (``test_fmu.Instance``).  Parameters and inputs come from the domain
of ``extremes.py`` (E, R, mu, friction law, corrugation, method, order; load, creep, speed and step size at their
extremes, with one draw in ten made invalid: NaN, inf, negative or zero where the model forbids it).

Properties
----------
Every ``doStep`` ends in one of two ways, never in fmi2Error or fmi2Fatal (an exception escaping the slave):

* fmi2OK, and the outputs are valid (``extremes.check_outputs``: finite, |T| <= mu N, 0 <= a* <= a, frictional
  power >= 0, exact full slip on the closed-form path beyond saturation);
* fmi2Discard (fmpy raises ``FMICallException`` with status 2), with the reason logged under status Discard
  (a host must be able to tell the user why): an invalid parameter or input is named with its value
  (``"<name> = <value>"``), a valid step is refused only when no allowed method solves the scene.  Valid
  parameters and inputs are never discarded for any other reason, and invalid ones are never accepted.
  Restoring the state saved before the step makes the instance usable again: with valid parameters a step
  without load is then accepted; with invalid parameters every step is discarded again, for the same reason.

Budget: derandomised hypothesis (``extremes.PROFILE``), 60 instances of 3 steps; a discretised step uses
``extremes.ELEMENTS`` elements.
"""

from __future__ import annotations

import pytest
from extremes import PROFILE, check_outputs, model_inputs, model_parameters
from fmpy.fmi1 import FMICallException
from fmu_host import DISCARD, Instance
from hypothesis import event, given, settings
from hypothesis import strategies as st

OK = 0


def step_or_discard(fmu: Instance, t: float, h: float, row) -> tuple[int, object]:
    """One step: ``(OK, outputs)`` or ``(DISCARD, logged reason)``; any other status fails the test."""
    before = len(fmu.log)
    try:
        return OK, fmu.step(t, h, *row)
    except FMICallException as exc:
        assert exc.status == DISCARD, f"t = {t!r}, h = {h!r}, inputs {row}: status {exc.status}, not OK or Discard"
    logged = [(status, message) for status, _, message in fmu.log[before:]]
    assert logged and logged[-1][0] == DISCARD and logged[-1][1].strip(), \
        f"inputs {row}: a Discard must log its reason with status Discard, got {logged}"
    return DISCARD, logged[-1][1]


@settings(PROFILE, max_examples=60)
@given(model_parameters(), st.data())
@pytest.mark.slow
def test_fmu_steps_end_in_valid_outputs_or_a_logged_discard(unzipped, description, case, data):
    parameters, bad_parameter = case
    fmu = Instance(unzipped, description, name="properties", **parameters)
    try:
        t = 0.0
        for _ in range(3):
            (h, *row), bad_input = data.draw(model_inputs(parameters["contact_width"]))
            state = fmu.fmu.getFMUstate()
            try:
                status, out = step_or_discard(fmu, t, h, row)
                if status == OK:
                    assert bad_parameter is None and bad_input is None, \
                        f"accepted although {bad_parameter or bad_input} is invalid: {out}"
                    event(f"fmu: OK, method_used {out.method_used}")
                    check_outputs(out, parameters, *row)
                    t += h
                    continue
                fmu.fmu.setFMUstate(state)
            finally:
                fmu.fmu.freeFMUstate(state)
            if bad_parameter is not None:
                event("fmu: Discard (invalid parameters)")
                assert f"invalid parameters: {bad_parameter} = " in out, out
                again = step_or_discard(fmu, t, 1e-3, (0.0, 0.0, 1.0))
                assert again == (DISCARD, out), f"a restored instance keeps its parameter problem: {again}"
                continue
            event(f"fmu: Discard ({'input' if bad_input else 'scene'})")
            assert f"{bad_input} = " in out if bad_input else "no method solved" in out, out
            status, unloaded = step_or_discard(fmu, t, 1e-3, (0.0, 0.0, 1.0))
            assert status == OK, f"after {out!r} and a restored state, a step without load failed: {unloaded!r}"
            t += 1e-3
    finally:
        fmu.free()
