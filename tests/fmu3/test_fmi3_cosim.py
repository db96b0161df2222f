"""The fmpy co-simulation master on the FMI 3.0 pair, the main job's ``--fmi 3`` and ``build_fmu.py --fmi``.

The regression scenes pass with the FMI 3.0 pair as with the FMI 2.0 pair, and give the same rows bit for bit (same
process, same calls).  libcosim cannot load FMI 3.0 FMUs (libcosimpy 0.0.6 crashes adding one): the master refuses
that combination with a one-line error before loading anything.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from rollcontact_cosim.__main__ import main as main_job
from rollcontact_cosim.master import run_cosimulation
from rollcontact_cosim.reference import compare, read_reference
from rollcontact_cosim.scenes import SCENE_NAMES, load_cosim_scene

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("name", SCENE_NAMES)
def test_the_regression_scenes_pass_with_the_fmi3_pair_bit_for_bit_as_with_fmi2(fmu_folders, name):
    scene = load_cosim_scene(name)
    runs = {version: run_cosimulation(scene, fmu_dir=fmu_folders[2], fmi_version=version) for version in (2, 3)}
    assert runs[3].success, runs[3].message
    reference, header = read_reference(scene.reference_path)
    problems = compare(runs[3].values, reference, scene.band)
    assert not problems, f"{name} (FMI 3.0) against {scene.reference_path.name} ({header.get('date')}): {problems}"
    assert runs[3].values.dtype == runs[2].values.dtype and np.array_equal(runs[3].values, runs[2].values), \
        f"{name}: the FMI 3.0 pair's rows differ from the FMI 2.0 pair's"


def test_a_refused_fmi3_step_ends_the_run_with_the_reason(fmu_folders):
    result = run_cosimulation("carter_sanity", fmu_dir=fmu_folders[2], fmi_version=3,
                              contact={"friction_coefficient": -1.0})
    assert not result.success and result.steps == 0, result.message
    assert "RollingContact2D" in result.message and "friction_coefficient" in result.message, result.message


def test_the_main_job_runs_fmi3_and_refuses_it_on_libcosim_in_one_line(fmu_folders, tmp_path, capsys):
    png = tmp_path / "carter.png"
    assert main_job(["carter_sanity", "--fmi", "3", "--plot", str(png), "--fmu-dir", str(fmu_folders[2])]) == 0
    out = capsys.readouterr().out
    assert "fmpy master (FMI 3.0)" in out and "peak adhesion T/N = 0.15" in out and "500 macro steps" in out, out
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main_job(["carter_sanity", "--fmi", "3", "--master", "libcosim", "--fmu-dir", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "libcosim cannot load FMI 3.0 FMUs" in err, err
    assert not (tmp_path / "fmi3").exists(), "nothing is built for a run that cannot start"
    with pytest.raises(ValueError, match="fmi_version = 4 is unknown"):
        run_cosimulation("carter_sanity", fmu_dir=fmu_folders[2], fmi_version=4)


def builder():
    spec = importlib.util.spec_from_file_location("rollcontact_build_fmu_for_tests", ROOT / "build_fmu.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_build_fmu_builds_fmi2_by_default_and_fmi3_on_request(capsys):
    build_fmu = builder()
    assert build_fmu.fmi_versions("3,2") == (2, 3) and build_fmu.fmi_versions("2") == (2,)
    for bad in ("4", "", "2,x"):
        with pytest.raises(Exception, match="give 2, 3 or 2,3"):
            build_fmu.fmi_versions(bad)
    assert build_fmu.fmi_dest("models", 2).as_posix() == "models"
    assert build_fmu.fmi_dest("models", 3).as_posix() == "models/fmi3"
    with pytest.raises(SystemExit) as done:
        build_fmu.main(["--integer-codes", "--fmi", "2,3"])
    assert done.value.code == 2 and "--integer-codes builds FMI 2.0 only" in capsys.readouterr().err
    assert all(fmu.variant(fmi=3) == fmu.variant(fmi=2) | ({"arrays": True} if fmu.arrays else {})
               for fmu in build_fmu.FMUS.values()), "an FMI 3.0 variant of every FMU"
