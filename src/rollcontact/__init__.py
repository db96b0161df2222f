"""rollcontact: fast, accurate rolling contact of quasi-identical elastic bodies (wheel on rail, roller on race),
for co-simulation.

One subpackage per geometry, each of the same shape (a scene, a result type, a ``methods`` folder of fidelity levels
with their accuracy models, and a dispatcher ``solve`` over its method table), on a shared core:

* :mod:`rollcontact.line`: the line (2D) contact, per unit length, by J.B. Nielsen's methods;
* :mod:`rollcontact.elliptic`: the elliptic (3D) contact with creep and spin, from Kalker's linear theory to his
  exact theory;
* :mod:`rollcontact.wheelrail`: a wheelset on its track from real profiles: contact search, tread and flange
  patches, non-Hertzian normal and tangential contact;
* :mod:`rollcontact.core`: checks, material, friction laws, the method contract, the dispatch engine, the
  discretised half-space;
* :mod:`rollcontact.stepping`: the FMUs' stepping models (parameters -> state, inputs, step -> outputs).

Conventions (docs/physics.md): SI units; per-length quantities of the line contact named so
(``normal_load_per_length`` N' [N/m]); x the rolling direction; a positive creepage gives a positive force on the
counter-surface (the rail).

Entry points: :class:`Scene` (and :func:`load_scene`), :func:`solve`, :class:`ContactResult` for the line contact;
:class:`EllipticScene`, :func:`solve_elliptic`, :class:`EllipticResult` for the elliptic contact;
:func:`read_profile`, :class:`Track`, :class:`Wheelset`, :class:`WheelRailScene`, :func:`solve_wheelrail`,
:class:`WheelRailResult` for the wheel/rail contact.
"""

from rollcontact.core.checks import SceneError
from rollcontact.core.friction import (
    Coulomb,
    ExponentialFalling,
    FrictionLaw,
    LinearFalling,
    RailCondition,
    RationalFalling,
    TabulatedFriction,
    rail_condition,
)
from rollcontact.core.materials import Material
from rollcontact.elliptic import EllipticResult, EllipticScene, HertzEllipse, creepage_coefficients, hertz_ellipse
from rollcontact.elliptic.dispatch import (
    METHODS as ELLIPTIC_METHODS,
)
from rollcontact.elliptic.dispatch import (
    register_method as register_elliptic_method,
)
from rollcontact.elliptic.dispatch import (
    solve as solve_elliptic,
)
from rollcontact.line.carter import carter
from rollcontact.line.dispatch import METHODS, choose_method, register_method, solve
from rollcontact.line.hertz import hertz
from rollcontact.line.result import ContactResult
from rollcontact.line.scene import Harmonic, Scene, Surface, load_scene, scene_toml
from rollcontact.wheelrail.conicity import equivalent_conicity
from rollcontact.wheelrail.dispatch import (
    METHODS as WHEELRAIL_METHODS,
)
from rollcontact.wheelrail.dispatch import (
    register_method as register_wheelrail_method,
)
from rollcontact.wheelrail.dispatch import (
    solve as solve_wheelrail,
)
from rollcontact.wheelrail.geometry import Track, Wheelset
from rollcontact.wheelrail.profiles import Profile, read_profile
from rollcontact.wheelrail.result import WheelRailResult
from rollcontact.wheelrail.scene import WheelRailScene

__version__ = "0.1.0"


__all__ = [
    "ELLIPTIC_METHODS",
    "METHODS",
    "WHEELRAIL_METHODS",
    "ContactResult",
    "Coulomb",
    "EllipticResult",
    "EllipticScene",
    "ExponentialFalling",
    "FrictionLaw",
    "Harmonic",
    "HertzEllipse",
    "LinearFalling",
    "Material",
    "Profile",
    "RailCondition",
    "RationalFalling",
    "Scene",
    "SceneError",
    "Surface",
    "TabulatedFriction",
    "Track",
    "WheelRailResult",
    "WheelRailScene",
    "Wheelset",
    "carter",
    "choose_method",
    "creepage_coefficients",
    "equivalent_conicity",
    "hertz",
    "hertz_ellipse",
    "load_scene",
    "rail_condition",
    "read_profile",
    "register_elliptic_method",
    "register_method",
    "register_wheelrail_method",
    "scene_toml",
    "solve",
    "solve_elliptic",
    "solve_wheelrail",
]
