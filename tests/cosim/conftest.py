"""Fixtures of the co-simulation tests: the wheel rig scenes' FMUs built once per test run into a temporary folder,
and the runs of the fmpy master on them, each distinct run once.

This process imports ``rollcontact`` and ``rollcontact_cosim`` itself, so the FMU instances run those copies rather
than the bundled ones.
"""

from __future__ import annotations

import pytest

from rollcontact_cosim.master import ensure_fmus, run_cosimulation


@pytest.fixture(scope="session")
def fmu_dir(tmp_path_factory):
    """The wheel rig scenes' FMUs (WheelRig, RollingContact2D), built by ``build_fmu.py`` into a temporary folder
    once per test run."""
    folder = tmp_path_factory.mktemp("cosim_fmus")
    paths = ensure_fmus(folder)
    assert all(p.is_file() for p in paths.values()), f"build_fmu.py did not write {paths}"
    return folder


@pytest.fixture(scope="session")
def run(fmu_dir):
    """``run(scene, **options)``: run_cosimulation with the test run's FMUs, each distinct run once."""
    done = {}

    def cached(scene, **options):
        key = (scene, repr(sorted(options.items())))
        if key not in done:
            done[key] = run_cosimulation(scene, fmu_dir=fmu_dir, **options)
            assert done[key].success, f"{scene} {options}: {done[key].message}"
        return done[key]

    return cached
