"""rollcontact: fast, accurate 2D rolling contact of quasi-identical elastic bodies.

Conventions (used by every module; docs/physics.md, Conventions)
---------------------------------------------------------
* 2D plane strain, half-space theory, quasi-identical bodies: the normal problem is solved first, the
  tangential one on top of it.  Contact modulus ``E* = E / (2 (1 - nu^2))``.
* SI units.  Quantities of the 2D core are per unit length and named so: ``normal_load_per_length`` N' [N/m],
  ``tangential_force_per_length`` T' [N/m].
* ``X`` is the surface-fixed coordinate [m]; the cylinder axis stands above ``X = x_c`` (``axis_position``).
  Distributions are evaluated at ``x = X - x_c`` [m].  The contact centre is at ``x = Delta``
  (``contact_offset``), the half-width is ``a``.
* Material flows through the contact in +x (the cylinder rolls towards -x): the leading edge is
  ``x = Delta - a`` and the stick zone of steady rolling touches it.
* ``q`` is the traction the cylinder exerts on the counter-surface; the tangential displacement difference
  obeys ``du/dx = (2 / (pi E*)) PV-int q(z) / (x - z) dz``; the slip is ``s = xi + du/dx + (1/V) du/dt``
  and in slip ``q = mu p sign(s)``.  Hence creep xi > 0 gives T' > 0, and Carter's ``a* = a - R xi / mu``.
* Surface height ``Z(X)`` points towards the cylinder; the undeformed gap is ``(X - x_c)^2 / (2R) - Z(X)``.

Entry points: :class:`Scene` (and :func:`load_scene`), :func:`solve`, :class:`ContactResult`; for the elliptic (3D)
contact :class:`EllipticScene`, :func:`solve_elliptic`, :class:`EllipticResult` (:mod:`rollcontact.elliptic`).
"""

from rollcontact.closed_form import carter, hertz
from rollcontact.dispatch import METHODS, choose_method, register_method, solve
from rollcontact.elliptic import EllipticResult, EllipticScene, HertzEllipse, creepage_coefficients, hertz_ellipse
from rollcontact.elliptic.dispatch import ELLIPTIC_METHODS, register_elliptic_method, solve_elliptic
from rollcontact.friction import (
    Coulomb,
    ExponentialFalling,
    FrictionLaw,
    LinearFalling,
    RailCondition,
    RationalFalling,
    TabulatedFriction,
    rail_condition,
)
from rollcontact.result import ContactResult
from rollcontact.scene import Harmonic, Material, Scene, SceneError, Surface, load_scene, scene_toml

__version__ = "0.1.0"


__all__ = [
    "METHODS",
    "ContactResult",
    "Coulomb",
    "ELLIPTIC_METHODS",
    "EllipticResult",
    "EllipticScene",
    "ExponentialFalling",
    "FrictionLaw",
    "Harmonic",
    "HertzEllipse",
    "LinearFalling",
    "Material",
    "RailCondition",
    "RationalFalling",
    "Scene",
    "SceneError",
    "Surface",
    "TabulatedFriction",
    "carter",
    "choose_method",
    "creepage_coefficients",
    "hertz",
    "hertz_ellipse",
    "load_scene",
    "rail_condition",
    "register_elliptic_method",
    "register_method",
    "scene_toml",
    "solve",
    "solve_elliptic",
]
