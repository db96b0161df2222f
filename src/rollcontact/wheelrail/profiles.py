"""Wheel and rail profiles: the curve of a profile in its own axes, its smoothing spline, and the readers of the
file formats in use (docs/physics.md, Wheel/rail geometry: profiles).

A profile is a plane curve (y, z) in metres in the profile's own axes: y lateral, z downward (the track's axes,
x along the track).  The files describe the RIGHT wheel and rail: the rail's gauge side at negative y, its top near
z = 0; the wheel's flange at negative y (its flange tip at z > 0, away from the axle), its taping line at y = 0.

The curve is represented by a parametric smoothing spline ``y(s), z(s)`` in the arc length s of the points (so the
near-vertical flanks of a rail head are represented as well as its crown).  Each coordinate minimises

    sum_i w_i (q_i - q(s_i))^2 + lambda int q''(s)^2 ds,     w_i = the points' share of arc length,

whose transfer function for a wave of wavelength L along the profile is ``1 / (1 + lambda (2 pi / L)^4)``: the
smoothing is stated as the wavelength ``L_c`` it halves, ``lambda = (L_c / (2 pi))^4`` (Reinsch, "Smoothing by spline
functions", Numer. Math. 10, 1967; the smoothing splines of CONTACT's and SIMPACK's profile input).  Measured
profiles carry noise of a few micrometres at wavelengths of a few point spacings, whose curvature ``a (2 pi / L)^2``
would swamp the profile's own; :data:`DEFAULT_SMOOTHING` removes it while moving the design arcs of the shared
profiles by micrometres (``tests/wheelrail/test_profiles.py`` checks the effect on rolling radii).

The profile is sampled once, uniformly in arc length (:attr:`Profile.samples`), for the contact search.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.interpolate import BSpline, make_interp_spline, make_smoothing_spline

__all__ = ["DEFAULT_SMOOTHING", "DEFAULT_SAMPLE_STEP", "Profile", "ProfileError", "ProfileSamples", "read_profile",
           "read_simpack", "read_miniprof", "read_text_profile"]

DEFAULT_SMOOTHING = 2.0e-3
"""L_c [m]: the wavelength along the profile that the default smoothing spline halves (module docstring).  White
noise of 1 um on points 0.2 mm apart (a Miniprof measurement) leaves a curvature noise of a few 1/m (enough for a
13 mm gauge corner, 77 1/m; a 300 mm crown, 3.3 1/m, needs a longer L_c), and the shared design profiles' contact
radii move by micrometres (``tests/wheelrail/test_profiles.py``)."""

DEFAULT_SAMPLE_STEP = 1.0e-4
"""Arc-length step [m] of the profile's samples that the contact search interpolates (Hermite, with the slopes)."""

MIN_POINTS = 5
"""Fewest points a profile may have (a cubic smoothing spline needs more than 4)."""

GAP_FACTOR = 10.0
"""A spacing of consecutive points above GAP_FACTOR times their median spacing is reported as a gap in the data."""


class ProfileError(ValueError):
    """A profile that cannot be read or used: the message names the file, the line and the value at fault."""


@dataclass(frozen=True)
class ProfileSamples:
    """The profile sampled uniformly in arc length (SI units, the profile's own axes).

    Attributes
    ----------
    s : ndarray
        Arc length [m] from the first point.
    y, z : ndarray
        The smoothed curve [m], y strictly increasing.
    slope : ndarray
        dz/dy [1].
    angle : ndarray
        atan(dz/dy) [rad], the angle of the tangent from the y axis (towards +z).
    curvature : ndarray
        d(angle)/ds [1/m] = z''/(1 + z'^2)^(3/2): positive where the curve bends towards +z (a convex rail head, a
        concave wheel tread).
    """

    s: np.ndarray
    y: np.ndarray
    z: np.ndarray
    slope: np.ndarray
    angle: np.ndarray
    curvature: np.ndarray


@dataclass(frozen=True, eq=False)
class Profile:
    """A wheel or rail profile: its points and their smoothing spline (module docstring).

    Parameters
    ----------
    y, z : array_like
        The points [m] in the profile's own axes (y lateral, z downward), in order along the profile (either
        direction: they are stored with y increasing).  y must be strictly monotone.
    smoothing : float
        L_c [m] >= 0, the wavelength the smoothing spline halves (0: the interpolating cubic spline).
    kind : str
        ``"rail"``, ``"wheel"`` or ``""`` (unknown).
    source : str
        Where the points come from (a file name), for messages.
    weights : array_like, optional
        Relative weights of the points (the SIMPACK files' third column), default 1.
    lines : array_like of int, optional
        The file's line number of each point, for messages.
    sample_step : float
        Arc-length step [m] of :attr:`samples`.

    Raises
    ------
    ProfileError
        Fewer than :data:`MIN_POINTS` points, a non-finite value, y not strictly monotone (unsorted points, a
        duplicated point, a profile folding back), a gap in the points, or a smoothing that folds the curve back.
    """

    y: np.ndarray
    z: np.ndarray
    smoothing: float = DEFAULT_SMOOTHING
    kind: str = ""
    source: str = "<points>"
    weights: np.ndarray | None = None
    lines: np.ndarray | None = None
    sample_step: float = DEFAULT_SAMPLE_STEP
    _spline: tuple = field(init=False, repr=False)
    _samples: ProfileSamples = field(init=False, repr=False)

    def __post_init__(self):
        y = np.asarray(self.y, dtype=float).ravel()
        z = np.asarray(self.z, dtype=float).ravel()
        if y.shape != z.shape:
            raise ProfileError(f"{self.source}: y has {y.size} values, z {z.size}: they must pair up")
        lines = (np.arange(1, y.size + 1) if self.lines is None else np.asarray(self.lines, dtype=int).ravel())
        weights = np.ones_like(y) if self.weights is None else np.asarray(self.weights, dtype=float).ravel()
        if y.size < MIN_POINTS:
            raise ProfileError(f"{self.source}: {y.size} points, a profile needs at least {MIN_POINTS}")
        bad = ~(np.isfinite(y) & np.isfinite(z) & np.isfinite(weights))
        if bad.any():
            k = int(np.argmax(bad))
            raise ProfileError(f"{self.source}, line {lines[k]}: the point ({y[k]!r}, {z[k]!r}) is not finite")
        if np.any(weights <= 0.0):
            k = int(np.argmax(weights <= 0.0))
            raise ProfileError(f"{self.source}, line {lines[k]}: weight {weights[k]!r} must be > 0")
        smoothing = float(self.smoothing)
        if not (math.isfinite(smoothing) and smoothing >= 0.0):
            raise ProfileError(f"{self.source}: smoothing = {smoothing!r} m must be finite and >= 0")
        step = float(self.sample_step)
        if not (math.isfinite(step) and step > 0.0):
            raise ProfileError(f"{self.source}: sample_step = {step!r} m must be finite and > 0")
        check_order(y, z, lines, self.source)
        if y[-1] < y[0]:
            y, z, weights, lines = y[::-1].copy(), z[::-1].copy(), weights[::-1].copy(), lines[::-1].copy()
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "z", z)
        object.__setattr__(self, "weights", weights)
        object.__setattr__(self, "lines", lines)
        object.__setattr__(self, "smoothing", smoothing)
        object.__setattr__(self, "sample_step", step)
        spline = fit_spline(y, z, weights, smoothing)
        object.__setattr__(self, "_spline", spline)
        object.__setattr__(self, "_samples", sample_spline(spline, step, self.source))

    def __repr__(self) -> str:
        lo, hi = self.lateral_extent
        return (f"Profile({self.source!r}, kind={self.kind!r}, {self.y.size} points, y {lo:.6g} to {hi:.6g} m, "
                f"smoothing={self.smoothing!r} m)")

    # -------------------------------------------------------------------------------------------- evaluation
    @property
    def samples(self) -> ProfileSamples:
        """The profile sampled every :attr:`sample_step` of arc length (precomputed)."""
        return self._samples

    @property
    def lateral_extent(self) -> tuple[float, float]:
        """(y_min, y_max) [m] of the smoothed profile."""
        return float(self._samples.y[0]), float(self._samples.y[-1])

    @property
    def length(self) -> float:
        """Arc length [m] of the profile."""
        return float(self._spline[0].t[-1] - self._spline[0].t[0])

    def arc_length(self, y) -> np.ndarray:
        """s(y) [m]: the arc length at lateral position y [m] (Newton on the spline from the samples)."""
        yq = self._in_extent(y)
        smp = self._samples
        s = np.interp(yq, smp.y, smp.s)
        ys, dys = self._spline[0], self._spline[2]
        for _ in range(3):
            s = s - (ys(s) - yq) / dys(s)
        return s

    def z_at(self, y) -> np.ndarray:
        """z(y) [m] on the smoothed profile."""
        return self._spline[1](self.arc_length(y))

    def slope(self, y) -> np.ndarray:
        """dz/dy [1] at y [m]."""
        s = self.arc_length(y)
        return self._spline[3](s) / self._spline[2](s)

    def normal_angle(self, y) -> np.ndarray:
        """atan(dz/dy) [rad] at y [m]: the angle of the surface normal from the z axis, positive where z grows with
        y (the normal ``(-sin, cos)`` in (y, z) turned from +z towards -y)."""
        s = self.arc_length(y)
        return np.arctan2(self._spline[3](s), self._spline[2](s))

    def curvature(self, y) -> np.ndarray:
        """Curvature [1/m] at y [m], ``z''/(1 + z'^2)^(3/2)``: positive where the curve bends towards +z (a convex
        rail head; a concave region of a wheel)."""
        s = self.arc_length(y)
        d1y, d1z, d2y, d2z = (self._spline[2](s), self._spline[3](s), self._spline[4](s), self._spline[5](s))
        return (d1y * d2z - d1z * d2y) / (d1y * d1y + d1z * d1z) ** 1.5

    def _in_extent(self, y) -> np.ndarray:
        yq = np.asarray(y, dtype=float)
        lo, hi = self.lateral_extent
        if np.any(~np.isfinite(yq)) or np.any((yq < lo) | (yq > hi)):
            bad = yq[~((yq >= lo) & (yq <= hi))].ravel()[0]
            raise ProfileError(f"{self.source}: y = {bad!r} m is outside the profile's extent [{lo!r}, {hi!r}] m")
        return yq

    def mirrored(self) -> Profile:
        """The mirror image ``(-y, z)`` (the other side's profile in its own axes)."""
        return Profile(-self.y, self.z, self.smoothing, self.kind, self.source, self.weights, self.lines,
                       self.sample_step)

    def with_smoothing(self, smoothing: float) -> Profile:
        """The same points with another smoothing wavelength L_c [m]."""
        return Profile(self.y, self.z, smoothing, self.kind, self.source, self.weights, self.lines, self.sample_step)


# ------------------------------------------------------------------------------------------------ the spline
def check_order(y: np.ndarray, z: np.ndarray, lines: np.ndarray, source: str) -> None:
    """Raise ProfileError unless y is strictly monotone along the points without gaps (the message names the line)."""
    dy = np.diff(y)
    ds = np.hypot(dy, np.diff(z))
    same = ds == 0.0
    if same.any():
        k = int(np.argmax(same))
        raise ProfileError(f"{source}, line {lines[k + 1]}: the point ({y[k + 1]!r}, {z[k + 1]!r}) duplicates the "
                           f"one of line {lines[k]}")
    direction = 1.0 if y[-1] > y[0] else -1.0
    back = direction * dy <= 0.0
    if back.any():
        k = int(np.argmax(back))
        raise ProfileError(f"{source}, line {lines[k + 1]}: y = {y[k + 1]!r} after y = {y[k]!r} (line {lines[k]}) "
                           f"goes {'back' if dy[k] else 'nowhere'}: y must be strictly "
                           f"{'increasing' if direction > 0 else 'decreasing'} along the profile (the points are "
                           "unsorted, or the profile folds back)")
    median = float(np.median(ds))
    wide = ds > GAP_FACTOR * median
    if wide.any():
        k = int(np.argmax(wide))
        raise ProfileError(f"{source}, lines {lines[k]}-{lines[k + 1]}: a gap of {ds[k]!r} m between consecutive "
                           f"points, more than {GAP_FACTOR:g} times their median spacing {median!r} m")


def fit_spline(y: np.ndarray, z: np.ndarray, weights: np.ndarray, smoothing: float) -> tuple:
    """The parametric spline (y(s), z(s)) through or near the points and its derivatives (module docstring)."""
    chord = np.hypot(np.diff(y), np.diff(z))
    s = np.concatenate(([0.0], np.cumsum(chord)))
    if smoothing > 0.0:
        share = 0.5 * (np.concatenate(([0.0], chord)) + np.concatenate((chord, [0.0])))  # each point's arc length
        w = share * weights / np.mean(weights)
        lam = (smoothing / (2.0 * math.pi)) ** 4
        ys = make_smoothing_spline(s, y, w=w, lam=lam)
        zs = make_smoothing_spline(s, z, w=w, lam=lam)
    else:
        ys = make_interp_spline(s, y, k=3)
        zs = make_interp_spline(s, z, k=3)
    ys = BSpline(ys.t, ys.c, ys.k, extrapolate=False)
    zs = BSpline(zs.t, zs.c, zs.k, extrapolate=False)
    return ys, zs, ys.derivative(1), zs.derivative(1), ys.derivative(2), zs.derivative(2)


def sample_spline(spline: tuple, step: float, source: str) -> ProfileSamples:
    """The spline sampled at about ``step`` of arc length (its parameter, the chord length of the points)."""
    ys, zs, d1y, d1z, d2y, d2z = spline
    s0, s1 = float(ys.t[0]), float(ys.t[-1])
    n = max(int(math.ceil((s1 - s0) / step)), 8) + 1
    s = np.linspace(s0, s1, n)
    y, z, a, b, c, d = ys(s), zs(s), d1y(s), d1z(s), d2y(s), d2z(s)
    if np.any(a <= 0.0):
        k = int(np.argmax(a <= 0.0))
        raise ProfileError(f"{source}: the smoothed profile folds back near y = {y[k]!r} m (dy/ds = {a[k]!r}): "
                           "y must increase along the profile (reduce the smoothing or mend the points there)")
    speed2 = a * a + b * b
    return ProfileSamples(s=s - s0, y=y, z=z, slope=b / a, angle=np.arctan2(b, a),
                          curvature=(a * d - b * c) / speed2**1.5)


# ---------------------------------------------------------------------------------------------------- readers
NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"
ROW = re.compile(rf"^\s*\"?\s*({NUMBER})[\s,;]+({NUMBER})(?:[\s,;]+({NUMBER}))?\s*$")


def parse_number(text: str, source: str, line: int, what: str) -> float:
    try:
        return float(text.strip().strip("'\"").replace("D", "e").replace("d", "e"))
    except ValueError:
        raise ProfileError(f"{source}, line {line}: {what} = {text.strip()!r} is not a number") from None


def read_lines(path) -> tuple[str, list[str]]:
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise ProfileError(f"{p}: cannot read the profile ({exc.strerror or exc})") from None
    return p.name, text.splitlines()


def read_simpack(path, smoothing: float | None = None, sample_step: float = DEFAULT_SAMPLE_STEP) -> Profile:
    """Read a SIMPACK profile, ``.prw`` (wheel) or ``.prr`` (rail).

    The file: ``!`` starts a comment (to the end of the line; a point commented out is skipped);
    ``header.begin ... header.end`` with ``type`` (0 rail, 1 wheel); ``spline.begin ... spline.end`` with the options
    below and the block ``point.begin ... point.end`` of rows ``y z [weight]``.  The options are applied in the
    order the format numbers them: (1) ``point.dist.min``: a point closer than this to the previous kept one is
    dropped; (2) ``shift.y``, ``shift.z``: added; (3) ``rotate``: the points turned by this angle about x (from y
    towards z); (4) ``bound.y.min/max``, ``bound.z.min/max``: points outside dropped (a bound pair with min > max
    is no bound); (5) ``mirror.y``, ``mirror.z``: the coordinate's sign changed; (6) ``inversion``: the order of
    the points reversed; lengths are in the file's unit, ``units.len.f`` per metre (1000: millimetres), angles
    ``units.ang.f`` per radian.  ``approx.smooth`` > 0 asks for a smoothing spline: the smoothing is then
    ``smoothing`` if given, else :data:`DEFAULT_SMOOTHING` (SIMPACK's own scale of approx.smooth is not this
    module's wavelength); with approx.smooth = 0 the default smoothing applies too unless ``smoothing`` is given.

    Parameters
    ----------
    path : str or Path
        The file.
    smoothing : float, optional
        L_c [m] of the spline (default :data:`DEFAULT_SMOOTHING`).
    sample_step : float
        Arc-length step [m] of the profile's samples.

    Returns
    -------
    Profile
        In metres, in the profile's own axes after the options, ``kind`` from the header's type.

    Raises
    ------
    ProfileError
        An unparseable line, an unknown option value, a missing point block, too few points, points out of order
        or with a gap: the message names the file and the line.
    """
    source, lines = read_lines(path)
    header: dict[str, tuple[str, int]] = {}
    options: dict[str, tuple[str, int]] = {}
    rows: list[tuple[float, float, float, int]] = []
    section = None
    seen_points = False
    for number, raw in enumerate(lines, start=1):
        text = raw.split("!", 1)[0].strip()
        if not text:
            continue
        low = text.lower()
        if low in ("header.begin", "spline.begin", "point.begin"):
            section = low.split(".")[0]
            seen_points = seen_points or section == "point"
            continue
        if low in ("header.end", "spline.end", "point.end"):
            section = "spline" if low == "point.end" else None
            continue
        if section == "point":
            parts = text.replace(",", " ").split()
            if len(parts) not in (2, 3):
                raise ProfileError(f"{source}, line {number}: {text!r} is not a point 'y z [weight]'")
            y = parse_number(parts[0], source, number, "y")
            z = parse_number(parts[1], source, number, "z")
            w = parse_number(parts[2], source, number, "weight") if len(parts) == 3 else 1.0
            rows.append((y, z, w, number))
            continue
        if "=" in text and section in ("header", "spline"):
            key, value = (part.strip() for part in text.split("=", 1))
            (header if section == "header" else options)[key.lower()] = (value, number)
            continue
        raise ProfileError(f"{source}, line {number}: cannot read {text!r}"
                           + (" outside the header and spline blocks" if section is None else ""))
    if not seen_points:
        raise ProfileError(f"{source}: no point block (point.begin ... point.end) in the file")
    if section == "point":
        raise ProfileError(f"{source}: the point block is not closed (point.end missing)")

    def option(key: str, default: float) -> float:
        if key not in options:
            return default
        value, number = options[key]
        return parse_number(value, source, number, key)

    length_factor = option("units.len.f", 1.0)
    angle_factor = option("units.ang.f", 1.0)
    for key, f in (("units.len.f", length_factor), ("units.ang.f", angle_factor)):
        if not (math.isfinite(f) and f > 0.0):
            raise ProfileError(f"{source}, line {options[key][1]}: {key} = {f!r} must be > 0 (units per metre or "
                               "per radian)")
    kind = ""
    if "type" in header:
        value, number = header["type"]
        code = parse_number(value, source, number, "type")
        if code not in (0.0, 1.0):
            raise ProfileError(f"{source}, line {number}: type = {value} must be 0 (rail) or 1 (wheel)")
        kind = "rail" if code == 0.0 else "wheel"
    if len(rows) < MIN_POINTS:
        raise ProfileError(f"{source}: {len(rows)} points in the point block, a profile needs at least {MIN_POINTS}")
    data = np.array(rows, dtype=float)
    y, z, w, line_no = data[:, 0], data[:, 1], data[:, 2], data[:, 3].astype(int)
    dist_min = option("point.dist.min", 0.0)
    if dist_min > 0.0:
        keep = [0]
        for k in range(1, y.size):  # reading only, not the hot path
            if math.hypot(y[k] - y[keep[-1]], z[k] - z[keep[-1]]) >= dist_min:
                keep.append(k)
        y, z, w, line_no = y[keep], z[keep], w[keep], line_no[keep]
    y = y + option("shift.y", 0.0)
    z = z + option("shift.z", 0.0)
    angle = option("rotate", 0.0) / angle_factor
    if angle != 0.0:
        c, s = math.cos(angle), math.sin(angle)
        y, z = c * y - s * z, s * y + c * z
    keep = np.ones(y.shape, dtype=bool)
    for axis, values in (("y", y), ("z", z)):
        lo, hi = option(f"bound.{axis}.min", 1.0), option(f"bound.{axis}.max", 0.0)
        if lo <= hi:
            keep &= (values >= lo) & (values <= hi)
    y, z, w, line_no = y[keep], z[keep], w[keep], line_no[keep]
    for key in ("mirror.y", "mirror.z", "inversion"):
        if key in options and option(key, 0.0) not in (0.0, 1.0):
            raise ProfileError(f"{source}, line {options[key][1]}: {key} = {options[key][0]} must be 0 or 1")
    if option("mirror.y", 0.0) == 1.0:
        y = -y
    if option("mirror.z", 0.0) == 1.0:
        z = -z
    if option("inversion", 0.0) == 1.0:
        y, z, w, line_no = y[::-1], z[::-1], w[::-1], line_no[::-1]
    if y.size < MIN_POINTS:
        raise ProfileError(f"{source}: {y.size} points left within the bounds, a profile needs at least {MIN_POINTS}")
    return Profile(y / length_factor, z / length_factor, DEFAULT_SMOOTHING if smoothing is None else smoothing,
                   kind, source, w, line_no, sample_step)


def read_miniprof(path, smoothing: float | None = None, sample_step: float = DEFAULT_SAMPLE_STEP) -> Profile:
    """Read a Miniprof profile, ``.ban`` (rail) or ``.whl`` (wheel).

    The file: a header of ``Key=Value`` lines (``XYPoints=`` the number of points, ``ColumnDef=X,Y``, reference
    points ...), then rows ``X Y`` in millimetres, some prefixed by ``"``.  X runs the other way from the SIMPACK
    files' y: the profile is ``y = -X``, ``z = Y`` (the shared UIC60 ``.ban`` and ``.prr`` give the same rail).

    Raises
    ------
    ProfileError
        An unparseable row, a point count other than ``XYPoints``, a ColumnDef other than X,Y, too few points,
        points out of order or with a gap: the message names the file and the line.
    """
    source, lines = read_lines(path)
    header: dict[str, tuple[str, int]] = {}
    rows: list[tuple[float, float, int]] = []
    for number, raw in enumerate(lines, start=1):
        text = raw.strip()
        if not text:
            continue
        m = ROW.match(text)
        if m and not rows and "=" in text:
            m = None
        if m:
            rows.append((parse_number(m.group(1), source, number, "X"), parse_number(m.group(2), source, number, "Y"),
                         number))
            continue
        if "=" in text and not rows:
            key, value = text.split("=", 1)
            header[key.strip().lower()] = (value.strip(), number)
            continue
        raise ProfileError(f"{source}, line {number}: cannot read {text!r} (expected 'X Y' or a 'Key=Value' header "
                           "line before the points)")
    if "columndef" in header:
        value, number = header["columndef"]
        columns = [c.strip().upper() for c in value.split(",") if c.strip()]
        if columns[:2] != ["X", "Y"]:
            raise ProfileError(f"{source}, line {number}: ColumnDef = {value} is not supported (only X,Y)")
    if not rows:
        raise ProfileError(f"{source}: no points after the header")
    if "xypoints" in header:
        value, number = header["xypoints"]
        expected = parse_number(value, source, number, "XYPoints")
        if expected != len(rows):
            raise ProfileError(f"{source}, line {number}: XYPoints = {value} but the file has {len(rows)} points")
    data = np.array(rows, dtype=float)
    kind = {".ban": "rail", ".whl": "wheel"}.get(Path(path).suffix.lower(), "")
    return Profile(-data[:, 0] / 1000.0, data[:, 1] / 1000.0, DEFAULT_SMOOTHING if smoothing is None else smoothing,
                   kind, source, None, data[:, 2].astype(int), sample_step)


UNITS = {"m": 1.0, "mm": 1000.0}


def read_text_profile(path, unit: str, kind: str = "", smoothing: float | None = None,
                      sample_step: float = DEFAULT_SAMPLE_STEP) -> Profile:
    """Read plain two-column text ``y z`` (blank lines and lines starting with ``#`` or ``!`` skipped).

    Parameters
    ----------
    unit : {"m", "mm"}
        The unit of both columns, stated by the caller (no guess).
    kind : str
        ``"rail"``, ``"wheel"`` or ``""``.

    Raises
    ------
    ProfileError
        An unknown unit, an unparseable line, too few points, points out of order or with a gap (file and line).
    """
    if unit not in UNITS:
        raise ProfileError(f"unit = {unit!r} is not one of {sorted(UNITS)}: state the unit of the file's columns")
    source, lines = read_lines(path)
    rows = []
    for number, raw in enumerate(lines, start=1):
        text = raw.strip()
        if not text or text[0] in "#!":
            continue
        parts = text.replace(",", " ").replace(";", " ").split()
        if len(parts) != 2:
            raise ProfileError(f"{source}, line {number}: {text!r} is not a point 'y z'")
        rows.append((parse_number(parts[0], source, number, "y"), parse_number(parts[1], source, number, "z"),
                     number))
    if not rows:
        raise ProfileError(f"{source}: no points in the file")
    data = np.array(rows, dtype=float)
    return Profile(data[:, 0] / UNITS[unit], data[:, 1] / UNITS[unit],
                   DEFAULT_SMOOTHING if smoothing is None else smoothing, kind, source, None,
                   data[:, 2].astype(int), sample_step)


def read_profile(path, unit: str | None = None, smoothing: float | None = None,
                 sample_step: float = DEFAULT_SAMPLE_STEP) -> Profile:
    """Read a profile by its file's extension: ``.prw``/``.prr`` (:func:`read_simpack`), ``.ban``/``.whl``
    (:func:`read_miniprof`), anything else as plain text (:func:`read_text_profile`, which needs ``unit``)."""
    suffix = Path(path).suffix.lower()
    if suffix in (".prw", ".prr"):
        return read_simpack(path, smoothing, sample_step)
    if suffix in (".ban", ".whl"):
        return read_miniprof(path, smoothing, sample_step)
    if unit is None:
        raise ProfileError(f"{Path(path).name}: a plain text profile needs its unit (unit='m' or 'mm')")
    return read_text_profile(path, unit, "", smoothing, sample_step)
