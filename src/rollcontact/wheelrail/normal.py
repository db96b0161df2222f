"""The normal problem of a wheel for a prescribed vertical load, and the rigid wheelset's roll and height
(docs/physics.md, Wheel/rail geometry: normal approach).

A wheel pressed onto its rail moves down by d from its pose (d is the wheelset's vertical displacement, the same for
every contact point of the wheel).  A contact point i of vertical gap ``g_i`` and contact angle ``delta_i`` then has
the normal approach (interpenetration of the undeformed surfaces along its normal)

    pen_i = (d - g_i) cos(delta_i),

and carries ``N_i = N(pen_i)`` along its normal; the rail's vertical load on the wheel is
``Q = sum_i N_i cos(delta_i)``, monotone in d.  Given Q, d is its root (Brent's method on the bracket
``[min g_i, d_0]``, d_0 the displacement at which the deepest point alone carries Q).

Normal laws: by default each contact point is Hertzian (:func:`rollcontact.elliptic.hertz.hertz_ellipse` from its
curvatures ``A = cos(alpha)/(2 r)``, ``B = (k_wheel + k_rail)/2``: ``pen = delta_1 N^(2/3)``, delta_1 the approach
under 1 N; the classical multi-Hertzian contact, e.g. Pascal & Sauvage, Vehicle System Dynamics 22, 1993).  Any
other law plugs in as ``normal_law(patch, approach) -> force``: it is then called once per patch (with the patch's
undeformed gap, :attr:`rollcontact.wheelrail.search.Patch.gap`, and the approach of its deepest point), so the
non-Hertzian methods that treat a two-lobed patch as one contact take over.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from scipy.optimize import brentq

from rollcontact.core.checks import check_real
from rollcontact.core.materials import Material
from rollcontact.elliptic.hertz import HertzEllipse, hertz_ellipse
from rollcontact.wheelrail.geometry import GeometryError, Pose, Track, Wheelset
from rollcontact.wheelrail.search import DEFAULT_DEPTH, Patch, WheelContact, contact_from_scan, scan_gap, search_wheel

__all__ = ["MIN_LATERAL_CURVATURE", "NormalLaw", "WheelLoad", "hertz_contacts", "loaded_position",
           "rigid_contacts", "rigid_position", "solve_normal", "wheel_forces_at_pose"]

NormalLaw = Callable[[Patch, float], float]
"""``normal_law(patch, approach) -> normal force [N]``: the force along the patch's normal at the normal approach
[m] (>= 0) of its deepest point."""

MIN_LATERAL_CURVATURE = 1.0e-3
"""[1/m]: Hertz's lateral curvature B is taken at least this (a radius of 500 m) where the profiles conform."""

STEEL = Material()
"""The default material: E = 210 GPa, nu = 0.28 (:class:`rollcontact.core.materials.Material`)."""

ROLL_TOLERANCE = 1.0e-11
"""[m]: the rigid wheelset's roll is iterated until the two wheels' vertical displacements agree to this."""

MAX_ROLL_STEPS = 40
"""Steps of the rigid wheelset's roll (:func:`rigid_contacts`) before it is refused."""


@dataclass(frozen=True)
class WheelLoad:
    """The normal contact of one wheel (SI units; forces are the rail's on the wheel).

    Attributes
    ----------
    contact : WheelContact
        The geometry at the pose.
    vertical_displacement : float
        d [m], how far the wheel is pressed down from the pose.
    approaches : tuple of float
        Normal approach [m] of each contact point (Hertz) or each patch (another law), in the order of
        ``contact.points`` or ``contact.patches``; <= 0 where it does not touch.
    normal_forces : tuple of float
        N [N] >= 0 in the same order.
    ellipses : tuple of HertzEllipse or None
        Hertz's ellipse of each contact point (None with another law).
    vertical_force : float
        Q = sum N cos(delta) [N].
    lateral_force : float
        sum N sin(delta) [N]: the normal forces' lateral push on the wheel, positive away from the flange side of
        the rail (mirror-symmetric: towards the track centre on both wheels).
    """

    contact: WheelContact
    vertical_displacement: float
    approaches: tuple
    normal_forces: tuple
    ellipses: tuple | None
    vertical_force: float
    lateral_force: float

    @property
    def in_contact(self) -> bool:
        """Whether any contact point carries load."""
        return any(f > 0.0 for f in self.normal_forces)

    @property
    def message(self) -> str:
        """A sentence on the state of contact."""
        if self.in_contact:
            return (f"{self.contact.side} wheel carries {self.vertical_force:.6g} N on "
                    f"{sum(f > 0.0 for f in self.normal_forces)} contact(s)")
        return (f"{self.contact.side} wheel: no contact (lifted off its rail by {self.contact.gap:.6g} m "
                f"beyond the displacement {self.vertical_displacement:.6g} m)")


def hertz_contacts(contact: WheelContact, material: Material) -> tuple[tuple[float, ...], tuple[HertzEllipse, ...]]:
    """delta_1 [m] (the approach under 1 N) and the unit-load ellipse of each contact point (module docstring)."""
    estar = material.contact_modulus
    unit, ellipses = [], []
    for p in contact.points:
        a, b = p.curvatures
        e = hertz_ellipse(1.0, a, max(b, MIN_LATERAL_CURVATURE), estar)
        unit.append(e.approach)
        ellipses.append(e)
    return tuple(unit), tuple(ellipses)


def solve_normal(contact: WheelContact, load: float, material: Material = STEEL,
                 normal_law: NormalLaw | None = None) -> WheelLoad:
    """The vertical displacement d and the normal forces that carry the vertical load (module docstring).

    Parameters
    ----------
    contact : WheelContact
        The wheel's geometry at its pose (:func:`rollcontact.wheelrail.search.search_wheel`).
    load : float
        Q [N] >= 0, the vertical load on the wheel.
    material : Material
        Elastic constants of wheel and rail (Hertz).
    normal_law : NormalLaw, optional
        Another normal law, per patch (module docstring).

    Returns
    -------
    WheelLoad
        At Q = 0: d at first touch, all forces 0 and ``in_contact`` False.
    """
    q = check_real("load", load, lower=0.0, unit="N")
    if normal_law is None:
        unit, ellipses = hertz_contacts(contact, material)
        items = [(p.vertical_gap, math.cos(p.contact_angle), math.sin(p.contact_angle), u)
                 for p, u in zip(contact.points, unit, strict=True)]

        def forces(d):
            return [((d - g) * c / u) ** 1.5 if d > g else 0.0 for g, c, _, u in items]
    else:
        ellipses = None
        items = [(contact.points[p.points[0]].vertical_gap, math.cos(p.contact_angle), math.sin(p.contact_angle), p)
                 for p in contact.patches]

        def forces(d):
            out = []
            for g, c, _, patch in items:
                f = float(normal_law(patch, (d - g) * c)) if d > g else 0.0
                if not (math.isfinite(f) and f >= 0.0):
                    raise GeometryError(f"normal_law returned {f!r} N at approach {(d - g) * c!r} m: a normal force "
                                        "must be finite and >= 0")
                out.append(f)
            return out

    def vertical(d):
        return sum(f * c for f, (_, c, _, _) in zip(forces(d), items, strict=True))

    d_lo = min(it[0] for it in items)
    if q == 0.0:
        d = d_lo
    else:
        g0, c0, _, x0 = items[0]
        if normal_law is None:
            d_hi = g0 + 1.01 * x0 * (q / c0) ** (2.0 / 3.0) / c0  # the deepest point alone carries q
        else:
            d_hi = d_lo + 1e-5
            while vertical(d_hi) < q:
                if d_hi - d_lo > 0.05:
                    raise GeometryError(f"normal_law carries {vertical(d_hi)!r} N < load = {q!r} N at a vertical "
                                        f"displacement of {d_hi - d_lo!r} m beyond first touch (limit 0.05 m)")
                d_hi = d_lo + 2.0 * (d_hi - d_lo)
        d = brentq(lambda x: vertical(x) - q, d_lo, d_hi, xtol=1e-15, rtol=1e-13, maxiter=200) if d_hi > d_lo else d_lo
    f = forces(d)
    approaches = tuple((d - g) * c for g, c, _, _ in items)
    vertical_force = sum(fi * c for fi, (_, c, _, _) in zip(f, items, strict=True))
    lateral_force = sum(fi * s for fi, (_, _, s, _) in zip(f, items, strict=True))
    return WheelLoad(contact, d, approaches, tuple(f), ellipses, vertical_force, lateral_force)


def wheel_forces_at_pose(contact: WheelContact, material: Material = STEEL,
                         normal_law: NormalLaw | None = None) -> WheelLoad:
    """The normal forces at the pose itself (d = 0): a wheel whose least gap is positive is lifted off its rail
    and carries nothing (``in_contact`` False, its message says by how much), never NaN."""
    if normal_law is None:
        unit, ellipses = hertz_contacts(contact, material)
        approaches = tuple(-p.gap for p in contact.points)
        f = tuple((a / u) ** 1.5 if a > 0.0 else 0.0 for a, u in zip(approaches, unit, strict=True))
        angles = [p.contact_angle for p in contact.points]
    else:
        ellipses = None
        approaches = tuple(-contact.points[p.points[0]].gap for p in contact.patches)
        f = tuple(float(normal_law(p, a)) if a > 0.0 else 0.0 for p, a in zip(contact.patches, approaches, strict=True))
        angles = [p.contact_angle for p in contact.patches]
    vertical_force = sum(fi * math.cos(a) for fi, a in zip(f, angles, strict=True))
    lateral_force = sum(fi * math.sin(a) for fi, a in zip(f, angles, strict=True))
    return WheelLoad(contact, 0.0, approaches, f, ellipses, vertical_force, lateral_force)


# ------------------------------------------------------------------------------------------- rigid wheelset
def _root(both, arm, lateral_shift, yaw):
    """The roll at which the two wheels need the same descent (:func:`loaded_position`): ``both(roll) ->
    (difference, what)``; returns ``(roll, what)`` at it (secant from ``-f / arm``, then Brent where it brackets)."""
    roll0, (f0, p0) = 0.0, both(0.0)
    if abs(f0) <= ROLL_TOLERANCE:
        return roll0, p0
    roll1 = roll0 - f0 / arm
    f1, p1 = both(roll1)
    for _ in range(12):  # secant: the difference is nearly linear in the roll (slope 2 Y_t)
        if abs(f1) <= ROLL_TOLERANCE:
            return roll1, p1
        if f1 * f0 < 0.0:
            break
        slope = (f1 - f0) / (roll1 - roll0) if roll1 != roll0 else arm
        if not slope > 0.1 * arm:
            slope = arm
        roll0, f0 = roll1, f1
        roll1 = roll1 - f1 / slope
        f1, p1 = both(roll1)
    if f1 * f0 > 0.0:
        raise GeometryError(f"no roll levels the wheelset at lateral_shift = {lateral_shift!r} m, yaw = {yaw!r} rad "
                            f"(the wheels' descents still differ by {f1!r} m at roll {roll1!r} rad)")
    lo, hi = sorted((roll0, roll1))
    roll = brentq(lambda x: both(x)[0], lo, hi, xtol=1e-15, rtol=1e-14, maxiter=100)
    return roll, both(roll)[1]


def _level(track, wheelset, lateral_shift, yaw, descent, depth):
    """Find the roll at which the two wheels need the same descent: ``descent(contact) -> (d, extra)`` per wheel."""

    def both(roll):
        pose = Pose(lateral_shift, yaw, roll, 0.0)
        left = descent(search_wheel(track, wheelset, pose, "left", depth))
        right = descent(search_wheel(track, wheelset, pose, "right", depth))
        return left[0] - right[0], (left, right)

    roll, (left, right) = _root(both, 2.0 * wheelset.taping_line, lateral_shift, yaw)
    return roll, left, right


def _newton_root(both, arm, lateral_shift, yaw):
    """The roll at which ``both(roll) -> (difference, its slope, what)`` vanishes to :data:`ROLL_TOLERANCE`:
    Newton's steps from roll 0 on the slope given (``arm`` where it is below a tenth of it), inside the bracket of
    the rolls passed on either side of the root once there is one (false position where a step leaves it, halving
    where that stalls); ``(roll, what)`` at it."""
    roll, (f, slope, what) = 0.0, both(0.0)
    below = above = None  # (roll, difference) of the nearest rolls where the difference is < 0, > 0
    stalled = 0
    for _ in range(MAX_ROLL_STEPS):
        if abs(f) <= ROLL_TOLERANCE:
            return roll, what
        if f < 0.0 and (below is None or roll > below[0]):
            below = (roll, f)
        elif f > 0.0 and (above is None or roll < above[0]):
            above = (roll, f)
        step = roll - f / (slope if slope > 0.1 * arm else arm)
        if below is not None and above is not None:
            (lo, f_lo), (hi, f_hi) = sorted((below, above))
            if not lo < step < hi:
                stalled += 1
                step = lo - f_lo * (hi - lo) / (f_hi - f_lo) if stalled % 3 else 0.5 * (lo + hi)
                if not lo < step < hi:
                    step = 0.5 * (lo + hi)
        roll = step
        f, slope, what = both(roll)
    raise GeometryError(f"no roll levels the wheelset at lateral_shift = {lateral_shift!r} m, yaw = {yaw!r} rad "
                        f"(the wheels' descents still differ by {f!r} m at roll {roll!r} rad after "
                        f"{MAX_ROLL_STEPS} steps)")


def rigid_contacts(track: Track, wheelset: Wheelset, lateral_shift: float, yaw: float = 0.0,
                   depth: float = DEFAULT_DEPTH) -> tuple[Pose, WheelContact, WheelContact]:
    """The roll and height of a rigid wheelset touching both rails without load, and its wheels' contact at the roll
    and ``vertical`` = 0, the pose a :class:`~rollcontact.wheelrail.scene.WheelRailScene` of that roll searches at.

    Each wheel must descend by its least vertical gap g(roll) to touch; the roll is the root of
    ``g_left(roll) - g_right(roll)``, by Newton's method from roll 0 on the gaps' own slopes
    (:attr:`~rollcontact.wheelrail.search.GapScan.roll_slope`; safeguarded by the bracket of the rolls passed): each
    step scans the gap over the profiles (:func:`~rollcontact.wheelrail.search.scan_gap`, the search's first pass,
    with its refusals), and only the root's scans are made into contact points and patches
    (:func:`~rollcontact.wheelrail.search.contact_from_scan`).  The height ``dz`` is the wheels' mean least gap
    there.

    Returns
    -------
    (Pose, WheelContact, WheelContact)
        The pose (roll, and ``vertical`` = dz) and the left and right wheels' contact at ``vertical`` = 0 (their
        vertical gaps are dz to :data:`ROLL_TOLERANCE`).

    Raises
    ------
    GeometryError
        A search refuses a pose on the way (:func:`~rollcontact.wheelrail.search.search_wheel`), or no roll levels
        the wheelset (the message names the lateral shift and yaw).
    """

    def both(roll):
        pose = Pose(lateral_shift, yaw, roll, 0.0)
        left = scan_gap(track, wheelset, pose, "left")
        left_gap = left.least_gap
        right = scan_gap(track, wheelset, pose, "right")
        return left_gap - right.least_gap, left.roll_slope - right.roll_slope, (left, right)

    roll, scans = _newton_root(both, 2.0 * wheelset.taping_line, lateral_shift, yaw)
    left, right = (contact_from_scan(scan, depth) for scan in scans)
    return Pose(lateral_shift, yaw, roll, 0.5 * (left.vertical_gap + right.vertical_gap)), left, right


def rigid_position(track: Track, wheelset: Wheelset, lateral_shift: float, yaw: float = 0.0,
                   depth: float = DEFAULT_DEPTH) -> tuple[Pose, WheelContact, WheelContact]:
    """The roll and height of a rigid wheelset touching both rails without load (the kinematic position).

    Each wheel must descend by its least vertical gap g(roll) to touch; the roll is the root of
    ``g_left(roll) - g_right(roll)`` (Newton's method on the gaps' slopes, :func:`rigid_contacts`), and the height
    ``dz = g_left = g_right``.

    Returns
    -------
    (Pose, WheelContact, WheelContact)
        The pose (with roll and vertical) and the left and right wheels' contact at it (vertical gaps ~0).
    """
    pose = rigid_contacts(track, wheelset, lateral_shift, yaw, depth)[0]
    return (pose, search_wheel(track, wheelset, pose, "left", depth),
            search_wheel(track, wheelset, pose, "right", depth))


def loaded_position(track: Track, wheelset: Wheelset, lateral_shift: float, yaw: float, left_load: float,
                    right_load: float, material: Material = STEEL, normal_law: NormalLaw | None = None,
                    depth: float = DEFAULT_DEPTH) -> tuple[Pose, WheelLoad, WheelLoad]:
    """The roll and height of a rigid wheelset whose wheels carry the given vertical loads (elastic contact).

    Each wheel needs the descent ``d(roll)`` that carries its load (:func:`solve_normal`); the roll is the root of
    ``d_left(roll) - d_right(roll)`` and the height their common value (the benchmark's prescribed roll is so
    found: CONTACT user guide, "The Manchester wheel-rail benchmark").

    Returns
    -------
    (Pose, WheelLoad, WheelLoad)
        The pose and each wheel's normal contact at it (displacement ~0 from the pose).
    """
    ql = check_real("left_load", left_load, lower=0.0, lower_open=True, unit="N")
    qr = check_real("right_load", right_load, lower=0.0, lower_open=True, unit="N")
    loads = {"left": ql, "right": qr}

    def descent(contact):
        sol = solve_normal(contact, loads[contact.side], material, normal_law)
        return sol.vertical_displacement, sol

    roll, left, right = _level(track, wheelset, lateral_shift, yaw, descent, depth)
    pose = Pose(lateral_shift, yaw, roll, 0.5 * (left[0] + right[0]))
    return (pose, solve_normal(search_wheel(track, wheelset, pose, "left", depth), ql, material, normal_law),
            solve_normal(search_wheel(track, wheelset, pose, "right", depth), qr, material, normal_law))
