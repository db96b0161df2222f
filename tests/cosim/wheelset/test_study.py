"""The in-process hunting study: the measurements, Klingel's wavelength, the simulated critical speed against the
eigenvalues' and the recorded reference results."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from rollcontact_cosim.wheelset import (
    SaturatedKalkerLaw,
    WheelsetParameters,
    linear_law,
)
from rollcontact_cosim.wheelset.study import decay_rate, hunting_sweep, klingel_study, wavelength

P = WheelsetParameters()
LAW = linear_law(P)


# time simulation ---------------------------------------------------------------------------------------------------
def test_the_measurements_recover_a_known_damped_oscillation():
    t = np.linspace(0.0, 5.0, 5001)
    y = 1e-3 * np.exp(-0.4 * t) * np.sin(2 * math.pi * 1.3 * t + 0.3)
    rate, peaks = decay_rate(t, y)
    assert rate == pytest.approx(-0.4, rel=2e-3) and peaks >= 12, f"decay rate {rate} from {peaks} peaks"
    assert wavelength(t, y, 10.0) == pytest.approx(10.0 / 1.3, rel=1e-4), "wavelength V / f"


def test_klingels_wavelength_within_2_percent_and_the_suspension_moves_it_away():
    points = klingel_study(P, LAW, speeds=(5.0,), suspension_scales=(1.0, 0.1, 0.0), periods=5)
    errors = [p.error for p in points]
    assert abs(errors[-1]) < 0.02, f"free wheelset at 5 m/s: wavelength off Klingel's by {errors[-1]:+.4%}"
    assert abs(errors[-1]) < 1e-3, f"the limit is reached to the step's phase error, got {errors[-1]:+.4%}"
    assert abs(errors[0]) > abs(errors[1]) > abs(errors[2]) - 1e-4, f"softer suspension, closer to Klingel: {errors}"
    for point in points:
        assert point.measured / point.eigenvalue - 1 == pytest.approx(0.0, abs=5e-4), \
            f"simulated wavelength {point.measured} against the eigenvalue's {point.eigenvalue}"


def test_the_simulated_critical_speed_matches_the_eigenvalues_within_5_percent():
    sweep = hunting_sweep([58.0, 62.0, 66.0, 70.0], P, LAW, periods=10, n_workers=0)
    assert sweep.simulated_critical_speed is not None, [r.simulated for r in sweep.runs]
    assert abs(sweep.error) < 0.05, f"simulated {sweep.simulated_critical_speed} against predicted " \
                                    f"{sweep.predicted_critical_speed} m/s"
    for run in sweep.runs:
        assert run.simulated == pytest.approx(run.predicted, abs=0.02 * abs(run.predicted) + 0.01), \
            f"decay rate at {run.speed} m/s: simulated {run.simulated}, eigenvalue {run.predicted}"


def test_the_nonlinear_law_at_small_amplitude_hunts_at_the_same_speed():
    law = SaturatedKalkerLaw(LAW)
    sweep = hunting_sweep([60.0, 68.0], dataclasses.replace(P, initial_lateral_displacement=1e-4), law,
                          periods=10, n_workers=0)
    assert abs(sweep.error) < 0.05, f"saturated law: V_c {sweep.simulated_critical_speed} against " \
                                    f"{sweep.predicted_critical_speed} m/s"


def test_the_scene_runs_in_process_and_refuses_the_cosimulation_options(capsys):
    from rollcontact_cosim.__main__ import main

    assert main(["--scene", "wheelset_hunting", "--fmi", "3"]) == 2, "exit code 2 for a bad option"
    assert "runs in process" in capsys.readouterr().err, "the message says why"


def test_the_simulated_critical_speed_does_not_depend_on_the_step():
    coarse = hunting_sweep([60.0, 66.0], P, LAW, periods=10, steps_per_period=40, n_workers=0)
    fine = hunting_sweep([60.0, 66.0], P, LAW, periods=10, steps_per_period=400, n_workers=0)
    assert coarse.simulated_critical_speed == pytest.approx(fine.simulated_critical_speed, rel=2e-3), \
        f"40 steps per period: {coarse.simulated_critical_speed}, 400: {fine.simulated_critical_speed} m/s"


@pytest.mark.slow
def test_the_sweep_on_dask_workers_equals_the_serial_sweep():
    pytest.importorskip("dask.distributed")
    from dask.distributed import Client

    from rollcontact_cosim.sweep import local_cluster

    speeds = [55.0, 65.0, 75.0]
    with local_cluster(2) as cluster, Client(cluster) as client:
        distributed = hunting_sweep(speeds, P, LAW, periods=8, client=client)
    serial = hunting_sweep(speeds, P, LAW, periods=8, n_workers=0)
    assert distributed == serial, "worker processes give the serial results bit for bit"


@pytest.mark.slow
def test_the_reference_results_are_the_studys(tmp_path):
    from rollcontact_cosim.wheelset.study import REFERENCE, write_reference

    fresh = write_reference(tmp_path / "reference.md")
    assert fresh.read_text() == REFERENCE.read_text(), \
        "models/cosim/wheelset_hunting_inprocess.md is not what the study gives: rerun write_reference()"
