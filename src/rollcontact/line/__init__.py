"""The line (2D) contact: a cylinder rolling on a surface of plane strain, per unit length, by J.B. Nielsen's
methods.

* :mod:`.scene` (:class:`~.scene.Scene`, :class:`~.scene.Surface`, :class:`~.scene.Harmonic`, TOML scenes),
  :mod:`.result` (:class:`~.result.ContactResult`, one result type for every method), :mod:`.hertz` and
  :mod:`.carter` (the closed forms of the normal and the tangential problem): the data layer;
* :mod:`.halfspace`: the line contact on the discretised half-space (grids, the transient solver);
* :mod:`.methods`: the fidelity levels, each exporting ``METHOD`` (a :class:`rollcontact.core.method.MethodSpec`);
* :mod:`.dispatch`: :func:`~.dispatch.solve`, the method table and the registry;
* :mod:`.instationary`: rolling whose inputs vary over a few contact widths.

Conventions in docs/physics.md (Conventions) and the :mod:`rollcontact` package docstring.
"""

from rollcontact.line.result import ContactResult
from rollcontact.line.scene import Harmonic, Scene, Surface, load_scene, scene_toml

__all__ = ["ContactResult", "Harmonic", "Scene", "Surface", "load_scene", "scene_toml"]
