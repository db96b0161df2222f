"""The largest stable macro step's measure: the explicit coupling beyond its limit against the linearly implicit one."""

from __future__ import annotations

import numpy as np

from rollcontact_cosim.scenes import CONTACT
from rollcontact_cosim.stable_step import deviation, is_stable

TRACTION = f"{CONTACT}.traction_coefficient"


def test_explicit_coupling_oscillates_where_linearly_implicit_matches_the_fine_run(run):
    """carter_sanity at H = 2 ms: |lambda| H ~ 3.9 > 2 for the explicit Gauss-Seidel loop (module
    rollcontact_cosim.wheel_rig), which ends in a limit cycle between the saturations; the linearly implicit
    host is within 1 % of a 0.1 ms run."""
    fine = run("carter_sanity", step_size=1e-4)
    implicit = run("carter_sanity", step_size=2e-3, host={"coupling": 1})
    explicit = run("carter_sanity", step_size=2e-3, host={"coupling": 0})
    assert deviation(implicit, fine) < 0.01, f"implicit deviates by {deviation(implicit, fine):.3g} of max T/N"
    assert not is_stable(explicit, fine), f"explicit should be unstable, deviates by {deviation(explicit, fine):.3g}"
    late = explicit.values[TRACTION][explicit.values["time"] > 0.3]
    assert np.ptp(late) > 0.3, f"explicit T/N must keep swinging (limit cycle), range {np.ptp(late):.3g}"
