"""Contact search per wheel: the contact points of a wheel on its rail, their patches' undeformed gap
(:class:`~rollcontact.wheelrail.patch.PatchGap`) and the creepages (docs/physics.md, Wheel/rail geometry: contact
search, kinematics).

The rail is prismatic along x, so at a contact point the wheel's surface normal has no x component.  On the wheel's
circle of radius r at the axle's lateral coordinate Y (profile slope ``tan(alpha) = dz_w/dy_w``) that point lies at
the angle theta from the lowest point, forward positive, where (wheel normal ``R (sin(theta) cos(alpha),
-sin(alpha), cos(theta) cos(alpha))``, ``R = R_z(psi) R_x(phi)``)

    cos(psi) sin(theta) + sin(phi) sin(psi) cos(theta) = -tan(alpha) cos(phi) sin(psi),

so ``sin(theta) ~ -tan(alpha) tan(psi)``: the contact point leads or trails the axle by about
``r tan(psi) tan(delta)`` (the yawed wheel's surface; Wickens, *Fundamentals of Rail Vehicle Dynamics*, 2003, ch.
2; the contact locus of Shabana, Zaazaa & Sugiyama, *Railroad Vehicle Dynamics*, 2008, ch. 5).  These points of
all circles form the wheel's contact locus, a curve whose projection on the y-z plane has the wheel's normal as its
normal: the 3D search becomes the 2D distance between the locus and the rail profile.

The search computes the locus at the wheel's samples, interpolates it (cubic Hermite, with its slopes) at the rail's
samples and forms the vertical gap ``g(y) = Z_rail(y) - Z_wheel(y)``.  Its local minima are where the surfaces have
a common normal; each is refined to the root of the Hermite cubic's derivative between two samples.  The minimum
is the point that touches first when the wheel is lowered vertically; its normal separation is ``g cos(delta)``.
That is the search's first pass, the gap over the profiles (:func:`scan_gap`, :class:`GapScan`: all a rigid wheelset's
roll needs of a wheel, its least gap); the second makes the minima into contact points and patches
(:func:`contact_from_scan`).  :func:`search_wheel` is both.

Several contact points (separation criterion): every local minimum whose gap exceeds the wheel's least gap by at
most ``depth`` (the largest elastic approach considered, :data:`DEFAULT_DEPTH`) is a contact point, unless the gap
between it and a deeper neighbour rises by less than :data:`MIN_RISE` above it (a ripple of the profiles).
Neighbouring points whose interpenetration regions at the approach ``depth`` merge (the gap between them stays below
the deeper one's gap plus ``depth``) form one patch; each patch's gap is sampled in the tangent plane of its deepest
point, over the region where the gap is below that point's gap plus ``depth`` (and a margin), so it covers both
lobes of a two-lobed patch.

Per-wheel quantities are reported mirror-symmetrically: the left wheel's problem is the mirror image of a right
wheel's (the pose mirrored: y_ws, yaw and roll change sign), contact angles are positive towards the flange on both
wheels and lateral positions are in each profile's own axes.  The patch gap and the creepages are in the contact
frame (x, s, n) of :mod:`rollcontact.wheelrail.patch`: s increasing with the track's y, n = x cross s (into the rail)
on both wheels, so their s, eta and phi change sign between mirror-image wheels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from typing import NamedTuple

import numpy as np

from rollcontact.wheelrail.geometry import (
    MAX_SURFACE_ANGLE,
    SEARCH_STRIDE,
    GeometryError,
    Pose,
    Track,
    Velocities,
    Wheelset,
    side_sign,
)
from rollcontact.wheelrail.patch import PatchGap

__all__ = ["DEFAULT_DEPTH", "FLANGE_TIP_MARGIN", "MIN_RISE", "PATCH_STEP", "ContactPoint", "Creepages", "GapScan",
           "Patch", "WheelContact", "contact_from_scan", "creepages", "scan_gap", "search_wheel"]

DEFAULT_DEPTH = 2.0e-4
"""The largest elastic approach [m] the search prepares for: contact points up to this gap above the least one, and
patch regions where the gap is below the patch's least gap plus this.  On S1002/UIC60 Hertz's approach reaches it at
a normal load of a few hundred kN on the tread and well over 100 kN on the flange
(benchmarks/results/wheelrail_geometry.md, part E)."""

MIN_RISE = 1.0e-6
"""[m]: two minima of the gap are distinct contact points only where the gap between them rises at least this much
above the shallower one."""

FLANGE_TIP_MARGIN = 1.0e-3
"""[m]: a wheel whose deepest contact point lies within this of its flange's crest
(:attr:`~rollcontact.wheelrail.geometry.Wheelset.flange_tip`), or beyond it towards the flange back, has climbed its
flange: the search reports it (:class:`~rollcontact.wheelrail.geometry.GeometryError`) instead of a contact."""

PATCH_STEP = 1.0e-4
"""Sampling step [m] of the patch gap along s."""

PATCH_MARGIN = 0.15
"""The patch region's margin on each side, a fraction of its width (at least two steps)."""


@dataclass(frozen=True)
class ContactPoint:
    """One contact point of a wheel on its rail (SI units; module docstring for the conventions).

    Attributes
    ----------
    rail_lateral : float
        y [m] of the point on the rail profile, in the profile's own axes.
    wheel_lateral : float
        y_w [m] of the point on the wheel profile, in its own axes (0 at the taping line, flange at negative y).
    contact_angle : float
        delta [rad] of the common normal from the track's vertical, positive towards the flange.
    rolling_radius : float
        r [m] of the wheel's circle through the point.
    gap : float
        Separation [m] along the normal at the pose (``vertical_gap cos(delta)``; negative: interpenetration).
    vertical_gap : float
        [m] the wheel must move down (at the pose's roll and yaw) for the point to touch.
    longitudinal_shift : float
        x [m] of the point ahead of the centre of the wheel's circle through it (the yaw's lead,
        ``~ r tan(psi) tan(delta)``).
    wheel_lateral_curvature : float
        [1/m] of the wheel profile at the point, positive convex (towards the rail).
    wheel_rolling_curvature : float
        ``cos(alpha) / r`` [1/m], the wheel's normal curvature along its circumference (alpha the wheel profile's
        own slope angle).
    rail_lateral_curvature : float
        [1/m] of the rail profile at the point, positive convex.
    position : tuple of float
        (x, y, z) [m] of the point on the rail in track axes.
    side : str
        ``"left"`` or ``"right"``.
    """

    rail_lateral: float
    wheel_lateral: float
    contact_angle: float
    rolling_radius: float
    gap: float
    vertical_gap: float
    longitudinal_shift: float
    wheel_lateral_curvature: float
    wheel_rolling_curvature: float
    rail_lateral_curvature: float
    position: tuple
    side: str

    @property
    def curvatures(self) -> tuple[float, float]:
        """(A, B) [1/m], Hertz's gap curvatures ``A = cos(alpha)/(2 r)``, ``B = (k_wheel + k_rail)/2``
        (docs/physics.md, Hertz's ellipse)."""
        return 0.5 * self.wheel_rolling_curvature, 0.5 * (self.wheel_lateral_curvature + self.rail_lateral_curvature)


@dataclass(frozen=True, eq=False)
class Patch:
    """One contact patch: its contact points and the undeformed gap in the tangent plane of the deepest.

    Attributes
    ----------
    points : tuple of int
        Indices into :attr:`WheelContact.points`, the first the patch's deepest point (the rigid contact point the
        tangent plane is taken at).
    contact_angle : float
        delta [rad] of the tangent plane (the deepest point's), positive towards the flange.
    memo : dict
        What a level computes of the patch alone, keyed by its exact arguments (the patch is immutable, so a
        value found here is the one computing it again gives: e.g. Hertz's departure, shared by the solves of one
        geometry).
    """

    points: tuple
    contact_angle: float
    source: PatchRegion = field(repr=False)
    memo: dict = field(default_factory=dict, repr=False, compare=False)

    @cached_property
    def gap(self) -> PatchGap:
        """The gap (:class:`PatchGap`): ``lateral`` s [m] from the deepest point (increasing with the track's y),
        ``lateral_gap`` h(s) [m] >= 0 along the normal at x = 0 (0 at s = 0), ``longitudinal_curvature``
        A(s) = cos(alpha(s)) / (2 r(s)) [1/m], over the region where the gap is below the point's gap plus the
        search's depth, widened by PATCH_MARGIN (computed when first asked for: a pure function of the search's
        inputs)."""
        return self.source.gap()


@dataclass(frozen=True)
class WheelContact:
    """The contact of one wheel on its rail at a pose.

    Attributes
    ----------
    side : str
        ``"left"`` or ``"right"``.
    points : tuple of ContactPoint
        Ordered by the deepest first (least gap), then by rail position.
    patches : tuple of Patch
        Patches, the deepest first.
    pose : Pose
        The pose searched at (track axes, not mirrored).
    scan : GapScan or None
        The gap over the profiles the points were found from.
    """

    side: str
    points: tuple
    patches: tuple
    pose: Pose
    scan: GapScan | None = field(default=None, repr=False, compare=False)

    @property
    def gap(self) -> float:
        """The least separation [m] along the normal (negative: interpenetration)."""
        return self.points[0].gap

    @property
    def vertical_gap(self) -> float:
        """How far [m] the wheel must move down from the pose to touch (negative: it is already in)."""
        return self.points[0].vertical_gap

    @property
    def in_contact(self) -> bool:
        """Whether the wheel touches or penetrates the rail at the pose."""
        return self.points[0].vertical_gap <= 0.0

    @property
    def message(self) -> str:
        """A sentence on the state of contact at the pose."""
        if self.in_contact:
            return (f"{self.side} wheel in contact: {len(self.points)} contact point(s) in {len(self.patches)} "
                    f"patch(es), approach {-self.gap:.6g} m")
        return (f"{self.side} wheel lifted off its rail by {self.gap:.6g} m (vertical {self.vertical_gap:.6g} m) at "
                "the pose: no contact")


class Creepages(NamedTuple):
    """Kalker's creepages at a contact point (docs/physics.md, Elliptic contact: rigid slip ``w_x = xi - phi s``,
    ``w_y = eta + phi x`` of the wheel relative to the rail over V) in the contact frame (x, s, n).

    Attributes
    ----------
    longitudinal : float
        xi [1].
    lateral : float
        eta [1], along s (increasing with the track's y).
    spin : float
        phi [1/m], about n = x cross s.
    """

    longitudinal: float
    lateral: float
    spin: float


# ------------------------------------------------------------------------------------------------ the search
STRIDE = SEARCH_STRIDE


def wheel_locus(wheelset: Wheelset, pose: Pose, idx: slice, coarse: bool = False):
    """The right wheel's contact locus (right-side frame) at the wheel samples ``idx``: Y, Z [m], dZ/dY, and
    whether each sample's normal can lie in the y-z plane (None: all can).  ``coarse``: ``idx`` indexes every
    STRIDE-th sample (module docstring)."""
    smp = wheelset.samples
    cpsi, spsi = math.cos(pose.yaw), math.sin(pose.yaw)
    cphi, sphi = math.cos(pose.roll), math.sin(pose.roll)
    arrays = smp.coarse if coarse else smp.__dict__
    r, ta, b = arrays["radius"][idx], arrays["tan"][idx], arrays["axle"][idx]
    # A sin(theta) + B cos(theta) = C: theta = asin(C / rho) - beta
    rho = math.hypot(cpsi, sphi * spsi)
    cb, sb = cpsi / rho, sphi * spsi / rho
    k1 = -cphi * spsi / rho
    c = ta * k1
    ok = None
    if abs(k1) * wheelset.steepest >= 0.99:  # only a large yaw on steep samples can leave no solution
        ok = np.abs(c) < 0.99
        np.clip(c, -0.99, 0.99, out=c)
    root = np.sqrt(1.0 - c * c)
    st = c * cb - root * sb
    ct = root * cb + c * sb
    a = r * st
    cc = r * ct
    v = b * cphi - cc * sphi
    y = a * spsi + v * cpsi + pose.lateral_shift
    z = b * sphi + cc * cphi + (pose.vertical - wheelset.nominal_radius)
    # the normal over cos(alpha): ny = st sin(psi) - ct sin(phi) cos(psi) - tan(alpha) cos(phi) cos(psi),
    # nz = ct cos(phi) - tan(alpha) sin(phi); the locus' slope is -ny / nz
    ny = st * spsi - ct * (sphi * cpsi) - ta * (cphi * cpsi)
    nz = ct * cphi - ta * sphi
    return y, z, -ny / nz, ok


def locus_point(wheelset: Wheelset, pose: Pose, radius: float, tan_alpha: float, axle: float) -> tuple:
    """(x, longitudinal shift) [m] of the locus point of one circle (radius, profile slope, axle coordinate)."""
    cpsi, spsi = math.cos(pose.yaw), math.sin(pose.yaw)
    cphi, sphi = math.cos(pose.roll), math.sin(pose.roll)
    rho = math.hypot(cpsi, sphi * spsi)
    c = min(max(-tan_alpha * cphi * spsi / rho, -0.99), 0.99)
    root = math.sqrt(1.0 - c * c)
    st = c * cpsi / rho - root * sphi * spsi / rho
    ct = root * cpsi / rho + c * sphi * spsi / rho
    a, cc = radius * st, radius * ct
    v = axle * cphi - cc * sphi
    return a * cpsi - v * spsi, a * cpsi + cc * sphi * spsi


def hermite_gap(ry, rz, rslope, wy, wz, wslope):
    """The vertical gap g = Z_rail - Z_wheel and its slope at the rail's samples ry (inside wy's range), the wheel
    locus interpolated by cubic Hermite with its slopes."""
    j = wy.searchsorted(ry)
    i = j - 1
    y0, z0, m0 = wy[i], wz[i], wslope[i]
    h = wy[j] - y0
    dz = wz[j] - z0
    m1 = wslope[j]
    t = (ry - y0) / h
    # z = z0 + t h m0 + t^2 (3 dz - h (2 m0 + m1)) + t^3 (h (m0 + m1) - 2 dz)
    c2 = 3.0 * dz - h * (2.0 * m0 + m1)
    c3 = h * (m0 + m1) - 2.0 * dz
    zw = z0 + t * (h * m0 + t * (c2 + t * c3))
    mw = m0 + t * (2.0 * c2 + 3.0 * t * c3) / h
    return rz - zw, rslope - mw


def hermite_minima(ry, g, dg, cand):
    """(y, g) at the minimum of the Hermite cubic of g on [ry[k], ry[k+1]] for each k in cand (g' from - to +)."""
    out_y, out_g = [], []
    for k in cand.tolist():  # a few points
        ya, hh = float(ry[k]), float(ry[k + 1] - ry[k])
        g0, g1, d0, d1 = float(g[k]), float(g[k + 1]), float(dg[k]) * hh, float(dg[k + 1]) * hh
        a_ = 6 * (g0 - g1) + 3 * (d0 + d1)   # g'(u) = a u^2 + b u + c on u in [0, 1]
        b_ = -6 * (g0 - g1) - 4 * d0 - 2 * d1
        c_ = d0
        if abs(a_) <= 1e-12 * (abs(b_) + abs(c_)):
            u = -c_ / b_ if b_ != 0.0 else 0.5
        else:
            disc = math.sqrt(max(b_ * b_ - 4 * a_ * c_, 0.0))
            u = (-b_ - disc) / (2 * a_)
            if 2 * a_ * u + b_ <= 0.0:
                u = (-b_ + disc) / (2 * a_)
        u = min(max(u, 0.0), 1.0)
        out_y.append(ya + u * hh)
        out_g.append(g0 + u * (d0 + u * (b_ / 2 + u * a_ / 3)))
    return out_y, out_g


@dataclass(frozen=True, eq=False)
class GapScan:
    """The vertical gap of one wheel over its rail at a pose, the search's first pass (module docstring): the wheel's
    contact locus at every STRIDE-th wheel sample (right-side frame) and the gap ``g = Z_rail - Z_wheel`` with its
    slope at every STRIDE-th rail sample, over the whole overlap of the profiles.  :func:`contact_from_scan` is the
    second pass, the contact points and patches; :attr:`least_gap` what a rigid wheelset's roll needs of a wheel.

    Attributes
    ----------
    track, wheelset : Track, Wheelset
    pose : Pose
        The pose scanned at (track axes).
    side : str
    frame : Pose
        The pose in the right-side frame (mirrored for the left wheel).
    w_first : int
        The wheel sample of ``wy[0]``.
    wy, wz, wslope : ndarray
        The locus' Y, Z [m] and dZ/dY at the wheel samples ``w_first, w_first + STRIDE, ...`` (increasing Y).
    ry, g, dg : ndarray
        The rail samples' Y [m], the vertical gap [m] and its slope there.
    rail_range : tuple of int
        The rail samples ``[k0, k1)`` the wheel's locus covers.
    """

    track: Track = field(repr=False)
    wheelset: Wheelset = field(repr=False)
    pose: Pose
    side: str
    frame: Pose
    w_first: int
    wy: np.ndarray = field(repr=False)
    wz: np.ndarray = field(repr=False)
    wslope: np.ndarray = field(repr=False)
    ry: np.ndarray = field(repr=False)
    g: np.ndarray = field(repr=False)
    dg: np.ndarray = field(repr=False)
    rail_range: tuple

    @cached_property
    def minima(self) -> tuple[np.ndarray, list, list]:
        """(k, y [m], g [m]) of the gap's local minima: the samples k where its slope turns from - to + and the
        minimum of the Hermite cubic on ``[ry[k], ry[k+1]]``; GeometryError where the least gap lies at an end of
        the searched profiles (or there is no minimum): the contact would run off them."""
        g = self.g
        k_least = int(g.argmin())
        cand = np.flatnonzero((self.dg[:-1] <= 0.0) & (self.dg[1:] > 0.0))
        if k_least in (0, g.size - 1) or cand.size == 0:
            pose, side, rail = self.pose, self.side, self.track.samples
            k0, k1 = self.rail_range
            at_start = k_least == 0
            base = self.frame.lateral_shift + self.wheelset.taping_line
            edge_w = float((self.wy[0] if at_start else self.wy[-1]) - base)
            raise GeometryError(
                f"{side} wheel at lateral_shift = {pose.lateral_shift!r} m, yaw = {pose.yaw!r} rad: the least gap lies "
                f"at the {'flange' if at_start else 'field-side'} end of the searched profiles (wheel y_w = "
                f"{edge_w!r} m, rail y = {float(rail.profile_y[k0 if at_start else k1 - 1])!r} m on its profile): "
                f"the contact would run off the profiles (flange climb, or the wheel off the rail head; the search "
                f"covers surfaces up to {MAX_SURFACE_ANGLE} rad steep)")
        yc, gc = hermite_minima(self.ry, g, self.dg, cand)
        return cand, yc, gc

    def point(self, m: int) -> tuple:
        """The quantities of minimum m's contact point (:func:`point_at`)."""
        _, yc, gc = self.minima
        return point_at(self.track, self.wheelset, self.frame, yc[m], gc[m], self.wy, self.w_first)

    @cached_property
    def deepest(self) -> tuple:
        """The quantities of the deepest contact point (:func:`point_at`; :func:`contact_from_scan`'s first), with
        the search's refusals: GeometryError where the least gap lies at an end of the searched profiles or the
        deepest point on the flange's crest."""
        _, yc, gc = self.minima
        least = min(gc)
        point = self.point(min((m for m in range(len(gc)) if gc[m] == least), key=lambda m: yc[m]))
        check_flange(self.wheelset, self.pose, self.side, point[5])
        return point

    @property
    def least_gap(self) -> float:
        """The least vertical gap [m], the deepest contact point's (:attr:`WheelContact.vertical_gap` of
        :func:`contact_from_scan`, bit for bit), with the search's refusals (:attr:`deepest`)."""
        return self.deepest[0]

    @property
    def roll_slope(self) -> float:
        """d(least vertical gap)/d(roll) [m/rad] at the pose (the track's roll: positive lowers the right wheel).

        The least gap is a minimum over the rail's Y, so its derivative is the gap's at the deepest point's fixed Y
        (the envelope theorem): minus the vertical speed there of the wheel's locus, which a roll rate about the
        wheelset's axis ``e = (cos(psi), sin(psi), 0)`` moves with the material points' velocity ``e x (P - C)``
        (its sliding along the yawed circles is along the locus itself):
        ``dg/droll = -(cos(psi) (Y + m Z) - sin(psi) x)``, ``(x, Y, Z)`` the point from the axle's centre and
        ``m = tan(-delta)`` the locus' slope there, in the wheel's right-side frame (whose roll is minus the track's
        on the left wheel)."""
        g0, y0, z0, delta = self.deepest[:4]
        frame = self.frame
        lateral = y0 - frame.lateral_shift
        vertical = (z0 - g0) - (frame.vertical - self.wheelset.nominal_radius)
        along = math.cos(frame.yaw) * (lateral + math.tan(-delta) * vertical) - math.sin(frame.yaw) * self.deepest[11]
        return -along if self.side == "right" else along


def check_flange(wheelset: Wheelset, pose: Pose, side: str, wheel_lateral: float) -> None:
    """GeometryError where the deepest contact point (at y_w = ``wheel_lateral`` on the wheel) lies on the flange's
    crest (:data:`FLANGE_TIP_MARGIN`)."""
    if wheel_lateral <= wheelset.flange_tip + FLANGE_TIP_MARGIN:
        raise GeometryError(
            f"{side} wheel at lateral_shift = {pose.lateral_shift!r} m, yaw = {pose.yaw!r} rad: its contact lies on "
            f"the flange's crest (wheel y_w = {wheel_lateral!r} m, the crest at {wheelset.flange_tip!r} m): "
            f"the wheel has climbed its flange (derailed)")


def scan_gap(track: Track, wheelset: Wheelset, pose: Pose, side: str = "right") -> GapScan:
    """The vertical gap of the wheel on ``side`` over its rail at ``pose`` (:class:`GapScan`, the search's first
    pass).

    Raises
    ------
    GeometryError
        The wheel and rail profiles do not overlap laterally at the pose.
    """
    sign = side_sign(side)
    frame = pose if sign > 0 else pose.mirrored()
    rail = track.samples
    wsmp = wheelset.samples
    base = frame.lateral_shift + wheelset.taping_line
    margin = 2e-3 + (abs(frame.roll) + abs(frame.yaw)) * 1.2 * wheelset.nominal_radius
    i0 = max(int(wsmp.y.searchsorted(rail.y[0] - base - margin)) - STRIDE, 0)
    i1 = min(int(wsmp.y.searchsorted(rail.y[-1] - base + margin)) + STRIDE, wsmp.y.size)
    i0 -= i0 % STRIDE
    wy, wz, wslope, wok = wheel_locus(wheelset, frame, slice(i0 // STRIDE, -(-i1 // STRIDE)), True)
    valid = wy[1:] > wy[:-1]
    if wok is not None:
        valid &= wok[:-1] & wok[1:]
    lo, hi = (0, wy.size - 1) if valid.all() else longest_run(valid)
    hi += 1
    if hi - lo < 4:
        raise GeometryError(f"{side} wheel: the wheel profile does not reach over the rail at lateral_shift = "
                            f"{pose.lateral_shift!r} m (the rail spans track y {float(rail.y[0])!r} to "
                            f"{float(rail.y[-1])!r} m)")
    wy, wz, wslope = wy[lo:hi], wz[lo:hi], wslope[lo:hi]
    w_first = i0 + lo * STRIDE  # the wheel sample of wy[0]
    k0 = int(rail.y.searchsorted(wy[0], side="right"))
    k1 = int(rail.y.searchsorted(wy[-1], side="left"))
    k0 += (-k0) % STRIDE
    if k1 - k0 < 4 * STRIDE:
        raise GeometryError(f"{side} wheel and rail do not overlap at lateral_shift = {pose.lateral_shift!r} m: the "
                            f"wheel spans track y {float(wy[0])!r} to {float(wy[-1])!r} m, the rail "
                            f"{float(rail.y[0])!r} to {float(rail.y[-1])!r} m")
    rsl = slice(k0 // STRIDE, -(-k1 // STRIDE))
    ry = rail.coarse[0][rsl]
    g, dg = hermite_gap(ry, rail.coarse[1][rsl], rail.coarse[2][rsl], wy, wz, wslope)
    return GapScan(track, wheelset, pose, side, frame, w_first, wy, wz, wslope, ry, g, dg, (k0, k1))


def search_wheel(track: Track, wheelset: Wheelset, pose: Pose, side: str = "right",
                 depth: float = DEFAULT_DEPTH) -> WheelContact:
    """The contact points and patches of one wheel on its rail (module docstring).

    Parameters
    ----------
    track, wheelset : Track, Wheelset
    pose : Pose
        The wheelset's pose in track axes.
    side : {"right", "left"}
    depth : float
        The largest elastic approach [m] prepared for (:data:`DEFAULT_DEPTH`).

    Returns
    -------
    WheelContact
        Contact points (the deepest first; at least one, the least gap, also when the wheel is lifted off) and
        patches; its ``scan`` the gap over the profiles they were found from (:class:`GapScan`).

    Raises
    ------
    GeometryError
        The wheel and rail profiles do not overlap laterally at the pose, or the least gap lies at the end of either
        profile's searched part (a flange climbing beyond the profile's end, a wheel off the rail's edge), or the
        deepest point lies on the flange's crest (:data:`FLANGE_TIP_MARGIN`: the wheel has climbed its flange): the
        message names the lateral shift and the limit.
    """
    return contact_from_scan(scan_gap(track, wheelset, pose, side), depth)


def contact_from_scan(scan: GapScan, depth: float = DEFAULT_DEPTH) -> WheelContact:
    """The contact points and patches of a wheel from its :class:`GapScan` (:func:`search_wheel`'s second pass,
    module docstring), with the search's refusals."""
    track, wheelset, pose, side, frame = scan.track, scan.wheelset, scan.pose, scan.side, scan.frame
    sign = side_sign(side)
    wy, w_first, ry, g = scan.wy, scan.w_first, scan.ry, scan.g
    n = g.size
    cand, yc, gc = scan.minima
    cand = cand.tolist()
    # separation criterion (module docstring)
    order = sorted(range(len(gc)), key=lambda m: gc[m])
    least = gc[order[0]]
    keep = [order[0]]
    for m in order[1:]:
        if gc[m] > least + depth:
            break
        if all(float(g[min(cand[m], cand[q]):max(cand[m], cand[q]) + 2].max()) - gc[m] >= MIN_RISE
               for q in keep):
            keep.append(m)
    keep.sort(key=lambda m: yc[m])
    pts = [point_at(track, wheelset, frame, yc[m], gc[m], wy, w_first) for m in keep]
    # patches: neighbours whose regions at the approach depth merge
    groups = [[0]]
    for i in range(1, len(keep)):
        hill = float(g[cand[keep[i - 1]]:cand[keep[i]] + 2].max())
        if hill < min(pts[i - 1][0], pts[i][0]) + depth:
            groups[-1].append(i)
        else:
            groups.append([i])
    rank = sorted(range(len(pts)), key=lambda i: (pts[i][0], pts[i][1]))
    new_index = {old: new for new, old in enumerate(rank)}
    points = tuple(make_point(pts[i], sign, side) for i in rank)
    check_flange(wheelset, pose, side, points[0].wheel_lateral)
    patches = []
    for grp in groups:
        main = min(grp, key=lambda i: (pts[i][0], i))
        level = pts[main][0] + depth
        below = np.nonzero(g >= level)[0]
        k_lo, k_hi = cand[keep[grp[0]]], cand[keep[grp[-1]]] + 1
        left = below[below < k_lo]
        right = below[below > k_hi]
        k_lo = int(left[-1]) if left.size else 0
        k_hi = int(right[0]) if right.size else n - 1
        members = (new_index[main],) + tuple(new_index[i] for i in grp if i != main)
        patches.append(Patch(members, pts[main][3], PatchRegion(track, wheelset, frame, sign,
                                                                 (float(ry[k_lo]), float(ry[k_hi])), pts[main])))
    patches.sort(key=lambda p: p.points[0])
    return WheelContact(side, points, tuple(patches), pose, scan)


def point_at(track, wheelset, frame, y0, g0, wy, w_first):
    """The contact point's quantities at track y0 (right-side frame) with vertical gap g0: the wheel's interpolated
    linearly on all its samples at the locus' fractional sample, the rail's (Hermite for its height) on all its
    samples."""
    rail = track.samples
    wsmp = wheelset.samples
    k = min(max(int(wy.searchsorted(y0)), 1), wy.size - 1)
    ft = (y0 - float(wy[k - 1])) / float(wy[k] - wy[k - 1])
    jf = w_first + (k - 1 + ft) * STRIDE
    j = min(int(jf), wsmp.y.size - 2)
    t = jf - j

    def on_wheel(arr):
        return float(arr[j]) * (1.0 - t) + float(arr[j + 1]) * t

    i = min(max(int(rail.y.searchsorted(y0)), 1), rail.y.size - 1)
    ya, h = float(rail.y[i - 1]), float(rail.y[i] - rail.y[i - 1])
    u = (y0 - ya) / h

    def on_rail(arr):
        return float(arr[i - 1]) * (1.0 - u) + float(arr[i]) * u

    za, dz, m0, m1 = float(rail.z[i - 1]), float(rail.z[i] - rail.z[i - 1]), float(rail.slope[i - 1]), \
        float(rail.slope[i])
    zr = za + u * (h * m0 + u * ((3.0 * dz - h * (2.0 * m0 + m1)) + u * (h * (m0 + m1) - 2.0 * dz)))
    r = on_wheel(wsmp.radius)
    x, shift = locus_point(wheelset, frame, r, on_wheel(wsmp.tan), on_wheel(wsmp.axle))
    return (g0, y0, zr, -on_rail(rail.angle), on_rail(rail.profile_y), on_wheel(wsmp.y), r,
            on_wheel(wsmp.cos) / r, -on_wheel(wsmp.curvature), on_rail(rail.curvature), shift, x)


def make_point(p, sign, side) -> ContactPoint:
    g0, y0, zr, delta, yr, yw, r, krol, kw, kr, shift, x = p
    return ContactPoint(rail_lateral=yr, wheel_lateral=yw, contact_angle=delta, rolling_radius=r,
                        gap=g0 * math.cos(delta), vertical_gap=g0, longitudinal_shift=shift,
                        wheel_lateral_curvature=kw, wheel_rolling_curvature=krol, rail_lateral_curvature=kr,
                        position=(x, sign * y0, zr), side=side)


@dataclass(frozen=True, eq=False)
class PatchRegion:
    """What a patch's gap is computed from (a pure function of these; computed when first asked for)."""

    track: Track
    wheelset: Wheelset
    frame: Pose
    sign: float
    region: tuple
    point: tuple

    def gap(self) -> PatchGap:
        return patch_gap(self)


def longest_run(mask: np.ndarray) -> tuple[int, int]:
    """[lo, hi) of the longest run of True in mask."""
    padded = np.concatenate(([False], mask, [False])).astype(np.int8)
    edges = np.diff(padded)
    starts, ends = np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0]
    if starts.size == 0:
        return 0, 0
    k = int(np.argmax(ends - starts))
    return int(starts[k]), int(ends[k])


def patch_gap(pr: PatchRegion) -> PatchGap:
    """The undeformed gap in the tangent plane at the patch's deepest point (right-side frame), over its region
    widened by PATCH_MARGIN; s mirrored to increase with the track's y on a left wheel.  The wheel's locus is first
    lowered by the point's vertical gap, so that it touches the rail at the point: a pose that interpenetrates (or
    stands off) moves the wheel along z, which in a tilted tangent plane has an s component as well as an n one."""
    rail = pr.track.samples
    wsmp = pr.wheelset.samples
    g0, y0, z0, delta = pr.point[:4]  # g0: the point's vertical gap
    cd, sd = math.cos(delta), math.sin(delta)
    y_lo, y_hi = pr.region
    pad = max(PATCH_MARGIN * (y_hi - y_lo), 4 * PATCH_STEP)
    k_a = max(int(np.searchsorted(rail.y, y_lo - pad)) - 1, 0)
    k_b = min(int(np.searchsorted(rail.y, y_hi + pad)) + 1, rail.y.size)
    base = pr.frame.lateral_shift + pr.wheelset.taping_line
    margin = 1e-3 + (abs(pr.frame.roll) + abs(pr.frame.yaw)) * 1.2 * pr.wheelset.nominal_radius
    j_a = max(int(np.searchsorted(wsmp.y, rail.y[k_a] - base - margin)) - 1, 0)
    j_b = min(int(np.searchsorted(wsmp.y, rail.y[k_b - 1] - base + margin)) + 1, wsmp.y.size)
    wy, wz, _, ok = wheel_locus(pr.wheelset, pr.frame, slice(j_a, j_b))
    wz = wz + g0  # the wheel lowered by its vertical gap g0 to touch: the gap is the shape, not the pose's offset
    ry, rz = rail.y[k_a:k_b], rail.z[k_a:k_b]
    rs = (ry - y0) * cd - (rz - z0) * sd
    rn = (ry - y0) * sd + (rz - z0) * cd
    ws = (wy - y0) * cd - (wz - z0) * sd
    wn = (wy - y0) * sd + (wz - z0) * cd
    # the parts where both curves are graphs over s, around the point
    rl, rh = run_around(np.concatenate(([True], np.diff(rs) > 0.0)), int(np.argmin(np.abs(rs))))
    wmono = ws[1:] > ws[:-1]
    if ok is not None:
        wmono &= ok[1:]
    wl, wh = run_around(np.concatenate(([True], wmono)), int(np.argmin(np.abs(ws))))
    s_lo = max(float(rs[rl]), float(ws[wl]))
    s_hi = min(float(rs[rh - 1]), float(ws[wh - 1]))
    s = np.arange(math.ceil(s_lo / PATCH_STEP - 1e-9), math.floor(s_hi / PATCH_STEP + 1e-9) + 1) * PATCH_STEP
    h = np.interp(s, rs[rl:rh], rn[rl:rh]) - np.interp(s, ws[wl:wh], wn[wl:wh])
    lateral_gap = np.maximum(h, 0.0)
    lateral_gap[s == 0.0] = 0.0
    wsl = slice(j_a + wl, j_a + wh)
    a = np.interp(s, ws[wl:wh], wsmp.cos[wsl] / (2.0 * wsmp.radius[wsl]))
    if pr.sign < 0:
        s, lateral_gap, a = -s[::-1], lateral_gap[::-1], a[::-1]
    return PatchGap(s + 0.0, lateral_gap, a)


def run_around(mask: np.ndarray, k: int) -> tuple[int, int]:
    """[lo, hi) of the run around k where mask[i] (sample i continues from i - 1) holds."""
    breaks = np.nonzero(~mask)[0]
    before = breaks[breaks <= k]
    after = breaks[breaks > k]
    lo = int(before[-1]) if before.size else 0
    hi = int(after[0]) if after.size else mask.size
    return lo, hi


# ------------------------------------------------------------------------------------------------ kinematics
def creepages(wheelset: Wheelset, pose: Pose, velocities: Velocities, point: ContactPoint) -> Creepages:
    """Kalker's creepages at a contact point from the wheelset's motion.

    The wheel's material point at the contact P (the wheel's surface point above the rail's contact point, the
    vertical gap above it) moves relative to the (resting) rail with ``v = v_C + Omega x
    (P - C)``: C the axle's centre moving with ``v_C = (V, dy/dt, dz/dt)``, ``Omega = omega e_a + dpsi/dt e_z +
    dphi/dt e_x`` with the axle's direction ``e_a = R_z(psi) R_x(phi) e_y`` and the pitch rate omega (negative
    forwards).  In the contact frame, right wheel ``n = (0, sin(delta), cos(delta))``, left wheel
    ``n = (0, -sin(delta), cos(delta))``, ``s = n x e_x`` (increasing with the track's y):

        xi = v . e_x / V,   eta = v . s / V,   phi = Omega . n / V

    (Kalker, *Three-Dimensional Elastic Bodies in Rolling Contact*, 1990, ch. 1; the wheelset kinematics of the
    CONTACT user guide, Vollebregt, section "Wheel-rail contact": the rigid slip of the wheel relative to the rail
    over V).  To first order on the right wheel: ``xi = 1 - r/r0 - (dpsi/dt) Y/V``, ``eta = (dy/dt / V - psi) /
    cos(delta)`` (the lead of the yawed contact point gives the 1/cos), ``phi = -sin(delta)/r0 + cos(delta)
    (dpsi/dt)/V``.

    Parameters
    ----------
    wheelset : Wheelset
    pose : Pose
        The pose the point was found at.
    velocities : Velocities
    point : ContactPoint

    Returns
    -------
    Creepages
        xi, eta [1], phi [1/m].
    """
    V = velocities.forward_speed
    omega = -V / wheelset.nominal_radius if velocities.pitch_rate is None else velocities.pitch_rate
    cpsi, spsi = math.cos(pose.yaw), math.sin(pose.yaw)
    cphi, sphi = math.cos(pose.roll), math.sin(pose.roll)
    ea = (-spsi * cphi, cpsi * cphi, sphi)
    Om = (omega * ea[0] + velocities.roll_rate, omega * ea[1], omega * ea[2] + velocities.yaw_rate)
    px, py, pz = point.position
    # the wheel's material point: the locus point above the rail's, by the vertical gap
    d = (px, py - pose.lateral_shift, pz - point.vertical_gap - (pose.vertical - wheelset.nominal_radius))
    vx = V + Om[1] * d[2] - Om[2] * d[1]
    vy = velocities.lateral_velocity + Om[2] * d[0] - Om[0] * d[2]
    vz = velocities.vertical_velocity + Om[0] * d[1] - Om[1] * d[0]
    sd, cd = math.sin(point.contact_angle), math.cos(point.contact_angle)
    sign = side_sign(point.side)
    n = (0.0, sign * sd, cd)
    s = (0.0, cd, -sign * sd)
    return Creepages(vx / V, (vy * s[1] + vz * s[2]) / V, (Om[1] * n[1] + Om[2] * n[2]) / V)


__all__ += ["GeometryError", "Track", "Wheelset"]
