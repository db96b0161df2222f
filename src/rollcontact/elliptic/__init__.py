"""Elliptic (3D) rolling contact: Hertz's ellipse and the steady tangential problem, Fx, Fy and Mz from
longitudinal, lateral and spin creepage, at several fidelity levels behind one dispatcher.

* :mod:`.scene` (:class:`EllipticScene`), :mod:`.hertz` (Hertz's ellipse), :mod:`.result` (:class:`EllipticResult`),
  :mod:`.creep_coefficients` (Kalker's C11..C33, from the table :mod:`.creep_table`): the data layer;
* :mod:`.methods`: the fidelity levels, each exporting ``METHOD`` (a :class:`rollcontact.core.method.MethodSpec`);
* :mod:`.dispatch`: :func:`~.dispatch.solve`, the method table and the registry.

Conventions in docs/physics.md (Elliptic contact) and :mod:`.scene`; the result reports the forces the wheel exerts
on the rail.
"""

from rollcontact.elliptic.creep_coefficients import CreepageCoefficients, creepage_coefficients
from rollcontact.elliptic.hertz import HertzEllipse, curvatures_from_radii, curvatures_from_semi_axes, hertz_ellipse
from rollcontact.elliptic.result import EllipticResult, TractionField
from rollcontact.elliptic.scene import EllipticScene

__all__ = ["CreepageCoefficients", "EllipticResult", "EllipticScene", "HertzEllipse", "TractionField",
           "creepage_coefficients", "curvatures_from_radii", "curvatures_from_semi_axes", "hertz_ellipse"]
