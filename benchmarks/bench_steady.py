"""Median time per steady solve: closed form and the polynomial method at several orders and numbers of harmonics.

Run: ``python benchmarks/bench_steady.py``.  Prints a markdown table; ratios are measured in the same run
(against the closed-form `solve` and against the field's compiled reference code CONTACT, whose 100-element 2D
Carter case takes about 2 ms on this machine class, physics.md section 7).  Machines here are noisy: medians.
"""

from __future__ import annotations

import platform
import statistics
import time

import numpy as np

import rollcontact as rc
from rollcontact import polynomial

CONTACT_CARTER_100 = 2e-3  # s, physics.md section 7


def median_time(fn, repeat: int = 400, warmup: int = 20) -> float:
    for _ in range(warmup):
        fn()
    samples = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        samples.append(time.perf_counter() - t0)
    return statistics.median(samples)


def corrugated(n_harmonics: int, creep: float = 1e-3) -> rc.Scene:
    """N' = 1 MN/m, R = 0.46 m; harmonics at 40, 60, 80, ... mm with 20/n um each (one patch everywhere)."""
    harmonics = tuple(rc.Harmonic.from_wavelength(0.04 + 0.02 * m, 20e-6 / n_harmonics, 0.3 * m)
                      for m in range(n_harmonics))
    return rc.Scene(normal_load_per_length=1e6, creep=creep, axis_position=0.003,
                    surface=rc.Surface(harmonics=harmonics))


def main() -> None:
    carter_scene = rc.Scene(normal_load_per_length=1e6, creep=1e-3)
    estar = carter_scene.material.contact_modulus
    rows = []
    t_closed = median_time(lambda: rc.solve(carter_scene, method="closed_form"))
    rows.append(("closed form `carter()` (pure function)", "-",
                 median_time(lambda: rc.carter(1e6, 1e-3, 0.46, estar, 0.3), repeat=2000), 0.0))
    rows.append(("closed form via `solve`", "-", t_closed, 0.0))
    ref = rc.solve(carter_scene, method="closed_form")
    for order in (2, 8, 32):
        r = rc.solve(carter_scene, method="polynomial", order=order)
        err = abs(r.tangential_force_per_length - ref.tangential_force_per_length) / ref.tangential_force_per_length
        rows.append((f"polynomial, Hertz profile, order {order}", "0",
                     median_time(lambda o=order: rc.solve(carter_scene, method="polynomial", order=o)), err))
    for n_h in (1, 2, 4):
        scene = corrugated(n_h)
        ref_h = rc.solve(scene, method="polynomial", order=80)
        for label, kwargs in (("auto order, checked", {}), ("auto order, no validity checks", {"check": False}),
                              ("order 32, checked", {"order": 32})):
            r = polynomial.solve_polynomial(scene, **kwargs)
            x = r.contact_offset + r.contact_half_width * np.linspace(-0.99, 0.99, 199)
            err = float(np.max(np.abs(r.traction(x) - ref_h.traction(x))) / ref_h.max_pressure)
            rows.append((f"polynomial, corrugation, {label} (order {r.info['order']})", str(n_h),
                         median_time(lambda s=scene, k=kwargs: polynomial.solve_polynomial(s, **k)), err))
    r = rc.solve(corrugated(1), method="polynomial", basis="monomial", order=12)
    rows.append(("polynomial, corrugation, monomial basis order 12", "1",
                 median_time(lambda: rc.solve(corrugated(1), method="polynomial", basis="monomial", order=12)),
                 float(abs(r.tangential_force_per_length - rc.solve(corrugated(1)).tangential_force_per_length)
                       / ref.tangential_force_per_length)))

    print(f"# Steady solves ({platform.processor() or platform.machine()}, Python {platform.python_version()}, "
          f"numpy {np.__version__})\n")
    print("| case | harmonics | median time [us] | x closed-form solve | x CONTACT 100-el Carter (2 ms) | error |")
    print("|---|---|---|---|---|---|")
    for name, nh, t, err in rows:
        print(f"| {name} | {nh} | {t * 1e6:.1f} | {t / t_closed:.2f} | {t / CONTACT_CARTER_100:.4f} | {err:.1e} |")
    print("\nerror: Carter rows: relative error of T'; corrugation rows: max |q - q_ref| / p0 against order 80; "
          "monomial row: relative error of T' against the Chebyshev solution.")


if __name__ == "__main__":
    main()
