"""Building what a run needs: ``ensure_fmus`` asks ``build_fmu.py --if-stale`` for exactly each FMU of the system
in its variant (the command lines recorded, no build), once per process while the FMU is there; and ``summarise``."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import rollcontact_cosim.fmus as fmus
from rollcontact_cosim.fmus import BUILD_FMU, CosimResult, ensure_fmus, summarise
from rollcontact_cosim.scenes import load_cosim_scene


@pytest.fixture
def builds(monkeypatch):
    """The build commands ensure_fmus runs (each "builds" its FMU: an empty file), none of them really run."""
    commands = []

    def fake_run(command, **options):
        commands.append(command[2:])
        arguments = list(command)
        dest = Path(arguments[arguments.index("--dest") + 1])
        dest = dest / "fmi3" if arguments[arguments.index("--fmi") + 1] == "3" else dest
        name = arguments[3] if arguments[2] == "--only" else f"RollingContact3D_{arguments[3]}"
        dest.mkdir(parents=True, exist_ok=True)
        (dest / f"{name}.fmu").write_bytes(b"")
        return subprocess.CompletedProcess(command, 0, "", "")

    monkeypatch.setattr(fmus.subprocess, "run", fake_run)
    monkeypatch.setattr(fmus, "_checked", set())
    return commands


def test_the_wheel_rig_fmus_are_built_if_stale_one_by_one(builds, tmp_path):
    paths = ensure_fmus(tmp_path)
    dest = str(tmp_path.resolve())
    assert builds == [("--only", "RollingContact2D", "--if-stale", "--fmi", "2", "--dest", dest),
                      ("--only", "WheelRig", "--if-stale", "--fmi", "2", "--dest", dest)], builds
    assert paths == {"RollingContact2D": tmp_path / "RollingContact2D.fmu", "WheelRig": tmp_path / "WheelRig.fmu"}
    ensure_fmus(tmp_path)
    assert len(builds) == 2, "checked once per process while the FMUs are there"
    (tmp_path / "WheelRig.fmu").unlink()
    ensure_fmus(tmp_path)
    assert builds[2:] == [builds[1]], "a missing FMU is built again"


def test_each_variant_is_asked_for_with_its_options(builds, tmp_path):
    ensure_fmus(tmp_path, fmi_version=3)
    ensure_fmus(tmp_path, integer_codes=True)
    dest = str(tmp_path.resolve())
    assert builds == [("--only", "RollingContact2D", "--if-stale", "--fmi", "3", "--dest", dest),
                      ("--only", "WheelRig", "--if-stale", "--fmi", "3", "--dest", dest),
                      ("--only", "RollingContact2D", "--if-stale", "--fmi", "2", "--integer-codes", "--dest",
                       f"{dest}/integer_codes"),
                      ("--only", "WheelRig", "--if-stale", "--fmi", "2", "--integer-codes", "--dest",
                       f"{dest}/integer_codes")], builds
    with pytest.raises(ValueError, match="integer-codes build .* is an FMI 2.0 build"):
        ensure_fmus(tmp_path, integer_codes=True, fmi_version=3)


def test_the_wheelset_scene_asks_for_its_host_and_its_two_contact_variant(builds, tmp_path):
    paths = ensure_fmus(tmp_path, integer_codes=True, system=load_cosim_scene("wheelset_hunting").system)
    dest = f"{tmp_path.resolve()}/integer_codes"
    assert builds == [("--contacts", "2", "--if-stale", "--fmi", "2", "--integer-codes", "--dest", dest),
                      ("--only", "Wheelset", "--if-stale", "--fmi", "2", "--integer-codes", "--dest", dest)], builds
    assert paths == {"RollingContact3D": tmp_path / "integer_codes" / "RollingContact3D_2.fmu",
                     "Wheelset": tmp_path / "integer_codes" / "Wheelset.fmu"}


def test_a_failed_build_says_what_the_builder_said(monkeypatch, tmp_path):
    monkeypatch.setattr(fmus, "_checked", set())
    monkeypatch.setattr(fmus.subprocess, "run", lambda command, **options: subprocess.CompletedProcess(
        command, 1, "", "no such model"))
    with pytest.raises(RuntimeError, match="build_fmu.py --only RollingContact2D --if-stale .* failed:\n\nno such"):
        ensure_fmus(tmp_path)


def test_the_build_command_is_the_build_contracts():
    """``build_fmu.py --help`` offers every option ensure_fmus passes."""
    done = subprocess.run([sys.executable, str(BUILD_FMU), "--help"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    for option in ("--only", "--contacts", "--fmi", "--integer-codes", "--if-stale", "--dest"):
        assert option in done.stdout, f"build_fmu.py --help lacks {option}"


def test_the_summary_is_the_peak_adhesion_and_the_cost():
    values = np.zeros(3, dtype=[("time", float), ("WheelRig.creep", float),
                                ("RollingContact2D.traction_coefficient", float)])
    values["time"], values["WheelRig.creep"] = (0.0, 0.1, 0.2), (1e-3, 2e-3, 3e-3)
    values["RollingContact2D.traction_coefficient"] = (0.1, -0.3, 0.2)
    s = summarise(CosimResult("x", "fmpy", "jacobi", 0.1, values, 2, 1e-3, True, "completed"))
    assert s == {"peak_traction_coefficient": -0.3, "creep_at_peak": 2e-3, "time_at_peak": 0.1, "steps": 2,
                 "wall_time": 1e-3, "wall_time_per_step_us": 500.0}, s
