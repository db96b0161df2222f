"""The hunting scene co-simulated through fmpy (rollcontact_cosim.wheelset.cosim): the Wheelset host FMU with one
RollingContact3D FMU of two contacts equals the in-process run with the contact FMU's own model bit for bit, and at
low speed its kinematic oscillation has Klingel's wavelength."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rollcontact_cosim.wheelset import WheelsetParameters, simulate
from rollcontact_cosim.wheelset.cosim import LibraryContactLaw, contact_parameters, cosimulate
from rollcontact_cosim.wheelset.stability import klingel_wavelength
from rollcontact_cosim.wheelset.study import wavelength

ROOT = Path(__file__).resolve().parents[3]


@pytest.fixture(scope="module")
def fmu_dir(tmp_path_factory) -> Path:
    dest = tmp_path_factory.mktemp("wheelset_cosim")
    for args in (["--only", "Wheelset"], ["--contacts", "2"]):
        done = subprocess.run([sys.executable, str(ROOT / "build_fmu.py"), *args, "--dest", str(dest)],
                              capture_output=True, text=True, timeout=600)
        assert done.returncode == 0, f"build_fmu.py {args} failed:\n{done.stdout}\n{done.stderr}"
    return dest


@pytest.mark.parametrize("method", (1, 3), ids=("linear", "strips"))
def test_the_cosimulation_is_the_in_process_run_bit_for_bit(fmu_dir, method):
    p = WheelsetParameters(speed=40.0, initial_lateral_displacement=2e-3)
    contact = contact_parameters(p, method=method)
    times, states = cosimulate(p, 0.2, 1e-3, fmu_dir, contact)
    reference_times, reference = simulate(p, LibraryContactLaw(contact), 0.2, 1e-3)
    assert np.array_equal(times, reference_times)
    assert np.array_equal(states, reference), f"largest difference {np.max(np.abs(states - reference))}"
    assert np.ptp(states[:, 0]) > 1e-4, "the wheelset moves"


def test_the_kinematic_oscillation_has_klingels_wavelength(fmu_dir):
    """At 5 m/s without suspension, started on the kinematic motion: within 2 % of 2 pi sqrt(r0 e / lambda)."""
    p0 = WheelsetParameters()
    speed = 5.0
    p = dataclasses.replace(p0, speed=speed, lateral_stiffness=0.0, yaw_stiffness=0.0, initial_lateral_velocity=0.0,
                            initial_yaw_rate=-speed * p0.conicity * p0.initial_lateral_displacement
                            / (p0.contact_half_distance * p0.rolling_radius))
    length = klingel_wavelength(p)
    step = length / speed / 200
    times, states = cosimulate(p, 6 * 200 * step, step, fmu_dir)
    measured = wavelength(times, states[:, 0], speed)
    assert abs(measured / length - 1.0) < 0.02, f"wavelength {measured:.4f} m against Klingel's {length:.4f} m"


def test_the_cosimulated_hunting_changes_sign_within_4_percent_of_the_linear_critical_speed(fmu_dir):
    """The eigenvalues of the linearised wheelset with the contact FMU's own Jacobian at zero creepage predict the
    critical speed; the co-simulation's decay rate of y is negative 4 % below it and positive 4 % above."""
    from rollcontact_cosim.wheelset.stability import critical_speed, linearised
    from rollcontact_cosim.wheelset.study import decay_rate

    p0 = WheelsetParameters()
    predicted = critical_speed(p0, linearised(LibraryContactLaw(contact_parameters(p0)), p0))
    rates = []
    for speed in (0.96 * predicted, 1.04 * predicted):
        p = dataclasses.replace(p0, speed=speed)
        period = klingel_wavelength(p) / speed
        times, states = cosimulate(p, 12 * period, period / 200, fmu_dir)
        rates.append(decay_rate(times, states[:, 0], start=2 * period)[0])
    assert rates[0] < 0.0 < rates[1], f"decay rates {rates} 1/s at 0.96 and 1.04 x {predicted:.2f} m/s"


def test_the_cosimulated_sweep_finds_the_critical_speed_of_the_eigenvalues(fmu_dir):
    """The co-simulated decay rates follow the least-damped eigenvalue's real part, and their zero crossing is the
    eigenvalues' critical speed within 2 % (the issue asks 5 %)."""
    from rollcontact_cosim.wheelset.cosim import cosim_hunting_sweep

    sweep = cosim_hunting_sweep([50.0, 60.0, 70.0, 80.0], fmu_dir, periods=10, n_workers=0)
    for run in sweep.runs:
        assert abs(run.simulated - run.predicted) < 0.01, f"{run.speed} m/s: {run.simulated} against {run.predicted}"
    assert abs(sweep.error) < 0.02, f"co-simulation {sweep.simulated_critical_speed} against eigenvalues " \
        f"{sweep.predicted_critical_speed} m/s"


@pytest.mark.slow
def test_the_cosimulated_sweep_on_dask_workers_equals_the_serial_one(fmu_dir):
    pytest.importorskip("dask.distributed")
    from dask.distributed import Client

    from rollcontact_cosim.sweep import local_cluster
    from rollcontact_cosim.wheelset.cosim import cosim_hunting_sweep

    speeds = [55.0, 75.0]
    with local_cluster(2) as cluster, Client(cluster) as client:
        distributed = cosim_hunting_sweep(speeds, fmu_dir, periods=6, client=client)
    assert distributed == cosim_hunting_sweep(speeds, fmu_dir, periods=6, n_workers=0), \
        "FMUs in worker processes give the serial results bit for bit"


@pytest.mark.slow
def test_the_cosimulated_reference_results_are_the_sweeps(fmu_dir, tmp_path):
    from rollcontact_cosim.wheelset.cosim import REFERENCES, write_cosim_reference

    fresh = write_cosim_reference(fmu_dir, tmp_path / "reference.md")
    assert fresh.read_text() == REFERENCES["fmpy"].read_text(), \
        "models/cosim/wheelset_hunting_cosim.md is not what the sweep gives: rerun write_cosim_reference()"


@pytest.fixture(scope="module")
def integer_codes_dir(fmu_dir, integer_codes, tmp_path_factory) -> Path:
    """The Wheelset FMU and the integer-codes build of RollingContact3D_2 (libcosim lists no enumerations; the
    test run's ``--contacts 2 --integer-codes`` build, ``tests/conftest.py``), in the ``integer_codes/`` folder where
    the libcosim master looks for them (below the folder it is given)."""
    dest = tmp_path_factory.mktemp("wheelset_osp") / "integer_codes"
    dest.mkdir()
    for name in ("RollingContact2D_2.fmu", "RollingContact3D_2.fmu"):
        (dest / name).write_bytes((integer_codes / name).read_bytes())
    (dest / "Wheelset.fmu").write_bytes((fmu_dir / "Wheelset.fmu").read_bytes())
    return dest


def test_libcosim_runs_the_jacobi_sequence_of_the_in_process_run(integer_codes_dir):
    """libcosim's fixed-step algorithm with force_lag = 1 against simulate(jacobi=True) with the FMU's own model:
    equal to the rounding of libcosim's nanosecond clock (the step it passes is not exactly H)."""
    pytest.importorskip("libcosimpy")
    p = WheelsetParameters(speed=40.0, initial_lateral_displacement=2e-3)
    times, states = cosimulate(p, 0.2, 1e-3, integer_codes_dir.parent, master="libcosim")
    reference = simulate(dataclasses.replace(p, force_lag=1), LibraryContactLaw(contact_parameters(p)), 0.2, 1e-3,
                         jacobi=True)[1]
    scale = np.abs(reference).max(axis=0)
    assert np.all(np.abs(states - reference) <= 1e-12 * scale), \
        f"largest relative difference {np.max(np.abs(states - reference) / scale)}"
    assert np.ptp(states[:, 0]) > 1e-4, "the wheelset moves"


@pytest.mark.slow
def test_the_libcosim_reference_results_are_the_sweeps_and_meet_the_eigenvalues(integer_codes_dir, tmp_path):
    """The sweep through libcosim (``--master libcosim``): its reference table, and a critical speed within 2 % of
    the eigenvalues' (the issue asks 5 %)."""
    pytest.importorskip("libcosimpy")
    from rollcontact_cosim.wheelset.cosim import REFERENCES, cosim_hunting_sweep, write_cosim_reference

    fresh = write_cosim_reference(integer_codes_dir.parent, tmp_path / "reference.md", master="libcosim")
    assert fresh.read_text() == REFERENCES["libcosim"].read_text(), \
        "models/cosim/wheelset_hunting_libcosim.md is not what the sweep gives: rerun write_cosim_reference"
    sweep = cosim_hunting_sweep((60.0, 70.0), integer_codes_dir.parent, master="libcosim", n_workers=0, periods=6)
    assert abs(sweep.error) <= 0.02, f"libcosim's critical speed is {100 * sweep.error:+.2f} % off the eigenvalues'"


@pytest.mark.slow
def test_the_scene_with_an_fmu_folder_runs_the_cosimulated_sweep(fmu_dir, tmp_path, capsys):
    """``python -m rollcontact_cosim --scene wheelset_hunting --fmu-dir DIR``: the co-simulated sweep on dask, its
    table (the reference's) on stdout and the figure."""
    from rollcontact_cosim.__main__ import main
    from rollcontact_cosim.wheelset.cosim import REFERENCES

    plot = tmp_path / "hunting.png"
    assert main(["--scene", "wheelset_hunting", "--fmu-dir", str(fmu_dir), "--plot", str(plot)]) == 0
    assert REFERENCES["fmpy"].read_text() in capsys.readouterr().out, "the printed table is the reference's"
    assert plot.stat().st_size > 10_000, "the figure is written"


def test_the_scene_passes_master_and_folder_to_the_cosimulated_sweep(monkeypatch, tmp_path, capsys):
    """``--master libcosim`` alone co-simulates the sweep through libcosim with the FMUs of models/; ``--fmu-dir``
    alone through fmpy; in-process options that do not apply are refused."""
    import rollcontact_cosim.wheelset.cosim as wheelset_cosim
    from rollcontact_cosim.__main__ import main
    from rollcontact_cosim.master import FMU_DIR

    calls = []

    def recorded(fmu_dir, path, plot, master="fmpy", **options):
        calls.append((Path(fmu_dir), master))
        Path(path).write_text(f"sweep through {master}\n")
        return Path(path)

    monkeypatch.setattr(wheelset_cosim, "write_cosim_reference", recorded)
    plot = str(tmp_path / "p.png")
    assert main(["--scene", "wheelset_hunting", "--master", "libcosim", "--plot", plot]) == 0
    assert main(["--scene", "wheelset_hunting", "--fmu-dir", str(tmp_path), "--plot", plot]) == 0
    assert calls == [(Path(FMU_DIR), "libcosim"), (tmp_path, "fmpy")], calls
    assert "sweep through libcosim" in capsys.readouterr().out, "the sweep's table is printed"
    assert main(["--scene", "wheelset_hunting", "--master", "libcosim", "--step-size", "1e-3"]) == 2, "refused"
    assert "--fmi, --algorithm, --step-size and --csv do not apply" in capsys.readouterr().err, "the refusal says why"
