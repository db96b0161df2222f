"""Shared test configuration and the FMU built once per test run.

One BLAS thread: the discretised solver's small dense solves are 10-100x slower with OpenBLAS threads on the
2-core machines here (it must be set before numpy is imported).
"""

import os
from pathlib import Path

import pytest

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from fmu_checks import run_build  # noqa: E402 - after the thread setting: fmpy imports numpy

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def fmu_path(tmp_path_factory) -> Path:
    """``python build_fmu.py --dest <tmp>``, once per test run (the FMU tests of every module share it)."""
    dest = tmp_path_factory.mktemp("fmu")
    out = run_build(dest=dest, timeout=120)
    path = dest / "RollingContact2D.fmu"
    assert path.is_file(), f"build_fmu.py did not write {path}: {out}"
    return path


@pytest.fixture(scope="session")
def contact_variants(tmp_path_factory) -> dict[int, Path]:
    """``build_fmu.py --fmi 2,3 --contacts 1`` and ``--contacts 3`` (both contact FMUs, one contact and three), once
    per test run into one folder: FMI version -> folder."""
    dest = tmp_path_factory.mktemp("contact_variants")
    for contacts in (1, 3):
        run_build("--fmi", "2,3", "--contacts", str(contacts), dest=dest)
    return {2: dest, 3: dest / "fmi3"}


@pytest.fixture(scope="session")
def fmu_folders(tmp_path_factory) -> dict[int, Path]:
    """``python build_fmu.py --all --dest <tmp>`` and ``--fmi 3 --all`` (each in a fresh process, as the docs give
    them) once per test run: version -> folder of the five FMUs (RollingContact2D, WheelRig, Wheelset,
    RollingContact3D, WheelsetContact; FMI 3.0 below ``fmi3/``)."""
    dest = tmp_path_factory.mktemp("fmi2_and_fmi3")
    out = run_build("--all", dest=dest) + run_build("--fmi", "3", "--all", dest=dest)
    folders = {2: dest, 3: dest / "fmi3"}
    for folder in folders.values():
        assert {p.name for p in folder.glob("*.fmu")} == {"RollingContact2D.fmu", "WheelRig.fmu", "Wheelset.fmu",
                                                        "RollingContact3D.fmu", "WheelsetContact.fmu"}, out
    return folders


@pytest.fixture(scope="session")
def eight_contacts(tmp_path_factory) -> dict[int, Path]:
    """``build_fmu.py --contacts 8`` and ``--fmi 3 --contacts 8`` (RollingContact2D_8 and RollingContact3D_8, each
    command in a fresh process) once per test run: FMI version -> folder."""
    dest = tmp_path_factory.mktemp("eight_contacts")
    run_build("--contacts", "8", dest=dest)
    run_build("--fmi", "3", "--contacts", "8", dest=dest)
    return {2: dest, 3: dest / "fmi3"}


@pytest.fixture(scope="session")
def integer_codes(tmp_path_factory) -> Path:
    """``build_fmu.py --integer-codes`` (RollingContact2D) and ``--contacts 2 --integer-codes`` (RollingContact2D_2,
    RollingContact3D_2), FMI 2.0 with plain Integer variables for the enumerations, once per test run into one
    folder."""
    dest = tmp_path_factory.mktemp("integer_codes")
    for args in (["--integer-codes"], ["--contacts", "2", "--integer-codes"]):
        run_build(*args, dest=dest)
    return dest


@pytest.fixture(scope="session")
def unzipped(fmu_path, tmp_path_factory) -> Path:
    from fmpy import extract

    return Path(extract(fmu_path, unzipdir=tmp_path_factory.mktemp("unzipped")))


@pytest.fixture(scope="session")
def description(unzipped):
    from fmpy import read_model_description

    return read_model_description(str(unzipped))
