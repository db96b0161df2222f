"""The polynomial method (paper sections 3 and 4): Nielsen's expansion of the surface slope in a Chebyshev basis.

* :mod:`.solver`: the steady solve of one patch (normal problem, stick zone, creep root) and the entry point
  :func:`solve_polynomial`;
* :mod:`.chebyshev`: the slope expansion and its tables (Jacobi-Anger for harmonics);
* :mod:`.monomial`: the paper's monomial basis (eqs 21-26), kept as an independent check;
* :mod:`.validity`: the checks that the one-patch, stick-at-the-leading-edge assumptions hold;
* :mod:`.patches`: several patches coupled through their fields (a split contact);
* :mod:`.slip`: velocity-dependent friction by the slip iteration (section 4.2); :mod:`.patches_slip` the same on
  several patches;
* :mod:`.accuracy`: the settings, error and cost model that ``auto`` chooses with.
"""

from rollcontact.core.method import MethodSpec
from rollcontact.line.methods.polynomial.accuracy import PolynomialAccuracy
from rollcontact.line.methods.polynomial.distributions import PolynomialDistributions
from rollcontact.line.methods.polynomial.solver import inapplicable, solve_polynomial

__all__ = ["METHOD", "PolynomialAccuracy", "PolynomialDistributions", "inapplicable", "solve_polynomial"]

METHOD = MethodSpec("polynomial", solve_polynomial, inapplicable, rank=10, accuracy=PolynomialAccuracy())
