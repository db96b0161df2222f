"""The discretised method: Kalker-type boundary elements on the half-space (any gap, any friction law).

* :mod:`.steady`: the steady solve :func:`solve_discretised` (direct, marched or structured for
  velocity-dependent friction) and the Richardson-extrapolated pair :func:`extrapolated`;
* :mod:`.rolling`: rolling over a surface (:func:`roll_over_surface`);
* :mod:`.accuracy`: the settings, error bounds and cost model that ``auto`` chooses with.

The grid, the influence coefficients and the transient stepper it builds on are in :mod:`rollcontact.core.halfspace`,
which the polynomial method and instationary rolling share.
"""

from rollcontact.core.method import MethodSpec
from rollcontact.line.methods.discretised.accuracy import DiscretisedAccuracy
from rollcontact.line.methods.discretised.rolling import RollingHistory, roll_over_surface
from rollcontact.line.methods.discretised.steady import extrapolated, inapplicable, solve_discretised

__all__ = ["METHOD", "DiscretisedAccuracy", "RollingHistory", "extrapolated", "inapplicable", "roll_over_surface",
           "solve_discretised"]

METHOD = MethodSpec("discretised", solve_discretised, inapplicable, rank=100, fallback=True,
                    accuracy=DiscretisedAccuracy())
