"""Wheel/rail patches: the fast strips and the discretised level against a fine discretised reference, on quadratic
gaps and on non-Hertzian gaps of the Manchester benchmark's S1002 wheel on UIC60 rail.

Run: ``python benchmarks/wheelrail_patches.py`` (``--quick``: coarser references, fewer cases, nothing written;
``--profiles DIR``: where the SIMPACK profiles are, by default the shared data beside the checkout).  Prints markdown
tables and writes ``benchmarks/results/wheelrail_patches.md`` and ``benchmarks/results/wheelrail_patches.png`` (the
realistic patches' shapes and pressure maps):

Hertz. Quadratic gaps over a/b 0.2..5: the strips' normal solution against Hertz (Fn at Hertz's approach, p0, a, b
   at his load), the strips' forces against the elliptic strips and the discretised patch level against the elliptic
   discretised level on the same grid (the largest over the creepage set), both patch levels against the elliptic
   discretised level's Richardson pair (60/30 elements).
Normal. The realistic patches (:data:`PATCHES`): the strips' and the default discretised level's (0.2 mm, finer on a
   patch narrower than 12 elements) Fn at the reference's approach, approach at the load, peak pressure, length and
   width, against the reference.
Tangential. Per patch and creepage (:func:`creepage_set`, in units of the equivalent ellipse's saturation): the
   reference's forces and the errors of both levels, ``|dFx|, |dFy|`` over mu Fn and ``|dMz|`` over mu Fn c (c =
   sqrt(area/pi)), with each level's own estimate.  The accuracy models' constants cite this table.
Convergence. The discretised level's forces, Fn at a given approach and peak pressure at element sizes halving
   down to the reference's, their changes and the observed order ``log2(change ratio)``.
Newton. The strips' normal problem with Newton's early stop off (``NEWTON_CONTRACTION`` infinite): the largest
   ``c_{k+1} / c_k^2`` of its final steps (``c_k <= 1e-2``, the relative changes of e and q) on the quadratic gaps and
   the realistic patches, at the load and at the approach; ``NEWTON_CONTRACTION`` cites it.
Time. Median CPU time per patch of the strips' normal problem alone and of the strips (without and with spin), of
   the default discretised level (normal and tangential), each timed in turn with its yardstick on one ellipse (the
   elliptic strips; the elliptic discretised level's default, the Richardson pair 60/30; their docs state their times
   on an idle machine), each level's time as a multiple of its yardstick's, and per-wheel sums: a wheel of one patch
   (the tread) and of two (the tread and the flange).

The reference is the discretised level's Richardson pair ``2 F(h) - F(2h)`` at an element of at most a 25th of the
patch's width (normal quantities: the finer grid's).  The profiles are read by a throwaway SIMPACK reader and
splined (not the project's reader): the wheel at lateral shift y of the centred wheelset (taping lines 1500 mm apart,
gauge 1435 mm 14 mm below the rail top), no roll or yaw; the patch's tangent plane at the rail's slope at the
point of least separation, the gap measured along its normal, ``A(s) = cos(alpha) / (2 r(s))``.  BLAS is limited to
one thread (before numpy loads).  Machines here are noisy: compare times within one run.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path

import common  # before numpy: limits BLAS to one thread
import numpy as np
from scipy.interpolate import CubicSpline

import rollcontact as rc
import rollcontact.wheelrail.methods.strip_normal as strip_normal_module
from rollcontact.core.halfspace.rolling import ellipse_grid
from rollcontact.elliptic.creep_coefficients import extended_creepage_coefficients
from rollcontact.elliptic.methods.discretised import solve_discretised_3d
from rollcontact.elliptic.methods.strips import solve_strips as elliptic_strips
from rollcontact.wheelrail.methods.discretised import solve_discretised
from rollcontact.wheelrail.methods.strip_normal import strip_normal
from rollcontact.wheelrail.methods.strips import normal_contact, solve_strips
from rollcontact.wheelrail.patch import PatchGap
from rollcontact.wheelrail.scene import PatchScene

PROFILES = common.ROOT.parent / "shared" / "data" / "profiles"
"""Default directory of ``MBench_S1002_v3.prw`` and ``MBench_UIC60_v3.prr`` (Manchester Contact Benchmark, as
distributed with CONTACT, Apache-2.0; not copied into the project)."""

MU = 0.3
MATERIAL = rc.Material(210e9, 0.28)
NOMINAL_RADIUS = 0.46
TAPING_LINES = 1.5  # m between the taping lines (flange backs 1360 mm apart, taping line 70 mm from the back)
GAUGE_POINT = -0.04303  # m: the rail's gauge point (14 mm below the top) in its own frame
GAUGE = 1.435

PATCHES = (("tread, centred (two-lobed)", 0.0, 50e3), ("flange root", 6e-3, 40e3), ("flange", 8e-3, 30e3))
"""(name, lateral shift of the wheelset [m], normal load [N]) of the realistic patches."""


# ------------------------------------------------------------------------------------------ throwaway profiles
def read_simpack(path: Path) -> np.ndarray:
    """Points (y, z) [m] of a SIMPACK ``.prw``/``.prr`` profile, with its ``mirror.y``, ``inversion`` and
    ``units.len.f``, y increasing (a throwaway reader for this benchmark)."""
    points, options, inside = [], {}, False
    for line in path.read_text().splitlines():
        text = line.split("!")[0].strip()
        if not text:
            continue
        if text.startswith("point.begin"):
            inside = True
        elif text.startswith("point.end"):
            inside = False
        elif inside:
            y, z = text.split()[:2]
            points.append((float(y), float(z)))
        elif "=" in text:
            key, value = text.split("=", 1)
            options[key.strip()] = value.strip()
    p = np.array(points)
    if int(options.get("mirror.y", "0")):
        p[:, 0] *= -1.0
    if int(options.get("inversion", "0")):
        p = p[::-1]
    p = p / float(options.get("units.len.f", "1000"))
    return p[::-1] if p[0, 0] > p[-1, 0] else p


class Profiles:
    """Cubic splines z(y) of the wheel and of the rail head (its top and gauge corner down to 16 mm)."""

    def __init__(self, directory: Path):
        wheel = read_simpack(directory / "MBench_S1002_v3.prw")
        rail = read_simpack(directory / "MBench_UIC60_v3.prr")
        head = rail[rail[:, 1] < rail[:, 1].min() + 0.016]
        head = head[np.argsort(head[:, 0])]
        _, unique = np.unique(head[:, 0], return_index=True)
        head = head[unique]
        self.wheel = CubicSpline(wheel[:, 0], wheel[:, 1])
        self.rail = CubicSpline(head[:, 0], head[:, 1])
        self.wheel_range = (wheel[0, 0], wheel[-1, 0])
        self.rail_range = (head[0, 0], head[-1, 0])

    def patch_gap(self, shift: float, samples: int = 1601, half_width: float = 0.02) -> tuple[PatchGap, float]:
        """The right wheel's patch at the wheelset's lateral ``shift`` [m]: ``(PatchGap, contact angle [rad])``
        (module docstring)."""
        wheel_origin, rail_origin = 0.5 * TAPING_LINES + shift, 0.5 * GAUGE - GAUGE_POINT
        lo = max(self.wheel_range[0] + wheel_origin, self.rail_range[0] + rail_origin)
        hi = min(self.wheel_range[1] + wheel_origin, self.rail_range[1] + rail_origin)
        y = np.linspace(lo, hi, 40001)
        vertical = self.rail(y - rail_origin) - self.wheel(y - wheel_origin)  # z downward: rail below the wheel
        k = int(np.argmin(vertical))
        y0 = y[k]
        z0 = float(self.wheel(y0 - wheel_origin))
        alpha = math.atan(float(self.rail(y0 - rail_origin, 1)))
        ca, sa = math.cos(alpha), math.sin(alpha)
        t = y0 + np.linspace(-0.06, 0.06, 60001)

        def rotated(spline, origin, bounds):
            inside = (t - origin > bounds[0]) & (t - origin < bounds[1])
            yy = t[inside]
            zz = spline(yy - origin)
            s, n = (yy - y0) * ca + (zz - z0) * sa, -(yy - y0) * sa + (zz - z0) * ca
            middle = int(np.argmin(np.abs(s)))
            rising = np.diff(s) > 0.0
            first, last = middle, middle
            while first > 0 and rising[first - 1]:
                first -= 1
            while last < rising.size and rising[last]:
                last += 1
            return s[first:last + 1], n[first:last + 1]

        sw, nw = rotated(self.wheel, wheel_origin, self.wheel_range)
        sr, nr = rotated(self.rail, rail_origin, self.rail_range)
        s = np.linspace(max(sw[0], sr[0], -half_width), min(sw[-1], sr[-1], half_width), samples)
        h = np.interp(s, sr, nr) - np.interp(s, sw, nw)
        least = int(np.argmin(h))
        h, s = h - h[least], s - s[least]
        radius = NOMINAL_RADIUS + self.wheel(np.clip(y0 + s * ca - wheel_origin, *self.wheel_range))
        return PatchGap(s, h, ca / (2.0 * radius)), alpha


# ------------------------------------------------------------------------------------------------- cases
def scale_of(result) -> tuple[float, float]:
    """mu Fn [N] and mu Fn c [N m] of a result."""
    return MU * result.normal_load, MU * result.normal_load * result.c


def creepage_set(scene: PatchScene, quick: bool) -> list[tuple[str, tuple[float, float, float]]]:
    """Creepages in units of the saturation of the strips' equivalent ellipse: ``xi_s = mu Fn / (G c^2 C11)``,
    ``eta_s`` likewise with C22, ``phi_s = mu Fn / (G c^3 C23)`` (linear force mu Fn), at 0.5 and 2 of them, and
    combined."""
    contact = normal_contact(scene)
    area = 2.0 * float(contact.widths @ contact.half_lengths)
    probe = solve_strips(scene.replace(longitudinal_creepage=1e-12))
    ratio = probe.info["equivalent_ratios"][0]
    k = extended_creepage_coefficients(ratio, MATERIAL.poisson_ratio)
    g = MATERIAL.youngs_modulus / (2.0 * (1.0 + MATERIAL.poisson_ratio))
    c2 = area / math.pi
    force = MU * contact.normal_load
    xi_s, eta_s, phi_s = force / (g * c2 * k.c11), force / (g * c2 * k.c22), force / (g * c2**1.5 * k.c23)
    cases = [("xi 0.5", (0.5 * xi_s, 0.0, 0.0)), ("xi 2", (2.0 * xi_s, 0.0, 0.0)),
             ("eta 0.5", (0.0, 0.5 * eta_s, 0.0)), ("eta 2", (0.0, 2.0 * eta_s, 0.0)),
             ("spin 0.5", (0.0, 0.0, 0.5 * phi_s)), ("spin 2", (0.0, 0.0, 2.0 * phi_s)),
             ("combined 0.5", (0.35 * xi_s, 0.35 * eta_s, 0.3 * phi_s)),
             ("combined 2", (1.4 * xi_s, 1.4 * eta_s, 1.2 * phi_s))]
    return cases[::3] if quick else cases


def forces(result) -> np.ndarray:
    force, moment = scale_of(result)
    return np.array([result.longitudinal_force / force, result.lateral_force / force, result.spin_moment / moment])


def reference_element(width: float, quick: bool) -> float:
    """The reference's element [m]: at most 0.1 mm (0.2 mm quick), at most a 25th (12th quick) of the width,
    rounded down to 0.01 mm steps."""
    top, share = (0.2e-3, 12.0) if quick else (0.1e-3, 25.0)
    return max(0.01e-3, min(top, 0.01e-3 * math.floor(width / share / 0.01e-3)))


# ----------------------------------------------------------------------------------------------- sections
def hertz_section(quick: bool) -> list[str]:
    lines = ["## Hertz: quadratic gaps", "",
             "Strips' normal solution against Hertz (Fn at Hertz's approach; p0, a, b at his load), relative; the "
             "forces' largest difference over the creepage set [mu Fn]: patch strips against elliptic strips, "
             "discretised patch against elliptic discretised on its grid (30 x 30 and margin), the patch strips, the "
             "elliptic strips and the discretised patch (0.2 mm) against the elliptic Richardson pair 60/30.", "",
             "| a/b | Fn | p0 | a | b | strips vs elliptic strips | discretised vs elliptic (same grid) | "
             "strips vs pair | elliptic strips vs pair | discretised default vs pair |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    ratios = (0.2, 1.0, 5.0) if quick else (0.2, 0.5, 1.0, 2.0, 5.0)
    for ratio in ratios:
        a, b = 6e-3 * ratio**0.5, 6e-3 / ratio**0.5
        ellipse = rc.EllipticScene.from_semi_axes(1e5, a, b, material=MATERIAL, friction=MU)
        h = ellipse.hertz
        s = np.linspace(-3 * b, 3 * b, 4001)
        gap = PatchGap(s, ellipse.lateral_curvature * s * s, np.full(s.size, ellipse.longitudinal_curvature))
        at_approach = strip_normal(gap, MATERIAL.contact_modulus, approach=h.approach)
        at_load = strip_normal(gap, MATERIAL.contact_modulus, normal_load=1e5)
        errors = [at_approach.normal_load / 1e5 - 1, at_load.max_pressure / h.max_pressure - 1,
                  at_load.length / (2 * h.a) - 1, at_load.width / (2 * h.b) - 1]
        scene = PatchScene(gap, normal_load=1e5, material=MATERIAL, friction=MU)
        worst = np.zeros(5)
        for _, (xi, eta, phi) in creepage_set(scene, quick):
            es = ellipse.replace(longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi)
            ps = scene.replace(longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi)
            pair = np.array(solve_discretised_3d(es, elements=30 if quick else 60).force_coefficients)
            fast = solve_strips(ps)
            strips = forces(fast) * np.array([1.0, 1.0, fast.c / h.c])
            same_grid = solve_discretised(ps, grid=ellipse_grid(h.a, h.b, 30, margin=3))
            elliptic_same = solve_discretised_3d(es, elements=30, extrapolate=False, normal="discretised")
            patch_fine = solve_discretised(ps, element=0.2e-3)
            ellipse_strips = np.array(elliptic_strips(es).force_coefficients)
            worst = np.maximum(worst, [np.abs(strips - ellipse_strips).max(),
                                       np.abs(as_ellipse(same_grid, h.c) - elliptic_same.force_coefficients).max(),
                                       np.abs(strips - pair).max(), np.abs(ellipse_strips - pair).max(),
                                       np.abs(as_ellipse(patch_fine, h.c) - pair).max()])
        lines.append(f"| {ratio:g} | " + " | ".join(f"{e:+.1e}" for e in errors) + " | "
                     + " | ".join(f"{w:.4f}" for w in worst) + " |")
    return lines + [""]


def as_ellipse(result, c: float) -> np.ndarray:
    """Fx, Fy over mu Fn and Mz over mu Fn c of a patch result, c the ellipse's."""
    scale = MU * result.normal_load
    return np.array([result.longitudinal_force / scale, result.lateral_force / scale, result.spin_moment / (scale * c)])


def realistic(profiles: Profiles, quick: bool):
    """Per patch: name, scene, the reference element, the reference (normal at its load, and per creepage), the
    default discretised and the strips."""
    out = []
    for name, shift, load in (PATCHES[::2] if quick else PATCHES):
        gap, alpha = profiles.patch_gap(shift)
        scene = PatchScene(gap, normal_load=load, material=MATERIAL, friction=MU)
        contact = normal_contact(scene)
        element = reference_element(contact.width, quick)
        out.append({"name": name, "scene": scene, "alpha": alpha, "element": element, "contact": contact})
    return out


def normal_section(patches, quick: bool) -> list[str]:
    lines = ["## Normal: the realistic patches", "",
             "Relative errors against the reference (the discretised level at the reference element): Fn at the "
             "reference's approach, the approach at the load, the peak pressure, the length and width.", "",
             "| patch | load [kN] | ref. element [mm] | ref. Fn(delta) approach [um] | ref. p0 [MPa] | ref. length x "
             "width [mm] | level | Fn(delta) | approach | p0 | length | width |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for patch in patches:
        scene = patch["scene"]
        reference = solve_discretised(scene, element=patch["element"])
        patch["reference_normal"] = reference
        at_approach = scene.replace(approach=reference.approach)
        for level, by_load, by_approach in (
                ("strips", solve_strips(scene), solve_strips(at_approach)),
                ("discretised default", solve_discretised(scene), solve_discretised(at_approach))):
            errors = [by_approach.normal_load / scene.normal_load - 1, by_load.approach / reference.approach - 1,
                      by_load.max_pressure / reference.max_pressure - 1, by_load.length / reference.length - 1,
                      by_load.width / reference.width - 1]
            lines.append(f"| {patch['name']} | {scene.normal_load / 1e3:g} | {patch['element'] * 1e3:g} | "
                         f"{reference.approach * 1e6:.2f} | {reference.max_pressure / 1e6:.0f} | "
                         f"{reference.length * 1e3:.2f} x {reference.width * 1e3:.2f} | {level} | "
                         + " | ".join(f"{e:+.4f}" for e in errors) + " |")
    return lines + [""]


def tangential_section(patches, quick: bool) -> list[str]:
    lines = ["## Tangential: the realistic patches", "",
             "Reference forces (Richardson pair at the reference element) over mu Fn (Mz over mu Fn c, c = "
             "sqrt(area/pi), about the rigid contact point) and the errors of each level, the largest of the three, "
             "with the level's estimate.", "",
             "| patch | creepages | reference Fx, Fy, Mz | strips error (Fx, Fy, Mz) | strips largest / estimate | "
             "discretised default largest / estimate |", "|---|---|---|---|---|---|"]
    summary = {}
    for patch in patches:
        scene = patch["scene"]
        for label, (xi, eta, phi) in creepage_set(scene, quick):
            case = scene.replace(longitudinal_creepage=xi, lateral_creepage=eta, spin_creepage=phi)
            reference = solve_discretised(case, element=patch["element"], extrapolate=True)
            expected = forces(reference)
            strips, discretised = solve_strips(case), solve_discretised(case)
            c_ratio = np.array([1.0, 1.0, reference.c])
            strip_error = np.abs(forces(strips) * np.array([1.0, 1.0, strips.c]) / c_ratio - expected)
            disc_error = np.abs(forces(discretised) * np.array([1.0, 1.0, discretised.c]) / c_ratio - expected)
            summary.setdefault(patch["name"], []).append((strip_error.max(), disc_error.max()))
            lines.append(f"| {patch['name']} | {label} | " + ", ".join(f"{v:+.3f}" for v in expected) + " | "
                         + ", ".join(f"{v:.3f}" for v in strip_error) + f" | {strip_error.max():.3f} / "
                         f"{strips.info['error_estimate']:.3f} | {disc_error.max():.3f} / "
                         f"{discretised.info['error_estimate']:.3f} |")
    lines += ["", "| patch | strips: largest error | discretised default: largest error |", "|---|---|---|"]
    for name, values in summary.items():
        lines.append(f"| {name} | {max(v[0] for v in values):.3f} | {max(v[1] for v in values):.3f} |")
    return lines + [""]


def convergence_section(patches, quick: bool) -> list[str]:
    lines = ["## Convergence of the discretised level", "",
             "Combined creepage at 0.5 saturation; changes from each element size to the next and the observed order "
             "``log2(change / next change)`` (1: first order).", "",
             "| patch | element [mm] | Fx, Fy, Mz [mu Fn] | Fn(delta) [N] | p0 [MPa] | largest force change | order |",
             "|---|---|---|---|---|---|---|"]
    for patch in patches:
        scene = patch["scene"]
        label, creepages = creepage_set(scene, False)[6]
        case = scene.replace(longitudinal_creepage=creepages[0], lateral_creepage=creepages[1],
                             spin_creepage=creepages[2])
        approach = patch["reference_normal"].approach
        sizes = [patch["element"] * 2**k for k in (2, 1, 0)]
        rows, changes = [], []
        previous = None
        for size in sizes:
            result = solve_discretised(case, element=size)
            normal = solve_discretised(case.replace(approach=approach), element=size)
            values = forces(result) * np.array([1.0, 1.0, result.c / patch["reference_normal"].c])
            change = math.nan if previous is None else float(np.abs(values - previous).max())
            changes.append(change)
            order = ""
            if len(changes) >= 3 and changes[-1] > 0.0:
                order = f"{math.log2(changes[-2] / changes[-1]):.2f}"
            rows.append(f"| {patch['name']} | {size * 1e3:g} | " + ", ".join(f"{v:+.4f}" for v in values)
                        + f" | {normal.normal_load:.0f} | {result.max_pressure / 1e6:.1f} | "
                        + ("" if math.isnan(change) else f"{change:.4f}") + f" | {order} |")
            previous = values
        lines += rows
    return lines + [""]


def newton_section(patches, quick: bool) -> list[str]:
    lines = ["## Newton: the strips' normal problem", "",
             "Newton's early stop off; the largest ``c_{k+1} / c_k^2`` over its final steps (``c_k <= 1e-2``) and its "
             "iterations, then with the early stop (``NEWTON_CONTRACTION``) the iterations and the largest relative "
             "change of Fn (at the approach), of the approach (at the load) and of the peak pressure.", "",
             "| patch | largest c_{k+1}/c_k^2 | Newton iterations | with the early stop | largest change |",
             "|---|---|---|---|---|"]
    cases = []
    for ratio in ((0.2, 1.0, 5.0) if quick else (0.2, 0.5, 1.0, 2.0, 5.0)):
        a, b = 6e-3 * ratio**0.5, 6e-3 / ratio**0.5
        ellipse = rc.EllipticScene.from_semi_axes(1e5, a, b, material=MATERIAL, friction=MU)
        s = np.linspace(-3 * b, 3 * b, 4001)
        gap = PatchGap(s, ellipse.lateral_curvature * s * s, np.full(s.size, ellipse.longitudinal_curvature))
        cases.append((f"quadratic a/b {ratio:g}", gap, 1e5))
    cases += [(patch["name"], patch["scene"].gap, patch["scene"].normal_load) for patch in patches]
    worst = 0.0
    for name, gap, load in cases:
        stopped = [strip_normal(gap, MATERIAL.contact_modulus, normal_load=load)]
        stopped.append(strip_normal(gap, MATERIAL.contact_modulus, approach=stopped[0].approach))
        saved = strip_normal_module.NEWTON_CONTRACTION
        strip_normal_module.NEWTON_CONTRACTION = math.inf
        try:
            full = [strip_normal(gap, MATERIAL.contact_modulus, normal_load=load),
                    strip_normal(gap, MATERIAL.contact_modulus, approach=stopped[0].approach)]
        finally:
            strip_normal_module.NEWTON_CONTRACTION = saved
        ratios = [b / a**2 for contact in full
                  for a, b in zip(contact.newton_steps[:-1], contact.newton_steps[1:], strict=True) if 0.0 < a <= 1e-2]
        largest = max(ratios, default=0.0)
        worst = max(worst, largest)
        change = max(abs(stopped[1].normal_load / full[1].normal_load - 1),
                     abs(stopped[0].approach / full[0].approach - 1),
                     *(abs(x.max_pressure / y.max_pressure - 1) for x, y in zip(stopped, full, strict=True)))
        lines.append(f"| {name} | {largest:.2f} | {len(full[0].newton_steps)}, {len(full[1].newton_steps)} | "
                     f"{len(stopped[0].newton_steps)}, {len(stopped[1].newton_steps)} | {change:.1e} |")
    bound = strip_normal_module.NEWTON_CONTRACTION
    lines += ["", f"Largest ratio {worst:.2f}; ``NEWTON_CONTRACTION`` = {bound:g}.", ""]
    return lines


def alternating_medians(functions, min_seconds: float, min_rounds: int) -> list[float]:
    """Median CPU time of the calling thread (``time.thread_time``) of one call of each function, timed in turn (one
    call of each per round, after one warm-up call each) for at least ``min_rounds`` rounds and ``min_seconds``.  On a
    shared machine the wall time of a call longer than a time slice counts the other jobs' slices too, more the
    longer the call, and a changing load falls on all the functions alike only when they are timed in turn."""
    for function in functions:
        function()
    samples = [[] for _ in functions]
    started = time.perf_counter()
    while len(samples[0]) < min_rounds or time.perf_counter() - started < min_seconds:
        for function, times in zip(functions, samples, strict=True):
            t0 = time.thread_time()
            function()
            times.append(time.thread_time() - t0)
    return [float(np.median(times)) for times in samples]


def time_section(patches, quick: bool) -> list[str]:
    seconds = 0.05 if quick else 1.0
    ellipse = rc.EllipticScene.from_radii(1e5, wheel_rolling_radius=0.46, rail_profile_radius=0.3,
                                          longitudinal_creepage=1e-3, spin_creepage=0.5)
    lines = ["## Time", "",
             "Medians of the CPU time of single calls, each level timed in turn with its yardstick on one ellipse with "
             "spin (the elliptic strips for the strips, the elliptic discretised level's default Richardson pair "
             "60/30 for the discretised level) in the same rounds: \"x strips\" and \"x discretised\" are the "
             "ratios to them, which hold under a changing load where the absolute times do not.", "",
             "| patch | elliptic strips [us] | strips' normal [ms] | strips, no spin [ms] | strips, spin [ms] | "
             "x strips (normal, no spin, spin) | elliptic discretised [s] | discretised default, normal + tangential "
             "[s] | x discretised | elements in contact |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    times = {}
    for patch in patches:
        scene = patch["scene"]
        _, creepages = creepage_set(scene, False)[0]
        no_spin = scene.replace(longitudinal_creepage=creepages[0], lateral_creepage=creepages[0])
        spin = no_spin.replace(spin_creepage=0.5)
        yardstick, normal, fast, fast_spin = alternating_medians(
            [lambda: elliptic_strips(ellipse), lambda s=no_spin: normal_contact(s), lambda s=no_spin: solve_strips(s),
             lambda s=spin: solve_strips(s)], seconds, 20)
        slow_yardstick, slow = alternating_medians(
            [lambda: solve_discretised_3d(ellipse), lambda s=spin: solve_discretised(s)], seconds, 2 if quick else 5)
        times[patch["name"]] = (fast_spin / yardstick, slow / slow_yardstick, fast_spin, slow)
        elements = solve_discretised(spin).info["contact_elements"]
        lines.append(f"| {patch['name']} | {yardstick * 1e6:.0f} | {normal * 1e3:.2f} | {fast * 1e3:.2f} | "
                     f"{fast_spin * 1e3:.2f} | {normal / yardstick:.1f}, {fast / yardstick:.1f}, "
                     f"{fast_spin / yardstick:.1f} | {slow_yardstick:.3f} | {slow:.3f} | {slow / slow_yardstick:.2f} | "
                     f"{elements} |")
    tread, flange = PATCHES[0][0], PATCHES[-1][0]
    if tread in times and flange in times:
        one, two = times[tread], tuple(a + b for a, b in zip(times[tread], times[flange], strict=True))
        lines += ["", "Per wheel (with spin), the sum of its patches' ratios and times:", "",
                  "| wheel | x strips | strips [ms] | x discretised | discretised default [s] |",
                  "|---|---|---|---|---|",
                  f"| one patch (tread) | {one[0]:.1f} | {one[2] * 1e3:.2f} | {one[1]:.2f} | {one[3]:.3f} |",
                  f"| two patches (tread, flange) | {two[0]:.1f} | {two[2] * 1e3:.2f} | {two[1]:.2f} | {two[3]:.3f} |"]
    return lines + [""]


def figure(patches, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, len(patches), figsize=(5 * len(patches), 8), squeeze=False)
    for column, patch in enumerate(patches):
        scene = patch["scene"]
        reference = solve_discretised(scene, element=patch["element"], fields=True)
        field = reference.fields
        top = axes[0, column]
        image = top.pcolormesh(field.y * 1e3, field.x * 1e3, field.pressure / 1e6, shading="nearest", cmap="viridis")
        contact = patch["contact"]
        inside = contact.contact
        top.plot(contact.centres[inside] * 1e3, contact.half_lengths[inside] * 1e3, "w-", lw=1)
        top.plot(contact.centres[inside] * 1e3, -contact.half_lengths[inside] * 1e3, "w-", lw=1,
                 label="strips' outline")
        top.set_title(f"{patch['name']}, {scene.normal_load / 1e3:g} kN")
        top.set_xlabel("s [mm]")
        top.set_ylabel("x [mm]")
        top.legend(loc="lower right", fontsize=7)
        fig.colorbar(image, ax=top, label="p [MPa] (discretised)")
        bottom = axes[1, column]
        centre = np.argmin(np.abs(field.x[:, 0]))
        bottom.plot(field.y[centre] * 1e3, field.pressure.max(axis=0) / 1e6, label="discretised, max over x")
        bottom.plot(contact.centres[inside] * 1e3, contact.peak_pressures[inside] / 1e6, "o-", ms=3,
                    label="strips' p0(s)")
        twin = bottom.twinx()
        s = np.asarray(scene.gap.lateral)
        low, high = contact.extent
        shown = (s > low - 0.3 * (high - low)) & (s < high + 0.3 * (high - low))
        twin.plot(s[shown] * 1e3, np.asarray(scene.gap.lateral_gap)[shown] * 1e6, "k:", label="h(s)")
        twin.set_ylabel("h [um]")
        bottom.set_xlabel("s [mm]")
        bottom.set_ylabel("p [MPa]")
        bottom.legend(loc="upper left", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="coarser references, fewer cases; nothing written")
    parser.add_argument("--profiles", type=Path, default=PROFILES, help="directory of the SIMPACK profiles")
    args = parser.parse_args()
    load = os.getloadavg()[0]
    started = time.perf_counter()
    profiles = Profiles(args.profiles)
    patches = realistic(profiles, args.quick)
    lines = ["# Wheel/rail patches: strips and discretised against the reference", "", *common.machine(load), ""]
    lines += hertz_section(args.quick)
    lines += normal_section(patches, args.quick)
    lines += tangential_section(patches, args.quick)
    lines += convergence_section(patches, args.quick)
    lines += newton_section(patches, args.quick)
    lines += time_section(patches, args.quick)
    lines.append(f"Study time {time.perf_counter() - started:.0f} s.")
    common.publish(lines, "wheelrail_patches.md", args.quick)
    if not args.quick:
        figure(patches, common.RESULTS / "wheelrail_patches.png")
        print(f"wrote {common.RESULTS / 'wheelrail_patches.png'}")


if __name__ == "__main__":
    main()
