"""Typed, validated description of one 2D rolling-contact case (a *scene*).

A scene holds everything a solver needs: material, geometry (cylinder radius, surface profile, axis position),
normal load per unit length, creep, friction and rolling speed.  Every value is checked when the scene is built;
an invalid one raises :class:`SceneError` naming the field, the value and the limit.

Scenes are loaded from TOML files (``models/*.toml``) by :func:`load_scene` and written by :func:`scene_toml`; see
``models/README.md`` for the format.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field, fields, replace
from functools import cached_property
from pathlib import Path

import numpy as np

from rollcontact.core.checks import SceneError, check_real
from rollcontact.core.friction import LAWS, Coulomb, FrictionLaw, friction_from_dict, friction_law
from rollcontact.core.materials import Material, check_material

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib




@dataclass(frozen=True)
class Harmonic:
    """One harmonic of the surface height: ``cos_amplitude cos(k X) + sin_amplitude sin(k X)``.

    Parameters
    ----------
    wavenumber : float
        k = 2 pi / wavelength [1/m], > 0.
    cos_amplitude, sin_amplitude : float
        Phi and Psi of the paper's eq 27 [m].
    """

    wavenumber: float
    cos_amplitude: float = 0.0
    sin_amplitude: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "wavenumber",
                           check_real("harmonic wavenumber", self.wavenumber, lower=0.0, lower_open=True))
        object.__setattr__(self, "cos_amplitude", check_real("harmonic cos_amplitude", self.cos_amplitude))
        object.__setattr__(self, "sin_amplitude", check_real("harmonic sin_amplitude", self.sin_amplitude))

    @classmethod
    def from_wavelength(cls, wavelength: float, amplitude: float, phase: float = 0.0) -> Harmonic:
        """``amplitude cos(2 pi X / wavelength + phase)`` as a Harmonic (wavelength, amplitude in m)."""
        wavelength = check_real("corrugation wavelength", wavelength, lower=0.0, lower_open=True)
        amplitude = check_real("corrugation amplitude", amplitude)
        phase = check_real("corrugation phase", phase)
        return cls(2.0 * math.pi / wavelength, amplitude * math.cos(phase), -amplitude * math.sin(phase))

    @property
    def amplitude(self) -> float:
        """Peak height sqrt(Phi^2 + Psi^2) [m]."""
        return math.hypot(self.cos_amplitude, self.sin_amplitude)


@dataclass(frozen=True)
class Surface:
    """Height Z(X) [m] of the (flat-on-average) counter-surface towards the cylinder, X surface-fixed [m].

    ``Z(X) = sum_j polynomial[j] X^j + sum_m Phi_m cos(k_m X) + Psi_m sin(k_m X)``  (paper eq 27 plus a
    polynomial part).  The undeformed gap to a cylinder of radius R whose axis stands above ``X = x_c`` is
    ``h0(X) = (X - x_c)^2 / (2R) - Z(X)``.  The constant term of the polynomial shifts both bodies alike and
    is irrelevant.
    """

    polynomial: tuple[float, ...] = ()
    harmonics: tuple[Harmonic, ...] = ()

    def __post_init__(self):
        poly = tuple(check_real(f"surface polynomial[{j}]", c) for j, c in enumerate(self.polynomial))
        object.__setattr__(self, "polynomial", poly)
        harm = tuple(h if isinstance(h, Harmonic) else Harmonic(**h) for h in self.harmonics)
        object.__setattr__(self, "harmonics", harm)

    @cached_property
    def is_flat(self) -> bool:
        """True when Z is at most linear with no harmonics; a tilt only moves the patch, see hertzian (cached: the
        surface is immutable and every method's applicability check asks)."""
        return all(c == 0.0 for c in self.polynomial[2:]) and all(h.amplitude == 0.0 for h in self.harmonics)

    @property
    def is_hertzian(self) -> bool:
        """True when the gap is exactly parabolic and symmetric about the axis (Hertz and Carter hold)."""
        return self.is_flat and (len(self.polynomial) < 2 or self.polynomial[1] == 0.0)

    def height(self, X):
        """Z(X) [m] at surface positions X [m]."""
        X = np.asarray(X, dtype=float)
        z = np.polynomial.polynomial.polyval(X, self.polynomial) if self.polynomial else np.zeros_like(X)
        for h in self.harmonics:
            z = z + h.cos_amplitude * np.cos(h.wavenumber * X) + h.sin_amplitude * np.sin(h.wavenumber * X)
        return z

    def slope(self, X):
        """dZ/dX [1] at surface positions X [m]."""
        X = np.asarray(X, dtype=float)
        if len(self.polynomial) > 1:
            z = np.polynomial.polynomial.polyval(X, np.polynomial.polynomial.polyder(self.polynomial))
        else:
            z = np.zeros_like(X)
        for h in self.harmonics:
            k = h.wavenumber
            z = z + k * (h.sin_amplitude * np.cos(k * X) - h.cos_amplitude * np.sin(k * X))
        return z


@dataclass(frozen=True)
class Scene:
    """One steady 2D rolling-contact case; all quantities SI, per unit length where named so.

    Parameters
    ----------
    normal_load_per_length : float
        N' [N/m] >= 0 (0 means no contact).
    creep : float
        Longitudinal creep xi [1] (both signs); xi > 0 gives T' > 0 (see the package conventions).
    radius : float
        Effective cylinder radius R [m] > 0, 1/R = 1/R1 + 1/R2.
    material : Material
        Elastic constants of the quasi-identical bodies.
    friction : FrictionLaw
        Friction law; a float is taken as a Coulomb coefficient mu.
    surface : Surface
        Counter-surface height Z(X) (smooth and flat by default).
    axis_position : float
        x_c [m], surface coordinate below the cylinder axis.
    rolling_speed : float
        V [m/s] >= 0; enters velocity-dependent friction and instationary rolling.
    name : str
        Free text identifying the scene.
    """

    normal_load_per_length: float
    creep: float = 0.0
    radius: float = 0.46
    material: Material = field(default_factory=Material)
    friction: FrictionLaw = field(default_factory=lambda: Coulomb(0.3))
    surface: Surface = field(default_factory=Surface)
    axis_position: float = 0.0
    rolling_speed: float = 1.0
    name: str = ""

    def __post_init__(self):
        set_ = object.__setattr__
        set_(self, "normal_load_per_length",
             check_real("normal_load_per_length", self.normal_load_per_length, lower=0.0))
        set_(self, "creep", check_real("creep", self.creep))
        set_(self, "radius", check_real("radius", self.radius, lower=0.0, lower_open=True))
        set_(self, "axis_position", check_real("axis_position", self.axis_position))
        set_(self, "rolling_speed", check_real("rolling_speed", self.rolling_speed, lower=0.0))
        check_material(self.material)
        if not isinstance(self.surface, Surface):
            raise SceneError(f"surface must be a Surface, got {type(self.surface).__name__}")
        set_(self, "friction", friction_law(self.friction))

    @property
    def friction_coefficient(self) -> float:
        """mu at zero slip velocity [1] (the Coulomb value for a Coulomb law)."""
        return self.friction.static_coefficient

    def replace(self, **changes) -> Scene:
        """A copy with some fields changed (validated again)."""
        return replace(self, **changes)


def far_gap_points(surface: Surface, radius: float, axis_position: float = 0.0) -> np.ndarray:
    """Positions X [m] (surface coordinates) where the polynomial part of a surface, of degree >= 3, can close the
    gap far from the contact: the minima of the undeformed gap ``(X - x_c)^2/2R - Z_poly(X)`` within
    ``|X - x_c| <= R`` and the ends ``X = x_c +- R`` (empty for a polynomial part of degree <= 2).

    Such a polynomial bends the surface back towards the cylinder (a quartic rising faster than the parabola closes
    the gap at ``(X - x_c)^2 = 1/(2 R c4)``, however far that is): a gap that closes there closes in an interval, and
    the interval holds a minimum of the gap or reaches ``|X - x_c| = R``.  Beyond the radius the parabola stands for
    no cylinder, so nothing past it is a candidate.  Both methods check their deformed gap at these points
    (docs/physics.md, Validity).
    """
    coefficients = surface.polynomial
    if len(coefficients) <= 3 or not any(coefficients[3:]):
        return np.empty(0)
    gap = -np.array(coefficients, dtype=float)  # ascending powers of X
    gap[:3] += np.array([axis_position * axis_position, -2.0 * axis_position, 1.0]) / (2.0 * radius)
    critical = np.polynomial.polynomial.polyroots(np.polynomial.polynomial.polyder(gap))
    x = np.concatenate((critical.real[np.abs(critical.imag) <= 1e-9 * np.abs(critical)],
                        (axis_position - radius, axis_position + radius)))
    return x[np.abs(x - axis_position) <= radius]


def scene_from_dict(data: dict, *, name: str = "") -> Scene:
    """Build a Scene from the nested dict of a TOML scene file (see ``models/README.md``)."""
    data = dict(data)
    known = {"scene", "material", "geometry", "surface", "load", "friction", "rolling"}
    unknown = set(data) - known
    if unknown:
        raise SceneError(f"unknown table(s) {sorted(unknown)} in scene; valid tables are {sorted(known)}")
    material = Material(**data.get("material", {}))
    geometry = dict(data.get("geometry", {}))
    surf = dict(data.get("surface", {}))
    harmonics = [Harmonic(**h) for h in surf.pop("harmonics", [])]
    for c in surf.pop("corrugations", []):
        harmonics.append(Harmonic.from_wavelength(**c))
    surface = Surface(polynomial=tuple(surf.pop("polynomial", ())), harmonics=tuple(harmonics))
    if surf:
        raise SceneError(f"unknown key(s) {sorted(surf)} in [surface]")
    load = dict(data.get("load", {}))
    rolling = dict(data.get("rolling", {}))
    kwargs = {}
    for table, keys in ((geometry, ("radius", "axis_position")),
                        (load, ("normal_load_per_length", "creep")),
                        (rolling, ("rolling_speed",))):
        for k in list(table):
            if k not in keys:
                raise SceneError(f"unknown key {k!r}; valid keys here are {list(keys)}")
            kwargs[k] = table[k]
    friction = friction_from_dict(data["friction"]) if "friction" in data else Coulomb(0.3)
    meta = dict(data.get("scene", {}))
    if set(meta) - {"name", "description"}:
        raise SceneError(f"unknown key(s) {sorted(set(meta) - {'name', 'description'})} in [scene]; "
                         "valid keys are ['description', 'name']")
    return Scene(material=material, surface=surface, friction=friction,
                 name=str(meta.get("name", name)), **kwargs)


def load_scene(path) -> Scene:
    """Read a Scene from a TOML file; errors name the file and the offending field."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise SceneError(f"cannot read scene file {str(path)!r}: {exc}") from exc
    try:
        return scene_from_dict(data, name=path.stem)
    except (ValueError, TypeError) as exc:  # SceneError and the friction laws' ValueErrors
        raise SceneError(f"{path.name}: {exc}") from exc


def scene_toml(scene: Scene) -> str:
    """The TOML text of a scene file that :func:`load_scene` reads back as ``scene`` (every value exactly).

    Harmonics are written by wavenumber and amplitudes (``[[surface.harmonics]]``), the friction law by its name in
    :data:`rollcontact.core.friction.LAWS` and its fields.  Use it to hand a scene to the FMU's ``scene_file`` parameter
    (which reads the surface in the FMU's frame: ``rollcontact.stepping.line.model`` module docstring).

    Parameters
    ----------
    scene : Scene
        A scene whose friction law is one of :data:`rollcontact.core.friction.LAWS` (a SceneError names any other, and
        anything but a Scene).

    Returns
    -------
    str
        The file's text.
    """
    def toml(value) -> str:
        if isinstance(value, tuple):
            return "[" + ", ".join(toml(v) for v in value) + "]"
        if isinstance(value, str):  # a basic string: quote, backslash and control characters escaped
            return '"' + "".join(f"\\u{ord(c):04x}" if c in '"\\' or ord(c) < 0x20 or ord(c) == 0x7F else c
                                 for c in value) + '"'
        return repr(float(value))  # repr round-trips every float; TOML reads inf and nan too

    if not isinstance(scene, Scene):
        raise SceneError(f"scene_toml needs a Scene, got {type(scene).__name__} {scene!r}")
    friction = scene.friction
    law = next((name for name, cls in LAWS.items() if type(friction) is cls), None)
    if law is None:
        raise SceneError(f"friction law {type(friction).__name__} has no scene-file form: the laws of a scene file "
                         f"are {sorted(LAWS)}")
    tables = {"scene": {"name": scene.name},
              "material": {"youngs_modulus": scene.material.youngs_modulus,
                           "poisson_ratio": scene.material.poisson_ratio},
              "geometry": {"radius": scene.radius, "axis_position": scene.axis_position},
              "load": {"normal_load_per_length": scene.normal_load_per_length, "creep": scene.creep},
              "rolling": {"rolling_speed": scene.rolling_speed},
              "friction": {"law": law, **{f.name: getattr(friction, f.name) for f in fields(friction)}},
              "surface": {"polynomial": tuple(scene.surface.polynomial)}}
    lines = []
    for table, values in tables.items():
        lines += [f"[{table}]", *(f"{key} = {toml(value)}" for key, value in values.items()), ""]
    for h in scene.surface.harmonics:
        lines += ["[[surface.harmonics]]", f"wavenumber = {toml(h.wavenumber)}",
                  f"cos_amplitude = {toml(h.cos_amplitude)}", f"sin_amplitude = {toml(h.sin_amplitude)}", ""]
    return "\n".join(lines)
