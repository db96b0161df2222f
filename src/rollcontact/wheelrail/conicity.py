"""Contact-geometry functions of a wheelset on its track as vehicle codes tabulate them: rolling radii and their
difference, contact angles, contact positions, roll, local curvatures over the lateral shift, the equivalent
conicity, and a table a host interpolates (docs/physics.md, Wheel/rail geometry: contact-geometry functions).

All functions are those of the rigid wheelset touching both rails without load (the kinematic position,
:func:`rollcontact.wheelrail.normal.rigid_position`), each wheel at its deepest contact point.  The rolling-radius
difference is ``Delta r(y) = r_right - r_left`` (a positive shift towards the right rail puts the right wheel on its
larger radius): a cone of conicity lambda on knife-edge rails has ``Delta r = 2 lambda y``.

Equivalent conicity (EN 15302:2008+A1:2010, "Railway applications - Method for determining the equivalent
conicity": the conicity of the cone whose wheelset runs the kinematic oscillation of the same wavelength at the
amplitude y^; its Annex B integrates the nonlinear equation, its Annex C linearises Delta r by regression):

* ``method="harmonic"`` (default): harmonic linearisation of Delta r over a sinusoid of amplitude y^,
  ``lambda_e = (1 / (2 pi y^)) int_0^(2 pi) Delta r(y^ sin t) sin t dt``, the first Fourier coefficient of Delta r
  along the motion over 2 y^ (equivalently the least-squares line through Delta r weighted by the time the
  sinusoid spends at each y; Gelb & Vander Velde, *Multiple-input describing functions*, 1968, for describing
  functions; the "Delta r method" of EN 15302).  On the piecewise-linear interpolant of Delta r on a grid the
  integral ``(1/(pi y^)) int_(-y^)^(y^) Delta r(y) (y/y^) / sqrt(y^2 - y^2) dy`` is exact.
* ``method="klingel"``: the wavelength L of the nonlinear kinematic oscillation ``y'' + Delta r(y) / (2 e r0) = 0``
  started at ``y = y^``, ``y' = 0`` (EN 15302 Annex B), and ``lambda_e = e r0 (2 pi / L)^2`` (Klingel's formula
  inverted; e r0 cancels).
"""

from __future__ import annotations

import math
from bisect import bisect_left, bisect_right
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from rollcontact.core.checks import check_real
from rollcontact.wheelrail.geometry import GeometryError, Track, Wheelset
from rollcontact.wheelrail.normal import rigid_position

__all__ = ["QUANTITIES", "ContactFunctions", "ContactTable", "contact_functions", "equivalent_conicity",
           "rolling_radius_difference"]

QUANTITIES = ("roll", "vertical", "radius_difference",
              "left_rolling_radius", "right_rolling_radius", "left_contact_angle", "right_contact_angle",
              "left_wheel_lateral", "right_wheel_lateral", "left_rail_lateral", "right_rail_lateral",
              "left_longitudinal_shift", "right_longitudinal_shift",
              "left_wheel_lateral_curvature", "right_wheel_lateral_curvature",
              "left_wheel_rolling_curvature", "right_wheel_rolling_curvature",
              "left_rail_lateral_curvature", "right_rail_lateral_curvature")
"""The quantities of :class:`ContactFunctions` and :class:`ContactTable`, in the order of the table's rows: the
wheelset's roll [rad] and vertical position [m] (:class:`rollcontact.wheelrail.geometry.Pose`), Delta r [m], and per
wheel the deepest point's rolling radius [m], contact angle [rad] (positive towards the flange), lateral positions on
the wheel and rail profiles [m] (their own axes), longitudinal shift [m] and curvatures [1/m] (mirror-symmetric,
:mod:`rollcontact.wheelrail.search`)."""

JUMP_SUSPECT = 1.0e-3
"""[m]: an interval of shifts over which a wheel's contact position moves more than this is searched for a jump."""

JUMP = 1.0e-4
"""[m]: a jump of the contact point is a move of a wheel's contact position by more than this over an interval of
shifts of :data:`JUMP_RESOLUTION`."""

JUMP_RESOLUTION = 1.0e-7
"""[m]: a jump's position is bisected to this."""

JUMP_MERGE = 5.0e-5
"""[m]: jumps closer than this are one jump (a contact point that holds the lead over a few micrometres of shift,
as between the flange root and the flange of S1002 on UIC60 at zero yaw, is dropped)."""

TOLERANCES = {"roll": 1.0e-6, "vertical": 1.0e-6, "radius_difference": 2.0e-6, "left_rolling_radius": 2.0e-6,
              "right_rolling_radius": 2.0e-6, "left_contact_angle": 1.0e-3, "right_contact_angle": 1.0e-3,
              "left_wheel_lateral": 5.0e-5, "right_wheel_lateral": 5.0e-5, "left_rail_lateral": 5.0e-5,
              "right_rail_lateral": 5.0e-5}
"""The largest midpoint error of linear interpolation (SI units) :meth:`ContactTable.build` refines its nodes to
(curvatures and longitudinal shifts are interpolated without such a bound; their errors are measured)."""

REFINE_LEVELS = 6
"""At most this many halvings of a table's node interval."""


def rigid_values(track: Track, wheelset: Wheelset, shift: float, yaw: float) -> np.ndarray:
    """The :data:`QUANTITIES` at one lateral shift [m] and yaw [rad] (rigid wheelset, deepest points)."""
    pose, left, right = rigid_position(track, wheelset, shift, yaw)
    pl, pr = left.points[0], right.points[0]
    return np.array([pose.roll, pose.vertical, pr.rolling_radius - pl.rolling_radius,
                     pl.rolling_radius, pr.rolling_radius, pl.contact_angle, pr.contact_angle,
                     pl.wheel_lateral, pr.wheel_lateral, pl.rail_lateral, pr.rail_lateral,
                     pl.longitudinal_shift, pr.longitudinal_shift,
                     pl.wheel_lateral_curvature, pr.wheel_lateral_curvature,
                     pl.wheel_rolling_curvature, pr.wheel_rolling_curvature,
                     pl.rail_lateral_curvature, pr.rail_lateral_curvature])


@dataclass(frozen=True)
class ContactFunctions:
    """Contact-geometry functions over the lateral shift (module docstring).

    Attributes
    ----------
    shift : ndarray
        Lateral shifts y [m] (with each jump of the contact point twice: the values either side).
    yaw : float
        [rad].
    values : ndarray
        ``values[i]`` is :data:`QUANTITIES` [i] over ``shift``.
    jumps : tuple of float
        Shifts [m] where a wheel's contact point jumps (to :data:`JUMP_RESOLUTION`).
    """

    shift: np.ndarray
    yaw: float
    values: np.ndarray
    jumps: tuple

    def __getitem__(self, name: str) -> np.ndarray:
        """The quantity ``name`` (one of :data:`QUANTITIES`) over ``shift``."""
        try:
            return self.values[QUANTITIES.index(name)]
        except ValueError:
            raise KeyError(f"{name!r} is not one of {QUANTITIES}") from None


def contact_functions(track: Track, wheelset: Wheelset, shifts, yaw: float = 0.0,
                      resolve_jumps: bool = True) -> ContactFunctions:
    """The contact-geometry functions at the given lateral shifts [m] (sorted, strictly increasing) and yaw [rad].

    With ``resolve_jumps``, each jump of a contact point between two shifts (a wheel's contact position moving more
    than :data:`JUMP`) is bisected to :data:`JUMP_RESOLUTION` and both sides are added as nodes, so that linear
    interpolation never blends two contact points.
    """
    y = np.asarray(shifts, dtype=float).ravel()
    if y.size < 2 or np.any(np.diff(y) <= 0.0) or not np.all(np.isfinite(y)):
        raise GeometryError("shifts must be at least 2 finite values, strictly increasing")
    psi = check_real("yaw", yaw, lower=-0.2, upper=0.2, unit="rad")
    vals = [rigid_values(track, wheelset, float(v), psi) for v in y]
    nodes = list(y)
    jumps = []
    if resolve_jumps:
        out_y, out_v = [nodes[0]], [vals[0]]
        for k in range(1, len(nodes)):
            found = find_jumps(track, wheelset, psi, nodes[k - 1], vals[k - 1], nodes[k], vals[k])
            for a, va, b, vb in found:
                if a > out_y[-1]:
                    out_y.append(a)
                    out_v.append(va)
                jumps.append(0.5 * (a + b))
                out_y.append(b)
                out_v.append(vb)
            if nodes[k] > out_y[-1]:
                out_y.append(nodes[k])
                out_v.append(vals[k])
        nodes, vals = out_y, out_v
        merged = []
        for j in jumps:  # jumps closer than JUMP_MERGE are one: drop the nodes between them
            if merged and j - merged[-1][1] < JUMP_MERGE:
                merged[-1][1] = j
            else:
                merged.append([j, j])
        keep = [i for i, v in enumerate(nodes) if not any(m[0] < v < m[1] for m in merged)]
        nodes, vals = [nodes[i] for i in keep], [vals[i] for i in keep]
        jumps = [0.5 * (m[0] + m[1]) for m in merged]
    return ContactFunctions(np.array(nodes), psi, np.array(vals).T.copy(), tuple(jumps))


WHEEL_POSITIONS = [QUANTITIES.index("left_wheel_lateral"), QUANTITIES.index("right_wheel_lateral")]


def find_jumps(track, wheelset, yaw, a, va, b, vb, depth=0):
    """The jumps of the contact point between the shifts a < b: a list of (a', values, b', values) with
    b' - a' <= JUMP_RESOLUTION and a contact position moving more than JUMP across (bisection into the half with the
    larger move; the rest of the interval searched again)."""
    def move(v0, v1):
        return float(np.max(np.abs(v1[WHEEL_POSITIONS] - v0[WHEEL_POSITIONS])))

    if move(va, vb) <= JUMP_SUSPECT or depth > 4:
        return []
    lo, vlo, hi, vhi = a, va, b, vb
    while hi - lo > JUMP_RESOLUTION:
        m = 0.5 * (lo + hi)
        vm = rigid_values(track, wheelset, m, yaw)
        if move(vlo, vm) >= move(vm, vhi):
            hi, vhi = m, vm
        else:
            lo, vlo = m, vm
    if move(vlo, vhi) <= JUMP:
        return []
    return (find_jumps(track, wheelset, yaw, a, va, lo, vlo, depth + 1) + [(lo, vlo, hi, vhi)]
            + find_jumps(track, wheelset, yaw, hi, vhi, b, vb, depth + 1))


def rolling_radius_difference(track: Track, wheelset: Wheelset, shifts, yaw: float = 0.0) -> np.ndarray:
    """Delta r = r_right - r_left [m] of the rigid wheelset at each lateral shift [m] (module docstring)."""
    return np.array([rigid_values(track, wheelset, float(v), yaw)[2] for v in np.asarray(shifts, float).ravel()])


def equivalent_conicity(track: Track, wheelset: Wheelset, amplitude: float, method: str = "harmonic",
                        step: float = 1.0e-4, functions: ContactFunctions | None = None) -> float:
    """The equivalent conicity lambda_e [1] at the amplitude y^ [m] (module docstring for the methods).

    Parameters
    ----------
    amplitude : float
        y^ [m] > 0 (the standard quotes 3 mm).
    method : {"harmonic", "klingel"}
    step : float
        Spacing [m] of the shifts at which Delta r is computed over [-y^, y^] (jumps resolved).
    functions : ContactFunctions, optional
        Precomputed contact functions covering [-y^, y^] (then ``step`` is not used).
    """
    amp = check_real("amplitude", amplitude, lower=0.0, lower_open=True, upper=0.05, unit="m")
    if method not in ("harmonic", "klingel"):
        raise GeometryError(f"method = {method!r} must be 'harmonic' or 'klingel'")
    if functions is None:
        reach = amp if method == "harmonic" else 1.25 * amp  # an asymmetric Delta r swings beyond -y^
        n = max(int(math.ceil(2.0 * reach / check_real("step", step, lower=1e-7, unit="m"))), 4)
        functions = contact_functions(track, wheelset, np.linspace(-reach, reach, n + 1))
    y, dr = functions.shift, functions["radius_difference"]
    if y[0] > -amp * (1 + 1e-12) + 1e-15 or y[-1] < amp * (1 - 1e-12) - 1e-15:
        if not (y[0] <= -amp + 1e-12 and y[-1] >= amp - 1e-12):
            raise GeometryError(f"the contact functions span [{y[0]!r}, {y[-1]!r}] m, not the amplitude "
                                f"+-{amp!r} m")
    if method == "harmonic":
        return harmonic_conicity(y, dr, amp)
    return klingel_conicity(y, dr, amp)


def harmonic_conicity(y: np.ndarray, dr: np.ndarray, amp: float) -> float:
    """``(1/(pi a)) int_(-a)^a Delta r(y) (y/a) / sqrt(a^2 - y^2) dy`` exactly for the piecewise-linear Delta r
    through (y, dr) (clipped to [-a, a])."""
    grid = np.concatenate(([-amp], y[(y > -amp) & (y < amp)], [amp]))
    values = np.interp(grid, y, dr)
    # duplicated nodes (a resolved jump) keep both values in order
    ya, yb = grid[:-1], grid[1:]
    fa, fb = values[:-1], values[1:]
    keep = yb > ya
    ya, yb, fa, fb = ya[keep], yb[keep], fa[keep], fb[keep]
    slope = (fb - fa) / (yb - ya)
    intercept = fa - slope * ya

    def primitives(v):  # int y/s dy, int y^2/s dy with s = sqrt(a^2 - y^2)
        s = np.sqrt(np.maximum(amp * amp - v * v, 0.0))
        return -s, 0.5 * amp * amp * np.arcsin(np.clip(v / amp, -1.0, 1.0)) - 0.5 * v * s

    p1a, p2a = primitives(ya)
    p1b, p2b = primitives(yb)
    integral = np.sum(intercept * (p1b - p1a) + slope * (p2b - p2a))
    return float(integral / (math.pi * amp * amp))


def klingel_conicity(y: np.ndarray, dr: np.ndarray, amp: float) -> float:
    """``(2 pi / L)^2`` with L the period of ``u'' = -Delta r(u)/2`` from ``u = amp``, ``u' = 0`` (module docstring,
    in units where ``e r0 = 1``)."""
    ymin, ymax = float(y[0]), float(y[-1])

    def rhs(_, s):
        u = s[0]
        if not ymin - 1e-9 <= u <= ymax + 1e-9:
            raise GeometryError(f"the kinematic oscillation reaches y = {u!r} m beyond the contact functions' "
                                f"[{ymin!r}, {ymax!r}] m")
        return (s[1], -0.5 * float(np.interp(u, y, dr)))

    def turn_up(_, s):
        return s[1]

    turn_up.direction = 1.0
    turn_up.terminal = True

    def turn_down(_, s):
        return s[1]

    turn_down.direction = -1.0
    turn_down.terminal = True
    lam0 = max(abs(float(np.interp(amp, y, dr)) / (2.0 * amp)), 1e-6)
    horizon = 20.0 * 2.0 * math.pi / math.sqrt(lam0)
    first = solve_ivp(rhs, (0.0, horizon), (amp, 0.0), events=turn_up, rtol=1e-10, atol=1e-14, max_step=horizon / 200)
    if not first.t_events[0].size:
        raise GeometryError(f"no kinematic oscillation at amplitude {amp!r} m: Delta r does not turn the wheelset "
                            "back (zero or negative conicity)")
    t1 = float(first.t_events[0][0])
    state = first.y_events[0][0]
    second = solve_ivp(rhs, (t1, t1 + horizon), state, events=turn_down, rtol=1e-10, atol=1e-14,
                       max_step=horizon / 200)
    if not second.t_events[0].size:
        raise GeometryError(f"the kinematic oscillation at amplitude {amp!r} m does not close")
    period = float(second.t_events[0][0])
    return (2.0 * math.pi / period) ** 2


def refine(track: Track, wheelset: Wheelset, functions: ContactFunctions) -> ContactFunctions:
    """Halve the node intervals (not across a jump) where linear interpolation misses the value at the midpoint
    by more than :data:`TOLERANCES`, up to :data:`REFINE_LEVELS` times."""
    rows = [QUANTITIES.index(name) for name in TOLERANCES]
    tol = np.array(list(TOLERANCES.values()))
    nodes = list(functions.shift)
    vals = list(functions.values.T)
    jumps = np.array(functions.jumps)
    todo = [i for i in range(len(nodes) - 1) if not np.any((jumps > nodes[i]) & (jumps < nodes[i + 1]))]
    for _ in range(REFINE_LEVELS):
        added = []
        for i in todo:
            m = 0.5 * (nodes[i] + nodes[i + 1])
            vm = rigid_values(track, wheelset, m, functions.yaw)
            if np.any(np.abs(vm[rows] - 0.5 * (vals[i][rows] + vals[i + 1][rows])) > tol):
                added.append((m, vm))
        if not added:
            break
        pairs = sorted(list(zip(nodes, vals, strict=True)) + added, key=lambda p: p[0])
        new = {m for m, _ in added}
        nodes = [p[0] for p in pairs]
        vals = [p[1] for p in pairs]
        todo = [i for i in range(len(nodes) - 1) if nodes[i] in new or nodes[i + 1] in new]
    return ContactFunctions(np.array(nodes), functions.yaw, np.array(vals).T.copy(), functions.jumps)


# ---------------------------------------------------------------------------------------------------- table
@dataclass(frozen=True, eq=False)
class ContactTable:
    """The contact-geometry functions tabulated over lateral shift and yaw, for a host to interpolate.

    Nodes: for each yaw node, the lateral shifts of :func:`contact_functions` (each jump resolved: two nodes a
    :data:`JUMP_RESOLUTION` apart; the intervals refined until linear interpolation meets :data:`TOLERANCES` at
    their midpoints).  Lookup (:meth:`__call__`): linear in y between the nodes of the segment (between jumps) the
    query lies in, and quadratic in yaw through the three yaw nodes nearest the query (linear with two).  The jump
    positions are interpolated in yaw too, and the query's fraction of its segment (between the interpolated jumps,
    or a jump and the table's end) is read at the same fraction of each yaw node's own segment, so that no node is
    read across its jump and a tread value is never blended with a flange value (where the yaw nodes have
    different numbers of jumps, plain interpolation in y at each node).  The error of the lookup
    against direct searches between the nodes is measured by :meth:`interpolation_error`.

    Attributes
    ----------
    yaws : ndarray
        Yaw nodes [rad], increasing.
    functions : tuple of ContactFunctions
        One per yaw node.
    """

    yaws: np.ndarray
    functions: tuple

    @classmethod
    def build(cls, track: Track, wheelset: Wheelset, shift_range: tuple = (-0.01, 0.01), step: float = 1.0e-4,
              yaws=(0.0,)) -> ContactTable:
        """Tabulate over ``shift_range`` [m] at ``step`` [m] and at the yaw nodes [rad]."""
        lo = check_real("shift_range[0]", shift_range[0], lower=-0.05, upper=0.05, unit="m")
        hi = check_real("shift_range[1]", shift_range[1], lower=lo, lower_open=True, upper=0.05, unit="m")
        h = check_real("step", step, lower=1e-6, upper=hi - lo, unit="m")
        psi = np.asarray(yaws, dtype=float).ravel()
        if psi.size < 1 or np.any(np.diff(psi) <= 0.0):
            raise GeometryError("yaws must be one or more values, strictly increasing")
        shifts = np.linspace(lo, hi, int(round((hi - lo) / h)) + 1)
        return cls(psi, tuple(refine(track, wheelset, contact_functions(track, wheelset, shifts, float(p)))
                              for p in psi))

    def __post_init__(self):
        shifts, jumps, cuts, offsets, rows = [], [], [], [], []
        total = 0
        for f in self.functions:
            shifts.append(f.shift.tolist())
            jumps.append(list(f.jumps))
            cut = [0] + [int(np.searchsorted(f.shift, j)) for j in f.jumps] + [f.shift.size]
            cuts.append(cut)
            offsets.append(total)
            rows.append(f.values.T)
            total += f.shift.size
        object.__setattr__(self, "_shifts", shifts)
        object.__setattr__(self, "_jumps", jumps)
        object.__setattr__(self, "_bounds", [[sh[0], *j, sh[-1]] for sh, j in zip(shifts, jumps, strict=True)])
        object.__setattr__(self, "_cuts", cuts)
        object.__setattr__(self, "_offsets", offsets)
        object.__setattr__(self, "_rows", np.ascontiguousarray(np.concatenate(rows)))
        object.__setattr__(self, "_yaws", self.yaws.tolist())
        object.__setattr__(self, "_aligned", len({len(j) for j in jumps}) == 1)

    def _node(self, k: int, y: float, jumps: list | None, seg: int | None = None) -> tuple[int, float]:
        """(row, t): the query y lies between the rows ``row`` and ``row + 1`` of the yaw node k at fraction t
        (within the segment ``seg`` between the jumps, by default the one y lies in)."""
        shift = self._shifts[k]
        a, b = 0, len(shift)
        if jumps is not None:
            if seg is None:
                seg = bisect_left(jumps, y)
            cut = self._cuts[k]
            if cut[seg + 1] - cut[seg] >= 2:
                a, b = cut[seg], cut[seg + 1]
        i = min(max(bisect_right(shift, y, a, b), a + 1), b - 1)
        y0, y1 = shift[i - 1], shift[i]
        t = min(max((y - y0) / (y1 - y0), 0.0), 1.0) if y1 > y0 else 1.0
        return self._offsets[k] + i - 1, t

    def __call__(self, lateral_shift: float, yaw: float = 0.0) -> np.ndarray:
        """The :data:`QUANTITIES` at the lateral shift [m] and yaw [rad] (class docstring); outside the table's
        range GeometryError names the value and the range."""
        y = float(lateral_shift)
        psi = float(yaw)
        s0 = self._shifts[0]
        if not (s0[0] <= y <= s0[-1]):
            raise GeometryError(f"lateral_shift = {y!r} m is outside the table's [{s0[0]!r}, {s0[-1]!r}] m")
        yaws = self._yaws
        n = len(yaws)
        if n == 1:
            if abs(psi - yaws[0]) > 1e-12:
                raise GeometryError(f"yaw = {psi!r} rad: the table has the one yaw {yaws[0]!r} rad")
            nodes, weights = (0,), (1.0,)
        else:
            if not (yaws[0] <= psi <= yaws[-1]):
                raise GeometryError(f"yaw = {psi!r} rad is outside the table's [{yaws[0]!r}, {yaws[-1]!r}] rad")
            k = min(max(bisect_right(yaws, psi), 1), n - 1)
            if n == 2:
                nodes = (0, 1)
            else:  # the three nodes around psi: quadratic in yaw (the lift of a yawed flange grows as psi^2)
                c = min(max(k if psi - yaws[k - 1] > yaws[k] - psi else k - 1, 1), n - 2)
                nodes = (c - 1, c, c + 1)
            weights = []
            for i in nodes:
                w = 1.0
                for j in nodes:
                    if j != i:
                        w *= (psi - yaws[j]) / (yaws[i] - yaws[j])
                weights.append(w)
        if self._aligned and len(nodes) > 1:
            # jump-aligned: the query's fraction u of its segment between the interpolated jumps (or the table's
            # ends) is taken at the same fraction of each node's own segment, so no node is read across its jump
            bounds = [self._bounds[i] for i in nodes]
            if len(nodes) == 3:
                w0, w1, w2 = weights
                mixed = [w0 * p + w1 * q + w2 * r for p, q, r in zip(*bounds, strict=True)]
            else:
                w0, w1 = weights
                mixed = [w0 * p + w1 * q for p, q in zip(*bounds, strict=True)]
            seg = min(max(bisect_left(mixed, y, 1, len(mixed) - 1), 1), len(mixed) - 1) - 1
            lo, hi = mixed[seg], mixed[seg + 1]
            u = (y - lo) / (hi - lo) if hi > lo else 0.0
            index, coef = [], []
            for i, w, own in zip(nodes, weights, bounds, strict=True):
                row, t = self._node(i, own[seg] + u * (own[seg + 1] - own[seg]), self._jumps[i], seg)
                index += (row, row + 1)
                coef += (w * (1.0 - t), w * t)
        else:
            index, coef = [], []
            for i, w in zip(nodes, weights, strict=True):
                row, t = self._node(i, y, self._jumps[i] if len(nodes) == 1 else None)
                index += (row, row + 1)
                coef += (w * (1.0 - t), w * t)
        return np.dot(coef, self._rows[index])

    @property
    def rows(self) -> np.ndarray:
        """The node values (one row per node, :data:`QUANTITIES` in its columns; the yaw nodes one after another)."""
        return self._rows

    def locate(self, lateral_shift: float) -> tuple[int, float, float]:
        """Where a lateral shift [m] lies in a table of one yaw node: ``(row, t, width)`` such that the lookup
        (:meth:`__call__` at that yaw) is ``(1 - t) rows[row] + t rows[row + 1]`` and, within the segment between
        jumps, its derivative in the shift is ``(rows[row + 1] - rows[row]) / width`` (``width`` [m] the distance of
        the two nodes).  GeometryError outside the table's range or for a table of several yaw nodes."""
        if len(self._yaws) != 1:
            raise GeometryError(f"locate needs a table of one yaw node; this one has {len(self._yaws)}")
        y = float(lateral_shift)
        s0 = self._shifts[0]
        if not (s0[0] <= y <= s0[-1]):
            raise GeometryError(f"lateral_shift = {y!r} m is outside the table's [{s0[0]!r}, {s0[-1]!r}] m")
        row, t = self._node(0, y, self._jumps[0])
        return row, t, s0[row + 1] - s0[row]

    def lookup(self, lateral_shift: float, yaw: float = 0.0) -> dict:
        """:meth:`__call__` as a dict by quantity name."""
        return dict(zip(QUANTITIES, self(lateral_shift, yaw).tolist(), strict=True))

    def interpolation_error(self, track: Track, wheelset: Wheelset, samples: int = 40,
                            seed: int = 0) -> dict:
        """The largest |lookup - direct search| of each quantity at ``samples`` points between the nodes: shifts
        halfway between the nodes (a fixed pseudo-random choice of them, ``seed``), yaws halfway between the yaw
        nodes (or the one yaw).  Returns ``{quantity: largest error}`` and ``"points"``: the (shift, yaw) tried."""
        rng = np.random.default_rng(seed)
        f0 = self.functions[0]
        mids = 0.5 * (f0.shift[1:] + f0.shift[:-1])
        mids = mids[np.diff(f0.shift) > 10 * JUMP_RESOLUTION]
        ys = rng.choice(mids, size=min(samples, mids.size), replace=False)
        if self.yaws.size > 1:
            ymid = 0.5 * (self.yaws[1:] + self.yaws[:-1])
            psis = rng.choice(ymid, size=ys.size)
        else:
            psis = np.full(ys.size, self.yaws[0])
        worst = np.zeros(len(QUANTITIES))
        for y, p in zip(ys, psis, strict=True):
            direct = rigid_values(track, wheelset, float(y), float(p))
            worst = np.maximum(worst, np.abs(self(float(y), float(p)) - direct))
        out = dict(zip(QUANTITIES, worst.tolist(), strict=True))
        out["points"] = list(zip(ys.tolist(), psis.tolist(), strict=True))
        return out
