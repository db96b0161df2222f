"""Steady solves: time per solve of the closed form, the polynomial method and the discretised solver, and the
accuracy-vs-cost measurements behind the polynomial method's defaults.

Run: ``python benchmarks/bench_steady.py`` (``--quick`` for fewer repeats and smaller studies).  Prints markdown
tables:

A. Median time per solve.  Every ratio is measured in the same run: to the closed-form ``solve`` (Carter), to the
   discretised solver on the same scene at n = 100 elements, and to the discretised solver at the smallest n of
   100, 200, 400, 800 whose T' is within 1e-3 (the project's accuracy target) of the reference.  References: the
   polynomial T' for Coulomb friction (exact to round-off, tests/test_polynomial.py) and the polynomial method
   with 512 nodes for falling friction.  The discretised T' converges at first order (1e-3 needs n = 800); its
   times are for a grid already used once (influence matrices cached), which favours the discretised solver.
B. Corrugation: T', p(x) and q(x) errors against order 80 and time, for orders 2..32 and the default (tolerance
   1e-10), k a = 0.1 .. 10.  With Coulomb friction a, Delta, a* and T' come from closed forms (eqs 28-31), so T' is
   exact at every order; the order only sets the fields, so the default (1e-10 fields) costs almost nothing more.
C. Falling friction: the largest T' error against 256 nodes over creeps (1e-4 .. 5e-3) and surfaces (flat,
   40 mm corrugation) per law, and the time of the slip iteration, for 8 .. 64 nodes; then random laws binned by
   their steepness kappa: the basis of slip.NODES_BY_STEEPNESS (16, 32, 64 nodes).

BLAS is limited to one thread (before numpy loads): the matrices are small, and threads only add overhead on a
shared machine.  Machines here are noisy: medians, and ratios from the same run.

What it prints goes to ``benchmarks/results/steady.md`` with the machine (not after ``--quick``).
"""

import argparse
import math
import platform
from functools import partial

import common  # before numpy: limits BLAS to one thread
import numpy as np

import rollcontact as rc
from rollcontact.line.methods.polynomial import solver
from rollcontact.line.methods.polynomial.slip import solve_velocity_dependent

median_time = partial(common.median_time, warmups=3)  # the polynomial paths fill size-keyed caches

LOAD = 1e6  # N' [N/m]
MU = 0.3
TARGET = 1e-3  # relative accuracy of T' at which the methods are compared
SIZES = (100, 200, 400, 800)
BASE = rc.Scene(normal_load_per_length=LOAD, creep=1e-3, friction=MU)
A_HERTZ = rc.hertz(LOAD, BASE.radius, BASE.material.contact_modulus)[0]
SATURATION = MU * A_HERTZ / BASE.radius


def corrugation(ka: float, position: float = 0.23, creep_fraction: float = 0.4, curvature: float = 0.3) -> rc.Scene:
    """One harmonic with ``k a_Hertz = ka`` and curvature amplitude ``A k^2 = curvature/R`` (one patch)."""
    k = ka / A_HERTZ
    wavelength = 2.0 * math.pi / k
    harmonic = rc.Harmonic.from_wavelength(wavelength, curvature / (BASE.radius * k * k), 0.3)
    return BASE.replace(creep=creep_fraction * SATURATION, axis_position=position * wavelength,
                        surface=rc.Surface(harmonics=(harmonic,)))


README_CORRUGATION = BASE.replace(axis_position=0.003,
                                  surface=rc.Surface(harmonics=(rc.Harmonic.from_wavelength(0.04, 20e-6),)))


def falling(decay: float, creep: float = 1e-3, surface: rc.Surface | None = None) -> rc.Scene:
    return BASE.replace(friction=rc.ExponentialFalling(MU, 0.4, decay), rolling_speed=20.0, creep=creep,
                        surface=surface or rc.Surface(), axis_position=0.002 if surface else 0.0)


def reference_force(scene: rc.Scene) -> float:
    """T' to compare against: the polynomial method, with 512 nodes for velocity-dependent friction."""
    options = {} if scene.friction.is_constant else {"nodes": 512}
    return rc.solve(scene, method="polynomial", **options).tangential_force_per_length


def discretised(scene: rc.Scene, n: int):
    """The discretised solve the tests validate: window +-1.25 a about the patch (edges on element boundaries)."""
    p = rc.solve(scene, method="polynomial")
    a, offset = p.contact_half_width, p.contact_offset
    return lambda: rc.solve(scene, method="discretised", elements=n, window=(offset - 1.25 * a, offset + 1.25 * a))


def discretised_costs(scene: rc.Scene, t_ref: float, repeats: tuple[int, float]):
    """``(time at n = 100, n reaching TARGET, its time, its error)``; the last n of SIZES when none does."""
    t100 = None
    for n in SIZES:
        solve = discretised(scene, n)
        error = abs(solve().tangential_force_per_length / t_ref - 1.0)
        t = median_time(solve, *repeats)
        if n == 100:
            t100 = t
        if error <= TARGET or n == SIZES[-1]:
            return t100, n, t, error
    raise AssertionError("unreachable")


def table_a(quick: bool) -> None:
    fast = (30, 0.2) if quick else (300, 1.0)
    slow = (5, 0.2) if quick else (20, 1.0)
    t_closed = median_time(lambda: rc.solve(BASE, method="closed_form"), *fast)
    estar = BASE.material.contact_modulus
    rows = [("closed form `carter()` (pure function)", median_time(lambda: rc.carter(LOAD, 1e-3, BASE.radius, estar,
                                                                                     MU), *fast), 0.0, None),
            ("closed form via `solve`", t_closed, 0.0, None)]
    cases = [(f"corrugation k a = {ka}", corrugation(ka)) for ka in (0.1, 0.3, 1.0, 3.0, 10.0)]
    cases.append(("corrugation 40 mm / 20 um (README)", README_CORRUGATION))
    cases += [("falling friction, Polach B = 0.6 s/m", falling(0.6)), ("falling friction, B = 30 s/m", falling(30.0)),
              ("falling B = 30 s/m on 40 mm / 20 um corrugation",
               falling(30.0, surface=README_CORRUGATION.surface))]
    for name, scene in cases:
        t_ref = reference_force(scene)
        variants = [("checked", {})]
        if scene.friction.is_constant:
            variants.append(("no checks", {"check": False}))
        disc = discretised_costs(scene, t_ref, slow)
        for label, options in variants:
            r = solver.solve_polynomial(scene, **options)
            assert r.success, f"{name}: {r.message}"
            err = abs(r.tangential_force_per_length / t_ref - 1.0)
            t = median_time(lambda s=scene, o=options: solver.solve_polynomial(s, **o),
                            *(fast if scene.friction.is_constant else slow))
            rows.append((f"polynomial, {name}, {label}", t, err, disc))
    print("## A. Time per solve\n")
    print(f"| case | median [us] | x closed-form solve | x discretised n=100 | discretised n for {TARGET:g} "
          "(its error) | x discretised at that n | polynomial T' error |")
    print("|---|---|---|---|---|---|---|")
    for name, t, err, disc in rows:
        if disc is None:
            print(f"| {name} | {1e6 * t:.1f} | {t / t_closed:.2f} | - | - | - | {err:.0e} |")
            continue
        t100, n, tn, en = disc
        print(f"| {name} | {1e6 * t:.1f} | {t / t_closed:.1f} | {t / t100:.4f} ({1e3 * t100:.2f} ms) | "
              f"{n} ({en:.1e}) | {t / tn:.5f} ({1e3 * tn:.1f} ms) | {err:.0e} |")
    print("\nx: time of the row over the time of the reference in the same run (< 1: faster).  T' errors against "
          "the polynomial method (exact for Coulomb friction; 512 nodes for falling friction).\n")


def table_b(quick: bool) -> None:
    repeats = (30, 0.1) if quick else (100, 0.3)
    orders = (2, 4, 8, 16, 32, None)
    print("## B. Corrugation: order vs accuracy and cost (default: tolerance 1e-10)\n")
    print("| k a | order | T' error | max abs(p - p_ref) / p0 | max abs(q - q_ref) / p0 | median [us] |")
    print("|---|---|---|---|---|---|")
    for ka in (0.1, 0.3, 1.0, 3.0, 10.0):
        scene = corrugation(ka)
        ref = rc.solve(scene, method="polynomial", order=80)
        x = ref.contact_offset + ref.contact_half_width * np.cos(np.pi * (np.arange(401) + 0.5) / 401)
        for order in orders:
            r = rc.solve(scene, method="polynomial", order=order)
            t = median_time(lambda o=order, s=scene: rc.solve(s, method="polynomial", order=o), *repeats)
            ep = float(np.max(np.abs(r.pressure(x) - ref.pressure(x)))) / ref.max_pressure
            eq = float(np.max(np.abs(r.traction(x) - ref.traction(x)))) / ref.max_pressure
            et = abs(r.tangential_force_per_length / ref.tangential_force_per_length - 1.0)
            label = f"default ({r.info['order']})" if order is None else str(order)
            print(f"| {ka} | {label} | {et:.0e} | {ep:.0e} | {eq:.0e} | {1e6 * t:.0f} |")
    print()


def exact_nodes(scene: rc.Scene, nodes: int) -> float:
    """T' of the slip iteration with exactly ``nodes`` patch nodes (``solve`` raises them for steep laws)."""
    normal = rc.solve(scene.replace(friction=scene.friction_coefficient), method="polynomial")
    out = solve_velocity_dependent(normal.info["pressure_coefficients"], normal.contact_half_width,
                                   normal.contact_offset, scene.material.contact_modulus, scene.friction,
                                   scene.rolling_speed, scene.creep, nodes=nodes)
    return out["tangential_force_per_length"] if out["converged"] else math.nan


def steepness(scene: rc.Scene) -> float:
    """``kappa = |dmu/dv(0)| V xi_sat / mu_s`` with the Hertz saturation creep (velocity_friction's Accuracy)."""
    return abs(float(scene.friction.derivative(0.0))) * scene.rolling_speed * SATURATION / MU


def table_c(quick: bool) -> None:
    laws = {"exponential B = 0.6 (Polach)": rc.ExponentialFalling(MU, 0.4, 0.6),
            "exponential B = 3": rc.ExponentialFalling(MU, 0.4, 3.0),
            "exponential B = 30": rc.ExponentialFalling(MU, 0.4, 30.0),
            "exponential B = 100": rc.ExponentialFalling(MU, 0.4, 100.0),
            "rational": rc.RationalFalling(MU, 0.15, 0.02), "linear": rc.LinearFalling(MU, 0.2, 2.0)}
    surfaces = (rc.Surface(), README_CORRUGATION.surface)
    creeps = (1e-4, 1e-3, 5e-3) if quick else (1e-4, 3e-4, 1e-3, 1.3e-3, 2e-3, 5e-3)
    nodes = (8, 12, 16, 24, 32, 64)
    errors, kappas = {}, {}
    for name, law in laws.items():
        for surface in surfaces:
            for creep in creeps:
                scene = BASE.replace(friction=law, rolling_speed=20.0, creep=creep, surface=surface,
                                     axis_position=0.002)
                kappas[name] = steepness(scene)
                ref = exact_nodes(scene, 256)
                for m in nodes + ("default",):
                    t = rc.solve(scene, method="polynomial").tangential_force_per_length if m == "default" else \
                        exact_nodes(scene, m)
                    errors[(name, m)] = max(errors.get((name, m), 0.0), abs(t / ref - 1.0))
    repeats = (5, 0.1) if quick else (20, 0.5)
    steep = falling(30.0)
    normal = rc.solve(steep.replace(friction=MU), method="polynomial")
    args = (normal.info["pressure_coefficients"], normal.contact_half_width, normal.contact_offset,
            steep.material.contact_modulus, steep.friction, steep.rolling_speed, steep.creep)
    times = {m: median_time(lambda m=m: solve_velocity_dependent(*args, nodes=m), *repeats) for m in nodes}
    print("## C. Falling friction: nodes vs accuracy and cost\n")
    print(f"Largest abs(T'/T'_256 - 1) over creeps {creeps} on a flat and a 40 mm / 20 um corrugated surface, "
          "V = 20 m/s, with exactly the nodes given (the corrugated pressure has 8 terms, so at least 16 nodes "
          "there); 'default': what `solve` uses (16, 32 or 64 by kappa).  Time of the slip iteration alone, "
          "B = 30 s/m, xi = 1e-3, flat.\n")
    print("| law | kappa | " + " | ".join(f"{m} nodes" for m in nodes) + " | default |")
    print("|---|---|" + "---|" * (len(nodes) + 1))
    for name in laws:
        print(f"| {name} | {kappas[name]:.2g} | " + " | ".join(f"{errors[(name, m)]:.0e}" for m in nodes)
              + f" | {errors[(name, 'default')]:.0e} |")
    print("| slip iteration, median [us] | | " + " | ".join(f"{1e6 * times[m]:.0f}" for m in nodes) + " | |\n")
    # random laws, creeps and surfaces, binned by steepness: the basis of NODES_BY_STEEPNESS
    rng = np.random.default_rng(5)
    bins = ((0.0, 0.1), (0.1, 0.3), (0.3, 1.0), (1.0, 3.0), (3.0, math.inf))
    worst = {}
    for _ in range(40 if quick else 160):
        kind = rng.integers(0, 3)
        if kind == 0:
            law = rc.ExponentialFalling(MU, rng.uniform(0.05, 0.9), 10 ** rng.uniform(-1, 2.5))
        elif kind == 1:
            law = rc.RationalFalling(MU, rng.uniform(0.05, 0.28), 10 ** rng.uniform(-3, 0))
        else:
            law = rc.LinearFalling(MU, rng.uniform(0.05, 0.28), 10 ** rng.uniform(-1, 1.5))
        surface = rc.Surface() if rng.random() < 0.5 else rc.Surface(harmonics=(rc.Harmonic.from_wavelength(
            rng.uniform(0.02, 0.1), rng.uniform(1e-6, 2e-5), rng.uniform(0, 6)),))
        scene = BASE.replace(friction=law, rolling_speed=10 ** rng.uniform(0, 1.7), surface=surface,
                             creep=rng.choice([-1, 1]) * SATURATION * 10 ** rng.uniform(-2, 0.5),
                             axis_position=rng.uniform(0, 0.02))
        ref = exact_nodes(scene, 256)
        b = next(b for b in bins if b[0] <= steepness(scene) < b[1])
        worst.setdefault(b, [0, {}])[0] += 1
        for m in (16, 32, 64):
            e = abs(exact_nodes(scene, m) / ref - 1.0)
            worst[b][1][m] = max(worst[b][1].get(m, 0.0), e)
    print("Random exponential, rational and linear laws, V = 1-50 m/s, creep 0.01-3 saturation, flat or corrugated: "
          "largest abs(T'/T'_256 - 1) per steepness bin.\n")
    print("| kappa | cases | 16 nodes | 32 nodes | 64 nodes |")
    print("|---|---|---|---|---|")
    for b in bins:
        if b in worst:
            count, e = worst[b]
            print(f"| [{b[0]:g}, {b[1]:g}) | {count} | {e[16]:.0e} | {e[32]:.0e} | {e[64]:.0e} |")
    print()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats, smaller studies")
    parser.add_argument("--tables", default="abc", help="which tables to print, e.g. 'a' (default: abc)")
    args = parser.parse_args()
    print(f"# Steady solves ({platform.processor() or platform.machine()}, Python {platform.python_version()}, "
          f"numpy {np.__version__}, one BLAS thread)\n")
    for letter, table in (("a", table_a), ("b", table_b), ("c", table_c)):
        if letter in args.tables:
            table(args.quick)


if __name__ == "__main__":
    common.run_and_publish(main, "steady.md")
