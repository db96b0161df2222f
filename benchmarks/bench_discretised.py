"""Benchmark of the discretised solver: median time per solve and error vs the closed forms, n = 50 ... 800.

Run as ``python benchmarks/bench_discretised.py``.  Prints a markdown table; asserts nothing.  BLAS is limited
to one thread (set before numpy loads) so the times compare with CONTACT's single-core figures (physics.md
section 7: 2D Carter about 2 ms with 100 elements, 0.29 s with 800; velocity-dependent cases 7-20 ms) and do
not suffer from thread oversubscription on a shared machine.  Machines are noisy: medians of repeated runs.

What it prints goes to ``benchmarks/results/discretised.md`` with the machine (not after ``--quick``).
"""

import math

import common  # before numpy: limits BLAS to one thread

import rollcontact as rc
from rollcontact.line.carter import carter
from rollcontact.line.halfspace.grid import automatic_grid
from rollcontact.line.halfspace.solver import TransientSolver
from rollcontact.line.hertz import hertz
from rollcontact.line.methods.discretised.steady import solve_discretised

LOAD = 1e7  # N' [N/m]
MU = 0.3
SCENE = rc.Scene(normal_load_per_length=LOAD, creep=0.0, friction=MU)
ESTAR = SCENE.material.contact_modulus
A_H, P0 = hertz(LOAD, SCENE.radius, ESTAR)
CREEP = 0.5 * MU * A_H / SCENE.radius  # half the Carter saturation creep
FALLING = SCENE.replace(friction=rc.ExponentialFalling(MU, 0.4, 0.6), rolling_speed=30.0, creep=CREEP)
CONTACT_MS = {100: 2.0, 800: 290.0}  # CONTACT's quoted times [ms], 2D Carter on one core
SIZES = (50, 100, 200, 400, 800)


def contact_time_ms(n):
    """CONTACT's Carter time, interpolated as a power law through its two published points."""
    exponent = math.log(CONTACT_MS[800] / CONTACT_MS[100]) / math.log(8.0)
    return CONTACT_MS[100] * (n / 100) ** exponent


def normal_only(n):
    grid = automatic_grid(SCENE, n)
    return TransientSolver.from_scene(SCENE, grid).normal(LOAD)


def main():
    t_exact = carter(LOAD, CREEP, SCENE.radius, ESTAR, MU)[0]
    reference_falling = solve_discretised(FALLING, elements=1600).tangential_force_per_length
    rows = []
    for n in SIZES:
        normal = normal_only(n)
        p0_error = normal.pressure.max() / P0 - 1
        t_normal = common.median_time(common.cold(lambda n=n: normal_only(n)))

        steady = solve_discretised(SCENE.replace(creep=CREEP), elements=n)
        t_error = steady.tangential_force_per_length / t_exact - 1
        t_steady = common.median_time(common.cold(lambda n=n: solve_discretised(SCENE.replace(creep=CREEP),
                                                                                 elements=n)))
        t_warm = common.median_time(lambda n=n: solve_discretised(SCENE.replace(creep=CREEP), elements=n))

        falling = solve_discretised(FALLING, elements=n)
        f_error = falling.tangential_force_per_length / reference_falling - 1
        t_falling = common.median_time(common.cold(lambda n=n: solve_discretised(FALLING, elements=n)))

        solver = TransientSolver.from_scene(SCENE, elements=n)
        pressure = solver.normal(LOAD).pressure
        h = solver.grid.element_width
        state = solver.initial_state()
        for _ in range(2 * n):  # near the steady state, where the stick set and its factorisation repeat
            state, _ = solver.step(state, pressure, h, creep=CREEP)
        t_step = common.median_time(lambda solver=solver, state=state, pressure=pressure, h=h:
                             solver.step(state, pressure, h, creep=CREEP))

        rows.append((n, t_normal, p0_error, t_steady, t_warm, t_error, contact_time_ms(n) / (1e3 * t_steady),
                     t_falling, f_error, t_step, steady.success and falling.success))
    print("Discretised solver, median time per solve (one BLAS thread); errors vs Hertz p0, Carter T' "
          f"(xi = {CREEP:.3g}) and, for falling friction, vs n = 1600.\n")
    print("| n | normal [ms] | p0 error | steady Coulomb [ms] | same grid again [ms] | T' error | CONTACT / ours | "
          "steady falling mu [ms] | T' error (vs n=1600) | transient step [ms] | success |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for n, tn, ep, ts, tw, et, ratio, tf, ef, tt, ok in rows:
        print(f"| {n} | {1e3 * tn:.2f} | {ep:.1e} | {1e3 * ts:.2f} | {1e3 * tw:.2f} | {et:.1e} | {ratio:.1f} | "
              f"{1e3 * tf:.1f} | {ef:.1e} | {1e3 * tt:.3f} | {ok} |")
    print("\nTimes are first solves (influence matrices built, nothing cached) except 'same grid again', where the"
          " matrices and factorisations of an earlier solve on the grid are reused (creep curves, time loops).")
    print("CONTACT / ours: CONTACT's Carter time (2 ms at n = 100, 0.29 s at n = 800, power law between) over ours;"
          " > 1 means faster.  CONTACT's velocity-dependent 2D cases take 7-20 ms.")


if __name__ == "__main__":
    common.run_and_publish(main, "discretised.md")
